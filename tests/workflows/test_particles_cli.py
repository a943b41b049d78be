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


@pytest.mark.parametrize("alloy, forward_gpa", [("6061", 28.2), ("7075", 44.8)])
def test_dao_example_specs_hold_dao_s_materials(alloy, forward_gpa):
    """The example specs load, carry a 70.3 degree cone, and their alloys are Dao's: Al 6061's
    sigma_y and n equal those of the packaged measured indents (Al6061.csv), and Dao's forward
    C of each alloy is the one the spec's comment quotes (to its 0.1 GPa)."""
    import csv
    from pathlib import Path

    from filmscale.continuum.indentation.reverse.functions import loading_curvature
    from filmscale.md.particle_spec import load_spec
    root = Path(__file__).resolve().parents[2]
    spec = load_spec(root / "examples" / "particles" / f"dao_al{alloy}.toml", "indent", None)
    mat = spec.target.substrate.material
    assert spec.tip.spec.startswith("cone:70.3")
    if alloy == "6061":
        data = root / "continuum" / "indentation" / "reverse" / "data" / "dao2001" / "Al6061.csv"
        with data.open(encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        assert {float(r["sy (GPa)"]) for r in rows} == {mat.sigma_y / 1e9}
        assert {float(r["n"]) for r in rows} == {mat.n}
    C, ok = loading_curvature("berkovich", mat.E, mat.plane_strain_modulus, mat.sigma_y, mat.n)
    assert bool(ok) and float(C) / 1e9 == pytest.approx(forward_gpa, abs=0.05)
