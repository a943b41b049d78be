"""The pipeline that links the scales: scene -> plan -> run units -> one HDF5 result.

A pipeline scene is an impact scene (`workflows.scene`, docs/scenes.md) plus:

- ``[target.layers.calibrate]`` on a layer: where its E and sigma_y come from when the scene
  does not give them: ``md`` (an MD preset or spec file), ``particles`` (a particle-model
  preset or spec file) or ``curves`` (curve files, ``tip`` where they name none), with ``np``
  MPI ranks and the cross-scale check's ``tolerance``. The layer still states ``nu`` (a
  sphere's loading does not separate E and nu). Sharp curves at three or more depths also
  give the layer's Nix-Gao length h* (the scene's ``h_star``). Several sources of one layer
  (``[[target.layers.calibrate]]`` tables: an MD run and measured curves, say) are
  calibrated one by one and then jointly (`workflows.joint`): one Nix-Gao law of sigma_y
  over all their depths.
- ``[outputs]``: ``want`` = any of maxima, history, map, restitution, residual_damage,
  tangential; ``tolerance`` (relative) for the planner's choices.
- ``impactor.friction`` and ``impactor.angle`` (degrees from the normal).

`plan_scene` chooses the models (rules below) and says why, with an estimated error and a
cost timed on this machine; `run_scene` executes the plan. Every run unit (an MD indentation,
a calibration, the impact evaluation) lives in ``STORE/<kind>-<hash>``, the hash taken over
its complete inputs and the code version, so a rerun reuses finished units and an interrupted
scene resumes where it stopped (an MD unit from its last restart file). Units are written
atomically; the scene's result file too.

Planner rules (physics.md; benchmarks/impact_speed_vs_error.py):
1. MD runs only for layers whose E or sigma_y is missing.
2. Normal impact only with friction below 0.3, a normal approach and no tangential output;
   anything else is refused (filmscale has no oblique impact model).
3. The films are modelled (Gao-weighted profile) only where skipping them changes the
   maxima by more than the tolerance at the scene's extreme points; otherwise the substrate
   alone, with that change reported as the error of skipping them.
4. The closed-form Hertz impact where no point yields; otherwise the elastic-plastic law.
5. The fast maxima path (energy quadrature) unless time histories are asked for.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import json
import math
import sys
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from filmscale.continuum import ImpactModel
from filmscale.continuum.materials import ElasticPlastic

from .scene import Scene, read_toml, scene_from_data
from filmscale.continuum.calibration.joint import CalibrationPart, combine, sharp_part, sphere_part
from filmscale.continuum.calibration.result import Calibration, CrossCheck, Parameter
from filmscale.continuum.calibration.sharp import with_size_effect
from filmscale.continuum.calibration.sphere import calibrate_sphere
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.profiles import StackProfile
from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError
from filmscale.core.provenance import provenance
from filmscale.core.files import atomic_h5, atomic_path, read_text

OUTPUTS = ("maxima", "history", "map", "restitution", "residual_damage", "tangential")
FRICTION_LIMIT = 0.3
#: /2: ``cross_check`` of a calibrated layer is a list (one check per source)
RESULT_FORMAT = "filmscale.scene_result/2"
#: MD throughput measured for the quick preset (14 336 atoms x 5 500 steps in 184 s on
#: 2 ranks, README), atom-steps per second per rank: the cost estimate of an MD unit
MD_ATOM_STEPS_PER_RANK_S = 14336 * 5500 / 184.0 / 2
#: particle-model throughput (TLSPH, lammps.md), particle-steps per second per core; PERI
#: (peri/lps) is about 4 times slower per particle
PARTICLE_STEPS_PER_CORE_S = 2.6e5
PERI_SLOWDOWN = 4.0


@functools.lru_cache(maxsize=None)
def _md_spec(md: str, base: Path):
    from filmscale.md.spec import PRESETS, load_spec, preset
    return preset(md) if md in PRESETS else load_spec(base / md)


@functools.lru_cache(maxsize=None)
def _particle_spec(name: str, base: Path):
    from filmscale.md.particle_spec import PRESETS, load_spec, preset
    return preset(name, "indent") if name in PRESETS["indent"] else \
        load_spec(base / name, "indent")


SOURCE_KINDS = ("md", "particles", "curves")
#: default tolerance of the cross-scale check: rms misfit of the calibrated forward model
#: over the calibration curves, as a fraction of the largest load
CROSS_CHECK_TOLERANCE = 0.1


@dataclass(frozen=True)
class CalibrationSource:
    """Where a layer's E and sigma_y come from: an MD indentation (preset or spec file), a
    particle-model indentation (preset or spec file), or curve files (measured)."""

    layer: int
    name: str
    kind: str                    #: one of SOURCE_KINDS
    source: tuple[str, ...]      #: the preset or spec file, or the curve files
    np: int = 1
    tip: str = ""                #: indenter of curve files that do not name one
    tolerance: float = CROSS_CHECK_TOLERANCE

    @property
    def label(self) -> str:
        """The source as results name it: ``md:quick``, ``curves:a.csv,b.h5``."""
        return f"{self.kind}:{','.join(self.source)}"

    def spec(self, base: Path):
        """The run's spec (None for curve files)."""
        if self.kind == "md":
            return _md_spec(self.source[0], Path(base).resolve())
        if self.kind == "particles":
            return _particle_spec(self.source[0], Path(base).resolve())
        return None

    def curves(self, base: Path) -> list:
        """The curves of curve files, each with its indenter (``tip`` where unnamed)."""
        from filmscale.continuum.indentation.io import read_curves
        out = []
        for name in self.source:
            for key, c in read_curves(Path(base) / name).items():
                if not c.indenter:
                    if not self.tip:
                        raise InputError(f"target.layers[{self.layer}].calibrate: curve "
                                         f"{key!r} of {name} names no indenter; give tip "
                                         "(e.g. \"sphere:5um\" or \"berkovich\")")
                    c = replace(c, indenter=self.tip)
                out.append(c)
        return out


