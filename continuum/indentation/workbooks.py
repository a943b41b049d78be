"""KLA/Agilent G200, G200X, iMicro and Nano Indenter XP workbooks (NanoSuite "Export to
Excel"), ``.xls`` (Excel 97-2003) and ``.xlsx``, read with python-calamine.

A NanoSuite workbook holds one sheet per test (``Test 001``, ...: a header row, a row of
units, then one row per point) and summary sheets: ``Results`` (the instrument's own per-test
E and H, averaged over the method's depth range, its drift correction, the tip's name and area
coefficients; one row per cycle ``1-1``, ``1-2`` in multi-cycle methods), ``Required Inputs``
and ``Inputs Editable Post Test`` (Poisson's ratio, frame-stiffness corrections, the depth
range of the averages, ...). What is read from each (docs/indentation.md, "Instrument files"):

- depth, load and time by the same header names and units as any export (`vendors.ALIASES`);
- the channels of a continuous-stiffness (CSM) test (`curves.CHANNELS`): ``Harmonic Contact
  Stiffness``, ``Harmonic Stiffness``, ``Harmonic Frame Stiffness``, ``Harmonic Displacement``,
  ``Harmonic Load`` and the instrument's ``Hardness`` and ``Modulus``, converted from the units
  the sheet gives. A channel in a unit not known here is left out and named once in
  ``meta["dropped_channels"]``, never a reason to refuse the file;
- the ``Segment`` column's markers label the points (``Load Segment Type``, ``Hold Segment
  Type``, ``Unload From Peak Segment Type``, ``Thermal Drift Hold Segment``, ``Cycle Begin
  Marker N``, ``Cycle Unload Marker N``, ...); ``Surface Marker`` gives the file's contact
  point; rows after ``END`` are not data;
- the instrument's marker for an invalid value (DBL_MAX, 1.797e308) becomes NaN;
- the summary sheets' values for each test go into the curve's ``meta["vendor"]`` in SI.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError
from filmscale.core.files import shown

from .curves import CHANNELS, HOLD, LOAD, SEGMENTS_FROM_FILE, UNLOAD, LoadDisplacementCurve
from .tips import POLYNOMIAL_EXPONENTS
from .vendors import (ALIASES, SEGMENT_NAMES, ReadOptions, _check_size, _is_unit_row,
                      _pick_columns, _unit, si_unit, split_name)

WORKBOOK_SUFFIXES = (".xls", ".xlsx", ".xlsm")
#: values at or above this are the instrument's invalid-value marker (DBL_MAX)
INVALID = 1e307
#: sheets that summarise the tests rather than hold one
SUMMARY_SHEETS = ("results", "required inputs", "pre-test inputs", "inputs editable post test",
                  "post-test inputs", "calculations", "statistics", "summary")
#: header name (lower case, no unit) -> channel of `curves.CHANNELS`
CHANNEL_NAMES = {
    "harmonic contact stiffness": "S",
    "harmonic stiffness": "S_total",
    "harmonic frame stiffness": "K_frame",
    "harmonic displacement": "h_harmonic",
    "harmonic load": "P_harmonic",
    "hardness": "H_vendor",
    "modulus": "E_vendor",
}
#: dimensions of each SI unit a channel or summary value is read in (`vendors.si_unit`)
SI_DIMENSIONS = {"N/m": {"F": 1.0, "L": -1.0}, "m": {"L": 1.0}, "N": {"F": 1.0},
                 "Pa": {"F": 1.0, "L": -2.0}, "m/s": {"L": 1.0, "T": -1.0}, "s": {"T": 1.0}}
#: units of channels knowingly passed over (dimensionless, frequencies, fractions)
PASSED_UNITS = {None, "", "Hz", "1/s", "%"}


def _readable(unit: str) -> bool:
    """True for a unit of a kind the reader reads (a length, force, stress, stiffness, time
    or rate): a channel in it is passed over knowingly, not dropped as unknown."""
    got = si_unit(unit)
    return got is not None and got[1] in SI_DIMENSIONS.values()


def _factor(si: str, unit: str | None) -> float | None:
    """The factor that takes ``unit`` to the SI unit ``si``; None when it is of another kind
    or not known."""
    got = si_unit(unit) if unit else None
    return got[0] if got is not None and got[1] == SI_DIMENSIONS[si] else None


def _number(value) -> float:
    """A cell as a float: NaN for text, blanks and the invalid-value marker."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return math.nan
    value = float(value)
    return math.nan if abs(value) >= INVALID else value


