"""Every command's outputs on a full disk (a 64 kB tmpfs, see tests/core/test_full_disk.py;
skipped where it cannot be mounted): `impact-map --out` (HDF5), `impact --history` (CSV) and
`--plot` (PNG), `run --out` (HDF5) and `--store` (the unit files), `report --out` (HTML)
and `--figure` (PNG). The real entry point runs in a child process; each case asserts exit
status 2, one error line that names the file the user named and "No space left on device",
no traceback, no h5py noise ("Exception ignored") and no crash, no temporary file left, and
the earlier output kept byte for byte. The disk is the `small_disk` fixture of
tests/conftest.py."""

import os
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

from filmscale.core.files import TEMP_MARK
from filmscale.workflows.cli import main
from filmscale.workflows.impact_cli import HISTORY_HEADER
from filmscale.workflows.outputs import REPORT_TITLE
from filmscale.workflows.result import IMPACT_MAP_FORMAT, RESULT_FORMAT
from tests.helpers.disk import ENOSPC, fill, temporaries
from tests.helpers.scenes import BASE, SCENE

#: a pipeline scene whose film has E and sigma_y (no MD), with a small map: its result is
#: about 70 kB
PIPELINE = BASE.format(R=10e-6, m=1.6e-6, V=0.2, t=4e-9, film="E = 200e9\nsigma_y = 8e9",
                       want='["maxima", "map"]', impactor_extra="") + """
[map]
velocity = [0.01, 1.0, 3]
radius = [1e-6, 1e-5, 3]
"""


@pytest.fixture(scope="module")
def result_file(tmp_path_factory) -> Path:
    """A scene result written by `run` (once for the module), for `report`."""
    d = tmp_path_factory.mktemp("result")
    (d / "pipe.toml").write_text(PIPELINE)
    assert main(["run", str(d / "pipe.toml"), "--store", str(d / "store"), "--out",
                 str(d / "result.h5")]) == 0
    return d / "result.h5"


@pytest.fixture
def work(tmp_path, monkeypatch) -> Path:
    """The inputs, on a disk with room: the current directory."""
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "pipe.toml").write_text(PIPELINE)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _h5(path: Path, fmt: str) -> None:
    with h5py.File(path, "w") as f:
        f.attrs["format"] = fmt


def _filmscale(*argv) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "FILMSCALE_DEBUG"}
    return subprocess.run([sys.executable, "-m", "filmscale", *map(str, argv)],
                          capture_output=True, text=True, stdin=subprocess.DEVNULL, env=env,
                          timeout=120)


def _fails_cleanly(done: subprocess.CompletedProcess, named: Path) -> str:
    """Exit 2 and, last on stderr, one error line naming ``named`` and the full disk; no
    traceback, no h5py or HDF5 text. Returns the line."""
    err = done.stderr
    assert done.returncode == 2, err[-3000:]
    for noise in ("Traceback", "Exception ignored", "h5py", "HDF5", "file write failed",
                  TEMP_MARK):
        assert noise not in err, err[-3000:]
    errors = [line for line in err.splitlines() if line.startswith("filmscale: error")]
    assert len(errors) == 1 and err.endswith(errors[0] + "\n"), err[-3000:]
    assert str(named) in errors[0] and ENOSPC in errors[0], errors[0]
    return errors[0]


def _unchanged(disk: Path, files: dict[Path, bytes]) -> None:
    for path, data in files.items():
        assert path.read_bytes() == data, path
    assert temporaries(disk) == []


@pytest.mark.parametrize("free", [0, 16384])
def test_impact_map_on_a_full_disk(work, small_disk, free):
    out = small_disk / "map.h5"
    _h5(out, IMPACT_MAP_FORMAT)             # an earlier map: replaced without --force
    old = out.read_bytes()
    fill(small_disk, free)
    _fails_cleanly(_filmscale("impact-map", "scene.toml", "--out", out), out)
    _unchanged(small_disk, {out: old})


def test_impact_history_on_a_full_disk(work, small_disk):
    out = small_disk / "history.csv"
    out.write_text(HISTORY_HEADER + "\n0,0,0,0,0,0,1,0\n")
    old = out.read_bytes()
    fill(small_disk, 16384)                 # the history is about 160 kB
    _fails_cleanly(_filmscale("impact", "scene.toml", "--history", out), out)
    _unchanged(small_disk, {out: old})


def test_impact_plot_on_a_full_disk(work, small_disk):
    out = small_disk / "history.png"
    out.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(64))
    old = out.read_bytes()
    fill(small_disk, 16384)
    _fails_cleanly(_filmscale("impact", "scene.toml", "--plot", out), out)
    _unchanged(small_disk, {out: old})


def test_run_out_on_a_full_disk(work, small_disk):
    out = small_disk / "result.h5"
    _h5(out, RESULT_FORMAT)
    old = out.read_bytes()
    fill(small_disk, 16384)
    _fails_cleanly(_filmscale("run", "pipe.toml", "--store", work / "store", "--out", out), out)
    _unchanged(small_disk, {out: old})


def test_run_store_on_a_full_disk_then_with_room(work, small_disk):
    """A unit that cannot be written is not marked done: with room again, it runs."""
    store = small_disk / "store"
    fill(small_disk, 0)
    line = _fails_cleanly(_filmscale("run", "pipe.toml", "--store", store, "--out",
                                     "result.h5"), store)
    assert line.split(": ")[-2].startswith(str(store) + os.sep), line     # a file in it
    assert temporaries(small_disk) == [] and not (work / "result.h5").exists()
    assert not list(store.rglob("done.json"))
    (small_disk / "filler").unlink()
    done = _filmscale("run", "pipe.toml", "--store", store, "--out", "result.h5")
    assert done.returncode == 0 and "1 unit(s) ran" in done.stderr, done.stderr[-3000:]


def test_report_on_a_full_disk(work, small_disk, result_file):
    out = small_disk / "report.html"
    out.write_text(f"<html><head>{REPORT_TITLE}</head></html>\n")
    old = out.read_bytes()
    fill(small_disk, 16384)                 # a report is about 130 kB
    _fails_cleanly(_filmscale("report", result_file, "--out", out), out)
    _unchanged(small_disk, {out: old})


def test_report_figure_on_a_full_disk(work, small_disk, result_file):
    out = small_disk / "figure.png"
    out.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(64))
    old = out.read_bytes()
    fill(small_disk, 16384)                 # the figure is about 100 kB
    _fails_cleanly(_filmscale("report", result_file, "--out", work / "report.html",
                              "--figure", out), out)
    _unchanged(small_disk, {out: old})
