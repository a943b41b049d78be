"""`filmscale indent analyze` and `indent calibrate` end to end on instrument exports.

The oracles are written outside the package: the real exports of tests/data/instruments (the
instrument's own ``Results`` sheet, read here cell by cell with python_calamine), closed forms
(fused silica's 72 GPa), and synthetic curves whose answer is known (a depth zero misplaced by
a known offset, an area function negative at a known depth, the generating area function of
`tests.continuum.test_tip_calibration`).
"""

import json
import math
import time
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest
from python_calamine import CalamineWorkbook

from filmscale.continuum.indentation.curves import LOAD
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_area_function, write_curve_group
from filmscale.continuum.indentation.tips import PolynomialArea, berkovich
from filmscale.core.files import atomic_h5
from filmscale.workflows.cli import main
from tests.helpers.instruments import write_native
from tests.helpers.tip_references import (C_F, E_R_SILICA, NM, TRUE_AREA, reference_curves,
                                          shifted)

DATA = Path(__file__).resolve().parents[1] / "data" / "instruments"
FS = DATA / "FS_Calibration.xls"
#: tests/data/instruments/README.md: 16 + 12 + 2 + 10 tests in the workbooks, one .hld test
EXPECTED_NAMES = ({f"FS_Calibration:Test {k:03d}" for k in range(1, 17)}
                  | {f"Popin:Test {k:03d}" for k in range(1, 13)}
                  | {f"Example:Test {k:03d}" for k in range(1, 3)}
                  | {f"FQ:Test {k:03d}" for k in range(1, 11)}
                  | {"Exp-50mN_0000"})


def _run(argv, capsys) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of the command line; argparse's usage errors included."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exit_:
        code = exit_.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _records(out: str) -> dict[str, dict]:
    return {r["name"]: r for r in map(json.loads, out.splitlines())}


def _error_lines(err: str) -> list[str]:
    """The stderr lines that report a problem (the progress lines are not)."""
    return [line for line in err.splitlines()
            if ": error:" in line or "Traceback" in line or "internal error" in line
            or "refused" in line]


def _results_sheet() -> dict[int, tuple[float, float]]:
    """{test number: (E, H) in Pa} from the Results sheet of FS_Calibration.xls, read here
    cell by cell: columns 'E Average Over Defined Range' and 'H Average Over Defined Range'
    (GPa, the unit row under the header)."""
    rows = CalamineWorkbook.from_path(str(FS)).get_sheet_by_name("Results").to_python()
    header, units = rows[0], rows[1]
    e, h = header.index("E Average Over Defined Range"), header.index("H Average Over "
                                                                      "Defined Range")
    assert units[e] == units[h] == "GPa"
    return {int(float(r[0])): (r[e] * 1e9, r[h] * 1e9) for r in rows[2:]
            if str(r[0]).replace(".0", "").isdigit()}


def _number(name: str) -> int:
    return int(name.rsplit(" ", 1)[1])


# ---- the shared exports, read whole -------------------------------------------------------

def test_the_fixture_folder_gives_every_test_by_its_whole_name(capsys):
    """Every test of the five exports (README.md is not a curve suffix and is passed over):
    41 records, the names whole; exit 0 (no file unreadable). The plain table prints the
    longest names (23 characters, 'FS_Calibration:Test 012') whole too."""
    code, out, err = _run(["indent", "analyze", DATA, "--tip", "berkovich", "--json"], capsys)
    assert code == 0, err
    rows = _records(out)
    assert len(out.splitlines()) == 41 and set(rows) == EXPECTED_NAMES
    assert not [r for r in rows.values() if r["status"] == "unreadable"]
    assert not _error_lines(err)
    code, out, _ = _run(["indent", "analyze", DATA, "--tip", "berkovich"], capsys)
    assert code == 0
    lines = out.splitlines()
    assert all(any(line.startswith(name + " ") for line in lines) for name in EXPECTED_NAMES)
    assert any(line.startswith("FS_Calibration:Test 012 ") for line in lines)


