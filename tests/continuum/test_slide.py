"""A slider sliding on a target (continuum.contact.slider, slide_map), against oracles: Hertz's
closed forms written here, the homogeneous closed-form fields of `sliding` (checked on their own
in test_sliding_homogeneous.py), Johnson's published shakedown limit, the thin- and thick-film
limits of the contact size, and an independent refined search (`layered_cylinder_sliding`,
L-BFGS-B) for the layered peaks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from filmscale.continuum.contact.slide_map import slide_map
from filmscale.continuum.contact.slider import Slider, contact, slide
from filmscale.continuum.contact.sliding import cylinder_sliding, sphere_sliding
from filmscale.continuum.contact.sliding_layered import layered_cylinder_sliding
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError

NIP = ElasticPlastic(E=160e9, nu=0.3, sigma_y=2.5e9, name="NiP")
DLC = ElasticPlastic(E=200e9, nu=0.25, sigma_y=8e9, name="DLC")
RU = ElasticPlastic(E=300e9, nu=0.3, sigma_y=3.5e9, name="Ru")
SOFT = ElasticPlastic(E=70e9, nu=0.34, sigma_y=3e8, name="Al")
ALTIC = ElasticPlastic(E=400e9, nu=0.23, name="AlTiC")
HALF_SPACE = LayerStack((), NIP)
EDGE = Slider("cylinder", 10e-6, length=10e-6, material=ALTIC)
BUMP = Slider("sphere", 10e-6, material=ALTIC)


def e_star(m, slider=ALTIC):
    return 1.0 / ((1 - m.nu**2) / m.E + (1 - slider.nu**2) / slider.E)


# ------------------------------------------------------------------------ the contact
def test_homogeneous_contact_is_hertz():
    P, R, L = 2e-3, 10e-6, 10e-6
    Es = e_star(NIP)
    a = (3 * P * R / (4 * Es)) ** (1 / 3)
    c = contact(HALF_SPACE, BUMP, P)
    assert c.size == pytest.approx(a, rel=1e-12)
    assert c.p0 == pytest.approx(3 * P / (2 * math.pi * a * a), rel=1e-12)
    b = math.sqrt(4 * (P / L) * R / (math.pi * Es))
    c = contact(HALF_SPACE, EDGE, P)
    assert c.size == pytest.approx(b, rel=1e-12)
    assert c.p0 == pytest.approx(2 * (P / L) / (math.pi * b), rel=1e-12)


@pytest.mark.parametrize("slider", [BUMP, EDGE], ids=["sphere", "cylinder"])
def test_contact_size_has_the_film_and_substrate_limits(slider):
    """A film 1e-4 of the contact thin gives the substrate's Hertz size, one 100 times the
    contact thick the film's (the self-consistent size, one film: exact apparent modulus)."""
    P = 5e-3
    bare = contact(LayerStack((), SOFT), slider, P).size
    thin = contact(LayerStack((Layer(bare * 1e-4, RU),), SOFT), slider, P)
    assert thin.size == pytest.approx(bare, rel=2e-3)
    film = contact(LayerStack((), RU), slider, P).size
    thick = contact(LayerStack((Layer(film * 100, RU),), SOFT), slider, P)
    assert thick.size == pytest.approx(film, rel=1e-2)
    # between the limits, and with more films (Gao weighting) too
    mid = contact(LayerStack((Layer(film, RU), Layer(film, DLC)), SOFT), slider, P)
    assert film < mid.size < bare


def test_bad_slider_and_load_are_refused_naming_the_key():
    with pytest.raises(InputError, match="slider.length"):
        Slider("cylinder", 1e-5)
    with pytest.raises(InputError, match="slider.length applies to a cylinder"):
        Slider("sphere", 1e-5, length=1e-5)
    with pytest.raises(InputError, match="slider.shape"):
        Slider("cone", 1e-5)
    with pytest.raises(InputError, match="slider.radius"):
        Slider("sphere", -1e-5)
    with pytest.raises(InputError, match="normal_load"):
        contact(HALF_SPACE, BUMP, 0.0)
    with pytest.raises(InputError, match="mu"):
        slide(HALF_SPACE, EDGE, 1e-3, -0.1)


# ------------------------------------------------------------------------ slide, homogeneous
@pytest.mark.parametrize("mu", [0.0, 0.2, 0.4])
def test_homogeneous_cylinder_peaks_equal_the_closed_form_search(mu):
    P = 1e-2
    r = slide(HALF_SPACE, EDGE, P, mu)
    ref = cylinder_sliding(P, EDGE.length, EDGE.radius, NIP.E, NIP.nu, mu, NIP.sigma_y,
                           ALTIC.E, ALTIC.nu)
    (row,) = r.layers
    # the grid and its zoom against L-BFGS on the closed form: measured <= 5e-6
    assert row.von_mises_max == pytest.approx(ref.vm_max, rel=2e-5)
    assert row.yield_ratio == pytest.approx(ref.yield_ratio, rel=2e-5)
    # trailing-edge tension of a line contact: 2 mu p0 at x = -b (Johnson eq 7.18)
    # (x = -b on the grid to rounding: sqrt(x^2 - b^2) behind the edge costs ~1e-8)
    assert r.surface_tensile_max == pytest.approx(2 * mu * r.contact.p0, rel=1e-7, abs=1e-6)
    if mu:
        assert r.surface_tensile_x == pytest.approx(-r.contact.size, rel=1e-9)
    assert r.first_yield["layer"] == "NiP"


