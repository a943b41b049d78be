"""The `filmscale` command line: a thin layer over the library.

Exit status: 0 success; 2 bad input (one line naming the field, no traceback); 1 a valid
question the model cannot answer (an approach that would exceed the sphere radius), or a
LAMMPS run that stopped with an error (its message and run directory).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import signal
import sys
import time
from pathlib import Path

from typing import TYPE_CHECKING

import numpy as np

from filmscale.core.checks import MASS_RANGE, RADIUS_RANGE, VELOCITY_RANGE, check_real
from filmscale.core.errors import FilmscaleError, InputError
from filmscale.core.files import atomic_path, shown
from filmscale.core.jsonable import dumps
from filmscale.core.quantities import eng

from . import calibrate_cli, indent_calibrate, indent_cli, md_cli, particles_cli, pipeline_cli
from .quantity_args import add_quantity_argument, convert_quantities, range_arg
from .outputs import (add_force_argument, check_outputs, hdf5_kind, image_kind, output_path,
                      plot_path, scene_files, text_kind)

if TYPE_CHECKING:
    from .scene import Scene

# The physics (scipy), the scene reader and the result files are imported inside each command,
# so that `filmscale --help` and a usage error answer without loading them.

#: what argparse takes for a value, not an option, after an option: a negative number in any
#: form float() reads (-5e6, -1e-9, -.5, -inf) and a range or list that starts with one
#: (-1:1:3); argparse's own pattern knows only -5 and -.5
NEGATIVE_VALUE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


class _Version(argparse.Action):
    """--version, reading the version only when asked (importlib.metadata is slow)."""

    def __call__(self, parser, namespace, values, option_string=None):
        from filmscale import __version__
        print(f"filmscale {__version__}")
        parser.exit()


class Parser(argparse.ArgumentParser):
    """filmscale's argument parser, subcommands included: negative numbers are values
    (`NEGATIVE_VALUE`; the range checks then judge them), and a usage error is one line."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_VALUE

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _range_arg(text: str) -> tuple[float, float, int]:
    parts = text.split(":")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"expected MIN:MAX:N, got {text!r}")
    try:
        low, high = float(parts[0]), float(parts[1])
        count = int(parts[2])
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers MIN:MAX:N, got {text!r}") from None
    return low, high, count


def _extreme(reduce, values) -> float:
    """max or min over the finite values; NaN if there are none."""
    finite = values[np.isfinite(values)]
    return float(reduce(finite)) if finite.size else math.nan


HISTORY_HEADER = ("time [s], delta [m], velocity [m/s], force [N], contact_radius [m], "
                  "mean_pressure [Pa], phase, branch")
#: a cylinder's line contact has a half-width, not a radius
CYLINDER_HISTORY_HEADER = HISTORY_HEADER.replace("contact_radius", "contact_half_width")
#: either history may replace the other without --force
HISTORY_KIND = text_kind((HISTORY_HEADER, CYLINDER_HISTORY_HEADER), "an impact history")


def _scene_files(scene: Scene) -> list[tuple[str, Path]]:
    """The scene file and the files it reads."""
    import tomllib
    return [("the input scene", Path(scene.source)),
            *scene_files(Path(scene.source).parent, tomllib.loads(scene.text))]


def _history_csv(history, size, header: str, path: Path) -> None:
    """One row per sample; ``size`` is the contact radius or half-width column (m)."""
    data = np.column_stack([history.time, history.delta, history.velocity, history.force,
                            size, history.mean_pressure, history.phase, history.branch])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=header, comments="",
                   fmt=["%.17g"] * 6 + ["%d", "%d"])


