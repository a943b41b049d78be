"""The unit store's mechanics: unit folders named by the hash of their inputs and the code
version, one process per unit (``STORE/<unit>.lock``), ``done.json`` records with checksums,
damaged units set aside (``<unit>.corrupt-<time>``), and the store's state for ``filmscale
status``. What the units compute is `workflows.units`.

The store stays inside itself: its folders and files are opened without following links
(a unit folder or a file in one that is a link is a corrupted unit, set aside; a lock file
that is a link is set aside), ``done.json`` is read with the bounded JSON reader and may
name only plain file names of its own unit, each hashed in chunks up to
`MAX_UNIT_FILE_BYTES`, and `unit_states` (``filmscale status``) creates no file, so a
read-only store can be inspected."""

from __future__ import annotations

import errno
import fcntl
import functools
import hashlib
import json
import os
import re
import stat
import sys
import time
from contextlib import contextmanager
from pathlib import Path

import filmscale
from filmscale import __version__
from filmscale.core.errors import InputError
from filmscale.core.files import MAX_INPUT_BYTES, parse_json, shown, write_json
from filmscale.core.jsonable import dumps

#: the file of a run unit that holds its curve: an MD unit's record (as `filmscale md
#: indent` writes it), a particle unit's arrays; MD units stored before the record was kept
#: hold CURVE_ARRAYS too and are still read
MD_RECORD, CURVE_ARRAYS = "indent.h5", "curve.npz"


def say(message: str):
    """A progress line on stderr."""
    print(f"filmscale: {message}", file=sys.stderr, flush=True)


#: the subpackages whose files (code and data) make the code version; the tests, benchmarks,
#: docs and scenes beside them in a checkout do not count
CODE_PARTS = ("core", "continuum", "md", "potentials", "workflows")


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """The package version and a digest of the package's own files, which every unit's hash
    includes: any change of the code makes new units, a change beside it does not."""
    root = Path(filmscale.__file__).resolve().parent
    files = [root / "__init__.py", root / "__main__.py"] + sorted(
        p for part in CODE_PARTS for p in (root / part).rglob("*")
        if p.is_file() and "__pycache__" not in p.parts)
    digest = hashlib.sha256()
    for p in files:
        digest.update(p.relative_to(root).as_posix().encode() + b"\0" + p.read_bytes())
    return f"{__version__}+{digest.hexdigest()[:16]}"


def unit_dir(store: Path, kind: str, inputs: dict) -> Path:
    """``store/<kind>-<16 hex>``, the hash over the kind, the inputs and the code version."""
    blob = json.dumps({"kind": kind, "inputs": inputs, "code": code_version()},
                      sort_keys=True, default=str)
    return Path(store) / f"{kind}-{hashlib.sha256(blob.encode()).hexdigest()[:16]}"


#: the flags every file and folder of the store is opened with: never through a link (the
#: last component; the folders above were checked), never waiting on a pipe, not inherited
_NOFOLLOW = os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC | getattr(os, "O_NOCTTY", 0)


@contextmanager
def unit_lock(path: Path, wait: bool = True):
    """Hold ``<unit>.lock`` beside the unit while it is checked and computed, and yield True:
    a second process (another `filmscale run`, a task of the same job array) waits here,
    then finds the unit done and reuses it; with ``wait=False`` it gets False at once instead
    (and must not touch the unit). Kernel locks (flock): they vanish with a killed process.
    The lock file is opened without following links and must be a regular file: a link or
    anything else in its place is set aside (`_lock_file`), never opened."""
    fd = _lock_file(Path(f"{path}.lock"))
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if not wait:
                yield False
                return
            say(f"waiting for another process computing {shown(path.name)}")
            fcntl.flock(fd, fcntl.LOCK_EX)
        try:
            yield True
        finally:
            fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)