def test_homogeneous_cylinder_shakedown_is_johnsons_4k_without_friction():
    r = slide(HALF_SPACE, EDGE, 1e-2, 0.0)
    k = NIP.sigma_y / math.sqrt(3)
    assert r.shakedown["modelled"]
    assert r.shakedown["p0_limit"] == pytest.approx(4.0 * k, rel=1e-3)
    # the load at which p0 reaches it: p0 = sqrt(P' E* / (pi R)) on a line contact
    P_sd = (4 * k) ** 2 * math.pi * EDGE.radius / e_star(NIP) * EDGE.length
    assert r.shakedown["load_limit"] == pytest.approx(P_sd, rel=1e-3)
    # friction above 0.367: the surface governs, k / mu (Johnson 1985 section 9.2)
    assert slide(HALF_SPACE, EDGE, 1e-2, 0.5).shakedown["p0_limit"] == \
        pytest.approx(k / 0.5, rel=1e-3)


def test_shakedown_is_said_not_modelled_where_it_is_not():
    layered = LayerStack((Layer(20e-9, DLC),), NIP)
    assert not slide(layered, EDGE, 1e-2, 0.3, refine=False).shakedown["modelled"]


# ------------------------------------------------------------------------ slide, layered
def test_layered_cylinder_peaks_agree_with_an_independent_refined_search():
    """slide's grid + zoom against layered_cylinder_sliding's grid + L-BFGS-B."""
    stack = LayerStack((Layer(20e-9, DLC), Layer(30e-9, RU)), NIP)
    P, mu = 2e-2, 0.3
    r = slide(stack, EDGE, P, mu)
    ref = layered_cylinder_sliding(stack, r.contact.size, r.contact.p0, mu)
    for row, peak in zip(r.layers, ref.layers):
        assert row.name == peak.name
        assert row.von_mises_max == pytest.approx(peak.vm_max, rel=1e-4)
        if peak.interface_txz_max is not None:
            assert row.interface_shear_max == pytest.approx(peak.interface_txz_max, rel=1e-4)
    assert r.surface_tensile_max == pytest.approx(ref.tensile_max, rel=1e-3)
    first = max(r.layers, key=lambda row: row.yield_ratio)
    assert r.first_yield["layer"] == first.name


def test_result_json_has_the_keys_the_issue_spells():
    stack = LayerStack((Layer(20e-9, DLC),), NIP)
    d = slide(stack, EDGE, 1e-2, 0.3, refine=False).to_dict()
    assert {"p0", "contact_radius", "layers", "first_yield"} <= set(d)
    for row in d["layers"]:
        assert {"name", "von_mises_max", "x", "z", "yield_ratio", "tensile_max",
                "interface_shear_max"} <= set(row)
    assert {"layer", "x", "z"} <= set(d["first_yield"])
    assert d["contact_half_width"] == d["contact_radius"]


# ------------------------------------------------------------------------ maps
def test_homogeneous_map_first_yield_load_is_the_closed_form():
    """vm_max = c p0 with c from the closed-form search, p0 ~ sqrt(P) on a line: the load of
    first yield is P (sigma_y / vm_max(P))^2 at every friction."""
    mus = np.array([0.0, 0.2, 0.4])
    loads = np.geomspace(1e-2, 1.0, 9)
    mp = slide_map(HALF_SPACE, EDGE, loads, mus)
    for f, mu in enumerate(mus):
        ref = cylinder_sliding(loads[0], EDGE.length, EDGE.radius, NIP.E, NIP.nu, mu,
                               NIP.sigma_y, ALTIC.E, ALTIC.nu)
        expected = loads[0] * (NIP.sigma_y / ref.vm_max) ** 2
        # the map's grid (121 x 16, no zoom) against the refined closed form
        assert mp["first_yield_load"][f] == pytest.approx(expected, rel=2e-2)
        ratio = mp["yield_ratio_max"][f]
        assert np.all(np.diff(ratio) > 0)
    assert mp["shakedown_load"][0] > mp["first_yield_load"][0]


