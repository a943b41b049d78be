"""The planner: the cheapest models that answer a scene within its tolerance, each choice with
its reason, estimated error and cost.

Rules (docs/physics.md; benchmarks/impact_speed_vs_error.py):
1. MD runs only for layers whose E or sigma_y is missing.
2. The oblique model (docs/physics.md section 5) when the impact has a tangential problem:
   an angle above 0 with friction above 0, or tangential outputs asked for; otherwise the
   normal impact (a normal approach has no tangential force, a frictionless one leaves the
   tangential velocity unchanged). Tangential outputs with a normal approach are refused.
3. The films are modelled (Gao-weighted profile) only where skipping them changes the
   maxima by more than the tolerance at the scene's extreme points; otherwise the substrate
   alone, with that change reported as the error of skipping them.
4. The closed-form Hertz impact where no point yields; otherwise the elastic-plastic law.
5. The fast maxima path (energy quadrature) unless time histories are asked for.
6. An MD source's settings are read against the measured speed-against-error table
   (`workflows.md_settings`): its bias and seed scatter are stated, and settings whose effect
   on the film's E exceeds the scene's tolerance, or cheaper ones within it, are named.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from filmscale.continuum.contact.kinds import ModelKind, kind_for
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.materials import ElasticPlastic, LayerStack
from filmscale.core.errors import InputError
from filmscale.workflows.md_settings import md_settings_advice
from filmscale.workflows.scene import Scene
from filmscale.workflows.pipeline_scene import CalibrationSource, PipelineScene, layer_sources

FRICTION_LIMIT = 0.3


#: MD throughput measured for the quick preset (14 336 atoms x 5 500 steps in 184 s on
#: 2 ranks, README), atom-steps per second per rank: the cost estimate of an MD unit
MD_ATOM_STEPS_PER_RANK_S = 14336 * 5500 / 184.0 / 2


def md_cost_s(spec, ranks: int) -> float:
    """Estimated wall time (s) of one MD run of ``spec`` on ``ranks`` ranks."""
    return spec.slab_built.n_atoms * spec.protocol.schedule().s_end / (
        MD_ATOM_STEPS_PER_RANK_S * ranks)


#: particle-model throughput (TLSPH, docs/lammps.md), particle-steps per second per core; PERI
#: (peri/lps) is about 4 times slower per particle
PARTICLE_STEPS_PER_CORE_S = 2.6e5


PERI_SLOWDOWN = 4.0


@dataclass(frozen=True)
class Step:
    """One model of the plan: what runs, why it was chosen, its error and cost."""

    name: str
    model: str
    reason: str
    error: str
    cost_s: float
    advice: tuple[str, ...] = ()


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
            lines += [f"   advice: {a}" for a in s.advice]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"steps": [asdict(s) for s in self.steps], "decisions": self.decisions}


def _calibration_step(src: CalibrationSource, base: Path, joint: bool,
                      tolerance: float) -> Step:
    """The plan step of one calibration source, its cost from measured throughputs and, for
    MD, its settings against the measured table (rule 6); ``joint``: one of several sources
    of its layer; ``tolerance``: the scene's, applied to the film's E."""
    fit = ("then a calibration (sphere tips: least squares to the contact law; sharp tips: "
           "Dao reverse analysis) and a cross-scale check to "
           + ("twice the curves' noise" if src.tolerance is None else f"{src.tolerance:.0%}")
           + " rms" + (f", {src.exclude} range left out" if src.exclude else ""))
    spec = src.spec(base)
    error, advice = "the fit's own standard deviations, reported with the calibration", ()
    if src.kind == "md":
        settings, advice = md_settings_advice(spec, tolerance)
        error = f"{error}; {settings} (rule 6)"
        atoms, steps = spec.slab_built.n_atoms, spec.protocol.schedule().s_end
        cost = md_cost_s(spec, src.np) * src.seeds
        ensemble = f", {src.seeds} seeds (one unit each)" if src.seeds > 1 else ""
        model = (f"MD indentation ({src.source[0]}: {atoms} atoms, {steps} steps, {src.np} "
                 f"rank(s){ensemble}) {fit}")
    elif src.kind == "particles":
        from filmscale.md.particle_inputs import estimated_steps
        n, steps = spec.grid.n_particles, estimated_steps(spec)
        rate = PARTICLE_STEPS_PER_CORE_S / (PERI_SLOWDOWN if spec.method == "peri" else 1)
        cost = n * steps / (rate * src.np)
        model = (f"particle-model indentation ({src.source[0]}: {spec.method}, {n} particles, "
                 f"about {steps} steps, {src.np} rank(s)) {fit}")
    else:
        cost = 0.0
        model = f"curves from {', '.join(src.source)} {fit}"
    return Step(f"calibrate {src.name}" + (f" from {src.label}" if joint else ""), model,
                "the layer's E and sigma_y are not given (rule 1)", error, cost, advice)


def _joint_step(name: str, sources: list[CalibrationSource]) -> Step:
    return Step(f"calibrate {name} jointly",
                f"one Nix-Gao law of sigma_y over {', '.join(s.label for s in sources)} "
                "(weighted least squares; E and n inverse-variance means); a cross-scale "
                "check per source",
                "the layer has several sources: nanometre and micrometre strengths both "
                "reach the depth profile", "standard deviations of the joint fit", 0.0)


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


def _check_direction(outputs, friction: float, angle: float) -> None:
    """Rule 2's refusal: tangential outputs of an impact that has no tangential motion."""
    if "tangential" in outputs and angle == 0:
        raise InputError(
            f"outputs {sorted(outputs)} ask for tangential results but impactor.angle = 0: a "
            "normal approach has no tangential motion; give impactor.angle in (0, 90) degrees")


