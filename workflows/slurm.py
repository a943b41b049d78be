"""A sweep as SLURM jobs: its run units (MD and particle indentations, deduplicated over the
scenes) as one array job, then its scenes (calibrations and impacts, which reuse the run units)
as a second array job that starts after every run-unit task succeeded (``afterok``). SLURM
is driven through its own commands (``sbatch --parsable``, ``squeue``, ``scancel``): four
stable command lines need no adapter library. The job ids go to ``STORE/jobs.json``, which
`filmscale status` and `filmscale cancel` read.

Each task is a ``filmscale`` command on the shared store (``sweep run-unit`` or
``sweep run --only``): the store's locks make a task that finds its unit done, running or
requeued safe, and an MD unit killed mid-run resumes from its last restart file when SLURM
requeues it (``--requeue``). A run-unit task also requeues itself before its time limit: SLURM
sends its batch shell ``USR1`` `REQUEUE_LEAD_S` ahead (``--signal=B:USR1@...``) and the shell
answers with ``scontrol requeue`` of its own task, at most `MAX_REQUEUES` times.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

from filmscale.core.errors import EngineError, InputError
from filmscale.core.files import read_json, shown, write_json
from filmscale.workflows.plan import md_cost_s
from filmscale.workflows.sweep import SweepScene
from filmscale.workflows.store import check_unit
from filmscale.workflows.units import run_unit_path

#: a task's wall-time limit: the planner's cost estimate times this, plus `TIME_FLOOR_S`
TIME_MARGIN, TIME_FLOOR_S = 3.0, 600.0
#: seconds before its time limit that a run-unit task requeues itself (SLURM's signal may come
#: up to a minute earlier than asked); the requeues of one task are capped so that a unit that
#: makes no progress between two restart files does not loop
REQUEUE_LEAD_S, MAX_REQUEUES = 120, 20


def run_units(scenes: list[SweepScene], store: Path) -> list[tuple[int, int, int, Path]]:
    """The sweep's distinct run units, in a fixed order: (scene, source, member, path)."""
    seen, units = set(), []
    for i, s in enumerate(scenes):
        for j, src in enumerate(s.scene.calibrations):
            if src.kind == "curves":
                continue
            for k, spec in enumerate(src.member_specs(s.scene.base)):
                path = run_unit_path(src, spec, store)
                if path not in seen:
                    seen.add(path)
                    units.append((i, j, k, path))
    return units


def _estimate_s(scene: SweepScene, j: int, k: int) -> float:
    src = scene.scene.calibrations[j]
    spec = src.member_specs(scene.scene.base)[k]
    if src.kind == "md":
        return md_cost_s(spec, src.np)
    return 3600.0       # a particle run: no measured model of its cost here; an hour


def _minutes(seconds: float) -> int:
    return math.ceil((TIME_MARGIN * seconds + TIME_FLOOR_S) / 60.0)


def _time_limit(minutes: int) -> str:
    return f"{minutes // 60:d}:{minutes % 60:02d}:00"


def task_script(command: list[str], requeue_on_timeout: bool) -> str:
    """The batch script of one array task. With ``requeue_on_timeout`` the command runs in the
    background so that the shell can answer SLURM's ``USR1`` (sent `REQUEUE_LEAD_S` before
    the time limit) by requeueing its own task; SLURM then stops the command with SIGTERM,
    which ends its MPI run and leaves the restart files the requeued task resumes from."""
    line = " ".join(_quote(c) for c in command)
    if not requeue_on_timeout:
        return f"#!/bin/sh\nexec {line}\n"
    return (
        "#!/bin/bash\n"
        f"trap 'if [ \"${{SLURM_RESTART_COUNT:-0}}\" -lt {MAX_REQUEUES} ]; then echo "
        "\"filmscale: time limit near: requeueing this task\" >&2; scontrol requeue "
        "\"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\"; fi' USR1\n"
        f"{line} &\n"
        "child=$!\n"
        # `wait` returns early when the trap runs; wait again until the command has ended
        "while :; do wait \"$child\"; rc=$?; kill -0 \"$child\" 2>/dev/null || exit $rc; done\n")


