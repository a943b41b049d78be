"""`filmscale md indent` and `filmscale potentials` from the command line: bad input gets
one line and exit status 2 before LAMMPS starts; the ci preset prints the promised JSON."""

import json
import subprocess
import sys
import time

import pytest

from filmscale.workflows.cli import main

SPEC = """
name = "cli-test"
[potential]
name = "{potential}"
[slab]
lateral_size = {lateral}
[[slab.films]]
element = "Cu"
thickness = {film}
[slab.substrate]
element = "{substrate}"
thickness = 2.2e-9
[indenter]
radius = {radius}
[protocol]
depth = {depth}
"""
GOOD = dict(potential="CuNi", lateral=3.7e-9, film=1.1e-9, substrate="Ni", radius=8e-10,
            depth=4e-10)


def _run(tmp_path, capsys, **changes):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC.format(**{**GOOD, **changes}))
    started = time.perf_counter()
    code = main(["md", "indent", str(spec), "--out", str(tmp_path / "run")])
    return code, capsys.readouterr().err, time.perf_counter() - started


@pytest.mark.parametrize("changes, message", [
    (dict(substrate="Al"), "Al"),                                  # not in CuNi
    (dict(film=1.5e-10), "thinner than one lattice period"),
    (dict(radius=2e-9, depth=1.5e-9), "footprint"),
    (dict(depth=3e-9), "below the mobile atoms"),
    (dict(potential="CuNi_nonexistent"), "CuNi_nonexistent"),
])
def test_bad_input_exits_2_with_one_line_before_lammps(tmp_path, capsys, changes, message):
    code, err, seconds = _run(tmp_path, capsys, **changes)
    assert code == 2
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "run").exists()          # nothing written, LAMMPS never started
    assert seconds < 5.0


def test_missing_spec_file_and_missing_potential_file(tmp_path, capsys):
    assert main(["md", "indent", str(tmp_path / "nope.toml")]) == 2
    assert "nope.toml" in capsys.readouterr().err
    spec = tmp_path / "own.toml"
    spec.write_text(SPEC.format(**GOOD).replace('name = "CuNi"', '''file = "mine.eam.alloy"
name = "mine"
elements = ["Cu", "Ni"]
pair_style = "eam/alloy"
citation = "nobody"'''))
    assert main(["md", "indent", str(spec)]) == 2
    assert "mine.eam.alloy" in capsys.readouterr().err


def test_potentials_commands(capsys):
    assert main(["potentials", "list"]) == 0
    out = capsys.readouterr().out
    assert "Cu_mishin1" in out and "SiC" in out
    assert main(["potentials", "show", "CuNi"]) == 0
    assert "Onat" in capsys.readouterr().out
    assert main(["potentials", "show", "nope"]) == 2
    assert main(["potentials", "verify"]) == 0