@dataclass(frozen=True)
class PipelineScene:
    """A parsed pipeline scene: the impact scene's data (layers to calibrate lack E and
    sigma_y until `completed`), the calibration sources and the outputs wanted."""

    data: dict
    text: str
    source: str
    base: Path
    calibrations: tuple[CalibrationSource, ...]
    outputs: frozenset
    tolerance: float
    friction: float
    angle: float

    def completed(self, materials: dict[int, ElasticPlastic],
                  h_star: dict[int, float] | None = None) -> Scene:
        """The impact scene with each calibrated layer's E and sigma_y (and the Nix-Gao
        length h*, where calibrated) filled in."""
        return scene_from_data(_filled(self.data, materials, h_star), self.text, self.source,
                               self.base)


def _filled(data: dict, materials: dict[int, ElasticPlastic],
            h_star: dict[int, float] | None) -> dict:
    data = copy.deepcopy(data)
    for k, mat in materials.items():
        layer = data["target"]["layers"][k]
        layer.setdefault("E", mat.E)
        layer.setdefault("sigma_y", mat.sigma_y)
    for k, h in (h_star or {}).items():
        data["target"]["layers"][k].setdefault("h_star", h)
    return data


def _calibration_source(cal, where: str, layer: int, name: str) -> CalibrationSource:
    """One ``calibrate`` table, checked."""
    allowed = set(SOURCE_KINDS) | {"np", "tip", "tolerance"}
    kinds = [key for key in SOURCE_KINDS if isinstance(cal, dict) and key in cal]
    if not isinstance(cal, dict) or set(cal) - allowed or len(kinds) != 1:
        raise InputError(f"{where} takes exactly one of md (an MD preset or spec file), "
                         "particles (a particle-model preset or spec file) or curves (a "
                         f"list of curve files), and np, tip, tolerance; got {cal!r} (one "
                         "layer takes several sources as [[target.layers.calibrate]] tables)")
    kind = kinds[0]
    np_ = cal.get("np", 1)
    if isinstance(np_, bool) or not isinstance(np_, int) or not 1 <= np_ <= 4096:
        raise InputError(f"{where}.np = {np_!r} must be an integer in [1, 4096]")
    given = cal[kind]
    files = given if kind == "curves" else [given]
    if not isinstance(files, list) or not files or \
            not all(isinstance(f, str) for f in files):
        raise InputError(f"{where}.{kind} = {given!r} must be "
                         + ("a non-empty list of file names" if kind == "curves"
                            else "a preset name or a spec file name"))
    tip = cal.get("tip", "")
    if tip:
        from filmscale.continuum.indentation.tips import parse_tip
        parse_tip(tip)
    tol = check_real(f"{where}.tolerance", cal.get("tolerance", CROSS_CHECK_TOLERANCE),
                     low=1e-4, high=1.0)
    return CalibrationSource(layer, name, kind, tuple(files), np_, str(tip), tol)


