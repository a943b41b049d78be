"""Readers of instrument exports: KLA/Agilent G200 and iMicro workbooks, Hysitron/Bruker
TriboScan text (``.txt``, ``.hld``), Anton Paar and any other delimited text.

Every reader returns curves in SI (m, N, s), converted from the units the file states
(``Depth (nm)``, ``Load [µN]``, a units row under the header) or the units a column mapping
gives. What each layout looks like and how a column mapping is written: docs/indentation.md,
"Instrument files".

- **Workbooks** (``.xls`` and ``.xlsx``): `workbooks.read_workbook`, one curve per test
  sheet, with the CSM channels and the summary sheets' analysis inputs.
- **Hysitron ``.hld``** (the header, approach, drift and test blocks TriboScan writes):
  `hld.read_hld`; a ``.hld`` holding one header line over its numbers is delimited text.
- **Delimited text**: the encoding (UTF-8, else Latin-1, as TriboScan writes ``µ``) and the
  separator (tab, ``;``, ``,`` or blanks) are found from the first rows of numbers; the line
  above them is the header, or the two lines above when the lower one holds only units; lines
  before are a preamble. The number format, a decimal mark and thousands separators
  (``1,234.5``, ``1.234,5``, ``1 234,5``; `MARKS`), is the one that reads every number of the
  table; quoted fields may hold the separator (``"1,234.5"``).

pandas and python-calamine are imported inside the functions that use them: the command line
starts without them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError
from filmscale.core.files import (check_regular_file, open_regular, read_bytes,
                                  read_toml, shown)

from .curves import LoadDisplacementCurve

FORMATS = ("auto", "filmscale", "g200", "hysitron", "anton-paar", "delimited")
EXCEL_SUFFIXES = (".xls", ".xlsx", ".xlsm")
#: bytes of a ``.hld`` read to tell its layout (the real header is about 6 kB)
HLD_HEAD_BYTES = 1 << 16
#: what the messages of the opening checks (regular file, size) call an instrument file
WHAT = "curve file"
#: what each named format fixes before the rest is found from the file
PRESETS = {
    "hysitron": {"encoding": "latin-1", "separator": "\t"},
    "anton-paar": {"separator": ";", "decimal": ","},
}
ROLES = ("h", "P", "t")
#: header names of each column, most specific first (compared without case and unit)
ALIASES = {
    "h": ("displacement into surface", "depth", "indentation depth", "penetration depth",
          "pd", "displacement", "disp", "h"),
    "P": ("load on sample", "load", "normal force", "fn", "force", "p", "f"),
    "t": ("time on sample", "time", "t"),
}
SEGMENT_NAMES = ("segment", "segment type", "marker")
#: unit -> factor to SI, by role (a column whose unit is of another kind is not that role:
#: TriboScan's ``Depth (V)`` beside ``Depth (nm)``)
ROLE_UNITS = {
    "h": {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9, "A": 1e-10, "Å": 1e-10},
    "P": {"N": 1.0, "mN": 1e-3, "uN": 1e-6, "µN": 1e-6, "nN": 1e-9},
    "t": {"s": 1.0, "ms": 1e-3, "min": 60.0},
}
_KNOWN_UNITS = {u for units in ROLE_UNITS.values() for u in units} | {
    "N/m", "GPa", "MPa", "Pa", "V", "mV", "nm/s", "mN/s", "uN/s", "µN/s", "1/s", "%", "-", "1",
    "Hz", "°C", "C", "K"}
_NAME_UNIT = re.compile(r"^(.*?)\s*(?:\[([^\]]*)\]|\(([^)]*)\))\s*$")


#: base units -> (factor to SI, dimensions): L length (m), F force (N), T time (s), V volts
_BASE_UNITS = {
    "m": (1.0, {"L": 1}), "mm": (1e-3, {"L": 1}), "µm": (1e-6, {"L": 1}),
    "nm": (1e-9, {"L": 1}), "A": (1e-10, {"L": 1}), "Å": (1e-10, {"L": 1}),
    "N": (1.0, {"F": 1}), "kN": (1e3, {"F": 1}), "mN": (1e-3, {"F": 1}),
    "µN": (1e-6, {"F": 1}), "nN": (1e-9, {"F": 1}),
    "Pa": (1.0, {"F": 1, "L": -2}), "kPa": (1e3, {"F": 1, "L": -2}),
    "MPa": (1e6, {"F": 1, "L": -2}), "GPa": (1e9, {"F": 1, "L": -2}),
    "s": (1.0, {"T": 1}), "ms": (1e-3, {"T": 1}), "min": (60.0, {"T": 1}),
    "V": (1.0, {"V": 1}), "mV": (1e-3, {"V": 1}),
}
_POWER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")


def micro_sign(text: str) -> str:
    """The Greek mu and an ASCII ``u`` before a unit letter made the micro sign."""
    text = text.replace("\u03bc", "\u00b5")
    return re.sub(r"(?<![A-Za-z])u(?=[mN]\b)", "\u00b5", text)


def si_unit(unit: str) -> tuple[float, dict[str, float]] | None:
    """(factor to SI, dimensions) of a unit as instruments write them: ``nm``, ``mN``,
    ``GPa``, ``N/m``, ``nm/µN``, ``nm^2/nm^0.5``; None for units without an SI conversion
    here (``deg``, ``%``, ``Hz``, text). The one place where the readers' units become SI."""
    parts = micro_sign(str(unit).strip()).split("/")
    if not str(unit).strip() or len(parts) > 2:
        return None
    factor, dims = 1.0, {}
    for sign, part in zip((1.0, -1.0), parts):
        base, _, power = part.strip().partition("^")
        if base not in _BASE_UNITS or (power and not _POWER.match(power)):
            return None
        p = sign * (float(power) if power else 1.0)
        scale, base_dims = _BASE_UNITS[base]
        factor *= scale ** p
        for dim, q in base_dims.items():
            dims[dim] = dims.get(dim, 0.0) + q * p
    return factor, {d: p for d, p in dims.items() if p != 0.0}


