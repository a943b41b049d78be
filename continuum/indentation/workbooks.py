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

Before calamine parses a workbook, its bounds are checked (docs/security.md, "Physical
plausibility and bounded readers"): a regular file within the input size limit, read once into memory, and for an
.xlsx the uncompressed size of its members and the rows and cells its references span
(`ARCHIVE_FACTOR`, `MAX_SHEET_ROWS`, `MAX_SHEET_CELLS`).
"""

from __future__ import annotations

import io
import math
import re
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError
from filmscale.core.files import MAX_INPUT_BYTES_ENV, excerpt, input_limit, read_bytes, shown

from .curves import CHANNELS, HOLD, LOAD, SEGMENTS_FROM_FILE, UNLOAD, LoadDisplacementCurve
from .tips import POLYNOMIAL_EXPONENTS
from .vendors import (ALIASES, SEGMENT_NAMES, ReadOptions, clean_unit, is_unit_row, pick_columns,
                      si_unit, split_name)

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


# ---- bounds: what a workbook may hold before it is parsed ---------------------------------

#: the most bytes the members of an ``.xlsx`` (a zip archive) may hold uncompressed, in
#: input size limits (`core.files.input_limit`): 16 x 16 MiB = 256 MiB by default. The
#: largest real exports (tests/data/instruments: FS_Calibration.xls, FQ.xls, 2.4-2.6 MB,
#: 120 000-140 000 cells) hold about 6 MB of sheet XML written as .xlsx (about 10:1
#: compressed), so the bound is 40 times the largest; a zip bomb (1.8 MB holding 550 MB of
#: sheet XML) is refused from the archive's directory, before anything is inflated
ARCHIVE_FACTOR = 16
#: the most members of an ``.xlsx``: a workbook holds a few per sheet (real ones: 20-30)
MAX_MEMBERS = 10_000
#: the most rows of one sheet: real sheets hold at most a few thousand (FQ.xls: 2984);
#: Excel itself stops at 1 048 576
MAX_SHEET_ROWS = 1_000_000
#: the most cells of one sheet's rectangle, rows x columns: calamine allocates every cell
#: of the rectangle from the first to the last cell given (32 bytes each: 320 MB at the
#: bound), so two cells far apart (A1 and XFD1048576: 1.7e10 cells) would abort the
#: process; real sheets hold at most 10^5 (FS_Calibration.xls: 136 000 in 20 sheets)
MAX_SHEET_CELLS = 10_000_000
#: bytes of a member inflated at a time while its cell references are scanned
_CHUNK = 1 << 22
#: a cell or row reference: r="AB12" (cell) or r="12" (row), in either quote, blanks
#: allowed around = as XML allows (text that looks like one counts too: an over-estimate)
_REF_LETTERS = re.compile(rb"""\sr\s*=\s*["']([A-Za-z]+)""")
_REF_DIGITS = re.compile(rb"""\sr\s*=\s*["'][A-Za-z]*([0-9]+)""")
#: start tags of cells and rows, with or without a namespace prefix (``x:c``), and those
#: that begin with their reference (as Excel, LibreOffice, openpyxl and XlsxWriter write)
_CELL_TAGS = (b"<c ", b"<c>", b"<c/", b":c ", b":c/")
_REFERENCED_CELLS = (b'<c r="', b"<c r='", b':c r="', b":c r='")
_ROW_TAGS = (b"<row ", b"<row>", b"<row/", b":row ", b":row/")
_REFERENCED_ROWS = (b'<row r="', b"<row r='", b':row r="', b":row r='")
#: prefixed start tags without attributes (``<x:c>``), which ``:c>`` would confuse with
#: end tags (``</x:c>``)
_PREFIXED_BARE = re.compile(rb"<[A-Za-z_][\w.-]*:(c|row)>")
#: the first bytes of an OLE2 compound document (.xls)
_OLE2 = b"\xd0\xcf\x11\xe0"


def _column_number(letters: bytes) -> int:
    """The column of ``AB``-style letters (1 for A); beyond 6 letters, 26^6 (past any
    limit, without looping over a reference of any length)."""
    if len(letters) > 6:
        return 26**6
    number = 0
    for ch in letters.upper():
        number = number * 26 + ch - 64
    return number


def _row_number(digits: bytes) -> int:
    """A row number; beyond 12 digits, 10^12 (int() refuses over 4300 digits)."""
    return int(digits) if len(digits) <= 12 else 10**12


def _mib(n: int) -> str:
    return f"{n / 2**20:.1f} MiB" if n >= 2**20 else f"{n / 2**10:.1f} KiB"


class _Extent:
    """Upper bounds of the rows and columns calamine will give a sheet part, from its XML
    as it streams past: the largest row number and column letters referenced, plus, for
    rows and cells without a reference (calamine places them after the previous one),
    their count (rows) and the most in one row (cells)."""

    def __init__(self):
        self.max_row = self.max_column = self.rows = self.cells = 0
        self.in_row = self.most_in_row = 0
        self.unreferenced = False
        self.tail = b""

    def feed(self, chunk: bytes, last: bool = False) -> None:
        data = self.tail + chunk
        cut = len(data) if last else data.rfind(b">") + 1
        if not last and (cut == 0 or len(data) - cut > _CHUNK):
            cut = max(len(data) - 64, 0)     # no tag ends here: keep a short overlap
        data, self.tail = data[:cut], data[cut:]
        letters = set(_REF_LETTERS.findall(data))
        if letters:
            self.max_column = max(self.max_column, max(map(_column_number, letters)))
        digits = set(_REF_DIGITS.findall(data))
        if digits:
            self.max_row = max(self.max_row, max(map(_row_number, digits)))
        bare = _PREFIXED_BARE.findall(data)
        bare_cells = bare.count(b"c")
        self.rows += max(0, sum(map(data.count, _ROW_TAGS)) + len(bare) - bare_cells
                         - sum(map(data.count, _REFERENCED_ROWS)))
        cells = sum(map(data.count, _CELL_TAGS)) + bare_cells
        if not self.unreferenced and cells > sum(map(data.count, _REFERENCED_CELLS)):
            # from here on, count the cells of each row; the row under way may hold any
            # of the cells before
            self.unreferenced, self.in_row = True, self.cells
        self.cells += cells
        if self.unreferenced:
            for k, piece in enumerate(data.split(b"row>")):
                if k:
                    self.most_in_row = max(self.most_in_row, self.in_row)
                    self.in_row = 0
                self.in_row += sum(map(piece.count, _CELL_TAGS)) + \
                    len(_PREFIXED_BARE.findall(piece))
            self.most_in_row = max(self.most_in_row, self.in_row)

    @property
    def height(self) -> int:
        return self.max_row + self.rows

    @property
    def width(self) -> int:
        return self.max_column + (self.most_in_row if self.unreferenced else 0)


def _check_archive(data: bytes, path: Path) -> None:
    """InputError unless the zip archive ``data`` (an .xlsx) is an OOXML workbook within the
    bounds: at most `MAX_MEMBERS` members holding at most `ARCHIVE_FACTOR` input size limits
    uncompressed, as its directory states and as inflating confirms (a member that inflates
    to more than stated fails its CRC), and no sheet part whose cell references span more
    than `MAX_SHEET_ROWS` rows or `MAX_SHEET_CELLS` cells."""
    import zipfile
    bound = ARCHIVE_FACTOR * input_limit()
    where = f"workbook {shown(path)}"
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        members = archive.infolist()
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError) as err:
        raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or .xlsx): "
                         f"it is not a valid zip archive ({_reason(err)})") from None
    if len(members) > MAX_MEMBERS:
        raise InputError(f"{where} is a zip archive of {len(members)} members, more than "
                         f"the {MAX_MEMBERS} a workbook may hold")
    total = sum(m.file_size for m in members)
    if total > bound:
        packed = sum(m.compress_size for m in members)
        raise InputError(f"{where} holds {_mib(total)} uncompressed ({_mib(packed)} "
                         f"compressed, a ratio of {total / max(packed, 1):.0f}), more than "
                         f"{_mib(bound)}, {ARCHIVE_FACTOR} times the input size limit (a zip "
                         f"bomb?; set {MAX_INPUT_BYTES_ENV} to raise it)")
    names = {m.filename.lower() for m in members}
    if "xl/workbook.xml" not in names or "content.xml" in names \
            or any(n.endswith(".bin") and n.startswith("xl/") and "workbook" in n for n in names):
        raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or .xlsx): "
                         "its zip archive holds no xl/workbook.xml (an .xlsb or .ods "
                         "workbook, or another archive: save it as .xlsx)")
    for member in members:
        if member.is_dir():
            continue
        extent = _Extent()
        try:
            with archive.open(member) as f:
                while chunk := f.read(_CHUNK):
                    extent.feed(chunk)
                    _check_extent(extent, path, member.filename)
        except InputError:
            raise
        except (zipfile.BadZipFile, OSError, ValueError, EOFError, NotImplementedError,
                RuntimeError) as err:      # a bad CRC, an unknown compression, encryption
            raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or "
                             f".xlsx): its zip archive is damaged ({_reason(err)})") from None
        extent.feed(b"", last=True)
        _check_extent(extent, path, member.filename)


