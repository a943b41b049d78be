"""The atomic von Mises strain (Shimizu, Ogata & Li 2007) and the damaged region, against
closed forms written here: a homogeneous deformation gradient F gives every atom
eta = (F^T F - I)/2 exactly (the least-squares fit is exact for any neighbour set), rigid
motions give zero, periodic images are found, and a block of disturbed atoms is reported
with its own width and depth."""

import math

import numpy as np
import pytest
from ase.build import bulk

from filmscale.md.damage import (atomic_strain, damaged_region, layer_index, neighbour_pairs,
                                 shell_cutoff)

A = 3.615                      # Cu lattice constant, A
NN = A / math.sqrt(2.0)        # nearest-neighbour distance
CUT = shell_cutoff("fcc", A)


def _lattice(n=(5, 5, 5)):
    """A perfect fcc lattice (cube axes) and its box; periodic in x and y."""
    atoms = bulk("Cu", "fcc", a=A, cubic=True).repeat(n)
    return atoms.positions.copy(), np.diag(atoms.cell.array).copy()


def _mises_closed(F):
    """eta = (F^T F - I)/2 and its von Mises invariant, written out component by component."""
    e = 0.5 * (np.asarray(F).T @ np.asarray(F) - np.eye(3))
    return math.sqrt(e[1, 2] ** 2 + e[0, 2] ** 2 + e[0, 1] ** 2
                     + ((e[1, 1] - e[2, 2]) ** 2 + (e[0, 0] - e[2, 2]) ** 2
                        + (e[0, 0] - e[1, 1]) ** 2) / 6.0)


@pytest.mark.parametrize("gamma", [0.02, 0.1, 0.3])
def test_simple_shear_gives_the_closed_form_at_every_atom(gamma):
    x0, box = _lattice()
    F = np.array([[1.0, 0.0, gamma], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])   # x += gamma z
    x = x0 @ F.T
    x[:, :2] %= box[:2]                      # wrapped back into the periodic box
    eta = atomic_strain(x0, x, CUT, box=box)
    # eta_xz = gamma/2, eta_zz = gamma^2/2: sqrt(gamma^2/4 + gamma^4/12)
    expected = math.sqrt(gamma ** 2 / 4 + gamma ** 4 / 12)
    assert _mises_closed(F) == pytest.approx(expected, rel=1e-14)
    assert np.all(np.isfinite(eta))
    np.testing.assert_allclose(eta, expected, rtol=0, atol=1e-10)


def test_rigid_translation_and_rotation_give_zero():
    x0, box = _lattice()
    x = x0 + np.array([7.3, -11.1, 2.2])
    x[:, :2] %= box[:2]
    np.testing.assert_allclose(atomic_strain(x0, x, CUT, box=box), 0.0, atol=1e-12)
    # a rotation (not periodic: a free cluster) about an oblique axis by 37 degrees
    axis = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
    t = math.radians(37.0)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K
    x = x0 @ R.T + 5.0
    eta = atomic_strain(x0, x, CUT, box=None)
    np.testing.assert_allclose(eta, 0.0, atol=1e-12)


@pytest.mark.parametrize("axis", [0, 2])
def test_uniaxial_stretch_of_one_percent(axis):
    x0, box = _lattice()
    F = np.eye(3)
    F[axis, axis] = 1.01
    x = x0 @ F.T
    box_now = box * np.diag(F)                  # the periodic box stretches with x
    x[:, :2] %= box_now[:2]
    eta = atomic_strain(x0, x, CUT, box=box, box_current=box_now)
    e = (1.01 ** 2 - 1) / 2                     # eta_axis; the rest zero: e / sqrt(3)
    assert _mises_closed(F) == pytest.approx(e / math.sqrt(3.0), rel=1e-14)
    np.testing.assert_allclose(eta, e / math.sqrt(3.0), rtol=0, atol=1e-10)


def test_periodic_images_an_edge_atom_equals_an_inner_one():
    x0, box = _lattice((6, 6, 6))
    pairs = neighbour_pairs(x0, CUT, box=box)
    count = np.bincount(pairs[:, 0], minlength=len(x0))
    z_inner = (x0[:, 2] > A) & (x0[:, 2] < box[2] - 2 * A)
    assert np.all(count[z_inner] == 12)         # images across x and y found: a full shell
    # stretch along x with the box, and shift so that atoms wrap across the x boundary
    F = np.diag([1.01, 1.0, 1.0])
    box_now = box * np.diag(F)
    x = x0 @ F.T - [1.0, 0.5, 0.0]               # the edge atoms wrap to the far side
    x[:, :2] %= box_now[:2]
    eta = atomic_strain(x0, x, CUT, box=box, box_current=box_now)
    edge = np.flatnonzero(z_inner & (x0[:, 0] < 1e-9) & (x0[:, 1] < 1e-9))
    inner = np.flatnonzero(z_inner & (np.abs(x0[:, 0] - 3 * A) < 1e-9)
                           & (np.abs(x0[:, 1] - 3 * A) < 1e-9))
    assert edge.size and inner.size
    np.testing.assert_allclose(eta[edge], eta[inner[0]], rtol=0, atol=1e-12)
    # without the periodic images the edge atom's neighbours are half a box away: wrong
    wrong = atomic_strain(x0, x, CUT, box=box, pbc=(False, False, False))
    assert abs(wrong[edge[0]] - eta[inner[0]]) > 0.1