def test_ci_preset_json(tmp_path):
    """The promised keys, in SI, from a real run (the process shows no traceback)."""
    result = subprocess.run([sys.executable, "-m", "filmscale.workflows.cli", "md", "indent",
                             "--preset", "ci", "--out", str(tmp_path / "ci"), "--json"],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    for key in ("P_max", "h_max", "residual_depth", "E_r_hertz", "popin_load", "result"):
        assert key in data
    assert data["h_max"] == pytest.approx(4e-10)
    assert 1e-9 < data["P_max"] < 1e-6              # tens of nN
    assert 50e9 < data["E_r_hertz"] < 300e9
    assert data["result"].endswith("indent.h5")


@pytest.fixture
def recorded(monkeypatch):
    """`md indent` on the recorded ci run (tests/md/recorded/ci): no LAMMPS for the
    indentation; the potential's elastic constants still run (a second)."""
    from filmscale.md import record as md_record
    from filmscale.md import run as md_run
    from tests.helpers.engines import RecordedEngine
    monkeypatch.setattr(md_run, "run_input", RecordedEngine())
    monkeypatch.setattr(md_record, "lammps_info", dict)


def test_the_summary_shows_what_indent_analyze_says_of_the_record(tmp_path, capsys, recorded):
    """The summary's Oliver-Pharr line and flags, the --json "oliver_pharr" and the --plot
    are those of `indent analyze` on the record the run wrote (oracle: that command's own
    JSON record). On the recorded ci run its unloading does not fit, and it raises
    displacement_offset and surface_shift."""
    png = tmp_path / "curve.png"
    assert main(["md", "indent", "--preset", "ci", "--out", str(tmp_path / "run"), "--plot",
                 str(png)]) == 0
    summary = capsys.readouterr().out
    assert main(["indent", "analyze", str(tmp_path / "run" / "indent.h5"), "--json"]) == 1
    (analysed,) = map(json.loads, capsys.readouterr().out.splitlines())
    assert analysed["status"] == 1 and analysed["flags"] == ["displacement_offset",
                                                             "surface_shift"]
    assert (f"Oliver-Pharr (as indent analyze on the record): not analysed: "
            f"{analysed['message']}; flags: displacement_offset, surface_shift") in summary
    for code, message in zip(analysed["flags"], analysed["flag_messages"]):
        assert f"\n  {code}: {message}\n" in summary
    assert f"plot: {png}" in summary and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # --json: every key it had, and the same record (the run is read back, not rerun)
    assert main(["md", "indent", "--preset", "ci", "--out", str(tmp_path / "run"),
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {"P_max", "E_r_hertz", "contact_area_op", "pile_up", "result"} <= set(data)
    assert data["plot"] is None
    assert data["oliver_pharr"] == {k: analysed.get(k) for k in data["oliver_pharr"]}
    assert set(data["oliver_pharr"]) >= {"E_r", "H", "status", "flags", "flag_messages"}


def test_an_analysed_record_shows_its_moduli_and_flags(tmp_path):
    """`oliver_pharr_text` of an analysed curve: E_r, H and A_c as `indent analyze`'s record
    has them, its flags with their messages (a curve whose depth zero sits 5 nm off)."""
    import h5py

    from filmscale.continuum.indentation.io import write_curve_group
    from filmscale.continuum.indentation.synthetic import synthetic_curve
    from filmscale.continuum.indentation.tips import berkovich
    from filmscale.workflows.md_cli import oliver_pharr_text, record_oliver_pharr
    c = synthetic_curve(150e9, 15e9, berkovich(), h_c=50e-9, m=1.4, noise=0.001, seed=1)
    path = tmp_path / "shifted.h5"
    with h5py.File(path, "w") as f:           # a file of one curve that names its tip
        write_curve_group(f.create_group("curve"), c.shifted(-5e-9))
    r = record_oliver_pharr(path)
    assert r["status"] == 0 and "surface_shift" in r["flags"]
    text = oliver_pharr_text(r)
    assert text.startswith(f"Oliver-Pharr (as indent analyze on the record): E_r "
                           f"{r['E_r'] / 1e9:.1f} GPa, H {r['H'] / 1e9:.2f} GPa, A_c "
                           f"{r['A_c'] * 1e18:.2f} nm^2; flags: {', '.join(r['flags'])}")
    assert f"  surface_shift: {r['flag_messages'][r['flags'].index('surface_shift')]}" in text
    assert oliver_pharr_text({**r, "flags": [], "flag_messages": []}).endswith("; no flags")


@pytest.mark.parametrize("plot, make, message", [
    ("curve.txt", None, "--plot"),                                  # not an image format
    ("curve.png", "notes", "exists and is"),                        # another file
])
def test_a_bad_plot_exits_2_before_the_run(tmp_path, capsys, plot, make, message):
    path = tmp_path / plot
    if make:
        path.write_text(make)
    code = main(["md", "indent", "--preset", "ci", "--out", str(tmp_path / "run"), "--plot",
                 str(path)])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1
    assert not (tmp_path / "run").exists()
