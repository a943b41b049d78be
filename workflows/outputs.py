"""The output files of a command, checked before any work: an output is never one of the
command's inputs (nor another of its outputs), whatever path reaches it (relative, through a
symbolic or a hard link), and it replaces an existing file only when that file is an earlier
output of the same kind, unless ``--force``. `describe` says what a file is, for messages."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable

from filmscale.core.errors import InputError

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"

#: the leading bytes of each plot format matplotlib writes; formats absent here (raw, rgba)
#: have none, and an existing file of their suffix is taken for an earlier plot
IMAGE_SIGNATURES = {
    "png": (b"\x89PNG\r\n\x1a\n",), "pdf": (b"%PDF",), "ps": (b"%!PS",), "eps": (b"%!PS",),
    "jpg": (b"\xff\xd8\xff",), "jpeg": (b"\xff\xd8\xff",), "tif": (b"II*\0", b"MM\0*"),
    "tiff": (b"II*\0", b"MM\0*"), "webp": (b"RIFF",), "svg": (b"<?xml", b"<svg"),
    "svgz": (b"\x1f\x8b",), "pgf": (b"%",)}


@dataclass(frozen=True)
class Kind:
    """What a command writes to an output, and how to tell a file it wrote there before (which
    it may replace without --force)."""

    description: str
    written_before: Callable[[Path], bool]


def add_force_argument(parser) -> None:
    """``--force`` of a command that writes files."""
    parser.add_argument("--force", action="store_true",
                        help="replace an existing file that is not an earlier output of this "
                             "command (an input is never replaced)")


def _head(path: Path, size: int = 4096) -> bytes:
    try:
        with open(path, "rb") as f:
            return f.read(size)
    except OSError:
        return b""


def hdf5_format(path: Path) -> str | None:
    """The ``format`` root attribute of a filmscale HDF5 file; None for any other file, or an
    HDF5 file that cannot be opened."""
    if _head(path, len(HDF5_SIGNATURE)) != HDF5_SIGNATURE:
        return None
    import h5py
    try:
        with h5py.File(path, "r") as f:
            value = f.attrs.get("format")
    except (OSError, KeyError):
        return None
    return value.decode() if isinstance(value, bytes) else value


def hdf5_kind(fmt: str | tuple[str, ...], description: str) -> Kind:
    """A filmscale HDF5 output of format ``fmt`` (or any of several: earlier layouts)."""
    formats = (fmt,) if isinstance(fmt, str) else fmt
    return Kind(description, lambda path: hdf5_format(path) in formats)


def text_kind(first_line: str | tuple[str, ...], description: str) -> Kind:
    """A text output recognised by its first line (a CSV header), or by any of several."""
    lines = {line.encode() for line in ((first_line,) if isinstance(first_line, str)
                                        else first_line)}

    def written_before(path: Path) -> bool:
        size = max(len(line) for line in lines) + 2
        return _head(path, size).split(b"\n")[0].rstrip(b"\r") in lines
    return Kind(description, written_before)


#: the largest JSON output read to recognise it
JSON_OUTPUT_BYTES = 2**24


def json_kind(keys: set[str], description: str) -> Kind:
    """A JSON output recognised as an object with ``keys``."""
    def written_before(path: Path) -> bool:
        text = _head(path, JSON_OUTPUT_BYTES + 1)
        if len(text) > JSON_OUTPUT_BYTES:           # no index of ours is that large
            return False
        try:
            data = json.loads(text)
        except ValueError:
            return False
        return isinstance(data, dict) and keys <= set(data)
    return Kind(description, written_before)


def image_kind(path) -> Kind:
    """A plot, recognised by the signature of its suffix's format (``path`` None: no plot)."""
    fmt = Path(path or "").suffix.lower().lstrip(".")
    signatures = IMAGE_SIGNATURES.get(fmt)
    return Kind(f"a {fmt.upper()} image",
                lambda p: signatures is None or _head(p, 16).lstrip().startswith(signatures))


#: the HTML report of `filmscale report`, by the title every report has
REPORT_TITLE = "<title>filmscale report</title>"
REPORT = Kind("an HTML report of filmscale report",
              lambda path: REPORT_TITLE.encode() in _head(path))


def _formats() -> dict[str, str]:
    """Each filmscale HDF5 format, described as `describe` names it."""
    from filmscale.continuum.indentation.io import CURVE_FORMAT
    from filmscale.md.particle_run import RECORD_FORMAT as PARTICLE_RECORD
    from filmscale.md.record import RECORD_FORMAT as MD_RECORD

    from .result import (IMPACT_MAP_FORMAT, IMPACT_MAP_FORMAT_1, INDENT_RESULTS_FORMAT,
                         RESULT_FORMATS, SLIDE_RESULT_FORMAT)
    from .slide_cli import SLIDE_MAP_FORMAT
    return {**{fmt: "a scene result (filmscale run)" for fmt in RESULT_FORMATS},
            SLIDE_RESULT_FORMAT: "a sliding scene's result (filmscale run)",
            SLIDE_MAP_FORMAT: "a slide map (filmscale slide-map)",
            IMPACT_MAP_FORMAT: "an impact map (filmscale impact-map)",
            IMPACT_MAP_FORMAT_1: "an impact map (filmscale impact-map)",
            INDENT_RESULTS_FORMAT: "indentation results (filmscale indent analyze)",
            MD_RECORD: "an MD indentation record (filmscale md indent)",
            PARTICLE_RECORD: "a particle-model record (filmscale particles)",
            CURVE_FORMAT: "a curve file"}


