"""The run units of a scene: an MD or particle-model indentation, a calibration (of one
source or several jointly) and the impact evaluation (or a sliding scene's slide
evaluation), each computed in (or reused from) its
folder of the unit store (`workflows.store`: ``STORE/<kind>-<hash>``, the hash over its
physics inputs and the code version; ``done.json`` with checksums; one process per unit; a
corrupted unit set aside and computed again; an interrupted MD unit resumed from its last
restart file). Every file of a unit is written atomically."""

from __future__ import annotations

from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

from filmscale.continuum.calibration.ensemble import calibrate_ensemble
from filmscale.continuum.calibration.joint import CalibrationPart, combine, sharp_part, sphere_part
from filmscale.continuum.calibration.result import Calibration
from filmscale.continuum.calibration.route import calibrate, sharp_tip_of, tip_counterpart
from filmscale.core.files import atomic_path
from filmscale.workflows.plan import Plan, chosen_model
from filmscale.workflows.progress import with_step_progress
from filmscale.workflows.result import SLIDE_LAYER_UNITS
from filmscale.workflows.scene import Scene
from filmscale.workflows.pipeline_scene import CalibrationSource
from filmscale.workflows.store import (CURVE_ARRAYS, MD_RECORD, done_record, finish_unit,
                                       own_folder, say, stream_digest, unit_dir, unit_lock)

def run_md(spec, path: Path, ranks: int):
    """The MD indentation, and the potential's own elastic constants of the film and of the
    substrate under it (0 K, Voigt-Reuss-Hill E and nu, and the indentation modulus M of
    the slab's surface orientation): the substrate for the film's calibration, the film's
    for the check of the calibrated E against the potential. A film named by a melt-quench
    recipe is cut from its block, made in (or reused from) the unit's store first; its
    constants are the block's own (`md.amorphous_run.block_elastic_constants`)."""
    from filmscale.continuum.elasticity import indentation_modulus
    from filmscale.md.amorphous_run import layer_elastic_constants
    from filmscale.md.analysis import analyze_indentation
    from filmscale.md.engine import EngineOptions
    from filmscale.md.record import RECORD_NAME, run_provenance, write_record
    from filmscale.md.run import run_indentation
    from filmscale.md.structures import surface_normal
    from filmscale.workflows.amorphous_units import with_blocks
    engine = EngineOptions(np=ranks)
    spec = with_blocks(spec, path.parent, engine)
    run = with_step_progress(spec.protocol.schedule().s_end, f"{path.name} (MD)",
                             lambda progress: run_indentation(spec, path, engine,
                                                              progress=progress))
    record = {"wall_time": run.wall_time, **run_provenance(run)}
    layers = {"top": (spec.slab.films or (spec.slab.substrate,))[0]}
    if spec.slab.films:
        layers["substrate"] = spec.slab.substrate
    constants = {key: layer_elastic_constants(spec.potential, layer, path / f"elastic-{key}")
                 for key, layer in layers.items()}
    # the record `filmscale md indent` writes: the unit's curve, analysis and provenance
    write_record(run, analyze_indentation(run, constants["top"]), constants["top"],
                 path / RECORD_NAME)
    normal = surface_normal(spec.slab.orientation)
    record["potential_elastic"] = {
        key: {"element": layers[key].element, "structure": layers[key].structure,
              "E": c.average.E, "nu": c.average.nu, "M": indentation_modulus(c.C, normal),
              "orientation": spec.slab.orientation}
        for key, c in constants.items()}
    if spec.slab.films:
        sub = constants["substrate"].average
        record["film"] = {"thickness": spec.slab.films[0].thickness,
                          "substrate": {"name": spec.slab.substrate.element,
                                        "E": sub.E, "nu": sub.nu}}
    return run.curve, record