def _oblique(outputs, friction: float, angle: float) -> bool:
    """Rule 2: an impact has a tangential problem when it comes at an angle with friction,
    or when tangential outputs are asked for."""
    return angle > 0 and (friction > 0 or "tangential" in outputs)


def _direction_step(outputs, friction: float, angle: float) -> Step:
    """Rule 2's choice between the normal and the oblique impact."""
    if _oblique(outputs, friction, angle):
        coupled = (f"; above mu = {FRICTION_LIMIT} the normal motion may depend on friction, "
                   "which the model leaves out" if friction >= FRICTION_LIMIT else "")
        return Step("direction", "oblique impact (Mindlin-Deresiewicz by MDR, Coulomb, rotation)",
                    f"angle {angle:g} deg with friction {friction:g}"
                    + (" and tangential outputs asked for" if "tangential" in outputs else "")
                    + ": the tangential velocity and spin change (rule 2)",
                    "normal motion independent of the tangential force" + coupled, 0.0)
    why = ("a frictionless contact leaves the tangential velocity unchanged" if angle > 0
           else "a normal approach has no tangential force, whatever the friction")
    return Step("direction", "normal impact", f"{why} (rule 2)", "none from the direction", 0.0)


def check_request(pipeline: PipelineScene) -> None:
    """What the impact rules refuse whatever the calibrations find: an oblique or tangential
    request (rule 2), a shape without an oblique model, and a map without valid axes. `plan`
    and `run` check it before any unit runs, so that a run never stops there after its MD
    runs."""
    _check_direction(pipeline.outputs, pipeline.friction, pipeline.angle)
    if _oblique(pipeline.outputs, pipeline.friction, pipeline.angle):
        kind_for(pipeline.data["impactor"].get("shape", "sphere"), oblique=True)
    if "map" in pipeline.outputs:
        pipeline.map_spec().axes()


#: the exact layered solution is asked for contact radii up to this many film thicknesses
#: (0.04 s a call there); beyond, the film's share of an elastic contact is below 1 %
GAO_CHECK_MAX_RADIUS = 100.0


