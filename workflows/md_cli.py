"""`filmscale md indent` and `filmscale potentials`: the atomistic commands.

Everything that can be wrong with the input (spec, potential, elements, sizes) is checked
before LAMMPS starts; the run shows its progress (`progress.progress_bar`: a bar on a
terminal, plain lines in a log) and can be interrupted and resumed by running the same
command again with the same ``--out``. The summary's Oliver-Pharr figures and flags are what
`indent analyze` gives on the run's record (`record_oliver_pharr`).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from filmscale.core.errors import InputError
from filmscale.core.jsonable import dumps
from filmscale.core.provenance import provenance
from filmscale.potentials import registry
from filmscale.potentials.registry import get_potential, verify_all
from filmscale.workflows.outputs import (add_force_argument, check_outputs, check_run_folder,
                                         image_kind, plot_path)
from filmscale.workflows.quantity_args import add_quantity_argument


def _indent_spec(args):
    from filmscale.md.spec import load_spec, preset
    if (args.spec is None) == (args.preset is None):
        raise InputError("give a spec file or --preset NAME (one of them)")
    return preset(args.preset) if args.preset else load_spec(args.spec)


def _check_plot(args) -> None:
    """--plot: a plot format, not an input, and no other file unless --force."""
    plot_path("--plot", args.plot)
    check_outputs([("the run specification", args.spec)] if args.spec else [],
                  [("--plot", args.plot, image_kind(args.plot))], args.force)


#: the figures of `indent analyze`'s record that `md indent --json` gives as "oliver_pharr"
OP_KEYS = ("E_r", "E", "H", "h_c", "A_c", "S", "status", "message", "flags", "flag_messages")


def record_oliver_pharr(record: Path, plot=None) -> dict:
    """What `filmscale indent analyze RECORD` gives on the run's record (the same function,
    its defaults: the record's tip, drift, surface): E_r, H and the flags; ``plot``: its
    load-displacement curve with the Oliver-Pharr fit drawn there."""
    from .indent import AnalysisOptions, analyze_file
    return analyze_file(record, AnalysisOptions(), plot_file=plot)[0]


def oliver_pharr_text(r: dict) -> str:
    """The summary's Oliver-Pharr line of `record_oliver_pharr`, one line per flag under it."""
    head = "Oliver-Pharr (as indent analyze on the record): "
    if r.get("status") == 0:
        head += (f"E_r {r['E_r'] * 1e-9:.1f} GPa, H {r['H'] * 1e-9:.2f} GPa, A_c "
                 f"{r['A_c'] * 1e18:.2f} nm^2")
    else:
        head += f"not analysed: {r.get('message', '')}"
    flags = r.get("flags", [])
    messages = list(r.get("flag_messages", [])) + [""] * len(flags)
    if not flags:
        return head + "; no flags"
    return "\n".join([f"{head}; flags: {', '.join(flags)}"] +
                     [f"  {code}: {text}" if text else f"  {code}"
                      for code, text in zip(flags, messages)])


def _json(run, analysis, record: Path, op: dict, plot) -> dict:
    return {"P_max": analysis.P_max, "h_max": analysis.h_max,
            "residual_depth": analysis.residual_depth,
            "E_r_hertz": analysis.E_r_hertz, "E_star": analysis.E_star,
            "hertz_ratio": analysis.hertz_ratio, "M": analysis.M,
            "hertz_ratio_M": analysis.hertz_ratio_M,
            "hertz_offset": analysis.hertz_offset, "popin_load": analysis.popin_load,
            "popin_depth": analysis.popin_depth,
            "popin_shear_stress": analysis.popin_shear_stress,
            "contact_area_md": analysis.contact_area_md,
            "contact_area_op": analysis.op.A_c if analysis.op is not None else None,
            "pile_up": analysis.pile_up, "n_atoms": run.n_atoms,
            "n_steps": run.n_steps, "wall_time": run.wall_time,
            "result": str(record), "oliver_pharr": {k: op.get(k) for k in OP_KEYS},
            "plot": plot}


