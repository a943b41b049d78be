"""The pipeline that links the scales: scene -> plan -> run units -> one HDF5 result.

`run_scene` executes a pipeline scene (`workflows.scene.parse_pipeline`, docs/pipeline.md):
each layer to calibrate gets its sources' run units and calibration units (`workflows.units`;
several sources of one layer are then combined by `continuum.calibration.joint`), the plan
(`workflows.plan`) is completed with the calibrated materials, the impact unit (a sliding
scene: the slide unit, `run_slide`) is evaluated, and everything goes into one result file
(`workflows.result`). Finished units are reused
and an interrupted scene resumes where it stopped.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from filmscale.continuum.calibration.result import Calibration, CrossCheck
from filmscale.continuum.contact.laws import DEFAULT_LAW
from filmscale.core.errors import InputError
from filmscale.workflows.plan import Plan, check_request, plan_scene
from filmscale.workflows.result import write_scene_result, write_slide_result
from filmscale.workflows.pipeline_scene import PipelineScene, filled_data, layer_sources
from filmscale.workflows.store import done_record, finish_unit, say, unit_dir, unit_lock
from filmscale.workflows.units import (calibration_part, calibration_unit, impact_evaluation,
                                       joint_unit, slide_evaluation, source_units)


@dataclass(frozen=True)
class SceneResult:
    """What `run_scene` wrote (``path``, the HDF5 result), the plan it followed and which
    units ran; the methods read the result back for a notebook."""

    path: Path
    plan: Plan
    units: dict            #: unit directory -> "ran" or "reused"

    @classmethod
    def open(cls, path) -> SceneResult:
        """An existing scene result (the RESULT.h5 of `filmscale run` or `run_scene`): its
        plan from the file's ``plan`` attribute, its ``units`` from a ``units`` attribute
        (JSON) where the file records one, else empty (a result file does not list the store
        units that made it). InputError for any other file, or a damaged one."""
        import h5py

        from filmscale.workflows.outputs import describe, hdf5_format
        from filmscale.workflows.result import (RESULT_FORMAT, RESULT_FORMATS,
                                                SLIDE_RESULT_FORMAT)
        path = Path(path)
        if not path.is_file() or hdf5_format(path) not in (*RESULT_FORMATS,
                                                           SLIDE_RESULT_FORMAT):
            what = describe(path) if path.is_file() else "not a file"
            raise InputError(f"{path} is {what}; SceneResult.open expects a scene result "
                             f"(format {RESULT_FORMAT}, or {SLIDE_RESULT_FORMAT} of a sliding "
                             "scene: the RESULT.h5 of filmscale run)")
        try:
            with h5py.File(path, "r") as f:
                plan = Plan.from_dict(json.loads(f.attrs["plan"]))
                units = json.loads(f.attrs["units"]) if "units" in f.attrs else {}
        except (KeyError, OSError, TypeError, ValueError) as err:
            raise InputError(f"scene result {path} is damaged or incomplete: {err}") from None
        return cls(path, plan, dict(units))

    @property
    def sliding(self) -> bool:
        """Whether the result is a sliding scene's (`slide`, `to_dataframe` per layer)."""
        return bool(self.plan.decisions.get("sliding"))

    def _impact_only(self, what: str) -> None:
        if self.sliding:
            raise InputError(f"{self.path} is a sliding scene's result: it has no {what}; "
                             "its results are SceneResult.slide() and to_dataframe() (one "
                             "row per layer)")

    def slide(self) -> dict:
        """A sliding result's ``slide`` group: the result as `SlideResult.to_dict` gives it,
        each layer row with the ``<quantity>_std`` the calibrations give (p0_std and
        contact_size_std beside p0), and ``std_note`` where none is propagated."""
        import h5py
        if not self.sliding:
            raise InputError(f"{self.path} is an impact result: it has no slide group")
        with h5py.File(self.path, "r") as f:
            g = f["slide"]
            out = json.loads(g.attrs["result"])
            std = {k.removesuffix("_std"): g[k][()] for k in g if k.endswith("_std")}
            out["std_note"] = str(f.attrs.get("std_note", ""))
        for j, row in enumerate(out["layers"]):
            row.update({f"{k}_std": float(v[j]) for k, v in std.items() if np.ndim(v)})
        out.update({f"{k}_std": float(v) for k, v in std.items() if not np.ndim(v)})
        return out

    def to_xarray(self):
        """The impact map (impact/map) as an xarray Dataset over (radius, velocity), SI
        with ``units`` attributes, each field's standard deviation from the calibrations
        (impact/map_std) as ``<field>_std`` where the calibrations give one (where the plan
        left the calibrated layers out, none, and ``attrs["std_note"]`` says why)."""
        import h5py
        import xarray as xr
        self._impact_only("impact map")
        with h5py.File(self.path, "r") as f:
            groups = [g for g in ("map", "map_std") if g in f["impact"]]
        if "map" not in groups:
            raise InputError(f"{self.path} holds no impact map: the scene's [outputs] want "
                             "no \"map\"")
        with xr.open_dataset(self.path, engine="h5netcdf", group="impact/map") as ds:
            ds = ds.load()
        if "map_std" not in groups:         # no calibrated spread
            if self.plan.decisions.get("std"):      # why: a calibrated layer left out
                ds.attrs["std_note"] = self.plan.decisions["std"]
            return ds
        with xr.open_dataset(self.path, engine="h5netcdf", group="impact/map_std") as std:
            std = std.load()
        return ds.assign({f"{k}_std": std[k] for k in std.data_vars})

    def to_dataframe(self):
        """The scene's impact (impact/point) as a table: one row per quantity, its value,
        standard deviation from the calibrations (NaN where none), unit (SI) and
        ``std_note``: why the std is NaN (empty where it is a number). Where the plan's
        target holds no calibrated layer (the substrate alone), the std is not computed:
        NaN with the plan's reason (``decisions["std"]``), also in ``attrs["std_note"]``.
        A sliding result: one row per layer (top first, substrate last), its quantities
        (`SlideResult.layers`, SI) and their ``_std`` (`slide`)."""
        import h5py
        import pandas as pd
        if self.sliding:
            d = self.slide()
            table = pd.DataFrame(d["layers"]).set_index("name")
            table.attrs["std_note"] = d["std_note"]
            return table

        from filmscale.continuum.contact.kinds import map_units
        units = map_units()
        with h5py.File(self.path, "r") as f:
            point = {k: float(f["impact/point"][k][()]) for k in f["impact/point"]}
            std = ({k: float(v[()]) for k, v in f["impact/point_std"].items()}
                   if "point_std" in f["impact"] else {})
        reason = self.plan.decisions.get("std") or (
            "not a quantity the calibrations' spread is propagated to" if std else
            "no calibrated parameter with a standard deviation")
        std = {k: std.get(k, math.nan) for k in point}
        table = pd.DataFrame({"value": point, "std": std,
                              "unit": {k: units.get(k, "") for k in point},
                              "std_note": {k: "" if math.isfinite(v) else reason
                                           for k, v in std.items()}}).rename_axis("quantity")
        table.attrs["std_note"] = self.plan.decisions.get("std", "")
        return table

    def calibrations(self) -> dict[str, Calibration]:
        """The calibrated layers by name, as `Calibration` objects (value, std, identified
        of E, sigma_y, n; ``summary()``)."""
        import h5py
        with h5py.File(self.path, "r") as f:
            cals = [Calibration.from_dict(json.loads(g.attrs["calibration"]))
                    for g in f["calibration"].values()]
        return {c.layer: c for c in cals}

    def figure(self):
        """The summary Figure of `filmscale run --figure` (`report.scene_figure`)."""
        self._impact_only("summary figure (report reads impact results)")
        from filmscale.workflows.report import scene_figure
        return scene_figure(self.path)