def parse_pipeline(text: str, source: str = "<scene>", base: Path | None = None
                   ) -> PipelineScene:
    """Validate a pipeline scene; an MD spec is loaded (and checked) here, before any run."""
    base = Path(".") if base is None else base
    data = read_toml(text, source)
    outputs = data.pop("outputs", {})
    if not isinstance(outputs, dict) or set(outputs) - {"want", "tolerance"}:
        raise InputError("[outputs] takes want (a list) and tolerance; got "
                         f"{sorted(outputs) if isinstance(outputs, dict) else outputs!r}")
    want = outputs.get("want", ["maxima"])
    if not isinstance(want, list) or not want:
        raise InputError(f"outputs.want must be a list from {', '.join(OUTPUTS)}; got {want!r}")
    for i, w in enumerate(want):
        check_choice(f"outputs.want[{i}]", w, OUTPUTS)
    tolerance = check_real("outputs.tolerance", outputs.get("tolerance", 0.05), low=1e-6,
                           high=0.5)
    imp = data.get("impactor", {})
    friction = check_real("impactor.friction", imp.pop("friction", 0.0), low=0.0, high=10.0)
    angle = check_real("impactor.angle", imp.pop("angle", 0.0), low=0.0, high=90.0,
                       high_open=True, unit="degrees")
    sources = []
    layers = data.get("target", {}).get("layers", [])
    for k, layer in enumerate(layers if isinstance(layers, list) else []):
        if not isinstance(layer, dict) or "calibrate" not in layer:
            continue
        cal = layer.pop("calibrate")
        tables = cal if isinstance(cal, list) and cal else [cal]
        given = "E" in layer and "sigma_y" in layer     # given properties win (rule 1)
        for j, table in enumerate(tables):
            where = f"target.layers[{k}].calibrate" + (f"[{j}]" if isinstance(cal, list)
                                                       else "")
            src = _calibration_source(table, where, k, str(layer.get("name", f"layer {k}")))
            if given:
                continue
            if src.kind == "curves":
                src.curves(base)    # readable, each with an indenter, before any work
            else:
                src.spec(base)      # the spec's own checks, before any work
            sources.append(src)
    pipeline = PipelineScene(data, text, source, base, tuple(sources), frozenset(want),
                             tolerance, friction, angle)
    placeholder = {s.layer: ElasticPlastic(100e9, 0.3, 1e9) for s in sources}
    pipeline.completed(placeholder)     # every other key checked now
    return pipeline


def load_pipeline(path) -> PipelineScene:
    path = Path(path)
    return parse_pipeline(read_text(path, "scene"), str(path), path.parent)


# ---------------------------------------------------------------- the plan

@dataclass(frozen=True)
class Step:
    """One model of the plan: what runs, why it was chosen, its error and cost."""

    name: str
    model: str
    reason: str
    error: str
    cost_s: float


@dataclass(frozen=True)
class Plan:
    steps: tuple[Step, ...]
    decisions: dict = field(default_factory=dict)   #: target, law, path, points

    def text(self) -> str:
        lines = []
        for i, s in enumerate(self.steps, 1):
            cost = f"{s.cost_s:.3g} s" if math.isfinite(s.cost_s) else "after calibration"
            lines += [f"{i}. {s.name}: {s.model}", f"   why:   {s.reason}",
                      f"   error: {s.error}", f"   cost:  {cost}"]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"steps": [asdict(s) for s in self.steps], "decisions": self.decisions}


def _calibration_step(src: CalibrationSource, base: Path, joint: bool) -> Step:
    """The plan step of one calibration source, its cost from measured throughputs;
    ``joint``: one of several sources of its layer."""
    fit = (f"then a calibration (sphere tips: least squares to the contact law; sharp tips: "
           f"Dao reverse analysis) and a cross-scale check to {src.tolerance:.0%} rms")
    spec = src.spec(base)
    if src.kind == "md":
        atoms, steps = spec.slab_built.n_atoms, spec.protocol.schedule().s_end
        cost = atoms * steps / (MD_ATOM_STEPS_PER_RANK_S * src.np)
        model = (f"MD indentation ({src.source[0]}: {atoms} atoms, {steps} steps, {src.np} "
                 f"rank(s)) {fit}")
    elif src.kind == "particles":
        from filmscale.md.particles import estimated_steps
        n, steps = spec.grid.n_particles, estimated_steps(spec)
        rate = PARTICLE_STEPS_PER_CORE_S / (PERI_SLOWDOWN if spec.method == "peri" else 1)
        cost = n * steps / (rate * src.np)
        model = (f"particle-model indentation ({src.source[0]}: {spec.method}, {n} particles, "
                 f"about {steps} steps, {src.np} rank(s)) {fit}")
    else:
        cost = 0.0
        model = f"curves from {', '.join(src.source)} {fit}"
    return Step(f"calibrate {src.name}" + (f" from {src.label}" if joint else ""), model,
                "the layer's E and sigma_y are not given (rule 1)",
                "the fit's own standard deviations, reported with the calibration", cost)


