"""Readers (and group writers) for continuum's data: unit-aware tables and load-displacement curves.

Text tables: the first non-empty line is the header (a leading # is allowed): it names each
column and may give its unit in brackets or parentheses, ``h_c [nm], E_r [GPa], H [GPa]``,
``h [nm], P [uN], t [s]`` or ``E (GPa), dP/dh (N/m)`` (comma- or whitespace-separated; with
commas, names may contain spaces). Later lines starting with # are comments. A column without
a unit is taken as SI already. In comma-separated rows an empty field is NaN.

HDF5 curves (format ``filmscale.curve/1``): one group per curve with datasets ``h`` (m), ``P``
(N), optional ``t`` (s) and ``segment`` (0 load, 1 hold, 2 unload), an optional group
``channels`` (the CSM and instrument channels, SI, with ``units``), attributes ``indenter``
and ``meta`` (JSON). `write_curve_group` fills a group of a file the caller opened (files are
created atomically with `atomic_h5`); `read_curves` reads every curve of a file.

Files are written atomically with `filmscale.core.files.atomic_h5`.
"""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path

import h5py
import numpy as np

from filmscale.core.checks import check_path
from filmscale.core.errors import InputError
from filmscale.core.files import (check_regular_file, excerpt, input_limit, parse_json,
                                  read_text, read_toml, shown)

from .curves import CHANNELS, LoadDisplacementCurve
from .tips import POLYNOMIAL_EXPONENTS, PolynomialArea, berkovich, parse_tip

#: unit -> factor to SI (m, Pa, N, s)
UNITS = {
    "m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9, "A": 1e-10, "Å": 1e-10,
    "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9,
    "N": 1.0, "mN": 1e-3, "uN": 1e-6, "µN": 1e-6, "nN": 1e-9,
    "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9, "ps": 1e-12,
    "1": 1.0, "-": 1.0,
    "m^2": 1.0, "um^2": 1e-12, "µm^2": 1e-12, "nm^2": 1e-18,
    "N/m": 1.0, "mN/nm": 1e6, "uN/nm": 1e3, "µN/nm": 1e3, "mN/um": 1e3, "uN/um": 1.0,
    "nm/s": 1e-9,
}

_COLUMN = re.compile(r"\s*([^\[\],\s]+)\s*(?:\[([^\]]*)\]|(?<=\s)\(([^)]*)\))?\s*")
#: one field of a comma-separated header: a name (spaces allowed) and an optional unit
_FIELD = re.compile(r"\s*([^\[\],]*?)\s*(?:\[([^\]]*)\]|(?<=\s)\(([^)]*)\))?\s*")


def _unit_factor(name: str, unit: str | None) -> float:
    if unit is None:
        return 1.0
    if unit.strip() not in UNITS:
        raise InputError(f"unknown unit {excerpt(unit)} for column {excerpt(name)}; known: "
                         f"{', '.join(UNITS)}")
    return UNITS[unit.strip()]


def parse_header(line: str) -> list[tuple[str, float]]:
    """[(name, factor to SI)] from a header such as ``h [nm], P [uN], t [s]``.

    A unit is given in brackets or, after a space, in parentheses (``E (GPa)``). Columns are
    separated by commas or whitespace; in a header with commas, only commas separate, so a
    name may contain spaces (``Young modulus (GPa), dP/dh (N/m)``).
    """
    text = line.strip().lstrip("#").strip()
    if "," in text:
        return _parse_comma_header(text)
    return _parse_words(text)


def _parse_words(text: str) -> list[tuple[str, float]]:
    out, pos = [], 0
    while pos < len(text):
        match = _COLUMN.match(text, pos)
        if not match or match.end() == pos:
            raise InputError(f"cannot read the column header near {excerpt(text[pos:pos + 20])}")
        name, unit = match.group(1), match.group(2) or match.group(3)
        out.append((name, _unit_factor(name, unit)))
        pos = match.end()
    return out


def _parse_comma_header(text: str) -> list[tuple[str, float]]:
    fields = text.split(",")
    if not fields[-1].strip():         # a trailing comma closes the header
        fields.pop()
    out = []
    for field in fields:
        if not field.strip():
            raise InputError(f"cannot read the column header near {excerpt(text[:20])}: an "
                             "empty column name")
        match = _FIELD.fullmatch(field)
        if match and match.group(1):
            name, unit = match.group(1), match.group(2) or match.group(3)
            out.append((name, _unit_factor(name, unit)))
        else:       # several bracketed columns between two commas: h [nm] P [uN], t [s]
            out += _parse_words(field.strip())
    return out


