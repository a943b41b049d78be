"""`filmscale slide` and `filmscale slide-map`: the stresses of a slider's protrusion sliding on
a film stack, and its first yield over normal load and friction (docs/sliding.md)."""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from filmscale.core.checks import check_real
from filmscale.core.errors import InputError
from filmscale.core.jsonable import dumps
from filmscale.core.quantities import eng

from .outputs import (add_force_argument, check_outputs, hdf5_kind, image_kind, output_path,
                      plot_path)
from .quantity_args import add_quantity_argument, range_arg

# The physics (scipy) and the scene reader are imported inside each command, so that
# `filmscale --help` and a usage error answer without loading them.

#: the format of a slide-map file
SLIDE_MAP_FORMAT = "filmscale.slide_map/1"


def _inputs(scene) -> list[tuple[str, Path]]:
    """The files a sliding scene reads: itself and the scratch record of its friction."""
    record = [("the scratch record of contact.friction_from",
               Path(scene.friction_source["record"]))] if scene.friction_source else []
    return [("the input scene", Path(scene.source)), *record]


def _friction(value, default: float, name: str = "--friction") -> float:
    if value is None:
        return default
    return check_real(name, value, low=0.0, high=10.0, unit="")


def _load(value, default: float) -> float:
    if value is None:
        return default
    return check_real("--load", value, low=0.0, high=1e6, low_open=True, unit="N")


# --- filmscale slide -----------------------------------------------------------------------

def slide_table(d: dict) -> str:
    """A sliding result for people, from its `SlideResult.to_dict` (or a scene result's
    `SceneResult.slide`, whose ``<name>_std`` entries are shown as +- std): the slider and
    its contact, one row per layer (depths, the largest von Mises stress and where, its ratio
    to sigma_y, the largest tension and interface shear), the first yield, the surface's
    largest tension and the shakedown answer."""
    def std(row, key, fmt):
        value = row.get(f"{key}_std")
        return f" ± {fmt(value)}" if value is not None and math.isfinite(value) else ""

    def pa(v):
        return eng(v, "Pa")

    def m(v):               # the surface is z = 0, not "0 m"
        return "0" if v == 0 else eng(v, "m")
    s = d["slider"]
    size = "contact radius a" if s["shape"] == "sphere" else "contact half-width b"
    lines = [f"{s['name']}: {s['shape']} R = {eng(s['radius'], 'm')}"
             + (f", L = {eng(s['length'], 'm')}" if s["length"] else "")
             + f", P = {eng(d['normal_load'], 'N')}, mu = {d['friction']:g}",
             f"{size} {eng(d['contact_radius'], 'm')}, p0 {pa(d['p0'])}{std(d, 'p0', pa)}, "
             f"E* {pa(d['contact_modulus'])} ({d['contact_method']})",
             f"{'layer':<14}{'depth':>20}{'von Mises max':>22}{'at x':>11}{'at z':>11}"
             f"{'/ sigma_y':>17}{'tension max':>13}{'interface shear':>17}"]
    for r in d["layers"]:
        depth = (f"{m(r['z_top'])}-{m(r['z_bottom'])}" if r["z_bottom"] is not None
                 else f"below {m(r['z_top'])}")
        ratio = "-" if r["yield_ratio"] is None else \
            f"{r['yield_ratio']:.3f}" + std(r, "yield_ratio", lambda v: f"{v:.3f}")
        shear = "-" if r["interface_shear_max"] is None else pa(r["interface_shear_max"])
        vm = pa(r["von_mises_max"]) + std(r, "von_mises_max", pa)
        lines.append(f"{r['name'][:13]:<14}{depth:>20}{vm:>22}{m(r['x']):>11}"
                     f"{m(r['z']):>11}{ratio:>17}{pa(r['tensile_max']):>13}{shear:>17}")
    first = d["first_yield"]
    if first is not None:
        verdict = "yields" if first["yielded"] else "elastic"
        lines.append(f"first yield: {first['layer']} at x = {m(first['x'])}, z = "
                     f"{m(first['z'])} (von Mises / sigma_y = "
                     f"{first['yield_ratio']:.3f}: {verdict})")
    lines.append(f"largest surface tension {pa(d['surface_tensile_max'])} at x = "
                 f"{eng(d['surface_tensile_x'], 'm')} (trailing edge at x = "
                 f"{eng(-d['contact_radius'], 'm')})")
    sd = d["shakedown"]
    if sd.get("modelled"):
        lines.append(f"shakedown: p0 limit {pa(sd['p0_limit'])}, load limit "
                     f"{eng(sd['load_limit'], 'N')}: "
                     + ("shakes down" if sd["shakes_down"] else "beyond the limit: ratchets"))
    else:
        lines.append(f"shakedown: {sd['reason']}")
    if d.get("friction_source"):
        src = d["friction_source"]
        lines.append(f"friction from the scratch record {src['record']}: {src['mean']:.3f} "
                     f"+- {src['std']:.3f} over {src['points']} points of its steady stroke")
    if d.get("std_note"):
        lines.append(f"std: {d['std_note']}")
    return "\n".join(lines)


