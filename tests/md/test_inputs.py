"""LAMMPS input generation, without LAMMPS: the golden input of the ci preset (a declared
regression file, reviewed by hand when it changes) beside independent checks of what the
input must do: the indenter formula reaches the protocol's depth at the right steps, seeds lie
in LAMMPS's range, and bad specs fail before any input is written."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from filmscale.core.errors import InputError
from filmscale.md.indentation import SEED_MAX, derive_seeds, indentation_input, resume_input
from filmscale.md.spec import PRESETS, preset, spec_from_mapping
from filmscale.potentials import PotentialError

GOLDEN = Path(__file__).parent / "golden"


def _normalised(text: str) -> str:
    """Machine-dependent parts out: the potentials folder and the package version."""
    text = re.sub(r"pair_coeff \* \* \S*/(\S+)", r"pair_coeff * * <potentials>/\1", text)
    return re.sub(r"# filmscale \S+ ", "# filmscale <version> ", text)


def test_ci_input_matches_golden_file():
    text = _normalised(indentation_input(preset("ci"), version="X"))
    golden = (GOLDEN / "ci.in.indent").read_text()
    assert text == golden


def test_resume_input_matches_golden_file():
    text = _normalised(resume_input(preset("ci"), restart_file="restart.600.bin",
                                    restart_step=600, z_surface=19.85, part=1,
                                    record="indent.1.dat", version="X"))
    assert text == (GOLDEN / "ci.in.resume.1").read_text()


def _evaluate_lammps_formula(formula: str, step: int, z_surface: float) -> float:
    """Evaluate the equal-style formula with Python's own abs (an independent reading)."""
    expr = formula.replace("v_z_surface", repr(z_surface)).replace("step", str(step))
    return eval(expr, {"abs": abs})


def test_indenter_formula_follows_the_protocol():
    spec = preset("ci")
    p = spec.protocol
    s = p.schedule()
    formula = re.search(r"variable z_tip equal (\S+)", indentation_input(spec)).group(1)
    z0 = 20.0                                   # A
    depth_a, gap_a = p.depth * 1e10, p.gap * 1e10
    at = lambda step: _evaluate_lammps_formula(formula, step, z0)   # noqa: E731
    assert at(0) == pytest.approx(z0 + gap_a)                  # waiting above the surface
    assert at(s.s_hold) == pytest.approx(z0 - depth_a)         # full depth at end of loading
    assert at(s.s_unload) == pytest.approx(z0 - depth_a)       # held
    assert at(s.s_end) == pytest.approx(z0 + gap_a)            # back where it started
    assert at(s.s_end + 500) == pytest.approx(z0 + gap_a)
    # constant speed: (gap + depth) covered in n_down steps of dt
    assert s.n_down * p.timestep * p.speed == pytest.approx(p.gap + p.depth, rel=1e-2)
    # the Python mirror the analysis uses to place the indenter agrees at every step
    steps = np.arange(0, s.s_end + 1, 7)
    np.testing.assert_allclose([at(k) for k in steps],
                               1e10 * s.tip_height(steps, z0 * 1e-10, p.gap), rtol=1e-12)


def test_seeds_are_in_lammps_range_and_reproducible():
    a = derive_seeds(7, ("velocity", "langevin"))
    assert a == derive_seeds(7, ("velocity", "langevin"))
    assert a != derive_seeds(7, ("velocity", "langevin"), part=1)
    for seed in (0, 1, 2**62):
        for value in derive_seeds(seed, ("a", "b", "c")).values():
            assert 1 <= value <= SEED_MAX


def _spec(**changes):
    data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in PRESETS["ci"].items()}
    data["slab"] = dict(data["slab"])
    for path, value in changes.items():
        if "." not in path:
            data[path] = value
            continue
        table, key = path.split(".")
        data[table] = dict(data[table])
        data[table][key] = value
    return spec_from_mapping(data)