def _sbatch(args: list[str], command: list[str], log: Path,
            requeue_on_timeout: bool = False) -> str:
    if shutil.which("sbatch") is None:
        raise EngineError("sbatch is not on PATH: submission needs SLURM (tools/"
                          "slurm-local.sh starts a single-node one for tests)")
    # appended, so that the log of a requeued task keeps what its first part wrote
    extra = ([f"--signal=B:USR1@{REQUEUE_LEAD_S}", "--open-mode=append"]
              if requeue_on_timeout else [])
    done = subprocess.run(["sbatch", "--parsable", "--requeue", *extra, f"--output={log}",
                           *args], input=task_script(command, requeue_on_timeout),
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise EngineError(f"sbatch refused the job: {done.stderr.strip()}")
    return done.stdout.strip().split(";")[0]


def _quote(word: str) -> str:
    """A shell word; the array task id alone stays a variable."""
    if word == TASK_ID:
        return f'"{TASK_ID}"'
    return "'" + word.replace("'", "'\\''") + "'"


TASK_ID = "${SLURM_ARRAY_TASK_ID}"


def check_unit_minutes(minutes: int | None) -> None:
    if minutes is not None and minutes * 60 <= REQUEUE_LEAD_S + 60:
        raise InputError(f"--time = {minutes} min must exceed {(REQUEUE_LEAD_S + 60) // 60} "
                         f"min: a task requeues itself {REQUEUE_LEAD_S} s before its limit")


def submit_sweep(sweep_file: Path, name: str, scenes: list[SweepScene], store: Path,
                 out_dir: Path, partition: str | None = None,
                 unit_minutes: int | None = None) -> dict:
    """Submit the sweep's pending run units and then its scenes; returns (and writes to
    ``STORE/jobs.json``) the job ids and what each array task runs. ``unit_minutes`` replaces
    the run-unit tasks' time limit from the cost model (a task that reaches it is requeued and
    resumes)."""
    check_unit_minutes(unit_minutes)
    store.mkdir(parents=True, exist_ok=True)
    out_dir.mkdir(parents=True, exist_ok=True)
    logs = out_dir / "slurm"
    logs.mkdir(exist_ok=True)
    base = [sys.executable, "-m", "filmscale", "sweep"]
    common = [f"--partition={partition}"] if partition else []
    pending = [(n, *u) for n, u in enumerate(run_units(scenes, store))
               if check_unit(u[3])[0] is None]
    jobs = {"sweep": str(sweep_file), "units": {}, "scenes": {}}
    after = []
    if pending:
        ranks = max(scenes[i].scene.calibrations[j].np for _, i, j, k, _ in pending)
        minutes = unit_minutes or _minutes(
            max(_estimate_s(scenes[i], j, k) for _, i, j, k, _ in pending))
        # array indices are the units' places in `run_units`, so a task finds its unit
        # whatever else is done by the time it starts
        units_job = _sbatch(
            [*common, f"--array={','.join(str(n) for n, *_ in pending)}",
             f"--job-name={name}-units", "--ntasks=1", f"--cpus-per-task={ranks}",
             f"--time={_time_limit(minutes)}"],
            [*base, "run-unit", str(sweep_file), "--store", str(store), "--unit", TASK_ID],
            logs / "unit_%a.log", requeue_on_timeout=True)
        jobs["units"] = {p.name: f"{units_job}_{n}" for n, *_, p in pending}
        after = [f"--dependency=afterok:{units_job}"]
    scenes_job = _sbatch(
        [*common, *after, f"--array=0-{len(scenes) - 1}", f"--job-name={name}-scenes",
         "--ntasks=1", "--cpus-per-task=1",
         f"--time={_time_limit(_minutes(60.0 * len(scenes)))}"],
        [*base, "run", str(sweep_file), "--store", str(store), "--out-dir", str(out_dir),
         "--only", TASK_ID], logs / "scene_%a.log")
    jobs["scenes"] = {s.name: f"{scenes_job}_{n}" for n, s in enumerate(scenes)}
    write_json(store / "jobs.json", jobs)
    return jobs


def read_jobs(store: Path) -> dict:
    """The jobs `submit_sweep` recorded in the store ({} when none); InputError when the
    file is damaged or a symbolic link (the store follows no links). Read only, with the
    bounded reader (`core.files.read_json`: size, nesting): a read-only store works."""
    path = Path(store) / "jobs.json"
    if os.path.islink(path):
        raise InputError(f"jobs file {shown(path)} is a symbolic link: the store follows no "
                         "links; remove it")
    if not path.exists():
        return {}
    jobs = read_json(path, "jobs file")
    if not isinstance(jobs, dict) or not all(
            isinstance(jobs.get(key), dict) and all(isinstance(j, str) for j in jobs[key].values())
            for key in ("units", "scenes")):
        raise InputError(f"jobs file {shown(path)} is damaged: it lacks the job ids of the "
                         "units and scenes that filmscale sweep submit records")
    return jobs


def queue_states(job_ids) -> dict[str, str]:
    """SLURM's state of each job id still in the queue (``PENDING``, ``RUNNING``, ...)."""
    if shutil.which("squeue") is None:
        return {}
    out = subprocess.run(["squeue", "-h", "-r", "-o", "%i %T"], capture_output=True,
                         text=True).stdout
    states = dict(line.split() for line in out.splitlines() if len(line.split()) == 2)
    return {j: states[j] for j in job_ids if j in states}


def cancel(store: Path) -> list[str]:
    """Cancel the store's recorded jobs still queued or running; their ids."""
    jobs = read_jobs(store)
    if not jobs:
        raise InputError(f"store {shown(store)} has no jobs.json: nothing was submitted "
                         "there")
    ids = [*jobs["units"].values(), *jobs["scenes"].values()]
    live = sorted({j.split("_")[0] for j in queue_states(ids)})
    if live:
        subprocess.run(["scancel", *live], check=False)
    return live