def _read_comma_rows(body: str, width: int) -> np.ndarray | None:
    """Rows of comma-separated numbers, an empty field read as NaN; None unless every row has
    ``width`` fields of numbers."""
    rows = []
    for line in body.splitlines():
        line = line.split("#", 1)[0]
        if not line.strip():
            continue
        fields = line.split(",")
        if len(fields) != width:
            return None
        try:
            rows.append([float(f) if f.strip() else math.nan for f in fields])
        except ValueError:
            return None
    return np.array(rows, dtype=float).reshape(-1, width)


_LOADTXT = re.compile(r"could not convert string (.*) to \w+ at row (\d+), column (\d+)",
                      re.DOTALL)


def _loadtxt_reason(err: ValueError) -> str:
    """numpy's reason a table body is not numbers, its quote of the field bounded and
    escaped (`excerpt`): numpy quotes the whole field, which may be a whole line."""
    match = _LOADTXT.match(str(err))
    if match:
        field = match.group(1)[1:-1] if match.group(1)[:1] in "'\"" else match.group(1)
        return (f"row {int(match.group(2)) + 1} of the numbers, column {match.group(3)}: "
                f"{excerpt(field)} is not a number")        # numpy counts rows from 0
    reason = ascii(str(err).splitlines()[0] if str(err) else type(err).__name__)[1:-1]
    return reason if len(reason) <= 100 else f"{reason[:97]}..."


def read_table(path, required: tuple[str, ...] = ()) -> dict[str, np.ndarray]:
    """Columns of a text table in SI, by header name. Raises InputError naming the file."""
    path = check_path("path", path)
    text = read_text(path, "table")
    header, _, body = text.lstrip().partition("\n")
    if not header or not re.search(r"[A-Za-z_]", header):
        raise InputError(f"table {shown(path)} has no header line naming its columns")
    try:
        columns = parse_header(header)
    except InputError as err:
        raise InputError(f"table {shown(path)}: {err}") from None
    if not re.search(r"^\s*[-+.0-9]", body, flags=re.MULTILINE):
        raise InputError(f"table {path} has a header but no rows of numbers")
    data, error = None, None
    try:
        # one replace over the whole text: thousands of files are read in a batch
        data = np.loadtxt(io.StringIO(body.replace(",", " ")), comments="#", ndmin=2)
    except ValueError as err:
        error = f"table {shown(path)}: {_loadtxt_reason(err)}"
    if error is None and data.shape[1] != len(columns):
        error = (f"table {path} has {data.shape[1]} columns of numbers but its header names "
                 f"{len(columns)}")
    if error is not None and "," in header:
        # comma-separated with empty fields (NaN), which the fast path above cannot place
        data = _read_comma_rows(body, len(columns))
        error = None if data is not None else error
    if error is not None:
        raise InputError(error)
    out = {name: data[:, k] * factor for k, (name, factor) in enumerate(columns)}
    missing = [c for c in required if c not in out]
    if missing:
        raise InputError(f"table {shown(path)} lacks column(s) {', '.join(missing)} "
                         f"(it has {excerpt(', '.join(out))})")
    return out


CURVE_FORMAT = "filmscale.curve/1"
#: suffixes of curve files a folder is searched for (text, instrument workbooks and exports)
CURVE_SUFFIXES = (".csv", ".txt", ".dat", ".tsv", ".hld", ".xlsx", ".xlsm", ".xls")
HDF5_SUFFIXES = (".h5", ".hdf5")
#: accepted header names of each curve column (case-insensitive)
CURVE_COLUMNS = {
    "h": ("h", "depth", "displacement", "disp"),
    "P": ("p", "load", "force", "f"),
    "t": ("t", "time"),
}


def _curve_column(columns: dict, key: str, path) -> np.ndarray | None:
    lower = {name.lower(): name for name in columns}
    for alias in CURVE_COLUMNS[key]:
        if alias in lower:
            return columns[lower[alias]]
    if key == "t":
        return None
    raise InputError(f"curve file {shown(path)} has no {key} column (header names accepted: "
                     f"{', '.join(CURVE_COLUMNS[key])}; it has {excerpt(', '.join(columns))})")


def read_curve_text(path, indenter: str = "") -> LoadDisplacementCurve:
    """A curve from a text table with a header such as ``h [nm], P [uN], t [s]``."""
    columns = read_table(path)
    h, P, t = (_curve_column(columns, key, path) for key in ("h", "P", "t"))
    return LoadDisplacementCurve(h, P, t, indenter=indenter, meta={"source": str(path)})


