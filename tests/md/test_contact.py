"""Contact area, radius and pile-up from synthetic indented surfaces with known geometry.

The film is a square lattice, spacing s = 2.5 A, 40 x 40 atoms per layer, two layers; a sphere
R = 20 A pressed to depth d moves every surface atom it would overlap vertically down onto its
surface (and the atom below it by the same amount), so the exact contact radius is
a = sqrt(2 R d - d^2). No LAMMPS runs: the dump files are written by the tests.
"""

import math

import MDAnalysis as mda
import numpy as np
import pytest

from filmscale.core.errors import InputError
from filmscale.md.contact import ContactAnalysis, contact_geometry, read_dumps

S = 2.5                 # lattice spacing, A
N = 40                  # atoms per row
L = N * S               # periodic box length, A
R = 20.0                # indenter radius, A
Z0 = 5.0                # undeformed surface height, A
AXIS = (50.0, 50.0)     # indenter axis on a lattice site, A


def film(depth, axis=AXIS, z0=Z0):
    """Two-layer film indented to `depth` (A) by a sphere on `axis`; returns positions, centre."""
    i, j = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    x, y = (i * S).ravel(), (j * S).ravel()
    top = np.column_stack([x, y, np.full(x.size, z0)])
    center = np.array([axis[0], axis[1], z0 + R - depth])
    rho2 = (x - axis[0]) ** 2 + (y - axis[1]) ** 2
    inside = rho2 < R**2 - (R - depth) ** 2          # surface atoms the sphere overlaps
    dz = np.zeros(x.size)
    dz[inside] = (center[2] - np.sqrt(R**2 - rho2[inside])) - z0
    top[:, 2] += dz
    below = top - [0.0, 0.0, S]                      # second layer follows the first
    return np.vstack([top, below]), center


def lattice_count(rho_c, axis=AXIS):
    """Surface lattice sites with lateral distance < rho_c from the axis (direct count)."""
    i, j = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    return int(np.count_nonzero((i * S - axis[0]) ** 2 + (j * S - axis[1]) ** 2 < rho_c**2))


@pytest.mark.parametrize("tol", [0.5, 1e-6])
def test_indented_lattice_gives_the_sphere_contact_radius_and_area(tol):
    d = 2.0
    pos, center = film(d)
    res = contact_geometry(pos, center, R, Z0, box_xy=(L, L), tolerance=tol)
    a = math.sqrt(2 * R * d - d**2)                  # exact contact radius, 8.72 A
    # the flat surface outside the contact is within R + tol of the centre out to
    # rho_c = sqrt((R + tol)^2 - (R - d)^2) (9.81 A for tol = 0.5 A; a for tol -> 0)
    rho_c = math.sqrt((R + tol) ** 2 - (R - d) ** 2)
    assert res.n_contact == lattice_count(rho_c)     # the subsurface layer never counts
    assert res.depth == pytest.approx(d, abs=1e-12)
    # radius: the outermost contact site lies within one lattice spacing inside rho_c,
    # and rho_c - a < s here, so radius_max is within one spacing of a
    assert rho_c - S < res.radius_max < rho_c
    assert abs(res.radius_max - a) < S
    assert abs(res.radius_hull - a) < S
    # area, discretisation bounds: (i) the hull lies in the disc rho_c (convexity) and holds
    # the disc rho_c - sqrt(2) s (every point of it lies in a lattice cell whose four corners
    # are within a cell diagonal, so all in contact); (ii) Pick's theorem for the hull, a
    # lattice polygon whose lattice points are exactly the n contact sites:
    # A = s^2 (n - B/2 - 1) with 3 <= B <= perimeter / s <= 2 pi rho_c / s boundary sites
    A, n = res.area_hull, res.n_contact
    assert math.pi * (rho_c - math.sqrt(2) * S) ** 2 <= A <= math.pi * rho_c**2
    assert S**2 * (n - math.pi * rho_c / S - 1) <= A <= S**2 * (n - 2.5)
    assert res.pile_up == 0.0                        # flat surface outside the contact
    assert set(res.to_dict()) == {"n_contact", "area_hull", "radius_hull", "radius_max",
                                  "depth", "pile_up"}


def test_no_contact_while_the_sphere_is_above_the_surface():
    pos, _ = film(0.0)
    center = np.array([*AXIS, Z0 + R + 1.0])         # apex 1 A above, gap > tolerance
    res = contact_geometry(pos, center, R, Z0, box_xy=(L, L))
    assert (res.n_contact, res.area_hull, res.radius_hull, res.radius_max, res.pile_up) == (
        0, 0.0, 0.0, 0.0, 0.0)
    assert res.depth == pytest.approx(-1.0, abs=1e-12)