def clean_unit(text) -> str:
    """A unit as written, with the Greek mu made the micro sign and brackets dropped."""
    text = str(text).strip().replace("\u03bc", "\u00b5")
    return text[1:-1].strip() if text[:1] in "[(" and text[-1:] in "])" else text


def split_name(text) -> tuple[str, str | None]:
    """(name, unit) of a header cell: ``Depth (nm)`` -> (``Depth``, ``nm``)."""
    text = str(text).strip()
    match = _NAME_UNIT.match(text)
    if match and match.group(1):
        return match.group(1), clean_unit(match.group(2) or match.group(3) or "")
    return text, None


def is_unit_row(cells) -> bool:
    """True for the row of units under a header (a G200 units row, a two-row header): no cell
    is a number and at least one is a known unit. Units not known here (``deg``, ``nm^2``,
    ``1/nm``) do not make it a data row."""
    seen = [c for c in cells if c is not None and str(c).strip() and str(c) != "nan"]
    if not seen or any(isinstance(c, (int, float)) and not isinstance(c, bool) for c in seen):
        return False
    if any(_admits(str(c).strip()) for c in seen):
        return False
    return any(clean_unit(c) in _KNOWN_UNITS for c in seen)


@dataclass(frozen=True)
class ReadOptions:
    """How to read instrument files (picklable: it travels to worker processes).

    ``format`` is one of `FORMATS`; ``columns`` maps a role (h, P, t) to a header name
    (compared without case and unit) or a 1-based column number, with an optional unit that
    overrides the file's; the rest, None where the file is to tell.
    """

    format: str = "auto"
    columns: tuple = ()            #: ((role, name or number, unit or None), ...)
    encoding: str | None = None
    separator: str | None = None   #: None: found; " " any run of blanks
    decimal: str | None = None
    header_rows: int | None = None   #: 1 or 2 (names, then units)
    skip_rows: int | None = None     #: preamble lines before the header

    def __post_init__(self):
        if self.format not in FORMATS:
            raise InputError(f"format = {self.format!r} is not one of {', '.join(FORMATS)}")
        if self.decimal not in (None, ".", ","):
            raise InputError(f"decimal = {self.decimal!r} must be '.' or ','")
        if self.header_rows not in (None, 1, 2):
            raise InputError(f"header_rows = {self.header_rows!r} must be 1 or 2")
        if self.skip_rows is not None and not (isinstance(self.skip_rows, int)
                                               and 0 <= self.skip_rows <= 10000):
            raise InputError(f"skip_rows = {self.skip_rows!r} must be a whole number 0-10000")
        if self.encoding is not None:
            text_encoding(self.encoding, "encoding")
        for role, _, unit in self.columns:
            if role not in ROLES:
                raise InputError(f"column mapping: role {role!r} is not one of h, P, t")
            if unit is not None and unit not in ROLE_UNITS[role]:
                raise InputError(f"column mapping: unit {unit!r} of {role} is not one of "
                                 f"{', '.join(ROLE_UNITS[role])}")

    def setting(self, key):
        """The option's value, else the named format's preset, else None."""
        value = getattr(self, key)
        return PRESETS.get(self.format, {}).get(key) if value is None else value


