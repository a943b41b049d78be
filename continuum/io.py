"""Reading columns of numbers with units in the header, converted to SI.

The first non-empty line is the header (a leading # is allowed): it names each column and may
give its unit in brackets, ``h_c [nm], E_r [GPa], H [GPa]`` (comma- or whitespace-separated).
Later lines starting with # are comments. A column without a unit is taken as SI already.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np

from .errors import InputError

#: unit -> factor to SI (m, Pa, N, s)
UNITS = {
    "m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9, "A": 1e-10, "Å": 1e-10,
    "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9,
    "N": 1.0, "mN": 1e-3, "uN": 1e-6, "µN": 1e-6, "nN": 1e-9,
    "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9, "ps": 1e-12,
    "1": 1.0, "-": 1.0,
}

_COLUMN = re.compile(r"\s*([^\[\],\s]+)\s*(?:\[([^\]]*)\])?\s*")


def parse_header(line: str) -> list[tuple[str, float]]:
    """[(name, factor to SI)] from a header such as ``h [nm], P [uN], t [s]``."""
    out, pos = [], 0
    text = line.strip().lstrip("#").strip()
    while pos < len(text):
        match = _COLUMN.match(text, pos)
        if not match or match.end() == pos:
            raise InputError(f"cannot read the column header near {text[pos:pos + 20]!r}")
        name, unit = match.group(1), match.group(2)
        if unit is not None and unit.strip() not in UNITS:
            raise InputError(f"unknown unit [{unit}] for column {name!r}; known: "
                             f"{', '.join(UNITS)}")
        out.append((name, UNITS[unit.strip()] if unit is not None else 1.0))
        pos = match.end()
        if pos < len(text) and text[pos] == ",":
            pos += 1
    return out


def read_table(path, required: tuple[str, ...] = ()) -> dict[str, np.ndarray]:
    """Columns of a text table in SI, by header name. Raises InputError naming the file."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError as err:
        raise InputError(f"cannot read table {path}: {err.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"table {path} is not UTF-8 text") from None
    lines = [ln for ln in lines if ln.strip()]
    if not lines or not re.search(r"[A-Za-z_]", lines[0]):
        raise InputError(f"table {path} has no header line naming its columns")
    header = lines[0]
    body = [ln for ln in lines[1:] if not ln.lstrip().startswith("#")]
    if not body:
        raise InputError(f"table {path} has a header but no rows of numbers")
    columns = parse_header(header)
    try:
        data = np.loadtxt(io.StringIO("\n".join(ln.replace(",", " ") for ln in body)), ndmin=2)
    except ValueError as err:
        raise InputError(f"table {path}: {err}") from None
    if data.shape[1] != len(columns):
        raise InputError(f"table {path} has {data.shape[1]} columns of numbers but its header "
                         f"names {len(columns)}")
    out = {name: data[:, k] * factor for k, (name, factor) in enumerate(columns)}
    missing = [c for c in required if c not in out]
    if missing:
        raise InputError(f"table {path} lacks column(s) {', '.join(missing)} "
                         f"(it has {', '.join(out)})")
    return out
