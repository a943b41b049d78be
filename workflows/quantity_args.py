"""Command-line options that take a dimensional number: a bare number in SI or a quantity with
units ("10 um", "90 GPa", "0.5 m/s"). Each option is declared with its SI unit
(`add_quantity_argument`) and converted after parsing (`convert_quantities`), so that a
value of the wrong dimension is an InputError naming the option, the value and the unit
(exit 2, one line), as every other bad input is.
"""

from __future__ import annotations

import argparse

from filmscale.core.quantities import to_si


def range_arg(text: str) -> tuple[str, str, int]:
    """MIN:MAX:N with MIN and MAX numbers or quantities (converted later), N an integer."""
    parts = text.split(":")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"expected MIN:MAX:N, got {text!r}")
    try:
        count = int(parts[2])
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer count N in MIN:MAX:N, got "
                                         f"{text!r}") from None
    return parts[0], parts[1], count


def add_quantity_argument(parser: argparse.ArgumentParser, flag: str, unit: str, **kwargs):
    """``parser.add_argument(flag, **kwargs)`` for a value in the SI ``unit`` ("m", "Pa",
    "m/s", ...); with ``type=range_arg`` the MIN and MAX of a range are quantities."""
    action = parser.add_argument(flag, **kwargs)
    known = dict(parser.get_default("quantities") or {})
    known[action.dest] = (flag, unit)
    parser.set_defaults(quantities=known)
    return action


def convert_quantities(args: argparse.Namespace) -> None:
    """Replace each quantity option's text in ``args`` by its SI float (ranges: MIN and
    MAX); InputError for one that is not a number or a quantity of the option's unit."""
    for dest, (flag, unit) in (getattr(args, "quantities", None) or {}).items():
        value = getattr(args, dest)
        if isinstance(value, tuple):
            low, high, count = value
            value = (_number(f"{flag} minimum", low, unit),
                     _number(f"{flag} maximum", high, unit), count)
        elif value is not None:
            value = _number(flag, value, unit)
        setattr(args, dest, value)


def _number(name: str, value, unit: str) -> float:
    return float(to_si(name, value, unit))
