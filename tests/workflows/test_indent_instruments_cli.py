"""`filmscale indent analyze` on instrument exports and `filmscale indent calibrate`."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.cycles import synthetic_multicycle
from filmscale.continuum.indentation.io import read_area_function, read_frame_compliance
from filmscale.continuum.indentation.tips import berkovich
from filmscale.continuum.indentation.vendors import FORMATS
from filmscale.workflows.cli import main
from filmscale.workflows.indent_calibrate import FORMAT_CHOICES
from tests.helpers.instruments import (write_anton_paar, write_g200, write_hld, write_native,
                                       write_triboscan)
from tests.helpers.tip_references import C_F, NM, TRUE_AREA, reference_curves

FILMSCALE = Path(sys.executable).with_name("filmscale")


def _rows(capsys):
    captured = capsys.readouterr()
    return {r["name"]: r for r in map(json.loads, captured.out.splitlines())}, captured.err


def test_a_folder_of_every_layout_gives_one_answer(tmp_path, capsys):
    curve = synthetic_curve(69.6e9, 9e9, berkovich(), h_c=150e-9)
    d = tmp_path / "lab"
    d.mkdir()
    write_native(d / "native.csv", curve)
    write_g200(d / "g200.xlsx", [curve])
    write_triboscan(d / "tribo.txt", curve)
    write_hld(d / "hys.hld", curve)
    write_anton_paar(d / "ap.csv", curve)
    assert main(["indent", "analyze", str(d), "--tip", "berkovich", "--json"]) == 0
    rows, _ = _rows(capsys)
    assert sorted(rows) == ["ap", "g200:Test 001", "hys", "native", "tribo"]   # none skipped
    for r in rows.values():
        # the same numbers in every file: only the unit factors' 1e-16 rounding differs
        assert r["E_r"] == pytest.approx(rows["native"]["E_r"], rel=1e-9)
        assert r["H"] == pytest.approx(rows["native"]["H"], rel=1e-9)
        assert r["E_r"] == pytest.approx(69.6e9, rel=1e-6)


def test_unreadable_workbook_is_named_and_exits_2_without_traceback(tmp_path):
    curve = synthetic_curve(69.6e9, 9e9, berkovich(), h_c=150e-9)
    write_native(tmp_path / "good.csv", curve)
    (tmp_path / "broken.xlsx").write_bytes(b"PK\x03\x04 cut short")
    run = subprocess.run([str(FILMSCALE), "indent", "analyze", str(tmp_path), "--tip",
                          "berkovich"], capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert "broken: cannot read" in run.stderr and "as an Excel workbook (.xls or .xlsx)" in run.stderr
    assert "good" in run.stdout


def test_column_mapping_on_the_command_line(tmp_path, capsys):
    curve = synthetic_curve(100e9, 8e9, berkovich(), h_c=100e-9)
    f = tmp_path / "raw.tsv"
    f.write_text("\n".join(f"{a:.12g}\t{b:.12g}" for a, b in zip(curve.h * 1e6, curve.P * 1e3)))
    assert main(["indent", "analyze", str(f), "--tip", "berkovich", "--json", "--columns",
                 "h=1:um,P=2:mN"]) == 0
    rows, _ = _rows(capsys)
    assert rows["raw"]["E_r"] == pytest.approx(100e9, rel=1e-6)
    assert main(["indent", "analyze", str(f), "--tip", "berkovich", "--columns", "h=1"]) == 2
    assert "give one of m, mm, um" in capsys.readouterr().err
    assert main(["indent", "analyze", str(f), "--tip", "berkovich", "--columns", "x=1:nm"]) == 2
    assert "role 'x' is not one of h, P, t" in capsys.readouterr().err


def test_calibrate_then_analyse_a_multicycle_test(tmp_path, capsys):
    (tmp_path / "ref").mkdir()
    write_g200(tmp_path / "ref" / "silica.xlsx", reference_curves())
    sample = synthetic_multicycle(150e9, 12e9, TRUE_AREA, frame_compliance=C_F,
                                  h_c=np.geomspace(25 * NM, 300 * NM, 5))
    write_triboscan(tmp_path / "film.txt", sample)
    tip = tmp_path / "tip.toml"
    assert main(["indent", "calibrate", str(tmp_path / "ref"), "--reference", "fused-silica",
                 "--terms", "3", "--out", str(tip)]) == 0
    out = capsys.readouterr().out
    assert "frame compliance C_f = 0.3 nm/mN" in out and "12 indents" in out
    # the file analyze reads: the blunted area and the frame (tolerances as in
    # tests/continuum/test_tip_calibration.py: noise-free data of the fitted model)
    h = np.geomspace(20 * NM, 360 * NM, 10)
    np.testing.assert_allclose(read_area_function(tip).area(h), TRUE_AREA.area(h), rtol=1e-5)
    assert read_frame_compliance(tip) == pytest.approx(C_F, rel=1e-4)
    assert main(["indent", "analyze", str(tmp_path / "film.txt"), "--tip", "berkovich",
                 "--area-file", str(tip), "--cycles", "--json"]) == 0
    rows, _ = _rows(capsys)
    assert sorted(rows) == [f"film#{k}" for k in range(1, 6)]
    np.testing.assert_allclose([r["E_r"] for r in rows.values()], 150e9, rtol=1e-4)
    np.testing.assert_allclose([r["H"] for r in rows.values()], 12e9, rtol=1e-4)
    np.testing.assert_allclose(sorted(r["h_c"] for r in rows.values()),
                               np.geomspace(25 * NM, 300 * NM, 5), rtol=1e-4)
    # --frame-compliance given on the command line wins over the file's
    assert main(["indent", "analyze", str(tmp_path / "film.txt"), "--tip", "berkovich",
                 "--area-file", str(tip), "--frame-compliance", "0", "--json"]) == 0
    rows, _ = _rows(capsys)
    assert rows["film"]["E_r"] < 0.99 * 150e9
    # an existing file that is not an area file is kept
    other = tmp_path / "notes.toml"
    other.write_text("title = 'mine'\n")
    assert main(["indent", "calibrate", str(tmp_path / "ref"), "--reference", "fused-silica",
                 "--out", str(other)]) == 2
    assert "exists and is" in capsys.readouterr().err and "title" in other.read_text()


@pytest.mark.parametrize("argv, message", [
    (["--reference", "quartz"], "reference = 'quartz' is not one of"),
    (["--reference", "tungsten", "--fit", "area", "--area-file", "a.toml"],
     "--area-file is the area function kept by --fit frame"),
    (["--reference", "tungsten", "--frame-compliance", "1e-7"],
     "--frame-compliance is the compliance kept by --fit area"),
    (["--reference", "tungsten", "--terms", "12"], "--terms = 12 is outside"),
    (["--reference", "tungsten", "--tip", "vickers"], "tip = 'vickers' is not one of"),
    (["--reference", "tungsten", "--window", "0.5:0.2"], "--window end = 0.2"),
])
def test_calibrate_bad_options_exit_2(tmp_path, capsys, argv, message):
    write_native(tmp_path / "c.csv", synthetic_curve(69.6e9, 9e9, berkovich(), h_c=150e-9))
    assert main(["indent", "calibrate", str(tmp_path / "c.csv"), "--out",
                 str(tmp_path / "tip.toml"), *argv]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "tip.toml").exists()


def test_format_choices_match_the_readers():
    assert FORMAT_CHOICES == FORMATS


def test_calibrate_area_only_as_json_from_text_read_with_a_reader_file(tmp_path, capsys):
    lines = []
    for k, curve in enumerate(reference_curves()):
        f = tmp_path / f"silica{k}.dat"     # unit-less names: the reader file gives them
        f.write_text("z;F\n" + "\n".join(f"{a:.12g};{b:.12g}".replace(".", ",")
                                          for a, b in zip(curve.h * 1e9, curve.P * 1e3)))
        lines.append(str(f))
    reader = tmp_path / "reader.toml"
    reader.write_text('[columns]\nh = "z"\nP = "F"\n[units]\nh = "nm"\nP = "mN"\n')
    assert main(["indent", "calibrate", *lines, "--reader", str(reader), "--reference",
                 "E=72GPa,nu=0.17", "--fit", "area", "--terms", "3", "--frame-compliance",
                 str(C_F), "--json", "--out", str(tmp_path / "tip.toml")]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["frame_compliance"] == C_F and data["reference_E"] == 72e9       # SI
    # C_f is given exactly: only the 12-digit text and the power-law refits (1e-8) stand
    # between the files and the generating polynomial, so the area comes back within 1e-6;
    # the coefficients within 1e-4, as C1 h and C2 h^(1/2) trade off a little
    np.testing.assert_allclose(data["coefficients"], TRUE_AREA.coefficients, rtol=1e-4)
    h = np.geomspace(20 * NM, 360 * NM, 10)
    np.testing.assert_allclose(read_area_function(tmp_path / "tip.toml").area(h),
                               TRUE_AREA.area(h), rtol=1e-6)
