"""Quantity text in one strict number format (issue 31): pint alone reads "10,5 um" as 105 um,
"10 5 um" as 50 um and "1.6.1 mg" as 0.16 mg; `to_si` refuses them, in scenes and on the
command line, saying what was likely meant, and every quantity written in the one format
still reads to its SI value."""

import math

import pytest

from filmscale.core.errors import InputError
from filmscale.core.quantities import to_si
from filmscale.workflows.cli import main
from tests.helpers.scenes import HERTZ_SCENE

SCENE = HERTZ_SCENE.replace("radius = 10e-6", "radius = {radius}")

#: (text, SI unit, the message after "x = '<text>': ")
MISREAD = [
    ("10,5 um", "m", "write 10.5 um (a decimal point, not a comma)"),
    ("10 5 um", "m", "two numbers; write one, e.g. 105 um or 10.5 um"),
    ("1.6.1 mg", "kg", "more than one decimal point"),
    ("-0,5 m/s", "m/s", "write -0.5 m/s (a decimal point, not a comma)"),
    (",5 um", "m", "write .5 um (a decimal point, not a comma)"),
    ("10,5", "m", "write 10.5 (a decimal point, not a comma)"),
    ("1,234.5 nm", "m", "thousands separators; write 1234.5 nm"),
    ("1,234,567 Pa", "Pa", "thousands separators; write 1234567 Pa"),
    ("1,234 nm", "m", "write 1.234 nm (a decimal point, not a comma) or 1234 nm (no thousands "
                      "separators)"),
    ("1.234,5 nm", "m", "thousands separators and a decimal comma; write 1234.5 nm"),
    ("1_000 nm", "m", "thousands separators; write 1000 nm"),
    ("1'000 nm", "m", "thousands separators; write 1000 nm"),
    ("1 000 000 nm", "m", "thousands separators; write 1000000 nm"),
    ("1 2 3 um", "m", "3 numbers (1, 2, 3); write one number before the unit"),
    ("1.2.3", "m", "more than one decimal point"),
    ("10 um 5", "m", "a number in the unit 'um 5'; write one number, then the unit"),
    ("10 um * 5", "m", "a number in the unit 'um * 5'"),
    ("10 * um", "m", "the unit '* um' after the number must start with a letter"),
]


@pytest.mark.parametrize("text, unit, says", MISREAD)
def test_numbers_in_another_format_are_refused_with_the_likely_meaning(text, unit, says):
    with pytest.raises(InputError) as err:
        to_si("x", text, unit)
    assert str(err.value).startswith(f"x = {text!r}: {says}")


@pytest.mark.parametrize("text", ["10,5 um", "10 5 um", "1.6.1 mg", "1,234.5 nm"])
def test_scene_text_numbers_are_checked_before_the_quotes(text):
    # a scene refuses quoted bare numbers, but a misread quantity is named as such
    with pytest.raises(InputError, match=r"^impactor\.radius = '"):
        to_si("impactor.radius", text, "m" if "mg" not in text else "kg", text_numbers=False)


@pytest.mark.parametrize("text", ["١٠ um", "١٠", "１０ um", "ten um", "um 10", "e5 m", "nan um",
                                  "0x10 m"])
def test_no_number_in_the_one_format_is_not_a_quantity(text):
    with pytest.raises(InputError, match=rf"^x (must be a number, got |= ){text!r}"):
        to_si("x", text, "m")