def text_encoding(name, what: str = "encoding") -> str:
    """``name`` when it names a text encoding (``codecs.lookup`` knows it and marks it one:
    rot13, zlib_codec, base64_codec and hex_codec are codecs but not text encodings), else
    InputError naming ``what`` and the value."""
    import codecs
    try:
        info = codecs.lookup(name) if isinstance(name, str) and name.strip() else None
    except LookupError:
        info = None
    if info is None or not getattr(info, "_is_text_encoding", True):
        kind = "is not a known" if info is None else "is a codec but not a"
        raise InputError(f"{what} = {name!r} {kind} text encoding (text encodings: utf-8, "
                         "latin-1, cp1252, utf-16, ...)")
    return name


def parse_columns(text: str) -> tuple:
    """Column mapping from text such as ``h=Depth:nm,P=Load (uN),t=3:s``: role = header name
    or 1-based column number, then ``:unit`` where the header gives none or a wrong one."""
    out = []
    for item in filter(str.strip, text.split(",")):
        role, eq, rest = item.partition("=")
        if not eq or not rest.strip():
            raise InputError(f"--columns item {item!r} is not ROLE=NAME[:UNIT] (ROLE h, P, t)")
        name, _, unit = rest.rpartition(":") if ":" in rest else (rest, "", "")
        out.append((role.strip(), _column_key(name.strip()), clean_unit(unit) if unit else None))
    return tuple(out)


def _column_key(name):
    return int(name) if name.isdigit() else name


def read_options_file(path, base: ReadOptions | None = None) -> ReadOptions:
    """`ReadOptions` from a small TOML file (keys of `ReadOptions`; ``[columns]`` maps a role
    to a name or number, ``[units]`` a role to its unit)."""
    data = read_toml(path, "reader options file")
    allowed = {"format", "encoding", "separator", "decimal", "header_rows", "skip_rows",
               "columns", "units"}
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise InputError(f"reader options file {shown(path)}: unknown key(s) "
                         f"{', '.join(unknown)}; known: {', '.join(sorted(allowed))}")
    columns, units = data.get("columns", {}), data.get("units", {})
    if not isinstance(columns, dict) or not isinstance(units, dict):
        raise InputError(f"reader options file {shown(path)}: columns and units must be tables")
    mapped = tuple((role, _column_key(str(key)), units.get(role))
                   for role, key in columns.items())
    mapped += tuple((role, None, unit) for role, unit in units.items() if role not in columns)
    base = base or ReadOptions()
    kwargs = {k: data.get(k, getattr(base, k)) for k in
              ("format", "encoding", "separator", "decimal", "header_rows", "skip_rows")}
    try:
        return ReadOptions(columns=mapped or base.columns, **kwargs)
    except InputError as err:
        raise InputError(f"reader options file {shown(path)}: {err}") from None