def run_scene(pipeline: PipelineScene, store: Path | str, out: Path | str) -> SceneResult:
    """Execute the plan: calibrations (MD units), then the impact evaluation (or a sliding
    scene's slide evaluation, `run_slide`); write ``out``."""
    check_request(pipeline)
    store = Path(store)
    store.mkdir(parents=True, exist_ok=True)
    units = {}
    calibrations, checks, run_records = calibrate_layers(pipeline, store, units)
    if pipeline.sliding:
        return run_slide(pipeline, store, out, (calibrations, checks, run_records), units)
    materials = {k: c.material() for k, c in calibrations.items()}
    h_star = {k: c.h_star.value for k, c in calibrations.items()
              if c.h_star is not None and math.isfinite(c.h_star.value)}
    plan = plan_scene(pipeline, materials, h_star)
    scene = pipeline.completed(materials, h_star)
    say("plan:\n" + plan.text())
    spread = parameter_spread(calibrations)
    correlation = spread_correlation(calibrations, spread)
    impact_path = unit_dir(store, "impact", {"scene": impact_inputs(pipeline, materials,
                                                                    h_star),
                                            "plan": plan.decisions, "spread": spread,
                                            "correlation": correlation.tolist()})
    with unit_lock(impact_path):
        if done_record(impact_path) is None:
            impact_path.mkdir(parents=True, exist_ok=True)
            perturbed = [pipeline.completed({**materials,
                                             k: replace(materials[k], **{name: value})},
                                            h_star) for k, name, value in spread
                         if not plan.decisions.get("std")]     # left out: NaN, not 0
            impact_evaluation(scene, plan, impact_path, perturbed, correlation)
            finish_unit(impact_path, {"decisions": plan.decisions}, ("impact.npz",))
            units[impact_path.name] = "ran"
        else:
            units[impact_path.name] = "reused"
    path = write_scene_result(out, pipeline, scene, plan, calibrations, checks, impact_path,
                              run_records)
    return SceneResult(path, plan, units)