def _lock_file(lock: Path) -> int:
    """An open descriptor of the regular file ``lock``, created when missing. A link, a
    folder, a pipe or a device in its place is set aside (renamed, the link itself, not what
    it points to) and a fresh lock file made; the file is opened with O_NOFOLLOW and checked
    again with fstat, so one put there meanwhile is refused too. The store is created when
    missing."""
    lock.parent.mkdir(parents=True, exist_ok=True)
    for _ in range(5):
        try:
            mode = os.lstat(lock).st_mode
        except FileNotFoundError:
            mode = None
        if mode is not None and not stat.S_ISREG(mode):
            _set_aside(lock, f"lock file {shown(lock)} is "
                       f"{'a symbolic link' if stat.S_ISLNK(mode) else 'not a plain file'}")
            continue
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | _NOFOLLOW, 0o666)
        except OSError as exc:
            if exc.errno in (errno.ELOOP, errno.EISDIR, errno.ENXIO, errno.EMLINK):
                continue        # replaced since the lstat: look again
            raise
        if stat.S_ISREG(os.fstat(fd).st_mode):
            return fd
        os.close(fd)
    raise InputError(f"lock file {shown(lock)} keeps being replaced by a link or another kind "
                     "of file: remove it")


def _busy(path: Path) -> bool:
    """Whether another process holds the unit's lock, found without creating or changing
    any file (for `unit_states` on a read-only store): a shared lock tried for an instant on
    the lock file opened read-only. No lock file (or none that is a regular file): nobody
    computes the unit, since a computing process creates it first."""
    lock = f"{path}.lock"
    try:
        if not stat.S_ISREG(os.lstat(lock).st_mode):
            return False
        fd = os.open(lock, os.O_RDONLY | _NOFOLLOW)
    except OSError:
        return False
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return False
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        fcntl.flock(fd, fcntl.LOCK_UN)
        return False
    finally:
        os.close(fd)


def _set_aside(path: Path, why: str, then: str = "") -> Path | None:
    """Rename ``path`` (a unit, a lock file; when it is a link, the link itself) to
    ``<name>.corrupt-<time>`` and say so, one line: ``why``, the new name, ``then``; nothing
    is deleted. The name it got (None when another process moved it first)."""
    stamp = time.strftime('%Y%m%dT%H%M%S')
    aside = path.with_name(f"{path.name}.corrupt-{stamp}")
    n = 0
    while os.path.lexists(aside):
        n += 1
        aside = path.with_name(f"{path.name}.corrupt-{stamp}-{n}")
    try:
        os.rename(path, aside)
    except FileNotFoundError:
        return None
    say(f"{why}: set aside as {shown(aside.name)}{then}")
    return aside


def _record_digest(record: dict) -> str:
    return hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()


#: why a record without checksums is not reused: an older filmscale wrote it (its code
#: version differs, so no current hash leads to it)
OLD_RECORD = "written by an older filmscale, without checksums"


#: the largest file of a unit that is hashed, bytes. The largest real one is the impact
#: arrays of a map of MAX_MAP_POINTS = 4e6 points (continuum.contact.impact_map): 14 result
#: fields of 8 bytes, a flag byte and 7 standard deviations, about 170 bytes a point, 0.7 GB;
#: the others are kilobytes (fit.npz, done.json) to megabytes (an MD record). 2 GiB is three
#: times that; a file is hashed in 1 MiB chunks, so memory stays flat, and a larger one is
#: refused from its size (fstat) before a byte of it is read.
MAX_UNIT_FILE_BYTES = 2 * 2**30
_CHUNK = 2**20
#: the largest ``done.json`` read: records are kilobytes; the default input limit, fixed
#: (not FILMSCALE_MAX_INPUT_BYTES: a small limit set for inputs must not make every unit
#: of a store look damaged and be set aside)
MAX_RECORD_BYTES = MAX_INPUT_BYTES
#: the names a checksum list may hold: plain file names of the unit itself, no separator,
#: no ".." or leading dot, no absolute path, no control character
_PLAIN_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9._-]{0,254}")


