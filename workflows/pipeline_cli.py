"""`filmscale plan`, `run`, `report`, `sweep plan|run` and `status`: the scene pipeline's
commands."""

from __future__ import annotations

import sys
from pathlib import Path

from filmscale.core.errors import InputError

from .outputs import (REPORT, add_force_argument, check_outputs, hdf5_kind, json_kind,
                      output_path, plot_path, scene_files)


def _store_folder(store) -> Path:
    """``--store``: a folder, or nothing yet."""
    store = Path(store)
    if store.exists() and not store.is_dir():
        raise InputError(f"--store {store} is a file, not a folder")
    return store


def _scene_result_kind():
    from .result import RESULT_FORMATS, SLIDE_RESULT_FORMAT
    return hdf5_kind((*RESULT_FORMATS, SLIDE_RESULT_FORMAT), "a scene result")


#: the index of a sweep's scenes that `sweep run` writes
SWEEP_INDEX = json_kind({"sweep", "scenes"}, "a sweep index")


def cmd_plan(args) -> int:
    from .plan import plan_scene
    from .pipeline_scene import load_pipeline
    print(plan_scene(load_pipeline(args.scene)).text())
    return 0


def cmd_run(args) -> int:
    from .pipeline import run_scene
    from .pipeline_scene import load_pipeline
    scene = Path(args.scene)
    pipeline = load_pipeline(scene)             # every input checked before any run
    if pipeline.sliding and args.report:
        raise InputError("--report: the HTML report reads impact results; a sliding scene's "
                         "result holds its table in the slide group, which `filmscale run` "
                         "prints")
    out = output_path("--out", args.out or Path("results") / f"{scene.stem}.h5")
    store = _store_folder(args.store)
    check_outputs([("the input scene", scene),
                   *scene_files(pipeline.base, pipeline.data, pipeline.calibrations)],
                  [("--out", out, _scene_result_kind()),
                   ("--report", out.with_suffix(".html") if args.report else None, REPORT)],
                  args.force)
    result = run_scene(pipeline, store, out)
    ran = sum(v == "ran" for v in result.units.values())
    print(f"filmscale: {ran} unit(s) ran, {len(result.units) - ran} reused; result {result.path}",
          file=sys.stderr)
    if args.report:
        from .report import write_report
        print(f"filmscale: report {write_report(result.path)}", file=sys.stderr)
    if result.sliding:
        from .slide_cli import slide_table
        print(slide_table(result.slide()))
    print(result.path)
    if args.strict:
        reasons = _strict_reasons(result.path)
        for reason in reasons:
            print(f"filmscale: strict: {reason}", file=sys.stderr)
        return 1 if reasons else 0
    return 0


def _strict_reasons(path: Path) -> list[str]:
    """`calibrate_cli.strict_reasons` of each calibrated layer of a scene result, as the
    result file holds its calibration and cross-scale checks: "layer <name>: <reason>"."""
    import json

    import h5py

    from filmscale.continuum.calibration.result import Calibration, CrossCheck

    from .calibrate_cli import strict_reasons
    out = []
    with h5py.File(path, "r") as f:
        for group in f["calibration"].values():
            cal = Calibration.from_dict(json.loads(group.attrs["calibration"]))
            checks = [CrossCheck(**c) for c in json.loads(group.attrs["cross_check"])]
            out += [f"layer {cal.layer}: {r}" for r in strict_reasons(cal, checks)]
    return out


def _sweep_inputs(sweep: Path, scenes) -> list[tuple[str, Path]]:
    """The sweep file, its base scene and the files the scenes read."""
    import tomllib

    from filmscale.core.files import read_text
    base = Path(sweep).parent / str(tomllib.loads(read_text(sweep, "sweep"))["base"])
    files = [("the sweep file", Path(sweep)), ("the sweep's base scene", base)]
    for s in scenes:
        files += [f for f in scene_files(s.scene.base, s.scene.data, s.scene.calibrations)
                  if f not in files]
    return files


