"""A full disk for the tests: a 64 kB tmpfs mounted under a test's folder (the tests skip,
with the reason, where mounting is impossible or FILMSCALE_NO_MOUNT is set), filled to a
chosen number of free bytes, and the temporary files a failed write may leave."""

import errno
import os
import shutil
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path

import pytest

from filmscale.core.files import TEMP_MARK

#: set (to anything) to skip the tests that mount a small file system
NO_MOUNT_ENV = "FILMSCALE_NO_MOUNT"
#: the size of the mounted file system
DISK_SIZE = "64k"
ENOSPC = os.strerror(errno.ENOSPC)          # "No space left on device"


def _mount_refused() -> str | None:
    if os.environ.get(NO_MOUNT_ENV):
        return f"{NO_MOUNT_ENV} is set"
    if not sys.platform.startswith("linux"):
        return "a tmpfs mount needs Linux"
    if os.geteuid() != 0:
        return "mounting a small tmpfs needs root"
    if not (shutil.which("mount") and shutil.which("umount")):
        return "no mount or umount command"
    return None


@contextmanager
def mounted_disk(folder: Path):
    """An empty 64 kB tmpfs at ``folder``/disk, unmounted afterwards; skips the test where
    mounting is impossible."""
    refused = _mount_refused()
    if refused:
        pytest.skip(refused)
    disk = folder / "disk"
    disk.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={DISK_SIZE},mode=0755",
                           "tmpfs", str(disk)], capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs: {(done.stderr or done.stdout).strip()}")
    try:
        yield disk
    finally:
        if subprocess.run(["umount", str(disk)], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", str(disk)], capture_output=True)


def fill(disk: Path, free: int) -> None:
    """Fill ``disk`` with a filler file so that ``free`` bytes (a multiple of 4096) stay free;
    0: none at all."""
    st = os.statvfs(disk)
    fd = os.open(disk / "filler", os.O_WRONLY | os.O_CREAT | os.O_APPEND)
    try:
        todo = st.f_bavail * st.f_frsize - free
        while todo > 0:
            todo -= os.write(fd, bytes(min(todo, 1 << 16)))
        if free == 0:
            try:
                while True:
                    os.write(fd, bytes(4096))
            except OSError as err:
                assert err.errno == errno.ENOSPC
    finally:
        os.close(fd)
    st = os.statvfs(disk)
    assert st.f_bavail * st.f_frsize == free


def temporaries(folder: Path) -> list[Path]:
    """The temporary files of `atomic_path` anywhere under ``folder``."""
    return [p for p in folder.rglob("*") if TEMP_MARK in p.name]