def write_curve_group(group, curve: LoadDisplacementCurve) -> None:
    """Store a curve in an open h5py group: datasets in SI with unit attributes."""
    group.attrs["format"] = CURVE_FORMAT
    for name, values, unit in (("h", curve.h, "m"), ("P", curve.P, "N"), ("t", curve.t, "s")):
        if values is not None:
            group.create_dataset(name, data=values).attrs["units"] = unit
    group.create_dataset("segment", data=curve.segment).attrs["labels"] = "0 load, 1 hold, 2 unload"
    if curve.channels:
        channels = group.create_group("channels")
        for name, values in curve.channels.items():
            channels.create_dataset(name, data=values).attrs["units"] = CHANNELS[name]
    group.attrs["indenter"] = _tip_text(curve.indenter)
    if isinstance(curve.indenter, PolynomialArea):     # a calibrated tip: its polynomial too
        group.attrs["indenter_area"] = json.dumps(
            {"coefficients": list(curve.indenter.coefficients),
             "h_range": list(curve.indenter.h_range) if curve.indenter.h_range else None})
    group.attrs["meta"] = json.dumps(dict(curve.meta), default=str)


def _tip_text(tip) -> str:
    """The text `parse_tip` reads back: a polynomial area function's nominal tip."""
    if tip is None:
        return ""
    return tip.base.spec if isinstance(tip, PolynomialArea) else tip.spec


#: bytes of one curve row: its h and P as float64s
CURVE_ROW_BYTES = 16


def curve_rows_limit() -> int:
    """The most rows (points) a curve read from a file may hold: the input limit
    (`filmscale.core.files.input_limit`, 16 MiB unless FILMSCALE_MAX_INPUT_BYTES sets
    another) over `CURVE_ROW_BYTES`, so 1,048,576 rows by default: ten times the longest
    instrument records (10^5 points, 5 MB of text), a text table of typical 30-50-byte rows
    within the input limit holds under 600,000, and a curve of 10^6 points takes under 1 s to
    analyse. Raising the input limit raises this one."""
    return input_limit() // CURVE_ROW_BYTES


def check_curve_rows(n_rows: int, what: str) -> int:
    """``n_rows`` when it is at most `curve_rows_limit`, else InputError naming ``what``."""
    limit = curve_rows_limit()
    if n_rows > limit:
        raise InputError(f"{what} has {n_rows} rows, more than the limit of {limit} (the "
                         f"input size limit over {CURVE_ROW_BYTES} bytes a row; set "
                         "FILMSCALE_MAX_INPUT_BYTES to read a longer curve)")
    return n_rows


def _dataset(group, name: str, required: bool = True):
    """A dataset of a curve group as an array; InputError naming the group when it is
    missing, larger than the input limit (a hostile file may declare terabytes) or longer
    than `curve_rows_limit` rows, checked before it is read."""
    if name not in group:
        if required:
            raise InputError(f"curve group {group.name} has no dataset {name!r}")
        return None
    data = group[name]
    if not isinstance(data, h5py.Dataset) or data.nbytes > input_limit():
        raise InputError(f"curve group {group.name}: {name!r} is not a dataset of at most "
                         f"{input_limit()} bytes")
    check_curve_rows(data.size, f"curve group {group.name}: dataset {name!r}")
    return data[()]


def read_curve_group(group) -> LoadDisplacementCurve:
    """The curve stored by `write_curve_group`."""
    meta = group.attrs.get("meta", "{}")
    if isinstance(meta, str):
        meta = parse_json(meta, "the meta attribute of curve group", group.name)
    if not isinstance(meta, dict):
        raise InputError(f"curve group {group.name}: its meta attribute is not a JSON object")
    indenter = str(group.attrs.get("indenter", ""))
    if "indenter_area" in group.attrs:
        area = parse_json(group.attrs["indenter_area"], "the indenter_area attribute of group",
                          group.name)
        if not isinstance(area, dict) or not isinstance(area.get("coefficients"), list):
            raise InputError(f"curve group {group.name}: indenter_area holds no coefficients")
        try:
            indenter = PolynomialArea(tuple(area["coefficients"]),
                                      parse_tip(indenter or "berkovich"),
                                      tuple(area["h_range"]) if area.get("h_range") else None)
        except (TypeError, ValueError):
            raise InputError(f"curve group {group.name}: indenter_area is not an area "
                             "function") from None
    channels = {}
    if isinstance(group.get("channels"), h5py.Group):
        for name in group["channels"]:      # named before any is read: a file may hold many
            if name not in CHANNELS:
                raise InputError(f"curve group {group.name}: unknown channel {excerpt(name)} "
                                 f"(known: {', '.join(CHANNELS)})")
        channels = {name: _dataset(group["channels"], name) for name in group["channels"]}
    return LoadDisplacementCurve(_dataset(group, "h"), _dataset(group, "P"),
                                 _dataset(group, "t", False), _dataset(group, "segment", False),
                                 indenter=indenter, meta=meta, channels=channels)