def cmd_slide(args) -> int:
    from filmscale.continuum.contact.slider import slide

    from .slide_scene import load_slide_scene
    scene = load_slide_scene(args.scene)
    load = _load(args.load, scene.normal_load)
    mu = _friction(args.friction, scene.friction)
    plot_path("--plot", args.plot)
    check_outputs(_inputs(scene), [("--plot", args.plot, image_kind(args.plot))], args.force)
    result = slide(scene.stack, scene.slider, load, mu)
    if args.plot:
        from .slide_plots import plot_slide
        plot_slide(result, args.plot, title=scene.title and f"{scene.title}: P = "
                   f"{eng(load, 'N')}, μ = {mu:g}")
    d = result.to_dict()
    if args.friction is None and scene.friction_source is not None:
        d["friction_source"] = scene.friction_source
    print(dumps(d) if args.json else slide_table(d))
    return 0


# --- filmscale slide-map -------------------------------------------------------------------

def _axis(text, name: str, low: float, high: float, unit: str, spacing: str) -> np.ndarray:
    lo, hi, count = text
    lo = check_real(f"{name} minimum", lo, low=low, high=high, low_open=name == "--load",
                    unit=unit)
    hi = check_real(f"{name} maximum", hi, low=lo, high=high, low_open=True, unit=unit)
    if not 1 <= count <= 500:
        raise InputError(f"{name} count = {count} must be in [1, 500]")
    if count == 1:
        return np.array([lo])
    return np.geomspace(lo, hi, count) if spacing == "log" else np.linspace(lo, hi, count)


def _map_outputs(args, scene) -> Path | None:
    """The map's outputs: --out, --plot (a file, or next to --out when given bare)."""
    plot = args.plot
    if plot == "":
        if not args.out:
            raise InputError("--plot without a file name draws next to --out MAP.h5: give "
                             "--out, or --plot MAP.png")
        plot = str(Path(args.out).with_suffix(".png"))
    if not (args.out or plot):
        raise InputError("slide-map writes --out MAP.h5, --plot [MAP.png] or both: give one")
    output_path("--out", args.out)
    plot_path("--plot", plot)
    check_outputs(_inputs(scene), [("--out", args.out, hdf5_kind(SLIDE_MAP_FORMAT,
                                                                 "a slide map")),
                                   ("--plot", plot, image_kind(plot))], args.force)
    return Path(plot) if plot else None


def write_slide_map(path, mp, scene, provenance: dict) -> Path:
    """A slide map to HDF5: normal_load, friction and layer are dimension scales that every
    array is attached to (netCDF-4 style, so xarray names its coordinates); SI units in each
    dataset's ``units``; the layer names, the scene text and provenance as attributes."""
    from filmscale.continuum.contact.slide_map import SLIDE_MAP_UNITS
    from filmscale.core.files import atomic_h5
    with atomic_h5(path) as f:
        f.attrs["format"] = SLIDE_MAP_FORMAT
        f.attrs["kind"] = mp.kind
        f.attrs["shape"] = scene.slider.shape
        f.attrs["layer_names"] = dumps(list(mp.layer_names))
        f.attrs["grid"] = dumps(list(mp.grid))
        for key, value in provenance.items():
            f.attrs[key] = value
        f.create_dataset("scene", data=scene.text)
        scales = {}
        n_layers = len(mp.layer_names)
        for name, values, unit in (("normal_load", mp.normal_load, "N"),
                                   ("friction", mp.friction, "1"),
                                   ("layer", np.arange(n_layers), "1"),
                                   ("interface", np.arange(max(n_layers - 1, 0)), "1")):
            ds = f.create_dataset(name, data=values)
            ds.attrs["units"] = unit
            ds.make_scale(name)
            scales[name] = ds
        dims = {1: ("normal_load",), 2: ("friction", "normal_load")}
        for key, values in mp.values.items():
            values = np.asarray(values)
            if key == "interface_shear_max":
                names = ("interface", "friction", "normal_load")
            elif key.startswith("layer_"):
                names = ("layer", "friction", "normal_load")
            elif key.startswith("first_yield_load") or key == "shakedown_load":
                names = ("friction",)
            else:
                names = dims[values.ndim]
            ds = f.create_dataset(key, data=values)
            ds.attrs["units"] = SLIDE_MAP_UNITS.get(key, "1")
            for i, name in enumerate(names):
                ds.dims[i].attach_scale(scales[name])
    return Path(path)


