"""A sweep submitted to a real SLURM (a single-node one: tools/slurm-local.sh start, which
.ci/run calls; skipped where no SLURM answers). Two scenes share one MD ci unit (np = 2): the
unit is one array job, the scenes a second one after it. Oracles: the same sweep run locally
(bit-identical results, the MD being deterministic at a fixed rank count), and the restart
files of a task killed and requeued mid-run (it resumes, and the sweep still completes)."""

import json
import shutil
import subprocess
import sys
import time

import h5py
import pytest

from tests.helpers.scenes import BASE


def _slurm_up() -> bool:
    if shutil.which("sinfo") is None:
        return False
    out = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True)
    return out.returncode == 0 and any(s in out.stdout for s in ("idle", "mix", "alloc"))


pytestmark = pytest.mark.skipif(not _slurm_up(), reason="no SLURM answers here (start one "
                                "with tools/slurm-local.sh start)")


def _sweep(tmp_path):
    (tmp_path / "base.toml").write_text(BASE.format(
        R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
        film='[target.layers.calibrate]\nmd = "ci"\nnp = 2', want='["maxima"]'))
    path = tmp_path / "sweep.toml"
    path.write_text('base = "base.toml"\n[axes]\n"impactor.velocity" = [0.5, 2.0]\n')
    return path


def _filmscale(*args, check=True):
    done = subprocess.run([sys.executable, "-m", "filmscale", *args], capture_output=True,
                          text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done


def _wait(job_ids, timeout=600):
    deadline = time.time() + timeout
    while time.time() < deadline:
        out = subprocess.run(["squeue", "-h", "-o", "%i"], capture_output=True,
                             text=True).stdout
        if not any(j.split("_")[0] in out for j in job_ids):
            return
        time.sleep(1)
    raise AssertionError(f"SLURM jobs {job_ids} still queued after {timeout} s")


def _maxima(path):
    with h5py.File(path, "r") as f:
        return (f["calibration/0"].attrs["E"], f["impact/point/delta_max"][()])


def test_a_submitted_sweep_equals_the_local_run(tmp_path):
    sweep, store, out = _sweep(tmp_path), tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale("sweep", "submit", str(sweep), "--store", str(store),
                                 "--out-dir", str(out)).stdout)
    assert len(jobs["units"]) == 1 and len(jobs["scenes"]) == 2    # the MD unit is shared
    _wait([*jobs["units"].values(), *jobs["scenes"].values()])
    status = json.loads(_filmscale("status", str(store), "--json").stdout)
    assert {r["state"] for r in status} == {"done"}
    assert [r["job"] for r in status if r["kind"] == "md-indent"] == list(jobs["units"].values())
    _filmscale("sweep", "run", str(sweep), "--store", str(tmp_path / "local"), "--out-dir",
               str(tmp_path / "local_out"), "--jobs", "1")
    for name in jobs["scenes"]:
        assert _maxima(out / f"{name}.h5") == _maxima(tmp_path / "local_out" / f"{name}.h5")


def test_a_task_killed_mid_run_is_requeued_and_resumes(tmp_path):
    """scontrol requeue while the MD task runs (after its first restart file): SLURM kills
    the task and starts it again; the unit resumes from the restart file (two parts in its
    run state) and the scenes finish."""
    sweep, store, out = _sweep(tmp_path), tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale("sweep", "submit", str(sweep), "--store", str(store),
                                 "--out-dir", str(out)).stdout)
    (unit, job), = jobs["units"].items()
    deadline = time.time() + 300
    while not list((store / unit).glob("restart.*.bin")):
        assert time.time() < deadline, "the MD task wrote no restart file"
        time.sleep(0.2)
    subprocess.run(["scontrol", "requeue", job], check=True)
    # a requeued job waits about two minutes before it may start again; no need here
    subprocess.run(["scontrol", "update", f"JobId={job}", "StartTime=now"], check=False)
    _wait([job, *jobs["scenes"].values()])
    state = json.loads((store / unit / "state.json").read_text())
    assert len(state["parts"]) >= 2, state["parts"]
    for name in jobs["scenes"]:
        assert (out / f"{name}.h5").exists()
    assert _filmscale("cancel", str(store)).returncode == 0


@pytest.mark.slow
def test_a_task_at_its_time_limit_requeues_itself_and_resumes(tmp_path):
    """A quick-preset MD unit (about 2 min 15 s at np = 2 here) under a 4 min limit: SLURM
    warns the task 2 min ahead (up to a minute earlier still), the task requeues itself, and
    the requeued task resumes from the last restart file. Nobody intervenes: SLURM's own hold
    on a requeued job is part of the wall time (5 min 24 s in all here)."""
    (tmp_path / "base.toml").write_text(BASE.format(
        R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
        film='[target.layers.calibrate]\nmd = "quick"\nnp = 2', want='["maxima"]'))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('base = "base.toml"\n')
    store, out = tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale("sweep", "submit", str(sweep), "--store", str(store),
                                 "--out-dir", str(out), "--time", "4").stdout)
    (unit, job), = jobs["units"].items()
    _wait([job, *jobs["scenes"].values()], timeout=1500)
    log = (out / "slurm" / f"unit_{job.split('_')[1]}.log").read_text()
    assert "time limit near: requeueing this task" in log, log
    state = json.loads((store / unit / "state.json").read_text())
    assert len(state["parts"]) >= 2, state["parts"]
    status = json.loads(_filmscale("status", str(store), "--json").stdout)
    assert {r["state"] for r in status} == {"done"}, status
    assert (out / "base.h5").exists() or list(out.glob("*.h5"))