def _print_summary(run, analysis, elastic, record: Path, op: dict, plot) -> None:
    from filmscale.md.analysis import HERTZ_TOLERANCE
    print(elastic.summary())
    print(analysis.summary(oliver_pharr=oliver_pharr_text(op)))
    if math.isfinite(analysis.hertz_ratio) and \
            abs(analysis.hertz_ratio - 1.0) > HERTZ_TOLERANCE:
        print(f"note: the Hertzian segment departs from the potential's E* by more than "
              f"{HERTZ_TOLERANCE:.0%} (a film on a stiffer or softer substrate does)")
    if plot:
        print(f"plot: {plot}")
    print(f"record: {record}  ({run.wall_time:.1f} s in LAMMPS)")


def _with_blocks(spec, out: Path, engine, args):
    """``spec`` with the blocks of the films it names by recipe, made in (or reused from)
    the store ``--blocks`` (default: ``blocks`` in the run directory)."""
    from filmscale.workflows.amorphous_units import with_blocks
    store = Path(args.blocks) if args.blocks else out / "blocks"
    if store.exists() and not store.is_dir():
        raise InputError(f"--blocks {store} is a file, not a folder")
    return with_blocks(spec, store, engine, quiet=args.json)


def cmd_md_indent(args) -> int:
    from filmscale.md.amorphous_run import layer_elastic_constants
    from filmscale.md.analysis import analyze_indentation
    from filmscale.md.engine import EngineOptions
    from filmscale.md.lammps_input import run_dir_for
    from filmscale.md.record import write_record
    from filmscale.md.run import run_indentation

    spec = _indent_spec(args)
    engine = EngineOptions(np=args.np, omp_threads=args.omp)
    out = Path(args.out) if args.out else run_dir_for("md_runs", spec.name)
    check_run_folder("--out", out, [("the run specification", args.spec)] if args.spec else [],
                     args.force)
    _check_plot(args)
    spec = _with_blocks(spec, out, engine, args)
    slab = spec.slab_built
    if not args.json:
        print(f"{spec.name}: {slab.n_atoms} atoms, {spec.protocol.schedule().s_end} steps, "
              f"{engine.to_dict()['mode']} with {args.np} rank(s); run directory {out}",
              file=sys.stderr)

    from filmscale.workflows.progress import with_step_progress
    run = with_step_progress(spec.protocol.schedule().s_end, spec.name,
                             lambda progress: run_indentation(spec, out, engine,
                                                              progress=progress))
    top = (spec.slab.films or (spec.slab.substrate,))[0]
    elastic = layer_elastic_constants(spec.potential, top, out / "elastic")
    analysis = analyze_indentation(run, elastic)
    record = write_record(run, analysis, elastic, provenance=provenance(
        command="filmscale " + " ".join(sys.argv[1:])))
    op = record_oliver_pharr(record, args.plot)
    if args.json:
        print(dumps(_json(run, analysis, record, op, args.plot)))
    else:
        _print_summary(run, analysis, elastic, record, op, args.plot)
    return 0


def _scratch_spec(args):
    from filmscale.md.scratch import load_scratch_spec, scratch_preset
    if (args.spec is None) == (args.preset is None):
        raise InputError("give a spec file or --preset NAME (one of them)")
    return scratch_preset(args.preset) if args.preset else load_scratch_spec(args.spec)


#: the figures of `md scratch --json` (SI: N, m; friction a pure number)
SCRATCH_KEYS = ("friction_mean", "friction_std", "normal_force_mean", "normal_force_sem",
                "normal_load", "lateral_force_mean", "depth_mean", "depth_std",
                "groove_depth", "groove_width", "pileup_height", "edge_height",
                "scratch_hardness", "steady_points")


