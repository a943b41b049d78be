"""Provenance of results: versions, platform, time and what was asked."""

from __future__ import annotations

import platform
import sys
from datetime import datetime, timezone
from importlib import metadata


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def provenance(**extra) -> dict[str, str]:
    """Flat string attributes for a result file: package versions, Python, platform, UTC time,
    plus ``extra`` (the command line, the scene source, ...). LAMMPS is recorded by the runs
    that use it."""
    info = {
        "filmscale_version": _version("filmscale"),
        "python": sys.version.split()[0],
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "h5py": _version("h5py"),
        "platform": platform.platform(),
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }
    info.update({k: str(v) for k, v in extra.items()})
    return info
