"""Instrument exports (G200/iMicro .xlsx, TriboScan .txt and .hld, Anton Paar, delimited
text) read to the same curve, E_r and H as the package's own table."""

import numpy as np
import pytest

from filmscale.continuum.indentation import oliver_pharr
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.cycles import analyse_cycles, synthetic_multicycle
from filmscale.continuum.indentation.io import read_curves
from filmscale.continuum.indentation.tips import berkovich
from filmscale.continuum.indentation.vendors import (ReadOptions, parse_columns,
                                                     read_options_file)
from filmscale.core.errors import InputError
from tests.helpers.instruments import (write_anton_paar, write_g200, write_hld, write_native,
                                       write_triboscan)

# fused silica against diamond (Oliver & Pharr 1992): E_r = 69.6 GPa; H = 9 GPa
E_R, H = 69.6e9, 9.0e9
CURVE = synthetic_curve(E_R, H, berkovich(), h_c=150e-9)
# Every file holds the same numbers rounded to 10 digits; the readers differ only in the unit
# factor they multiply by (1e-3 mN vs 1e-6 uN), a rounding of 1e-16 that the least-squares
# unloading fit carries to E_r and H well below 1e-9.
SAME = 1e-9
# against the generating E_r and H: the 10-digit rounding of the written values moves the
# fitted power law by ~1e-9; the noise-free synthetic curve is fitted to ~1e-8 (as in
# test_indent_cli), so 1e-6 leaves room and still catches any unit or column slip.
KNOWN = 1e-6


def _native(tmp_path, curve=CURVE):
    write_native(tmp_path / "native.csv", curve)
    return read_curves(tmp_path / "native.csv")["native"]


@pytest.mark.parametrize("writer, name", [
    (write_triboscan, "tribo.txt"), (write_hld, "test.hld"), (write_anton_paar, "ap.csv")])
def test_text_exports_read_as_the_native_table(tmp_path, writer, name):
    writer(tmp_path / name, CURVE)
    got = read_curves(tmp_path / name)
    assert list(got) == [name.split(".")[0]]
    curve, native = got[name.split(".")[0]], _native(tmp_path)
    np.testing.assert_allclose(curve.h, native.h, rtol=1e-15)
    np.testing.assert_allclose(curve.P, native.P, rtol=1e-15)
    np.testing.assert_allclose(curve.t, native.t, rtol=1e-15)
    a, b = oliver_pharr(curve, "berkovich"), oliver_pharr(native, "berkovich")
    assert a.E_r == pytest.approx(b.E_r, rel=SAME) and a.H == pytest.approx(b.H, rel=SAME)
    assert a.E_r == pytest.approx(E_R, rel=KNOWN) and a.H == pytest.approx(H, rel=KNOWN)


def test_triboscan_is_latin1_with_a_preamble(tmp_path):
    write_triboscan(tmp_path / "t.txt", CURVE)
    raw = (tmp_path / "t.txt").read_bytes()
    assert b"Load (\xb5N)" in raw and b"\r\n" in raw       # Latin-1 micro sign, CR LF
    with pytest.raises(UnicodeDecodeError):
        raw.decode("utf-8")
    assert read_curves(tmp_path / "t.txt")["t"].meta["separator"] == "\t"


def test_g200_workbook_sheets_units_and_markers(tmp_path):
    second = synthetic_curve(120e9, 6e9, berkovich(), h_c=300e-9)
    write_g200(tmp_path / "run.xlsx", [CURVE, second])
    got = read_curves(tmp_path / "run.xlsx")
    assert list(got) == ["Test 001", "Test 002"]       # Results, Required Inputs passed over
    first = got["Test 001"]
    np.testing.assert_array_equal(first.segment, CURVE.segment)    # from the markers
    native = _native(tmp_path)
    np.testing.assert_allclose(first.h, native.h, rtol=1e-15)
    np.testing.assert_allclose(first.P, native.P, rtol=1e-12)       # mN vs uN, 1e-16 apart
    for curve, (E_r, H_) in zip(got.values(), ((E_R, H), (120e9, 6e9))):
        r = oliver_pharr(curve, "berkovich")
        assert r.E_r == pytest.approx(E_r, rel=KNOWN) and r.H == pytest.approx(H_, rel=KNOWN)
    a, b = oliver_pharr(first, "berkovich"), oliver_pharr(native, "berkovich")
    assert a.E_r == pytest.approx(b.E_r, rel=SAME) and a.H == pytest.approx(b.H, rel=SAME)


def test_g200_multi_cycle_sheet_keeps_every_cycle(tmp_path):
    depths = np.array([60e-9, 120e-9, 240e-9])
    curve = synthetic_multicycle(E_R, H, berkovich(), h_c=depths)
    write_g200(tmp_path / "mc.xlsx", [curve])
    read = read_curves(tmp_path / "mc.xlsx")["Test 001"]
    np.testing.assert_array_equal(read.segment, curve.segment)
    results = analyse_cycles(read, "berkovich")
    np.testing.assert_allclose([r.h_c for r in results], depths, rtol=KNOWN)
    np.testing.assert_allclose([r.E_r for r in results], E_R, rtol=KNOWN)
    np.testing.assert_allclose([r.H for r in results], H, rtol=KNOWN)