@pytest.mark.parametrize("center_xy", [(0.0, 0.0), (L, L), (0.0, L)])
def test_contact_across_the_periodic_boundary_is_whole(center_xy):
    pos, center = film(2.0)
    ref = contact_geometry(pos, center, R, Z0, box_xy=(L, L))
    # shift by half a box and wrap: the contact now straddles the corner of the box
    moved = pos.copy()
    moved[:, :2] = np.mod(moved[:, :2] + L / 2, L)
    c = np.array([*center_xy, center[2]])
    res = contact_geometry(moved, c, R, Z0, box_xy=(L, L))
    # positions are multiples of 0.5 A, so the shift is exact: same atoms, same hull
    assert res.n_contact == ref.n_contact
    assert res.area_hull == pytest.approx(ref.area_hull, rel=1e-12)
    assert res.radius_max == pytest.approx(ref.radius_max, rel=1e-12)
    # without the minimum image the hull would miss all but one quadrant of the contact
    cut = contact_geometry(moved, c, R, Z0)
    assert cut.area_hull < 0.5 * ref.area_hull


def test_pile_up_ring_height():
    pos, center = film(2.0)
    ref = contact_geometry(pos, center, R, Z0, box_xy=(L, L))
    rho = np.hypot(pos[:, 0] - AXIS[0], pos[:, 1] - AXIS[1])
    top = np.arange(len(pos)) < N * N
    ring = top & (rho >= 12.5) & (rho <= 15.0)
    # ring atoms raised by 1.3 A stay out of contact: their distance from the centre is at
    # least sqrt(12.5^2 + (18 - 1.3)^2) = 20.86 A > R + 0.5 A
    raised = pos.copy()
    raised[ring, 2] += 1.3
    far = top & (rho > 3 * ref.radius_max)           # outside the pile-up ring: ignored
    raised[np.flatnonzero(far)[0], 2] += 5.0
    res = contact_geometry(raised, center, R, Z0, box_xy=(L, L))
    assert res.n_contact == ref.n_contact
    assert res.pile_up == pytest.approx(1.3, abs=1e-12)
    # a sunk-in surround gives no pile-up (0, not negative)
    sunk = pos.copy()
    sunk[top & (rho > ref.radius_max + 0.5), 2] -= 0.7
    assert contact_geometry(sunk, center, R, Z0, box_xy=(L, L)).pile_up == 0.0


def test_too_few_or_collinear_contact_atoms_have_zero_area():
    row = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    center = [1.0, 0.0, R - 0.1]
    res = contact_geometry(row, center, R, 0.0)
    assert (res.n_contact, res.area_hull, res.radius_max) == (3, 0.0, 1.0)
    res = contact_geometry(row[:2], center, R, 0.0)
    assert (res.n_contact, res.area_hull) == (2, 0.0)


def test_bad_input_raises_input_error():
    pos, center = film(2.0)
    with pytest.raises(InputError, match="positions"):
        contact_geometry(pos[:, :2], center, R, Z0)
    with pytest.raises(InputError, match="radius"):
        contact_geometry(pos, center, -1.0, Z0)
    with pytest.raises(InputError, match="tolerance"):
        contact_geometry(pos, center, R, Z0, tolerance=-0.1)
    with pytest.raises(InputError, match="box_xy"):
        contact_geometry(pos, center, R, Z0, box_xy=(L, 0.0))
    with pytest.raises(InputError, match="center"):
        contact_geometry(pos, [np.nan, 0.0, 0.0], R, Z0)


# --- ContactAnalysis on LAMMPS dump files ---------------------------------------------

STEPS = (0, 1000, 2000)
SPEED = 1.5e-3          # indenter descent, A per timestep
ZLO = (-10.0, -9.5, -11.0)   # shrink-wrapped (ss) lower z bound, different in every frame


def center_z_angstrom(step):
    return Z0 + R + 1.0 - SPEED * step           # depth -1, 0.5, 2 A at STEPS


def write_dump(path, frames, rng):
    """LAMMPS ``dump custom ... id type x y z c_pe`` text, atoms in shuffled order."""
    with open(path, "w") as f:
        for step, zlo, pos in frames:
            f.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(pos)}\n"
                    f"ITEM: BOX BOUNDS pp pp ss\n0 {L:g}\n0 {L:g}\n{zlo:g} 30\n"
                    "ITEM: ATOMS id type x y z c_pe\n")
            for k in rng.permutation(len(pos)):
                x, y, z = pos[k]
                f.write(f"{k + 1} 1 {float(x)!r} {float(y)!r} {float(z)!r} -3.54\n")


def dump_frames():
    """Frames with the indent on the box corner (periodic).

    Coordinates are rounded to multiples of 2^-10 A (moving atoms off the sphere by < 5e-4 A,
    far below the tolerance) so that MDAnalysis's float32 positions relative to the box
    corner, x - xlo, are exact: the reader then sees exactly these arrays.
    """
    frames = []
    for step, zlo in zip(STEPS, ZLO):
        pos, _ = film(max(0.0, Z0 + R - center_z_angstrom(step)))
        pos[:, :2] = np.mod(pos[:, :2] + L / 2, L)
        frames.append((step, zlo, np.round(pos * 1024) / 1024))
    return frames