def _check_sweep_outputs(sweep: Path, name: str, scenes, out_dir: Path,
                         index_name: str | None, force: bool) -> None:
    """Each scene's result and the index in ``--out-dir``: neither an input nor a file of
    another kind (`check_outputs`), before any scene runs."""
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out-dir {out_dir} is a file, not a folder")
    check_outputs(_sweep_inputs(sweep, scenes),
                  [("--out-dir", out_dir / f"{s.name}.h5", _scene_result_kind())
                   for s in scenes]
                  + [("--out-dir", out_dir / (index_name or f"{name}.json"), SWEEP_INDEX)],
                  force)


def cmd_sweep(args) -> int:
    """``sweep plan|run|submit|run-unit``: every scene of the sweep checked before any runs."""
    name, scenes = _load_sweep(args)
    if args.sweep_command == "run-unit":
        return _run_sweep_unit(args, scenes)
    out_dir = Path(args.out_dir) if getattr(args, "out_dir", None) else Path("results") / name
    if args.sweep_command == "submit":
        return _submit_sweep(args, name, scenes, out_dir)
    if args.sweep_command == "plan":
        return _plan_sweep(scenes)
    return _run_sweep(args, name, scenes, out_dir)


def _load_sweep(args):
    """(name, scenes) of the sweep file, its options and (but for ``plan``) every scene's
    request and the store checked."""
    from .plan import check_request
    from .sweep import load_sweep
    if getattr(args, "jobs", None) is not None and args.jobs < 1:
        raise InputError(f"--jobs = {args.jobs} must be at least 1")
    if args.sweep_command == "submit":
        from .slurm import check_unit_minutes
        check_unit_minutes(args.time)
    name, scenes = load_sweep(args.sweep)        # every scene checked before any run
    if args.sweep_command != "plan":
        for s in scenes:
            check_request(s.scene)
        _store_folder(args.store)
    return name, scenes


def _plan_sweep(scenes) -> int:
    """``sweep plan``: each scene's overrides and plan; on stderr, one line per swept key
    that changes nothing the plans keep (`sweep.unused_keys`; a plan that waits for its
    calibrations is checked by `sweep run`)."""
    from .plan import plan_scene
    from .sweep import default_jobs, unused_keys
    plans = []
    for s in scenes:
        changes = ", ".join(f"{k} = {v!r}" for k, v in s.overrides.items()) or "the base"
        plans.append(plan_scene(s.scene))
        print(f"== {s.name}: {changes}\n{plans[-1].text()}")
    print(f"{len(scenes)} scene(s); `filmscale sweep run` would run "
          f"{default_jobs(scenes)} at a time here")
    for w in unused_keys(scenes, [p.decisions for p in plans]):
        print(f"filmscale: warning: {w['text']}", file=sys.stderr)
    waiting = sum("law" not in p.decisions and not p.decisions.get("sliding") for p in plans)
    if waiting:
        print(f"filmscale: {waiting} scene(s) choose their impact models after calibration; "
              "`filmscale sweep run` checks their swept keys then", file=sys.stderr)
    return 0


def _submit_sweep(args, name: str, scenes, out_dir: Path) -> int:
    """``sweep submit``: the run units as one SLURM array job, then the scenes after them."""
    from filmscale.core.jsonable import dumps

    from .slurm import dry_run_text, submit_sweep
    options = _submit_options(args)
    _check_sweep_outputs(Path(args.sweep), name, scenes, out_dir, None, False)
    where = (Path(args.sweep).resolve(), name, scenes, Path(args.store).resolve(),
             out_dir.resolve(), options)
    if args.dry_run:
        print(dry_run_text(*where))
        return 0
    jobs = submit_sweep(*where)
    print(f"filmscale: submitted {len(jobs['units'])} run unit(s) and {len(jobs['scenes'])} "
          f"scene(s); `filmscale status {args.store}` follows them", file=sys.stderr)
    print(dumps(jobs))
    return 0