def cmd_impact(args) -> int:
    from .scene import load_scene
    scene = load_scene(args.scene)
    imp = scene.impactor
    def option(name, value, default, bounds, unit):
        if value is None:
            return default
        return check_real(name, value, low=bounds[0], high=bounds[1], low_open=True, unit=unit)

    V = option("--velocity", args.velocity, imp.velocity, VELOCITY_RANGE, "m/s")
    R = option("--radius", args.radius, imp.radius, RADIUS_RANGE, "m")
    m = option("--mass", args.mass, imp.mass, MASS_RANGE, "kg")
    if imp.shape == "cylinder":
        return _cylinder_impact(args, scene, V, R, m)
    _check_history_outputs(args, scene)
    model = scene.model()
    want_history = args.history or args.plot or scene.path == "time"
    if want_history:
        history = model.history(V, R, m, rtol=scene.rtol)
        result = history.result
        _write_history(args, history, history.contact_radius, HISTORY_HEADER)
    else:
        result = model.maxima(V, R, m).result(())
    angle = imp.angle if args.angle is None else check_real(
        "--angle", args.angle, low=0.0, high=90.0, high_open=True, unit="degrees")
    if angle > 0:       # the normal result above stays in the history; friction adds no cost
        from filmscale.continuum.contact.oblique import solve_oblique
        result = solve_oblique(model, V, R, m, angle, scene.friction,
                               inertia_factor=imp.inertia_factor,
                               path="time" if want_history else "fast", rtol=scene.rtol)
    if args.json:
        print(dumps(result.to_dict()))
    else:
        print(result.summary())
    return 0


def _check_history_outputs(args, scene: Scene) -> None:
    output_path("--history", args.history)
    plot_path("--plot", args.plot)
    check_outputs(_scene_files(scene), [("--history", args.history, HISTORY_KIND),
                                        ("--plot", args.plot, image_kind(args.plot))],
                  args.force)


def _write_history(args, history, size, header: str) -> None:
    """The --history table and the --plot of a sphere or cylinder history."""
    if args.history:
        _history_csv(history, size, header, Path(args.history))
    if args.plot:
        from .plots import plot_history
        plot_history(history, args.plot)


def _cylinder_impact(args, scene: Scene, V, R, m) -> int:
    """`filmscale impact` on a cylinder scene: a normal impact, its maxima or its history."""
    if args.angle:
        raise InputError("--angle applies to sphere impactors: the cylinder model is a "
                         "normal impact")
    _check_history_outputs(args, scene)
    model = scene.cylinder_model()
    if args.history or args.plot or scene.path == "time":
        history = model.history(V, R, m, rtol=scene.rtol)
        result = history.result
        _write_history(args, history, history.contact_half_width, CYLINDER_HISTORY_HEADER)
    else:
        result = model.maxima(V, R, m)
    print(dumps(result.to_dict()) if args.json else result.summary())
    return 0


