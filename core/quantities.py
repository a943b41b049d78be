"""Quantities with units: text such as "90 GPa", "10 um" or "0.5 m/s" read into SI numbers
(`to_si`), and SI numbers written for people in engineering units (`eng`: "617.5 nm",
"7.133 GPa"). Files and JSON stay in SI; only what people type and read carries units.

pint parses the unit, imported on the first string that is not a bare number, so that a
command given SI numbers never loads it. The number is read here first, in one strict format
(a sign, ASCII digits with at most one decimal point, an exponent): pint alone reads "10,5 um"
as 105 um, "10 5 um" as 50 um and "1.6.1 mg" as 0.16 mg, where these are refused saying what
was likely meant.
"""

from __future__ import annotations

import functools
import math
import re
from decimal import Decimal

from .errors import InputError

#: what each SI unit measures, for the message of a quantity of the wrong dimension
_MEASURES = {"m": "a length", "Pa": "a stress or modulus", "m/s": "a speed", "kg": "a mass",
             "N": "a force", "s": "a time", "N/m": "a stiffness", "m/N": "a compliance",
             "degree": "an angle", "J": "an energy", "kg/m^3": "a density"}
#: an example of each, written with units
_EXAMPLES = {"m": "10 um", "Pa": "90 GPa", "m/s": "0.5 m/s", "kg": "1.6 mg", "N": "5 mN",
             "s": "2 us", "N/m": "1e5 N/m", "m/N": "0.2 nm/mN", "degree": "30 deg",
             "J": "1 nJ", "kg/m^3": "3.0 g/cm3"}
#: longer text is not a quantity (and is not handed to the parser)
_MAX_TEXT = 100
#: the one number format read: a sign, ASCII digits with at most one decimal point (``.5``
#: and ``5.`` too), an exponent; no decimal comma, no thousands separators
_NUMBER = r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?"
_BARE = re.compile(rf"{_NUMBER}|[-+]?(?:nan|inf|infinity)", re.IGNORECASE)
#: a number, then the unit: starting with a letter, ``°``, ``%``, ``/`` or ``1/`` (``1/s``)
_QUANTITY = re.compile(rf"({_NUMBER})\s*((?:[^\W\d_]|[°%/]|1\s*/).*)", re.DOTALL)
#: the digits a unit may hold: a power (``m^2``, ``m**-1``, ``m^(1/2)``), digits right after
#: a letter (``cm3``) and the 1 of a leading ``1/``
_UNIT_DIGITS = re.compile(r"^1(?=\s*/)|(?<=[^\W\d_])[0-9]+|(?:\^|\*\*)\s*\(?\s*[-+]?[0-9]+"
                          r"(?:\.[0-9]+)?(?:\s*/\s*[0-9]+)?\s*\)?")
#: the leading digits, marks and blanks of a quantity that is not in the one format
_HEAD = re.compile(r"([-+]?)([0-9.,_'\s]*[0-9]\.?)\s*(.*)", re.DOTALL)


@functools.lru_cache(maxsize=1)
def _registry():
    import pint             # 0.2-0.3 s: only when some text needs parsing
    return pint.UnitRegistry()


def to_si(name: str, value, unit: str, text_numbers: bool = True):
    """``value`` in the SI ``unit`` ("m", "Pa", "m/s", "kg", "N", "s", "N/m", "m/N",
    "degree"): text with units ("10 um", "5 µm", "90 GPa") is converted, text that is a bare
    number is that number in SI (refused when not ``text_numbers``: a scene writes numbers
    without quotes), and anything else (numbers, lists, None) is returned as it is for the
    range checks to judge. The number is in one format (`_NUMBER`: no decimal comma, no
    thousands separators, one number) and the unit after it starts with a letter. Raises
    InputError naming ``name``, the value and the unit expected when the text is not a
    quantity or has another dimension, and what was likely meant for a number in another
    format ("10,5 um": write 10.5 um)."""
    if not isinstance(value, str):
        return value
    measure = _MEASURES.get(unit, f"a quantity in {unit}")
    expected = (f"{measure} in {unit} or with units, such as "
                f"{_EXAMPLES.get(unit, '1 ' + unit)!r}")
    text = value.strip()
    if _BARE.fullmatch(text):
        if text_numbers:
            return float(text)
        raise InputError(f"{name} must be a number, got {value!r} (a number without quotes, "
                         f"or {expected})")
    match = _QUANTITY.fullmatch(text) if len(text) <= _MAX_TEXT else None
    if match is None or re.search(r"[0-9]", _UNIT_DIGITS.sub("", match.group(2))):
        # a quantity starts with its number, in one format: pint alone would read "a" as a
        # year, "m" as 1 m, "10 5 um" as 50 um and "10,5 um" as 105 um
        reason = _misread(text)
        if reason:
            raise InputError(f"{name} = {value!r}: {reason}")
        raise InputError(f"{name} must be a number, got {value!r} (or {expected})")
    import pint
    ureg = _registry()
    try:
        # a power written right after its unit ("g/cm3") as pint reads it ("g/cm^3")
        unit_text = re.sub(r"(?<=[^\W\d_])([0-9]+)", r"^\1", match.group(2))
        quantity = ureg.Quantity(f"{match.group(1)} {unit_text}")
    except Exception:       # pint's tokenizer and parser raise many kinds on malformed text
        raise InputError(f"{name} must be a number, got {value!r} (or {expected})") from None
    try:
        factor = float(ureg.Quantity(1.0, quantity.units).to(unit).magnitude)
        magnitude = float(quantity.magnitude)
    except pint.DimensionalityError:
        raise InputError(f"{name} = {value!r} is not {measure}: expected {expected}") \
            from None
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} is not a single number: expected {expected}") \
            from None
    exponent = round(math.log10(factor)) if factor > 0 else 0
    if math.isclose(factor, 10.0**exponent, rel_tol=1e-12):
        # a power of ten shifts the decimal text, so that "1.6 mg" is the very float that
        # 1.6e-6 is (1.6 * 1e-6 is not)
        return float(Decimal(repr(magnitude)).scaleb(exponent))
    return magnitude * factor


