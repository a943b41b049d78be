"""`filmscale impact` and `filmscale impact-map`: one impact, or maps over (V, R) or (V,
angle), of whatever model kind the scene's impactor is (`continuum.contact.kinds`): the
commands ask the kind for its model, result, history and map and never test its type."""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from filmscale.core.checks import MASS_RANGE, RADIUS_RANGE, VELOCITY_RANGE, check_real
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_path
from filmscale.core.jsonable import dumps
from filmscale.core.quantities import eng

from .outputs import (add_force_argument, check_outputs, hdf5_kind, image_kind, output_path,
                      plot_path, scene_files, text_kind)
from .quantity_args import add_quantity_argument, range_arg

# The physics (scipy), the scene reader and the result files are imported inside each command,
# so that `filmscale --help` and a usage error answer without loading them.

#: the history table's columns; the contact-size column is the kind's (`ModelKind.size`)
HISTORY_HEADER = ("time [s], delta [m], velocity [m/s], force [N], contact_radius [m], "
                  "mean_pressure [Pa], phase, branch")
#: a map this large shows its progress (oblique maps, and kinds whose model takes one point
#: at a time, always do)
PROGRESS_POINTS = 20_000


def _angle_range(text: str) -> tuple[float, float, int]:
    """MIN:MAX:N of incidence angles, degrees."""
    low, high, count = range_arg(text)
    try:
        return float(low), float(high), count
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers MIN:MAX:N, got {text!r}") from None


def history_header(size: str) -> str:
    """The history table's header for a kind whose contact size is ``size``."""
    return HISTORY_HEADER.replace("contact_radius", size)


def _history_kind():
    """Any kind's history table may replace another's without --force."""
    from filmscale.continuum.contact.kinds import KINDS
    return text_kind(tuple({history_header(k.size) for k in KINDS.values()}),
                     "an impact history")


def _scene_files(scene) -> list[tuple[str, Path]]:
    """The scene file and the files it reads."""
    import tomllib
    return [("the input scene", Path(scene.source)),
            *scene_files(Path(scene.source).parent, tomllib.loads(scene.text))]


def _extreme(reduce, values) -> float:
    """max or min over the finite values; NaN if there are none."""
    finite = values[np.isfinite(values)]
    return float(reduce(finite)) if finite.size else math.nan


def _oblique_kind(scene, angle):
    """The scene's kind at incidence ``angle`` (degrees; an array for maps over angles);
    InputError naming --angle when the shape has no oblique model."""
    from filmscale.continuum.contact.kinds import KINDS, kind_for
    oblique = bool(np.any(np.asarray(angle) > 0))
    if oblique and not any(k.oblique and k.shape == scene.impactor.shape
                           for k in KINDS.values()):
        shapes = sorted({k.shape for k in KINDS.values() if k.oblique})
        raise InputError(f"--angle applies to {' and '.join(shapes)} impactors: the "
                         f"{scene.impactor.shape} model is a normal impact")
    return kind_for(scene.impactor.shape, oblique)


# --- filmscale impact ----------------------------------------------------------------------

def _point(args, scene) -> tuple[float, float, float]:
    """(V, R, m): the options where given, else the scene's."""
    imp = scene.impactor

    def option(name, value, default, bounds, unit):
        if value is None:
            return default
        return check_real(name, value, low=bounds[0], high=bounds[1], low_open=True, unit=unit)
    return (option("--velocity", args.velocity, imp.velocity, VELOCITY_RANGE, "m/s"),
            option("--radius", args.radius, imp.radius, RADIUS_RANGE, "m"),
            option("--mass", args.mass, imp.mass, MASS_RANGE, "kg"))


def _history_outputs(args, scene, kind) -> bool:
    """Whether a time history is wanted; its outputs checked against the inputs."""
    output_path("--history", args.history)
    plot_path("--plot", args.plot)
    check_outputs(_scene_files(scene), [("--history", args.history, _history_kind()),
                                        ("--plot", args.plot, image_kind(args.plot))],
                  args.force)
    wanted = bool(args.history or args.plot or scene.path == "time")
    if wanted and kind.history is None:
        raise InputError(f"the {kind.name} model has no time history: leave out --history, "
                         "--plot and model.path = \"time\"")
    return wanted


def _write_history(args, history, kind) -> None:
    """The --history table and the --plot of a history of ``kind``."""
    if args.history:
        data = np.column_stack([history.time, history.delta, history.velocity, history.force,
                                getattr(history, kind.size), history.mean_pressure,
                                history.phase, history.branch])
        with atomic_path(Path(args.history)) as tmp:
            np.savetxt(tmp, data, delimiter=",", header=history_header(kind.size),
                       comments="", fmt=["%.17g"] * 6 + ["%d", "%d"])
    if args.plot:
        from .plots import plot_history
        plot_history(history, args.plot, kind=kind.name)


