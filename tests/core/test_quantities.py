"""Quantities with units in (`to_si`) and engineering units out (`eng`)."""

import math

import pytest

from filmscale.core.errors import InputError
from filmscale.core.quantities import eng, to_si


@pytest.mark.parametrize("text, unit, si", [
    ("90 GPa", "Pa", 90e9), ("10 um", "m", 10e-6), ("10um", "m", 10e-6),
    ("5 µm", "m", 5e-6), ("5 μm", "m", 5e-6),          # micro sign and Greek mu
    ("0.5 m/s", "m/s", 0.5), ("1 mm/s", "m/s", 1e-3), ("1.6 mg", "kg", 1.6e-6),
    ("250 nm", "m", 250e-9), ("2.4 GPa", "Pa", 2.4e9), ("5 mN", "N", 5e-3),
    ("0.2 nm/mN", "m/N", 0.2e-6), ("30 deg", "degree", 30.0), ("1 inch", "m", 0.0254),
])
def test_text_with_units_is_the_float_of_the_same_value_typed_in_si(text, unit, si):
    # exact: a decimal prefix shifts the decimal text ("1.6 mg" is 1.6e-6, not 1.6 * 1e-6);
    # the one non-decimal factor (inch) is pint's exact 0.0254
    assert to_si("x", text, unit) == si


@pytest.mark.parametrize("value", [1e-5, 0.2, 90e9, 7, None, [1, 2], True])
def test_numbers_and_non_text_pass_unchanged(value):
    assert to_si("x", value, "m") is value


def test_text_that_is_a_bare_number_is_si():
    assert to_si("x", " 1e-5 ", "m") == 1e-5


@pytest.mark.parametrize("text, unit, says", [
    ("10 GPa", "m", "impactor.radius = '10 GPa' is not a length: expected"),
    ("10 um", "Pa", "impactor.radius = '10 um' is not a stress or modulus: expected"),
    ("5 kg", "m/s", "impactor.radius = '5 kg' is not a speed: expected"),
    ("ten microns", "m", "impactor.radius must be a number, got 'ten microns' (or"),
    ("a", "m/s", "impactor.radius must be a number, got 'a' (or"),     # pint: a year
    ('__import__("os")', "m", "impactor.radius must be a number, got '__import__"),
    ("1 um um", "m", "impactor.radius = '1 um um' is not a length"),
    ("", "m", "impactor.radius must be a number, got '' (or"),
])
def test_wrong_dimension_or_no_quantity_names_parameter_value_and_unit(text, unit, says):
    with pytest.raises(InputError) as err:
        to_si("impactor.radius", text, unit)
    message = str(err.value)
    assert message.startswith(says)
    assert f" in {unit} or with units, such as " in message


def test_text_numbers_can_be_refused():
    with pytest.raises(InputError, match=r"^E must be a number, got '90e9' \(a number without "
                                         r"quotes, or a stress or modulus in Pa or with units"):
        to_si("E", "90e9", "Pa", text_numbers=False)
    assert to_si("E", "90 GPa", "Pa", text_numbers=False) == 90e9


@pytest.mark.parametrize("value, unit, text", [
    (6.17535e-07, "m", "617.5 nm"), (7.133e9, "Pa", "7.133 GPa"), (0.2, "m/s", "0.2 m/s"),
    (1.6e-6, "kg", "1.6 mg"), (0.119737, "N", "119.7 mN"), (8.41092e-6, "s", "8.411 µs"),
    (9.99996e-7, "m", "1 µm"),            # rounds up into the next prefix
    (1.14e12, "Pa", "1140 GPa"),          # moduli stay in GPa
    (0.0, "m", "0 m"), (-5e-9, "m", "-5 nm"), (2.5e5, "N/m", "2.5e+05 N/m"),
    (0.3, "", "0.3"), (math.inf, "m", "inf m"),
])
def test_eng_writes_engineering_units(value, unit, text):
    assert eng(value, unit) == text


def test_eng_gives_the_std_in_the_value_prefix():
    assert eng(101.23e9, "Pa", std=3.14e9) == "101.2 +- 3.14 GPa"
    assert eng(12e-9, "m", std=0.3e-9) == "12 +- 0.3 nm"
    assert eng(5e9, "Pa", std=math.nan) == "5 GPa"
