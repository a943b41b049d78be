"""`filmscale particles indent|impact`: the particle continuum models (SPH, peridynamics).

The spec (or preset) is checked in full before LAMMPS starts; bad input exits with status 2
and one line. The run shows its progress (`progress.progress_bar`: a bar on a terminal, plain
lines with the time left in a log); ``--json`` prints one object in SI.
"""

from __future__ import annotations

import sys
from pathlib import Path

from filmscale.core.errors import InputError
from filmscale.core.jsonable import dumps
from filmscale.core.provenance import provenance
from filmscale.workflows.md_cli import PRESET_METAVAR
from filmscale.workflows.outputs import (add_force_argument, check_outputs, check_run_folder,
                                         image_kind, plot_path)


def _spec(args):
    from filmscale.md.particle_spec import load_spec, preset
    if (args.spec is None) == (args.preset is None):
        raise InputError("give a spec file or --preset NAME (one of them)")
    if args.preset:
        return preset(args.preset, args.kind, args.method)
    return load_spec(args.spec, args.kind, args.method)


def cmd_particles(args) -> int:
    from filmscale.md.engine import EngineOptions
    from filmscale.md.lammps_input import run_dir_for
    from filmscale.md.particle_inputs import estimated_steps
    from filmscale.md.particle_run import (analyze_impact, analyze_indent, run_particles,
                                           write_particle_record)

    spec = _spec(args)
    engine = EngineOptions(np=args.np, omp_threads=1)
    out = Path(args.out) if args.out else run_dir_for("md_runs", f"particles-{spec.name}")
    check_run_folder("--out", out, [("the run specification", args.spec)] if args.spec else [],
                     args.force)
    total = estimated_steps(spec)
    if not args.json:
        print(f"{spec.name}: {spec.method}, {spec.grid.n_particles} particles, about {total} "
              f"steps, {args.np} rank(s); run directory {out}", file=sys.stderr)

    from filmscale.workflows.progress import with_step_progress
    run = with_step_progress(total, spec.name,
                             lambda progress: run_particles(spec, out, engine, progress=progress))
    result = analyze_impact(run) if args.kind == "impact" else analyze_indent(run)
    record = write_particle_record(run, result, provenance(
        command="filmscale " + " ".join(sys.argv[1:])))
    if args.json:
        d = result.to_dict()
        if args.kind == "impact":
            d["h_max"] = d["delta_max"]
        d["result"] = str(record)
        print(dumps(d))
    else:
        print(result.summary())
        print(f"record: {record}")
    return 0


def cmd_particles_scratch(args) -> int:
    from filmscale.md.engine import EngineOptions
    from filmscale.md.lammps_input import run_dir_for
    from filmscale.md.particle_scratch import estimated_steps, load_spec, preset
    from filmscale.md.particle_scratch_run import (JSON_KEYS, analyze_scratch, run_scratch,
                                                   write_scratch_record)
    from filmscale.md.scratch_run import scratch_json
    from filmscale.workflows.progress import with_step_progress

    if (args.spec is None) == (args.preset is None):
        raise InputError("give a spec file or --preset NAME (one of them)")
    spec = preset(args.preset) if args.preset else load_spec(args.spec)
    engine = EngineOptions(np=args.np, omp_threads=1)
    out = Path(args.out) if args.out else run_dir_for("md_runs", f"particles-{spec.name}")
    inputs = [("the run specification", args.spec)] if args.spec else []
    check_run_folder("--out", out, inputs, args.force)
    plot_path("--plot", args.plot)
    check_outputs(inputs, [("--plot", args.plot, image_kind(args.plot))], args.force)
    total = estimated_steps(spec)
    if not args.json:
        print(f"{spec.name}: {spec.method} scratch, {spec.grid.n_particles} particles, about "
              f"{total} steps, {args.np} rank(s); run directory {out}", file=sys.stderr)
    run = with_step_progress(total, spec.name,
                             lambda progress: run_scratch(spec, out, engine, progress=progress))
    analysis = analyze_scratch(run)
    record = write_scratch_record(run, analysis, provenance(
        command="filmscale " + " ".join(sys.argv[1:])))
    if args.plot:
        from filmscale.workflows.scratch_plots import particle_scratch_figure_data, plot_scratch
        plot_scratch(particle_scratch_figure_data(run, analysis), args.plot)
    if args.json:
        print(dumps({**scratch_json(analysis, JSON_KEYS), "particles": analysis.particles, "steps": analysis.steps,
                     "wall_time": analysis.wall_time, "result": str(record),
                     "plot": args.plot}))
    else:
        print(analysis.summary())
        if args.plot:
            print(f"plot: {args.plot}")
        print(f"record: {record}")
    return 0


def add_arguments(sub) -> None:
    """Register ``particles`` on the top-level subparsers."""
    p = sub.add_parser("particles", help="SPH and peridynamics particle models in LAMMPS")
    psub = p.add_subparsers(dest="particles_command", required=True)
    # ULSPH models indentation only (md/particles.py); the impact offers what it runs
    for kind, text, methods in (
            ("indent", "quasi-static indentation (load, hold, unload)", ("tlsph", "peri", "ulsph")),
            ("impact", "impact of a free rigid sphere", ("tlsph", "peri"))):
        q = psub.add_parser(kind, help=text,
                            description=f"Run a particle-model {text}, analyse it and write "
                                        "the HDF5 record (particles.h5 in the run directory).")
        q.add_argument("spec", nargs="?", metavar="SPEC.toml", help="run specification")
        q.add_argument("--preset", metavar=PRESET_METAVAR,
                       help="a built-in spec instead of a spec file: ci (seconds), quick "
                            "(minutes on 2 cores) or research (sizes for a study, for MPI on "
                            "many cores)")
        q.add_argument("--method", choices=methods,
                       help="override the spec's method")
        q.add_argument("--np", type=int, default=1, help="MPI ranks (default 1: the library)")
        q.add_argument("--out", metavar="DIR",
                       help="run directory (default md_runs/particles-NAME)")
        q.add_argument("--json", action="store_true", help="print one JSON object (SI)")
        add_force_argument(q)
        q.set_defaults(func=cmd_particles, kind=kind)
    q = psub.add_parser("scratch", help="scratch with a rigid sphere (TLSPH homogeneous, "
                                        "ULSPH layered)",
                        description="Run a particle-model scratch (down, a stroke along x, up, "
                                    "relax), analyse friction and the residual groove and "
                                    "write the HDF5 record (particle_scratch.h5).")
    q.add_argument("spec", nargs="?", metavar="SPEC.toml", help="run specification")
    q.add_argument("--preset", metavar=PRESET_METAVAR,
                   help="a built-in spec instead of a spec file: ci (elastic, seconds), quick "
                        "(a hard film on a softer layer, ULSPH, minutes) or research (sizes "
                        "for a study, for MPI on many cores)")
    q.add_argument("--np", type=int, default=1, help="MPI ranks (default 1: the library)")
    q.add_argument("--out", metavar="DIR",
                   help="run directory (default md_runs/particles-NAME)")
    q.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    q.add_argument("--plot", metavar="FILE.png",
                   help="plot the forces and friction against the sliding distance, the "
                        "residual groove profile and the cross-section of the plastic zone "
                        "per layer")
    add_force_argument(q)
    q.set_defaults(func=cmd_particles_scratch, kind="scratch")