def _submit_options(args):
    """`slurm.SubmitOptions` of ``sweep submit``'s options, checked (InputError, one line)."""
    from .slurm import SubmitOptions, sbatch_options
    return SubmitOptions(
        partition=args.partition, account=args.account, qos=args.qos, mem=args.mem,
        constraint=args.constraint, gres=args.gres, array_limit=args.array_limit,
        extra=sbatch_options(args.sbatch), unit_minutes=args.time,
        scene_minutes=args.scene_time, allow_local_paths=args.allow_local_paths)


def _run_sweep(args, name: str, scenes, out_dir: Path) -> int:
    """``sweep run``: every scene (or --only one) side by side; exit 1 when one failed."""
    from .sweep import run_sweep
    index_name = None
    if args.only is not None:
        if not 0 <= args.only < len(scenes):
            raise InputError(f"--only = {args.only} must be a scene index in [0, "
                             f"{len(scenes) - 1}]")
        scenes = [scenes[args.only]]
        index_name = f"{scenes[0].name}.json"
    _check_sweep_outputs(Path(args.sweep), name, scenes, out_dir, index_name, args.force)
    index, entries = run_sweep(name, scenes, Path(args.store), out_dir, args.jobs,
                               say=lambda m: print(f"filmscale: {m}", file=sys.stderr),
                               index_name=index_name)
    failed = [e["name"] for e in entries if e["state"] == "failed"]
    print(index)
    if failed:
        print(f"filmscale: {len(failed)} of {len(entries)} scene(s) failed: "
              f"{', '.join(failed)} (see {index})", file=sys.stderr)
        return 1
    return 0


def _run_sweep_unit(args, scenes) -> int:
    """One run unit of a sweep (what a SLURM task of `sweep submit` runs)."""
    from .slurm import run_units
    from .units import run_unit
    units = run_units(scenes, Path(args.store))
    if not 0 <= args.unit < len(units):
        raise InputError(f"--unit = {args.unit} must be in [0, {len(units) - 1}]: the sweep "
                         f"has {len(units)} run unit(s)")
    i, j, k, _ = units[args.unit]
    src = scenes[i].scene.calibrations[j]
    path, reused = run_unit(src, src.member_specs(scenes[i].scene.base)[k], Path(args.store))
    print(f"filmscale: {path.name} {'reused' if reused else 'ran'}", file=sys.stderr)
    print(path)
    return 0


def cmd_cancel(args) -> int:
    """Cancel a store's jobs: reads ``jobs.json`` only (a read-only store works), prints the
    ids escaped (`core.files.shown`)."""
    from filmscale.core.files import shown
    from .slurm import cancel
    ids = [shown(i) for i in cancel(Path(args.store))]
    print(f"filmscale: cancelled {' '.join(ids) if ids else 'nothing (no job left)'}",
          file=sys.stderr)
    return 0


def cmd_status(args) -> int:
    """Every unit of a store (`store.unit_states`: creates no file, so a read-only store
    works); the text prints every name, state and reason escaped (`core.files.shown`: a
    folder name with a terminal escape sequence prints as its escapes), the JSON as JSON
    escapes them."""
    from filmscale.core.files import shown
    store = Path(args.store)
    if not store.is_dir():
        raise InputError(f"store {shown(store)} is not a folder")
    rows = _unit_rows(store)
    if args.json:
        from filmscale.core.jsonable import dumps
        print(dumps(rows))
        return 0
    for r in rows:
        print(_status_line(r))
    counts = {s: sum(r["state"] == s for r in rows) for s in dict.fromkeys(
        r["state"] for r in rows)}
    print(", ".join(f"{n} {shown(s)}" for s, n in counts.items()) or "no units")
    return 0