def _column(rows, k: int) -> np.ndarray:
    return np.array([_number(r[k]) if k < len(r) else math.nan for r in rows], dtype=float)


def _label(cell) -> str:
    return split_name(cell)[0].strip().lower() if isinstance(cell, str) else ""


# ---- sheets -----------------------------------------------------------------------------

def _open(path: Path):
    _check_size(path)
    if not path.is_file():
        raise InputError(f"cannot read {shown(path)}: not a regular file")
    from python_calamine import CalamineWorkbook
    try:
        return CalamineWorkbook.from_path(str(path))
    except Exception as err:  # calamine raises its own errors on files that are not workbooks
        reason = str(err).splitlines()[0][:200] if str(err) else type(err).__name__
        raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or .xlsx): "
                         f"{reason}") from None


def _rows(book, name: str, path: Path) -> list[list]:
    try:
        return book.get_sheet_by_name(name).to_python(skip_empty_area=False)
    except Exception as err:
        raise InputError(f"cannot read sheet {name!r} of {shown(path)}: "
                         f"{str(err).splitlines()[0][:200] if str(err) else type(err).__name__}"
                         ) from None


def _test_number(text) -> int | None:
    match = re.search(r"(\d+)\s*$", str(text))
    return int(match.group(1)) if match else None


def read_workbook(path, options: ReadOptions | None = None) -> dict[str, LoadDisplacementCurve]:
    """Curves of a NanoSuite workbook, one per test sheet, by sheet name; each curve's meta
    carries what the summary sheets say of its test (`summary_meta`)."""
    options = options or ReadOptions()
    path = Path(path)
    book = _open(path)
    names = list(book.sheet_names)
    summaries = [n for n in names if n.strip().lower() in SUMMARY_SHEETS]
    vendor = summary_meta({n: _rows(book, n, path) for n in summaries})
    out, reasons = {}, []
    for name in names:
        if name in summaries:
            continue
        rows = _rows(book, name, path)
        if not rows:
            continue
        number = _test_number(name)
        meta = {"source": str(path), "sheet": name, "format": "g200-workbook",
                "vendor": vendor.get(number, {}) if number is not None else {}}
        try:
            out[name] = sheet_curve(rows, options, f"{path} sheet {name!r}", meta)
        except InputError as err:
            reasons.append(str(err))
    if not out:
        why = "; ".join(reasons[:3]) + (f"; and {len(reasons) - 3} more" if len(reasons) > 3
                                        else "")
        raise InputError(f"workbook {shown(path)} holds no test sheet with depth and load "
                         f"columns ({why or 'its sheets ' + ', '.join(map(repr, names))})")
    return out


def _markers(cells):
    """(per-row segment codes or None, surface row or None, end row or None) from the
    Segment column: text at the first row of each segment."""
    codes = np.full(len(cells), -1, dtype=np.int8)
    current, labelled, surface, end = None, False, None, None
    for k, cell in enumerate(cells):
        text = str(cell).strip().lower() if cell not in (None, "") else ""
        if not text or text == "nan":
            pass
        elif text == "end":
            end = k
            break
        elif "surface" in text:
            surface = k
        elif "drift" in text or "hold" in text:
            current, labelled = HOLD, True
        elif "unload" in text:
            current, labelled = UNLOAD, True
        elif "load" in text or "cycle begin" in text:
            current, labelled = LOAD, True
        if current is not None:
            codes[k] = current
    stop = len(cells) if end is None else end
    codes = codes[:stop]
    if not labelled:
        return None, surface, end
    codes[codes < 0] = LOAD          # rows before the first marker: the approach, loading
    return codes, surface, end


