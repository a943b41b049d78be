"""HDF5 result files: datasets in SI with a ``units`` attribute, provenance as attributes,
written atomically (a temporary file in the same folder, then a rename), so an interrupted
write never leaves a half-written result behind."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
from filmscale.continuum.contact.impact import ImpactMaxima, STATUS_MESSAGES
from filmscale.continuum.contact.impact_map import ImpactMap
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_h5


IMPACT_MAP_FORMAT = "filmscale.impact_map/1"


def write_impact_maps(path, maps: dict[str, ImpactMap], models: dict[str, dict],
                      provenance: dict[str, str], scene_text: str = "") -> Path:
    """One file holding impact maps on shared axes: /velocity, /radius, one group per label
    (e.g. "layered", "homogeneous") with a dataset per result field, and the scene text."""
    labels = list(maps)
    first = maps[labels[0]]
    with atomic_h5(path) as f:
        f.attrs["format"] = IMPACT_MAP_FORMAT
        for key, value in provenance.items():
            f.attrs[key] = value
        f.create_dataset("scene", data=scene_text)
        for name in ("velocity", "radius"):
            f.create_dataset(name, data=getattr(first, name)).attrs["units"] = (
                ImpactMaxima.UNITS[name])
        f.attrs["mass"] = first.mass
        f.attrs["mass_units"] = "kg"
        for label in labels:
            g = f.create_group(label)
            fields = maps[label].to_dict()
            for key, values in fields.items():
                if key in ("velocity", "radius", "mass"):
                    continue
                ds = g.create_dataset(key, data=np.asarray(values), compression="gzip")
                ds.attrs["units"] = ImpactMaxima.UNITS.get(key, "1")
            g.attrs["regime_names"] = json.dumps(list(maps[label].maxima.regime_names))
            g.attrs["status_codes"] = json.dumps(STATUS_MESSAGES)
            g.attrs["model"] = json.dumps(models.get(label, {}))
    return Path(path)


def read_impact_maps(path) -> tuple[dict[str, dict[str, np.ndarray]], dict]:
    """(fields by label, root attributes) of a file written by `write_impact_maps`."""
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != IMPACT_MAP_FORMAT:
                raise InputError(f"{path} is not a filmscale impact-map file")
            attrs = dict(f.attrs)
            axes = {name: f[name][()] for name in ("velocity", "radius")}
            out = {}
            for label, g in f.items():
                if isinstance(g, h5py.Group):
                    out[label] = {k: g[k][()] for k in g} | axes
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
                "n_fit": "1", "status": "1"}


def write_indentation_results(path, records: list[dict], provenance: dict[str, str],
                              options: dict, profile: dict | None = None) -> Path:
    """Oliver-Pharr results of many curves: one dataset per field (one row per curve, SI),
    the curve names and source files, the flags as JSON text, and the property-depth
    profile when one was computed."""
    with atomic_h5(path) as f:
        f.attrs["format"] = INDENT_RESULTS_FORMAT
        for key, value in provenance.items():
            f.attrs[key] = value
        f.attrs["options"] = json.dumps(options)
        text = h5py.string_dtype()
        f.create_dataset("name", data=[r["name"] for r in records], dtype=text)
        f.create_dataset("file", data=[r["file"] for r in records], dtype=text)
        f.create_dataset("flags", data=[json.dumps(r.get("flags", [])) for r in records],
                         dtype=text)
        f.create_dataset("message", data=[r.get("message", "") for r in records], dtype=text)
        for key, unit in INDENT_UNITS.items():
            values = np.array([np.nan if r.get(key) is None else r[key] for r in records],
                              dtype=float)
            f.create_dataset(key, data=values).attrs["units"] = unit
        if profile is not None:
            g = f.create_group("profile")
            g.attrs["layer_names"] = json.dumps(profile["layer_names"])
            g.create_dataset("interfaces", data=np.asarray(profile["interfaces"], dtype=float)
                             ).attrs["units"] = "m"
            for key, unit in (("h_c", "m"), ("E_r", "Pa"), ("H", "Pa"), ("E_r_std", "Pa"),
                              ("H_std", "Pa"), ("n", "1")):
                g.create_dataset(f"group_{key}", data=profile["groups"][key]).attrs["units"] = unit
            g.attrs["layers"] = json.dumps(profile["layers"])
            if profile.get("nix_gao"):
                g.attrs["nix_gao"] = json.dumps(profile["nix_gao"])
    return Path(path)


def read_indentation_results(path) -> tuple[dict[str, np.ndarray], dict]:
    """Datasets and attributes of a file written by `write_indentation_results`."""
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