def _print_scratch(run, a, record: Path, plot=None) -> None:
    print(f"friction {a.friction_mean:.3f} +- {a.friction_std:.3f} over {a.steady_points} "
          f"points of the steady stroke; normal force {a.normal_force_mean * 1e9:.2f} nN, "
          f"lateral force {a.lateral_force_mean * 1e9:.2f} nN")
    if run.control is not None:
        print(f"constant load: target {a.normal_load * 1e9:.2f} nN, measured "
              f"{a.normal_force_mean * 1e9:.2f} +- {a.normal_force_sem * 1e9:.2f} nN (standard "
              f"error); depth {a.depth_mean * 1e9:.3f} +- {a.depth_std * 1e9:.3f} nm")
    print(f"residual groove at mid-stroke: depth {a.groove_depth * 1e9:.3f} nm, width "
          f"{a.groove_width * 1e9:.3f} nm, pile-up {a.pileup_height * 1e9:.3f} nm "
          f"(edge of the profile {a.edge_height * 1e9:+.3f} nm)")
    if len(a.passes) > 1:
        for x in a.passes:
            print(f"pass {x.number}: friction {x.friction_mean:.3f} +- {x.friction_std:.3f}, "
                  f"normal force {x.normal_force_mean * 1e9:.2f} nN")
    if math.isfinite(a.scratch_hardness):
        print(f"scratch hardness 8 F_n / (pi w^2): {a.scratch_hardness / 1e9:.3f} GPa")
    for d in a.damage:
        print(f"damage (eta_Mises > {a.damage_threshold:g}) in {d.layer}: width "
              f"{d.width * 1e9:.3f} nm, depth {d.depth * 1e9:.3f} nm ({d.atoms} atoms)")
    if plot:
        print(f"plot: {plot}")
    print(f"record: {record}  ({run.wall_time:.1f} s in LAMMPS)")


def cmd_md_scratch(args) -> int:
    from filmscale.md.engine import EngineOptions
    from filmscale.md.lammps_input import run_dir_for
    from filmscale.md.scratch_run import (analyze_scratch, run_scratch, scratch_json,
                                          write_scratch_record)
    from filmscale.workflows.progress import with_step_progress

    spec = _scratch_spec(args)
    engine = EngineOptions(np=args.np, omp_threads=args.omp)
    out = Path(args.out) if args.out else run_dir_for("md_runs", spec.name)
    check_run_folder("--out", out, [("the run specification", args.spec)] if args.spec else [],
                     args.force)
    _check_plot(args)
    spec = _with_blocks(spec, out, engine, args)
    total = spec.schedule().s_end
    if not args.json:
        print(f"{spec.name}: {spec.indent.slab_built.n_atoms} atoms, {total} steps, "
              f"{args.np} rank(s); run directory {out}", file=sys.stderr)
    run = with_step_progress(total, spec.name,
                             lambda progress: run_scratch(spec, out, engine, progress=progress))
    analysis = analyze_scratch(run)
    record = write_scratch_record(run, analysis, provenance=provenance(
        command="filmscale " + " ".join(sys.argv[1:])))
    if args.plot:
        from filmscale.workflows.scratch_plots import plot_scratch, scratch_figure_data
        plot_scratch(scratch_figure_data(run, analysis), args.plot)
    if args.json:
        print(dumps({**scratch_json(analysis, SCRATCH_KEYS), "n_atoms": run.n_atoms, "n_steps": run.n_steps,
                     "wall_time": run.wall_time, "result": str(record), "plot": args.plot}))
    else:
        _print_scratch(run, analysis, record, args.plot)
    return 0


#: the figures of `md amorphous --json` (SI: kg/m^3, Pa, J, m; fractions and nu plain)
AMORPHOUS_KEYS = ("density", "sp3_fraction", "sp2_fraction", "sp_fraction", "other_fraction",
                  "mean_coordination", "bond_cutoff", "E", "nu", "E_std", "nu_std", "K", "G",
                  "axial_spread", "shear_ratio", "residual_stress", "energy_per_atom")


def _amorphous_recipe(args):
    from filmscale.md.amorphous import amorphous_preset, load_recipe, with_density
    if (args.spec is None) == (args.preset is None):
        raise InputError("give a recipe file or --preset NAME (one of them)")
    recipe = amorphous_preset(args.preset) if args.preset else load_recipe(args.spec)
    return recipe if args.density is None else with_density(recipe, args.density)


#: the figures an ensemble of quench seeds averages (`md amorphous --seeds N`)
ENSEMBLE_KEYS = ("density", "sp3_fraction", "sp2_fraction", "sp_fraction", "mean_coordination",
                 "E", "nu", "K", "G", "residual_stress", "energy_per_atom")


def _ensemble(summaries: list[dict]) -> tuple[dict, dict]:
    """Mean and sample standard deviation over the seeds of each `ENSEMBLE_KEYS` figure."""
    import numpy as np
    values = {k: np.array([s[k] for s in summaries], float) for k in ENSEMBLE_KEYS}
    return ({k: float(v.mean()) for k, v in values.items()},
            {k: float(v.std(ddof=1)) for k, v in values.items()})


