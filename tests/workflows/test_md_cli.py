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
