"""Checks of input values: each returns the value in canonical form or raises `InputError`
with a message that names the parameter, its value and the valid range."""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from .errors import InputError

#: valid ranges of impact inputs: generous physical bounds that also keep every product of
#: them finite in double precision (above 1e4 m/s impacts are shock physics, not contact)
VELOCITY_RANGE = (0.0, 1e4)       # m/s
RADIUS_RANGE = (1e-12, 1e3)       # m
MASS_RANGE = (0.0, 1e6)           # kg
MODULUS_MAX = 1e14                # Pa
THICKNESS_MAX = 1.0               # m


def _fmt(value) -> str:
    try:
        return f"{float(value):.6g}"
    except (TypeError, ValueError):
        return repr(value)


def check_real(name: str, value, *, low: float = -math.inf, high: float = math.inf,
               low_open: bool = False, high_open: bool = False, unit: str = "") -> float:
    """Return `value` as a float, or raise InputError naming `name`, its value and the range.

    Rejects None, booleans, non-numbers, NaN and infinities (unless the range admits them).
    """
    if value is None or isinstance(value, (bool, str)):
        raise InputError(f"{name} must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    lo_ok = x > low if low_open else x >= low
    hi_ok = x < high if high_open else x <= high
    if math.isnan(x) or not (lo_ok and hi_ok):
        lb = "(" if low_open else "["
        rb = ")" if high_open else "]"
        u = f" {unit}" if unit else ""
        raise InputError(f"{name} = {_fmt(value)}{u} is outside the valid range "
                         f"{lb}{_fmt(low)}, {_fmt(high)}{rb}{u}")
    return x


def check_positive(name: str, value, unit: str = "") -> float:
    """A finite number > 0."""
    return check_real(name, value, low=0.0, high=math.inf, low_open=True, high_open=True,
                      unit=unit)


def check_float_array(name: str, values, description: str = "numbers") -> np.ndarray:
    """``values`` as a new float array, or InputError naming ``name`` (text and non-numbers
    are refused; shape checks are the caller's)."""
    if isinstance(values, str):
        raise InputError(f"{name} must be {description}, got {values!r}")
    try:
        return np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be {description}") from None


def check_positive_array(name: str, values, unit: str = "", low: float = 0.0,
                         high: float = math.inf) -> np.ndarray:
    """A float array of finite values in (low, high] (scalars become 0-d arrays)."""
    if isinstance(values, str) or (isinstance(values, (list, tuple))
                                   and any(isinstance(v, (str, bool)) for v in values)):
        raise InputError(f"{name} must be numbers, got {values!r}")
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers, got {values!r}") from None
    bad = ~np.isfinite(arr) | (arr <= low) | (arr > high)
    if np.any(bad):
        first = arr[bad].flat[0]
        u = f" {unit}" if unit else ""
        raise InputError(f"{name} contains {_fmt(first)}{u}: every value must be finite and "
                         f"in ({_fmt(low)}, {_fmt(high)}]{u}")
    return arr


def check_int(name: str, value, low: int, high: int) -> int:
    """An integer in [low, high] (an integral float such as 5.0 is accepted)."""
    x = check_real(name, value, low=low, high=high)
    if x != int(x):
        raise InputError(f"{name} = {value!r} must be an integer in [{low}, {high}]")
    return int(x)


def check_choice(name: str, value, choices: Iterable[str]) -> str:
    """One of `choices` (strings)."""
    choices = tuple(choices)
    if value not in choices:
        raise InputError(f"{name} = {value!r} is not one of: {', '.join(choices)}")
    return value


def check_table(where: str, value) -> dict:
    """A TOML table (a dict), or InputError naming ``[where]``."""
    if not isinstance(value, dict):
        raise InputError(f"[{where}] must be a table, got {type(value).__name__}")
    return value


def check_keys(where: str, table, allowed: Iterable[str]) -> dict:
    """``table`` (a dict) when every key is in ``allowed``; else InputError naming the first
    unknown key as ``where.key`` and listing the valid ones."""
    table = check_table(where, table)
    allowed = set(allowed)
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise InputError(f"unknown key {where}.{unknown[0]} (valid keys in [{where}]: "
                         f"{', '.join(sorted(allowed))})")
    return table


def required(where: str, table: dict, key: str):
    """``table[key]``, or InputError naming ``where.key`` as missing."""
    if key not in table:
        raise InputError(f"{where}.{key} is missing")
    return table[key]
