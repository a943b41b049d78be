"""Writes onto a full disk fail cleanly: the library's writers (`atomic_path`, `atomic_h5`,
`write_json`) raise one OSError whose ``filename`` is the file the caller named (not the
temporary one) with the system's reason, remove their temporary file and keep the previous
file byte for byte; h5py prints nothing and does not crash, whatever its deallocators meet.

The full disk is a 64 kB tmpfs mounted in the test, so these tests need root (or
CAP_SYS_ADMIN); they are skipped, with the reason, where mounting is impossible or when
FILMSCALE_NO_MOUNT is set: the `small_disk` fixture (tests/conftest.py) over
`mounted_disk` and `fill` of tests/helpers/disk.py, which serve
tests/workflows/test_full_disk_cli.py too."""

import errno
import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.core.files import TEMP_MARK, atomic_h5, atomic_path, write_json
from tests.helpers.disk import ENOSPC, fill, temporaries


def _check_write_error(err: OSError, target: Path) -> None:
    assert err.errno == errno.ENOSPC and err.strerror == ENOSPC
    assert err.filename == str(target)          # the file named, not the temporary one
    assert str(target) in str(err) and ENOSPC in str(err) and "\n" not in str(err)
    assert TEMP_MARK not in str(err)


@pytest.mark.parametrize("free", [0, 16384])
def test_write_json_on_a_full_disk_keeps_the_old_file(small_disk, free):
    target = small_disk / "index.json"
    write_json(target, {"old": True})
    old = target.read_bytes()
    fill(small_disk, free)
    with pytest.raises(OSError) as caught:
        write_json(target, {"values": list(range(20000))})     # about 140 kB
    _check_write_error(caught.value, target)
    assert target.read_bytes() == old and temporaries(small_disk) == []


def test_atomic_path_names_the_target_of_a_failed_write(small_disk):
    target = small_disk / "table.csv"
    fill(small_disk, 0)
    with pytest.raises(OSError) as caught:
        with atomic_path(target) as tmp:
            np.savetxt(tmp, np.zeros((2000, 4)))
    _check_write_error(caught.value, target)
    assert not target.exists() and temporaries(small_disk) == []


def test_a_read_error_inside_a_write_keeps_its_own_file_name(tmp_path):
    """Only the errors of the write are the target's: a file the block reads keeps its name."""
    missing = tmp_path / "missing.txt"
    with pytest.raises(FileNotFoundError) as caught:
        with atomic_path(tmp_path / "out.txt") as tmp:
            Path(tmp).write_text(missing.read_text())
    assert caught.value.filename == str(missing)
    assert not (tmp_path / "out.txt").exists() and temporaries(tmp_path) == []


#: writes 60 kB of datasets and attributes through atomic_h5 to argv[1]; prints the error
H5_SCRIPT = """
import sys
import numpy as np
from filmscale.core.files import atomic_h5
try:
    with atomic_h5(sys.argv[1]) as f:
        f.attrs["format"] = "test/1"
        for i in range(25):
            g = f.create_group(f"g{i}")
            g.create_dataset("a", data=np.arange(300.0) + i).attrs["units"] = "m"
            g.attrs["model"] = "x" * 200
except OSError as err:
    print(err.errno, err.filename, err.strerror, sep="|")
    sys.exit(3)
"""


@pytest.mark.parametrize("free", [0, 16384])
def test_atomic_h5_on_a_full_disk_is_quiet_and_keeps_the_old_file(small_disk, free):
    """A child process, as a crash in h5py's deallocators would end this one: it must end by
    the error alone, nothing on stderr (no "Exception ignored", no segmentation fault)."""
    target = small_disk / "map.h5"
    with h5py.File(target, "w") as f:
        f.attrs["format"] = "old"
    old = target.read_bytes()
    fill(small_disk, free)
    done = subprocess.run([sys.executable, "-c", H5_SCRIPT, str(target)], capture_output=True,
                          text=True, stdin=subprocess.DEVNULL, timeout=60)
    assert (done.returncode, done.stderr) == (3, "")
    assert done.stdout == f"{errno.ENOSPC}|{target}|{ENOSPC}\n"
    assert target.read_bytes() == old and temporaries(small_disk) == []


def test_atomic_h5_writes_the_same_bytes_as_h5py_on_disk(tmp_path):
    """atomic_h5 builds the file in memory and writes its image: the very file h5py would
    have written in place."""
    def content(f):
        f.attrs["format"] = "test/1"
        f.attrs["meta"] = json.dumps({"a": 1})
        g = f.create_group("map")
        g.create_dataset("x", data=np.linspace(0, 1, 1000)).attrs["units"] = "m"
        g.create_dataset("text", data="scene text")
    with atomic_h5(tmp_path / "a.h5") as f:
        content(f)
    with h5py.File(tmp_path / "b.h5", "w") as f:
        content(f)
    assert (tmp_path / "a.h5").read_bytes() == (tmp_path / "b.h5").read_bytes()
    with h5py.File(tmp_path / "a.h5", "r") as f:
        assert f["map/x"][-1] == 1.0 and f["map/x"].attrs["units"] == "m"


def test_atomic_h5_keeps_the_old_file_when_the_block_fails(tmp_path):
    target = tmp_path / "r.h5"
    target.write_bytes(b"old")
    with pytest.raises(KeyError):
        with atomic_h5(target) as f:
            f.attrs["format"] = "new"
            raise KeyError("stop")
    assert target.read_bytes() == b"old" and temporaries(tmp_path) == []