def sheet_curve(rows, options: ReadOptions, source, meta) -> LoadDisplacementCurve:
    """The curve of one test sheet given as rows of cells (header, units row, data)."""
    wanted = [split_name(key)[0].strip().lower() for _, key, _ in options.columns
              if isinstance(key, str)]
    header = None
    for k in range(min(len(rows), 30)):
        labels = [_label(c) for c in rows[k]]
        if (all(w in labels for w in wanted) if wanted else
                any(a in labels for a in ALIASES["h"]) and any(a in labels for a in ALIASES["P"])):
            header = k
            break
    if header is None:
        raise InputError(f"{source}: no header row naming depth and load")
    names = [c if isinstance(c, str) else "" for c in rows[header]]
    first = header + 1
    units = [None] * len(names)
    if first < len(rows) and _is_unit_row(rows[first]):
        units = [_unit(c) if isinstance(c, str) and c.strip() else None for c in rows[first]]
        units += [None] * (len(names) - len(units))
        first += 1
    picked = _pick_columns(names, units, options, source)
    body = rows[first:]
    labels = [_label(n) for n in names]
    units = [u if u is not None else split_name(n)[1] for u, n in zip(units, names)]
    segment, meta = None, dict(meta)
    for k, label in enumerate(labels):
        if label in SEGMENT_NAMES:
            segment, surface, end = _markers([r[k] if k < len(r) else None for r in body])
            if end is not None:
                body = body[:end]
            if surface is not None:
                meta["surface_row"] = surface
            break
    data = {role: _column(body, k) * factor for role, (k, factor) in picked.items()}
    channels, dropped = {}, []
    used = {k for k, _ in picked.values()}
    for k, label in enumerate(labels):
        if k in used or not label or label in SEGMENT_NAMES:
            continue
        channel = CHANNEL_NAMES.get(label)
        factor = _factor(CHANNELS[channel], units[k]) if channel else None
        if channel and factor is not None and channel not in channels:
            values = _column(body, k) * factor
            if np.isfinite(values).any():      # a channel the export left blank is none
                channels[channel] = values
        elif channel or not (units[k] in PASSED_UNITS or _readable(units[k])):
            dropped.append(f"{names[k]} [{units[k] or 'no unit'}]")
    keep = np.isfinite(data["h"]) & np.isfinite(data["P"])
    if keep.sum() < 2:
        raise InputError(f"{source}: fewer than 2 rows of numbers under the header")
    if segment is not None:
        segment = np.concatenate([segment, np.full(len(body) - segment.size, segment[-1])])
        segment = _hold_tails(segment[keep], data["P"][keep])
        meta["segment_source"] = SEGMENTS_FROM_FILE
    if "surface_row" in meta:       # the file's contact point, as an index of the kept points
        meta["surface_index"] = int(np.count_nonzero(keep[:meta.pop("surface_row")]))
    if dropped:
        meta["dropped_channels"] = dropped
    return LoadDisplacementCurve(data["h"][keep], data["P"][keep],
                                 data["t"][keep] if "t" in data else None, segment, meta=meta,
                                 channels={k: v[keep] for k, v in channels.items()})


#: a marked hold ends where its load leaves the hold's median by this fraction of it
HOLD_LOAD_TOLERANCE = 0.01