class _Damaged(Exception):
    """A unit found damaged while it is read: the message says why, one line."""


def check_unit(path: Path) -> tuple[dict | None, str]:
    """(the record of a finished unit, "") when its record and checked files match their
    checksums; (None, "") while it is not finished; (None, why) when it is corrupted: the
    unit, or anything in it, is a symbolic link (nothing is read through one) or not of its
    kind; ``done.json`` is larger than `MAX_RECORD_BYTES`, not JSON or nested deeper than
    MAX_NESTING (`core.files.parse_json`); its checksums name anything but plain file names
    of the unit, or leave out the file a reuse reads (`_reads`); a listed file is not a
    regular file, is larger than `MAX_UNIT_FILE_BYTES`, is missing or changed."""
    try:
        folder = _open_folder(path)
    except FileNotFoundError:
        return None, ""
    except _Damaged as exc:
        return None, str(exc)
    try:
        link = _first_link(folder)
        if link is not None:
            return None, f"{shown(path / link)} is a symbolic link: the store follows no links"
        try:
            data = _read_in(folder, "done.json", path, MAX_RECORD_BYTES)
        except FileNotFoundError:
            return None, ""
        record = parse_json(data.decode("utf-8"), "unit record", path / "done.json")
        if isinstance(record, dict) and "checksums" not in record:
            return None, OLD_RECORD
        if not isinstance(record, dict):
            return None, "its record is not a JSON object"
        sums = record.pop("checksums")
        if not (isinstance(sums, dict) and isinstance(sums.get("record"), str)
                and isinstance(sums.get("files"), dict)):
            return None, "its checksums are damaged"
        if _record_digest(record) != sums["record"]:
            return None, "its record was changed"
        for name in sums["files"]:
            if not (isinstance(name, str) and _PLAIN_NAME.fullmatch(name)):
                return None, f"its checksums name {shown(name)}, not a plain file name of " \
                    "the unit"
        for name in _reads(path, folder):
            if name not in sums["files"]:
                return None, f"its checksums leave out {name}, which a reuse reads"
        for name, digest in sums["files"].items():
            if _digest_in(folder, name, path) != digest:
                return None, f"{name} is missing or changed"
    except _Damaged as exc:
        return None, str(exc)
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        # InputError of parse_json (size, syntax, nesting), UnicodeDecodeError, ...
        return None, f"its record cannot be read: {shown(exc)}"
    finally:
        os.close(folder)
    return record, ""


def _open_folder(path: Path) -> int:
    """A descriptor of the unit folder ``path``, opened without following a link;
    FileNotFoundError when it does not exist, _Damaged when it is a link or no folder."""
    try:
        return os.open(path, os.O_RDONLY | os.O_DIRECTORY | _NOFOLLOW)
    except FileNotFoundError:
        raise
    except OSError as exc:
        try:
            mode = os.lstat(path).st_mode
        except OSError:
            mode = None
        if mode is not None and stat.S_ISLNK(mode):
            try:
                target = f" to {shown(os.readlink(path))}"
            except OSError:
                target = ""
            raise _Damaged(f"{shown(path)} is a symbolic link{target}: the store follows no "
                           "links") from None
        if mode is not None and not stat.S_ISDIR(mode):
            raise _Damaged(f"{shown(path)} is not a folder") from None
        raise _Damaged(f"it cannot be read: {exc.strerror or exc}") from None


def _first_link(folder: int) -> str | None:
    """The first symbolic link anywhere in the open unit folder (its path inside), None when
    there is none. Subfolders are entered without following links."""
    pending = [""]
    while pending:
        rel = pending.pop()
        fd = os.open(rel, os.O_RDONLY | os.O_DIRECTORY | _NOFOLLOW, dir_fd=folder) \
            if rel else os.dup(folder)
        try:
            with os.scandir(fd) as entries:
                for entry in entries:
                    if entry.is_symlink():
                        return rel + entry.name
                    if entry.is_dir(follow_symlinks=False):
                        pending.append(f"{rel}{entry.name}/")
        finally:
            os.close(fd)
    return None