# ---- columns -----------------------------------------------------------------------------

def pick_columns(names, units, options: ReadOptions, source) -> dict:
    """{role: (column index, factor to SI)} for h, P and, when present, t, from a header's
    column ``names`` and ``units`` (None where a name carries its own) and the user's
    column choices in ``options``."""
    parsed = [split_name(n) for n in names]
    labels = [p[0].strip().lower() for p in parsed]
    units = [u if u is not None else p[1] for u, p in zip(units, parsed)]
    mapping = {role: (key, unit) for role, key, unit in options.columns}
    out = {}
    for role in ROLES:
        key, forced = mapping.get(role, (None, None))
        if isinstance(key, int):
            if not 1 <= key <= len(names):
                raise InputError(f"{shown(source)}: column {key} of {role} is beyond its "
                                 f"{len(names)} columns")
            candidates = [key - 1]
        elif key is not None:
            want = split_name(key)[0].strip().lower()
            candidates = [k for k, label in enumerate(labels) if label == want]
            if not candidates:
                raise InputError(f"{shown(source)}: no column named {key!r} for {role} (it has "
                                 f"{', '.join(map(str, names))})")
        else:
            candidates = [k for alias in ALIASES[role] for k, label in enumerate(labels)
                          if label == alias]
        chosen = None
        for k in candidates:
            unit = forced or units[k]
            if unit in ROLE_UNITS[role]:
                chosen = (k, ROLE_UNITS[role][unit])
                break
        if chosen is None and candidates and role != "t":
            k = candidates[0]
            unit = forced or units[k]
            raise InputError(f"{shown(source)}: column {names[k]!r} ({role}) has "
                             f"{'no unit' if not unit else f'unit {unit!r}'}; give one of "
                             f"{', '.join(ROLE_UNITS[role])} in the header or the column "
                             f"mapping ({role}=NAME:UNIT)")
        if chosen is None and role != "t":
            raise InputError(f"{shown(source)}: no {role} column (names accepted: "
                             f"{', '.join(ALIASES[role])}, or a column mapping; it has "
                             f"{', '.join(map(str, names))})")
        if chosen is not None:
            out[role] = chosen
    return out


def _curve(frame, picked, source, meta, segment=None) -> LoadDisplacementCurve:
    """A curve from the numeric columns of a DataFrame; rows without h and P are dropped."""
    import pandas as pd

    data = {role: pd.to_numeric(frame.iloc[:, k], errors="coerce").to_numpy(float) * factor
            for role, (k, factor) in picked.items()}
    keep = np.isfinite(data["h"]) & np.isfinite(data["P"])
    if keep.sum() < 2:
        raise InputError(f"{shown(source)}: fewer than 2 rows of numbers under the header")
    t = data["t"][keep] if "t" in data else None
    seg = segment[keep] if segment is not None else None
    return LoadDisplacementCurve(data["h"][keep], data["P"][keep], t, seg, meta=meta)


# ---- delimited text ----------------------------------------------------------------------