def cmd_md_amorphous(args) -> int:
    """Make (or reuse) the amorphous block of a recipe, or of ``--seeds N`` quench seeds
    (seed, seed + 1, ...): each a unit of the store ``--out`` (default md_runs) named by the
    hash of its recipe (`workflows.store`)."""
    import dataclasses

    from filmscale.md.amorphous_run import RECORD_NAME, read_amorphous_summary, summary_lines
    from filmscale.md.engine import EngineOptions
    from filmscale.workflows.amorphous_units import amorphous_unit

    recipe = _amorphous_recipe(args)
    if isinstance(args.seeds, bool) or not 1 <= args.seeds <= 64:
        raise InputError(f"--seeds {args.seeds} must be an integer in [1, 64]")
    engine = EngineOptions(np=args.np, omp_threads=args.omp)
    store = Path(args.out) if args.out else Path("md_runs")
    if store.exists() and not store.is_dir():
        raise InputError(f"--out {store} is a file, not a folder")
    rows = []
    for k in range(args.seeds):
        seeded = dataclasses.replace(recipe, seed=recipe.seed + k)
        unit, reused = amorphous_unit(seeded, store, engine, quiet=args.json)
        summary = read_amorphous_summary(unit / RECORD_NAME)
        rows.append({**{key: summary[key] for key in AMORPHOUS_KEYS}, "seed": seeded.seed,
                     "n_atoms": summary["n_atoms"], "wall_time": summary["wall_time"],
                     "reused": reused, "unit": str(unit), "result": str(unit / RECORD_NAME)})
        if not args.json:
            print("\n".join(summary_lines(summary, seeded)))
            print(f"record: {unit / RECORD_NAME}  ({'reused' if reused else 'made'}, "
                  f"{summary['wall_time']:.1f} s in LAMMPS)")
    if args.seeds == 1:
        if args.json:
            print(dumps({k: v for k, v in rows[0].items() if k != "seed"}))
        return 0
    mean, std = _ensemble(rows)
    if args.json:
        print(dumps({**mean, "E_std": std["E"], "nu_std": std["nu"],
                     "sp3_fraction_std": std["sp3_fraction"],
                     "residual_stress_std": std["residual_stress"], "ensemble_std": std,
                     "seeds": rows}))
    else:
        print(f"ensemble of {args.seeds} seeds (mean +- sample std): sp3 "
              f"{mean['sp3_fraction']:.3f} +- {std['sp3_fraction']:.3f}, E "
              f"{mean['E'] / 1e9:.1f} +- {std['E'] / 1e9:.1f} GPa, nu {mean['nu']:.3f} +- "
              f"{std['nu']:.3f}, density {mean['density']:.1f} kg/m^3")
    return 0


def cmd_potentials(args) -> int:
    if args.action == "list":
        for pot in registry().values():
            print(f"{pot.name:14s} {' '.join(pot.elements):10s} {pot.pair_style:16s} "
                  f"{pot.file}")
        return 0
    if args.action == "show":
        if not args.name:
            raise InputError("potentials show needs a NAME (see: filmscale potentials list)")
        print(get_potential(args.name).summary())
        return 0
    failed = 0
    for name, status in verify_all():
        print(f"{name:14s} {status}")
        failed += status != "ok"
    return 2 if failed else 0


#: the built-in specs of `md indent` and `particles` (md.spec.PRESETS and
#: md.particle_spec.PRESETS, named here so that --help does not import the MD layer)
PRESET_NAMES = ("ci", "quick", "research")
#: shown in the help; not argparse choices, so that a wrong name is the presets' own
#: InputError (exit 2 from main, as every bad input)
PRESET_METAVAR = "{" + ",".join(PRESET_NAMES) + "}"


