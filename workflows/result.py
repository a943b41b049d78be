"""Result files, HDF5 with SI datasets and unit attributes: the scene result of `filmscale run`,
the impact maps of `filmscale impact-map` and the indentation results of
`filmscale indent analyze`. Every file is written atomically and carries provenance."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np

from filmscale.continuum.contact.impact_map import row_dimension
from filmscale.continuum.contact.kinds import map_units
from filmscale.continuum.contact.profiles import StackProfile
from filmscale.core.checks import check_path
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_h5, check_regular_file
from filmscale.core.jsonable import dumps
from filmscale.core.provenance import provenance

if TYPE_CHECKING:       # annotations only: an impact map is written without the planner or MD
    from filmscale.continuum.calibration.result import Calibration, CrossCheck
    from filmscale.workflows.plan import Plan
    from filmscale.workflows.scene import Scene
    from filmscale.workflows.pipeline_scene import PipelineScene

#: /2: ``cross_check`` of a calibrated layer is a list (one check per source); /3: impact/map
#: and impact/map_std in the one map layout (`write_map_group`)
RESULT_FORMAT = "filmscale.scene_result/3"
#: the formats `filmscale report` reads: /2 differs only in its maps' lack of dimension scales
RESULT_FORMATS = ("filmscale.scene_result/2", RESULT_FORMAT)


def profile_table(scene: Scene, R: float, points: int = 80) -> dict[str, np.ndarray]:
    """Effective E_p and sigma_y of the stack against approach, for a sphere of radius R."""
    depth = 3 * sum(l.thickness for l in scene.stack.layers) or 1e-8
    delta = np.geomspace(depth * 1e-3, depth * 10, points)
    E_p, sy, nu = StackProfile(scene.stack).properties(delta, R)
    return {"delta": delta, "E_p": E_p, "sigma_y": sy, "nu": nu}


def write_scene_result(out, pipeline: PipelineScene, scene: Scene, plan: Plan,
                       calibrations: dict[int, Calibration],
                       checks: dict[int, list[CrossCheck]],
                       impact_path: Path,
                       run_records: dict[str, dict]) -> Path:
    """One HDF5 file: scene text, plan, calibrations (curves, fits, parameters), depth
    profile, impact results; SI datasets with unit attributes; provenance attributes, with
    each run unit's record as ``md_<layer>`` (LAMMPS version, potential checksum, seeds) or
    ``particles_<layer>`` (LAMMPS version, method, particles, steps), ``..._<layer>_<i>`` for
    the i-th of several sources of a layer. ``cross_check`` of a layer is a JSON list, one
    check per source; each ``curve_<i>`` of a joint calibration names its ``source``."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_h5(out) as f:
        write_result_header(f, RESULT_FORMAT, pipeline, plan, run_records)
        write_calibrations(f.create_group("calibration"), calibrations, checks)
        prof = profile_table(scene, scene.impactor.radius)
        p = f.create_group("profile")
        for name, unit in (("delta", "m"), ("E_p", "Pa"), ("sigma_y", "Pa"), ("nu", "1")):
            p.create_dataset(name, data=prof[name]).attrs["units"] = unit
        i = f.create_group("impact")
        with np.load(impact_path / "impact.npz") as d:
            arrays = {key.replace("__", "/"): d[key] for key in d.files}
        groups = {}
        for key, value in arrays.items():
            group, name = key.split("/", 1)
            groups.setdefault(group, {})[name] = value
        for group, values in groups.items():
            if group in ("map", "map_std"):     # maps: the one layout, std on the map's axes
                axes = {k: v for k, v in groups["map"].items() if k in MAP_COORDINATES}
                write_map_group(i.create_group(group), {**values, **axes},
                                {"kind": plan.decisions.get("kind", "sphere")})
            else:
                for name, value in values.items():
                    i.create_dataset(f"{group}/{name}", data=value)
    return out



def write_result_header(f: h5py.File, fmt: str, pipeline: PipelineScene, plan: Plan,
                        run_records: dict[str, dict]) -> None:
    """What every scene result starts with: its ``format``, the provenance attributes with
    each run unit's record (JSON) under its key, the scene text (``scene``) and the plan
    (``plan``, JSON)."""
    f.attrs["format"] = fmt
    extra = {k: dumps(r) for k, r in run_records.items()}
    for k, v in provenance(scene=pipeline.source, **extra).items():
        f.attrs[k] = v
    f.create_dataset("scene", data=pipeline.text)
    f.attrs["plan"] = dumps(plan.to_dict())


