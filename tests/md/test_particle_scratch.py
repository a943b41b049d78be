"""Particle scratch (TLSPH): the encoded indenter path against the stroke written here, the
frictionless elastic limit against `particles indent` at the same depth (LAMMPS, ~10 s), and
spec errors (exit 2, one line)."""

import copy

import h5py
import numpy as np
import pytest

from filmscale.md.particle_run import run_particles
from filmscale.md.particle_scratch import (PRESETS, path_formulas, preset, scratch_input,
                                           tip_path)
from filmscale.md.particle_scratch import spec_from_mapping as scratch_spec
from filmscale.md.particle_scratch_run import analyze_scratch, run_scratch, write_scratch_record
from filmscale.md.particle_spec import spec_from_mapping
from filmscale.workflows.cli import main

# ---- the path ---------------------------------------------------------------------------------

# a stroke written out by hand, SI: down at 50 m/s to 0.1 um, along +x at 100 m/s over 1 um,
# back along -x, up at 50 m/s, relax 1 ns
V_N, DEPTH, V_S, LENGTH = 50.0, 1e-7, 100.0, 1e-6
T1 = DEPTH / V_N                  # 2 ns
T = LENGTH / V_S                  # 10 ns


def stroke_by_hand(t):
    """(x, depth) of the stroke above, piece by piece."""
    if t <= T1:
        return 0.0, V_N * t
    if t <= T1 + T:
        return V_S * (t - T1), DEPTH
    if t <= T1 + 2 * T:
        return LENGTH - V_S * (t - T1 - T), DEPTH
    if t <= 2 * T1 + 2 * T:
        return 0.0, DEPTH - V_N * (t - T1 - 2 * T)
    return 0.0, 0.0


def two_pass_spec():
    data = copy.deepcopy(PRESETS["ci"])
    data["scratch"].update(passes=2, depth=DEPTH, length=LENGTH, speed=V_S, load_speed=V_N)
    return scratch_spec(data)


def test_encoded_path_equals_the_stroke_written_here():
    spec = two_pass_spec()
    formulas = path_formulas(spec.stroke)
    text = scratch_input(spec)
    for name, formula in formulas.items():
        assert f"variable {name} equal {formula}" in text
    assert "sphere v_x_tip 0 v_zc" in text
    times = np.linspace(0.0, 2 * T1 + 2 * T + 1e-9, 997)
    for t in times:
        want_x, want_d = stroke_by_hand(t)
        # the formulas are in um of v_t in ns: numbers, v_t, abs, + - * and parentheses
        env = {"abs": abs, "__builtins__": {}}
        x_um = eval(formulas["x_tip"].replace("v_t", repr(float(t) * 1e9)), env)
        d_um = eval(formulas["depth"].replace("v_t", repr(float(t) * 1e9)), env)
        assert x_um * 1e-6 == pytest.approx(want_x, abs=1e-15)
        assert d_um * 1e-6 == pytest.approx(want_d, abs=1e-15)
        x, d = tip_path(spec.stroke, t)
        assert float(x) == pytest.approx(want_x, abs=1e-15)
        assert float(d) == pytest.approx(want_d, abs=1e-15)


# ---- the frictionless elastic limit (LAMMPS) --------------------------------------------------

@pytest.fixture(scope="module")
def ci_scratch(tmp_path_factory):
    return run_scratch(preset("ci"), tmp_path_factory.mktemp("ci_scratch"))


def reference_indent_load(spec, run_dir):
    """`particles indent` on the scratch's material, tip, spacing, width and depth at the
    scratch depth: held there, the mean load over the hold's second half (N)."""
    g, s = spec.grid, spec.stroke
    mat = spec.target.substrate
    indent = spec_from_mapping({
        "name": "ref", "method": "tlsph", "tip": spec.tip.spec,
        "target": {"substrate": {"E": mat.material.E, "nu": mat.material.nu,
                                 "density": mat.density}},
        "grid": {"spacing": g.spacing, "width": g.width, "depth": g.depth, "quarter": True},
        "loading": {"depth": s.depth, "speed": s.load_speed, "hold_time": 4e-9,
                    "frames": 0, "unload": False}}, "indent")
    run = run_particles(indent, run_dir)
    t1, t2, _ = indent.loading.times
    held = run.time > 0.5 * (t1 + t2)
    return float(run.load[held].mean()), run