def _check_extent(extent: _Extent, path: Path, part: str) -> None:
    if extent.height > MAX_SHEET_ROWS or extent.height * extent.width > MAX_SHEET_CELLS:
        raise _too_big(path, f"part {excerpt(part)}", extent.height, extent.width)


def _too_big(path: Path, what: str, rows: int, columns: int) -> InputError:
    return InputError(f"workbook {shown(path)}: {what} spans up to {rows} rows x {columns} "
                      f"columns; the limits are {MAX_SHEET_ROWS} rows and {MAX_SHEET_CELLS} "
                      "cells a sheet")


def _reason(err: BaseException) -> str:
    """A library's one-line reason, escaped and at most 100 characters (it may hold a piece
    of the file)."""
    text = str(err).splitlines()[0] if str(err).strip() else type(err).__name__
    text = ascii(text)[1:-1]
    return text if len(text) <= 100 else text[:97] + "..."


# ---- sheets -----------------------------------------------------------------------------

def _open(path: Path):
    """The workbook, read from the bytes that passed the checks: a regular file within the
    input size limit (`core.files.read_bytes`), an OLE2 document (.xls) or a zip archive
    within the bounds above (.xlsx). calamine reads the same bytes from memory, never the
    name again: a file replaced after the checks (by a pipe, by a bomb) is not read."""
    data = read_bytes(path, "workbook")
    is_zip = data[:2] == b"PK"
    if not is_zip and data[:4] != _OLE2:
        import zipfile
        is_zip = zipfile.is_zipfile(io.BytesIO(data))
    if is_zip:
        _check_archive(data, path)
    elif data[:4] != _OLE2:
        raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or .xlsx): "
                         "it is neither an OLE2 document (.xls) nor a zip archive (.xlsx)")
    from python_calamine import CalamineWorkbook
    try:
        return CalamineWorkbook.from_filelike(io.BytesIO(data))
    except Exception as err:  # calamine raises its own errors on files that are not workbooks
        reason = _reason(err)
        if reason == "Cannot detect file format":
            reason = ("its zip archive holds no workbook calamine reads" if is_zip else
                      "its OLE2 container is damaged or not an office document")
        raise InputError(f"cannot read {shown(path)} as an Excel workbook (.xls or .xlsx): "
                         f"{reason}") from None