def run_particle_model(spec, path: Path, ranks: int):
    from filmscale.md.engine import EngineOptions, lammps_info
    from filmscale.md.particle_inputs import estimated_steps
    from filmscale.md.particle_run import run_particles
    run = with_step_progress(estimated_steps(spec), f"{path.name} (particles)",
                             lambda progress: run_particles(
                                 spec, path, EngineOptions(np=ranks, omp_threads=1),
                                 progress=progress))
    return run.curve(), {"wall_time": run.wall_time, "steps": run.steps,
                         "particles": spec.grid.n_particles, "method": spec.method,
                         **lammps_info()}


#: run-unit kind and runner of each run source
_RUNNERS = {"md": ("md-indent", run_md), "particles": ("particle-indent", run_particle_model)}


def run_unit(src: CalibrationSource, spec, store: Path, wait: bool = True
             ) -> tuple[Path, bool] | None:
    """Run (or resume, or reuse) one MD or particle-model indentation of a source; None when
    another process holds it and not ``wait``."""
    kind, runner = _RUNNERS[src.kind]
    path = run_unit_path(src, spec, store)
    with unit_lock(path, wait) as held:
        if not held:
            return None
        if done_record(path) is not None:
            return path, True
        say(f"{kind} {spec.name} for {src.name} in {path}")
        own_folder(path, create=False)
        curve, record = runner(spec, path, src.np)
        if src.kind == "md":            # the curve is in the record run_md wrote
            files = (MD_RECORD,)
        else:
            files = (CURVE_ARRAYS,)
            with atomic_path(path / CURVE_ARRAYS) as tmp:
                with open(tmp, "wb") as f:
                    np.savez(f, h=curve.h, P=curve.P, segment=curve.segment)
        finish_unit(path, {"indenter": curve.indenter.spec,
                           "base_depth": curve.meta.get("base_depth"), **record}, files)
    return path, False


def run_unit_path(src: CalibrationSource, spec, store: Path) -> Path:
    """Where the run unit of ``spec`` (an MD or particle spec of ``src``) lives in ``store``."""
    return unit_dir(store, _RUNNERS[src.kind][0], {"spec": _physics(spec.to_dict())})


def _physics(spec: dict) -> dict:
    """A spec's record as its unit is hashed: the potential by content (its sha256), not by
    where it is installed."""
    if isinstance(spec.get("potential"), dict):
        spec = {**spec, "potential": {k: v for k, v in spec["potential"].items()
                                      if k != "path"}}
    return spec


def source_units(src: CalibrationSource, base: Path, store: Path
                 ) -> tuple[list[tuple[Path, bool]], list]:
    """The source's run units, each with whether it was reused (none for curve files: they
    are read), and its curves: one per run unit (an MD ensemble has one per seed)."""
    if src.kind == "curves":
        return [], src.curves(base)
    specs = src.member_specs(base)
    # first the members no other process holds, then wait for the rest: the tasks of a job
    # array that share an ensemble spread over its seeds instead of queueing on the first
    units = [run_unit(src, spec, store, wait=False) for spec in specs]
    units = [u or run_unit(src, spec, store) for u, spec in zip(units, specs)]
    return units, [unit_curve(path) for path, _ in units]


def unit_curve(path: Path):
    """The curve of a finished MD or particle unit (h, P and segments, as calibrated)."""
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    meta = done_record(path)
    if (path / CURVE_ARRAYS).is_file():
        with np.load(path / CURVE_ARRAYS) as d:
            h, P, segment = d["h"], d["P"], d["segment"]
    else:
        from filmscale.md.record import read_record_curve
        c = read_record_curve(path / MD_RECORD)
        h, P, segment = c.h, c.P, c.segment
    # the rigid base's depth, for the calibration's note on it (absent in older units)
    base = {"base_depth": meta["base_depth"]} if meta.get("base_depth") else {}
    return LoadDisplacementCurve(h, P, segment=segment, indenter=meta["indenter"],
                                 meta={"source": str(path), **base})


def _file_digest(path: Path) -> str:
    """The sha256 of a source file of the user's (links followed: it is no store file),
    read in chunks."""
    with open(path, "rb") as f:
        return stream_digest(f.fileno())