def write_calibrations(g: h5py.Group, calibrations: dict[int, Calibration],
                       checks: dict[int, list[CrossCheck]]) -> h5py.Group:
    """The ``calibration`` group of a scene result (impact or sliding): per calibrated layer
    ``<layer>``, its parameters with their standard deviations and identifiability as
    attributes, the calibration and its cross-scale checks (one per source) as JSON, and
    per fitted curve ``curve_<i>`` its h, P and the forward model's P_model (SI, ``units``;
    ``source`` in a joint calibration; ``fitted_for``: 1 sets E, 2 sigma_y, 3 both)."""
    for k, cal in calibrations.items():
        c = g.create_group(str(k))
        c.attrs["layer"] = cal.layer
        c.attrs["calibration"] = dumps(cal.to_dict())
        for name in ("E", "sigma_y", "n", "h_star"):
            p = getattr(cal, name)
            if p is None:
                continue
            c.attrs[name] = p.value
            c.attrs[f"{name}_std"] = p.std
            c.attrs[f"{name}_identified"] = p.identified
        c.attrs["cross_check"] = dumps([check.to_dict() for check in checks[k]])
        for i, (h, P, F) in enumerate(cal.fitted_curves):
            curve = c.create_group(f"curve_{i}")
            if cal.curve_sources:
                curve.attrs["source"] = cal.curve_sources[i]
            for name, data, unit in (("h", h, "m"), ("P", P, "N"), ("P_model", F, "N")):
                curve.create_dataset(name, data=data).attrs["units"] = unit
            if cal.fit_roles:
                # 1: sets E, 2: sets sigma_y, 3: both, 0: not fitted
                curve.create_dataset("fitted_for", data=cal.fit_roles[i])
    return g


#: the result of a sliding scene (`write_slide_result`)
SLIDE_RESULT_FORMAT = "filmscale.slide_result/1"
#: the per-layer quantities of a slide (`SlideResult.layers`) in a slide unit and result, and
#: their units
SLIDE_LAYER_UNITS = {"von_mises_max": "Pa", "x": "m", "z": "m", "yield_ratio": "1",
                     "tensile_max": "Pa", "interface_shear_max": "Pa", "z_top": "m",
                     "z_bottom": "m"}