def _hold_tails(codes: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Marked holds cut where the load leaves them: NanoSuite marks the start of its thermal
    drift hold but not the final unloading after it, which the marker run then holds."""
    from .curves import _runs
    codes = codes.copy()
    for label, start, stop in _runs(codes):
        if label != HOLD or stop - start < 3:
            continue
        level = float(np.median(P[start:stop]))
        away = np.abs(P[start:stop] - level) > HOLD_LOAD_TOLERANCE * abs(level)
        steady = np.flatnonzero(~away)
        if steady.size and steady[-1] + 1 < stop - start:
            tail = slice(start + steady[-1] + 1, stop)
            codes[tail] = np.where(P[tail] < level, UNLOAD, LOAD)
    return codes


# ---- summary sheets ---------------------------------------------------------------------

#: summary columns (lower-case name without unit) -> key in meta["vendor"] and its SI unit
SUMMARY_KEYS = {
    "poissons ratio": ("nu", None), "poisson's ratio": ("nu", None),
    "poisson ratio": ("nu", None),
    "frame stiffness correction": ("frame_stiffness_correction", "N/m"),
    "harmonic frame stiffness correction": ("harmonic_frame_stiffness_correction", "N/m"),
    "frame stiffness": ("frame_stiffness", "N/m"),
    "minimum calculation depth": ("depth_min", "m"), "minimum depth for average": ("depth_min", "m"),
    "maximum calculation depth": ("depth_max", "m"), "maximum depth for average": ("depth_max", "m"),
    "perform drift correction": ("drift_correction", None),
    "drift correction": ("drift_rate", "m/s"), "drift": ("drift_rate", "m/s"),
    "percent unload in stiffness calculation": ("unload_percent", None),
    "tip name": ("tip_name", None),
}
_AREA = re.compile(r"^area coefficient\s*(\d+)$")
_DEPTHS = re.compile(r"\[\s*([\d.]+)\s*-\s*([\d.]+)\s*(nm|um|µm)\s*\]")


def _summary_key(name: str):
    """(key, SI unit) of a summary column: E and H averages, per-cycle values, inputs."""
    label, _ = split_name(name)
    label = label.strip().lower()
    if label in SUMMARY_KEYS:
        return SUMMARY_KEYS[label]
    words = re.findall(r"[a-z]+", label)
    averaged = "avg" in words or "average" in words or "mean" in words
    if "modulus" in words or (words[:1] == ["e"] and not averaged) or (averaged and "e" in words):
        return ("E" if averaged or "modulus" in words else "E_cycle"), "Pa"
    if "hardness" in words or (words[:1] == ["h"] and not averaged) or (averaged and "h" in words):
        return ("H" if averaged or "hardness" in words else "H_cycle"), "Pa"
    cycle = {"displacement": ("h_cycle", "m"), "load": ("P_cycle", "N"),
             "stiffness": ("S_cycle", "N/m")}
    return cycle.get(label, (None, None))


def summary_meta(sheets: dict[str, list[list]]) -> dict[int, dict]:
    """{test number: what the summary sheets say of that test, in SI}: ``E``, ``H`` (the
    instrument's averages, Pa), ``depth_range`` (m) of those averages, ``nu``, frame-stiffness
    corrections (N/m), ``drift_rate`` (m/s), ``tip_name``, ``area_coefficients`` (SI, for
    `tips.PolynomialArea`) and, in multi-cycle methods, ``cycles``: per cycle E, H (Pa), h (m),
    P (N) and S (N/m)."""
    out: dict[int, dict] = {}
    for sheet, rows in sheets.items():
        if len(rows) < 2:
            continue
        names = [c if isinstance(c, str) else "" for c in rows[0]]
        first = 1
        units = [None] * len(names)
        if _is_unit_row(rows[1]) or not any(isinstance(c, (int, float)) for c in rows[1]):
            units = [_unit(c) if isinstance(c, str) and c.strip() else None for c in rows[1]]
            first = 2
        units += [None] * (len(names) - len(units))
        for row in rows[first:]:
            key = str(row[0]).strip() if row else ""
            if key.endswith(".0"):
                key = key[:-2]
            cycle = re.fullmatch(r"(\d+)-(\d+)", key)
            if not (key.isdigit() or cycle):
                continue
            test = out.setdefault(int(cycle.group(1) if cycle else key), {})
            target = test.setdefault("cycles", {}).setdefault(int(cycle.group(2)), {}) \
                if cycle else test
            for k in range(1, min(len(names), len(row))):
                _summary_value(target, test, names[k], units[k] or split_name(names[k])[1],
                               row[k])
    for test in out.values():
        if "cycles" in test:
            test["cycles"] = [{k.removesuffix("_cycle"): v for k, v in c.items()}
                              for _, c in sorted(test["cycles"].items())]
        if "depth_min" in test and "depth_max" in test:
            test["depth_range"] = [test.pop("depth_min"), test.pop("depth_max")]
        coefficients = test.pop("area", None)
        if coefficients:
            n = max(coefficients) + 1
            test["area_coefficients"] = [coefficients.get(j, 0.0) * 1e-9**(2.0 - p)
                                         for j, p in zip(range(n), POLYNOMIAL_EXPONENTS)]
    return out


def _summary_value(target: dict, test: dict, name: str, unit, cell) -> None:
    label = split_name(name)[0].strip().lower()
    area = _AREA.match(label)
    if area:
        if isinstance(cell, (int, float)) and not isinstance(cell, bool):
            test.setdefault("area", {})[int(area.group(1)) - 1] = float(cell)
        return
    key, si = _summary_key(name)
    if key is None:
        return
    if si is None:
        if isinstance(cell, str) and cell.strip():
            target[key] = cell.strip()
        elif not math.isnan(_number(cell)):
            target[key] = _number(cell)
        return
    value, factor = _number(cell), _factor(si, unit)
    if math.isnan(value) or factor is None:
        return
    target[key] = value * factor
    depths = _DEPTHS.search(name)
    if key in ("E", "H") and depths and "depth_min" not in test:
        scale = 1e-9 if depths.group(3) == "nm" else 1e-6
        test["depth_min"] = float(depths.group(1)) * scale
        test["depth_max"] = float(depths.group(2)) * scale
