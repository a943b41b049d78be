"""Files written atomically, and text read with one-line errors.

Every result file of the package is written through `atomic_path`: a temporary file in the
same folder, renamed over the target only when complete, so an interrupted or failed write
never leaves a half-written result and never destroys the previous one.
"""

from __future__ import annotations

import json
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .errors import InputError
from .jsonable import dumps


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path`` (same suffix) that is renamed to ``path`` when
    the block ends without error, and removed otherwise."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}",
                               dir=path.parent)
    os.close(fd)
    try:
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


def read_json(path, what: str = "JSON file"):
    """The parsed content of a JSON file; InputError naming ``what`` and the file."""
    text = read_text(path, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as err:
        raise InputError(f"{what} {path} is not valid JSON: {err.msg} at line {err.lineno}") \
            from None


def read_text(path, what: str) -> str:
    """The UTF-8 text of a file; InputError naming `what` (table, scene, ...) and the file."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except OSError as err:
        raise InputError(f"cannot read {what} {path}: {err.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{what} {path} is not UTF-8 text") from None
