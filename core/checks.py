"""Checks of input values: each returns the value in canonical form or raises `InputError`
with a message that names the parameter, its value and the valid range."""

from __future__ import annotations

import copy
import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from .errors import InputError

#: valid ranges of impact inputs: generous physical bounds that also keep every product of
#: them finite in double precision (above 1e4 m/s impacts are shock physics, not contact)
VELOCITY_RANGE = (0.0, 1e4)       # m/s
RADIUS_RANGE = (1e-12, 1e3)       # m
MASS_RANGE = (0.0, 1e6)           # kg
MODULUS_MAX = 1e14                # Pa
THICKNESS_MAX = 1.0               # m

#: Physical plausibility of material and impactor values: wide enough for every solid the
#: package models, narrow enough that a unit slip (a factor 1e3 or more) falls outside.
#: Young's, reduced and indentation moduli: soft polymers (LDPE, rubber-toughened plastics,
#: about 0.1-0.2 GPa) to above diamond (1.14 TPa; no solid reaches 2 TPa).
MODULUS_PLAUSIBLE = (1e8, 2e12)   # Pa
#: sigma_y / E: the ideal strength of a crystal is about E/10 (Frenkel), so sigma_y >= E is
#: impossible; above YIELD_STRAIN_HIGH only whiskers and nanopillars come near
YIELD_STRAIN_HIGH = 0.1
#: Mean density m / (4/3 pi R^3) of an impactor, kg/m^3: below that of air (1.2) a body
#: floats; a ping-pong ball (80), expanded polystyrene (15) and aerogels (from a few) stay
#: above. No upper bound: m may be the effective mass of a larger body whose corner of radius
#: R strikes (a slider corner: 1.6 mg on R = 10 um, 3.8e8 kg/m^3).
DENSITY_MIN = 1.0                 # kg/m^3
#: deepest contact depth of an indentation property profile: 1 mm is macro-hardness
#: (Brinell), beyond the nanometre-to-micrometre depths of a film's profile
INDENT_DEPTH_MAX = 1e-3           # m
#: what a unit slip multiplies a value by: the SI prefixes in steps of 1000
SLIP_FACTORS = (1e-12, 1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e9, 1e12)
#: the units a value in Pa, m or N is usually written in by mistake, by factor to SI
SLIP_UNITS = {
    "Pa": {1e3: "kPa", 1e6: "MPa", 1e9: "GPa"},
    "m": {1e-10: "Angstrom", 1e-9: "nm", 1e-6: "um", 1e-3: "mm"},
    "N": {1e-3: "mN", 1e-6: "uN", 1e-9: "nN"},
}


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
    except OverflowError:       # an integer beyond the float range (TOML allows 4300 digits)
        raise InputError(f"{name} is beyond the range of a float (1.8e308)") from None
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
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be {description}") from None


def check_real_array(name: str, values, *, low: float = -math.inf, high: float = math.inf,
                     low_open: bool = False, high_open: bool = False,
                     unit: str = "") -> np.ndarray:
    """`check_real` for every element: a float array (scalars become 0-d arrays), or
    InputError naming ``name``, the first bad value and the range (NaN always refused)."""
    if isinstance(values, (str, bool)) or (isinstance(values, (list, tuple))
                                           and any(isinstance(v, (str, bool)) for v in values)):
        raise InputError(f"{name} must be numbers, got {values!r}")
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers, got {values!r}") from None
    except OverflowError:
        raise InputError(f"{name} holds a number beyond the range of a float (1.8e308)") \
            from None
    with np.errstate(invalid="ignore"):
        ok = (arr > low if low_open else arr >= low) & (arr < high if high_open else arr <= high)
    if not np.all(ok):
        first = arr[~ok].flat[0]
        u = f" {unit}" if unit else ""
        admits_inf = (math.isinf(high) and not high_open) or (math.isinf(low) and not low_open)
        finite = "" if admits_inf else "finite and "
        raise InputError(f"{name} contains {_fmt(first)}{u}: every value must be {finite}in "
                         f"{'(' if low_open else '['}{_fmt(low)}, {_fmt(high)}"
                         f"{')' if high_open else ']'}{u}")
    return arr


def check_positive_array(name: str, values, unit: str = "", low: float = 0.0,
                         high: float = math.inf) -> np.ndarray:
    """A float array of finite values in (low, high] (scalars become 0-d arrays)."""
    return check_real_array(name, values, low=low, high=high, low_open=True,
                            high_open=math.isinf(high), unit=unit)


def check_int(name: str, value, low: int, high: int) -> int:
    """An integer in [low, high] (an integral float such as 5.0 is accepted)."""
    x = check_real(name, value, low=low, high=high)
    if x != int(x):
        raise InputError(f"{name} = {value!r} must be an integer in [{low}, {high}]")
    return int(x)


def check_path(name: str, value) -> Path:
    """``value`` as a Path when it names a file: a non-empty str or an os.PathLike that gives
    one; else InputError naming ``name`` and what it got. None, numbers (``os.stat(3)`` would
    read file descriptor 3), bytes and open files are not file names."""
    text = os.fspath(value) if isinstance(value, os.PathLike) else value
    if isinstance(text, str) and text:
        return Path(text)
    got = "an empty name" if isinstance(text, str) else "None" if value is None else \
        f"{type(value).__name__} {_short_repr(value)}"
    raise InputError(f"{name} must be a file path (str or os.PathLike), got {got}")