def calibrate_layers(pipeline: PipelineScene, store: Path, units: dict
                     ) -> tuple[dict[int, Calibration], dict[int, list[CrossCheck]], dict]:
    """Each layer's calibration units (its sources' run units, their calibrations, a joint
    one for several sources), computed or reused; ``units`` gets each unit's "ran" or
    "reused". Returns (calibrations, cross-scale checks, run records) by layer."""
    calibrations: dict[int, Calibration] = {}
    checks: dict[int, list[CrossCheck]] = {}
    run_records: dict[str, dict] = {}
    law = pipeline.data.get("model", {}).get("contact_law", DEFAULT_LAW)
    for k, sources in layer_sources(pipeline).items():
        nu = float(pipeline.data["target"]["layers"][k]["nu"])
        parts, part_units = [], []
        for src in sources:
            runs, curves = source_units(src, pipeline.base, store)
            for path, reused in runs:
                units[path.name] = "reused" if reused else "ran"
            record = done_record(runs[0][0]) if runs else None
            if record is not None:
                run_records[f"{src.kind}_{k}" + (f"_{len(part_units)}" if len(sources) > 1
                                                 else "")] = record
            cal, cal_path, reused = calibration_unit(src, [path for path, _ in runs], curves,
                                                     nu, law, pipeline.base, store)
            units[cal_path.name] = "reused" if reused else "ran"
            part_units.append(cal_path)
            parts.append((src, cal, curves, src.film(pipeline.base, record)))
        if len(sources) > 1:
            cal, cal_path, reused = joint_unit(
                sources[0].name, lambda: [calibration_part(*p, law) for p in parts],
                part_units, store)
            units[cal_path.name] = "reused" if reused else "ran"
        calibrations[k] = cal
        checks[k] = [cal.cross_check(s.tolerance, s.label if len(sources) > 1 else "",
                                     s.exclude) for s in sources]
        say(cal.summary() + "".join(f"\n  {c.text()}" for c in checks[k]))
    return calibrations, checks, run_records


def run_slide(pipeline: PipelineScene, store: Path, out: Path | str, calibrated: tuple,
              units: dict) -> SceneResult:
    """A sliding scene after its calibrations (``calibrated``: `calibrate_layers`'
    calibrations, checks and run records): the slide unit (`units.slide_evaluation`, hashed
    over the completed scene data, friction, load and the calibrations' spread), computed or
    reused, then the result file (`result.write_slide_result`)."""
    calibrations, checks, run_records = calibrated
    materials = {k: c.material() for k, c in calibrations.items()}
    scene = pipeline.slide_scene(materials)
    spread = parameter_spread(calibrations)
    correlation = spread_correlation(calibrations, spread)
    completed = filled_data(pipeline.data, materials, None)
    path = unit_dir(store, "slide", {"scene": completed, "friction": scene.friction,
                                     "normal_load": scene.normal_load, "spread": spread,
                                     "correlation": correlation.tolist()})
    with unit_lock(path):
        record = done_record(path)
        units[path.name] = "reused" if record is not None else "ran"
        if record is None:
            record = finish_unit(path, slide_evaluation(scene, path, spread, correlation),
                                 ("slide.npz",))
    plan = plan_scene(pipeline, materials, slide_cost_s=record["slide_seconds"])
    say("plan:\n" + plan.text())
    note = "" if spread else ("not propagated: " + (
        "the calibrations identified no E or sigma_y with a standard deviation"
        if calibrations else "no layer is calibrated"))
    written = write_slide_result(out, pipeline, plan, calibrations, checks, path, record,
                                 run_records, completed, note)
    return SceneResult(written, plan, units)


def parameter_spread(calibrations: dict[int, Calibration]) -> list[tuple[int, str, float]]:
    """(layer, parameter, value + 1 std) of every identified E and sigma_y of the calibrated
    layers: the shifts whose results give the impact results' standard deviations."""
    return [(k, name, p.value + p.std) for k, cal in calibrations.items()
            for name, p in (("E", cal.E), ("sigma_y", cal.sigma_y))
            if p.identified and math.isfinite(p.std) and p.std > 0]


def spread_correlation(calibrations: dict[int, Calibration], spread) -> np.ndarray:
    """The correlation matrix of the shifted parameters of `parameter_spread`: each layer's
    E and sigma_y as its calibration correlates them, different layers independent."""
    rho = np.eye(len(spread))
    for i, (k, name, _) in enumerate(spread):
        for j, (k2, name2, _) in enumerate(spread):
            if i != j and k == k2 and {name, name2} == {"E", "sigma_y"}:
                rho[i, j] = calibrations[k].correlation
    return rho


def impact_inputs(pipeline: PipelineScene, materials, h_star=None) -> dict:
    """The complete impact inputs: the scene data with calibrated values filled in."""
    return {"data": filled_data(pipeline.data, materials, h_star),
            "outputs": sorted(pipeline.outputs),
            "tolerance": pipeline.tolerance}


