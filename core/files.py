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
import tempfile
import tomllib
from contextlib import contextmanager
from pathlib import Path

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


@contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path`` (same suffix) that is renamed to ``path`` when
    the block ends without error, and removed otherwise (an exception, Ctrl-C, or SIGTERM,
    which the command line turns into KeyboardInterrupt). Temporary files that killed
    processes left in the folder are removed first (`remove_stale_temporaries`)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(path.parent)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:80]}{TEMP_MARK}{_host()}.{os.getpid()}.",
                               suffix=path.suffix, dir=path.parent)
    try:
        os.close(fd)
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())    # mkstemp makes 0600; results are meant to be shared
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


@contextmanager
def atomic_h5(path):
    """Yield an open h5py File that appears at ``path`` only once fully written."""
    import h5py
    with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
        yield f


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


def read_text(path, what: str, limit: int | None = None) -> str:
    """The UTF-8 text of a user's input file, line ends made \\n; InputError naming ``what``
    (table, scene, ...) and the file when it cannot be read, is larger than ``limit`` bytes
    (default `input_limit`) or is not text (NUL bytes, not UTF-8). At most limit + 1 bytes
    are read, so that endless files (/dev/zero, a pipe) end too."""
    limit = input_limit() if limit is None else limit
    try:
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except FileNotFoundError:
        raise InputError(f"cannot read {what} {shown(path)}: it does not exist") from None
    except OSError as err:
        raise InputError(f"cannot read {what} {shown(path)}: {err.strerror or err}") from None
    except ValueError:          # a NUL character in the name
        raise InputError(f"cannot read {what} {shown(path)}: its name holds a NUL "
                         "character") from None
    if len(data) > limit:
        raise InputError(f"{what} {shown(path)} is larger than {limit} bytes, the input size "
                         f"limit (set {MAX_INPUT_BYTES_ENV} to read it)")
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