def calibration_part(src: CalibrationSource, cal: Calibration, curves: list, film, law: str
                     ) -> CalibrationPart:
    """A source's calibration as a joint calibration of its layer takes it; ``film`` is
    its (thickness, substrate), (None, None) for a half-space (`CalibrationSource.film`):
    a sphere source's film is forward-modelled on its own substrate in the joint fit too."""
    indenter, E_i, nu_i = tip_counterpart(src.tip_material)
    tip = sharp_tip_of(curves)
    if tip is None:
        return sphere_part(src.label, cal, curves, law, indenter, *film)
    return sharp_part(src.label, cal, curves, tip, E_i=E_i, nu_i=nu_i)


def _stored_calibration(path: Path, compute) -> tuple[Calibration, bool]:
    """The calibration stored in unit ``path`` (reused), or ``compute()`` stored there."""
    with unit_lock(path):
        record = done_record(path)
        reused = record is not None
        if not reused:
            own_folder(path)
            cal = compute()
            fitted = {}
            for i, (h, P, F) in enumerate(cal.fitted_curves):
                fitted.update({f"h_{i}": h, f"P_{i}": P, f"P_model_{i}": F})
            fitted.update({f"fitted_for_{i}": r for i, r in enumerate(cal.fit_roles)})
            with atomic_path(path / "fit.npz") as tmp:
                with open(tmp, "wb") as f:
                    np.savez(f, **fitted)
            record = finish_unit(path, cal.to_dict(), ("fit.npz",))
    with np.load(path / "fit.npz") as d:
        count = sum(name.startswith("h_") for name in d.files)
        fitted = tuple((d[f"h_{i}"], d[f"P_{i}"], d[f"P_model_{i}"]) for i in range(count))
        roles = tuple(d[f"fitted_for_{i}"] for i in range(count)) \
            if f"fitted_for_{count - 1}" in d.files else ()
    return Calibration.from_dict(record, fitted, roles), reused


def calibration_unit(src: CalibrationSource, run_paths: list[Path], curves: list, nu: float,
                     law: str, base: Path, store: Path) -> tuple[Calibration, Path, bool]:
    """Calibrate (or reuse the calibration of) a source's curves
    (`filmscale.continuum.calibration.calibrate`; an MD ensemble through
    `calibrate_ensemble`): its tip material, and for a film its thickness and substrate
    (from the run unit's record for an MD source)."""
    origin = [p.name for p in run_paths] if run_paths else \
        {f: _file_digest(Path(base) / f) for f in src.source}
    record = done_record(run_paths[0]) if run_paths else None
    thickness, substrate = src.film(base, record)
    path = unit_dir(store, "calibration", {
        "source": origin, "nu": nu, "law": law, "layer": src.name, "tip": src.tip,
        "tip_material": src.tip_material, "film_thickness": thickness,
        "substrate": None if substrate is None else asdict(substrate),
        "contact_zero": src.contact_zero})
    how = calibrate_ensemble if len(run_paths) > 1 else calibrate
    cal, reused = _stored_calibration(path, lambda: how(
        curves, nu=nu, tip_material=src.tip_material, thickness=thickness, substrate=substrate,
        law=law, layer=src.name, contact_zero=src.contact_zero))
    return cal, path, reused


def joint_unit(name: str, parts, part_units: list[Path], store: Path
               ) -> tuple[Calibration, Path, bool]:
    """The joint calibration of a layer from its sources' calibration units; ``parts()``
    gives the `CalibrationPart` of each (built only when the unit runs)."""
    path = unit_dir(store, "calibration-joint", {"layer": name,
                                                 "parts": [p.name for p in part_units]})
    cal, reused = _stored_calibration(path, lambda: combine(parts(), name))
    return cal, path, reused