def cmd_impact_map(args) -> int:
    from filmscale.continuum.contact.impact_map import axis, cylinder_map, impact_map
    from filmscale.continuum.contact.oblique import oblique_map

    from .scene import MapSpec, check_map_points, load_scene
    scene = load_scene(args.scene)
    cylinder = scene.impactor.shape == "cylinder"
    if cylinder and args.angle is not None:
        raise InputError("--angle maps oblique sphere impacts: a cylinder map is over (V, R) "
                         "only")
    spec = MapSpec(velocity=args.velocity or scene.map.velocity,
                   radius=args.radius or scene.map.radius,
                   spacing=args.spacing or scene.map.spacing,
                   velocity_name="--velocity" if args.velocity else "map.velocity",
                   radius_name="--radius" if args.radius else "map.radius")
    angle = scene.impactor.angle
    if args.angle is not None:      # rows: incidence angles at the scene's radius
        if spec.velocity is None:
            raise InputError("an impact map needs a velocity range: give --velocity "
                             "MIN:MAX:N or [map] velocity")
        check_map_points(spec.velocity[2], args.angle[2], spec.velocity_name, "--angle")
        velocity = axis(*spec.velocity, spec.spacing, spec.velocity_name, VELOCITY_RANGE,
                        "m/s")
        for value in args.angle[:2]:
            check_real("--angle", value, low=0.0, high=90.0, high_open=True, unit="degrees")
        angle = axis(*args.angle, "linear", "--angle", (-math.inf, 90.0))
        radius = scene.impactor.radius
    else:
        velocity, radius = spec.axes()
    oblique = np.any(np.asarray(angle) > 0)
    n_rows = np.size(angle) if args.angle is not None else radius.size
    if not (args.out or args.plot):
        raise InputError("impact-map writes --out MAP.h5, --plot MAP.png or both: give one")
    output_path("--out", args.out)
    plot_path("--plot", args.plot)
    if args.plot and (velocity.size < 2 or n_rows < 2):
        rows = "angles" if args.angle is not None else "radii"
        raise InputError(f"--plot draws contours: give at least 2 velocities and 2 {rows}")
    from .result import IMPACT_MAP_FORMAT, IMPACT_MAP_FORMAT_1
    check_outputs(_scene_files(scene),
                  [("--out", args.out, hdf5_kind((IMPACT_MAP_FORMAT, IMPACT_MAP_FORMAT_1),
                                                 "an impact map")),
                   ("--plot", args.plot, image_kind(args.plot))], args.force)
    if cylinder:
        models = _cylinder_models(scene)
    else:
        models = {"layered": scene.model()} if scene.layered else {}
        models["homogeneous"] = scene.substrate_model()
    label_of = {"layered": "layered target", "homogeneous": f"{scene.stack.substrate.name} only"}
    start = time.perf_counter()
    maps = {}
    for key, model in models.items():
        def progress(done, total, key=key):
            print(f"\r{label_of[key]}: {done}/{total} impacts", end="", file=sys.stderr,
                  flush=True)
        # cylinders: one impact at a time, tens of ms each
        large = oblique or cylinder or velocity.size * n_rows > 20_000
        if cylinder:
            maps[key] = cylinder_map(model, velocity, radius, scene.impactor.mass,
                                     progress=progress)
        elif oblique:
            maps[key] = oblique_map(model, velocity, radius, scene.impactor.mass, angle,
                                    scene.friction, inertia_factor=scene.impactor.inertia_factor,
                                    rtol=scene.rtol, progress=progress)
        else:
            maps[key] = impact_map(model, velocity, radius, scene.impactor.mass,
                                   progress=progress if large else None)
        print(f"{chr(13) if large else ''}{label_of[key]}: {velocity.size} x {n_rows} "
              f"impacts", file=sys.stderr)
    elapsed = time.perf_counter() - start

    from filmscale.core.provenance import provenance

    from .result import write_impact_maps
    described = {k: m.describe() | ({"friction": scene.friction,
                                     "inertia_factor": scene.impactor.inertia_factor}
                                    if oblique else {}) for k, m in models.items()}
    out = None
    if args.out:
        out = write_impact_maps(args.out, maps, described,
                                provenance(command=" ".join(sys.argv),
                                           scene_source=scene.source), scene.text)
    if args.plot:
        from .plots import plot_impact_maps
        what = (f"cylinder L = {scene.impactor.length:g} m" if cylinder else scene.law.name)
        plot_impact_maps({label_of[k]: v for k, v in maps.items()}, args.plot,
                         title=scene.title or f"{what}, m = {scene.impactor.mass:g} kg")
    summary = {"out": str(out) if out else None, "plot": args.plot, "seconds": round(elapsed, 3),
               "points": int(velocity.size * n_rows)}
    for key, mp in maps.items():
        summary[key] = {"out_of_range": int(mp.out_of_range.sum()),
                        "yielded": int(mp.yielded.sum())}
        summary[key].update({f: _extreme(np.max, mp.field(f))
                             for f in mp.fields if f != "restitution"})
        summary[key]["restitution_min"] = _extreme(np.min, mp.field("restitution"))
        if oblique:
            e_x = mp.field("restitution_tangential")
            summary[key].update(restitution_tangential_min=_extreme(np.min, e_x),
                                restitution_tangential_max=_extreme(np.max, e_x))
    if args.json:
        print(dumps(summary))
    else:
        print(f"wrote {' and '.join(str(f) for f in (out, args.plot) if f)}"
              + f": {summary['points']} points per target in {elapsed:.2f} s")
        for key in maps:
            s = summary[key]
            print(f"  {label_of[key]}: largest approach {eng(s['delta_max'], 'm')}, largest "
                  f"mean pressure {eng(s['mean_pressure_max'], 'Pa')}, smallest e_y "
                  f"{s['restitution_min']:.4f}, yielded at {s['yielded']} points, "
                  f"{s['out_of_range']} points beyond the model's range "
                  f"({maps[key].range_limit})")
    return 0


def _cylinder_models(scene: Scene) -> dict:
    """The cylinder model of the full target and of the bare substrate."""
    models = {"layered": scene.cylinder_model()} if scene.layered else {}
    models["homogeneous"] = scene.cylinder_model(bare_substrate=True)
    return models