def test_generic_text_with_a_column_mapping_and_a_reader_file(tmp_path):
    h, P, t = CURVE.h * 1e6, CURVE.P * 1e3, CURVE.t     # um and mN, named freely
    f = tmp_path / "lab.dat"
    f.write_text("sample A\nz\tforce\tclock\n" + "\n".join(
        f"{a:.12g}\t{b:.12g}\t{c:.12g}" for a, b, c in zip(h, P, t)))
    with pytest.raises(InputError, match="lab.dat.*no h column"):
        read_curves(f)
    options = ReadOptions(columns=parse_columns("h=z:um,P=force:mN,t=3:s"))
    curve = read_curves(f, options)["lab"]
    assert oliver_pharr(curve, "berkovich").E_r == pytest.approx(E_R, rel=KNOWN)
    spec = tmp_path / "reader.toml"
    spec.write_text('format = "delimited"\nseparator = "\\t"\n[columns]\nh = "z"\nP = 2\n'
                    '[units]\nh = "um"\nP = "mN"\n')
    curve = read_curves(f, read_options_file(spec))["lab"]
    assert curve.t is None and oliver_pharr(curve, "berkovich").H == pytest.approx(H, rel=KNOWN)


def test_two_row_header_whitespace_and_decimal_comma(tmp_path):
    f = tmp_path / "two.txt"
    f.write_text("Depth Load\n(nm) (uN)\n" + "\n".join(
        f"{a:.12g} {b:.12g}".replace(".", ",") for a, b in zip(CURVE.h * 1e9, CURVE.P * 1e6)))
    curve = read_curves(f)["two"]
    assert curve.meta["decimal"] == ","
    assert oliver_pharr(curve, "berkovich").E_r == pytest.approx(E_R, rel=KNOWN)


@pytest.mark.parametrize("name, content, match", [
    ("a.xlsx", b"PK\x03\x04 not a workbook", "cannot read .*a.xlsx as an Excel workbook"),
    ("b.xls", b"\xd0\xcf\x11\xe0", "b.xls as an Excel workbook .*not an office document"),
    ("c.txt", "Depth (V)\tLoad (V)\n1\t2\n3\t4\n5\t6\n7\t8\n".encode(),
     "column 'Depth \\(V\\)' \\(h\\) has unit 'V'"),
    ("d.txt", b"just words\nand more words\n", "d.txt.*no rows of numbers"),
    ("e.csv", b"x [nm], P [uN]\n0, 0\n1, 1\n", "no h column"),
])
def test_unreadable_files_name_the_file_and_why(tmp_path, name, content, match):
    (tmp_path / name).write_bytes(content)
    with pytest.raises(InputError, match=match):
        read_curves(tmp_path / name)


def test_workbook_without_test_sheets(tmp_path):
    from openpyxl import Workbook
    wb = Workbook()
    wb.active.append(["Sample", "Operator"])
    wb.save(tmp_path / "empty.xlsx")
    with pytest.raises(InputError, match="holds no test sheet with depth and load"):
        read_curves(tmp_path / "empty.xlsx")


@pytest.mark.parametrize("kwargs, match", [
    ({"format": "nanoxyz"}, "format = 'nanoxyz' is not one of"),
    ({"decimal": ";"}, "decimal = ';' must be"),
    ({"encoding": "klingon"}, "not a known text encoding"),
    ({"columns": (("x", "a", None),)}, "role 'x' is not one of h, P, t"),
    ({"columns": (("h", "a", "mN"),)}, "unit 'mN' of h is not one of"),
])
def test_bad_reader_options(kwargs, match):
    with pytest.raises(InputError, match=match):
        ReadOptions(**kwargs)


def test_bad_column_mapping_text():
    with pytest.raises(InputError, match="is not ROLE=NAME"):
        parse_columns("h,P=Load")
    assert parse_columns("h=Depth (nm),P=2:uN") == (("h", "Depth (nm)", None), ("P", 2, "uN"))
    assert ReadOptions(format="anton-paar").setting("decimal") == ","      # the preset
    assert ReadOptions(format="anton-paar", decimal=".").setting("decimal") == "."


def test_a_header_that_does_not_match_its_rows_is_refused(tmp_path):
    # read leniently, the third column would be dropped without a word
    f = tmp_path / "shifted.csv"
    f.write_text("h [nm], P [uN]\n" + "\n".join(f"{k}, {k * k}, 7" for k in range(10)))
    with pytest.raises(InputError, match="3 columns of numbers but its header names 2.*"
                                         "header names 2 columns but its rows hold 3"):
        read_curves(f)


def test_named_formats(tmp_path):
    write_anton_paar(tmp_path / "ap.txt", CURVE)
    with pytest.raises(InputError, match="format g200 reads the .xls and .xlsx workbooks"):
        read_curves(tmp_path / "ap.txt", ReadOptions(format="g200"))
    with pytest.raises(InputError, match="is not a number|could not convert"):
        read_curves(tmp_path / "ap.txt", ReadOptions(format="filmscale"))    # no fallback
    curve = read_curves(tmp_path / "ap.txt", ReadOptions(format="anton-paar"))["ap"]
    assert oliver_pharr(curve, "berkovich").E_r == pytest.approx(E_R, rel=KNOWN)