def _joint_step(name: str, sources: list[CalibrationSource]) -> Step:
    return Step(f"calibrate {name} jointly",
                f"one Nix-Gao law of sigma_y over {', '.join(s.label for s in sources)} "
                "(weighted least squares; E and n inverse-variance means); a cross-scale "
                "check per source",
                "the layer has several sources: nanometre and micrometre strengths both "
                "reach the depth profile", "standard deviations of the joint fit", 0.0)


def layer_sources(pipeline: PipelineScene) -> dict[int, list[CalibrationSource]]:
    """The calibration sources of each layer to calibrate, in scene order."""
    by_layer: dict[int, list[CalibrationSource]] = {}
    for src in pipeline.calibrations:
        by_layer.setdefault(src.layer, []).append(src)
    return by_layer


def _points(scene: Scene, outputs) -> tuple[np.ndarray, np.ndarray]:
    """The (V, R) points a decision must hold at: the scene's impact, and for a map its
    four corners."""
    V, R = [scene.impactor.velocity], [scene.impactor.radius]
    if "map" in outputs:
        v_axis, r_axis = scene.map.axes()
        for v in (v_axis[0], v_axis[-1]):
            for r in (r_axis[0], r_axis[-1]):
                V.append(v)
                R.append(r)
    return np.array(V), np.array(R)


def _timed(fn):
    start = time.perf_counter()
    value = fn()
    return value, time.perf_counter() - start


def plan_impact(scene: Scene, outputs, tolerance: float, friction: float = 0.0,
                angle: float = 0.0) -> Plan:
    """Rules 2-5 on a complete scene."""
    if friction >= FRICTION_LIMIT or angle > 0 or "tangential" in outputs:
        raise InputError(
            f"impactor.friction = {friction:g}, impactor.angle = {angle:g} deg, outputs "
            f"{sorted(outputs)}: filmscale models normal impact only (friction below "
            f"{FRICTION_LIMIT}, angle 0, no tangential output); an oblique model is not built")
    steps = [Step("direction", "normal impact",
                  f"friction {friction:g} < {FRICTION_LIMIT}, normal approach, no tangential "
                  "output (rule 2)", "tangential traction neglected", 0.0)]
    V, R = _points(scene, outputs)
    m = scene.impactor.mass
    law = scene.law
    target = "layered"
    full = scene.model().maxima(V, R, m)
    if not np.any(np.isfinite(full.delta_max)):
        raise InputError(f"impactor: at V = {V[0]:g} m/s, R = {R[0]:g} m, m = {m:g} kg (and "
                         "the map's corners) the approach would exceed the sphere radius; "
                         "no contact model holds there")
    bare = full
    if scene.stack.layers:
        bare = scene.substrate_model().maxima(V, R, m)
        change = float(np.nanmax(np.abs(np.r_[bare.delta_max / full.delta_max,
                                               bare.force_max / full.force_max] - 1.0)))
        depth = float(np.nanmax(full.delta_max))
        if change <= tolerance:
            target = "substrate"
            steps.append(Step("target", f"substrate alone ({scene.stack.substrate.name})",
                              f"skipping the films changes the maxima by {change:.2%} at "
                              f"most, within the tolerance {tolerance:.0%} (rule 3)",
                              f"{change:.2%} from the films left out", 0.0))
        else:
            steps.append(Step("target", "layered profile (Gao weighting, physics.md s. 7)",
                              f"the films change the maxima by up to {change:.1%} (deepest "
                              f"approach {depth:.3g} m against "
                              f"{sum(l.thickness for l in scene.stack.layers):.3g} m of "
                              "film), above the tolerance (rule 3)",
                              "the weighting's own (Gao 1992: a few % for moderate "
                              "mismatch)", 0.0))
    else:
        target = "substrate"
    check = bare if target == "substrate" else full
    if np.any(check.yielded):
        chosen = law
        steps.append(Step("contact law", law.name,
                          f"first yield is reached at {int(np.sum(check.yielded))} of "
                          f"{V.size} checked points (rule 4)",
                          "the law's own against FE (physics.md)", 0.0))
    else:
        chosen = contact_law("hertz")
        steps.append(Step("contact law", "Hertz (closed form)",
                          f"no checked point reaches first yield (largest V {V.max():.3g} "
                          f"m/s under V_Y = {float(np.nanmin(check.yield_velocity)):.3g} "
                          "m/s) (rule 4)", "exact for an elastic contact", 0.0))
    run_model = _chosen_model(scene, target, chosen.name)
    path = "time" if "history" in outputs else "fast"
    count = 1
    if "map" in outputs:
        v_axis, r_axis = scene.map.axes()
        count = v_axis.size * r_axis.size
    if path == "time":
        _, one = _timed(lambda: run_model.history(scene.impactor.velocity,
                                                  scene.impactor.radius, m))
        steps.append(Step("impact", "time integration (histories)",
                          "time histories are asked for (rule 5)",
                          f"rtol {scene.rtol:g}", one))
    _, one = _timed(lambda: run_model.maxima(V[:1], R[:1], m))
    steps.append(Step("impact", ("impact map " if "map" in outputs else "") +
                      "fast maxima (energy quadrature)",
                      "maxima, restitution and residual depth need no time history (rule 5)",
                      "about 1e-11 relative (12-node quadrature)", one * count))
    return Plan(tuple(steps), {"target": target, "law": chosen.name, "path": path,
                               "map": "map" in outputs, "history": path == "time"})


