"""The MD cone's contact against its geometry, one atom at a time in LAMMPS (`run 0`).

The reference is written here: a point pressed delta past the nominal flank of a cone with
half-angle alpha and apex flat r0 feels k_w delta along the flank's outward normal
(cos alpha, 0, -sin alpha); past the flat, k_w delta straight down; outside, nothing. The
indenter's fix reports the opposite force, the one on the tip. LAMMPS's own ``fix indent
cone`` is checked to push elsewhere: the reason the package does not use it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from filmscale.md.indentation import CONE_AXIS_OFFSET, CONE_RANGE, RigidIndenter
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps

ALPHA, R0, HEIGHT = 60.0, 3e-10, 3e-9      # deg, m, m
X_TIP, Z_TIP = 2.3, 1.7                    # A: where the variables put the apex


def _forces(lammps_module, fix_lines: str, point) -> tuple[np.ndarray, np.ndarray]:
    """(force on the atom, force the fix reports on the tip), eV/A, one atom at ``point``."""
    lmp = lammps_module.lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    try:
        lmp.commands_string(
            "units metal\nboundary p p p\nregion box block -80 80 -80 80 -80 80\n"
            "create_box 1 box\nmass 1 63.5\n"
            "create_atoms 1 single {:.12g} {:.12g} {:.12g} units box\n".format(*point) +
            "pair_style zero 5.0\npair_coeff * *\n"
            f"variable z_tip equal {Z_TIP}\nvariable x_tip equal {X_TIP}\n"
            f"{fix_lines}\nrun 0")
        atom = lmp.numpy.extract_atom("f")[0].copy()
        tip = np.array([lmp.extract_fix("indenter", 0, 1, i) for i in range(3)])
    finally:
        lmp.close()
    return atom, tip


def _k_wall(indenter: RigidIndenter) -> float:
    return float(si_to_lammps(indenter.wall_stiffness, "stiffness"))     # eV/A^2


def _flank_point(height: float, delta: float) -> np.ndarray:
    """A point ``delta`` (A) inside the nominal flank, ``height`` (A) above the apex."""
    a = math.radians(ALPHA)
    r0 = float(si_to_lammps(R0, "length"))
    surface = np.array([X_TIP + r0 + height * math.tan(a), 0.0, Z_TIP + height])
    return surface - delta * np.array([math.cos(a), 0.0, -math.sin(a)])


@pytest.mark.parametrize("height, delta", [(0.5, 0.05), (2.0, 0.1), (5.0, 0.5), (12.0, 1.0)])
def test_an_atom_pressed_into_the_flank_is_pushed_along_its_normal(lammps_module, height,
                                                                    delta):
    cone = RigidIndenter.cone(ALPHA, R0, height=HEIGHT)
    atom, tip = _forces(lammps_module, cone.fix_command("v_x_tip", 0.0),
                        _flank_point(height, delta))
    a = math.radians(ALPHA)
    expected = _k_wall(cone) * delta * np.array([math.cos(a), 0.0, -math.sin(a)])
    # the axis sits 1e-3 A off y = 0, which tilts the normal by under 1e-3 of delta's force
    assert atom == pytest.approx(expected, abs=1e-3 * np.linalg.norm(expected))
    assert tip == pytest.approx(-atom, rel=1e-12)


def test_outside_the_nominal_surface_nothing_pushes(lammps_module):
    cone = RigidIndenter.cone(ALPHA, R0, height=HEIGHT)
    for point in (_flank_point(3.0, -0.2), (X_TIP, 0.0, Z_TIP - 0.1)):
        atom, _ = _forces(lammps_module, cone.fix_command("v_x_tip", 0.0), point)
        assert np.all(atom == 0.0)


def test_an_atom_under_the_apex_on_the_axis_is_pushed_straight_down(lammps_module):
    """LAMMPS's cone gives no force to a point exactly on its axis; the package's axis is
    moved off the indenter's y for that reason, and a lattice column on it is pushed."""
    cone = RigidIndenter.cone(ALPHA, R0, height=HEIGHT)
    atom, _ = _forces(lammps_module, cone.fix_command("v_x_tip", 0.0), (X_TIP, 0.0, Z_TIP + 0.3))
    assert atom == pytest.approx([0.0, 0.0, -_k_wall(cone) * 0.3], abs=1e-9)