def write_slide_result(out, pipeline: PipelineScene, plan: Plan,
                       calibrations: dict[int, Calibration],
                       checks: dict[int, list[CrossCheck]], slide_path: Path,
                       record: dict, run_records: dict[str, dict], completed: dict,
                       std_note: str = "") -> Path:
    """A sliding scene's result: the header and calibrations of every scene result
    (`write_result_header`, `write_calibrations`), then the ``slide`` group: the result as
    JSON (``result``, `SlideResult.to_dict`), the completed scene data (``completed_scene``,
    JSON: the calibrated E and sigma_y filled in), the layer names; per layer (top first,
    substrate last) each quantity of `units.SLIDE_LAYER_UNITS` and its ``<name>_std`` from
    the calibrations where propagated; p0 and the contact size (a or b); and ``slide/field``
    (x (nx), z (layers, nz), von_mises (layers, nz, nx)). SI with ``units``. ``std_note``
    (an attribute) says why no standard deviation is there, where none is. ``record``: the
    slide unit's (`units.slide_evaluation`), ``slide_path`` its folder."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with np.load(slide_path / "slide.npz") as d:
        arrays = {key: d[key] for key in d.files}
    units = {**SLIDE_LAYER_UNITS, "p0": "Pa", "contact_size": "m"}
    with atomic_h5(out) as f:
        write_result_header(f, SLIDE_RESULT_FORMAT, pipeline, plan, run_records)
        write_calibrations(f.create_group("calibration"), calibrations, checks)
        if std_note:
            f.attrs["std_note"] = std_note
        g = f.create_group("slide")
        g.attrs["result"] = dumps(record["slide"])
        g.attrs["completed_scene"] = dumps(completed)
        g.attrs["layer_names"] = dumps([r["name"] for r in record["slide"]["layers"]])
        for key, value in arrays.items():
            if key.startswith("field_"):
                continue
            g.create_dataset(key, data=value).attrs["units"] = units[key.removesuffix("_std")]
        field = g.create_group("field")
        for key, unit in (("x", "m"), ("z", "m"), ("layer", "1"), ("von_mises", "Pa")):
            field.create_dataset(key, data=arrays[f"field_{key}"]).attrs["units"] = unit
    return out


#: /2: each target's group holds its own axes as dimension scales (`write_map_group`)
IMPACT_MAP_FORMAT = "filmscale.impact_map/2"
#: the layout of /1: shared /velocity and /radius at the root, no dimension scales
IMPACT_MAP_FORMAT_1 = "filmscale.impact_map/1"
#: arrays of a map group that are coordinates, not results
MAP_COORDINATES = ("velocity", "radius", "angle", "mass")


def write_map_group(g: h5py.Group, arrays: dict, attrs: dict | None = None) -> h5py.Group:
    """One impact map into ``g``: the layout of every map filmscale writes (the groups of an
    impact-map file, a scene result's impact/map and impact/map_std). ``arrays`` is a map's
    ``to_dict`` (axes, mass, (rows, V) results). The row quantity (`row_dimension`: radius,
    or the angle of an oblique map over angles) and velocity are HDF5 dimension scales that
    every result is attached to, netCDF-4 style, so ``xarray.open_dataset(path,
    engine="h5netcdf", group=...)`` names its coordinates; the other row quantity and the
    mass are coordinates too. Every dataset has a ``units`` attribute (SI, angles in
    degrees); booleans are stored as int8 marked ``dtype = "bool"`` (xarray's convention)."""
    units = map_units()
    row = row_dimension(arrays)
    scales = {}
    for name in ("velocity", row):
        ds = g.create_dataset(name, data=np.asarray(arrays[name], dtype=float))
        ds.attrs["units"] = units[name]
        ds.make_scale(name)
        scales[name] = ds
    others = [n for n in ("radius", "angle") if n in arrays and n != row]
    for name in others:
        ds = g.create_dataset(name, data=np.asarray(arrays[name], dtype=float))
        ds.attrs["units"] = units[name]
        ds.dims[0].attach_scale(scales[row])
    g.create_dataset("mass", data=float(arrays["mass"])).attrs["units"] = "kg"
    coordinates = " ".join([*others, "mass"])
    for key, values in arrays.items():
        if key in MAP_COORDINATES:
            continue
        values = np.asarray(values)
        flag = values.dtype == bool
        # byte shuffle + fast gzip: smaller than gzip's default level alone, and 30 % faster
        ds = g.create_dataset(key, data=values.astype(np.int8) if flag else values,
                              compression="gzip", compression_opts=1, shuffle=True)
        ds.attrs["units"] = units.get(key, "1")
        ds.attrs["coordinates"] = coordinates
        if flag:
            ds.attrs["dtype"] = "bool"
        ds.dims[0].attach_scale(scales[row])
        ds.dims[1].attach_scale(scales["velocity"])
    for key, value in (attrs or {}).items():
        g.attrs[key] = value
    return g


def read_map_group(g: h5py.Group) -> dict[str, np.ndarray]:
    """The arrays of a group written by `write_map_group` (``to_dict`` form, booleans
    restored)."""
    out = {}
    for key, ds in g.items():
        if isinstance(ds, h5py.Dataset):
            value = ds[()]
            out[key] = value.astype(bool) if ds.attrs.get("dtype") == "bool" else value
    return out


def write_impact_maps(path, maps: dict, models: dict[str, dict],
                      provenance: dict[str, str], scene_text: str = "") -> Path:
    """One file holding impact maps of one impactor shape: one `write_map_group` per label
    (e.g. "layered", "homogeneous") with the model as JSON in its ``model`` attribute, and
    the scene text; the root attribute ``shape`` says "sphere" or "cylinder", ``mass`` (kg)
    and, for cylinders, ``length`` (m) are root attributes too."""
    labels = list(maps)
    first = maps[labels[0]]
    with atomic_h5(path) as f:
        f.attrs["format"] = IMPACT_MAP_FORMAT
        f.attrs["shape"] = first.shape
        for key, value in provenance.items():
            f.attrs[key] = value
        f.create_dataset("scene", data=scene_text)
        f.attrs["mass"] = first.mass
        f.attrs["mass_units"] = "kg"
        for key, value in first.attrs.items():      # e.g. a cylinder's length, in m
            f.attrs[key], f.attrs[f"{key}_units"] = value, "m"
        for label in labels:
            m = maps[label]
            write_map_group(f.create_group(label), m.to_dict(),
                            {"regime_names": dumps(list(m.regime_names)),
                             "status_codes": dumps(m.status_messages),
                             "model": dumps(models.get(label, {})),
                             "shape": m.shape, "kind": m.kind})
    return Path(path)


def read_impact_maps(path) -> tuple[dict[str, dict[str, np.ndarray]], dict]:
    """(fields by label, root attributes) of a file written by `write_impact_maps`, of this
    layout or of the first (``filmscale.impact_map/1``: shared root axes)."""
    path = check_path("path", path)
    check_regular_file(path, "impact-map file")     # h5py would block on a named pipe
    try:
        with h5py.File(path, "r") as f:
            fmt = f.attrs.get("format")
            if fmt not in (IMPACT_MAP_FORMAT, IMPACT_MAP_FORMAT_1):
                raise InputError(f"{path} is not a filmscale impact-map file")
            attrs = dict(f.attrs)
            axes = ({name: f[name][()] for name in ("velocity", "radius")}
                    | {"mass": f.attrs["mass"]} if fmt == IMPACT_MAP_FORMAT_1 else {})
            out = {}
            for label, g in f.items():
                if isinstance(g, h5py.Group):
                    out[label] = read_map_group(g) | axes
                    out[label]["regime_names"] = json.loads(g.attrs["regime_names"])
                    out[label]["model"] = json.loads(g.attrs["model"])
            attrs["scene"] = f["scene"][()].decode() if "scene" in f else ""
    except OSError as err:
        raise InputError(f"cannot read {path}: {err}") from None
    return out, attrs


INDENT_RESULTS_FORMAT = "filmscale.indent_results/1"


#: unit of each numeric field of an Oliver-Pharr result
INDENT_UNITS = {"E_r": "Pa", "H": "Pa", "h_c": "m", "S": "N/m", "A_c": "m^2", "P_max": "N",
                "h_max": "m", "h_f": "m", "m": "1", "B": "N/m^m", "epsilon": "1", "beta": "1",
                "E": "Pa", "W_t": "J", "W_e": "J", "W_p": "J", "We_Wt": "1", "fit_rms": "1",
                "n_fit": "1", "status": "1", "surface_shift": "m", "drift_rate": "m/s",
                "E_r_std": "Pa", "E_std": "Pa", "H_std": "Pa", "n_range": "1"}


def write_indentation_results(path, records: list[dict], provenance: dict[str, str],
                              options: dict, profile: dict | None = None) -> Path:
    """Oliver-Pharr or CSM results of many curves: one dataset per field (one row per curve,
    SI), the curve names and source files, the flags as JSON text, the CSM arrays of each
    row (group ``csm/ROW``), and the property-depth profile when one was computed."""
    with atomic_h5(path) as f:
        f.attrs["format"] = INDENT_RESULTS_FORMAT
        for key, value in provenance.items():
            f.attrs[key] = value
        f.attrs["options"] = dumps(options)
        text = h5py.string_dtype()
        f.create_dataset("name", data=[r["name"] for r in records], dtype=text)
        f.create_dataset("file", data=[r["file"] for r in records], dtype=text)
        f.create_dataset("flags", data=[dumps(r.get("flags", [])) for r in records],
                         dtype=text)
        f.create_dataset("message", data=[r.get("message", "") for r in records], dtype=text)
        for key, unit in INDENT_UNITS.items():
            values = np.array([np.nan if r.get(key) is None else r[key] for r in records],
                              dtype=float)
            f.create_dataset(key, data=values).attrs["units"] = unit
        for key in ("E", "H"):      # against the instrument's own channels (CSM)
            f.create_dataset(f"vendor_difference_{key}", data=np.array(
                [(r.get("vendor_difference") or {}).get(key, np.nan) for r in records],
                dtype=float)).attrs["units"] = "1"
        csm = [(k, r["csm"]) for k, r in enumerate(records) if r.get("csm")]
        if csm:         # the per-depth CSM arrays of each record, by its row
            g = f.create_group("csm")
            for k, arrays in csm:
                row = g.create_group(str(k))
                for key, unit in (("h", "m"), ("h_c", "m"), ("S", "N/m"), ("E_r", "Pa"),
                                  ("E", "Pa"), ("H", "Pa")):
                    row.create_dataset(key, data=np.asarray(arrays[key], dtype=float)
                                       ).attrs["units"] = unit
        if profile is not None:
            g = f.create_group("profile")
            g.attrs["layer_names"] = dumps(profile["layer_names"])
            g.create_dataset("interfaces", data=np.asarray(profile["interfaces"], dtype=float)
                             ).attrs["units"] = "m"
            for key, unit in (("h_c", "m"), ("E_r", "Pa"), ("H", "Pa"), ("E_r_std", "Pa"),
                              ("H_std", "Pa"), ("n", "1")):
                g.create_dataset(f"group_{key}", data=profile["groups"][key]).attrs["units"] = unit
            g.attrs["layers"] = dumps(profile["layers"])
            if profile.get("nix_gao"):
                g.attrs["nix_gao"] = dumps(profile["nix_gao"])
            if profile.get("film"):      # the film's E by a film/substrate model (JSON, SI)
                g.attrs["film"] = dumps(profile["film"])
    return Path(path)


def read_indentation_results(path) -> tuple[dict[str, np.ndarray], dict]:
    """Datasets and attributes of a file written by `write_indentation_results`."""
    path = check_path("path", path)
    check_regular_file(path, "indentation result file")     # h5py would block on a pipe
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != INDENT_RESULTS_FORMAT:
                raise InputError(f"{path} is not a filmscale indentation result file")
            data = {k: f[k][()] for k in f if isinstance(f[k], h5py.Dataset)}
            for k in ("name", "file", "flags", "message"):
                data[k] = [v.decode() if isinstance(v, bytes) else v for v in data[k]]
            return data, dict(f.attrs)
    except OSError as err:
        raise InputError(f"cannot read {path}: {err}") from None