def _decode(path: Path, encoding: str | None) -> str:
    data = read_bytes(path, WHAT)
    for enc in ([encoding] if encoding else ["utf-8-sig", "latin-1"]):
        try:
            text = data.decode(enc)
            break
        except UnicodeError as err:     # UnicodeDecodeError, and plain from punycode
            if encoding:
                where = (f"{err.reason} at byte {err.start}"
                         if isinstance(err, UnicodeDecodeError) else str(err))
                raise InputError(f"{shown(path)} is not {encoding} text: {where}") from None
    # NUL characters, not bytes: UTF-16 text holds NUL bytes
    if "\0" in text:
        raise InputError(f"{shown(path)} is not text (it holds NUL bytes): export it as text "
                         "or .xlsx")
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _fields(line: str, sep: str) -> list[str]:
    """The fields of a line; with a separator other than blanks, quoted fields may hold it
    (``"1,234.5"`` in a comma-separated table)."""
    if sep == " ":
        return line.split()
    if '"' in line:
        import csv
        row = next(csv.reader([line], delimiter=sep, skipinitialspace=True), [])
        return [f.strip().strip('"') for f in row]
    return [f.strip() for f in line.split(sep)]


#: the number formats a table may use, (decimal mark, thousands separator), in the order one
#: is chosen when several read every number of the table (a blank stands for the no-break
#: spaces too): ``1,5`` is a decimal comma, ``1,234.5`` a thousands comma, ``1,234`` either
MARKS = ((".", None), (",", None), (".", ","), (",", "."), (".", " "), (",", " "),
         (".", "'"), (",", "'"))
_BLANKS = str.maketrans({"\u00a0": " ", "\u202f": " "})


def _number_pattern(decimal: str, thousands: str | None) -> str:
    """A number in one format: a sign, digits (in groups of three after the first one to
    three where ``thousands`` separates them, then without an exponent), at most one
    ``decimal`` mark, an exponent; or nan, inf."""
    d = re.escape(decimal)
    plain = rf"(?:[0-9]+(?:{d}[0-9]*)?|{d}[0-9]+)(?:[eE][-+]?[0-9]+)?"
    if thousands:
        t = "[ \u00a0\u202f]" if thousands == " " else re.escape(thousands)
        plain = rf"[1-9][0-9]{{0,2}}(?:{t}[0-9]{{3}})+(?:{d}[0-9]*)?|{plain}"
    return rf"[-+]?(?:{plain}|nan|inf|infinity)"


_IN_FORMAT = tuple(re.compile(_number_pattern(*marks), re.IGNORECASE) for marks in MARKS)
_ANY_NUMBER = re.compile("|".join(f"(?:{_number_pattern(*m)})" for m in MARKS), re.IGNORECASE)


def _bit(decimal: str, thousands: str | None) -> int:
    return 1 << MARKS.index((decimal, thousands))


def _admits(field: str) -> int:
    """The number formats (bits of `MARKS`) that read ``field`` as a number; 0 for text."""
    return sum(1 << k for k, pattern in enumerate(_IN_FORMAT) if pattern.fullmatch(field))


def _values(fields: list[str], marks: tuple) -> list[float]:
    """``fields``, numbers in the format ``marks`` or empty (NaN), as floats."""
    decimal, thousands = marks
    fields = [f or "nan" for f in fields]
    if thousands:
        fields = [f.translate(_BLANKS).replace(thousands, "") for f in fields]
    if decimal == ",":
        fields = [f.replace(",", ".") for f in fields]
    return list(map(float, fields))


def _describe(marks: tuple) -> str:
    decimal, thousands = marks
    text = "a decimal point" if decimal == "." else "a decimal comma"
    names = {",": "commas", ".": "points", " ": "blanks", "'": "apostrophes"}
    return text + (f" and {names[thousands]} between thousands" if thousands else "")


def _numeric_row(line: str, sep: str) -> int:
    """Number of fields when every non-empty field is a number in some format (at least
    2), else 0."""
    fields = _fields(line, sep)
    filled = [f for f in fields if f]
    return len(fields) if len(filled) >= 2 and all(map(_ANY_NUMBER.fullmatch, filled)) else 0


def _split_thousands(line: str, sep: str, width: int) -> str | None:
    """The first number written with thousands commas in ``line`` when it is a row of a
    comma-separated table of ``width`` columns cut into more fields by them."""
    if sep != "," or not _numeric_row(line, sep) > width:
        return None
    match = re.search(r"(?<![0-9.])[0-9]{1,3}(?:,[0-9]{3})+(?:\.[0-9]+)?(?![0-9])", line)
    return match.group(0) if match else None