def _map_summary(mp, out, plot, elapsed) -> dict:
    names = mp.layer_names
    rows = []
    for mu, load, layer, z in zip(mp.friction, mp["first_yield_load"],
                                  mp["first_yield_load_layer"], mp["first_yield_load_z"]):
        rows.append({"friction": float(mu), "load": None if math.isnan(load) else float(load),
                     "layer": names[layer] if layer >= 0 else None,
                     "z": None if math.isnan(z) else float(z)})
    return {"out": str(out) if out else None, "plot": str(plot) if plot else None,
            "seconds": round(elapsed, 3), "points": int(mp.normal_load.size * mp.friction.size),
            "first_yield": rows}


def cmd_slide_map(args) -> int:
    from filmscale.continuum.contact.slide_map import slide_map
    from filmscale.core.provenance import provenance

    from .progress import progress_bar, step_callback
    from .slide_scene import load_slide_scene
    scene = load_slide_scene(args.scene)
    loads = _axis(args.load, "--load", 0.0, 1e6, "N", args.spacing)
    mus = _axis(args.friction, "--friction", 0.0, 10.0, "", "linear")
    plot = _map_outputs(args, scene)
    start = time.perf_counter()
    bar = progress_bar(loads.size, "load", "slide map", enabled=not scene.stack.is_homogeneous)
    try:
        mp = slide_map(scene.stack, scene.slider, loads, mus,
                       progress=step_callback(bar, loads.size))
    finally:
        bar.close()
    elapsed = time.perf_counter() - start
    if args.out:
        write_slide_map(args.out, mp, scene, provenance(command=" ".join(sys.argv),
                                                        scene_source=scene.source))
    if plot:
        from .slide_plots import plot_slide_map
        plot_slide_map(mp, plot, title=scene.title)
    summary = _map_summary(mp, args.out, plot, elapsed)
    if args.json:
        print(dumps(summary))
        return 0
    written = " and ".join(str(p) for p in (args.out, plot) if p)
    print(f"wrote {written}: {summary['points']} points in {elapsed:.2f} s")
    for row in summary["first_yield"]:
        where = (f"{eng(row['load'], 'N')} in {row['layer']} at z = {eng(row['z'], 'm')}"
                 if row["load"] is not None else "not within the load axis")
        print(f"  mu = {row['friction']:.3g}: first yield at {where}")
    return 0


# --- the parsers ---------------------------------------------------------------------------

def add_arguments(sub) -> None:
    """The `slide` and `slide-map` sub-commands."""
    p = sub.add_parser("slide", help="stresses below a sliding sphere or cylinder on the "
                                     "scene's films: per-layer table, first yield",
                       description="Stresses of a slider's protrusion ([slider] of a sliding "
                                   "scene) sliding with friction on the target stack: per "
                                   "layer the largest von Mises stress and where, its ratio "
                                   "to sigma_y, the largest tension and interface shear; the "
                                   "first yield; the shakedown limit where modelled.")
    p.add_argument("scene", help="sliding scene file (TOML with [slider])")
    add_quantity_argument(p, "--load", "N", help="normal load: N, or with units (5 mN); "
                                                 "default: slider.normal_load")
    p.add_argument("--friction", type=float, metavar="MU",
                   help="friction coefficient (default: the scene's [contact] friction)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--plot", metavar="FILE.png", help="the x-z stress field, per layer over "
                                                      "its yield strength")
    add_force_argument(p)
    p.set_defaults(func=cmd_slide)

    p = sub.add_parser("slide-map", help="first yield of a sliding contact over normal load "
                                         "and friction",
                       description="First-yield map over (normal load, friction): the "
                                   "largest yield ratio of each layer, which layer yields "
                                   "first, where and at which load; the shakedown load of a "
                                   "cylinder on a homogeneous target.")
    p.add_argument("scene", help="sliding scene file (TOML with [slider])")
    add_quantity_argument(p, "--load", "N", type=range_arg, metavar="MIN:MAX:N",
                          required=True, help="load axis in N or with units, 0.1mN:10mN:50")
    add_quantity_argument(p, "--friction", "1", type=range_arg, metavar="MIN:MAX:N",
                          required=True, help="friction axis (linear), 0:0.6:50")
    p.add_argument("--spacing", choices=("log", "linear"), default="log",
                   help="load axis spacing (default log)")
    p.add_argument("--out", metavar="MAP.h5", help="HDF5 map (SI units, dimension scales)")
    p.add_argument("--plot", metavar="MAP.png", nargs="?", const="",
                   help="the map's figure; bare: next to --out, as MAP.png")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    add_force_argument(p)
    p.set_defaults(func=cmd_slide_map)