def plan_scene(pipeline: PipelineScene, calibrated: dict[int, ElasticPlastic] | None = None,
               h_star: dict[int, float] | None = None) -> Plan:
    """The whole plan; impact steps wait for the calibrations unless all layers are known.
    The calibration steps stay in the plan once done, so that the stored plan is complete."""
    steps = []
    for sources in layer_sources(pipeline).values():
        steps += [_calibration_step(s, pipeline.base, len(sources) > 1) for s in sources]
        if len(sources) > 1:
            steps.append(_joint_step(sources[0].name, sources))
    missing = [s for s in pipeline.calibrations if not calibrated or s.layer not in calibrated]
    if missing:
        steps.append(Step("impact", "chosen after calibration",
                          "rules 2-5 need every layer's E and sigma_y", "-", math.nan))
        return Plan(tuple(steps))
    scene = pipeline.completed(calibrated or {}, h_star)
    impact = plan_impact(scene, pipeline.outputs, pipeline.tolerance, pipeline.friction,
                         pipeline.angle)
    return Plan(tuple(steps) + impact.steps, impact.decisions)


# ---------------------------------------------------------------- run units

@functools.lru_cache(maxsize=1)
def code_version() -> str:
    info = provenance()
    return f"{info['filmscale_version']}+{info['source_revision']}"


def unit_dir(store: Path, kind: str, inputs: dict) -> Path:
    """``store/<kind>-<16 hex>``, the hash over the kind, the inputs and the code version."""
    blob = json.dumps({"kind": kind, "inputs": inputs, "code": code_version()},
                      sort_keys=True, default=str)
    return Path(store) / f"{kind}-{hashlib.sha256(blob.encode()).hexdigest()[:16]}"


def _done(path: Path) -> dict | None:
    marker = path / "done.json"
    return json.loads(marker.read_text()) if marker.exists() else None


def _finish(path: Path, record: dict) -> dict:
    with atomic_path(path / "done.json") as tmp:
        Path(tmp).write_text(json.dumps(record, default=str))
    return record


def _say(message: str):
    print(f"filmscale: {message}", file=sys.stderr, flush=True)


def _progress_bar(total: int):
    from tqdm import tqdm
    bar = tqdm(total=total, unit="step", disable=None, file=sys.stderr)
    return bar, lambda step, _total: bar.update(max(0, min(step, total) - bar.n))


def _run_md(spec, path: Path, ranks: int):
    from filmscale.md.engine import EngineOptions
    from filmscale.md.record import run_provenance
    from filmscale.md.run import run_indentation
    bar, progress = _progress_bar(spec.protocol.schedule().s_end)
    try:
        run = run_indentation(spec, path, EngineOptions(np=ranks), progress=progress)
    finally:
        bar.close()
    return run.curve, {"wall_time": run.wall_time, **run_provenance(run)}