def cmd_impact(args) -> int:
    from .scene import load_scene
    scene = load_scene(args.scene)
    V, R, m = _point(args, scene)
    angle = scene.impactor.angle if args.angle is None else check_real(
        "--angle", args.angle, low=0.0, high=90.0, high_open=True, unit="degrees")
    kind = _oblique_kind(scene, angle)
    want_history = _history_outputs(args, scene, kind)
    options = scene.kind_options(kind) | ({"angle": angle} if kind.oblique else {})
    model = scene.model(kind=kind)
    result = None
    if want_history:
        history = kind.history(model, V, R, m, options)
        result = history.result
        _write_history(args, history, kind)
    if kind.oblique or result is None:  # the normal history stays written; friction is cheap
        result = kind.solve(model, V, R, m,
                            options | {"path": "time" if want_history else "fast"})
    print(dumps(result.to_dict()) if args.json else result.summary())
    return 0


# --- filmscale impact-map ------------------------------------------------------------------

def _map_rows(args, scene):
    """(velocity axis, rows, row count, angle): the rows are the radius axis, or with
    --angle the incidence angles at the scene's radius."""
    from filmscale.continuum.contact.impact_map import axis

    from .scene import MapSpec, check_map_points
    spec = MapSpec(velocity=args.velocity or scene.map.velocity,
                   radius=args.radius or scene.map.radius,
                   spacing=args.spacing or scene.map.spacing,
                   velocity_name="--velocity" if args.velocity else "map.velocity",
                   radius_name="--radius" if args.radius else "map.radius")
    if args.angle is None:
        velocity, radius = spec.axes()
        return velocity, radius, radius.size, scene.impactor.angle
    if spec.velocity is None:
        raise InputError("an impact map needs a velocity range: give --velocity MIN:MAX:N or "
                         "[map] velocity")
    check_map_points(spec.velocity[2], args.angle[2], spec.velocity_name, "--angle")
    velocity = axis(*spec.velocity, spec.spacing, spec.velocity_name, VELOCITY_RANGE, "m/s")
    for value in args.angle[:2]:
        check_real("--angle", value, low=0.0, high=90.0, high_open=True, unit="degrees")
    angle = axis(*args.angle, "linear", "--angle", (-math.inf, 90.0))
    return velocity, scene.impactor.radius, angle.size, angle


def _map_mass(args, scene, kind, rows) -> float:
    """The impactor mass of every map point: --mass, range-checked as `impact --mass` and
    not lighter than the kind's body at the map's largest radius, else the scene's."""
    if args.mass is None:
        return scene.impactor.mass
    mass = check_real("--mass", args.mass, low=MASS_RANGE[0], high=MASS_RANGE[1],
                      low_open=True, unit="kg")
    radius = ("impactor.radius" if args.angle is not None
              else "--radius maximum" if args.radius else "map.radius maximum")
    kind.check_body(float(np.max(rows)), mass, scene.impactor.options,
                    {"radius": radius, "mass": "--mass", "length": "impactor.length"})
    return mass


def _map_outputs(args, scene, velocity, n_rows: int) -> None:
    """The map's outputs: at least one, plottable, and none overwriting an input."""
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


def _compute_maps(scene, kind, velocity, rows, n_rows, options, mass) -> dict:
    """The kind's map of the layered target (when the scene has films) and of the bare
    substrate, at impactor mass ``mass``, with progress on stderr for the large or slow ones
    (`progress.progress_bar`: a bar on a terminal, plain lines in a log)."""
    from .progress import count_callback, progress_bar
    models = {"layered": scene.model(kind=kind)} if scene.layered else {}
    models["homogeneous"] = scene.substrate_model(kind=kind)
    # an oblique point may take a time integration; a kind whose model takes one point at a
    # time may take ms a point
    large = (kind.oblique or not kind.vectorised
             or velocity.size * n_rows > PROGRESS_POINTS)
    maps = {}
    for key, model in models.items():
        label = map_label(scene, key)
        bar = progress_bar(velocity.size * n_rows, "impact", label, enabled=large)
        try:
            maps[key] = kind.impact_map(model, velocity, rows, mass, options,
                                        count_callback(bar) if large else None)
        finally:
            bar.close()
        print(f"{label}: {velocity.size} x {n_rows} impacts", file=sys.stderr)
    return {"maps": maps, "models": models}


def map_label(scene, key: str) -> str:
    """How plots and summaries name the map of the "layered" or "homogeneous" target."""
    return "layered target" if key == "layered" else f"{scene.stack.substrate.name} only"