def read_curves(path, options=None) -> dict[str, LoadDisplacementCurve]:
    """Curves of a file by name: every curve group of an HDF5 file, every test sheet of an
    instrument workbook, or the one curve of a text table (named by the file's stem).

    ``options`` (`vendors.ReadOptions`) names an instrument format or a column mapping. In
    the default ``auto`` format a text file is read as the package's own table first and, when
    that fails, as an instrument export (`vendors.read_instrument`); when both fail, the
    InputError gives both reasons. ``path`` must be a str or an os.PathLike; a curve may hold
    at most `curve_rows_limit` rows.
    """
    path = check_path("path", path)
    curves = _read_curves(path, options)
    for name, curve in curves.items():
        check_curve_rows(len(curve.h), f"curve {name!r} of {shown(path)}")
    return curves


def _read_curves(path: Path, options) -> dict[str, LoadDisplacementCurve]:
    suffix = path.suffix.lower()
    if options is None:
        from .vendors import ReadOptions
        options = ReadOptions()
    fmt = options.format
    if suffix not in HDF5_SUFFIXES:
        from . import vendors
        if fmt == "filmscale":
            return {path.stem: read_curve_text(path)}
        if fmt != "auto" or options.columns or suffix in vendors.EXCEL_SUFFIXES + (".xls",):
            return vendors.read_instrument(path, options)
        try:
            return {path.stem: read_curve_text(path)}
        except InputError as native:
            if not path.is_file() or path.stat().st_size > input_limit():
                raise
            try:
                return vendors.read_instrument(path, options)
            except InputError as err:
                raise InputError(f"{native}; read as an instrument export: {err}") from None

    check_regular_file(path, "HDF5 file")  # h5py would block on a pipe, misread a device
    out = {}
    try:
        with h5py.File(path, "r") as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Group) and obj.attrs.get("format") == CURVE_FORMAT:
                    out[name] = read_curve_group(obj)
            if f.attrs.get("format") == CURVE_FORMAT:
                out[path.stem] = read_curve_group(f)
            f.visititems(visit)
    except OSError as err:
        raise InputError(f"cannot read HDF5 file {path}: {err}") from None
    if not out:
        raise InputError(f"HDF5 file {path} holds no curve (no group with format "
                         f"{CURVE_FORMAT!r})")
    return out


def read_area_function(path, base=None):
    """A polynomial area function from a TOML file.

    ``C = [C0, C1, ...]`` are the coefficients of A = C0 h^2 + C1 h + C2 h^(1/2) + ... and
    ``length_unit`` (m, um or nm; default m) the unit of h in which they were fitted, A being
    in its square, as instrument software reports them; ``h_c_range = [low, high]`` (same
    unit, optional) the contact depths they were calibrated on. ``base`` is the nominal tip
    (Berkovich when None).
    """
    path = check_path("path", path)
    data = read_toml(path, "area file")
    coef = data.get("C")
    if not isinstance(coef, list) or not 1 <= len(coef) <= 9 or not all(
            isinstance(c, (int, float)) and not isinstance(c, bool) for c in coef):
        raise InputError(f"area file {path}: C must be a list of 1 to 9 numbers "
                         f"(C0, C1, ... of A = C0 h^2 + C1 h + C2 h^(1/2) + ...)")
    unit = data.get("length_unit", "m")
    if unit not in ("m", "um", "µm", "nm"):
        raise InputError(f"area file {shown(path)}: length_unit = {excerpt(unit)} is not one "
                         "of m, um, nm")
    u = UNITS[unit]
    si = tuple(float(c) * u**(2.0 - p) for c, p in zip(coef, POLYNOMIAL_EXPONENTS))
    h_range = data.get("h_c_range")
    if h_range is not None:
        if not (isinstance(h_range, list) and len(h_range) == 2 and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in h_range)
                and 0 <= h_range[0] < h_range[1]):
            raise InputError(f"area file {path}: h_c_range must be [low, high] contact depths "
                             f"in {unit}, 0 <= low < high")
        h_range = (h_range[0] * u, h_range[1] * u)
    return PolynomialArea(si, berkovich() if base is None else base, h_range)


def read_frame_compliance(path) -> float | None:
    """The ``frame_compliance`` (m/N) an area file holds (`indent calibrate` writes it), or
    None when it holds none."""
    path = check_path("path", path)
    data = read_toml(path, "area file")
    if "frame_compliance" not in data:
        return None
    value = data["frame_compliance"]
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not 0.0 <= value <= 1.0:
        raise InputError(f"area file {shown(path)}: frame_compliance = {excerpt(value)} must "
                         "be a number of m/N in [0, 1]")
    return float(value)