@pytest.mark.parametrize("n_files", [1, 2])
def test_contact_analysis_on_a_dump_matches_contact_geometry_in_si(tmp_path, n_files):
    frames = dump_frames()
    rng = np.random.default_rng(1)
    if n_files == 1:
        paths = [tmp_path / "indent.dump"]
        write_dump(paths[0], frames, rng)
    else:                                            # chained files, given in order
        paths = [tmp_path / "a.dump", tmp_path / "b.dump"]
        write_dump(paths[0], frames[:2], rng)
        write_dump(paths[1], frames[2:], rng)
    u = read_dumps(paths if n_files > 1 else paths[0], dt=1e-15)
    calls = []

    def center_z(step):                              # SI: metres of a LAMMPS step
        calls.append(step)
        return center_z_angstrom(step) * 1e-10

    ana = ContactAnalysis(u.atoms, radius=R * 1e-10, center_xy=(0.0, 0.0), center_z=center_z,
                          surface_z=Z0 * 1e-10).run()
    assert calls == list(STEPS)
    assert list(ana.results.step) == list(STEPS)
    for k, (step, zlo, pos) in enumerate(frames):
        ref = contact_geometry(pos, [0.0, 0.0, center_z_angstrom(step)], R, Z0,
                               box_xy=(L, L), tolerance=0.5)
        u.trajectory[k]
        assert u.trajectory.ts.data["lammps_origin"] == pytest.approx([0.0, 0.0, zlo])
        # MDAnalysis holds x - xlo exactly (see dump_frames); only the A <-> m conversions and
        # the shift by the box corner differ from the reference (float64 round-off, 1e-12)
        assert np.array_equal(u.atoms.positions, pos - [0.0, 0.0, zlo])
        assert ana.results.n_contact[k] == ref.n_contact
        for key, want in [("depth", ref.depth * 1e-10), ("area", ref.area_hull * 1e-20),
                          ("radius", ref.radius_hull * 1e-10),
                          ("radius_max", ref.radius_max * 1e-10),
                          ("pile_up", ref.pile_up * 1e-10)]:
            assert ana.results[key][k] == pytest.approx(want, rel=1e-12, abs=1e-24), key
    # the callable was honoured: the sphere starts above the film and then presses in
    assert ana.results.depth == pytest.approx([-1e-10, 0.5e-10, 2e-10], rel=1e-9)
    assert ana.results.n_contact[0] == 0 < ana.results.n_contact[1] < ana.results.n_contact[2]
    assert np.allclose(ana.times, np.array(STEPS) * 1e-3)     # ps, from dt = 1 fs


@pytest.mark.filterwarnings("ignore:Guessed all Masses:UserWarning")
def test_contact_analysis_input_checks(tmp_path):
    path = tmp_path / "one.dump"
    write_dump(path, dump_frames()[:1], np.random.default_rng(2))
    u = read_dumps(path)
    ok = ContactAnalysis(u.atoms, radius=R * 1e-10, center_xy=(0.0, 0.0),
                         center_z=(Z0 + R + 1.0) * 1e-10, surface_z=Z0 * 1e-10).run()
    assert ok.results.depth == pytest.approx([-1e-10], rel=1e-12)
    # MDAnalysis alone moves positions by the box corner: ContactAnalysis refuses such a dump
    raw = mda.Universe(str(path), format="LAMMPSDUMP", dt=1.0)
    with pytest.raises(InputError, match="read_dumps"):
        ContactAnalysis(raw.atoms, radius=R * 1e-10, center_xy=(0.0, 0.0),
                        center_z=(Z0 + R + 1.0) * 1e-10, surface_z=Z0 * 1e-10)
    with pytest.raises(InputError, match="radius"):
        ContactAnalysis(u.atoms, radius=0.0, center_xy=(0, 0), center_z=1e-9, surface_z=0.0)
    with pytest.raises(InputError, match="center_xy"):
        ContactAnalysis(u.atoms, radius=2e-9, center_xy=(0,), center_z=1e-9, surface_z=0.0)
    with pytest.raises(InputError, match="atomgroup"):
        ContactAnalysis([1, 2], radius=2e-9, center_xy=(0, 0), center_z=1e-9, surface_z=0.0)
    with pytest.raises(InputError, match=r"center_z\(0\)"):
        ContactAnalysis(u.atoms, radius=2e-9, center_xy=(0, 0), center_z=lambda s: "x",
                        surface_z=0.0).run()
    with pytest.raises(FileNotFoundError):
        read_dumps(tmp_path / "missing.dump")