def test_layered_map_agrees_with_slide_within_the_grid_error():
    stack = LayerStack((Layer(20e-9, DLC), Layer(30e-9, RU)), NIP)
    loads, mus = np.array([5e-3, 2e-2]), np.array([0.0, 0.5])
    mp = slide_map(stack, EDGE, loads, mus)
    for i, P in enumerate(loads):
        for f, mu in enumerate(mus):
            r = slide(stack, EDGE, float(P), float(mu))
            for j, row in enumerate(r.layers):
                grid = mp["layer_von_mises_max"][j, f, i]
                # the map's coarser grid finds at most the refined value, within 3 %
                assert grid <= row.von_mises_max * (1 + 1e-9)
                assert grid == pytest.approx(row.von_mises_max, rel=3e-2)


def test_map_axes_are_checked():
    with pytest.raises(InputError, match="normal_load"):
        slide_map(HALF_SPACE, EDGE, [1e-3, 1e-4], [0.1])
    with pytest.raises(InputError, match="friction"):
        slide_map(HALF_SPACE, EDGE, [1e-3], [0.1, float("nan")])


# ------------------------------------------------------------------------ the sphere
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_homogeneous_sphere_peak_and_trailing_edge(mu):
    P = 1e-3
    r = slide(HALF_SPACE, BUMP, P, mu)
    ref = sphere_sliding(P, BUMP.radius, NIP.E, NIP.nu, mu, NIP.sigma_y, ALTIC.E, ALTIC.nu)
    assert r.layers[0].von_mises_max == pytest.approx(ref.vm_max, rel=1e-3)
    p0, nu = r.contact.p0, NIP.nu
    hamilton = p0 * ((1 - 2 * nu) / 3 + (4 + nu) * math.pi * mu / 8)
    assert r.surface_tensile_max == pytest.approx(hamilton, rel=1e-4)


def test_homogeneous_sphere_map_first_yield_load_is_the_closed_form():
    """On a half-space vm_max = c p0 and p0 ~ P^(1/3): the load of first yield is
    P (sigma_y / vm_max(P))^3 at every friction (c from the 3-D search of sphere_sliding)."""
    mus = np.array([0.0, 0.3])
    loads = np.geomspace(1e-4, 1e-2, 7)
    mp = slide_map(HALF_SPACE, BUMP, loads, mus)
    for f, mu in enumerate(mus):
        ref = sphere_sliding(loads[0], BUMP.radius, NIP.E, NIP.nu, mu, NIP.sigma_y, ALTIC.E,
                             ALTIC.nu)
        expected = loads[0] * (NIP.sigma_y / ref.vm_max) ** 3
        # the map's grid (no local search) finds vm within 1.5e-3: the load within 3 x that
        assert mp["first_yield_load"][f] == pytest.approx(expected, rel=6e-3)
        assert mp["first_yield_load"][f] >= expected        # a grid maximum is never above
    assert "shakedown_load" not in mp.values                # not modelled for a sphere


def test_unit_fields_superpose_to_the_field_and_the_map_cut_costs_nothing():
    """p0 (N + mu T) from `layered_cylinder_unit_fields` (the maps' path, cut at s l = 30)
    equals `layered_cylinder_stresses` (cut at 45) on a thin-film stack."""
    from filmscale.continuum.contact.sliding_layered import (layered_cylinder_stresses,
                                                             layered_cylinder_unit_fields)
    stack = LayerStack((Layer(4e-9, DLC), Layer(10e-9, RU)), NIP)
    b, p0, mu = 3e-7, 2e9, 0.3
    x = np.linspace(-1.5 * b, 1.5 * b, 31)
    z = np.array([0.0, 2e-9, 4e-9, 9e-9, 2e-8, 1e-7, 5e-7])
    normal, tangential = layered_cylinder_unit_fields(x, z, stack, b, cut=30.0)
    X, Z = np.meshgrid(x, z)
    ref = layered_cylinder_stresses(X, Z, stack, b, p0, mu)
    for k in ("sxx", "syy", "szz", "txz"):
        assert np.max(np.abs(p0 * (normal[k] + mu * tangential[k]) - ref[k])) < 1e-9 * p0


def test_a_film_far_thinner_than_the_contact_is_refused_before_any_field():
    """The layered solutions' cost grows as a/h_1: beyond FILM_RATIO_MAX the slide and the
    map stop at once, naming the layer and the ratio."""
    import time

    from filmscale.continuum.contact.slider import FILM_RATIO_MAX
    stack = LayerStack((Layer(1e-10, DLC),), NIP)
    size = contact(stack, EDGE, 1.0).size
    assert size / 1e-10 > FILM_RATIO_MAX
    start = time.perf_counter()
    with pytest.raises(InputError, match=r"target.layers\[0\] \(DLC\).*1/\d+ of the contact"):
        slide(stack, EDGE, 1.0, 0.3)
    with pytest.raises(InputError, match="largest load"):
        slide_map(stack, EDGE, [1e-3, 1.0], [0.0])
    assert time.perf_counter() - start < 1.0