_COMMA_NUMBER = re.compile(r"^[-+]?\d*,?\d+(?:[eE][-+]?\d+)?$")


def _separator(line: str) -> str:
    """Tab or ``;`` when present; a comma, unless blanks separate numbers with a decimal
    comma (``1,5 2,25``)."""
    for sep in ("\t", ";"):
        if sep in line:
            return sep
    words = line.split()
    if "," in line and not (len(words) >= 2 and all(map(_COMMA_NUMBER.match, words))):
        return ","
    return " "


def _layout(lines, options: ReadOptions):
    """(first data line, separator) of delimited text."""
    start = options.skip_rows + (options.header_rows or 1) if options.skip_rows is not None \
        else 0
    for k in range(start, len(lines)):
        line = lines[k].strip()
        if not line:
            continue
        following = [ln.strip() for ln in lines[k + 1:k + 4] if ln.strip()]
        # the separator and decimal mark from the last of these rows: a first row of zeros
        # ("0 0") tells neither
        sep = options.setting("separator") or _separator(following[-1] if following else line)
        width = _numeric_row(line, sep)
        if width and all(_numeric_row(ln, sep) == width for ln in following):
            return k, sep
    raise InputError("no rows of numbers (three lines with the same number of numeric fields)")


def read_delimited(path, options: ReadOptions | None = None) -> dict[str, LoadDisplacementCurve]:
    """The curve of a delimited text export (TriboScan ``.txt``/``.hld``, Anton Paar, ...)."""
    import pandas as pd

    options = options or ReadOptions()
    path = Path(path)
    text = _decode(path, options.setting("encoding"))
    lines = text.split("\n")
    try:
        first, sep = _layout(lines, options)
    except InputError as err:
        raise InputError(f"{shown(path)}: {err}") from None
    above = [k for k in range(first) if lines[k].strip()]
    if options.skip_rows is not None:
        above = [k for k in above if k >= options.skip_rows]
    if not above and not options.columns:
        raise InputError(f"{shown(path)}: no header line above its numbers (give a column "
                         "mapping with column numbers and units)")
    two = options.header_rows == 2 or (options.header_rows is None and len(above) >= 2
                                       and is_unit_row(_fields(lines[above[-1]], sep)))
    width = _numeric_row(lines[first].strip(), sep)
    if above:
        names = _fields(lines[above[-2] if two else above[-1]].strip().lstrip("#"), sep)
        units = [clean_unit(u) or None for u in _fields(lines[above[-1]], sep)] if two else []
    else:
        names, units = [str(k + 1) for k in range(width)], []
    while names and not names[-1]:        # a trailing separator closes some headers
        names.pop()
    if len(names) != width:
        split = _split_thousands(lines[first].strip(), sep, len(names))
        if split:
            raise InputError(_thousands_commas(path, first + 1, split))
        raise InputError(f"{shown(path)}: its header names {len(names)} columns but its rows "
                         f"hold {width} numbers")
    units = (units + [None] * width)[:width]
    picked = pick_columns(names, units, options, path)
    marks, body = _table(path, lines, first, sep, width, names, options)
    frame = pd.DataFrame(np.array(_values(body, marks), dtype=float).reshape(-1, width))
    meta = {"source": str(path), "format": "delimited", "separator": sep,
            "decimal": marks[0]}
    if marks[1]:
        meta["thousands"] = marks[1]
    return {path.stem: _curve(frame, picked, path, meta)}