def test_the_stiffness_is_the_spheres_at_one_ev_per_angstrom():
    """2 sqrt(K F): at F = 1 eV/A the sphere's law F = K d^2 has this slope (20 eV/A^2 at
    K = 100 eV/A^3)."""
    cone = RigidIndenter.cone(ALPHA, R0)
    assert _k_wall(cone) == pytest.approx(20.0, rel=1e-9)
    K = float(si_to_lammps(cone.K, "indent_constant"))
    d = math.sqrt(1.0 / K)                                  # A, where the sphere carries 1 eV/A
    assert (K * (d + 1e-6)**2 - K * (d - 1e-6)**2) / 2e-6 == pytest.approx(_k_wall(cone))
    assert float(lammps_to_si(_k_wall(cone), "stiffness")) == pytest.approx(cone.wall_stiffness)


def test_lammps_fix_indent_cone_does_not_push_along_the_flank_normal(lammps_module):
    """Why the cone is a wall: ``fix indent cone`` pushes along the line from the cone's
    mid-axis point, so the same penetration is pushed 4 deg off the normal 2 A above the apex
    and 73 deg off it 25 A up (of 30): the direction depends on the cone's height, and the
    ploughing force of a scratch follows it."""
    r0 = float(si_to_lammps(R0, "length"))
    H = float(si_to_lammps(HEIGHT, "length"))
    r1 = r0 + H * math.tan(math.radians(ALPHA))
    fix = (f"variable z_top equal v_z_tip+{H}\n"
           f"fix indenter all indent 100 cone z v_x_tip 0 {r0} {r1} v_z_tip v_z_top units box")
    a = math.radians(ALPHA)
    normal = np.array([math.cos(a), 0.0, -math.sin(a)])
    mid_axis = np.array([X_TIP, 0.0, Z_TIP + H / 2])
    for height, off_normal in ((2.0, 3.69), (25.0, 72.76)):
        point = _flank_point(height, 0.5)
        atom, _ = _forces(lammps_module, fix, point)
        along = (point - mid_axis) / np.linalg.norm(point - mid_axis)
        assert atom / np.linalg.norm(atom) == pytest.approx(along, abs=1e-9)
        angle = math.degrees(math.acos(atom @ normal / np.linalg.norm(atom)))
        assert angle == pytest.approx(off_normal, abs=0.01)


def test_the_contact_read_from_positions_is_the_walls_atom_by_atom(lammps_module):
    """`cone_contact` rebuilds, from positions alone, the force LAMMPS's wall puts on each
    atom: on the flank, under the flat, around the flat's rounded rim, and none outside."""
    from filmscale.continuum.indentation.tips import Cone
    from filmscale.md.cone_contact import cone_contact

    cone = RigidIndenter.cone(ALPHA, R0, height=HEIGHT)
    rng = np.random.default_rng(7)
    a = math.radians(ALPHA)
    r0 = float(si_to_lammps(R0, "length"))
    # points in a shell around the apex and the lower flank, in A
    s = rng.uniform(-1.5, 8.0, 400)
    r = np.clip(r0 + np.maximum(s, 0) * math.tan(a) + rng.uniform(-1.0, 1.5, 400), 0.05, None)
    phi = rng.uniform(0, 2 * math.pi, 400)
    points = np.column_stack([X_TIP + r * np.cos(phi), r * np.sin(phi), Z_TIP + s])
    lmp = lammps_module.lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    try:
        lmp.commands_string(
            "units metal\nboundary p p p\nregion box block -80 80 -80 80 -80 80\n"
            "create_box 1 box\nmass 1 63.5\npair_style zero 5.0\npair_coeff * *\n"
            f"variable z_tip equal {Z_TIP}\nvariable x_tip equal {X_TIP}\n"
            f"{cone.fix_command('v_x_tip', 0.0)}")
        kept = []
        for p in points:       # LAMMPS stops on an atom inside the region: leave those out
            inside_region = _inside_region(p, a, r0)
            if not inside_region:
                lmp.command("create_atoms 1 single {:.12g} {:.12g} {:.12g} units box".format(*p))
                kept.append(p)
        lmp.command("run 0")
        ids = lmp.numpy.extract_atom("id").copy()
        f_lammps = lmp.numpy.extract_atom("f")[np.argsort(ids)].copy()
    finally:
        lmp.close()
    kept = np.array(kept)
    atoms = {k: lammps_to_si(kept[:, i], "length") for i, k in enumerate("xyz")}
    apex = (float(lammps_to_si(X_TIP, "length")), CONE_AXIS_OFFSET,
            float(lammps_to_si(Z_TIP, "length")))
    contact = cone_contact(atoms, Cone(ALPHA, tip_radius=R0), apex, cone.wall_stiffness,
                           (1.6e-8, 1.6e-8))
    pushed = np.linalg.norm(f_lammps, axis=1) > 0
    assert 100 < pushed.sum() < len(kept)              # both sides of the surface sampled
    f_si = lammps_to_si(f_lammps[pushed], "force")
    assert contact.force.shape == f_si.shape
    assert contact.force == pytest.approx(f_si, abs=1e-6 * np.abs(f_si).max())


