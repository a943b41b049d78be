"""`filmscale particles`: bad input exits 2 with one line before LAMMPS starts."""

import pytest

from filmscale.workflows.cli import main

SPEC = """
name = "t"
method = "{method}"
tip = "sphere:1um"
[target.substrate]
E = 70e9
nu = 0.3
{extra}
[grid]
spacing = {spacing}
width = 2e-6
depth = 2e-6
quarter = {quarter}
[loading]
depth = 1e-7
speed = 50.0
"""


@pytest.mark.parametrize("method, spacing, quarter, extra, message", [
    ("tlsph", 4e-7, "true", "", "grid.spacing = 4e-07 m is too coarse"),
    ("peri", 1.25e-7, "false", "sigma_y = 3e8", "method = 'peri' models elastic targets"),
    ("peri", 1.25e-7, "true", "", "grid.quarter = true"),
])
def test_bad_particle_specs_exit_2_with_one_line(tmp_path, capsys, method, spacing, quarter,
                                                 extra, message):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.format(method=method, spacing=spacing, quarter=quarter, extra=extra))
    out = tmp_path / "run"
    assert main(["particles", "indent", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not out.exists()                      # nothing was started


def test_tlsph_refuses_a_layered_target_and_missing_files(tmp_path, capsys):
    path = tmp_path / "spec.toml"
    path.write_text(SPEC.format(method="tlsph", spacing=2e-7, quarter="true", extra="") +
                    "[[target.films]]\nthickness = 2e-7\nE = 200e9\nnu = 0.25\n")
    assert main(["particles", "indent", str(path)]) == 2
    assert "cannot bond a film" in capsys.readouterr().err
    assert main(["particles", "impact", str(tmp_path / "none.toml")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["particles", "impact", "--preset", "huge"]) == 2
