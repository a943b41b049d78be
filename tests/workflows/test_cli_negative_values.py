"""Negative numbers on the command line are values, in any form float() reads (-5e6, -.5,
-inf) and as the start of a range (-1:1:3): `cli.Parser` joins each to the option before it
that takes a value (``--angle=-5e6``), through argparse's public interface only; the range
checks then judge them (tests/workflows/test_hostile_cli.py: exit 2 and one line)."""

from pathlib import Path

import pytest

from filmscale.workflows import cli

EXAMPLE = str(Path(__file__).resolve().parents[2] / "examples" / "slider_corner_disk.toml")

@pytest.fixture(scope="module")
def parser():
    return cli.build_parser()


@pytest.mark.parametrize("argv, dest, value", [
    (["impact", "s.toml", "--angle", "-5e6"], "angle", -5e6),
    (["impact", "s.toml", "--velocity", "-inf"], "velocity", "-inf"),
    (["impact", "s.toml", "--velocity", "-NaN"], "velocity", "-NaN"),
    (["impact", "s.toml", "--mass", "-.5"], "mass", "-.5"),
    (["impact", "s.toml", "--vel", "-1e3"], "velocity", "-1e3"),          # an abbreviation
    (["impact", "s.toml", "--radius=-1e-6"], "radius", "-1e-6"),           # already joined
    (["impact-map", "s.toml", "--velocity", "-1:1:3"], "velocity", ("-1", "1", 3)),
    (["impact-map", "s.toml", "--radius", "-1e-6:1e-5:3"], "radius",      # in a group
     ("-1e-6", "1e-5", 3)),
    (["indent", "reverse", "--C", "-1E11", "--dPdh", "2e5", "--WpWt", "0.5", "--hm",
      "1e-6"], "C", "-1E11"),
    (["indent", "analyze", "f.csv", "--window", "-.1:0.9"], "window", (-0.1, 0.9)),
    (["calibrate", "f.csv", "--tolerance", "-1e-2"], "tolerance", -1e-2),
    (["sweep", "run", "s.toml", "--only", "-1"], "only", -1),
])
def test_a_negative_number_after_an_option_is_its_value(parser, argv, dest, value):
    assert getattr(parser.parse_args(argv), dest) == value


def test_the_joined_arguments(parser):
    impact = next(a for a in parser._actions if a.dest == "command").choices["impact"]
    assert impact.joined_values(["s.toml", "--angle", "-5e6", "--json", "--mass", "-inf"]) \
        == ["s.toml", "--angle=-5e6", "--json", "--mass=-inf"]
    # a flag takes no value; an unknown option and what follows `--` are left as they are
    assert impact.joined_values(["--json", "-5e6"]) == ["--json", "-5e6"]
    assert impact.joined_values(["--out", "-5e6"]) == ["--out", "-5e6"]
    assert impact.joined_values(["--", "--angle", "-5e6"]) == ["--", "--angle", "-5e6"]
    # an option's value that is an ordinary word, and a negative word that is not a number
    assert impact.joined_values(["--angle", "5", "--mass", "-x"]) == \
        ["--angle", "5", "--mass", "-x"]


def test_an_ambiguous_abbreviation_is_left_to_argparse(parser, capsys):
    with pytest.raises(SystemExit) as done:
        parser.parse_args(["indent", "analyze", "f.csv", "--fi", "-1e-9"])
    assert done.value.code == 2
    assert "ambiguous option: --fi could match" in capsys.readouterr().err


def test_the_parser_sets_no_private_attribute_of_argparse():
    assert "_negative_number_matcher" not in Path(cli.__file__).read_text()


@pytest.mark.parametrize("argv, message", [
    (["impact-map", EXAMPLE, "--velocity", "-inf:1:3", "--out", "m.h5"],
     "--velocity minimum = -inf m/s is outside the valid range"),
    (["impact", EXAMPLE, "--radius", "-INF"], "--radius = -inf m is outside the valid range"),
])
def test_the_range_check_answers_a_negative_value(argv, message, tmp_path, monkeypatch,
                                                   capsys):
    """Past the parser: exit 2 and one line from the range check, nothing written."""
    monkeypatch.chdir(tmp_path)
    status = cli.main(argv)
    err = capsys.readouterr().err
    assert status == 2 and message in err and len(err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