def _summary(maps: dict, kind, out, plot, elapsed: float, points: int, mass: float) -> dict:
    """The --json summary: the impactor mass; per target, the points out of range and
    yielded, the largest value of each field the map shows, the smallest restitution (and,
    for an oblique kind, the range of the tangential restitution)."""
    summary = {"out": str(out) if out else None, "plot": plot, "seconds": round(elapsed, 3),
               "points": points, "mass": mass}
    for key, mp in maps.items():
        s = {"out_of_range": int(mp.out_of_range.sum()), "yielded": int(mp.yielded.sum())}
        s.update({f: _extreme(np.max, mp.field(f)) for f in mp.fields if f != "restitution"})
        s["restitution_min"] = _extreme(np.min, mp.field("restitution"))
        if kind.oblique:
            e_x = mp.field("restitution_tangential")
            s.update(restitution_tangential_min=_extreme(np.min, e_x),
                     restitution_tangential_max=_extreme(np.max, e_x))
        summary[key] = s
    return summary


def _print_summary(scene, summary: dict, maps: dict, elapsed: float) -> None:
    written = [str(f) for f in (summary["out"], summary["plot"]) if f]
    print(f"wrote {' and '.join(written)}: {summary['points']} points per target "
          f"(m = {eng(summary['mass'], 'kg')}) in {elapsed:.2f} s")
    for key, mp in maps.items():
        s = summary[key]
        largest = ", ".join(f"largest {name} {eng(s[field], unit)}" for field, name, unit in (
            ("delta_max", "approach", "m"), ("mean_pressure_max", "mean pressure", "Pa"))
            if field in s)
        print(f"  {map_label(scene, key)}: {largest + ', ' if largest else ''}smallest e_y "
              f"{s['restitution_min']:.4f}, yielded at {s['yielded']} points, "
              f"{s['out_of_range']} points beyond the model's range ({mp.range_limit})")


def cmd_impact_map(args) -> int:
    from filmscale.core.provenance import provenance

    from .result import write_impact_maps
    from .scene import load_scene
    scene = load_scene(args.scene)
    velocity, rows, n_rows, angle = _map_rows(args, scene)
    kind = _oblique_kind(scene, angle)
    mass = _map_mass(args, scene, kind, rows)
    _map_outputs(args, scene, velocity, n_rows)
    options = scene.kind_options(kind) | ({"angle": angle} if kind.oblique else {})
    start = time.perf_counter()
    done = _compute_maps(scene, kind, velocity, rows, n_rows, options, mass)
    maps = done["maps"]
    elapsed = time.perf_counter() - start
    described = {k: m.describe() | ({"friction": options["friction"],
                                     "inertia_factor": options["inertia_factor"]}
                                    if kind.oblique else {})
                 for k, m in done["models"].items()}
    out = None
    if args.out:
        out = write_impact_maps(args.out, maps, described,
                                provenance(command=" ".join(sys.argv),
                                           scene_source=scene.source), scene.text)
    if args.plot:
        from .plots import plot_impact_maps
        what = kind.label(options) if kind.label else kind.name
        plot_impact_maps({map_label(scene, k): v for k, v in maps.items()}, args.plot,
                         title=scene.title or f"{what}, m = {eng(mass, 'kg')}")
    summary = _summary(maps, kind, out, args.plot, elapsed, int(velocity.size * n_rows),
                       mass)
    if args.json:
        print(dumps(summary))
    else:
        _print_summary(scene, summary, maps, elapsed)
    return 0


# --- the parsers -----------------------------------------------------------------------------

def add_arguments(sub) -> None:
    """The `impact` and `impact-map` sub-commands."""
    p = sub.add_parser("impact", help="one impact of the scene's impactor (sphere or "
                                      "cylinder; oblique with --angle)",
                       description="Maxima of one impact (fast energy quadrature), or its time "
                                   "history with --history/--plot; a sphere's impact is "
                                   "oblique with --angle or the scene's impactor.angle.")
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
    rows.add_argument("--angle", type=_angle_range, metavar="MIN:MAX:N",
                      help="incidence axis in degrees (linear) at the scene's radius instead: "
                           "oblique impacts with the scene's [contact] friction, about 0.1-0.2 s "
                           "per point that neither slides throughout nor lacks friction")
    p.add_argument("--spacing", choices=("log", "linear"), help="axis spacing (default log)")
    add_quantity_argument(p, "--mass", "kg",
                          help="impacting mass m of every map point: kg, or with units (1.6 "
                               "mg); default: the scene's impactor.mass")
    p.add_argument("--out", metavar="MAP.h5", help="HDF5 result file (--out, --plot or both)")
    p.add_argument("--plot", metavar="MAP.png", help="contour plots")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    add_force_argument(p)
    p.set_defaults(func=cmd_impact_map)