def _run_particles(spec, path: Path, ranks: int):
    from filmscale.md.engine import EngineOptions, lammps_info
    from filmscale.md.particle_run import run_particles
    from filmscale.md.particles import estimated_steps
    bar, progress = _progress_bar(estimated_steps(spec))
    try:
        run = run_particles(spec, path, EngineOptions(np=ranks, omp_threads=1),
                            progress=progress)
    finally:
        bar.close()
    return run.curve(), {"wall_time": run.wall_time, "steps": run.steps,
                         "particles": spec.grid.n_particles, "method": spec.method,
                         **lammps_info()}


#: run-unit kind and runner of each run source
_RUNNERS = {"md": ("md-indent", _run_md), "particles": ("particle-indent", _run_particles)}


def run_unit(src: CalibrationSource, base: Path, store: Path) -> tuple[Path, bool]:
    """Run (or resume, or reuse) the MD or particle-model indentation of a source."""
    kind, runner = _RUNNERS[src.kind]
    spec = src.spec(base)
    path = unit_dir(store, kind, {"spec": spec.to_dict(), "np": src.np})
    if _done(path) is not None:
        return path, True
    _say(f"{kind} {spec.name} for {src.name} in {path}")
    curve, record = runner(spec, path, src.np)
    np.savez(path / "curve.npz", h=curve.h, P=curve.P, segment=curve.segment)
    _finish(path, {"indenter": curve.indenter, **record})
    return path, False


def source_unit(src: CalibrationSource, base: Path, store: Path
                ) -> tuple[Path | None, bool, list]:
    """The source's run unit (None for curve files), whether it was reused, its curves."""
    if src.kind == "curves":
        return None, True, src.curves(base)
    path, reused = run_unit(src, base, store)
    return path, reused, [unit_curve(path)]


def unit_curve(path: Path):
    """The curve of a finished MD or particle unit."""
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    d = np.load(path / "curve.npz")
    meta = _done(path)
    return LoadDisplacementCurve(d["h"], d["P"], segment=d["segment"],
                                 indenter=meta["indenter"], meta={"source": str(path)})