def _table(path, lines, first, sep, width, names, options):
    """(number format, fields row after row) of the table from line ``first``: it ends at
    its first line that is not ``width`` numbers. The format (`MARKS`) is the first that
    reads every number (those of the ``decimal`` option first). InputError naming the line
    and column of a number that no format shared with the rows above reads, and for
    thousands commas in a comma-separated table, where they cannot be told from the
    separator."""
    body, numbers, plain = [], [], True
    for n, line in enumerate(lines[first:], start=first + 1):
        line = line.strip()
        if not line:
            continue
        fields = _fields(line, sep)
        filled = [f for f in fields if f]
        if len(fields) != width or len(filled) < 2:
            break
        if not all(map(_IN_FORMAT[0].fullmatch, filled)):     # the common format first
            if not all(map(_ANY_NUMBER.fullmatch, filled)):
                break
            plain = False
        body += fields
        numbers.append(n)
    else:
        line = None
    split = _split_thousands(line, sep, width) if line else None
    if split:
        raise InputError(_thousands_commas(path, n, split))
    filled = [f for f in body if f]
    decimal = options.setting("decimal")
    order = sorted(range(len(MARKS)), key=lambda k: MARKS[k][0] != decimal)
    for k in order:
        if (plain and k == 0) or all(map(_IN_FORMAT[k].fullmatch, filled)):
            return MARKS[k], body
    # no one format reads them all: the first number that none shared with the rows above
    bits = (1 << len(MARKS)) - 1
    for row, n in enumerate(numbers):
        for k, field in enumerate(body[row * width:(row + 1) * width]):
            if field and not bits & _admits(field):
                was = next(MARKS[j] for j in order if bits >> j & 1)
                raise InputError(
                    f"{shown(path)}: line {n}, column {names[k]!r} holds {field!r}, which "
                    f"does not fit the number format of the rows above ({_describe(was)}): "
                    f"{_advice(field)}")
            bits &= _admits(field) if field else bits
    raise InputError(f"{shown(path)}: its numbers are not in one format")   # not reached


def _advice(field: str) -> str:
    if not _admits(field) & (_bit(".", None) | _bit(",", None)):
        return ("it holds thousands separators; export the table without them, or with one "
                "number format throughout")
    return "export the table with one decimal mark throughout"


def _thousands_commas(path, line: int, number: str) -> str:
    return (f"{shown(path)}: line {line} holds a number with thousands separators ({number}) "
            "in a comma-separated table, where they cannot be told from the separator: export "
            f"without thousands separators, or with the numbers quoted (\"{number}\")")


def read_instrument(path, options: ReadOptions | None = None) -> dict[str, LoadDisplacementCurve]:
    """Curves of an instrument file by name: a workbook's test sheets, a Hysitron ``.hld``'s
    test, or a text export's one curve. InputError naming the file and why it cannot be
    read."""
    path = Path(path)
    options = options or ReadOptions()
    check_regular_file(path, WHAT)      # before any reader opens it: a FIFO would block
    suffix = path.suffix.lower()
    if suffix in EXCEL_SUFFIXES:
        from .workbooks import read_workbook
        return read_workbook(path, options)
    if options.format == "g200":
        raise InputError(f"{shown(path)}: format g200 reads the .xls and .xlsx workbooks "
                         "NanoSuite exports; give the workbook, or --format delimited for its "
                         "text")
    if suffix == ".hld" and not options.columns and _hld_layout(path):
        from .hld import read_hld
        return read_hld(path)
    return read_delimited(path, options)


def _hld_layout(path: Path) -> bool:
    """True for the layout TriboScan writes to ``.hld``: a ``File Version: Hysitron`` header
    and data blocks each opened by a ``... Data Points: N`` line (a text export with one
    header line is read as delimited text). Only the header is read: its first block opens
    within the first few kilobytes. The size limit is the reader's that follows
    (`core.files.read_bytes`); `read_instrument` has checked that the file is regular."""
    try:
        with open_regular(path, WHAT) as f:
            head = f.read(HLD_HEAD_BYTES)
    except OSError as err:
        raise InputError(f"cannot read {shown(path)}: {err.strerror}") from None
    return head.startswith(b"File Version: Hysitron") and b"Data Points:" in head