def _open_in(folder: int, name: str, path: Path, limit: int) -> int:
    """A descriptor of the regular file ``name`` of the open unit folder (at ``path``), not
    through a link and at most ``limit`` bytes; FileNotFoundError, or _Damaged saying why."""
    mode = os.stat(name, dir_fd=folder, follow_symlinks=False).st_mode
    if stat.S_ISLNK(mode):
        raise _Damaged(f"{shown(path / name)} is a symbolic link: the store follows no links")
    if not stat.S_ISREG(mode):      # a pipe, a device, a folder: never opened
        raise _Damaged(f"{shown(name)} is not a plain file")
    fd = os.open(name, os.O_RDONLY | _NOFOLLOW, dir_fd=folder)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise _Damaged(f"{shown(name)} is not a plain file")
        if info.st_size > limit:
            raise _Damaged(f"{shown(name)} is larger than {limit} bytes, more than any file "
                           "of a unit")
    except BaseException:
        os.close(fd)
        raise
    return fd


def _read_in(folder: int, name: str, path: Path, limit: int) -> bytes:
    """The bytes of ``name`` in the open unit folder (`_open_in`), at most ``limit``."""
    fd = _open_in(folder, name, path, limit)
    try:
        data = b""
        while len(data) <= limit and (chunk := os.read(fd, min(_CHUNK, limit + 1 - len(data)))):
            data += chunk
    finally:
        os.close(fd)
    if len(data) > limit:
        raise _Damaged(f"{shown(name)} is larger than {limit} bytes, more than any file of a "
                       "unit")
    return data


def _digest_in(folder: int, name: str, path: Path) -> str:
    """The sha256 of ``name`` in the open unit folder, read in chunks up to
    `MAX_UNIT_FILE_BYTES`; _Damaged (missing, a link, not a regular file, too large)."""
    try:
        fd = _open_in(folder, name, path, MAX_UNIT_FILE_BYTES)
    except FileNotFoundError:
        raise _Damaged(f"{shown(name)} is missing or changed") from None
    try:
        return stream_digest(fd, MAX_UNIT_FILE_BYTES, name)
    finally:
        os.close(fd)


def stream_digest(fd: int, limit: int | None = None, name: str = "") -> str:
    """The sha256 of what is left to read of the open descriptor ``fd``, read in `_CHUNK`s;
    _Damaged naming ``name`` when more than ``limit`` bytes come (None: no limit)."""
    digest, size = hashlib.sha256(), 0
    while chunk := os.read(fd, _CHUNK):
        size += len(chunk)
        if limit is not None and size > limit:      # it grew while read
            raise _Damaged(f"{shown(name)} is larger than {limit} bytes, more than any file "
                           "of a unit")
        digest.update(chunk)
    return digest.hexdigest()


def _reads(path: Path, folder: int) -> tuple[str, ...]:
    """The file of a unit that a reuse reads, by the unit's kind: its checksums must list
    it (a record that leaves it out would let a damaged one be read)."""
    kind = path.name.rsplit("-", 1)[0]
    if kind in ("calibration", "calibration-joint"):
        return ("fit.npz",)
    if kind == "impact":
        return ("impact.npz",)
    if kind == "slide":
        return ("slide.npz",)
    if kind == "particle-indent":
        return (CURVE_ARRAYS,)
    if kind == "md-amorphous":
        return ("amorphous.h5",)
    if kind == "md-indent":         # `unit_curve` reads the arrays where a unit holds them
        try:
            os.stat(CURVE_ARRAYS, dir_fd=folder, follow_symlinks=False)
            return (CURVE_ARRAYS,)
        except FileNotFoundError:
            return (MD_RECORD,)
    return ()