def _rows(book, name: str, path: Path) -> list[list]:
    try:
        sheet = book.get_sheet_by_name(name)
        end = sheet.end
    except Exception as err:
        raise InputError(f"cannot read sheet {excerpt(name)} of {shown(path)}: "
                         f"{_reason(err)}") from None
    # the rows as to_python gives them (from A1: skip_empty_area=False), counted first
    rows, columns = (end[0] + 1, end[1] + 1) if end else (0, 0)
    if rows > MAX_SHEET_ROWS or rows * columns > MAX_SHEET_CELLS:
        raise _too_big(path, f"sheet {excerpt(name)}", rows, columns)
    try:
        return sheet.to_python(skip_empty_area=False)
    except Exception as err:
        raise InputError(f"cannot read sheet {excerpt(name)} of {shown(path)}: "
                         f"{_reason(err)}") from None


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
            out[name] = sheet_curve(rows, options, f"{path} sheet {excerpt(name)}", meta)
        except InputError as err:
            reasons.append(str(err))
    if not out:
        why = "; ".join(reasons[:3]) + (f"; and {len(reasons) - 3} more" if len(reasons) > 3
                                        else "")
        raise InputError(f"workbook {shown(path)} holds no test sheet with depth and load "
                         f"columns ({why or 'its sheets ' + excerpt(', '.join(names))})")
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
    if first < len(rows) and is_unit_row(rows[first]):
        units = [clean_unit(c) if isinstance(c, str) and c.strip() else None for c in rows[first]]
        units += [None] * (len(names) - len(units))
        first += 1
    picked = pick_columns(names, units, options, source)
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
    from .curves import segment_runs
    codes = codes.copy()
    for label, start, stop in segment_runs(codes):
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
        if is_unit_row(rows[1]) or not any(isinstance(c, (int, float)) for c in rows[1]):
            units = [clean_unit(c) if isinstance(c, str) and c.strip() else None for c in rows[1]]
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