def test_csm_with_the_files_own_area_function_matches_the_results_sheet(capsys):
    """FS_Calibration.xls, --csm --area-file file: each test's E and H averages against the
    instrument's own Results sheet (100-200 nm, nu 0.18, its area coefficients). Measured:
    averages +0.34 to +0.40 % in E and +0.66 to +0.75 % in H off the sheet; point by point
    against its Modulus and Hardness channels (vendor_difference, medians) +0.34 to +0.36 %
    and +0.64 to +0.67 %."""
    sheet = _results_sheet()
    assert sorted(sheet) == list(range(1, 17))
    start = time.perf_counter()
    code, out, err = _run(["indent", "analyze", FS, "--csm", "--area-file", "file", "--json"],
                          capsys)
    elapsed = time.perf_counter() - start
    assert code == 0, err
    # the budget for reading the 2.5 MB workbook and the CSM analysis of its 16 tests
    # is 2 s; measured 0.23-0.38 s here (of which 0.1 s the analysis the command reports)
    assert elapsed < 2.0
    rows = _records(out)
    assert len(rows) == 16
    for name, r in rows.items():
        E, H = sheet[_number(name)]
        assert r["status"] == 0 and r["nu_source"] == "file" and r["nu"] == 0.18
        assert r["vendor"]["E"] == pytest.approx(E, rel=1e-12)      # the reader's copy
        assert r["vendor"]["H"] == pytest.approx(H, rel=1e-12)
        assert r["E_mean"] == pytest.approx(E, rel=0.02)
        assert r["H_mean"] == pytest.approx(H, rel=0.02)
        assert abs(r["vendor_difference"]["E"]) < 0.02
        assert abs(r["vendor_difference"]["H"]) < 0.03
        assert r["depth_range"] == pytest.approx([100e-9, 200e-9], rel=1e-12)
        assert r["n_range"] > 100
        assert set(r["csm"]) == {"h", "h_c", "S", "A", "E_r", "E", "H"}
    code, out, _ = _run(["indent", "analyze", FS, "--csm", "--area-file", "file"], capsys)
    assert code == 0
    header = out.splitlines()[0]
    assert "E vs file" in header and "H vs file" in header


# ---- options refused before any work ----------------------------------------------------

def test_depth_range_changes_the_averages_and_bad_ranges_exit_2(capsys):
    """--depth-range 100nm:1000nm replaces the file's 100-200 nm (measured: 440-447 points
    averaged instead of 130-133); a reversed or one-ended range, a range without --csm and
    --csm with --cycles are usage errors: exit 2, one line."""
    code, out, _ = _run(["indent", "analyze", FS, "--csm", "--area-file", "file",
                         "--depth-range", "100nm:1000nm", "--json"], capsys)
    assert code == 0
    for r in _records(out).values():
        assert r["depth_range"] == pytest.approx([100e-9, 1000e-9], rel=1e-12)
        assert r["n_range"] > 300
    for argv, named in ((["--csm", "--depth-range", "200nm:100nm"], "--depth-range"),
                        (["--csm", "--depth-range", "100nm"], "--depth-range"),
                        (["--depth-range", "100nm:200nm"], "--depth-range"),
                        (["--csm", "--cycles"], "--cycles")):
        code, out, err = _run(["indent", "analyze", FS, "--tip", "berkovich", *argv], capsys)
        assert code == 2, argv
        assert len(err.strip().splitlines()) == 1 and named in err and "Traceback" not in err
        assert out == ""


@pytest.mark.parametrize("surface", ["contact", "load", "stiffness", "stiffness:0",
                                     "file:3nm"])