def _impact_arrays(scene: Scene, plan: Plan, history: bool) -> dict[str, np.ndarray]:
    """The point (and history, map) results of the plan's model on ``scene``: the normal
    impact of the plan's model kind, with the oblique kind's tangential results at the
    point."""
    from filmscale.continuum.contact.kinds import kind_for, kind_named
    kind = kind_named(plan.decisions.get("kind", "sphere"))
    normal = kind_for(kind.shape)
    model = chosen_model(scene, plan.decisions["target"], plan.decisions["law"], normal)
    imp, options = scene.impactor, scene.kind_options(normal)
    one = normal.solve(model, imp.velocity, imp.radius, imp.mass, options)
    arrays = {f"point/{k}": v for k, v in asdict(one).items()
              if isinstance(v, (int, float)) and not isinstance(v, bool)}
    if kind.oblique:
        arrays.update(_tangential_point(scene, plan, kind, model))
    if history:
        hist = normal.history(model, imp.velocity, imp.radius, imp.mass, options)
        arrays.update({f"history/{k}": getattr(hist, k)
                       for k in ("time", "delta", "velocity", "force", normal.size)})
    if plan.decisions.get("map"):
        V, R = scene.map.axes()
        mp = normal.impact_map(model, V, R, imp.mass, options)
        arrays.update({f"map/{k}": np.asarray(v) for k, v in mp.to_dict().items()
                       if np.asarray(v).dtype.kind in "fiub"})
    return arrays


def _tangential_point(scene: Scene, plan: Plan, kind, model) -> dict:
    """The oblique kind's tangential results at the scene's point."""
    imp = scene.impactor
    options = scene.kind_options(kind) | {"angle": plan.decisions["angle"],
                                          "friction": plan.decisions["friction"]}
    from filmscale.continuum.contact.oblique import OBLIQUE_FIELDS, REGIMES
    res = kind.solve(model, imp.velocity, imp.radius, imp.mass, options)
    arrays = {f"point/{k}": getattr(res, k) for k in ("angle", "friction", *OBLIQUE_FIELDS)}
    # an index into the regimes of the oblique result: the store holds numbers
    arrays["point/regime_tangential"] = REGIMES.index(res.regime_tangential)
    return arrays


#: point and map results that carry a standard deviation from the calibrations
UNCERTAIN = ("delta_max", "force_max", "mean_pressure_max", "contact_radius_max",
             "contact_half_width", "contact_time", "residual_depth", "restitution")


def impact_evaluation(scene: Scene, plan: Plan, path: Path, perturbed=(), correlation=None):
    """The impact results of the plan, and with ``perturbed`` (scenes with one calibrated
    parameter raised by its standard deviation each) their standard deviation, linearised:
    with d_i = result(p + std_i) - result(p) and rho the parameters' correlation matrix
    (identity when None), std^2 = sum_ij rho_ij d_i d_j. Written as ``point_std/*`` and
    ``map_std/*`` beside the results. Not where the plan says the calibrations cannot reach
    the modelled target (``decisions["std"]``: a calibrated layer left out), where each d_i
    would be 0 by construction: then nothing is written and the std reads NaN, not 0."""
    own_folder(path)        # a real folder of the store, never written through a link
    arrays = _impact_arrays(scene, plan, bool(plan.decisions.get("history")))
    if perturbed and not plan.decisions.get("std"):
        rho = np.eye(len(perturbed)) if correlation is None else np.asarray(correlation)
        keys = [k for k in arrays if k.split("/")[0] in ("point", "map")
                and k.split("/")[1] in UNCERTAIN]
        shifts = [_impact_arrays(shifted, plan, False) for shifted in perturbed]
        for k in keys:
            d = np.stack([np.asarray(other[k], dtype=float) - arrays[k] for other in shifts])
            var = np.einsum("i...,ij,j...->...", d, rho, d)
            arrays[k.replace("/", "_std/", 1)] = np.sqrt(np.clip(var, 0.0, None))
    with atomic_path(path / "impact.npz") as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **{k.replace("/", "__"): np.asarray(v) for k, v in arrays.items()})