def _unit_rows(store: Path) -> list[dict]:
    """The store's units (`store.unit_states`), each with its SLURM job where `sweep submit`
    recorded one, and the queue's state while the job is not done."""
    from .slurm import queue_states, read_jobs
    from .store import unit_states
    rows = unit_states(store)
    jobs = read_jobs(store).get("units", {})
    queue = queue_states(jobs.values())
    for r in rows:
        if r["unit"] in jobs:
            r["job"] = jobs[r["unit"]]
            if r["state"] != "done" and r["job"] in queue:
                r["state"] = queue[r["job"]].lower()
    return rows


def _status_line(r: dict) -> str:
    """One unit: its name, state, job, wall time and why, escaped (`core.files.shown`)."""
    from filmscale.core.files import shown
    extra = (f"  job {shown(r['job'])}" if "job" in r else "") + \
        (f"  {r['wall_time']:.0f} s" if "wall_time" in r else "") + \
        (f"  ({shown(r['why'])})" if "why" in r else "")
    return f"{shown(r['unit']):<40} {shown(r['state']):<11}{extra}"


def cmd_report(args) -> int:
    from .outputs import hdf5_format, image_kind
    from .report import check_result, write_figure, write_report
    from .result import SLIDE_RESULT_FORMAT
    if Path(args.result).is_file() and hdf5_format(Path(args.result)) == SLIDE_RESULT_FORMAT:
        raise InputError(f"{args.result} is a sliding scene's result: `filmscale report` "
                         "reads impact results; the sliding table is in its slide group "
                         "(`filmscale run` prints it, SceneResult.slide() reads it)")
    result = check_result(args.result)
    out = output_path("--out", args.out or result.with_suffix(".html"))
    figure = plot_path("--figure", args.figure)
    check_outputs([("the input result", result)],
                  [("--out", out, REPORT), ("--figure", figure, image_kind(figure))],
                  args.force)
    print(write_report(result, out))
    if figure:
        print(write_figure(result, figure))
    return 0


def _store_argument(p, help_text="folder of the hash-named run units (default filmscale_runs)"):
    p.add_argument("--store", default="filmscale_runs", help=help_text)


def _sweep_parser(ssub, name: str, help_text: str):
    q = ssub.add_parser(name, help=help_text)
    q.add_argument("sweep", help="sweep file (TOML)")
    q.set_defaults(func=cmd_sweep)
    return q


def _submit_arguments(q) -> None:
    """``sweep submit``'s options (`slurm.SubmitOptions`, docs/hpc.md)."""
    _store_argument(q, "folder of the hash-named run units, shared by every task")
    q.add_argument("--out-dir", metavar="DIR",
                   help="results, indexes and the tasks' logs (default results/NAME)")
    q.add_argument("--partition", help="SLURM partition (default: the cluster's)")
    q.add_argument("--account", help="SLURM account both jobs are charged to")
    q.add_argument("--qos", help="SLURM quality of service of both jobs")
    q.add_argument("--mem", metavar="SIZE",
                   help="memory of each task's node share, SLURM's format: 4G, 4000M, 500K")
    q.add_argument("--constraint", metavar="FEATURES",
                   help="node features both jobs need (sbatch --constraint)")
    q.add_argument("--gres", help="generic resources of each task, e.g. gpu:1")
    q.add_argument("--array-limit", type=int, metavar="N",
                   help="at most N tasks of each array job at once (--array=...%%N)")
    q.add_argument("--sbatch", action="append", default=[], metavar="'OPTIONS'",
                   help="further sbatch options for both jobs, each --name or --name=value, "
                        "split as a shell would; write --sbatch='--exclusive "
                        "--mail-type=END' (with the =). Refused: what filmscale sets itself "
                        "(--array, --dependency, --output, --time, ...) and its own options")
    q.add_argument("--time", type=int, metavar="MINUTES",
                   help="time limit of each run-unit task (default: three times the "
                        "largest task's estimate plus 10 min: an array's tasks share one "
                        "limit); a task near it requeues itself and resumes from its last "
                        "restart file")
    q.add_argument("--scene-time", type=int, metavar="MINUTES",
                   help="time limit of each scene task (default: three times the largest "
                        "scene's estimated impact evaluations plus 10 min)")
    q.add_argument("--dry-run", action="store_true",
                   help="print each job's sbatch command line and script; submit nothing, "
                        "write nothing")
    q.add_argument("--allow-local-paths", action="store_true",
                   help="allow an interpreter, sweep file, store or out-dir under /tmp, "
                        "/var/tmp, /dev/shm or $TMPDIR (a single-node site; tests)")