def cmd_indent_reverse(args) -> int:
    from filmscale.continuum.indentation.reverse.dao import dao_reverse
    from filmscale.continuum.indentation.reverse.dual import dual_reverse

    common = dict(tip=args.tip, nu=args.nu, E_i=args.E_i, nu_i=args.nu_i, C_std=args.C_std,
                  dPdh_std=args.dPdh_std, WpWt_std=args.WpWt_std, h_m_std=args.hm_std,
                  method=args.method, samples=args.samples, seed=args.seed)
    if (args.C2 is None) != (args.tip2 is None):
        raise InputError("the dual-indenter analysis needs both --C2 and --tip2")
    if args.C2 is not None:
        result = dual_reverse(args.C, args.dPdh, args.WpWt, args.hm, args.C2, tip2=args.tip2,
                              C2_std=args.C2_std, **common)
    else:
        result = dao_reverse(args.C, args.dPdh, args.WpWt, args.hm, **common)
    if args.json:
        print(dumps(result.to_dict()))
    else:
        print(result.summary())
    for warning in result.warnings:
        print(f"filmscale: warning: {warning}", file=sys.stderr)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="filmscale",
        description="Multiscale contact, indentation and impact analysis of thin films.")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and exit")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("impact", help="one normal impact of the scene's sphere or cylinder",
                       description="Maxima of one normal impact (fast energy quadrature), or "
                                   "its time history with --history/--plot.")
    p.add_argument("scene", help="scene file (TOML)")
    add_quantity_argument(p, "--velocity", "m/s",
                          help="normal impact velocity V: m/s, or with units (0.5 m/s)")
    add_quantity_argument(p, "--radius", "m", help="sphere radius R: m, or with units (10 um)")
    add_quantity_argument(p, "--mass", "kg", help="impacting mass m: kg, or with units (1.6 mg)")
    p.add_argument("--angle", type=float, metavar="DEG",
                   help="incidence from the normal in degrees, V staying the normal speed: an "
                        "oblique impact with the scene's [contact] friction (default: the "
                        "scene's impactor.angle)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--history", metavar="FILE.csv",
                   help="integrate in time and write the history (SI units)")
    p.add_argument("--plot", metavar="FILE.png", help="integrate in time and plot P-delta, "
                                                      "delta(t) and P(t)")
    add_force_argument(p)
    p.set_defaults(func=cmd_impact)

    p = sub.add_parser("impact-map", help="impact maxima over a (V, R) grid",
                       description="Impact maps of the layered target and of its bare "
                                   "substrate, to HDF5 (SI) and contour plots.")
    p.add_argument("scene", help="scene file (TOML)")
    add_quantity_argument(p, "--velocity", "m/s", type=range_arg, metavar="MIN:MAX:N",
                          help="velocity axis in m/s or with units, 1mm/s:2m/s:60 (default: "
                               "the scene's [map])")
    rows = p.add_mutually_exclusive_group()
    add_quantity_argument(rows, "--radius", "m", type=range_arg, metavar="MIN:MAX:N",
                          help="radius axis in m or with units, 1um:50um:60 (default: the "
                               "scene's [map])")
    rows.add_argument("--angle", type=_range_arg, metavar="MIN:MAX:N",
                      help="incidence axis in degrees (linear) at the scene's radius instead: "
                           "oblique impacts with the scene's [contact] friction, about 0.5 s "
                           "per point that neither slides throughout nor lacks friction")
    p.add_argument("--spacing", choices=("log", "linear"), help="axis spacing (default log)")
    p.add_argument("--out", metavar="MAP.h5", help="HDF5 result file (--out, --plot or both)")
    p.add_argument("--plot", metavar="MAP.png", help="contour plots")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    add_force_argument(p)
    p.set_defaults(func=cmd_impact_map)

    indent = sub.add_parser("indent", help="indentation analysis: Oliver-Pharr, reverse analysis",
                            description="Analyse indentation load-displacement curves.")
    isub = indent.add_subparsers(dest="indent_command", required=True)
    indent_cli.add_parser(isub)
    indent_calibrate.add_parser(isub)

    p = isub.add_parser("reverse", help="E*, sigma_r, n, sigma_y from a sharp-tip curve (Dao)",
                        description="Reverse analysis of sharp indentation (Dao et al. 2001): "
                                    "from the loading curvature C, the unloading slope dP/dh, "
                                    "W_p/W_t and the maximum depth h_m to E*, the 3.3 % "
                                    "representative stress sigma_r, n and sigma_y, each with "
                                    "its standard deviation (Monte Carlo over the inputs' "
                                    "standard deviations). With --C2/--tip2: dual indenter "
                                    "(Chollacoop, Dao & Suresh 2003). SI units.")
    add_quantity_argument(p, "--C", "Pa", required=True,
                          help="loading curvature P/h^2: Pa, or with units (30 GPa)")
    add_quantity_argument(p, "--dPdh", "N/m", required=True,
                          help="initial unloading slope: N/m, or with units (2e5 N/m)")
    p.add_argument("--WpWt", type=float, required=True, help="plastic over total work")
    add_quantity_argument(p, "--hm", "m", required=True,
                          help="maximum depth h_m: m, or with units (500 nm)")
    p.add_argument("--tip", default="berkovich", help="berkovich (default) or cone:70.3")
    p.add_argument("--WpWt-std", type=float, default=0.0, dest="WpWt_std",
                   help="standard deviation of --WpWt (default 0)")
    for name, unit in (("C", "Pa"), ("dPdh", "N/m"), ("hm", "m")):
        add_quantity_argument(p, f"--{name}-std", unit, default=0.0, dest=f"{name}_std",
                              help=f"standard deviation of --{name}, {unit} (default 0)")
    add_quantity_argument(p, "--C2", "Pa",
                          help="second tip's loading curvature, Pa (dual indenter)")
    add_quantity_argument(p, "--C2-std", "Pa", default=0.0, dest="C2_std",
                          help="standard deviation of --C2, Pa")
    p.add_argument("--tip2", help="second tip, cone:THETA with THETA in 50-80 deg")
    p.add_argument("--nu", type=float, default=0.3, help="sample Poisson ratio (default 0.3)")
    add_quantity_argument(p, "--E-i", "Pa", default=1100e9, dest="E_i",
                          help="indenter modulus, Pa (default 1100e9, as Dao et al.)")
    p.add_argument("--nu-i", type=float, default=0.07, dest="nu_i",
                   help="indenter Poisson ratio (default 0.07)")
    p.add_argument("--method", choices=("closed-form", "surrogate"), default="closed-form",
                   help="Dao's closed form (default) or the surrogate trained on the FE cases")
    p.add_argument("--samples", type=int, default=2000, help="Monte Carlo draws (default 2000)")
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.set_defaults(func=cmd_indent_reverse)
    calibrate_cli.add_commands(sub)
    md_cli.add_commands(sub)
    particles_cli.add_commands(sub)
    pipeline_cli.add_commands(sub)
    return parser


