"""Reader of Hysitron/Bruker TriboScan ``.hld`` files, the instrument's native record of one
indentation test.

An ``.hld`` file is Latin-1 text with CR LF line ends (the micro sign is byte 0xB5). It opens
with ``File Version: Hysitron ...`` and a header of ``Key: value unit`` lines (calibrations,
``Machine Comp`` in nm/µN, ``Tip C0`` ... ``Tip C5`` of the area function in nm^2/nm^p,
``Drift Rate`` in nm/s, ``Number of Segments`` and, per segment of the load function, its
``Segment Begin Time``/``End Time`` in s and ``Segment Begin Demand``/``End Demand`` in µN).
Three blocks of numbers follow, each introduced by a ``... Data Points: N`` line and a
tab-separated row of column names (``Time_s``, ``Disp_nm``, ``Force_µN``, ...):
``Sample Approach``, ``Drift Measurement`` and ``Test``. The curve is the Test block.

`read_hld` returns the curve in SI (m, N, s) with each point labelled by the load-function
segment whose time window holds it, and the header's frame compliance, area function,
drift rate and segment table, in SI, in its ``meta``. It does not correct the curve: frame
compliance and drift are the analysis's to remove (`LoadDisplacementCurve.frame_corrected`,
`LoadDisplacementCurve.drift_corrected`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError
from filmscale.core.files import excerpt, read_bytes, shown

from .curves import HOLD, LOAD, SEGMENTS_FROM_FILE, UNLOAD, LoadDisplacementCurve
from .tips import POLYNOMIAL_EXPONENTS
from .vendors import micro_sign as _micro
from .vendors import si_unit

FORMAT = "hysitron-hld"
MAGIC = "File Version: Hysitron"
TEST_BLOCK = "Test"
#: a point within this fraction of the median time step outside every segment window still
#: belongs to the nearest one (the instrument's clock and the segment table are rounded)
WINDOW_SLACK = 0.5
#: the segment table is not used when more than this fraction of the points fall outside
#: every window, or its point counts differ from the data's by more than this fraction
SEGMENT_MISMATCH = 0.1

_BLOCK = re.compile(r"^(.*?)\s*Data Points:\s*(\S*)\s*$")
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")


def _value(text: str):
    """(number, unit) when the text starts with a number, else the text itself."""
    fields = text.split(None, 1)
    if fields and _NUMBER.match(fields[0]):
        return float(fields[0]), fields[1].strip() if len(fields) > 1 else ""
    return text.strip()


def _header_lines(lines: list[str]) -> list[tuple[str, str]]:
    """(key, text after the colon) of each header line, in file order (the segment keys
    repeat); lines without a colon are passed over."""
    return [(key.strip(), rest.strip()) for key, colon, rest in
            (line.partition(":") for line in lines) if colon]


def parse_header(lines: list[str]) -> dict:
    """The header lines (before the first data block) as key -> (number, unit) or text;
    keys that repeat (the segment table) keep their last value."""
    return {key: _value(text) for key, text in _header_lines(lines)}


def _in_si(value, dims: dict[str, float]) -> float | None:
    """A parsed header value in SI when its unit has dimensions ``dims``; None when it is
    missing, text, or in units of another kind."""
    if not isinstance(value, tuple):
        return None
    unit = si_unit(value[1])
    if unit is None or unit[1] != dims:
        return None
    return value[0] * unit[0]


def _area_coefficients(header: dict) -> list[float] | None:
    """C0, C1, ... of A = sum C_k h^(2^(1-k)) in SI (m^(2 - p_k)); None when a coefficient is
    missing or its unit is not an area per length^p_k."""
    out = []
    for k, p in enumerate(POLYNOMIAL_EXPONENTS):
        value = header.get(f"Tip C{k}")
        if value is None:
            break
        if not isinstance(value, tuple):
            return None
        # nm^2/nm^p: the coefficient of h^p carries length^(2-p); no unit means nm
        unit = si_unit(value[1]) if value[1] else ((1e-9) ** (2.0 - p), {"L": 2.0 - p})
        if unit is None or not math.isclose(unit[1].get("L", 0.0), 2.0 - p, abs_tol=1e-12) \
                or set(unit[1]) - {"L"}:
            return None
        out.append(value[0] * unit[0])
    return out or None


def _segment_table(pairs: list[tuple[str, object]]) -> list[dict] | None:
    """The load function's segments in SI, or None when the table is missing or its rows do
    not line up (a key missing in one segment, a unit that is not s or µN)."""
    columns = {"Segment Begin Time": ("begin_time", {"T": 1.0}),
               "Segment End Time": ("end_time", {"T": 1.0}),
               "Segment Begin Demand": ("begin_demand", {"F": 1.0}),
               "Segment End Demand": ("end_demand", {"F": 1.0})}
    values = {name: [] for name, _ in columns.values()}
    points = []
    for key, value in pairs:
        if key in columns:
            name, dims = columns[key]
            values[name].append(_in_si(value, dims))
        elif key == "Segment Points":
            points.append(int(value[0]) if isinstance(value, tuple) and value[0] >= 0
                          and value[0] == int(value[0]) else None)
    n = len(values["begin_time"])
    if n == 0 or any(len(v) != n for v in values.values()) or \
            any(x is None or not math.isfinite(x) for v in values.values() for x in v):
        return None
    rows = [{name: values[name][k] for name in values} for k in range(n)]
    if len(points) == n and None not in points:
        for row, count in zip(rows, points):
            row["points"] = count
    return rows


def _labels(segments: list[dict] | None, t: np.ndarray | None) -> np.ndarray | None:
    """Each point's label from the segment whose time window holds it (the later segment
    where two windows overlap); None when the table does not fit the data."""
    if not segments or t is None or t.size < 2 or not np.all(np.isfinite(t)):
        return None
    begin = np.array([s["begin_time"] for s in segments])
    end = np.array([s["end_time"] for s in segments])
    if np.any(np.diff(begin) < 0) or np.any(end < begin):
        return None
    steps = np.diff(t)
    slack = WINDOW_SLACK * float(np.median(np.abs(steps))) if steps.size else 0.0
    index = np.searchsorted(begin, t, side="right") - 1
    early = index < 0
    index = np.clip(index, 0, begin.size - 1)
    inside = ~early & (t <= end[index] + slack)
    inside |= early & (t >= begin[0] - slack)
    if not inside.any() or (~inside).mean() > SEGMENT_MISMATCH:
        return None
    declared = [s.get("points") for s in segments]
    if None not in declared:
        total = sum(declared)
        if abs(total - t.size) > SEGMENT_MISMATCH * t.size:
            return None
        held = np.bincount(index, minlength=begin.size)
        # a segment whose window holds far more or fewer points than it declares: the table
        # belongs to another load function than the data
        if np.any(np.abs(held - np.array(declared)) > np.maximum(5, 0.5 * np.array(declared))):
            return None
    codes = np.empty(begin.size, dtype=np.int8)
    for k, s in enumerate(segments):
        rise = s["end_demand"] - s["begin_demand"]
        tiny = 1e-9 * max(abs(s["end_demand"]), abs(s["begin_demand"]))
        codes[k] = LOAD if rise > tiny else UNLOAD if rise < -tiny else HOLD
    return codes[index]


def _read_text(path: Path) -> str:
    """The file's text, line ends made \\n, after the checks that keep a pipe, a device or an
    oversized file from being read (`core.files.read_bytes`)."""
    data = read_bytes(path, "Hysitron .hld file")
    if not data.strip():
        raise InputError(f"{shown(path)} is empty: not a Hysitron .hld file")
    if b"\0" in data:
        raise InputError(f"{shown(path)} is not a Hysitron .hld file: it is binary (NUL bytes)")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = data.decode("latin-1")     # what TriboScan writes: µ is byte 0xB5
    # not str.splitlines: it also splits at Latin-1 0x85 and other controls inside a line
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _plain(name: str) -> str:
    """A block's name for a message: as it is when it is a few plain words (``Test``,
    ``Sample Approach``), else a bounded, escaped `excerpt`."""
    return name if re.fullmatch(r"[A-Za-z0-9 _-]{1,40}", name) else excerpt(name)


def _blocks(lines: list[str], path: Path) -> dict[str, tuple[int, int, int]]:
    """name -> (declared rows, first line of the column names, end line) of each data
    block; InputError for a block whose row count is not a whole number or whose rows fall
    short of it or exceed it."""
    starts = []
    for i, line in enumerate(lines):
        match = _BLOCK.match(line)
        if match:
            starts.append((i, match.group(1).strip(), match.group(2)))
    blocks = {}
    for j, (i, name, count) in enumerate(starts):
        if not count.isdigit():
            raise InputError(f"{shown(path)}: '{_plain(name)} Data Points' gives "
                             f"{excerpt(count, 20)}, not a number of rows")
        stop = starts[j + 1][0] if j + 1 < len(starts) else len(lines)
        held = sum(1 for line in lines[i + 2:stop] if line.strip())
        declared = int(count)
        if held != declared:
            cut = "is cut short" if held < declared else "holds more rows than it declares"
            raise InputError(f"{shown(path)}: the {_plain(name)} Data block {cut}: it holds "
                             f"{held} rows of the {declared} it declares")
        blocks[name] = (declared, i + 1, stop)
    return blocks


def _column_names(line: str) -> list[str]:
    return [c.strip() for c in line.split("\t")] if "\t" in line else line.split()


def _find(names: list[str], wanted: str) -> int | None:
    """Index of the column ``wanted`` (lower case, micro sign), however µ is written."""
    normal = [_micro(n).lower() for n in names]
    return normal.index(wanted) if wanted in normal else None


def _column_factor(name: str) -> float:
    """SI factor of a column that `_find` matched, from its unit suffix (``Disp_nm``: 1e-9)."""
    return si_unit(name.rpartition("_")[2])[0]


def _numbers(lines: list[str], columns: int, first: int, path: Path) -> np.ndarray:
    """The rows as a (rows, columns) float array; InputError naming the first bad row."""
    rows = [line for line in lines if line.strip()]
    try:
        flat = np.array(" ".join(rows).split(), dtype=float)
        if flat.size == len(rows) * columns:
            return flat.reshape(len(rows), columns)
    except (ValueError, OverflowError):
        pass
    # only on failure: find the row to name
    for k, line in enumerate(lines):
        fields = line.split()
        if not fields:
            continue
        ok = len(fields) == columns and all(_NUMBER.match(f) or f.lower() in ("nan", "inf", "-inf")
                                            for f in fields)
        if not ok:
            what = (f"holds {len(fields)} values for {columns} columns"
                    if len(fields) != columns else "is not numbers")
            raise InputError(f"{shown(path)} line {first + k + 1}: the Test Data row {what}: "
                             f"{excerpt(line.strip())}")
    raise InputError(f"{shown(path)}: the Test Data block is not a table of numbers")


def read_hld(path) -> dict[str, LoadDisplacementCurve]:
    """The test curve of a TriboScan ``.hld`` file, as ``{file stem: curve}``, in SI.

    h is ``Disp_nm``, P ``Force_µN`` and t ``Time_s`` of the Test Data block, found by their
    names. Each point is labelled load, hold or unload by the load-function segment whose
    time window holds it (rising, constant or falling demand); when the header's segment
    table is missing or does not fit the data, the curve finds its segments from the load
    rate instead. ``meta`` holds, in SI and as plain values: ``source``, ``format``,
    ``instrument`` (the File Version), ``time_stamp``, ``tip_name``, ``area_coefficients``
    (C0, C1, ... of A = C0 h^2 + C1 h + C2 h^(1/2) + ..., m^(2 - p_k), for `PolynomialArea`),
    ``frame_compliance`` (m/N), ``drift_rate`` (m/s), ``contact_threshold`` (N),
    ``maximum_demand`` (N), ``segments`` (begin/end time in s and demand in N, per segment),
    ``approach_points`` and ``drift_points`` (rows of those blocks), ``extra_columns``
    (the names of the Test Data columns other than time, depth and load) and, when the
    labels came from the segment table, ``segment_source`` = ``"file"``. A value the file
    does not give, or gives in units of another kind, is None. The curve is not corrected
    for frame compliance or drift: whether the header's Machine Comp is still in
    ``Disp_nm`` is for the analysis to judge from the unloading stiffness.

    Raises InputError, naming the file, for anything that is not a complete Hysitron test
    record: another file type, no Test Data block, a block cut short, a row that is not
    numbers, a missing depth or load column, a file over the input size limit or not a
    regular file.
    """
    path = Path(path)
    lines = _read_text(path).split("\n")
    if not lines[0].startswith(MAGIC):
        raise InputError(f"{shown(path)} is not a Hysitron .hld file: its first line lacks "
                         f"'{MAGIC}'")
    blocks = _blocks(lines, path)
    if TEST_BLOCK not in blocks:
        raise InputError(f"{shown(path)} holds no 'Test Data Points' block: no test curve")
    first_block = min(start for _, start, _ in blocks.values()) - 1
    texts = _header_lines(lines[:first_block])
    pairs = [(key, _value(text)) for key, text in texts]
    header, texts = dict(pairs), dict(texts)

    declared, names_line, stop = blocks[TEST_BLOCK]
    if declared < 2:
        raise InputError(f"{shown(path)}: the Test Data block holds {declared} rows; a curve "
                         "needs at least 2")
    names = _column_names(lines[names_line])
    i_h, i_P = _find(names, "disp_nm"), _find(names, "force_\u00b5n")
    i_t = _find(names, "time_s")
    if i_h is None or i_P is None:
        missing = " and ".join(n for n, i in (("Disp_nm", i_h), ("Force_µN", i_P)) if i is None)
        raise InputError(f"{shown(path)}: the Test Data block has no {missing} column "
                         f"(columns: {excerpt(', '.join(names))})")
    data = _numbers(lines[names_line + 1:stop], len(names), names_line + 1, path)
    h = data[:, i_h] * _column_factor(names[i_h])
    P = data[:, i_P] * _column_factor(names[i_P])
    t = data[:, i_t] * _column_factor(names[i_t]) if i_t is not None else None

    segments = _segment_table(pairs)
    labels = _labels(segments, t)
    meta = {
        "source": str(path),
        "format": FORMAT,
        "instrument": texts.get("File Version"),
        "time_stamp": texts.get("Time Stamp"),
        "tip_name": texts.get("Tip ID"),
        "area_coefficients": _area_coefficients(header),
        "frame_compliance": _in_si(header.get("Machine Comp"), {"L": 1.0, "F": -1.0}),
        "drift_rate": _in_si(header.get("Drift Rate"), {"L": 1.0, "T": -1.0}),
        "contact_threshold": _in_si(header.get("Contact Threshold"), {"F": 1.0}),
        "maximum_demand": _in_si(header.get("Maximum Demand"), {"F": 1.0}),
        "segments": segments,
        "approach_points": blocks.get("Sample Approach", (None,))[0],
        "drift_points": blocks.get("Drift Measurement", (None,))[0],
        "extra_columns": [n for k, n in enumerate(names) if k not in (i_h, i_P, i_t)],
    }
    if labels is not None:
        # labels the load function gave, to be kept as they are
        meta["segment_source"] = SEGMENTS_FROM_FILE
    try:
        curve = LoadDisplacementCurve(h, P, t, labels, meta=meta)
    except InputError as err:
        raise InputError(f"{shown(path)}: {err}") from None
    return {path.stem: curve}
