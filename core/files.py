"""Files written atomically, and text read with one-line errors.

Every result file of the package is written through `atomic_path`: a temporary file in the
same folder, renamed over the target only when complete, so an interrupted or failed write
never leaves a half-written result and never destroys the previous one. The temporary file
is removed when the write fails or is interrupted; one that a killed process left (SIGKILL)
is removed by the next write in its folder.
"""

from __future__ import annotations

import json
import os
import re
import socket
import stat
import tempfile
import tomllib
from contextlib import contextmanager
from pathlib import Path

from .checks import check_path
from .errors import InputError
from .jsonable import dumps


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: in the name of every temporary file, followed by the host and the process id:
#: ``.<name>.filmscale-tmp-<host>.<pid>.<random><suffix>``, so that a later write can tell
#: the leftovers of a killed process from the files of a live one
TEMP_MARK = ".filmscale-tmp-"


def _host() -> str:
    return re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:         # another user's process
        return True
    return True


def remove_stale_temporaries(folder) -> list[Path]:
    """Remove the temporary files of `atomic_path` that a process of this host left in
    ``folder`` when it was killed (SIGKILL, a node's power); those of live processes and of
    other hosts (a shared file system) stay. Returns the files removed."""
    mark = f"{TEMP_MARK}{_host()}."
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if not entry.name.startswith(".") or mark not in entry.name:
            continue
        pid = entry.name.split(mark, 1)[1].split(".", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            try:
                os.unlink(entry.path)
            except OSError:         # removed by another process meanwhile, or not ours to remove
                continue
            removed.append(Path(entry.path))
    return removed


def _write_error(err: OSError, named) -> OSError:
    """``err`` (an OSError of writing) as the error of the file the caller named: the same
    errno and the system's reason, ``filename`` the named file (not the temporary one)."""
    return OSError(err.errno, err.strerror or str(err), os.fspath(named))


def _of_file(err: OSError, tmp: str) -> bool:
    """Whether ``err`` is an error of writing ``tmp``: it has an errno, and no file name
    (a write or flush of an open file) or the name ``tmp``."""
    name = err.filename
    if isinstance(name, (os.PathLike, bytes)):
        name = os.fsdecode(name)
    return err.errno is not None and name in (None, tmp)


@contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path`` (same suffix) that is renamed to ``path`` when
    the block ends without error, and removed otherwise (an exception, Ctrl-C, or SIGTERM,
    which the command line turns into KeyboardInterrupt). Temporary files that killed
    processes left in the folder are removed first (`remove_stale_temporaries`).

    A failed write (a full disk, a quota, a read-only or vanished folder) raises one OSError
    whose ``filename`` is ``path`` as named, never the temporary file, with the system's
    errno and reason (``OSError(ENOSPC, "No space left on device", path)``; the command line
    prints it on one line, exit status 2). That covers creating the temporary file, renaming
    it, and the errors of the block that concern the temporary file (an errno, and no file
    name or the temporary one); an OSError of another file the block reads is raised as it
    is. The previous ``path`` is kept intact in every case."""
    named = path
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temporaries(path.parent)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:80]}{TEMP_MARK}{_host()}."
                                   f"{os.getpid()}.", suffix=path.suffix, dir=path.parent)
    except OSError as err:
        raise _write_error(err, named) from err
    try:
        try:
            os.close(fd)
            yield tmp
        except OSError as err:
            if not _of_file(err, tmp):
                raise           # not the write's: a file the block reads, h5py's own errors
            raise _write_error(err, named) from err
        try:
            os.chmod(tmp, 0o666 & ~_umask())   # mkstemp makes 0600; results are to be shared
            os.replace(tmp, path)
        except OSError as err:
            raise _write_error(err, named) from err
    finally:
        if os.path.lexists(tmp):
            try:
                os.unlink(tmp)
            except OSError:     # e.g. the folder went away; a later write removes it
                pass


@contextmanager
def atomic_h5(path):
    """Yield an open h5py File that appears at ``path`` only once fully written.

    The file is built in memory (HDF5's ``core`` driver without backing store) and its image
    written to the temporary file of `atomic_path` with plain writes, so the HDF5 library
    never writes to disk: a full disk or a quota is one OSError naming ``path``
    (`atomic_path`), and never an HDF5 write failure, which h5py cannot recover from (its
    deallocators then print "Exception ignored ..." for every object and may crash the
    interpreter). The image is byte for byte the file h5py writes in place; memory use is
    about twice the file, and filmscale's HDF5 results are kilobytes to a few megabytes (two
    200 x 200 maps of 25 fields each make 16 MB)."""
    import h5py
    with atomic_path(path) as tmp:
        f = h5py.File(tmp, "w", driver="core", backing_store=False)
        try:
            yield f
            f.flush()
            image = f.id.get_file_image()
        finally:
            f.close()
        with open(tmp, "wb") as out:
            out.write(image)
        del image


def write_json(path, data, *, indent: int | None = 2) -> None:
    """Write ``data`` as JSON (`filmscale.core.jsonable.dumps`: no NaN) atomically."""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(dumps(data, indent=indent))


#: the largest text input (scene, sweep, spec, site file, curve table, area file) read, in
#: bytes: real ones are kilobytes (a curve table of 10^5 rows is about 5 MB); the limit keeps
#: /dev/zero, an endless pipe or a mistaken multi-gigabyte file from filling the memory
MAX_INPUT_BYTES = 16 * 2**20
#: the environment variable that sets another limit (bytes)
MAX_INPUT_BYTES_ENV = "FILMSCALE_MAX_INPUT_BYTES"
#: the deepest nesting of tables and arrays in a TOML or JSON input: scenes need 5; deeper
#: input is hostile (it would exhaust Python's recursion where it is copied or checked)
MAX_NESTING = 32


def shown(path) -> str:
    """A file name for a one-line message: as it is, or quoted with escapes when it holds
    line breaks or other control characters."""
    text = str(path)
    return text if text.isprintable() else ascii(text)


#: the most characters of a file's content an error message quotes (`excerpt`)
MAX_EXCERPT = 60


def excerpt(value, limit: int = MAX_EXCERPT) -> str:
    """Content of a user's data file (a curve table, an instrument export, a value of a TOML
    input) as an error message may quote it: ``ascii(value)`` (a string in quotes, with no
    line break, control character or terminal escape left) cut to at most ``limit``
    characters, ``...`` marking a cut. Files that are not in a format the package reads (a
    potential file pointed at any path, a file of unknown kind) are never quoted, not even
    so."""
    text = ascii(value)
    return text if len(text) <= limit else f"{text[:limit - 3]}..."


def input_limit() -> int:
    """The size limit of text inputs, bytes: `MAX_INPUT_BYTES_ENV` or `MAX_INPUT_BYTES`."""
    raw = os.environ.get(MAX_INPUT_BYTES_ENV)
    if raw is None:
        return MAX_INPUT_BYTES
    try:
        limit = int(raw)
    except ValueError:
        limit = 0
    if limit <= 0:
        raise InputError(f"{MAX_INPUT_BYTES_ENV} = {raw!r} must be a positive whole number "
                         "of bytes")
    return limit


def _kind(mode: int) -> str:
    return ("a folder" if stat.S_ISDIR(mode) else "a named pipe (FIFO)" if stat.S_ISFIFO(mode)
            else "a character device" if stat.S_ISCHR(mode)
            else "a block device" if stat.S_ISBLK(mode)
            else "a socket" if stat.S_ISSOCK(mode) else "of another kind")


def _not_regular(what: str, path, mode: int) -> InputError:
    return InputError(f"cannot read {what} {shown(path)}: it is {_kind(mode)}, not a regular "
                      "file")


def _unreadable(what: str, path, err: BaseException) -> InputError:
    if isinstance(err, FileNotFoundError):
        return InputError(f"cannot read {what} {shown(path)}: it does not exist")
    if isinstance(err, ValueError):             # a NUL character in the name
        return InputError(f"cannot read {what} {shown(path)}: its name holds a NUL character")
    return InputError(f"cannot read {what} {shown(path)}: "
                      f"{getattr(err, 'strerror', None) or err}")


def check_regular_file(path, what: str) -> os.stat_result:
    """The `os.stat` of ``path`` when it is a regular file (a symbolic link to one is);
    else InputError, one line naming ``what`` and the file: it does not exist, cannot be
    reached, or is a folder, a named pipe, a device or a socket. Call it before opening a
    user's input: opening a FIFO for reading waits for a writer for ever, a device may never
    end (/dev/zero) or act when opened, and a folder reads as an error of the library that
    opens it."""
    path = check_path(what, path)       # not None, a number (a file descriptor) or bytes
    try:
        info = os.stat(path)
    except (OSError, ValueError) as err:
        raise _unreadable(what, path, err) from None
    if not stat.S_ISREG(info.st_mode):
        raise _not_regular(what, path, info.st_mode)
    return info


def open_regular(path, what: str):
    """A user's input file opened for binary reading, after `check_regular_file`: opened
    with O_NONBLOCK and checked again with fstat on the open descriptor, so a name replaced
    by a pipe or a device after the check is refused, not waited on (on a regular file
    O_NONBLOCK changes nothing). InputError as `check_regular_file`."""
    return _open_regular(path, what)[0]


def _open_regular(path, what: str):
    """`open_regular`'s file and the fstat of its open descriptor (its size, read once)."""
    check_regular_file(path, what)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)
                     | getattr(os, "O_NOCTTY", 0))
    except (OSError, ValueError) as err:
        raise _unreadable(what, path, err) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise _not_regular(what, path, info.st_mode)
        return os.fdopen(fd, "rb"), info
    except BaseException:
        os.close(fd)
        raise


