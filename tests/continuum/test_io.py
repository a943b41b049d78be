"""Tables with units in the header."""

import numpy as np
import pytest

from filmscale.continuum.indentation.io import parse_header, read_table
from filmscale.core.errors import InputError


def test_units_in_header_convert_to_si(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text("h_c [nm], E_r [GPa], H [GPa], t\n# a comment\n10, 150, 12, 1\n20, 140, 10, 2\n")
    cols = read_table(f, required=("h_c", "E_r", "H"))
    np.testing.assert_allclose(cols["h_c"], [10e-9, 20e-9], rtol=1e-15)
    np.testing.assert_allclose(cols["E_r"], [150e9, 140e9], rtol=1e-15)
    np.testing.assert_allclose(cols["t"], [1.0, 2.0])


def test_whitespace_separated_with_commented_header(tmp_path):
    f = tmp_path / "t.txt"
    f.write_text("# h [um] P [mN]\n1 2\n3 4\n")
    cols = read_table(f)
    np.testing.assert_allclose(cols["h"], [1e-6, 3e-6])
    np.testing.assert_allclose(cols["P"], [2e-3, 4e-3])


@pytest.mark.parametrize("text, match", [
    ("1, 2\n3, 4\n", "no header"),
    ("h [furlong], P\n1, 2\n", "unknown unit"),
    ("h, P\n1, 2, 3\n", "3 columns"),
    ("h, P\n", "no rows"),
])
def test_bad_tables_are_input_errors(tmp_path, text, match):
    f = tmp_path / "t.csv"
    f.write_text(text)
    with pytest.raises(InputError, match=match):
        read_table(f)


def test_missing_required_column_and_file(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text("h, P\n1, 2\n")
    with pytest.raises(InputError, match="lacks column"):
        read_table(f, required=("H",))
    with pytest.raises(InputError, match="cannot read"):
        read_table(tmp_path / "absent.csv")
    assert parse_header("a [nm] b") == [("a", 1e-9), ("b", 1.0)]


def test_units_in_parentheses_names_with_spaces_and_empty_fields(tmp_path):
    # the form of the packaged Dao/Lu FE tables: commas only, units in parentheses
    assert parse_header("Case,n,E (GPa),sy (GPa),dP/dh (N/m),Wp/Wt") == [
        ("Case", 1.0), ("n", 1.0), ("E", 1e9), ("sy", 1e9), ("dP/dh", 1.0), ("Wp/Wt", 1.0)]
    assert parse_header("Young modulus (GPa), depth [nm], f(x)") == [
        ("Young modulus", 1e9), ("depth", 1e-9), ("f(x)", 1.0)]
    assert parse_header("E (GPa) h [nm]") == [("E", 1e9), ("h", 1e-9)]
    # earlier forms are unchanged, mixed separators included
    assert parse_header("h [nm], P [uN], t [s]") == [("h", 1e-9), ("P", 1e-6), ("t", 1.0)]
    assert parse_header("# h [um] P [mN]") == [("h", 1e-6), ("P", 1e-3)]
    assert parse_header("h [nm] P [uN], t [s],") == [("h", 1e-9), ("P", 1e-6), ("t", 1.0)]
    with pytest.raises(InputError, match="unknown unit"):
        parse_header("E (furlong), n")
    with pytest.raises(InputError, match="empty column name"):
        parse_header("h,, P")
    f = tmp_path / "t.csv"
    f.write_text("Case,E (GPa),dP/dh (N/m),Wp/Wt\r\n1,10,15727,0.94\r\n2,20,9278.4,\r\n")
    cols = read_table(f)
    assert list(cols) == ["Case", "E", "dP/dh", "Wp/Wt"]
    np.testing.assert_array_equal(cols["E"], [10e9, 20e9])
    np.testing.assert_array_equal(cols["dP/dh"], [15727.0, 9278.4])
    assert cols["Wp/Wt"][0] == 0.94 and np.isnan(cols["Wp/Wt"][1])
    f.write_text("a, b\n1, x\n")
    with pytest.raises(InputError, match="t.csv"):
        read_table(f)
