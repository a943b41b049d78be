"""Declared input keys: one row per key of a scene table (name, SI unit, default, range,
choices, which model kinds read it), used to check a table, to convert quantities with
units, and to write the key list of docs/scenes.md, so that the three never disagree."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .checks import check_choice, check_real
from .errors import InputError

#: the default of a key that must be given
REQUIRED = "required"


@dataclass(frozen=True)
class Key:
    """One key of a scene table.

    ``unit`` is the SI unit of a number ("m", "Pa", "degree"; "1" for a pure number); a key
    with a unit other than "1" also takes a quantity with units ("10 um"). A key without a
    unit is text, or one of ``choices``. ``kinds`` names the impactor shapes that read the key
    (empty: every shape). ``default`` is `REQUIRED`, None (optional, no value) or the value.
    """

    name: str
    unit: str = ""
    default: object = None
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] = ()
    kinds: tuple[str, ...] = ()
    doc: str = ""
    #: the "valid" column of docs/scenes.md when the range alone does not say it
    valid: str = ""
    #: the scene table that holds the key ("impactor", "model", ...)
    section: str = "impactor"

    @property
    def quantity(self) -> bool:
        """Whether the key takes a quantity with units as well as a bare SI number."""
        return self.unit not in ("", "1")

    def read(self, where: str, table: dict):
        """The checked value of this key in ``table`` (a TOML table already in SI), its
        default when absent; InputError naming ``where.name`` otherwise."""
        path = f"{where}.{self.name}"
        if self.name not in table:
            if self.default == REQUIRED:
                raise InputError(f"{path} is missing")
            return self.default
        value = table[self.name]
        if self.choices:
            return check_choice(path, value, self.choices)
        if self.unit:
            return check_real(path, value, low=self.low, high=self.high,
                              low_open=self.low_open, high_open=self.high_open,
                              unit={"1": "", "degree": "degrees"}.get(self.unit, self.unit))
        if not isinstance(value, str):
            raise InputError(f"{path} must be a string, got {value!r}")
        return value

    def valid_text(self) -> str:
        """What docs/scenes.md shows as the valid values."""
        if self.valid:
            return self.valid
        if self.choices:
            return ", ".join(f"`{c}`" for c in self.choices)
        if not self.unit:
            return "text"
        lb, rb = "(" if self.low_open else "[", ")" if self.high_open else "]"
        return f"{lb}{_number(self.low)}, {_number(self.high)}{rb}"

    def default_text(self) -> str:
        """What docs/scenes.md shows in its "required" column."""
        if self.default == REQUIRED:
            return "yes"
        if self.default is None:
            return "no"
        shown = f'"{self.default}"' if isinstance(self.default, str) else _number(self.default)
        return f"no ({shown})"


def _number(value: float) -> str:
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return f"{value:g}"


def read_keys(where: str, table: dict, keys) -> dict:
    """Every key of ``keys`` read from ``table`` (`Key.read`), by name."""
    return {k.name: k.read(where, table) for k in keys}