def _misread(text: str) -> str | None:
    """Why ``text``, not in the one number format, is refused and what was likely meant: a
    decimal comma, thousands separators, two numbers, a second decimal point; None when
    it does not start with a number at all."""
    match = _HEAD.fullmatch(text) if len(text) <= _MAX_TEXT else None
    if match is None:
        return None
    sign, head, rest = match.groups()
    head = re.sub(r"\s+", " ", head)
    unit = f" {rest}" if rest else ""
    if re.fullmatch(r"[0-9]{1,3}(?:\.[0-9]{3})+,[0-9]+", head):
        whole, frac = head.split(",")
        return (f"thousands separators and a decimal comma; write "
                f"{sign}{whole.replace('.', '')}.{frac}{unit}")
    if re.fullmatch(r"[0-9]{1,3}(?:,[0-9]{3})+(?:\.[0-9]*)?", head):
        if "." in head or head.count(",") > 1:
            return f"thousands separators; write {sign}{head.replace(',', '')}{unit}"
        return (f"write {sign}{head.replace(',', '.')}{unit} (a decimal point, not a comma) "
                f"or {sign}{head.replace(',', '')}{unit} (no thousands separators)")
    if re.fullmatch(r"[0-9]*,[0-9]+", head):
        return f"write {sign}{head.replace(',', '.')}{unit} (a decimal point, not a comma)"
    if re.fullmatch(r"[0-9]{1,3}(?:[_'][0-9]{3})+(?:\.[0-9]*)?|[0-9]{1,3}(?: [0-9]{3}){2,}",
                    head):
        plain = re.sub(r"[_' ]", "", head)
        return f"thousands separators; write {sign}{plain}{unit}"
    words = head.split(" ")
    if len(words) == 2 and all(w.isdigit() for w in words):
        return (f"two numbers; write one, e.g. {sign}{''.join(words)}{unit} or "
                f"{sign}{'.'.join(words)}{unit}")
    if len(words) > 1:
        return f"{len(words)} numbers ({', '.join(words)}); write one number before the unit"
    if "," in head:
        return "a comma in the number; write it with a decimal point and no commas"
    if head.count(".") > 1:
        return "more than one decimal point"
    if re.match(r"[0-9]", rest):
        return "two numbers; write one number before the unit"
    if re.search(r"[0-9]", _UNIT_DIGITS.sub("", rest)):
        return (f"a number in the unit {rest!r}; write one number, then the unit "
                "(powers as m^2)")
    if rest and not re.match(r"[^\W\d_]|[°%/]", rest):
        return f"the unit {rest!r} after the number must start with a letter"
    return None


#: prefixes by power of ten
_PREFIXES = {-12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G"}
#: the powers of ten each unit is written with: the ones its users read (moduli and
#: pressures in MPa and GPa, never TPa; masses in g with prefixes)
_SCALES = {"m": (-12, -9, -6, -3, 0), "Pa": (0, 3, 6, 9), "N": (-9, -6, -3, 0),
           "s": (-12, -9, -6, -3, 0), "J": (-15, -12, -9, -6, -3, 0),
           "g": (-9, -6, -3, 0, 3)}
_PREFIXES[-15] = "f"


def eng(value, unit: str, digits: int = 4, std=None) -> str:
    """An SI ``value`` in ``unit`` for people: scaled to the prefix that puts it in
    [1, 1000) where the unit takes prefixes ("617.5 nm", "7.133 GPa", "1.6 mg" for kg),
    with ``digits`` significant digits; other units ("m/s", "N/m") as they are. A standard
    deviation ``std`` (not NaN) follows in the same prefix with 3 digits: "101.2 +- 3.14 GPa"."""
    x = float(value)
    scale = 1.0
    if unit == "kg":
        scale, unit = 1e3, "g"
    x *= scale
    scales = _SCALES.get(unit)
    power = 0
    if scales is not None and math.isfinite(x) and x != 0.0:
        power = 3 * math.floor(math.log10(abs(x)) / 3)
        # a mantissa that rounds up to 1000 belongs to the next prefix
        if abs(float(f"{x / 10.0**power:.{digits}g}")) >= 1000.0:
            power += 3
        power = min(max(power, scales[0]), scales[-1])
    text = f"{x / 10.0**power:.{digits}g}"
    if std is not None and not math.isnan(std):
        text += f" +- {float(std) * scale / 10.0**power:.3g}"
    return f"{text} {_PREFIXES[power]}{unit}".rstrip()