def _file_digest(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _tip_counterpart(src: CalibrationSource):
    """Tips of MD and particle runs are rigid; tips of curve files are taken as diamond:
    (sphere indenter, sharp-tip E_i)."""
    from filmscale.continuum.materials import DIAMOND
    from filmscale.continuum.indentation.reverse.functions import E_I_DAO
    return (None, math.inf) if src.kind != "curves" else (DIAMOND, E_I_DAO)


def _sharp_tip(src: CalibrationSource, curves: list) -> str | None:
    """The one sharp tip of the curves, or None when all are spheres."""
    from filmscale.continuum.indentation.tips import Sphere, parse_tip
    spheres = [isinstance(parse_tip(c.indenter), Sphere) for c in curves]
    if all(spheres):
        return None
    tips = {c.indenter for c in curves}
    if any(spheres) or len(tips) != 1:
        raise InputError(f"target.layers[{src.layer}].calibrate: the curves mix indenters "
                         f"({', '.join(sorted(tips))}); calibrate from one tip shape")
    return tips.pop()


def calibrate_curves(src: CalibrationSource, curves: list, nu: float, law: str
                     ) -> Calibration:
    """Sphere tips: the contact-law fit; sharp tips: Dao's reverse analysis (with the Nix-Gao
    length of sigma_y from three or more depths)."""
    from filmscale.continuum.calibration.sharp import calibrate_sharp
    indenter, E_i = _tip_counterpart(src)
    tip = _sharp_tip(src, curves)
    if tip is None:
        return calibrate_sphere(curves, nu=nu, law=law, layer=src.name, indenter=indenter)
    cal = calibrate_sharp(curves, nu=nu, tip=tip, layer=src.name, E_i=E_i)
    depths = {round(float(np.max(c.h)), 12) for c in curves}
    return with_size_effect(cal, curves, tip, E_i=E_i) if len(depths) >= 3 else cal


def calibration_part(src: CalibrationSource, cal: Calibration, curves: list, law: str
                     ) -> CalibrationPart:
    """A source's calibration as a joint calibration of its layer takes it."""
    indenter, E_i = _tip_counterpart(src)
    tip = _sharp_tip(src, curves)
    if tip is None:
        return sphere_part(src.label, cal, curves, law, indenter)
    return sharp_part(src.label, cal, curves, tip, E_i=E_i)


def _stored_calibration(path: Path, compute) -> tuple[Calibration, bool]:
    """The calibration stored in unit ``path`` (reused), or ``compute()`` stored there."""
    record = _done(path)
    reused = record is not None
    if not reused:
        path.mkdir(parents=True, exist_ok=True)
        cal = compute()
        fitted = {}
        for i, (h, P, F) in enumerate(cal.fitted_curves):
            fitted.update({f"h_{i}": h, f"P_{i}": P, f"P_model_{i}": F})
        with atomic_path(path / "fit.npz") as tmp:
            with open(tmp, "wb") as f:
                np.savez(f, **fitted)
        record = _finish(path, cal.to_dict())
    with np.load(path / "fit.npz") as d:
        fitted = tuple((d[f"h_{i}"], d[f"P_{i}"], d[f"P_model_{i}"])
                       for i in range(len(d.files) // 3))
    return _calibration_from_dict(record, fitted), reused


def calibration_unit(src: CalibrationSource, run_path: Path | None, curves: list, nu: float,
                     law: str, base: Path, store: Path) -> tuple[Calibration, Path, bool]:
    """Calibrate (or reuse the calibration of) a source's curves."""
    origin = run_path.name if run_path is not None else \
        {f: _file_digest(Path(base) / f) for f in src.source}
    path = unit_dir(store, "calibration", {"source": origin, "nu": nu, "law": law,
                                          "layer": src.name, "tip": src.tip})
    cal, reused = _stored_calibration(path, lambda: calibrate_curves(src, curves, nu, law))
    return cal, path, reused


def joint_unit(name: str, parts, part_units: list[Path], store: Path
               ) -> tuple[Calibration, Path, bool]:
    """The joint calibration of a layer from its sources' calibration units; ``parts()``
    gives the `CalibrationPart` of each (built only when the unit runs)."""
    path = unit_dir(store, "calibration-joint", {"layer": name,
                                                 "parts": [p.name for p in part_units]})
    cal, reused = _stored_calibration(path, lambda: combine(parts(), name))
    return cal, path, reused


def _calibration_from_dict(d: dict, fitted) -> Calibration:
    d = dict(d)
    for key in ("E", "sigma_y", "n"):
        d[key] = Parameter(**d[key])
    for key in ("sources", "warnings", "curve_sources", "components"):
        d[key] = tuple(d[key])
    if d.get("h_star") is not None:
        d["h_star"] = Parameter(**d["h_star"])
    return Calibration(**d, fitted_curves=fitted)


@dataclass(frozen=True)
class SceneResult:
    path: Path
    plan: Plan
    units: dict            #: unit directory -> "ran" or "reused"


def run_scene(pipeline: PipelineScene, store: Path | str, out: Path | str) -> SceneResult:
    """Execute the plan: calibrations (MD units), then the impact evaluation; write ``out``."""
    store = Path(store)
    store.mkdir(parents=True, exist_ok=True)
    units = {}
    calibrations: dict[int, Calibration] = {}
    checks: dict[int, CrossCheck] = {}
    run_records: dict[str, dict] = {}
    law = pipeline.data.get("model", {}).get("contact_law", "komvopoulos-ye")
    for k, sources in layer_sources(pipeline).items():
        nu = float(pipeline.data["target"]["layers"][k]["nu"])
        parts, part_units = [], []
        for src in sources:
            run_path, reused, curves = source_unit(src, pipeline.base, store)
            if run_path is not None:
                units[run_path.name] = "reused" if reused else "ran"
                run_records[f"{src.kind}_{k}" + (f"_{len(part_units)}" if len(sources) > 1
                                                 else "")] = _done(run_path)
            cal, cal_path, reused = calibration_unit(src, run_path, curves, nu, law,
                                                     pipeline.base, store)
            units[cal_path.name] = "reused" if reused else "ran"
            part_units.append(cal_path)
            parts.append((src, cal, curves))
        if len(sources) > 1:
            cal, cal_path, reused = joint_unit(
                sources[0].name, lambda: [calibration_part(*p, law) for p in parts],
                part_units, store)
            units[cal_path.name] = "reused" if reused else "ran"
        calibrations[k] = cal
        checks[k] = [cal.cross_check(s.tolerance, s.label if len(sources) > 1 else "")
                     for s in sources]
        _say(cal.summary() + "".join(f"\n  {c.text()}" for c in checks[k]))
    materials = {k: c.material() for k, c in calibrations.items()}
    h_star = {k: c.h_star.value for k, c in calibrations.items() if c.h_star is not None}
    plan = plan_scene(pipeline, materials, h_star)
    scene = pipeline.completed(materials, h_star)
    _say("plan:\n" + plan.text())
    impact_path = unit_dir(store, "impact", {"scene": impact_inputs(pipeline, materials,
                                                                    h_star),
                                            "plan": plan.decisions})
    record = _done(impact_path)
    if record is None:
        impact_path.mkdir(parents=True, exist_ok=True)
        _impact_evaluation(scene, plan, impact_path)
        record = _finish(impact_path, {"decisions": plan.decisions})
        units[impact_path.name] = "ran"
    else:
        units[impact_path.name] = "reused"
    path = write_scene_result(out, pipeline, scene, plan, calibrations, checks, impact_path,
                              run_records)
    return SceneResult(path, plan, units)


def impact_inputs(pipeline: PipelineScene, materials, h_star=None) -> dict:
    """The complete impact inputs: the scene data with calibrated values filled in."""
    return {"data": _filled(pipeline.data, materials, h_star),
            "outputs": sorted(pipeline.outputs),
            "tolerance": pipeline.tolerance}


def _chosen_model(scene: Scene, target: str, law: str) -> ImpactModel:
    """The impact model the plan chose: ``target`` "substrate" or "layered", ``law`` the
    scene's law or "hertz"."""
    base = scene.substrate_model() if target == "substrate" else scene.model()
    chosen = contact_law("hertz") if law == "hertz" else scene.law
    return ImpactModel(base.target, chosen, scene.impactor.material, scene.unloading)


def _impact_evaluation(scene: Scene, plan: Plan, path: Path):
    from filmscale.continuum.contact.impact_map import impact_map
    model = _chosen_model(scene, plan.decisions["target"], plan.decisions["law"])
    imp = scene.impactor
    one = model.maxima(imp.velocity, imp.radius, imp.mass).result()
    arrays = {f"point/{k}": v for k, v in one.to_dict().items()
              if isinstance(v, (int, float)) and not isinstance(v, bool)}
    if plan.decisions.get("history"):
        hist = model.history(imp.velocity, imp.radius, imp.mass, rtol=scene.rtol)
        arrays.update({f"history/{k}": getattr(hist, k)
                       for k in ("time", "delta", "velocity", "force", "contact_radius")})
    if plan.decisions.get("map"):
        V, R = scene.map.axes()
        mp = impact_map(model, V, R, imp.mass)
        arrays.update({f"map/{k}": np.asarray(v) for k, v in mp.to_dict().items()
                       if np.asarray(v).dtype.kind in "fiub"})
    with atomic_path(path / "impact.npz") as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **{k.replace("/", "__"): np.asarray(v) for k, v in arrays.items()})


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
    extra = {k: json.dumps(r) for k, r in run_records.items()}
    with atomic_h5(out) as f:
        f.attrs["format"] = RESULT_FORMAT
        for k, v in provenance(scene=pipeline.source, **extra).items():
            f.attrs[k] = v
        f.create_dataset("scene", data=pipeline.text)
        f.attrs["plan"] = json.dumps(plan.to_dict())
        g = f.create_group("calibration")
        for k, cal in calibrations.items():
            c = g.create_group(str(k))
            c.attrs["layer"] = cal.layer
            c.attrs["calibration"] = json.dumps(cal.to_dict())
            for name in ("E", "sigma_y", "n", "h_star"):
                p = getattr(cal, name)
                if p is None:
                    continue
                c.attrs[name] = p.value
                c.attrs[f"{name}_std"] = p.std
                c.attrs[f"{name}_identified"] = p.identified
            c.attrs["cross_check"] = json.dumps([check.to_dict() for check in checks[k]])
            for i, (h, P, F) in enumerate(cal.fitted_curves):
                curve = c.create_group(f"curve_{i}")
                if cal.curve_sources:
                    curve.attrs["source"] = cal.curve_sources[i]
                for name, data, unit in (("h", h, "m"), ("P", P, "N"), ("P_model", F, "N")):
                    curve.create_dataset(name, data=data).attrs["units"] = unit
        prof = profile_table(scene, scene.impactor.radius)
        p = f.create_group("profile")
        for name, unit in (("delta", "m"), ("E_p", "Pa"), ("sigma_y", "Pa"), ("nu", "1")):
            p.create_dataset(name, data=prof[name]).attrs["units"] = unit
        i = f.create_group("impact")
        with np.load(impact_path / "impact.npz") as d:
            for key in d.files:
                i.create_dataset(key.replace("__", "/"), data=d[key])
    return out
