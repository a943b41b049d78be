"""`filmscale plan`, `run`, `report`, `sweep plan|run` and `status`: the scene pipeline's
commands."""

from __future__ import annotations

import sys
from pathlib import Path


def cmd_plan(args) -> int:
    from .plan import plan_scene
    from .scene import load_pipeline
    print(plan_scene(load_pipeline(args.scene)).text())
    return 0


def cmd_run(args) -> int:
    from .pipeline import run_scene
    from .scene import load_pipeline
    scene = Path(args.scene)
    pipeline = load_pipeline(scene)             # every input checked before any run
    out = Path(args.out) if args.out else Path("results") / f"{scene.stem}.h5"
    result = run_scene(pipeline, Path(args.store), out)
    ran = sum(v == "ran" for v in result.units.values())
    print(f"filmscale: {ran} unit(s) ran, {len(result.units) - ran} reused; result {result.path}",
          file=sys.stderr)
    if args.report:
        from .report import write_report
        print(f"filmscale: report {write_report(result.path)}", file=sys.stderr)
    print(result.path)
    return 0


def cmd_sweep(args) -> int:
    from .plan import plan_scene
    from .sweep import default_jobs, load_sweep, run_sweep
    if getattr(args, "jobs", None) is not None and args.jobs < 1:
        from filmscale.core.errors import InputError
        raise InputError(f"--jobs = {args.jobs} must be at least 1")
    name, scenes = load_sweep(args.sweep)        # every scene checked before any run
    if args.sweep_command == "plan":
        for s in scenes:
            changes = ", ".join(f"{k} = {v!r}" for k, v in s.overrides.items()) or "the base"
            print(f"== {s.name}: {changes}\n{plan_scene(s.scene).text()}")
        print(f"{len(scenes)} scene(s); `filmscale sweep run` would run "
              f"{default_jobs(scenes)} at a time here")
        return 0
    out_dir = Path(args.out_dir) if args.out_dir else Path("results") / name
    index, entries = run_sweep(name, scenes, Path(args.store), out_dir, args.jobs,
                               say=lambda m: print(f"filmscale: {m}", file=sys.stderr))
    failed = [e["name"] for e in entries if e["state"] == "failed"]
    print(index)
    if failed:
        print(f"filmscale: {len(failed)} of {len(entries)} scene(s) failed: "
              f"{', '.join(failed)} (see {index})", file=sys.stderr)
        return 1
    return 0


def cmd_status(args) -> int:
    from filmscale.core.jsonable import dumps

    from .units import unit_states
    store = Path(args.store)
    if not store.is_dir():
        from filmscale.core.errors import InputError
        raise InputError(f"store {store} is not a folder")
    rows = unit_states(store)
    if args.json:
        print(dumps(rows))
        return 0
    for r in rows:
        extra = (f"  {r['wall_time']:.0f} s" if "wall_time" in r else "") + \
            (f"  ({r['why']})" if "why" in r else "")
        print(f"{r['unit']:<40} {r['state']:<11}{extra}")
    counts = {s: sum(r["state"] == s for r in rows) for s in dict.fromkeys(
        r["state"] for r in rows)}
    print(", ".join(f"{n} {s}" for s, n in counts.items()) or "no units")
    return 0


def cmd_report(args) -> int:
    from .report import write_figure, write_report
    print(write_report(args.result, args.out))
    if args.figure:
        print(write_figure(args.result, args.figure))
    return 0


def add_commands(sub) -> None:
    p = sub.add_parser("plan", help="print the models a scene needs, why, error and cost")
    p.add_argument("scene", help="scene file (TOML)")
    p.set_defaults(func=cmd_plan)

    p = sub.add_parser("run", help="run a scene's plan (reuses finished units, resumes)",
                       description="Execute the plan: MD calibrations, then the impact "
                                   "models; write one HDF5 result per scene.")
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--store", default="filmscale_runs",
                   help="folder of the hash-named run units (default filmscale_runs)")
    p.add_argument("--out", metavar="RESULT.h5",
                   help="result file (default results/SCENE.h5)")
    p.add_argument("--report", action="store_true", help="also write the HTML report")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("sweep", help="many scenes from one base scene and its overrides",
                       description="A sweep file names a base scene and the overrides (axes: "
                                   "every combination; cases: explicit sets) that make its "
                                   "scenes; they run side by side on one shared store.")
    ssub = p.add_subparsers(dest="sweep_command", required=True)
    q = ssub.add_parser("plan", help="print each scene's overrides and plan")
    q.add_argument("sweep", help="sweep file (TOML)")
    q.set_defaults(func=cmd_sweep)
    q = ssub.add_parser("run", help="run every scene (units shared, reused and resumed)")
    q.add_argument("sweep", help="sweep file (TOML)")
    q.add_argument("--store", default="filmscale_runs",
                   help="folder of the hash-named run units (default filmscale_runs)")
    q.add_argument("--out-dir", metavar="DIR",
                   help="results and the sweep's index NAME.json (default results/NAME)")
    q.add_argument("--jobs", type=int, metavar="N",
                   help="scenes at once (default: the usable CPUs over the largest np)")
    q.set_defaults(func=cmd_sweep)

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
    p.set_defaults(func=cmd_report)