def test_frictionless_elastic_limit(ci_scratch, tmp_path):
    spec = ci_scratch.spec
    assert spec.target.elastic
    a = analyze_scratch(ci_scratch)
    # lateral force within its noise of zero (measured: mean 1.9e-6 N against a scatter of
    # the friction of 0.0066, mean friction 0.00045)
    assert abs(a.friction_mean) < a.friction_std
    assert abs(a.lateral_force_mean) < 0.01 * a.normal_force_mean
    # no residual groove: the surface particles come back within 1 % of a spacing
    # (measured 0.23 nm on a 200 nm spacing)
    dx = spec.grid.spacing
    assert abs(a.groove_depth) < 0.01 * dx
    assert abs(a.pileup_height) < 0.01 * dx
    assert a.damage[0].width == 0.0 and a.damage[0].depth == 0.0
    assert np.isnan(a.scratch_hardness)           # no plastic groove, no scratch hardness
    # the normal force equals the indentation load at the same depth within 3 % (measured
    # 4.158 mN against 4.078 mN: +2.0 %)
    P_indent, _ = reference_indent_load(spec, tmp_path / "indent")
    assert a.normal_force_mean == pytest.approx(P_indent, rel=0.03)


def test_record_and_rerun_without_lammps(ci_scratch):
    a = analyze_scratch(ci_scratch)
    path = write_scratch_record(ci_scratch, a, {"command": "test"})
    with h5py.File(path, "r") as f:
        assert f.attrs["format"] == "filmscale.md_particle_scratch/1"
        assert f["analysis"].attrs["normal_force_mean"] == pytest.approx(a.normal_force_mean)
        np.testing.assert_allclose(f["history/normal_force"][()], ci_scratch.fz)
        assert "in.tlsph" in f["inputs"]
    again = run_scratch(ci_scratch.spec, ci_scratch.run_dir)      # finished: read back
    np.testing.assert_array_equal(again.fz, ci_scratch.fz)
    # a sliding scene's friction_from reads a particle record as it reads an MD one
    from filmscale.md.scratch_run import read_scratch_friction
    friction = read_scratch_friction(path)
    assert (friction.mean, friction.std, friction.points) == (
        pytest.approx(a.friction_mean), pytest.approx(a.friction_std), a.steady_points)


# ---- spec errors ------------------------------------------------------------------------------

SPEC = """
name = "t"
tip = "{tip}"
[target.substrate]
E = 70e9
nu = 0.3
[grid]
spacing = {spacing}
width = 1.2e-6
depth = 1.2e-6
[scratch]
depth = 1e-7
length = 1e-6
speed = {speed}
{extra}
"""


@pytest.mark.parametrize("tip, spacing, speed, extra, message", [
    ("sphere:1um", 2.5e-7, 100.0, "", "grid.spacing = 2.5e-07 m is too coarse"),
    ("cone:70.3", 2e-7, 100.0, "", "takes a sphere"),
    ("sphere:1um", 2e-7, 1000.0, "", "scratch.speed = 1000 m/s is not quasi-static"),
    ("sphere:1um", 2e-7, 100.0, "passes = 0", "scratch.passes = 0"),
    ("sphere:1um", 2e-7, 100.0, "stroke = 1", "stroke"),
])
def test_bad_scratch_specs_exit_2_with_one_line(tmp_path, capsys, tip, spacing, speed, extra,
                                                message):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.format(tip=tip, spacing=spacing, speed=speed, extra=extra))
    out = tmp_path / "run"
    assert main(["particles", "scratch", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not out.exists()


def test_layered_target_preset_and_source_errors(tmp_path, capsys):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.format(tip="sphere:1um", spacing=2e-7, speed=100.0, extra="") +
                    "[[target.films]]\nthickness = 2e-7\nE = 200e9\nnu = 0.25\n")
    assert main(["particles", "scratch", str(path)]) == 2
    assert "method = 'ulsph'" in capsys.readouterr().err
    assert main(["particles", "scratch", "--preset", "huge"]) == 2
    assert "preset" in capsys.readouterr().err
    assert main(["particles", "scratch"]) == 2
    assert "--preset" in capsys.readouterr().err


def test_second_pass_in_its_own_groove_ploughs_less(tmp_path):
    """Plastic Al (sigma_y 0.3 GPa) scratched twice at one depth: the second pass slides in
    the groove the first ploughed, so it carries less load and far less lateral force
    (measured, 3 passes: friction 0.247, 0.027, 0.008; normal force 0.43, 0.16, 0.14 mN)."""
    data = copy.deepcopy(PRESETS["ci"])
    data["target"]["substrate"]["sigma_y"] = 0.3e9
    data["scratch"]["passes"] = 2
    a = analyze_scratch(run_scratch(scratch_spec(data), tmp_path))
    first, second = a.passes
    # the first pass is the analysis's steady stroke
    assert first.friction_mean == a.friction_mean and first.points == a.steady_points
    assert first.friction_mean > 0.1 and second.points > 0.8 * first.points
    assert second.friction_mean < 0.5 * first.friction_mean
    assert second.normal_force_mean < 0.7 * first.normal_force_mean