def test_bad_specs_fail_before_any_input_is_written():
    with pytest.raises(PotentialError, match="Ni"):          # element not in Cu_mishin1
        _spec(**{"slab.substrate": {"element": "Ni", "thickness": 2e-9, "structure": "fcc",
                                    "a": 3.52e-10}})
    with pytest.raises(InputError, match="thinner than one lattice period"):
        _spec(**{"slab.films": [{"element": "Cu", "thickness": 1e-10}]})
    with pytest.raises(InputError, match="footprint .* box width"):
        _spec(**{"indenter.radius": 3e-9, "protocol.depth": 1.5e-9,
                 "slab.substrate": {"element": "Cu", "thickness": 4e-9}})
    with pytest.raises(InputError, match="protocol.depth .* below the mobile atoms"):
        _spec(**{"protocol.depth": 1.2e-9})
    with pytest.raises(PotentialError, match="Cu_mishin"):
        _spec(**{"potential.name": "Cu_mishin"})
    with pytest.raises(InputError, match="protocol.speed"):
        _spec(**{"protocol.speed": -1.0})
    with pytest.raises(InputError, match="unknown key"):
        _spec(**{"protocol.depht": 1e-10})


def test_cone_indenter_input_is_a_wall_on_a_moving_cone_region():
    """The cone's region is the tip shrunk by the wall's range along its normals: its flank
    r_c / cos(alpha) further in at every height, its apex flat r_c up; it follows v_z_tip."""
    spec = _spec(indenter={"shape": "cone", "half_angle": 70.3, "tip_radius": 2e-10})
    text = indentation_input(spec)
    half, rc = math.radians(70.3), 2.0
    line = re.search(r"region indenter_body cone z (.*) side out move NULL NULL v_z_tip "
                     r"units box", text).group(1)
    x, y, r_lo, r_hi, lo, hi = (float(v) for v in line.split())
    assert (lo, hi) == (rc, 50.0)
    for z, r in ((lo, r_lo), (hi, r_hi)):       # the nominal flank, r0 + z tan(alpha), moved in
        assert r == pytest.approx(2.0 + z * math.tan(half) - rc / math.cos(half), rel=1e-9)
    assert "fix indenter all wall/region indenter_body harmonic" in text
    assert "fix indenter all indent" not in text


def test_md_cone_reaches_the_analysis_as_a_tip_object_with_its_apex_radius(tmp_path):
    """One indenter type crosses scales: the MD cone is a continuum `Cone` whose apex flat is
    radius its contact region is built from (2 A here), and a curve carrying it keeps that radius
    through a curve file; its contact area at zero depth is the flat's, pi r0^2."""
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    from filmscale.continuum.indentation.io import read_curves, write_curve_group
    from filmscale.continuum.indentation.tips import Cone
    from filmscale.core.files import atomic_h5

    spec = _spec(indenter={"shape": "cone", "half_angle": 70.3, "tip_radius": 2e-10})
    tip = spec.indenter.tip
    assert isinstance(tip, Cone) and tip.tip_radius == 2e-10 and tip.half_angle == 70.3
    r_lo = re.search(r"cone z \S+ \S+ (\S+) ", indentation_input(spec)).group(1)
    flat = 2.0 - 2.0 * (1 - math.sin(math.radians(70.3))) / math.cos(math.radians(70.3))
    assert float(r_lo) == pytest.approx(flat, rel=1e-9)          # A, the flat 2 A in, shrunk
    assert float(tip.area(0.0)) == pytest.approx(math.pi * (2e-10)**2, rel=1e-12)
    h = np.linspace(0.0, 1e-9, 20)
    curve = LoadDisplacementCurve(h, 1e-6 * h, segment=np.zeros(h.size, int), indenter=tip)
    with atomic_h5(tmp_path / "c.h5") as f:
        write_curve_group(f.create_group("md"), curve)
    assert read_curves(tmp_path / "c.h5")["md"].indenter == tip


def test_bad_cone_geometry_is_named_before_any_input():
    with pytest.raises(InputError, match="indenter.tip_radius"):
        _spec(indenter={"shape": "cone", "half_angle": 70.3, "tip_radius": 0.0})
    with pytest.raises(InputError, match="indenter.half_angle"):
        _spec(indenter={"shape": "cone", "half_angle": 89.0})
    # a 60 deg cone's region, shrunk 2 A along its normals, keeps no flat under 0.536 A
    with pytest.raises(InputError, match=r"indenter.tip_radius = 5e-11 m must exceed 5.359e-11"):
        _spec(indenter={"shape": "cone", "half_angle": 60.0, "tip_radius": 5e-11})
    with pytest.raises(InputError, match="indenter.radius"):
        _spec(indenter={"radius": 5e-6})