def test_damaged_block_width_and_depth_per_layer():
    """Atoms of a block (|y - 0| < 0.9 nm across the periodic y boundary, down to 1.5 nm below
    the surface) displaced at random by up to 0.6 A: the region reported in each layer is the
    block's within one neighbour distance (its boundary atoms see displaced neighbours)."""
    x0, box = _lattice((8, 10, 8))                # 2.9 x 3.6 x 2.9 nm
    z_surf = x0[:, 2].max()
    dy = (x0[:, 1] + 0.5 * box[1]) % box[1] - 0.5 * box[1]   # from the axis y = 0
    half_w, D = 9.0, 15.0
    block = (np.abs(dy) <= half_w) & (z_surf - x0[:, 2] <= D)
    rng = np.random.default_rng(35)
    x = x0 + np.where(block[:, None], rng.uniform(-0.6, 0.6, x0.shape), 0.0)
    eta = atomic_strain(x0, x, CUT, box=box)
    # three layers: the film (top 1.0 nm), an interlayer down to 2.0 nm, the substrate
    tops = (z_surf, z_surf - 10.0 - 0.5, z_surf - 20.0 - 0.5)
    layer_of = layer_index(x0[:, 2], tops)
    assert set(layer_of[z_surf - x0[:, 2] < 10.0]) == {0}
    assert set(layer_of[z_surf - x0[:, 2] > 20.9]) == {2}
    rows = damaged_region(x0, eta, ["film", "inter", "substrate"], layer_of, z_surf, 0.0,
                          box[1])
    w_block = np.ptp(dy[block])
    film, inter, sub = rows
    assert film.layer == "film" and film.atoms > 0
    assert film.width == pytest.approx(w_block, abs=NN)
    assert film.depth == pytest.approx(np.max(z_surf - x0[layer_of == 0, 2]), abs=NN)
    assert inter.width == pytest.approx(w_block, abs=NN)
    assert inter.depth == pytest.approx(D, abs=NN)
    assert (sub.width, sub.depth, sub.atoms) == (0.0, 0.0, 0)
    # a subset (a cross-section) of the atoms only
    sel = np.abs(x0[:, 0] - box[0] / 2) < 4.0
    cut = damaged_region(x0, eta, ["film", "inter", "substrate"], layer_of, z_surf, 0.0,
                         box[1], select=sel)
    assert 0 < cut[0].atoms < film.atoms and cut[0].width == pytest.approx(w_block, abs=NN)


def test_too_few_neighbours_give_nan_and_a_too_large_cutoff_is_refused():
    x0 = np.array([[0.0, 0, 0], [2.5, 0, 0], [0, 2.5, 0], [2.5, 2.5, 0]])   # coplanar
    assert np.all(np.isnan(atomic_strain(x0, x0 * 1.1, 3.0)))
    x0, box = _lattice((2, 2, 2))
    with pytest.raises(ValueError, match="half the period"):
        atomic_strain(x0, x0, 4.0, box=box)


def test_diamond_cutoff_holds_its_first_two_shells():
    """Between the 2nd (a/sqrt 2, 12 atoms) and 3rd (a sqrt(11)/4, 12 atoms) shells of
    diamond: 4 + 12 = 16 neighbours, counted by brute force on a periodic 3x3x3 cell."""
    from ase.build import bulk
    a = 3.567
    atoms = bulk("C", "diamond", a=a, cubic=True).repeat(3)
    cut = shell_cutoff("diamond", a)
    d = atoms.get_all_distances(mic=True)
    counts = ((d > 0) & (d < cut)).sum(axis=1)
    assert np.all(counts == 16)
    assert a / np.sqrt(2) < cut < a * np.sqrt(11) / 4


def test_amorphous_cutoff_holds_fourteen_neighbours_of_a_uniform_gas():
    """A uniform random gas of the number density of 3 g/cm3 carbon: the sphere of the cutoff
    holds 14 atoms on average (counted here, within three standard errors)."""
    from filmscale.md.damage import AMORPHOUS_NEIGHBOURS, amorphous_cutoff
    n = 3000.0 / (12.011 * 1.66053906660e-27) * 1e-30          # atoms per cubic Angstrom
    L = (4000 / n) ** (1 / 3)
    x = np.random.default_rng(5).uniform(0, L, size=(4000, 3))
    cut = amorphous_cutoff(n)
    d = x[:500, None, :] - x[None, :, :]
    d -= L * np.round(d / L)
    counts = ((np.linalg.norm(d, axis=2) < cut).sum(axis=1) - 1)
    assert AMORPHOUS_NEIGHBOURS == 14
    assert abs(counts.mean() - 14) < 3 * counts.std() / np.sqrt(counts.size)