def done_record(path: Path) -> dict | None:
    """The record of a finished unit, None while it is not finished. A corrupted unit
    (`check_unit`) is set aside as ``<unit>.corrupt-<time>`` with one line saying why, and
    None returned: it is computed again, and nothing of it is deleted. A unit that is a
    link is set aside as such (the link is renamed; what it points to is left untouched)."""
    record, problem = check_unit(path)
    if problem:
        _set_aside(path, f"unit {shown(path.name)} is corrupted ({problem})",
                   ", computing it again")
    return record


def own_folder(path: Path, create: bool = True) -> Path:
    """``path``, a unit's folder about to be written, created when missing (with
    ``create``): InputError when it is a link or not a folder, so that nothing is written
    through a link (`done_record` sets such a unit aside first; this catches one put there
    since)."""
    if create:
        path.mkdir(parents=True, exist_ok=True)
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        if create:
            raise
        return path
    if stat.S_ISLNK(mode) or not stat.S_ISDIR(mode):
        raise InputError(f"store unit {shown(path)} is "
                         f"{'a symbolic link' if stat.S_ISLNK(mode) else 'not a folder'}: "
                         "filmscale writes nothing through links; remove it and run again")
    return path


def unit_states(store: Path) -> list[dict]:
    """Every unit of a store, read without changing it and without creating a file (a
    read-only store is read too): name, kind, state ("done", "running" while another
    process holds its lock, "incomplete" when a run stopped before its end (it resumes),
    "corrupted" with why, "set aside" for a corrupted unit already moved, "old" for a unit
    an older filmscale wrote), its wall time where recorded. Every link in the store (but
    jobs.json, which `slurm.read_jobs` refuses) is a row "corrupted": nothing is read
    through it."""
    with os.scandir(store) as it:
        entries = sorted((e.name, e.is_symlink(), e.is_dir(follow_symlinks=False))
                         for e in it)
    rows = []
    for name, link, folder in entries:
        if not (link or folder) or (link and name == "jobs.json"):
            continue
        path = Path(store) / name
        kind = name.split(".corrupt-")[0].rsplit("-", 1)[0]
        if ".corrupt-" in name:
            rows.append({"unit": name, "kind": kind, "state": "set aside"})
            continue
        record, problem = check_unit(path)
        if link and not problem:        # a link to a file: no folder, still never followed
            problem = f"{shown(path)} is a symbolic link: the store follows no links"
        state = ("corrupted" if problem else "done" if record is not None
                 else "running" if _busy(path) else "incomplete")
        if problem == OLD_RECORD:
            state = "old"
        row = {"unit": name, "kind": kind, "state": state}
        if problem:
            row["why"] = problem
        wall = record.get("wall_time") if record is not None else None
        if isinstance(wall, (int, float)) and not isinstance(wall, bool):
            row["wall_time"] = wall
        rows.append(row)
    return rows


def finish_unit(path: Path, record: dict, files=()) -> dict:
    """Mark the unit finished: ``done.json`` holds the record and the checksums of the record
    and of ``files`` (the names, in the unit, that a reuse reads): plain names, each a
    regular file of the unit folder, which must not be a link (InputError otherwise)."""
    plain = json.loads(dumps(record))
    try:
        folder = _open_folder(own_folder(path, create=False))
        try:
            for name in files:
                if not _PLAIN_NAME.fullmatch(name):
                    raise _Damaged(f"{shown(name)} is not a plain file name of the unit")
            hashed = {name: _digest_in(folder, name, path) for name in files}
        finally:
            os.close(folder)
    except _Damaged as exc:
        raise InputError(f"unit {shown(path)} cannot be finished: {exc}") from None
    sums = {"record": _record_digest(plain), "files": hashed}
    write_json(path / "done.json", {**plain, "checksums": sums}, indent=None)
    return plain


