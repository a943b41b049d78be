"""`filmscale indent analyze`: JSON keys, batch folders, flags, HDF5, profile file, errors."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_table
from filmscale.continuum.indentation.tips import berkovich
from filmscale.workflows.cli import main
from filmscale.workflows.result import read_indentation_results

FILMSCALE = Path(sys.executable).with_name("filmscale")
KEYS = ("E_r", "H", "h_c", "S", "P_max", "h_max", "A_c", "flags")
DEPTHS = (10e-9, 20e-9, 40e-9, 80e-9)


def truth(h_c):
    return np.interp(h_c, [0, 30e-9, 100e-9], [180e9, 140e9, 110e9]), \
        np.interp(h_c, [0, 30e-9, 100e-9], [18e9, 12e9, 9e9])


def write_curve(path, curve):
    np.savetxt(path, np.column_stack([curve.h * 1e9, curve.P * 1e6, curve.t]), delimiter=", ",
               header="h [nm], P [uN], t [s]", comments="")


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "indents"
    d.mkdir()
    for k, h_c in enumerate(np.repeat(DEPTHS, 2)):
        E_r, H = truth(h_c)
        write_curve(d / f"i{k}.csv", synthetic_curve(E_r, H, berkovich(), h_c=h_c, m=1.4,
                                                     noise=0.001, seed=k))
    return d


def test_json_lines_recover_properties(folder, capsys):
    assert main(["indent", "analyze", str(folder), "--tip", "berkovich", "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(rows) == 8
    for row in rows:
        assert all(k in row for k in KEYS)
        E_r, H = truth(row["h_c"])
        # 0.1 % load noise: well inside the 1 % of the synthetic-curve test
        assert row["E_r"] == pytest.approx(E_r, rel=0.01) and row["H"] == pytest.approx(H, rel=0.01)
        assert row["flags"] == []


def test_outputs_profile_and_plots(folder, tmp_path, capsys):
    out, prof, plots = tmp_path / "r.h5", tmp_path / "p.csv", tmp_path / "plots"
    code = main(["indent", "analyze", str(folder), "--tip", "berkovich", "--layers", "30nm",
                 "--layer-names", "DLC,CoCrPt", "--out", str(out), "--profile", str(prof),
                 "--plot", str(plots), "--workers", "1"])
    assert code == 0
    text = capsys.readouterr().out
    assert "DLC: 4 indents" in text and "CoCrPt: 4 indents" in text
    data, attrs = read_indentation_results(out)
    assert len(data["name"]) == 8 and data["E_r"].shape == (8,)
    assert "filmscale_version" in attrs
    table = read_table(prof, required=("h_c", "E_r", "H"))      # what a scene reads
    np.testing.assert_allclose(np.sort(table["h_c"]), np.sort(data["h_c"]), rtol=1e-9)
    assert (plots / "profile.png").stat().st_size > 0 and len(list(plots.glob("i*.png"))) == 8


def test_flags_and_unreadable_files(tmp_path, capsys):
    c = synthetic_curve(150e9, 15e9, berkovich(), h_c=50e-9)
    write_curve(tmp_path / "load_only.csv", type(c)(c.h[:240], c.P[:240], c.t[:240]))
    write_curve(tmp_path / "good.csv", c)
    (tmp_path / "broken.csv").write_text("h [nm], P [uN]\n1, 2, 3\n")
    code = main(["indent", "analyze", str(tmp_path / "load_only.csv"), str(tmp_path / "good.csv"),
                 str(tmp_path / "broken.csv"), "--tip", "berkovich", "--json"])
    captured = capsys.readouterr()
    rows = {r["name"]: r for r in map(json.loads, captured.out.splitlines())}
    assert code == 2            # an unreadable file is bad input, after the rest was analysed
    assert "no_unloading" in rows["load_only"]["flags"] and rows["load_only"]["E_r"] is None
    assert rows["good"]["E_r"] == pytest.approx(150e9, rel=1e-6)
    assert rows["broken"]["flags"] == ["unreadable"] and "broken" in captured.err


@pytest.mark.parametrize("argv, message", [
    (["--tip", "vickers"], "tip = 'vickers' is not one of"),
    (["--tip", "cone:120"], "cone half_angle = 120"),
    (["--tip", "berkovich", "--window", "0.5:0.3"], "--window end = 0.3"),
    (["--tip", "berkovich", "--beta", "hay"], "needs the sample Poisson ratio --nu"),
    (["--tip", "berkovich", "--out", "results.txt"], "must end in one of .h5"),
])
def test_bad_options_exit_2_without_traceback(folder, argv, message):
    run = subprocess.run([str(FILMSCALE), "indent", "analyze", str(folder), *argv],
                         capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 2
    assert message in run.stderr and "Traceback" not in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1


def test_missing_path_is_an_input_error(tmp_path, capsys):
    assert main(["indent", "analyze", str(tmp_path / "absent.csv"), "--tip", "berkovich"]) == 2
    assert "does not exist" in capsys.readouterr().err


ORACLE = ["--C", "43.840e9", "--dPdh", "4.3354e5", "--WpWt", "0.8242", "--hm", "1e-6",
          "--nu", "0.33"]


def test_reverse_json_has_every_value_with_its_std(capsys):
    assert main(["indent", "reverse", *ORACLE, "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    for key in ("E_star", "sigma_r", "n", "sigma_y"):
        assert key in row and f"{key}_std" in row
    # docs/physics.md round-trip oracle (inputs given to 5 digits): E* = 73.440 GPa,
    # sigma_0.033 = 0.6173 GPa, n = 0.122, sigma_Y = 0.5 GPa, E = 70.1 GPa
    assert row["E_star"] == pytest.approx(73.440e9, rel=1e-4)
    assert row["sigma_r"] == pytest.approx(0.6173e9, rel=2e-4)
    assert row["n"] == pytest.approx(0.122, abs=2e-3)
    assert row["sigma_y"] == pytest.approx(0.5e9, rel=0.01)
    assert row["E"] == pytest.approx(70.1e9, rel=1e-3)
    assert row["E_star_std"] == 0.0


def test_reverse_uncertainty_and_dual(capsys):
    assert main(["indent", "reverse", *ORACLE, "--C-std", "1e9", "--dPdh-std", "4e3",
                 "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["E_star_std"] > 0 and row["sigma_r_std"] > 0
    assert main(["indent", "reverse", *ORACLE, "--C2", "20e9"]) == 2     # --tip2 missing
    assert "--C2 and --tip2" in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    (["--C", "-1", "--dPdh", "4e5", "--WpWt", "0.8", "--hm", "1e-6"], "C = -1 Pa"),
    (["--C", "4e10", "--dPdh", "4e5", "--WpWt", "1.2", "--hm", "1e-6"], "WpWt = 1.2"),
    (["--C", "4e10", "--dPdh", "4e5", "--WpWt", "0.8", "--hm", "1e-6", "--tip", "cone:30"],
     "tip"),
])
def test_reverse_bad_input_exit_2(argv, message):
    run = subprocess.run([str(FILMSCALE), "indent", "reverse", *argv], capture_output=True,
                         text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 2 and message in run.stderr and "Traceback" not in run.stderr


def test_pool_and_single_process_agree(tmp_path):
    # 64 files start the process pool; its records must equal the in-process ones
    from filmscale.workflows.indent import AnalysisOptions, analyze_files
    paths = []
    for k in range(64):
        p = tmp_path / f"c{k:02d}.csv"
        write_curve(p, synthetic_curve(100e9 + 1e9 * k, 10e9, berkovich(), h_c=50e-9, m=1.4,
                                       noise=0.001, seed=k))
        paths.append(p)
    options = AnalysisOptions(tip="berkovich")
    pooled = analyze_files(paths, options, workers=2, progress=False)
    single = analyze_files(paths, options, workers=1, progress=False)
    assert [r["name"] for r in pooled] == [p.stem for p in paths]
    assert [r["E_r"] for r in pooled] == [r["E_r"] for r in single]


def test_area_file_in_instrument_units(folder, tmp_path, capsys):
    from filmscale.continuum.indentation.io import read_area_function
    from filmscale.continuum.indentation.tips import PolynomialArea
    area = tmp_path / "area.toml"
    area.write_text('length_unit = "nm"\nC = [24.494, 1000.0]\n')
    # A [nm^2] = 24.494 h^2 + 1000 h [nm]  ->  C1 = 1000 nm = 1e-6 m in SI
    tip = read_area_function(area)
    assert tip.coefficients == (24.494, pytest.approx(1e-6, rel=1e-12))
    assert tip.area(50e-9) == pytest.approx((24.494 * 50**2 + 1000 * 50) * 1e-18, rel=1e-12)
    assert main(["indent", "analyze", str(folder / "i0.csv"), "--tip", "berkovich",
                 "--area-file", str(area), "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["A_c"] == pytest.approx(float(PolynomialArea((24.494, 1e-6)).area(row["h_c"])))
    area.write_text("C = 'many'\n")
    assert main(["indent", "analyze", str(folder), "--tip", "berkovich",
                 "--area-file", str(area)]) == 2
    assert "C must be a list" in capsys.readouterr().err


def test_shallow_correction_uses_the_elastic_indent(folder, capsys):
    # an elastic indent: P = K h^1.5 loaded and unloaded along one path, so W_p = 0 and
    # h_e = h_me - 0.75 P_e / S_e = h_me / 2 (S = 1.5 P / h)
    h = np.linspace(0, 4e-9, 200)
    P = 2e-3 * (h / 4e-9)**1.5 * 1e-3
    hh, PP = np.concatenate([h, h[-2::-1]]), np.concatenate([P, P[-2::-1]])
    np.savetxt(folder / "elastic.csv", np.column_stack([hh * 1e9, PP * 1e6]), delimiter=", ",
               header="h [nm], P [uN]", comments="")
    assert main(["indent", "analyze", str(folder), "--tip", "berkovich", "--json",
                 "--shallow-correction", "--no-drift"]) == 0
    rows = {r["name"]: r for r in map(json.loads, capsys.readouterr().out.splitlines())}
    h_e = rows["elastic"]["h_max"] - 0.75 * rows["elastic"]["P_max"] / rows["elastic"]["S"]
    assert h_e == pytest.approx(2e-9, rel=0.01)     # the fit window sees a pure h^1.5 law
    r = rows["i7"]
    # Yeo-Polycarpou with A = k h^2: H_shallow = H h_c / (h_c - h_e)
    assert r["H_shallow"] == pytest.approx(r["H"] * r["h_c"] / (r["h_c"] - h_e), rel=1e-9)


def test_the_table_names_every_curve_whole_and_shows_E_with_nu(folder, capsys):
    """Names up to 40 characters widen the curve column to the longest of them; a longer one
    is printed whole on a line of its own, its figures on the next line in the same columns. --nu adds E (oracle:
    E from E_r, nu and diamond, as the JSON has it)."""
    from filmscale.workflows.indent_cli import NAME_WIDTH_MAX
    long = "sample_2024-05-17_DLC_on_CoCrPt_array_row03_col17"       # 49 characters
    middle = "DLC_on_CoCrPt_row03_col17_second_run"                    # 36 characters
    assert len(middle) < NAME_WIDTH_MAX < len(long)
    (folder / "i0.csv").rename(folder / f"{long}.csv")
    (folder / "i1.csv").rename(folder / f"{middle}.csv")
    assert main(["indent", "analyze", str(folder), "--tip", "berkovich", "--nu", "0.25",
                 "--json"]) == 0
    rows = {r["name"]: r for r in map(json.loads, capsys.readouterr().out.splitlines())}
    assert main(["indent", "analyze", str(folder), "--tip", "berkovich", "--nu", "0.25"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header = lines[0]
    assert header.split()[:4] == ["curve", "E_r", "[GPa]", "E"]
    # the curve column is as wide as the longest name that fits in it
    assert header.startswith("curve" + " " * (len(middle) - 5) + "  E_r [GPa]")
    own = lines.index(long)                       # the long name alone on its line
    figures = lines[own + 1]
    assert figures.startswith(" " * len(middle)) and not lines[own + 1].startswith(long)
    E = f"{rows[long]['E'] / 1e9:.4g}"
    assert figures.split()[:2] == [f"{rows[long]['E_r'] / 1e9:.4g}", E]
    assert any(line.startswith(middle + " ") for line in lines)
    # the columns line up: each figure ends where its header does
    end = header.index("E [GPa]") + len("E [GPa]")
    assert figures[:end].endswith(E)


def test_a_standard_deviation_follows_its_value():
    """A record that has E_r_std (and E_std, H_std) shows each +- its deviation; the column
    widens to it."""
    from filmscale.workflows.indent_cli import _table
    record = {"name": "c", "status": 0, "E_r": 150.0e9, "E_r_std": 2.5e9, "E": 160e9,
              "H": 15e9, "h_c": 50e-9, "S": 4e4, "flags": []}
    header, row = _table([record], csm=False, nu=0.25)
    assert "150 +- 2.5" in row and "160" in row
    assert row.index("150 +- 2.5") + len("150 +- 2.5") == header.index("E_r [GPa]") + 9