def _short_repr(value, width: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= width else text[:width - 3] + "..."


def preset_table(presets: dict, name) -> dict:
    """A copy of the named preset's table (a spec's, a recipe's) to build from; InputError
    naming the presets."""
    if not isinstance(name, str) or name not in presets:
        raise InputError(f"preset = {_short_repr(name)} is not one of {', '.join(presets)}")
    return copy.deepcopy(presets[name])


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


def check_broadcast(**arrays) -> list[np.ndarray]:
    """The arrays broadcast to one shape, or InputError naming each one's shape."""
    try:
        return np.broadcast_arrays(*arrays.values())
    except ValueError:
        shapes = ", ".join(f"{name} {np.shape(a)}" for name, a in arrays.items())
        raise InputError(f"array shapes do not match: {shapes} cannot be broadcast to one "
                         "shape") from None


def slip_factor(value: float, plausible, typical: float, exponent: float = 1.0,
                factors=SLIP_FACTORS) -> float | None:
    """The unit slip that explains an implausible value: the factor f (a step of 1000, see
    `SLIP_FACTORS`) for which the checked quantity ``value * f**exponent`` is
    ``plausible(...)`` and nearest ``typical`` (logarithmically); None when no factor helps.
    ``exponent`` is how the checked quantity scales with the input that was mistyped (-3 for
    a density against a radius)."""
    best = None
    for f in factors:
        scaled = value * f**exponent
        if scaled > 0 and plausible(scaled):
            distance = abs(math.log(scaled / typical))
            if best is None or distance < best[0]:
                best = (distance, f)
    return None if best is None else best[1]


def slip_hint(name: str, value: float, factor: float | None, unit: str) -> str:
    """The suggestion ``; did you mean NAME = 10e-6 (um written as m)?`` of ``value`` times
    ``factor``, or "" when there is no factor."""
    if factor is None:
        return ""
    written = f"{value:g}"
    exponent = round(math.log10(factor))
    meant = f"{written}e{exponent}" if "e" not in written and "inf" not in written \
        else f"{value * factor:g}"
    prefixed = SLIP_UNITS.get(unit, {}).get(factor)
    why = f" ({prefixed} written as {unit})" if prefixed else ""
    return f"; did you mean {name} = {meant}{why}?"


def check_modulus(name: str, value, what: str = "modulus") -> float:
    """A modulus in `MODULUS_PLAUSIBLE` (Pa), else InputError that suggests the unit slip."""
    x = check_positive(name, value, "Pa")
    low, high = MODULUS_PLAUSIBLE
    if low <= x <= high:
        return x
    where = (f"below {low / 1e9:g} GPa, softer than soft polymers" if x < low else
             f"above {high / 1e12:g} TPa, stiffer than diamond (1.14 TPa)")
    factor = slip_factor(x, lambda v: low <= v <= high, typical=100e9)
    raise InputError(f"{name} = {_fmt(x)} Pa is not a plausible {what}: {where}"
                     + slip_hint(name, x, factor, "Pa"))


def check_yield_strength(name: str, sigma_y: float, E: float, E_name: str = "E") -> float:
    """``sigma_y`` (Pa) below ``E`` (Pa; yield strains of 1 and more do not exist), else
    InputError that suggests the slip; infinity (never yields) passes."""
    if sigma_y < E or math.isinf(sigma_y):
        return sigma_y
    factor = slip_factor(sigma_y, lambda v: v <= YIELD_STRAIN_HIGH * E, typical=0.01 * E)
    raise InputError(f"{name} = {_fmt(sigma_y)} Pa is not below {E_name} = {_fmt(E)} Pa: a "
                     f"yield strain sigma_y/E of {sigma_y / E:.3g} is impossible (the ideal "
                     f"strength of a crystal is about E/10)"
                     + slip_hint(name, sigma_y, factor, "Pa"))


def sphere_density(radius: float, mass: float) -> float:
    """m / (4/3 pi R^3), kg/m^3."""
    return mass / (4.0 / 3.0 * math.pi * radius**3)


def check_density(radius: float, mass: float, radius_name: str = "radius",
                  mass_name: str = "mass") -> float:
    """The mean density (kg/m^3) of a sphere of ``radius`` (m) and ``mass`` (kg), or
    InputError when it is below `DENSITY_MIN`, with the radius that the likely unit slip
    meant."""
    density = sphere_density(radius, mass)
    if density >= DENSITY_MIN:
        return density
    factor = slip_factor(density, lambda v: v >= DENSITY_MIN, typical=5000.0, exponent=-3.0,
                         factors=(1e-3, 1e-6, 1e-9))
    raise InputError(f"{radius_name} = {_fmt(radius)} m with {mass_name} = {_fmt(mass)} kg "
                     f"gives a mean density m/(4/3 pi R^3) of {density:.3g} kg/m^3, below "
                     f"{DENSITY_MIN:g} kg/m^3 (lighter than air)"
                     + slip_hint(radius_name, radius, factor, "m"))


def check_indent_depths(name: str, depths) -> np.ndarray:
    """Contact depths (m) no deeper than `INDENT_DEPTH_MAX`, else InputError that suggests
    the unit the depths were written in."""
    depths = np.asarray(depths, dtype=float)
    deepest = float(np.max(depths))
    if deepest <= INDENT_DEPTH_MAX:
        return depths
    factor = slip_factor(deepest, lambda v: v <= INDENT_DEPTH_MAX, typical=1e-6,
                         factors=(1e-9, 1e-6, 1e-3))
    raise InputError(f"{name} reaches {_fmt(deepest)} m, deeper than "
                     f"{INDENT_DEPTH_MAX * 1e3:g} mm (macro-hardness, not a film's depth "
                     f"profile)" + slip_hint(f"{name} values", deepest, factor, "m"))
