"""Delimited tables with thousands separators (issue 31): read to the same curve as the
table written without them, or refused saying why, never cut at the first one (the curve
was then blamed: "no unloading segment"). And reader encodings that are text encodings
only: rot13 or zlib_codec are codecs, not ways to read text."""

import json

import numpy as np
import pytest

from filmscale.continuum.indentation import oliver_pharr
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_curves
from filmscale.continuum.indentation.tips import berkovich
from filmscale.continuum.indentation.vendors import ReadOptions, read_options_file
from filmscale.core.errors import InputError
from filmscale.workflows.cli import main
from tests.helpers.instruments import columns

E_R, H = 69.6e9, 9.0e9
# the load reaches 4960 uN: the rows from the 91st on hold a thousands separator
CURVE = synthetic_curve(E_R, H, berkovich(), h_c=150e-9)
HEADER = ("Depth (nm)", "Load (uN)", "Time (s)")


def _grouped(x: float, thousands: str = ",", decimal: str = ".") -> str:
    """``x`` as Python writes it (the shortest text that reads back to it) with its
    thousands grouped."""
    text = f"{x:,}"
    assert "e" not in text
    return text.replace(",", "\0").replace(".", decimal).replace("\0", thousands)


def _write(path, sep: str, number, quote: bool = False, encoding="utf-8"):
    q = '"' if quote else ""
    rows = [sep.join(f"{q}{number(v)}{q}" for v in row) for row in zip(*columns(CURVE))]
    names = [n.replace(" ", "") if sep == " " else n for n in HEADER]    # Depth(nm)
    path.write_text("\n".join([sep.join(f"{q}{n}{q}" for n in names), *rows]) + "\n",
                    encoding=encoding)
    return path


@pytest.fixture
def plain(tmp_path):
    """The curve read from the table without thousands separators: the oracle."""
    path = _write(tmp_path / "plain.txt", "\t", repr)
    curve = read_curves(path)["plain"]
    assert len(curve.h) == len(CURVE.h) and curve.P.max() > 1e-3 * 1.001   # above 1000 uN
    return curve


@pytest.mark.parametrize("name, sep, number, quote", [
    ("tab.txt", "\t", _grouped, False),                                    # 1,234.5
    ("semicolon.csv", ";", _grouped, False),
    ("blanks.txt", " ", _grouped, False),
    ("quoted.csv", ",", _grouped, True),                                   # "1,234.5"
    ("european.csv", ";", lambda x: _grouped(x, ".", ","), False),         # 1.234,5
    ("spaced.txt", "\t", lambda x: _grouped(x, " ", ","), False),          # 1 234,5
    ("nbsp.txt", "\t", lambda x: _grouped(x, "\u00a0", ","), False),       # 1 234,5 (no-break)
    ("narrow.txt", ";", lambda x: _grouped(x, "\u202f", "."), False),      # 1 234.5
    ("swiss.txt", "\t", lambda x: _grouped(x, "'", "."), False),           # 1'234.5
])
def test_thousands_separators_read_as_the_table_without_them(tmp_path, plain, name, sep,
                                                             number, quote):
    path = _write(tmp_path / name, sep, number, quote)
    curve = read_curves(path)[path.stem]
    assert len(curve.h) == len(plain.h)          # not cut at the first separator
    for got, want in ((curve.h, plain.h), (curve.P, plain.P), (curve.t, plain.t)):
        np.testing.assert_array_equal(got, want)
    result = oliver_pharr(curve, "berkovich")
    assert result.E_r == pytest.approx(E_R, rel=1e-6) and result.H == pytest.approx(H, rel=1e-6)


def test_the_command_line_analyses_a_table_with_thousands_separators(tmp_path, capsys):
    path = _write(tmp_path / "tab.txt", "\t", _grouped)
    assert main(["indent", "analyze", str(path), "--tip", "berkovich", "--json"]) == 0
    row = json.loads(capsys.readouterr().out.splitlines()[0])
    assert row["E_r"] == pytest.approx(E_R, rel=1e-6)


def test_unquoted_thousands_commas_in_a_comma_separated_table_are_refused(tmp_path):
    path = _write(tmp_path / "unquoted.csv", ",", _grouped)
    with pytest.raises(InputError, match=r"line 92 holds a number with thousands separators "
                                         r"\(1,0[0-9.]+\) in a comma-separated table, where "
                                         r"they cannot be told from the separator"):
        read_curves(path)


def test_a_comma_separated_table_of_thousands_from_its_first_row_is_refused(tmp_path):
    path = tmp_path / "big.csv"
    path.write_text("Depth (nm),Load (uN)\n" + "".join(
        f"{1000 + k}.5,{2000 + k}.25\n" if k < 3 else f"1,{k:03d}.5,2,{k:03d}.25\n"
        for k in range(3)) + "".join(f"1,{k:03d}.5,2,{k:03d}.25\n" for k in range(3, 9)))
    with pytest.raises(InputError, match=r"thousands separators \(1,003.5\)"):
        read_curves(path, ReadOptions(format="delimited"))


def _comma_table_with_a_thousands_number(tmp_path):
    path = _write(tmp_path / "ap.csv", ";", lambda x: repr(x).replace(".", ","))
    lines = path.read_text().splitlines()
    lines[120] = lines[120].split(";")[0] + ";1,234.5;" + lines[120].split(";")[2]
    path.write_text("\n".join(lines) + "\n")
    return path


