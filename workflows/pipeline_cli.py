"""`filmscale plan`, `filmscale run` and `filmscale report`: the scene pipeline's commands."""

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

    p = sub.add_parser("report", help="self-contained HTML report of a scene result")
    p.add_argument("result", help="RESULT.h5 from filmscale run")
    p.add_argument("--out", metavar="REPORT.html", help="default: RESULT with .html")
    p.add_argument("--figure", metavar="FIGURE.png",
                   help="also a one-line PNG summary: calibration, profile, map")
    p.set_defaults(func=cmd_report)