#: the quantities of a slide evaluation that carry a standard deviation from the calibrations
SLIDE_UNCERTAIN = ("von_mises_max", "yield_ratio", "tensile_max", "interface_shear_max",
                   "p0", "contact_size")


def slide_arrays(result) -> dict[str, np.ndarray]:
    """A `SlideResult` as arrays (SI): per layer (top first, substrate last) each of
    `SLIDE_LAYER_UNITS` (NaN where a row has none: a yield ratio without sigma_y, the
    substrate's interface shear, its infinite bottom stays inf), p0 and the contact size,
    and the x-z field: ``field_x`` (nx), ``field_z`` (rows: every layer's depths, top
    first), ``field_layer`` (rows: the layer of each) and ``field_von_mises`` (rows, nx)."""
    from filmscale.continuum.contact.slider import field_von_mises
    arrays = {key: np.array([np.nan if getattr(r, key) is None else getattr(r, key)
                             for r in result.layers], dtype=float)
              for key in SLIDE_LAYER_UNITS}
    arrays["p0"] = np.float64(result.contact.p0)
    arrays["contact_size"] = np.float64(result.contact.size)
    x, depths, vm = field_von_mises(result)
    arrays.update(field_x=np.asarray(x), field_z=np.concatenate(depths),
                  field_layer=np.concatenate([np.full(z.size, j) for j, z in enumerate(depths)]),
                  field_von_mises=np.concatenate(vm))
    return arrays


def shifted_slide(scene, base: dict, layer: int, name: str, value: float) -> dict:
    """The arrays of `slide_arrays` with one calibrated parameter shifted: E by a new slide;
    sigma_y (the stresses are elastic and do not depend on it) by the layer's yield ratio
    alone, exactly."""
    from filmscale.continuum.contact.slider import slide
    from filmscale.continuum.materials import Layer, LayerStack
    if name == "sigma_y":
        ratio = base["yield_ratio"].copy()
        ratio[layer] = base["von_mises_max"][layer] / value
        return {**base, "yield_ratio": ratio}
    layers = list(scene.stack.layers)
    old = layers[layer]
    layers[layer] = Layer(old.thickness, replace(old.material, E=value))
    stack = LayerStack(tuple(layers), scene.stack.substrate)
    return slide_arrays(slide(stack, scene.slider, scene.normal_load, scene.friction))


def slide_evaluation(scene, path: Path, spread=(), correlation=None) -> dict:
    """The slide of a completed `SlideScene` (`continuum.contact.slider.slide`) into unit
    ``path``: ``slide.npz`` (`slide_arrays`) and, with ``spread`` ((layer, "E" or "sigma_y",
    value + std) of the calibrated parameters, `pipeline.parameter_spread`), the standard
    deviations ``<name>_std`` of `SLIDE_UNCERTAIN`, linearised as the impact's
    (`impact_evaluation`: std^2 = sum_ij rho_ij d_i d_j). Returns the record: the result's
    ``to_dict``, the wall time of the one slide (``slide_seconds``) and of the whole unit."""
    import time

    from filmscale.continuum.contact.slider import slide
    own_folder(path)
    start = time.perf_counter()
    result = slide(scene.stack, scene.slider, scene.normal_load, scene.friction)
    one = time.perf_counter() - start
    arrays = slide_arrays(result)
    if spread:
        rho = np.eye(len(spread)) if correlation is None else np.asarray(correlation)
        shifts = [shifted_slide(scene, arrays, *shift) for shift in spread]
        for key in SLIDE_UNCERTAIN:
            d = np.stack([np.asarray(other[key], dtype=float) - arrays[key]
                          for other in shifts])
            var = np.einsum("i...,ij,j...->...", d, rho, d)
            arrays[f"{key}_std"] = np.sqrt(np.clip(var, 0.0, None))
    with atomic_path(path / "slide.npz") as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **arrays)
    return {"slide": result.to_dict(), "slide_seconds": one,
            "wall_time": time.perf_counter() - start}
