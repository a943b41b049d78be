"""Slab building against crystallographic closed forms."""

import math

import numpy as np
import pytest

from filmscale.core.errors import InputError
from filmscale.md.structures import Crystal, SlabLayer, SlabSpec, build_slab

CU, NI = Crystal("Cu", "fcc", 3.615e-10), Crystal("Ni", "fcc", 3.52e-10)


def test_coherent_film_misfit_and_counts():
    spec = SlabSpec(films=(SlabLayer(CU, 1.1e-9),), substrate=SlabLayer(NI, 2.1e-9),
                    lateral_size=3.5e-9)
    slab = build_slab(spec)
    # ten Ni cells of 3.52 A laterally; the Cu film takes them: strain = a_Ni/a_Cu - 1
    assert slab.box[0] == pytest.approx(10 * 3.52e-10)
    assert slab.misfit[0][0] == pytest.approx(3.52 / 3.615 - 1.0, rel=1e-12)
    # fcc: 4 atoms per cubic cell; 10 x 10 lateral cells, 3 (Cu) and 6 (Ni) cells deep
    assert slab.element_counts == {"Cu": 4 * 100 * 3, "Ni": 4 * 100 * 6}
    # interface gap: the mean of the two (001) interplanar spacings a/2
    z = np.unique(np.round(slab.atoms.positions[:, 2], 6))
    ni_top = z[z < 21.0].max()
    assert z[z > ni_top].min() - ni_top == pytest.approx((3.52 + 3.615) / 4, abs=1e-6)
    assert slab.z_surface == pytest.approx(slab.layer_tops[0])


def test_111_interplanar_spacing():
    slab = build_slab(SlabSpec(films=(), substrate=SlabLayer(CU, 2e-9), orientation="111",
                               lateral_size=2.5e-9))
    z = np.unique(np.round(slab.atoms.positions[:, 2], 6))
    # heights were rounded to 1e-6 A to group the layers
    np.testing.assert_allclose(np.diff(z), 3.615 / math.sqrt(3.0), atol=2e-6)
    assert slab.surface_layer_gap == pytest.approx(3.615e-10 / math.sqrt(3.0), rel=1e-9)


def test_film_thinner_than_a_lattice_period_is_refused():
    with pytest.raises(InputError, match=r"films\[0\]\.thickness .* thinner than one lattice"):
        build_slab(SlabSpec(films=(SlabLayer(CU, 2e-10),), substrate=SlabLayer(NI, 2e-9)))


def test_hcp_on_fcc_is_refused_and_names_the_structures():
    co = Crystal("Co", "hcp", 2.507e-10)
    with pytest.raises(InputError, match="cubic or all hcp"):
        SlabSpec(films=(SlabLayer(co, 1e-9),), substrate=SlabLayer(NI, 2e-9))


def test_regions_leave_mobile_atoms():
    with pytest.raises(InputError, match="leaves no mobile atoms"):
        build_slab(SlabSpec(films=(), substrate=SlabLayer(CU, 1.1e-9),
                            fixed_thickness=6e-10, thermostat_thickness=6e-10))


def test_multilayer_order_and_bcc_cells():
    # Ni on Cu on a Ni substrate: layer tops run down the stack, counts follow the cells
    slab = build_slab(SlabSpec(films=(SlabLayer(NI, 0.704e-9), SlabLayer(CU, 0.723e-9)),
                               substrate=SlabLayer(NI, 1.408e-9), lateral_size=1.76e-9))
    tops = slab.layer_tops
    assert tops[0] > tops[1] > tops[2]
    assert slab.element_counts == {"Ni": 4 * 25 * (2 + 4), "Cu": 4 * 25 * 2}
    # the top Ni film sits coherently on the Ni substrate's lattice: no misfit
    assert slab.misfit[0] == pytest.approx((0.0, 0.0), abs=1e-12)
    # bcc W (001): 2 atoms per cubic cell, (001) planes a/2 apart
    w = Crystal("W", "bcc", 3.165e-10)
    slab = build_slab(SlabSpec(films=(), substrate=SlabLayer(w, 1.266e-9),
                               lateral_size=1.27e-9, fixed_thickness=2e-10,
                               thermostat_thickness=2e-10))
    assert slab.n_atoms == 2 * 4 * 4 * 4
    assert slab.surface_layer_gap == pytest.approx(3.165e-10 / 2, rel=1e-9)


def test_hcp_basal_slab_with_ideal_c():
    co = Crystal("Co", "hcp", 2.507e-10)            # c defaults to sqrt(8/3) a
    slab = build_slab(SlabSpec(films=(), substrate=SlabLayer(co, 2.05e-9), orientation="0001",
                               lateral_size=1.5e-9, fixed_thickness=3e-10,
                               thermostat_thickness=3e-10))
    # basal planes are c/2 apart; the orthogonal cell holds 4 atoms
    assert slab.surface_layer_gap == pytest.approx(2.507e-10 * math.sqrt(8 / 3) / 2, rel=1e-9)
    assert slab.n_atoms % 4 == 0
    with pytest.raises(InputError, match="orientation = '001' is not available for hcp"):
        build_slab(SlabSpec(films=(), substrate=SlabLayer(co, 2e-9)))