def test_bad_surface_exits_2_naming_it(capsys, surface):
    code, out, err = _run(["indent", "analyze", FS, "--tip", "berkovich", "--surface",
                           surface], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "--surface" in err
    assert "Traceback" not in err


def test_stiffness_surface_on_csm_tests_and_on_a_curve_without_the_channel(tmp_path, capsys):
    """--surface stiffness:500: re-found on the 16 CSM tests (within 1.5 nm of the
    instrument's own zero, measured); a text curve has no stiffness channel: that curve
    fails with the reason (status 1), the workbook is analysed, exit 0. Exit rule
    (indent_cli.cmd_indent_analyze): 2 when a file is unreadable, else 0 when at least one
    curve was analysed, else 1."""
    plain = tmp_path / "plain.csv"
    write_native(plain, synthetic_curve(69.6e9, 9e9, berkovich(), h_c=150e-9))
    code, out, err = _run(["indent", "analyze", FS, plain, "--tip", "berkovich", "--surface",
                           "stiffness:500", "--json"], capsys)
    assert code == 0, err
    rows = _records(out)
    assert len(rows) == 17
    failed = rows.pop("plain")
    assert failed["status"] == 1 and "stiffness" in failed["message"]
    for r in rows.values():
        assert r["status"] == 0 and r["surface_method"] == "stiffness:500"
        assert abs(r["surface_shift"]) < 5e-9
    code, _, _ = _run(["indent", "analyze", plain, "--tip", "berkovich", "--surface",
                       "stiffness:500"], capsys)
    assert code == 1                    # nothing analysed, nothing unreadable


# ---- the contact point ------------------------------------------------------------------

def _misplaced_zero_curve(path: Path, offset=60e-9, approach=40):
    """A synthetic fused-silica-like curve (E_r 69.6 GPa, H 9 GPa, h_c 500 nm, 0.01 % load
    noise) whose file depths are ``offset`` too large, after ``approach`` points at zero load
    before contact: an instrument surface-find that fired ``offset`` early."""
    c = synthetic_curve(69.6e9, 9e9, berkovich(), h_c=500e-9, noise=1e-4, seed=1)
    h = np.concatenate([np.linspace(0.0, offset, approach, endpoint=False), c.h + offset])
    P = np.concatenate([np.zeros(approach), c.P])
    t = np.concatenate([np.linspace(-4.0, 0.0, approach, endpoint=False), c.t])
    segment = np.concatenate([np.full(approach, LOAD), c.segment])
    write_native(path, type(c)(h, P, t, segment))


def test_auto_surface_refinds_a_zero_60_nm_off(tmp_path, capsys):
    """Default --surface auto: the zero re-found at 59.2 nm (measured), E_r within 0.2 % of
    the truth (measured -0.16 %), flagged surface_shift; the file's zero (--surface file)
    reads E_r 10.7 % low (measured)."""
    f = tmp_path / "shifted.csv"
    _misplaced_zero_curve(f)
    code, out, err = _run(["indent", "analyze", f, "--tip", "berkovich", "--json"], capsys)
    assert code == 0, err
    r = _records(out)["shifted"]
    assert r["status"] == 0 and r["surface_method"] != "file"
    assert abs(r["surface_shift"] - 60e-9) < 2e-9
    assert r["E_r"] == pytest.approx(69.6e9, rel=0.01)
    assert "surface_shift" in r["flags"]
    code, out, _ = _run(["indent", "analyze", f, "--tip", "berkovich", "--surface", "file",
                         "--json"], capsys)
    assert code == 0
    r = _records(out)["shifted"]
    assert r["surface_shift"] == 0.0 and abs(r["E_r"] / 69.6e9 - 1) > 0.03


# ---- calibration ------------------------------------------------------------------------

def _write_reference(folder: Path, offset=65 * NM) -> list[Path]:
    """The three multi-cycle fused-silica indents of test_tip_calibration (0.05 % load noise),
    their depth zeros ``offset`` off, as text files."""
    folder.mkdir()
    files = []
    for k, curve in enumerate(shifted(reference_curves(noise=5e-4), offset)):
        files.append(folder / f"ref{k}.csv")
        write_native(files[-1], curve)
    return files


def test_calibration_gate_refuses_a_misplaced_zero_and_auto_surface_passes(tmp_path, capsys):
    """Depth zeros 65 nm off and kept (--surface file): the fitted area function falls below
    the ideal pyramid's (measured: 75 % at h_c 85 nm), the gate refuses, exit 1, one line,
    no file; --force writes it with a warning; re-found (--surface auto) the gate passes."""
    files = _write_reference(tmp_path / "ref")
    tip = tmp_path / "tip.toml"
    base = ["indent", "calibrate", *files, "--reference", "fused-silica", "--out", tip]
    code, _, err = _run([*base, "--surface", "file"], capsys)
    assert code == 1
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert err.startswith(f"filmscale: calibration refused, {tip} not written")
    assert "below the ideal" in err and "(--force writes it anyway)" in err
    assert not tip.exists()
    code, _, err = _run([*base, "--surface", "file", "--force"], capsys)
    assert code == 0 and tip.exists()
    assert "warning: written although refused (--force)" in err
    tip.unlink()
    code, _, err = _run(base, capsys)
    assert code == 0, err
    assert "surface re-found on 3 of 3 curves" in err
    written = tomllib.loads(tip.read_text())
    assert len(written["h_c_range"]) == 2 and len(written["C"]) == 4
    assert written["length_unit"] == "nm"


@pytest.mark.parametrize("layout", ["text", "hdf5"])
def test_calibration_refinds_each_zero_of_a_multicycle_export(tmp_path, capsys, layout):
    """The same three multi-cycle indents, zeros 65 nm off, as a text export (depth, load,
    time: the segments found from the load rate) and as filmscale HDF5 (segments stored):
    --surface auto must re-find every zero within 1 nm (surface.py's claim for a 60 nm
    error) and the calibrated area must follow the generating one within 2 % over
    20-360 nm. Measured: HDF5 64.89-64.98 nm, area within 0.5 %; text 69.7, 72.7, 72.2 nm,
    area 31 % high at 20 nm (the load-rate segments call the first cycles, under 10 % of the
    peak load, loading, so the fit runs through the first unloading; with the true segments
    the same text data gives 64.89 nm)."""
    curves = shifted(reference_curves(noise=5e-4), 65 * NM)
    if layout == "text":
        files = _write_reference(tmp_path / "ref")
    else:
        files = [tmp_path / "ref.h5"]
        with atomic_h5(files[0]) as f:
            for k, c in enumerate(curves):    # the nominal tip's name (see the next test)
                write_curve_group(f.create_group(f"ref{k}"),
                                  type(c)(c.h, c.P, c.t, c.segment, indenter="berkovich"))
    tip = tmp_path / "tip.toml"
    code, out, err = _run(["indent", "calibrate", *files, "--reference", "fused-silica",
                           "--out", tip, "--json"], capsys)
    assert code == 0, err
    shifts = json.loads(out)["surface_shift"]
    assert len(shifts) == 3
    assert all(abs(s - 65 * NM) < 1 * NM for s in shifts.values()), shifts
    h = np.geomspace(20 * NM, 360 * NM, 10)
    np.testing.assert_allclose(read_area_function(tip).area(h), TRUE_AREA.area(h), rtol=0.02)


def test_a_curve_group_with_a_calibrated_tip_reads_back(tmp_path, capsys):
    """write_curve_group stores the curve's indenter by its spec; a curve made with a
    polynomial area function (reference_curves: TRUE_AREA) must read back from the file it
    wrote, and its four cycles analyse to E_r of fused silica within 1 % (noise-free, with
    the generating area function and frame compliance)."""
    curve = reference_curves()[0]
    f = tmp_path / "ref.h5"
    with atomic_h5(f) as h5:
        write_curve_group(h5.create_group("ref0"), curve)
    code, out, err = _run(["indent", "analyze", f, "--tip", "berkovich", "--area-file",
                           _area_file(tmp_path, TRUE_AREA), "--frame-compliance", C_F,
                           "--cycles", "--json"], capsys)
    assert code == 0, err
    rows = _records(out)
    assert len(rows) == 4
    for r in rows.values():
        assert r["status"] == 0 and r["E_r"] == pytest.approx(E_R_SILICA, rel=0.01)


def _area_file(folder: Path, area: PolynomialArea, h_c_range=None) -> Path:
    """An area file of ``area`` (C in nm), written here, not by the package."""
    coef = [c / NM**(2.0 - p) for c, p in zip(area.coefficients, (2.0, 1.0, 0.5, 0.25))]
    text = f"C = [{', '.join(repr(c) for c in coef)}]\nlength_unit = \"nm\"\n"
    if h_c_range is not None:
        text += f"h_c_range = [{h_c_range[0]!r}, {h_c_range[1]!r}]\n"
    path = folder / "area.toml"
    path.write_text(text)
    return path


def test_calibrate_on_fs_calibration_then_measure_fused_silica(tmp_path, capsys):
    """Calibrated on the 16 CSM tests (E 72 GPa, nu 0.17), then analysed with that area file
    and frame compliance over 100-1000 nm with the file's Poisson ratio 0.18: every test's E
    within 3 % of fused silica's 72 GPa (Oliver & Pharr 1992). Measured: -1.7 % to +1.6 %."""
    tip = tmp_path / "tip.toml"
    code, _, err = _run(["indent", "calibrate", FS, "--reference", "fused-silica", "--fit",
                         "both", "--out", tip], capsys)
    assert code == 0, err
    assert tip.exists() and "12021 CSM points" in err
    code, out, err = _run(["indent", "analyze", FS, "--csm", "--tip", "berkovich",
                           "--area-file", tip, "--depth-range", "100nm:1000nm", "--json"],
                          capsys)
    assert code == 0, err
    rows = _records(out)
    assert len(rows) == 16
    for r in rows.values():
        assert r["status"] == 0 and r["nu_source"] == "file" and r["nu"] == 0.18
        assert r["E_mean"] == pytest.approx(72e9, rel=0.03), r["name"]
        assert r["depth_range"] == pytest.approx([100e-9, 1000e-9], rel=1e-12)


# ---- area files -------------------------------------------------------------------------

def test_an_area_function_negative_at_the_contact_depth_fails_that_curve(tmp_path, capsys):
    """A = 24.5 h^2 - 5000 h (nm) is negative below h = 204 nm: the curve at h_c 100 nm fails
    ('not a contact area'), the curve at 500 nm (made with that very area function) is
    analysed to its E_r and H, exit 0, no internal error."""
    area = PolynomialArea((24.5, -5000 * NM), berkovich())
    (tmp_path / "area.toml").write_text('C = [24.5, -5000]\nlength_unit = "nm"\n')
    assert area.area(100 * NM) < 0 < area.area(500 * NM)
    write_native(tmp_path / "shallow.csv", synthetic_curve(69.6e9, 9e9, berkovich(),
                                                           h_c=100e-9))
    write_native(tmp_path / "deep.csv", synthetic_curve(69.6e9, 9e9, area, h_c=500e-9))
    code, out, err = _run(["indent", "analyze", tmp_path / "shallow.csv", tmp_path / "deep.csv",
                           "--tip", "berkovich", "--area-file", tmp_path / "area.toml",
                           "--json"], capsys)
    assert code == 0, err
    assert "internal error" not in err + out and "Traceback" not in err
    rows = _records(out)
    assert rows["shallow"]["status"] == 1 and "not a contact area" in rows["shallow"]["message"]
    assert rows["deep"]["status"] == 0
    assert rows["deep"]["E_r"] == pytest.approx(69.6e9, rel=1e-6)
    assert rows["deep"]["H"] == pytest.approx(9e9, rel=1e-6)


def test_contact_depth_outside_the_calibrated_range_is_flagged(tmp_path, capsys):
    """h_c_range = [200, 300] nm, a curve at h_c 150 nm: flagged area_extrapolated (the ideal
    pyramid's area, so E_r is still the truth); at 250 nm no flag."""
    area = _area_file(tmp_path, PolynomialArea((berkovich().area_coefficient,), berkovich()),
                      h_c_range=(200, 300))
    for h_c, flagged in ((150e-9, True), (250e-9, False)):
        f = tmp_path / f"c{h_c * 1e9:.0f}.csv"
        write_native(f, synthetic_curve(69.6e9, 9e9, berkovich(), h_c=h_c))
        code, out, err = _run(["indent", "analyze", f, "--tip", "berkovich", "--area-file",
                               area, "--json"], capsys)
        assert code == 0, err
        r = _records(out)[f.stem]
        assert ("area_extrapolated" in r["flags"]) is flagged
        assert r["E_r"] == pytest.approx(69.6e9, rel=1e-6)


# ---- results file -----------------------------------------------------------------------

def test_csm_results_file_holds_the_arrays_and_the_vendor_differences(tmp_path, capsys):
    """--out with --csm: one row per test of surface_shift and vendor_difference_E, and the
    per-depth arrays of each row under csm/ROW, the same numbers as the JSON records."""
    out_file = tmp_path / "results.h5"
    code, out, err = _run(["indent", "analyze", FS, "--csm", "--area-file", "file", "--json",
                           "--out", out_file], capsys)
    assert code == 0, err
    rows = list(map(json.loads, out.splitlines()))
    with h5py.File(out_file, "r") as f:
        assert f["surface_shift"].shape == (16,) and f["vendor_difference_E"].shape == (16,)
        np.testing.assert_array_equal(f["surface_shift"][()],
                                      [r["surface_shift"] for r in rows])
        np.testing.assert_allclose(f["vendor_difference_E"][()],
                                   [r["vendor_difference"]["E"] for r in rows], rtol=1e-12)
        assert np.all(np.abs(f["vendor_difference_E"][()]) < 0.02)
        assert sorted(f["csm"], key=int) == [str(k) for k in range(16)]
        h, E = f["csm/0/h"][()], f["csm/0/E"][()]
        assert h.ndim == 1 and h.size > 1000 and E.shape == h.shape
        np.testing.assert_array_equal(h, rows[0]["csm"]["h"])
        np.testing.assert_array_equal(E, rows[0]["csm"]["E"])


# ---- hostile files ----------------------------------------------------------------------

def _no_test_sheet(path: Path) -> None:
    from openpyxl import Workbook
    wb = Workbook()
    wb.active.title = "Results"
    wb.active.append(["Test", "Modulus At Max Load"])
    wb.active.append([1, 70.0])
    wb.save(path)


@pytest.mark.parametrize("name, make, why", [
    ("x.xls", lambda p: p.write_text("this is text, not a workbook\n"),
     "as an Excel workbook"),
    ("half.hld", lambda p: p.write_bytes((DATA / "Exp-50mN_0000.hld").read_bytes()[
        :(DATA / "Exp-50mN_0000.hld").stat().st_size // 2]), "cut short"),
    ("notests.xlsx", _no_test_sheet, "holds no test sheet"),
])
def test_a_hostile_file_beside_a_good_one(tmp_path, capsys, name, make, why):
    """Each hostile file is named on one stderr line with the reason, exit 2 (bad input),
    no traceback, and the good file beside it is still analysed."""
    bad = tmp_path / name
    make(bad)
    good = tmp_path / "good.csv"
    write_native(good, synthetic_curve(69.6e9, 9e9, berkovich(), h_c=150e-9))
    code, out, err = _run(["indent", "analyze", bad, good, "--tip", "berkovich", "--json"],
                          capsys)
    assert code == 2
    problems = _error_lines(err)
    assert len(problems) == 1, err
    assert problems[0].startswith(f"filmscale: error: {bad.stem}: ") and name in problems[0]
    assert why in problems[0]
    assert "Traceback" not in err and "internal error" not in err
    rows = _records(out)
    assert rows[bad.stem]["status"] == "unreadable"
    assert rows["good"]["status"] == 0
    assert rows["good"]["E_r"] == pytest.approx(69.6e9, rel=1e-6)
    assert math.isfinite(rows["good"]["H"])


def test_csm_plots_one_figure_per_test(tmp_path, capsys):
    """--csm --plot DIR: E and H against depth beside the instrument's channels, one PNG per
    test (looked at: docs/indentation.md, the CSM section)."""
    plots = tmp_path / "plots"
    code, _, err = _run(["indent", "analyze", DATA / "Example.xls", "--csm", "--area-file",
                         "file", "--plot", plots], capsys)
    assert code == 0, err
    files = sorted(p.name for p in plots.iterdir())
    assert files == ["Example_Test_001.png", "Example_Test_002.png", "profile.png"]
    assert all((plots / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for f in files)


def test_csm_refuses_an_epsilon_from_the_unloading_exponent(capsys):
    """A CSM point has no unloading to fit: --epsilon exponent exits 2 before any work."""
    code, out, err = _run(["indent", "analyze", FS, "--csm", "--area-file", "file",
                           "--epsilon", "exponent"], capsys)
    assert code == 2 and out == ""
    assert len(_error_lines(err)) == 1 and "--epsilon" in err and "Traceback" not in err