def gao_error(scene: Scene, R: float, depth: float) -> str:
    """The Gao weighting's error (docs/layered-contact.md) for the scene's stack: with one
    film, measured here as the Gao-weighted Hertz load of a rigid sphere of radius ``R`` at
    the approach ``depth`` (m) against the exact layered solution at that approach; with
    several films, the measured range for their largest modulus ratio."""
    from filmscale.continuum.contact.coated import coated_sphere_load
    from filmscale.continuum.contact.hertz import hertz_force_unchecked
    from filmscale.continuum.contact.profiles import StackProfile
    layers = scene.stack.layers
    materials = [layer.material for layer in layers] + [scene.stack.substrate]
    ratios = [a.plane_strain_modulus / b.plane_strain_modulus
              for a, b in zip(materials, materials[1:])]
    worst = max(ratios, key=lambda r: abs(math.log(r)))
    if len(layers) > 1:
        return (f"the weighting's own: largest modulus ratio between neighbours {worst:.3g} "
                "(one film against the exact solution: 1-3 % at 1.5, 12-74 % at 5.7, "
                "docs/layered-contact.md)")
    t = layers[0].thickness
    a = math.sqrt(R * depth)
    if a > GAO_CHECK_MAX_RADIUS * t:
        return (f"the weighting's own: the contact radius is {a / t:.3g} film thicknesses, "
                "where the film's share of the elastic load is below 1 %")
    stack = LayerStack(layers, scene.stack.substrate)
    E_p = StackProfile(stack).properties(np.array([depth]), R)[0]
    gao = float(hertz_force_unchecked(depth, R, float(np.asarray(E_p).ravel()[0])))
    exact = float(coated_sphere_load(depth, R, t, layers[0].material,
                                     scene.stack.substrate)[0])
    return (f"the weighting's own: {gao / exact - 1:+.1%} in elastic load at the deepest "
            f"approach against the exact layered solution (film/substrate modulus ratio "
            f"{worst:.3g}, contact radius {a / t:.3g} film thicknesses)")


def _target_step(scene: Scene, kind: ModelKind, V, R, tolerance: float):
    """Rule 3: the films, or the substrate alone when skipping them changes the maxima by
    at most ``tolerance``; (the step or None without films, the target, the maxima that
    decide rule 4)."""
    m = scene.impactor.mass
    full = kind.maxima(scene.model(kind=kind), V, R, m)
    if not np.any(np.isfinite(full["delta_max"])):
        raise InputError(f"impactor: at V = {V[0]:g} m/s, R = {R[0]:g} m, m = {m:g} kg (and "
                         "the map's corners) no point is inside the model's range "
                         f"({kind.range_limit}); no contact model holds there")
    if not scene.stack.layers:
        return None, "substrate", full
    bare = kind.maxima(scene.substrate_model(kind=kind), V, R, m)
    change = float(np.nanmax(np.abs(np.r_[bare["delta_max"] / full["delta_max"],
                                           bare["force_max"] / full["force_max"]] - 1.0)))
    depth = float(np.nanmax(full["delta_max"]))
    if change <= tolerance:
        return (Step("target", f"substrate alone ({scene.stack.substrate.name})",
                     f"skipping the films changes the maxima by {change:.2%} at most, within "
                     f"the tolerance {tolerance:.0%} (rule 3)",
                     f"{change:.2%} from the films left out", 0.0), "substrate", bare)
    deepest = float(R[int(np.nanargmax(full["delta_max"]))])
    return (Step("target", "layered profile (Gao weighting, docs/physics.md s. 7)",
                 f"the films change the maxima by up to {change:.1%} (deepest approach "
                 f"{depth:.3g} m against {sum(l.thickness for l in scene.stack.layers):.3g} m "
                 "of film), above the tolerance (rule 3)", gao_error(scene, deepest, depth),
                 0.0), "layered", full)


def _law_step(scene: Scene, kind: ModelKind, check: dict, V) -> tuple[Step, str]:
    """Rule 4: the closed-form Hertz impact where no checked point yields, else the scene's
    law; a kind without a choice of law keeps its own."""
    if "contact_law" not in {k.name for k in kind.keys}:
        return Step("contact law", f"the {kind.name} model's own", kind.summary,
                    "the model's own (docs/physics.md)", 0.0), scene.law.name
    law = scene.law
    if np.any(check["yielded"]):
        return Step("contact law", law.name, f"first yield is reached at "
                    f"{int(np.sum(check['yielded']))} of {V.size} checked points (rule 4)",
                    "the law's own against FE (docs/physics.md)", 0.0), law.name
    return Step("contact law", "Hertz (closed form)", f"no checked point reaches first yield "
                f"(largest V {V.max():.3g} m/s under V_Y = "
                f"{float(np.nanmin(check['yield_velocity'])):.3g} m/s) (rule 4)",
                "exact for an elastic contact", 0.0), "hertz"


