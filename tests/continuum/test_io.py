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
