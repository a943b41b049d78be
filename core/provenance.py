"""The one provenance builder: what produced a result, as flat text attributes."""

from __future__ import annotations

import platform
import subprocess
import sys
from datetime import datetime, timezone
from functools import lru_cache
from importlib import metadata
from pathlib import Path

from filmscale import __version__


def _version(dist: str) -> str:
    # a module already imported knows its version; the package metadata is a file search
    module = sys.modules.get(dist)
    if isinstance(getattr(module, "__version__", None), str):
        return module.__version__
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


@lru_cache(maxsize=1)
def source_revision() -> str:
    """The git commit of the filmscale source in use, "-dirty" if it has uncommitted changes;
    "not a git checkout" for an installed wheel."""
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"],
                              capture_output=True, text=True, timeout=10)
        if head.returncode != 0:
            return "not a git checkout"
        status = subprocess.run(["git", "-C", str(root), "status", "--porcelain",
                                 "--untracked-files=no"], capture_output=True, text=True,
                                timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    return head.stdout.strip() + ("-dirty" if status.stdout.strip() else "")


def provenance(**extra) -> dict[str, str]:
    """Flat string attributes for a result file: filmscale's version and source revision,
    Python, numpy, scipy, h5py, the platform and the UTC time, plus ``extra`` (the command
    line, the scene, LAMMPS's version and packages, potential checksums, seeds, ...)."""
    info = {
        "filmscale_version": __version__,
        "source_revision": source_revision(),
        "python": sys.version.split()[0],
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "h5py": _version("h5py"),
        "platform": platform.platform(),
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    info.update({k: str(v) for k, v in extra.items()})
    return info
