"""`filmscale run` killed with SIGKILL at random moments (issue 31): after each kill the same
command, rerun in the same store and onto the same output, completes with the result of a run
that was never killed, and no temporary file is left anywhere under the work folder (a killed
process cannot remove its own; the next write into each folder does). Oracle: the same scene
run alone in a store of its own. The kill moments are drawn from a seeded generator over the
lone run's wall time, so the kills land in Python's start-up, the calibration unit, the
impact unit and the result's write; the first waits until a unit has started, so that at least
one kill cuts work short however loaded the machine is."""

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

from filmscale.core.files import TEMP_MARK
from tests.helpers.scenes import BASE

SEED, KILLS = 31, 10
FILM = '[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"'
SCENE = BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="", film=FILM,
                    want='["maxima", "map"]') + \
    "[map]\nvelocity = [0.1, 10.0, 20]\nradius = [1e-7, 1e-5, 20]\n"


def _command(store: str, out: str) -> list[str]:
    return [sys.executable, "-m", "filmscale", "run", "scene.toml", "--store", store,
            "--out", out]


def _result(path: Path) -> dict:
    """What a scene result says, without its provenance: the calibrated layer's parameters
    and every impact dataset."""
    out = {}
    with h5py.File(path, "r") as f:
        cal = json.loads(f["calibration/0"].attrs["calibration"])
        out["calibration"] = {k: cal[k]["value"] for k in ("E", "sigma_y")}

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
        f["impact"].visititems(visit)
    return out


def _same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(
        np.array_equal(np.asarray(a[k]), np.asarray(b[k]), equal_nan=True)
        if not isinstance(a[k], dict) else a[k] == b[k] for k in a)


def _temporaries(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if TEMP_MARK in p.name]


def _unfinished_units(store: Path) -> list[str]:
    return [p.name for p in store.glob("*-*") if p.is_dir()
            and not (p / "done.json").exists()] if store.exists() else []


def _kill_inside_a_unit(proc: subprocess.Popen, store: Path, limit: float) -> None:
    """Kill ``proc`` as soon as a unit of ``store`` has started and not finished: on a loaded
    machine every seeded moment can land in Python's start-up, and this kill still cuts a unit
    short (or, should the process finish first, kills nothing)."""
    end = time.monotonic() + limit
    while (time.monotonic() < end and proc.poll() is None
           and not (_unfinished_units(store) or (store.exists() and _temporaries(store)))):
        time.sleep(0.005)


def test_sigkill_at_random_moments_then_rerun_gives_the_lone_run_result(tmp_path, film_csv):
    (tmp_path / "scene.toml").write_text(SCENE)
    start = time.monotonic()
    lone = subprocess.run(_command("lone-store", "lone.h5"), cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    wall = time.monotonic() - start
    assert lone.returncode == 0, lone.stderr
    reference = _result(tmp_path / "lone.h5")
    rng = np.random.default_rng(SEED)
    left_behind = 0         # kills that left a temporary file or an unfinished unit
    for k, moment in enumerate(rng.uniform(0.05, 0.95, KILLS) * wall):
        # a fresh store and output half of the time, the store of the earlier kills the rest:
        # both a first run and a run over a killed one's leftovers are cut short
        store, out = ("store", "r.h5") if k % 2 else (f"store-{k}", f"r-{k}.h5")
        proc = subprocess.Popen(_command(store, out), cwd=tmp_path, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        if k == 0:
            _kill_inside_a_unit(proc, tmp_path / store, 3 * wall + 30)
        else:
            time.sleep(moment)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        cut = _unfinished_units(tmp_path / store)
        left_behind += bool(_temporaries(tmp_path) or cut)
        rerun = subprocess.run(_command(store, out), cwd=tmp_path, capture_output=True,
                               text=True, timeout=300)
        assert rerun.returncode == 0, f"kill {k} at {moment:.2f} s: {rerun.stderr}"
        assert "Traceback" not in rerun.stderr
        assert _same(_result(tmp_path / out), reference), f"kill {k} at {moment:.2f} s"
        assert _temporaries(tmp_path) == [], f"kill {k} at {moment:.2f} s"
    # the test can fail: some kills did cut a write or a unit short
    assert left_behind >= 1