def main(argv=None) -> int:
    """The command line: returns the exit status (0 done, 2 bad input, 1 a model or engine
    failure, 130 interrupted); every failure is one line on stderr, never a traceback."""
    parser = build_parser()
    args = parser.parse_args(argv)
    # a batch system stops a job with SIGTERM: end as Ctrl-C does, so that MPI children
    # are terminated and no half-written file is kept
    previous = signal.signal(signal.SIGTERM, _terminated)
    try:
        convert_quantities(args)
        return args.func(args)
    except FilmscaleError as err:
        kind = "error: " if isinstance(err, InputError) else ""
        print(f"filmscale: {kind}{err}", file=sys.stderr)
        return err.exit_code
    except OSError as err:          # reading or writing a file: permissions, full disk, ...
        where = f"{shown(err.filename)}: " if err.filename else ""
        print(f"filmscale: error: {where}{err.strerror or err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("filmscale: interrupted; nothing half-written was kept", file=sys.stderr)
        return 130
    except Exception as err:        # a defect of filmscale: one line, the traceback on request
        if os.environ.get("FILMSCALE_DEBUG"):
            raise
        print(f"filmscale: internal error ({type(err).__name__}: {err}); rerun with "
              "FILMSCALE_DEBUG=1 for the traceback and please report it", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)


def _terminated(signum, frame):
    raise KeyboardInterrupt


if __name__ == "__main__":
    sys.exit(main())