def _point_table_with_a_comma_row(tmp_path):
    path = _write(tmp_path / "mixed.txt", "\t", repr)
    lines = path.read_text().splitlines()
    lines[200] = lines[200].replace(".", ",")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("table, message", [
    # a thousands separator in a decimal comma table: refused naming line and column
    (_comma_table_with_a_thousands_number,
     r"line 121, column 'Load \(uN\)' holds '1,234.5', which does not fit the number format "
     r"of the rows above \(a decimal comma\): it holds thousands separators"),
    # a table mixing decimal points and commas
    (_point_table_with_a_comma_row,
     r"line 201, column 'Depth \(nm\)' holds '[0-9]+,[0-9]+', which does not fit the number "
     r"format of the rows above \(a decimal point\): export the table with one decimal mark "
     r"throughout"),
], ids=["thousands_in_a_decimal_comma_table", "decimal_points_and_commas_mixed"])
def test_a_number_out_of_the_table_format_is_refused_naming_line_and_column(tmp_path, table,
                                                                              message):
    with pytest.raises(InputError, match=message):
        read_curves(table(tmp_path), ReadOptions(format="delimited"))


def test_whole_thousands_after_decimal_points_are_thousands(tmp_path):
    path = tmp_path / "t.txt"
    path.write_text("Depth (nm)\tLoad (uN)\n999.5\t998.25\n999.75\t999.5\n1,000\t1,000.5\n"
                    "1,001\t2,000,000\n")
    curve = read_curves(path, ReadOptions(format="delimited"))["t"]
    np.testing.assert_array_equal(curve.h, np.array([999.5, 999.75, 1000, 1001]) * 1e-9)
    np.testing.assert_array_equal(curve.P, np.array([998.25, 999.5, 1000.5, 2e6]) * 1e-6)
    assert curve.meta["decimal"] == "." and curve.meta["thousands"] == ","


@pytest.mark.parametrize("decimal, h", [(None, 1.234), (",", 1.234), (".", 1234.0)])
def test_one_comma_and_three_digits_stay_a_decimal_comma_unless_told(tmp_path, decimal, h):
    # 1,234 alone is 1.234 with a decimal comma (as before) or 1234 with a thousands comma:
    # the decimal option tells
    path = tmp_path / "t.txt"
    path.write_text("Depth (nm)\tLoad (uN)\n1,234\t2,500\n1,234\t2,500\n1,234\t2,500\n")
    curve = read_curves(path, ReadOptions(format="delimited", decimal=decimal))["t"]
    assert curve.h[0] == pytest.approx(h * 1e-9, rel=1e-15)


def test_a_decimal_comma_table_reads_as_before(tmp_path, plain):
    path = _write(tmp_path / "ap.csv", ";", lambda x: repr(x).replace(".", ","))
    curve = read_curves(path)["ap"]
    np.testing.assert_array_equal(curve.P, plain.P)
    assert curve.meta["decimal"] == "," and "thousands" not in curve.meta


# ---- text encodings only ------------------------------------------------------------------

@pytest.mark.parametrize("encoding", ["rot13", "zlib_codec", "base64_codec", "hex_codec",
                                      "bz2_codec", "uu_codec"])
def test_codecs_that_are_not_text_encodings_are_refused(encoding):
    with pytest.raises(InputError, match=rf"^encoding = '{encoding}' is a codec but not a text "
                                         r"encoding \(text encodings: utf-8, latin-1, cp1252, "
                                         r"utf-16"):
        ReadOptions(encoding=encoding)


@pytest.mark.parametrize("encoding, says", [
    ("klingon", "'klingon' is not a known text encoding"),
    ("", "'' is not a known text encoding"), (5, "5 is not a known text encoding")])
def test_unknown_encodings_are_refused(encoding, says):
    with pytest.raises(InputError, match=f"^encoding = {says}"):
        ReadOptions(encoding=encoding)


@pytest.mark.parametrize("encoding", ["utf-8", "latin-1", "cp1252", "utf-16", "UTF8",
                                      "iso-8859-15"])
def test_text_encodings_read(tmp_path, plain, encoding):
    path = _write(tmp_path / "enc.txt", "\t", _grouped, encoding=encoding)
    curve = read_curves(path, ReadOptions(format="delimited", encoding=encoding))["enc"]
    np.testing.assert_array_equal(curve.P, plain.P)


@pytest.mark.parametrize("encoding", ["rot13", "zlib_codec"])
def test_reader_file_encoding_that_is_a_codec_exits_2_with_one_line(tmp_path, capsys,
                                                                   encoding):
    path = _write(tmp_path / "tab.txt", "\t", repr)
    reader = tmp_path / "reader.toml"
    reader.write_text(f'encoding = "{encoding}"\n')
    with pytest.raises(InputError, match=f"reader options file .*reader.toml: encoding = "
                                         f"'{encoding}' is a codec but not a text encoding"):
        read_options_file(reader)
    for fmt in ("auto", "delimited"):
        assert main(["indent", "analyze", str(path), "--tip", "berkovich", "--format", fmt,
                     "--reader", str(reader)]) == 2
        err = capsys.readouterr().err
        assert f"encoding = '{encoding}' is a codec but not a text encoding" in err
        assert err.count("\n") == 1 and "Traceback" not in err and "internal" not in err


def test_text_that_an_encoding_cannot_decode_is_named(tmp_path):
    path = _write(tmp_path / "tab.txt", "\t", repr)
    # punycode raises a plain UnicodeError (no byte position), utf-8 a UnicodeDecodeError
    with pytest.raises(InputError, match=r"tab.txt is not punycode text: "):
        read_curves(path, ReadOptions(format="delimited", encoding="punycode"))
    path.write_bytes(path.read_bytes().replace(b"(uN)", b"(\xb5N)"))
    with pytest.raises(InputError, match=r"tab.txt is not utf-8 text: invalid start byte at "
                                         r"byte \d+"):
        read_curves(path, ReadOptions(format="delimited", encoding="utf-8"))
