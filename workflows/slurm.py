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

Both jobs take the site's options (`SubmitOptions`: account, QOS, memory, node features,
generic resources, an array throttle and further sbatch options, each checked before anything
is submitted). Each task's time limit comes from the planner's cost model of that task; the
array job asks for the largest, since SLURM gives every task of an array one limit
(`array_limit`). Before a submission the interpreter, the sweep file, the store and the
output folder must lie outside this node's own folders (`check_shared_paths`). A dry run
(`dry_run_text`) prints each job's sbatch command line and script and submits and writes
nothing.
"""

from __future__ import annotations

import math
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from filmscale.core.errors import EngineError, InputError
from filmscale.core.files import read_json, shown, write_json
from filmscale.workflows.plan import md_cost_s, plan_impact
from filmscale.workflows.sweep import SweepScene
from filmscale.workflows.store import check_unit
from filmscale.workflows.units import run_unit_path

#: a task's wall-time limit: the planner's cost estimate times this, plus `TIME_FLOOR_S`
TIME_MARGIN, TIME_FLOOR_S = 3.0, 600.0
#: seconds before its time limit that a run-unit task requeues itself (SLURM's signal may come
#: up to a minute earlier than asked); the requeues of one task are capped so that a unit that
#: makes no progress between two restart files does not loop
REQUEUE_LEAD_S, MAX_REQUEUES = 120, 20
#: the sbatch options `sweep submit` sets itself or relies on: refused in ``--sbatch``, by
#: name or by an abbreviation of it (sbatch takes unambiguous abbreviations of long options)
OWN_OPTIONS = ("--array", "--dependency", "--output", "--error", "--open-mode", "--signal",
               "--requeue", "--no-requeue", "--parsable", "--job-name", "--time", "--ntasks",
               "--cpus-per-task", "--wrap", "--wait", "--test-only")
#: the sbatch options `sweep submit` has an option of its own for (checked, both jobs)
NAMED_OPTIONS = ("partition", "account", "qos", "mem", "constraint", "gres")
#: SLURM's memory size: a whole number, megabytes unless a unit K, M, G or T follows (a B
#: after the unit is taken too: sbatch accepts 4GB, refuses 4.5G, 4Gi and 4B)
MEM_FORMAT = re.compile(r"[0-9]+([KMGT]B?)?", re.IGNORECASE)
#: folders of one node by convention (and ``$TMPDIR``, which sites point at a node's own
#: disk): a compute node has its own, not the submitting node's
NODE_LOCAL = ("/tmp", "/var/tmp", "/dev/shm")
#: a layer still to calibrate, when a scene task's impact is timed at submission: these
#: fractions of the substrate's E and sigma_y, a film that differs from its substrate and
#: yields, so that the planner times the dearer paths (the films kept, the elastic-plastic
#: law) where the scene allows them
STAND_IN_E, STAND_IN_SIGMA_Y = 0.5, 0.25


@dataclass(frozen=True)
class SubmitOptions:
    """How `submit_sweep` submits: the options both array jobs get (``partition`` to
    ``gres`` as the sbatch options of those names, ``array_limit`` as ``--array=...%N``,
    ``extra`` as they are, last), the time limits (minutes) that replace the cost model's of
    the run-unit tasks and of the scene tasks, and whether paths of this node only are
    allowed (a single-node site, the tests). Checked when made: InputError names the option."""

    partition: str | None = None
    account: str | None = None
    qos: str | None = None
    mem: str | None = None
    constraint: str | None = None
    gres: str | None = None
    array_limit: int | None = None
    extra: tuple[str, ...] = ()
    unit_minutes: int | None = None
    scene_minutes: int | None = None
    allow_local_paths: bool = False

    def __post_init__(self):
        for name in NAMED_OPTIONS:
            value = getattr(self, name)
            if value is not None and (not value or not value.isprintable()
                                      or any(c.isspace() for c in value)):
                raise InputError(f"--{name} = {value!r} must be one word of printable "
                                 "characters")
        if self.mem is not None and not MEM_FORMAT.fullmatch(self.mem):
            raise InputError(f"--mem = {self.mem!r} is not SLURM's memory format: a whole "
                             "number with an optional unit K, M, G or T (4G, 4000M, 500K; "
                             "without a unit, megabytes)")
        if self.array_limit is not None and self.array_limit < 1:
            raise InputError(f"--array-limit = {self.array_limit} must be at least 1 (tasks "
                             "of each array job running at once)")
        check_unit_minutes(self.unit_minutes)
        if self.scene_minutes is not None and self.scene_minutes < 1:
            raise InputError(f"--scene-time = {self.scene_minutes} min must be at least 1")
        check_extra_options(self.extra)

    def sbatch_args(self) -> list[str]:
        """The options both jobs get: the named ones, then the extra ones."""
        return [f"--{name}={getattr(self, name)}" for name in NAMED_OPTIONS
                if getattr(self, name) is not None] + list(self.extra)

    def array(self, indices: str) -> str:
        return f"--array={indices}" + (f"%{self.array_limit}" if self.array_limit else "")


def sbatch_options(texts) -> tuple[str, ...]:
    """The further sbatch options of ``--sbatch`` texts, each split as a shell would split it
    (`shlex`), checked (`check_extra_options`)."""
    words = []
    for text in texts:
        try:
            words += shlex.split(text)
        except ValueError as exc:
            raise InputError(f"--sbatch {text!r}: {exc} (the text is split as a shell "
                             "would split it)") from None
    check_extra_options(words)
    return tuple(words)


def check_extra_options(words) -> None:
    """Each word a long option (``--name`` or ``--name=value``) that filmscale neither sets
    itself (`OWN_OPTIONS`) nor has an option of its own for (`NAMED_OPTIONS`), not even
    abbreviated; InputError naming the word and the option."""
    for word in words:
        name = word.split("=", 1)[0]
        if not word.startswith("--") or len(name) < 3:
            raise InputError(f"--sbatch: {word!r} is not a long option: give each "
                             "option as --name or --name=value (no short options, no value "
                             "apart from its option)")
        own = [o for o in OWN_OPTIONS if o.startswith(name)]
        if own:
            how = "is" if name == own[0] else "abbreviates"
            raise InputError(f"--sbatch: {word!r} {how} {own[0]}, which filmscale sweep "
                             "submit sets itself for its array jobs: it cannot be passed "
                             "through")
        named = [n for n in NAMED_OPTIONS if f"--{n}".startswith(name)]
        if named:
            raise InputError(f"--sbatch: {word!r} sets --{named[0]}: give filmscale "
                             f"sweep submit's own --{named[0]} (checked, and passed to both "
                             "jobs)")


def _node_local_roots() -> list[Path]:
    """`NODE_LOCAL` and ``$TMPDIR`` (absolute, not ``/``), as named and as resolved."""
    roots = []
    for root in (*NODE_LOCAL, os.environ.get("TMPDIR", "")):
        if root and os.path.isabs(root) and os.path.realpath(root) != "/":
            roots += [Path(os.path.abspath(root)), Path(os.path.realpath(root))]
    return roots


def submission_paths(sweep_file: Path, store: Path, out_dir: Path) -> dict[str, Path]:
    """What every task reads or writes from a compute node: the Python environment and
    interpreter that run ``filmscale`` (a venv's folder and its ``bin/python``), the sweep
    file, the store and the output folder."""
    return {"the Python environment (sys.prefix)": Path(sys.prefix),
            "the interpreter (sys.executable)": Path(sys.executable),
            "the sweep file": Path(sweep_file), "--store": Path(store),
            "--out-dir": Path(out_dir)}


def check_shared_paths(paths: dict[str, Path]) -> None:
    """Refuse (InputError, one line) a path under a folder of this node only (`NODE_LOCAL`,
    ``$TMPDIR``), as given or with its links resolved: the tasks run on compute nodes that
    see their own such folders, not this one's. The check knows folder names, not mounts:
    a path it lets through may still be a disk of this node alone."""
    roots = _node_local_roots()
    for what, path in paths.items():
        for form in (Path(os.path.abspath(path)), Path(os.path.realpath(path))):
            root = next((r for r in roots if form == r or r in form.parents), None)
            if root is not None:
                raise InputError(
                    f"{what} {shown(path)} is under {shown(root)}, a folder of this node only: "
                    "the compute nodes that run the tasks do not see it; put it on a file "
                    "system they share (or give --allow-local-paths on a single-node site)")


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
    """The planner's cost of one run unit (`plan.md_cost_s` for MD)."""
    src = scene.scene.calibrations[j]
    spec = src.member_specs(scene.scene.base)[k]
    if src.kind == "md":
        return md_cost_s(spec, src.np)
    return 3600.0       # a particle run: no measured model of its cost here; an hour


def _stand_ins(pipeline) -> list[dict]:
    """The materials that may stand for the layers still to calibrate while the impact is
    timed: `STAND_IN_E` and `STAND_IN_SIGMA_Y` of the substrate, else the substrate's own."""
    from filmscale.continuum.materials import ElasticPlastic
    sub = pipeline.data["target"]["substrate"]
    E, sigma_y = float(sub["E"]), float(sub["sigma_y"])
    layers = sorted({c.layer for c in pipeline.calibrations})
    out = []
    for e, s in ((STAND_IN_E, STAND_IN_SIGMA_Y), (1.0, 1.0)):
        try:
            out.append({k: ElasticPlastic(e * E, 0.3, s * sigma_y) for k in layers})
        except InputError:          # a stand-in that is no real solid: the next one
            continue
    return out


def scene_estimate_s(s: SweepScene) -> float:
    """The planner's cost (s) of what a scene task computes. Its run units are the units
    job's (the scenes start after it succeeded) or done already; the task fits its
    calibrations and evaluates its impact. The impact is `plan.plan_impact`'s timed steps,
    counted once and once more for each shifted scene of the calibrations' spread (up to two
    a calibrated layer: E and sigma_y, `pipeline.parameter_spread`). A layer still to
    calibrate is given a stand-in (`_stand_ins`); where none gives a plan the estimate is 0
    and `TIME_FLOOR_S` stands. The planner has no model of a calibration's fit (about 2 s
    for an MD ci unit here): `TIME_FLOOR_S` holds it."""
    p = s.scene
    evaluations = 1 + 2 * len({c.layer for c in p.calibrations})
    for stand_in in _stand_ins(p) if p.calibrations else [{}]:
        try:
            plan = plan_impact(p.completed(stand_in), p.outputs, p.tolerance, p.friction,
                               p.angle)
        except InputError:
            continue
        return evaluations * sum(st.cost_s for st in plan.steps if math.isfinite(st.cost_s))
    return 0.0


def _minutes(seconds: float) -> int:
    return math.ceil((TIME_MARGIN * seconds + TIME_FLOOR_S) / 60.0)


def _time_limit(minutes: int) -> str:
    return f"{minutes // 60:d}:{minutes % 60:02d}:00"


def array_limit(given: int | None, estimates: dict[str, float], option: str
                ) -> tuple[int, str]:
    """(minutes, why) of an array job's one time limit: ``given`` (``option``), else the
    largest task's: its estimate (s) times `TIME_MARGIN` plus `TIME_FLOOR_S`. SLURM gives
    every task of an array the same limit, so the array asks for its longest task's."""
    if given is not None:
        return given, f"{given} min, as {option} gives"
    task, worst = max(estimates.items(), key=lambda item: item[1])
    return _minutes(worst), (
        f"the largest task's (SLURM gives every task of an array one limit): {task}, "
        f"estimated {worst:.3g} s, times {TIME_MARGIN:g} plus {TIME_FLOOR_S / 60:g} min")


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


@dataclass(frozen=True)
class ArrayJob:
    """One array job as sbatch gets it: what it is (``key``: "units" or "scenes"; ``label``),
    its options, the command of each task, its log, whether a task requeues itself near its
    limit, the array index of each unit or scene (``tasks``), why its time limit is what it
    is, and whether it waits for the job before it (``afterok``)."""

    key: str
    label: str
    options: tuple[str, ...]
    command: tuple[str, ...]
    log: Path
    requeue_on_timeout: bool
    tasks: dict
    limit_why: str
    after: bool = False

    def argv(self, after_job: str | None = None) -> list[str]:
        """The sbatch command line; ``after_job``: the id of the job it waits for."""
        # appended, so that the log of a requeued task keeps what its first part wrote
        extra = ([f"--signal=B:USR1@{REQUEUE_LEAD_S}", "--open-mode=append"]
                 if self.requeue_on_timeout else [])
        after = [f"--dependency=afterok:{after_job}"] if self.after else []
        return ["sbatch", "--parsable", "--requeue", *extra, f"--output={self.log}", *after,
                *self.options]

    def script(self) -> str:
        return task_script(list(self.command), self.requeue_on_timeout)


def array_jobs(sweep_file: Path, name: str, scenes: list[SweepScene], store: Path,
               out_dir: Path, options: SubmitOptions) -> list[ArrayJob]:
    """The sweep's array jobs: its pending run units (if any), then its scenes after them.
    Reads the store (which units are done); writes nothing."""
    base = [sys.executable, "-m", "filmscale", "sweep"]
    logs, common = out_dir / "slurm", options.sbatch_args()
    pending = [(n, *u) for n, u in enumerate(run_units(scenes, store))
               if check_unit(u[3])[0] is None]
    jobs = []
    if pending:
        ranks = max(scenes[i].scene.calibrations[j].np for _, i, j, k, _ in pending)
        minutes, why = array_limit(options.unit_minutes, {
            f"unit {n} ({p.name})": _estimate_s(scenes[i], j, k) for n, i, j, k, p in pending},
            "--time")
        # array indices are the units' places in `run_units`, so a task finds its unit
        # whatever else is done by the time it starts
        jobs.append(ArrayJob(
            "units", f"{len(pending)} run unit(s)",
            (options.array(",".join(str(n) for n, *_ in pending)), f"--job-name={name}-units",
             "--ntasks=1", f"--cpus-per-task={ranks}", f"--time={_time_limit(minutes)}",
             *common),
            (*base, "run-unit", str(sweep_file), "--store", str(store), "--unit", TASK_ID),
            logs / "unit_%a.log", True, {p.name: n for n, *_, p in pending}, why))
    minutes, why = array_limit(options.scene_minutes, {
        f"scene {n} ({s.name})": scene_estimate_s(s) for n, s in enumerate(scenes)},
        "--scene-time")
    jobs.append(ArrayJob(
        "scenes", f"{len(scenes)} scene(s)",
        (options.array(f"0-{len(scenes) - 1}"), f"--job-name={name}-scenes", "--ntasks=1",
         "--cpus-per-task=1", f"--time={_time_limit(minutes)}", *common),
        (*base, "run", str(sweep_file), "--store", str(store), "--out-dir", str(out_dir),
         "--only", TASK_ID), logs / "scene_%a.log", False,
        {s.name: n for n, s in enumerate(scenes)}, why, after=bool(pending)))
    return jobs


def _checked_jobs(sweep_file: Path, name: str, scenes: list[SweepScene], store: Path,
                  out_dir: Path, options: SubmitOptions) -> list[ArrayJob]:
    if not options.allow_local_paths:
        check_shared_paths(submission_paths(sweep_file, store, out_dir))
    return array_jobs(sweep_file, name, scenes, store, out_dir, options)


def dry_run_text(sweep_file: Path, name: str, scenes: list[SweepScene], store: Path,
                 out_dir: Path, options: SubmitOptions = SubmitOptions()) -> str:
    """What `submit_sweep` would submit, checked as it checks: each job's sbatch command line
    and its script (sbatch reads it on its standard input). Submits and writes nothing."""
    jobs, lines = _checked_jobs(sweep_file, name, scenes, store, out_dir, options), []
    for n, job in enumerate(jobs, 1):
        lines += [f"# job {n} of {len(jobs)}: {job.label}"
                  + (f", after every task of job {n - 1} succeeded" if job.after else ""),
                  f"# time limit: {job.limit_why}",
                  shlex.join(job.argv(f"<job {n - 1}>")),
                  "# its script, on sbatch's standard input:", job.script().rstrip("\n")]
    return "\n".join(lines + ["# dry run: nothing submitted, nothing written"])


def submit_sweep(sweep_file: Path, name: str, scenes: list[SweepScene], store: Path,
                 out_dir: Path, options: SubmitOptions = SubmitOptions()) -> dict:
    """Submit the sweep's pending run units and then its scenes; returns (and writes to
    ``STORE/jobs.json``) the job ids and what each array task runs. Should sbatch refuse the
    scenes' job, the units' job is cancelled: nothing is left waiting for it."""
    jobs = _checked_jobs(sweep_file, name, scenes, store, out_dir, options)
    for folder in (store, out_dir, out_dir / "slurm"):
        folder.mkdir(parents=True, exist_ok=True)
    ids, last = {"sweep": str(sweep_file), "units": {}, "scenes": {}}, None
    for job in jobs:
        try:
            job_id = _sbatch(job.argv(last), job.script())
        except EngineError as err:
            if last is None:
                raise
            subprocess.run(["scancel", last], check=False)
            raise EngineError(f"{err}; the run units' job {last} was cancelled") from None
        ids[job.key] = {task: f"{job_id}_{n}" for task, n in job.tasks.items()}
        last = job_id
    write_json(store / "jobs.json", ids)
    return ids


def _sbatch(argv: list[str], script: str) -> str:
    if shutil.which("sbatch") is None:
        raise EngineError("sbatch is not on PATH: submission needs SLURM (tools/"
                          "slurm-local.sh starts a single-node one for tests)")
    done = subprocess.run(argv, input=script, capture_output=True, text=True)
    if done.returncode != 0:
        said = "; ".join(line.strip() for line in done.stderr.splitlines() if line.strip())
        raise EngineError(f"sbatch refused the job: {said or f'exit status {done.returncode}'}")
    return done.stdout.strip().split(";")[0]


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