def read_bytes(path, what: str, limit: int | None = None) -> bytes:
    """The bytes of a user's input file through `open_regular` (a regular file, never a
    pipe or device), at most ``limit`` bytes (default `input_limit`): InputError naming
    ``what`` and the file when it is larger (refused from its size before reading, and at
    limit + 1 bytes should it grow)."""
    limit = input_limit() if limit is None else limit
    f, info = _open_regular(path, what)
    with f:
        if info.st_size > limit:
            raise _too_large(what, path, limit)
        try:
            data = f.read(limit + 1)
        except OSError as err:
            raise _unreadable(what, path, err) from None
    if len(data) > limit:
        raise _too_large(what, path, limit)
    return data


def _too_large(what: str, path, limit: int) -> InputError:
    return InputError(f"{what} {shown(path)} is larger than {limit} bytes, the input size "
                      f"limit (set {MAX_INPUT_BYTES_ENV} to read it)")


def read_text(path, what: str, limit: int | None = None) -> str:
    """The UTF-8 text of a user's input file, line ends made \\n; InputError naming ``what``
    (table, scene, ...) and the file when it cannot be read, is not a regular file (a
    folder, a named pipe, a device: `check_regular_file`, checked before it is opened), is
    larger than ``limit`` bytes (default `input_limit`) or is not text (NUL bytes, not
    UTF-8). At most limit + 1 bytes are read (`read_bytes`)."""
    data = read_bytes(path, what, limit)
    if b"\0" in data:
        raise InputError(f"{what} {shown(path)} is not a text file (binary?): it holds NUL "
                         "bytes")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{what} {shown(path)} is not a text file (binary?): it is not UTF-8 "
                         "text") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def check_nesting(data, what: str, source, limit: int = MAX_NESTING):
    """``data`` (parsed TOML or JSON) when its tables and arrays nest at most ``limit`` deep;
    else InputError. Walks without recursion, so any depth is measured."""
    stack = [(data, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > limit:
            raise _nesting_error(what, source, limit)
        children = node.values() if isinstance(node, dict) else \
            node if isinstance(node, list) else ()
        stack.extend((child, depth + 1) for child in children
                     if isinstance(child, (dict, list)))
    return data


def _nesting_error(what: str, source, limit: int = MAX_NESTING) -> InputError:
    return InputError(f"{what} {shown(source)} nests tables and arrays more than {limit} "
                      "deep")


def parse_toml(text: str, what: str, source) -> dict:
    """TOML text parsed and its nesting checked (`check_nesting`); InputError naming
    ``what`` and ``source`` (the file) for invalid or too deeply nested TOML."""
    try:
        data = tomllib.loads(text)
    except RecursionError:
        raise _nesting_error(what, source) from None
    except ValueError as err:    # TOMLDecodeError; an integer of over 4300 digits
        raise InputError(f"{what} {shown(source)} is not valid TOML: {err}") from None
    return check_nesting(data, what, source)


def read_toml(path, what: str) -> dict:
    """A TOML input file through `read_text` (size, text) and `parse_toml` (syntax,
    nesting)."""
    return parse_toml(read_text(path, what), what, path)


def parse_json(text: str, what: str, source):
    """JSON text parsed and its nesting checked (`check_nesting`); InputError naming
    ``what`` and ``source`` for invalid or too deeply nested JSON."""
    try:
        data = json.loads(text)
    except RecursionError:
        raise _nesting_error(what, source) from None
    except json.JSONDecodeError as err:
        raise InputError(f"{what} {shown(source)} is not valid JSON: {err.msg} at line "
                         f"{err.lineno}") from None
    except ValueError as err:    # an integer of over 4300 digits
        raise InputError(f"{what} {shown(source)} is not valid JSON: {err}") from None
    return check_nesting(data, what, source)


def read_json(path, what: str = "JSON file"):
    """The parsed content of a JSON input file through `read_text` (size, text) and
    `parse_json` (syntax, nesting); InputError naming ``what`` and the file."""
    return parse_json(read_text(path, what), what, path)