#: (text, SI unit, SI value) written in the one format: every one reads exactly as before.
#: The SI values are written by hand (the unit's definition), independent of pint; they are
#: compared with == (no tolerance): each is the float the conversion gave before issue 31
VALID = [
    ("90 GPa", "Pa", 90e9), ("2.4e9 Pa", "Pa", 2.4e9), ("90 gigapascal", "Pa", 90e9),
    ("+2.5 GPa", "Pa", 2.5e9), ("500 MPa", "Pa", 5e8),
    ("10 um", "m", 10e-6), ("10um", "m", 10e-6), ("10\tum", "m", 10e-6), ("5 µm", "m", 5e-6),
    ("5 μm", "m", 5e-6), (".5 um", "m", 0.5e-6), ("5. um", "m", 5e-6), ("-3 nm", "m", -3e-9),
    ("250 nm", "m", 250e-9), ("1e+3 nm", "m", 1e-6), ("1E-3 m", "m", 1e-3),
    ("1e-5m", "m", 1e-5), ("10 Å", "m", 1e-9), ("1 inch", "m", 0.0254),
    ("0.5 m/s", "m/s", 0.5), ("100 mm/s", "m/s", 0.1), ("1 mm/s", "m/s", 1e-3),
    ("1.6 mg", "kg", 1.6e-6), ("2 g", "kg", 2e-3),
    ("5 mN", "N", 5e-3), ("5 kN", "N", 5e3), ("2 us", "s", 2e-6), ("1 nJ", "J", 1e-9),
    ("1e5 N/m", "N/m", 1e5), ("2 mN/um", "N/m", 2e3), ("0.2 nm/mN", "m/N", 0.2e-6),
    ("30 deg", "degree", 30.0), ("30°", "degree", 30.0), ("5 1/s", "1/s", 5.0),
    ("5/s", "1/s", 5.0), ("2 m^2", "m^2", 2.0), ("1 m**2", "m^2", 1.0),
    ("3 cm^2", "m^2", 3e-4), ("1 g/cm^3", "kg/m^3", 1e3), ("2.7 g/cm3", "kg/m^3", 2.7e3),
    # bare numbers as text (the command line): SI
    ("1e-5", "m", 1e-5), (" 1e-5 ", "m", 1e-5), ("5.", "m", 5.0), (".5", "m", 0.5),
    ("-7", "m", -7.0), ("+7", "m", 7.0), ("90E9", "Pa", 90e9),
]


def test_the_one_format_table_covers_every_kind_of_quantity():
    assert len(VALID) >= 30


@pytest.mark.parametrize("text, unit, si", VALID)
def test_quantities_in_the_one_format_read_to_their_si_value(text, unit, si):
    assert to_si("x", text, unit) == si


@pytest.mark.parametrize("text", ["nan", "inf", "-inf", "Infinity", "NaN"])
def test_non_finite_text_numbers_reach_the_range_checks(text):
    value = to_si("x", text, "m")
    assert math.isnan(value) or math.isinf(value)


def test_a_non_decimal_factor_still_converts():
    assert to_si("x", "3 km/h", "m/s") == pytest.approx(3000 / 3600, rel=1e-15)


@pytest.mark.parametrize("radius, says", [
    ('"10,5 um"', "impactor.radius = '10,5 um': write 10.5 um (a decimal point, not a comma)"),
    ('"10 5 um"', "impactor.radius = '10 5 um': two numbers; write one, e.g. 105 um or 10.5 um"),
    ('"1.6.1 mm"', "impactor.radius = '1.6.1 mm': more than one decimal point"),
    ('["1,5 um", "50 um", 4]', "map.radius minimum = '1,5 um': write 1.5 um"),
])
def test_a_scene_with_a_misread_quantity_exits_2_with_one_line(tmp_path, capsys, radius, says):
    scene = tmp_path / "s.toml"
    text = SCENE.format(radius=radius if not radius.startswith("[") else "10e-6")
    if radius.startswith("["):
        text += f"\n[map]\nvelocity = [0.01, 1.0, 4]\nradius = {radius}\n"
    scene.write_text(text)
    assert main(["plan", str(scene)]) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1 and "Traceback" not in err


@pytest.mark.parametrize("flag, value, says", [
    ("--radius", "10,5 um", "--radius = '10,5 um': write 10.5 um (a decimal point, not a comma)"),
    ("--radius", "10 5 um", "--radius = '10 5 um': two numbers; write one, e.g. 105 um or 10.5 um"),
    ("--mass", "1.6.1 mg", "--mass = '1.6.1 mg': more than one decimal point"),
    ("--velocity", "1,5", "--velocity = '1,5': write 1.5 (a decimal point, not a comma)"),
])
def test_the_command_line_refuses_misread_quantities(tmp_path, capsys, flag, value, says):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.format(radius="10e-6"))
    assert main(["impact", str(scene), flag, value]) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1 and "Traceback" not in err


def test_the_command_line_still_reads_quantities(tmp_path, capsys):
    import json
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.format(radius='"10.5 um"'))
    assert main(["impact", str(scene), "--mass", "1.6 mg", "--velocity", "5e-2 m/s",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["radius"], out["mass"], out["velocity"]) == (10.5e-6, 1.6e-6, 0.05)