def add_arguments(sub) -> None:
    """``plan``, ``run``, ``sweep``, ``cancel``, ``status`` and ``report``, on the top-level
    sub-parsers."""
    p = sub.add_parser("plan", help="print the models a scene needs, why, error and cost",
                       description="Plan a scene without running it: for each layer, the "
                                   "model chosen to calibrate it (MD, particles or the "
                                   "curves given) and why, the expected error and the "
                                   "estimated cost, then the impact model. `filmscale run` "
                                   "executes the same plan.")
    p.add_argument("scene", help="scene file (TOML)")
    p.set_defaults(func=cmd_plan)

    p = sub.add_parser("run", help="run a scene's plan (reuses finished units, resumes)",
                       description="Execute the plan: MD calibrations, then the impact "
                                   "models; write one HDF5 result per scene.")
    p.add_argument("scene", help="scene file (TOML)")
    _store_argument(p)
    p.add_argument("--out", metavar="RESULT.h5",
                   help="result file (default results/SCENE.h5)")
    p.add_argument("--report", action="store_true", help="also write the HTML report")
    from .calibrate_cli import add_strict_argument
    add_strict_argument(p, "a layer's calibration is not one to trust (the result is still "
                           "written)")
    add_force_argument(p)
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("sweep", help="many scenes from one base scene and its overrides",
                       description="A sweep file names a base scene and the overrides (axes: "
                                   "every combination; cases: explicit sets) that make its "
                                   "scenes; they run side by side on one shared store.")
    ssub = p.add_subparsers(dest="sweep_command", required=True)
    _sweep_parser(ssub, "plan", "print each scene's overrides and plan")
    q = _sweep_parser(ssub, "run", "run every scene (units shared, reused and resumed)")
    _store_argument(q)
    q.add_argument("--out-dir", metavar="DIR",
                   help="results and the sweep's index NAME.json (default results/NAME)")
    q.add_argument("--jobs", type=int, metavar="N",
                   help="scenes at once (default: the usable CPUs over the largest np)")
    q.add_argument("--only", type=int, metavar="K",
                   help="run scene K only (0-based), its index as OUT/SCENE.json")
    add_force_argument(q)
    q = _sweep_parser(ssub, "submit", "submit the sweep to SLURM: its run units as one array "
                                      "job, then its scenes after them")
    _submit_arguments(q)
    q = _sweep_parser(ssub, "run-unit", "run one run unit of a sweep (what a SLURM task of "
                                        "`sweep submit` runs)")
    _store_argument(q, "the shared store")
    q.add_argument("--unit", type=int, required=True, metavar="K",
                   help="the unit's place among the sweep's distinct run units")

    p = sub.add_parser("cancel", help="cancel the SLURM jobs a sweep submitted to a store")
    p.add_argument("store", help="the store folder (--store of filmscale sweep submit)")
    p.set_defaults(func=cmd_cancel)

    p = sub.add_parser("status", help="every unit of a store: done, running, incomplete, "
                                      "corrupted")
    p.add_argument("store", help="the store folder (--store of filmscale run)")
    p.add_argument("--json", action="store_true", help="one JSON list")
    p.set_defaults(func=cmd_status)

    p = sub.add_parser("report", help="self-contained HTML report of a scene result")
    p.add_argument("result", help="RESULT.h5 from filmscale run")
    p.add_argument("--out", metavar="REPORT.html", help="default: RESULT with .html")
    p.add_argument("--figure", metavar="FIGURE.png",
                   help="also a one-line PNG summary: calibration, profile, map")
    add_force_argument(p)
    p.set_defaults(func=cmd_report)