def describe(path) -> str:
    """What a file is, in a few words: a filmscale HDF5 file by its format, a damaged one,
    another HDF5 file, an image, a text or a binary file."""
    path = Path(path)
    if path.is_dir():
        return "a folder"
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError as err:
        return f"a file that cannot be read ({err.strerror})"
    if not head:
        return "an empty file"
    if head.startswith(HDF5_SIGNATURE):
        import h5py
        try:
            with h5py.File(path, "r"):
                pass
        except OSError:
            return "a damaged HDF5 file (it cannot be opened: truncated or overwritten?)"
        fmt = hdf5_format(path)
        if fmt is None:
            return "an HDF5 file without a filmscale format"
        return _formats().get(fmt, f"a filmscale file of format {fmt!r}")
    for fmt in ("png", "pdf", "jpeg", "tiff", "ps"):
        if head.startswith(IMAGE_SIGNATURES[fmt]):
            return f"a {fmt.upper()} file"
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as err:
        if err.start < len(head) - 3:       # not a character cut at the 4 KB boundary
            return "a binary file"
    return "a binary file" if b"\0" in head else "a text file"


def output_path(option: str, path, suffixes: tuple[str, ...] | None = None) -> Path | None:
    """Check an output file's place before any work: not a folder, no file in the way of its
    folder, and (for plots) a suffix in ``suffixes``. Missing folders are created when
    writing."""
    if path is None:
        return None
    out = Path(path)
    if out.is_dir():
        raise InputError(f"{option} {path} is a folder: give a file name")
    parent = out.parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"{option} {path}: {parent} is a file, not a folder")
    if suffixes is not None and out.suffix.lower().lstrip(".") not in suffixes:
        raise InputError(f"{option} {path}: the file name must end in one of "
                         f"{', '.join('.' + s for s in suffixes)}")
    return out


def plot_path(option: str, path) -> Path | None:
    """`output_path` of a plot: a format matplotlib writes."""
    if path is None:
        return None
    from .plots import PLOT_FORMATS
    return output_path(option, path, PLOT_FORMATS)


def _same(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)       # links, hard links, relative paths
    except OSError:                         # one of them does not exist (yet)
        return a.resolve() == b.resolve()


def check_outputs(inputs: Iterable[tuple[str, str | Path]],
                  outputs: Iterable[tuple[str, str | Path | None, Kind]],
                  force: bool = False) -> None:
    """Refuse, before any work, an output that is one of ``inputs`` ((what, path): "the input
    scene", ...) or another of ``outputs`` ((option, path or None when not asked for, kind)),
    and one that would replace an existing file that is not an earlier output of its kind,
    unless ``force``."""
    inputs = [(what, Path(path)) for what, path in inputs]
    checked: list[tuple[str, Path]] = []
    for option, path, kind in outputs:
        if path is None:
            continue
        path = Path(path)
        for what, source in inputs:
            if _same(path, source):
                raise InputError(f"{option} {path} is {what}; choose another file")
        for other, earlier in checked:
            if _same(path, earlier):
                raise InputError(f"{option} {path} is also {other}; give each output its own "
                                 "file")
        checked.append((option, path))
        if path.is_dir():
            raise InputError(f"{option} {path} is a folder: give a file name")
        if path.is_file() and not force and not kind.written_before(path):
            raise InputError(f"{option} {path} exists and is {describe(path)}, not "
                             f"{kind.description}; choose another file, or --force replaces "
                             "it")


def scene_files(base, data: dict, calibrations=()) -> list[tuple[str, Path]]:
    """The files a scene reads besides itself: its measured profile (target.profile.file)
    and the files of its calibration sources (curve and spec files, not presets)."""
    base = Path(base)
    files = []
    profile = data.get("target", {}).get("profile")
    if isinstance(profile, dict) and "file" in profile:
        files.append(("the scene's target.profile file", base / str(profile["file"])))
    for src in calibrations:
        files += [(f"a calibration source of the scene ({src.label})", base / name)
                  for name in src.source if (base / name).is_file()]
    return files


#: what a run directory of `filmscale md indent` and `filmscale particles` holds
RUN_STATE = "state.json"


def check_run_folder(option: str, path: Path, inputs: Iterable[tuple[str, str | Path]],
                     force: bool = False) -> None:
    """A run directory: not a file, not an input, and (unless ``force``) either new, empty
    or one that holds a filmscale run (which it resumes or reads back), so that a run never
    writes its files into a folder of other files."""
    for what, source in inputs:
        if _same(path, Path(source)):
            raise InputError(f"{option} {path} is {what}; choose another folder")
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path} is a file, not a folder")
    if path.is_dir() and not force and not (path / RUN_STATE).is_file() \
            and any(path.iterdir()):
        raise InputError(f"{option} {path} is a folder of other files (no filmscale run in "
                         "it); choose a new or empty folder, or --force runs there")