def add_arguments(sub) -> None:
    """Register ``md`` and ``potentials`` on the top-level subparsers."""
    md = sub.add_parser("md", help="LAMMPS molecular dynamics runs")
    msub = md.add_subparsers(dest="md_command", required=True)
    p = msub.add_parser("indent", help="atomistic nanoindentation of a film stack",
                        description="Run (or resume, with the same --out) an MD indentation, "
                                    "analyse its curve and write the HDF5 record.")
    p.add_argument("spec", nargs="?", metavar="SPEC.toml", help="run specification")
    p.add_argument("--preset", metavar=PRESET_METAVAR,
                   help="a built-in spec instead of a spec file: ci (seconds), quick (minutes "
                        "on 2 cores) or research (sizes for a study, for MPI on many cores)")
    p.add_argument("--np", type=int, default=1, help="MPI ranks (default 1: the library)")
    p.add_argument("--omp", type=int, default=1, help="OpenMP threads per rank (default 1)")
    p.add_argument("--out", metavar="DIR", help="run directory (default md_runs/NAME)")
    p.add_argument("--blocks", metavar="STORE", help="store of the amorphous blocks "
                   "that films name by recipe (default DIR/blocks)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.add_argument("--plot", metavar="FILE.png",
                   help="plot the load-displacement curve with its Oliver-Pharr fit (as "
                        "indent analyze --plot draws it)")
    add_force_argument(p)
    p.set_defaults(func=cmd_md_indent)

    p = msub.add_parser("scratch", help="atomistic nanoscratch with a rigid sphere or cone",
                        description="Run (or resume, with the same --out) an MD scratch at "
                                    "constant depth or constant load, analyse friction and "
                                    "residual groove and write the HDF5 record.")
    p.add_argument("spec", nargs="?", metavar="SPEC.toml", help="run specification")
    p.add_argument("--preset", metavar="{ci,quick,research}",
                   help="a built-in spec: ci (under a minute on 2 cores), quick (minutes) or "
                        "research (sizes for a study, for MPI on many cores)")
    p.add_argument("--np", type=int, default=1, help="MPI ranks (default 1: the library)")
    p.add_argument("--omp", type=int, default=1, help="OpenMP threads per rank (default 1)")
    p.add_argument("--out", metavar="DIR", help="run directory (default md_runs/NAME)")
    p.add_argument("--blocks", metavar="STORE", help="store of the amorphous blocks "
                   "that films name by recipe (default DIR/blocks)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.add_argument("--plot", metavar="FILE.png",
                   help="plot the forces and friction against the sliding distance, the "
                        "residual groove profile and the cross-section of the plastic zone")
    add_force_argument(p)
    p.set_defaults(func=cmd_md_scratch)

    p = msub.add_parser("amorphous", help="an amorphous carbon block by melt-quench",
                        description="Make (or reuse) an amorphous block: random start at the "
                                    "target density, liquid, quench and anneal at fixed "
                                    "volume, then its density, sp3/sp2/sp fractions, radial "
                                    "distribution, residual stress, energy and elastic "
                                    "constants, in a unit named by the hash of the recipe.")
    p.add_argument("spec", nargs="?", metavar="RECIPE.toml", help="melt-quench recipe")
    p.add_argument("--preset", metavar=PRESET_METAVAR,
                   help="a built-in recipe: ci (512 atoms, under a minute), quick (4096 "
                        "atoms, minutes) or research (32768 atoms, for MPI on many cores)")
    add_quantity_argument(p, "--density", "kg/m^3",
                          help="target density, e.g. 3.0g/cm3 (default: the recipe's)")
    p.add_argument("--np", type=int, default=1, help="MPI ranks (default 1: the library)")
    p.add_argument("--omp", type=int, default=1, help="OpenMP threads per rank (default 1)")
    p.add_argument("--out", metavar="DIR", help="the store the unit is kept in (default "
                                                "md_runs)")
    p.add_argument("--seeds", type=int, default=1, metavar="N",
                   help="quench N seeds (the recipe's, +1, ...), each a unit; --json gives "
                        "their mean, their scatter and each seed's figures")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.set_defaults(func=cmd_md_amorphous)

    p = sub.add_parser("potentials", help="the interatomic potentials filmscale knows",
                       description="The interatomic potentials in filmscale's registry: list "
                                   "them, show one (elements, citation, file and its SHA-256) "
                                   "or verify every file against its checksum (exit 2 when "
                                   "one differs).")
    p.add_argument("action", choices=("list", "show", "verify"),
                   help="list every potential, show NAME, or verify the files' checksums")
    p.add_argument("name", nargs="?", help="potential name (for show)")
    p.set_defaults(func=cmd_potentials)