def _inside_region(p, a, r0) -> bool:
    """Whether a point (A) lies inside the shrunk region (where LAMMPS stops a run)."""
    rc = float(si_to_lammps(CONE_RANGE, "length"))
    r = math.hypot(p[0] - X_TIP, p[1])
    s = p[2] - Z_TIP
    return s >= rc and r <= r0 - rc * (1 - math.sin(a)) / math.cos(a) + (s - rc) * math.tan(a)


def test_a_real_cone_scratch_carries_the_load_its_atoms_say(lammps_module, tmp_path):
    """The ci scratch with a 45 deg cone (LAMMPS, about 15 s on 2 ranks): at the end of the
    stroke, still at depth, the force the atoms' positions put on the cone
    (`cone_contact`) is the force the run recorded, normal and lateral, and the lateral force
    resists the motion."""
    import copy

    from filmscale.md.cone_contact import scratch_contact
    from filmscale.md.engine import EngineOptions
    from filmscale.md.scratch import PRESETS, scratch_spec_from_mapping
    from filmscale.md.scratch_run import analyze_scratch, run_scratch

    data = copy.deepcopy(PRESETS["ci"])
    data["indenter"] = {"shape": "cone", "half_angle": 45.0, "tip_radius": 2e-10,
                        "height": 3e-9}
    data["protocol"]["record_every"] = 1          # the record holds the dump's own step
    spec = scratch_spec_from_mapping(data)
    run = run_scratch(spec, tmp_path / "run", EngineOptions(np=2))
    contact = scratch_contact(run)
    k = int(np.flatnonzero(run.data["step"] == spec.schedule().s_unload)[0])
    assert contact.normal_force > 1e-8                          # N: a loaded contact
    # the dump keeps positions to 1e-5 A or so: forces agree to 1e-3
    assert contact.normal_force == pytest.approx(run.data["fz"][k], rel=1e-3)
    assert contact.lateral_force == pytest.approx(-run.data["fx"][k], rel=1e-3)
    assert analyze_scratch(run).lateral_force_mean > 0


def test_the_contact_of_a_scratch_under_load_is_refused():
    """Under load the apex follows the feedback, so its height is not the schedule's."""
    import copy
    from types import SimpleNamespace

    from filmscale.core.errors import InputError
    from filmscale.md.cone_contact import scratch_contact
    from filmscale.md.scratch import PRESETS, scratch_spec_from_mapping

    data = copy.deepcopy(PRESETS["ci"])
    data["indenter"] = {"shape": "cone", "half_angle": 45.0, "tip_radius": 2e-10,
                        "height": 3e-9}
    data["scratch"] = {"normal_load": 5e-8, "max_depth": 6e-10, "length": 1.2e-9}
    spec = scratch_spec_from_mapping(data)
    with pytest.raises(InputError, match="scratch.normal_load = 5e-08 N"):
        scratch_contact(SimpleNamespace(spec=spec))