def _path_steps(scene: Scene, kind: ModelKind, run_model, outputs, V, R) -> list[Step]:
    """Rule 5, with the measured cost of one history and of one maxima point."""
    imp, steps = scene.impactor, []
    options = scene.kind_options(kind)
    if "history" in outputs:
        _, one = _timed(lambda: kind.history(run_model, imp.velocity, imp.radius, imp.mass,
                                             options))
        steps.append(Step("impact", "time integration (histories)",
                          "time histories are asked for (rule 5)", f"rtol {scene.rtol:g}",
                          one))
    count = 1
    if "map" in outputs:
        v_axis, r_axis = scene.map.axes()
        count = v_axis.size * r_axis.size
    _, one = _timed(lambda: kind.maxima(run_model, V[:1], R[:1], imp.mass))
    steps.append(Step("impact", ("impact map " if "map" in outputs else "") +
                      "fast maxima (energy quadrature)",
                      "maxima, restitution and residual depth need no time history (rule 5)",
                      "about 1e-11 relative (12-node quadrature)", one * count))
    return steps


def _oblique_step(scene: Scene, kind: ModelKind, run_model, angle, friction) -> Step:
    """The tangential step of an oblique impact, timed at the scene's point."""
    imp = scene.impactor
    options = scene.kind_options(kind) | {"angle": angle, "friction": friction}
    res, one = _timed(lambda: kind.solve(run_model, imp.velocity, imp.radius, imp.mass,
                                         options))
    return Step("tangential", f"oblique impact at the scene's point ({res.path})",
                "closed form where the contact slips throughout or has no friction, else time "
                "integration (docs/physics.md s. 5)", "closed form exact; time integration "
                "rtol 1e-9", one)


def plan_impact(scene: Scene, outputs, tolerance: float, friction: float = 0.0,
                angle: float = 0.0) -> Plan:
    """Rules 2-5 on a complete scene, for the model kind of its impactor's shape."""
    _check_direction(outputs, friction, angle)
    steps = [_direction_step(outputs, friction, angle)]
    oblique = _oblique(outputs, friction, angle)
    # the normal kind of the shape decides rules 3-5; the oblique one adds the tangential step
    kind, normal = kind_for(scene.impactor.shape, oblique), kind_for(scene.impactor.shape)
    V, R = _points(scene, outputs)
    target_step, target, check = _target_step(scene, normal, V, R, tolerance)
    steps += [target_step] if target_step else []
    law_step, law = _law_step(scene, normal, check, V)
    steps.append(law_step)
    run_model = chosen_model(scene, target, law, normal)
    steps += _path_steps(scene, normal, run_model, outputs, V, R)
    if oblique:
        steps.append(_oblique_step(scene, kind, run_model, angle, friction))
    decisions = {"kind": kind.name, "target": target, "law": law, "path":
                 "time" if "history" in outputs else "fast", "map": "map" in outputs,
                 "history": "history" in outputs}
    if oblique:
        decisions.update(direction="oblique", friction=friction, angle=angle)
    return Plan(tuple(steps), decisions)


def plan_scene(pipeline: PipelineScene, calibrated: dict[int, ElasticPlastic] | None = None,
               h_star: dict[int, float] | None = None) -> Plan:
    """The whole plan; impact steps wait for the calibrations unless all layers are known.
    The calibration steps stay in the plan once done, so that the stored plan is complete."""
    steps = []
    for sources in layer_sources(pipeline).values():
        steps += [_calibration_step(s, pipeline.base, len(sources) > 1, pipeline.tolerance)
                  for s in sources]
        if len(sources) > 1:
            steps.append(_joint_step(sources[0].name, sources))
    missing = [s for s in pipeline.calibrations if not calibrated or s.layer not in calibrated]
    if missing:
        check_request(pipeline)
        steps.append(Step("impact", "chosen after calibration",
                          "rules 2-5 need every layer's E and sigma_y", "-", math.nan))
        return Plan(tuple(steps))
    scene = pipeline.completed(calibrated or {}, h_star)
    impact = plan_impact(scene, pipeline.outputs, pipeline.tolerance, pipeline.friction,
                         pipeline.angle)
    return Plan(tuple(steps) + impact.steps, impact.decisions)


def chosen_model(scene: Scene, target: str, law: str, kind: ModelKind | None = None):
    """The impact model the plan chose: of ``kind`` (default: the scene's), ``target``
    "substrate" or "layered", ``law`` the scene's law or "hertz"."""
    kind = kind or scene.kind
    chosen = contact_law("hertz") if law == "hertz" else scene.law
    return replace(scene, law=chosen).model(bare_substrate=target == "substrate", kind=kind)
