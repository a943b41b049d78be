"""The planner: the cheapest models that answer a scene within its tolerance, each choice with
its reason, estimated error and cost.

Rules (docs/physics.md; benchmarks/impact_speed_vs_error.py):
1. MD runs only for layers whose E or sigma_y is missing.
2. The oblique model (docs/physics.md section 5) when the impact has a tangential problem:
   an angle above 0 with friction above 0, or tangential outputs asked for; otherwise the
   normal impact (a normal approach has no tangential force, a frictionless one leaves the
   tangential velocity unchanged). Tangential outputs with a normal approach are refused.
3. The films (Gao-weighted profile, or the measured `target.profile`) are modelled only
   where skipping them changes the maxima by more than the tolerance at the scene's extreme
   points; otherwise the substrate alone, with that change reported as the error of skipping
   them. A tolerance of 0 keeps them whenever they change anything. ``model.target``
   ("layered" or "substrate") overrides the rule; the step then says so, with the measured
   change. Calibrated layers that the chosen target leaves out give the results no standard
   deviation: it is not computed (NaN), and an "uncertainty" step says why.
4. The closed-form Hertz impact where no point yields; otherwise the elastic-plastic law.
5. The fast maxima path (energy quadrature) unless time histories are asked for.
6. An MD source's settings are read against the measured speed-against-error table
   (`workflows.md_settings`): its bias and seed scatter are stated, and settings whose effect
   on the film's E exceeds the scene's tolerance, or cheaper ones within it, are named
   (with a tolerance of 0: every setting the table measured to move E, an ensemble always,
   and no cheaper setting).
Rules 1, 2, 4 and 5 read no tolerance.

A sliding scene ([slider], `plan_slide`) has rules 1 and 6 (its calibrations) and one sliding
model, which the slider's shape and the stack decide: no rule of 2-5 applies.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from filmscale.continuum.contact.kinds import ModelKind, kind_for
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.slider import sliding_kind
from filmscale.continuum.materials import ElasticPlastic, LayerStack
from filmscale.core.errors import InputError
from filmscale.workflows.amorphous_units import quench_cost_s
from filmscale.workflows.md_settings import md_settings_advice
from filmscale.workflows.scene import Scene
from filmscale.workflows.pipeline_scene import CalibrationSource, PipelineScene, layer_sources

FRICTION_LIMIT = 0.3


#: MD throughput measured for the quick preset (14 336 atoms x 5 500 steps in 184 s on
#: 2 ranks, README), atom-steps per second per rank: the cost estimate of an MD unit
MD_ATOM_STEPS_PER_RANK_S = 14336 * 5500 / 184.0 / 2


def quenched_recipes(spec) -> list:
    """The recipes of the films of an MD ``spec`` whose blocks a run quenches first."""
    return [f.recipe for f in spec.slab.films
            if getattr(f, "recipe", None) is not None and f.block.stand_in]


def md_cost_s(spec, ranks: int) -> float:
    """Estimated wall time (s) of one MD run of ``spec`` on ``ranks`` ranks, the quench of
    the blocks its amorphous films name by recipe included."""
    return spec.slab_built.n_atoms * spec.protocol.schedule().s_end / (
        MD_ATOM_STEPS_PER_RANK_S * ranks) + sum(quench_cost_s(r, ranks)
                                                 for r in quenched_recipes(spec))


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

    @classmethod
    def from_dict(cls, data: dict) -> Plan:
        """The plan `to_dict` wrote (a result file's ``plan`` attribute)."""
        steps = tuple(Step(**{**s, "advice": tuple(s.get("advice", ()))})
                      for s in data["steps"])
        return cls(steps, dict(data.get("decisions", {})))


def percent(x: float) -> str:
    """A tolerance as a percentage: 5%, 0.1%, 0%."""
    return f"{100 * x:g}%"


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
        ensemble = (f", {src.seeds} seeds (one unit each" + (", each its own quench" if
                    quenched_recipes(spec) else "") + ")") if src.seeds > 1 else ""
        quench = "".join(f"a melt-quench of its film (recipe {r.name}, {r.n_atoms} atoms, "
                         f"{r.density / 1000:g} g/cm3, {r.schedule().total} steps), then "
                         for r in quenched_recipes(spec))
        model = (f"{quench}MD indentation ({src.source[0]}: {atoms} atoms, {steps} steps, "
                 f"{src.np} rank(s){ensemble}) {fit}")
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
    four corners and its fastest column (every radius at the largest speed): on a layered
    target the first yield need not come first at a corner (an a-C overcoat's map yielded
    at 5 m/s and 1 um, not at 5 m/s and 10 um, and 20 nm was out of range)."""
    V, R = [scene.impactor.velocity], [scene.impactor.radius]
    if "map" in outputs:
        v_axis, r_axis = scene.map.axes()
        for v in (v_axis[0], v_axis[-1]):
            for r in (r_axis[0], r_axis[-1]):
                V.append(v)
                R.append(r)
        V += [v_axis[-1]] * (len(r_axis) - 2)
        R += list(r_axis[1:-1])
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
    request (rule 2), model.target = "layered" without films (rule 3), a shape without an
    oblique model, and a map without valid axes. `plan` and `run` check it before any unit
    runs, so that a run never stops there after its MD runs. A sliding scene has none of
    these (`parse_pipeline` checked it whole)."""
    if pipeline.sliding:
        return
    _check_direction(pipeline.outputs, pipeline.friction, pipeline.angle)
    target = pipeline.data.get("target")
    if pipeline.model_target == "layered" and isinstance(target, dict) and \
            not target.get("layers") and "profile" not in target:
        raise InputError('model.target = "layered" keeps the films, but the target has none '
                         "(no target.layers, no target.profile)")
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


def films_change(full: dict, bare: dict) -> float:
    """The largest relative change of the maxima (approach and force) over the checked
    points when the films are left out: ``bare`` (the substrate alone) against ``full``; NaN
    where no point has both in the model's range."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.r_[np.asarray(bare["delta_max"]) / np.asarray(full["delta_max"]),
                       np.asarray(bare["force_max"]) / np.asarray(full["force_max"])] - 1.0
    finite = np.abs(ratios[np.isfinite(ratios)])
    return float(finite.max()) if finite.size else math.nan


def _check_range(maxima: dict, kind: ModelKind, V, R, m: float) -> None:
    if not np.any(np.isfinite(maxima["delta_max"])):
        raise InputError(f"impactor: at V = {V[0]:g} m/s, R = {R[0]:g} m, m = {m:g} kg (and "
                         "the map's corners) no point is inside the model's range "
                         f"({kind.range_limit}); no contact model holds there")


def _films(scene: Scene) -> str:
    return "the measured profile" if scene.profile is not None else "the films"


def _change_text(change: float, tolerance: float, what: str) -> str:
    """How far ``what`` (the films) moves the maxima, against the tolerance."""
    if not math.isfinite(change):
        return (f"the change that {what} make is not measured: the substrate alone or the "
                "layered target is outside the model's range at every checked point")
    side = "within" if change <= tolerance else "above"
    verb = "change" if what == "the films" else "changes"
    return f"{what} {verb} the maxima by {change:.2%} at most, {side} the tolerance " \
        f"{percent(tolerance)}"


def _substrate_step(scene: Scene, change: float, tolerance: float) -> Step:
    """Rule 3's step when the substrate alone is modelled (by the rule or by model.target)."""
    what = _films(scene)
    if scene.model_target == "substrate":
        why = (f'forced by model.target = "substrate": {_change_text(change, tolerance, what)}'
               + (" (rule 3 would keep them)" if change > tolerance else ""))
    else:
        why = _change_text(change, tolerance, what) + (
            " (they change nothing)" if change == 0 else "") + " (rule 3)"
    error = (f"{change:.2%} from {what} left out" if math.isfinite(change) else
             f"{what} left out: their effect is not measured (outside the model's range)")
    return Step("target", f"substrate alone ({scene.stack.substrate.name})", why, error, 0.0)


def _layered_step(scene: Scene, full: dict, R, change: float, tolerance: float) -> Step:
    """Rule 3's step when the films (or the measured profile) are modelled."""
    depth = float(np.nanmax(full["delta_max"]))
    what = _films(scene)
    if scene.profile is not None:
        model = "measured depth profile (target.profile, docs/physics.md s. 7)"
        error = "the profile's own: its piecewise-linear fit of the measured E_r and H"
        extent = f"deepest approach {depth:.3g} m"
    else:
        model = "layered profile (Gao weighting, docs/physics.md s. 7)"
        error = gao_error(scene, float(R[int(np.nanargmax(full["delta_max"]))]), depth)
        extent = (f"deepest approach {depth:.3g} m against "
                  f"{sum(l.thickness for l in scene.stack.layers):.3g} m of film")
    if scene.model_target == "layered":
        why = (f'forced by model.target = "layered": {_change_text(change, tolerance, what)}'
               + (" (rule 3 would leave them out)" if change <= tolerance else "")
               + f"; {extent}")
    else:
        why = f"{_change_text(change, tolerance, what)} ({extent}) (rule 3)"
    return Step("target", model, why, error, 0.0)


def _target_step(scene: Scene, kind: ModelKind, V, R, tolerance: float):
    """Rule 3: the films, or the substrate alone when skipping them changes the maxima by
    at most ``tolerance`` (0: whenever they change anything), unless ``model.target`` forces
    either; (the step or None without films, the target, the maxima that decide rule 4,
    the films' measured change or None)."""
    m, forced = scene.impactor.mass, scene.model_target
    full = kind.maxima(scene.model(kind=kind), V, R, m)
    if not scene.layered:
        if forced == "layered":
            raise InputError('model.target = "layered" keeps the films, but the target has '
                             "none (no target.layers, no target.profile)")
        _check_range(full, kind, V, R, m)
        return None, "substrate", full, None
    bare = kind.maxima(scene.substrate_model(kind=kind), V, R, m)
    _check_range(bare if forced == "substrate" else full, kind, V, R, m)
    change = films_change(full, bare)
    if forced == "substrate" or (forced == "auto" and change <= tolerance):
        return _substrate_step(scene, change, tolerance), "substrate", bare, change
    return _layered_step(scene, full, R, change, tolerance), "layered", full, change


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


#: values per axis of the sub-grid on which a map's cost is timed (a vectorised map's cost
#: per point falls with its size, so this errs on the dear side)
MAP_SAMPLE = 4


def _path_steps(scene: Scene, kind: ModelKind, run_model, outputs, V, R) -> list[Step]:
    """Rule 5, with the measured cost of one history, and of one point or of the map."""
    imp, steps = scene.impactor, []
    options = scene.kind_options(kind)
    if "history" in outputs:
        _, one = _timed(lambda: kind.history(run_model, imp.velocity, imp.radius, imp.mass,
                                             options))
        steps.append(Step("impact", "time integration (histories)",
                          "time histories are asked for (rule 5)", f"rtol {scene.rtol:g}",
                          one))
    if "map" in outputs:        # the kind's own map, timed on a corner sub-grid and scaled
        v_axis, r_axis = scene.map.axes()
        v_sub, r_sub = v_axis[:MAP_SAMPLE], r_axis[:MAP_SAMPLE]
        _, sample = _timed(lambda: kind.impact_map(run_model, v_sub, r_sub, imp.mass, options))
        cost = sample * v_axis.size * r_axis.size / (v_sub.size * r_sub.size)
    else:
        _, cost = _timed(lambda: kind.maxima(run_model, V[:1], R[:1], imp.mass))
    steps.append(Step("impact", ("impact map " if "map" in outputs else "") +
                      "fast maxima (energy quadrature)",
                      "maxima, restitution and residual depth need no time history (rule 5)",
                      "about 1e-11 relative (12-node quadrature)", cost))
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
    """Rules 2-5 on a complete scene, for the model kind of its impactor's shape. The
    decisions record ``model_target`` (what the scene asked: "auto" is rule 3) beside the
    ``target`` chosen, and ``films_change``: how far the films move the maxima (None without
    films, or where it cannot be measured)."""
    _check_direction(outputs, friction, angle)
    steps = [_direction_step(outputs, friction, angle)]
    oblique = _oblique(outputs, friction, angle)
    # the normal kind of the shape decides rules 3-5; the oblique one adds the tangential step
    kind, normal = kind_for(scene.impactor.shape, oblique), kind_for(scene.impactor.shape)
    V, R = _points(scene, outputs)
    target_step, target, check, change = _target_step(scene, normal, V, R, tolerance)
    steps += [target_step] if target_step else []
    law_step, law = _law_step(scene, normal, check, V)
    steps.append(law_step)
    run_model = chosen_model(scene, target, law, normal)
    steps += _path_steps(scene, normal, run_model, outputs, V, R)
    if oblique:
        steps.append(_oblique_step(scene, kind, run_model, angle, friction))
    decisions = {"kind": kind.name, "target": target, "model_target": scene.model_target,
                 "films_change": change if change is not None and math.isfinite(change)
                 else None,
                 "law": law, "path": "time" if "history" in outputs else "fast",
                 "map": "map" in outputs, "history": "history" in outputs}
    if oblique:
        decisions.update(direction="oblique", friction=friction, angle=angle)
    return Plan(tuple(steps), decisions)


def _pending_steps(pipeline: PipelineScene) -> tuple[list[Step], dict]:
    """The impact steps of a plan whose calibrations have not run: rules 2-5 wait for them,
    but a target that ``model.target`` forces is known already."""
    forced, steps, decisions = pipeline.model_target, [], {}
    if forced != "auto":
        model = ("substrate alone" if forced == "substrate" else
                 "the films kept (layered target)")
        steps.append(Step("target", model, f'forced by model.target = "{forced}"',
                          "the films' effect is measured after calibration", 0.0))
        decisions = {"target": forced, "model_target": forced}
    steps.append(Step("impact", "chosen after calibration",
                      "rules 2-5 need every layer's E and sigma_y", "-", math.nan))
    return steps, decisions


def _uncertainty_step(pipeline: PipelineScene, scene: Scene, target: str) -> Step | None:
    """Where the modelled target holds no calibrated layer (the substrate alone, or a measured
    profile in the layers' place), the calibrations' standard deviations cannot reach the
    impact results: they are not computed (NaN, not 0)."""
    if not pipeline.calibrations or (target == "layered" and scene.profile is None):
        return None
    names = ", ".join(dict.fromkeys(s.name for s in pipeline.calibrations))
    where = ("the plan models the substrate alone" if target == "substrate" else
             "the measured target.profile stands for the layers")
    return Step("uncertainty", "not computed: the results' standard deviations are NaN",
                f"the calibrated layer(s) {names} are not in the modelled target ({where}), "
                "so their standard deviations cannot reach the impact results",
                "the error of the target step stands instead", 0.0)


def _slide_target(layers: int) -> tuple[str, str, str]:
    """(target, its words, how the contact is sized) of a sliding stack of ``layers`` films."""
    if not layers:
        return "homogeneous", "homogeneous target", "Hertz"
    how = ("the coated half-space's apparent modulus" if layers == 1 else
           "the Gao-weighted modulus of the stack")
    return ("layered", f"layered target ({layers} layer(s) on the substrate)",
            f"Hertz pressure at the self-consistent contact size of {how}")


def plan_slide(pipeline: PipelineScene, stack: LayerStack | None = None,
               cost_s: float | None = None) -> tuple[list[Step], dict]:
    """The sliding steps of a sliding scene: its model (the slider's kind: 2-D plane strain
    for a cylinder, 3-D for a sphere; homogeneous or layered; the x-z field grid per layer)
    and, with calibrated layers, how their spread reaches the results. ``stack``: the
    completed stack (None while calibrations wait; then the cost is "after calibration");
    ``cost_s``: the evaluation's measured wall time, else one `slide` is timed here."""
    from filmscale.continuum.contact.slider import FIELD_NX, FIELD_NZ, ZOOM_LEVELS, slide
    from filmscale.workflows.slide_scene import read_slider
    slider, load = read_slider(pipeline.data)
    layers = len(pipeline.data["target"].get("layers", []))
    kind = sliding_kind(slider.shape)
    target, words, sizing = _slide_target(layers)
    dimension = ("2-D plane strain" if kind.dimension == "2-D" else "3-D") + \
        f" ({slider.shape})"
    if cost_s is None and stack is not None:
        cost_s = _timed(lambda: slide(stack, slider, load, pipeline.friction))[1]
    cost = math.nan if cost_s is None else cost_s
    grid = (f"{FIELD_NX} x {FIELD_NZ} points (x by depth) per film, {FIELD_NX} x "
            f"{3 * FIELD_NZ} in the substrate ({layers} film(s)), each maximum refined by "
            f"{ZOOM_LEVELS} zoomed grids")
    steps = [Step("sliding", f"{dimension}, {words}: {sizing}, "
                  f"q = mu p (P = {load:.3g} N, mu = {pipeline.friction:g}); field {grid}",
                  f"outputs.want = {sorted(pipeline.outputs)}: each layer's largest von "
                  "Mises stress and where, its ratio to sigma_y, tension and interface shear; "
                  "the shakedown where modelled (docs/sliding.md)",
                  "exact Hertz tractions on a homogeneous target" if target == "homogeneous"
                  else "the pressure keeps Hertz's shape at the layered contact size "
                  "(docs/sliding.md)", cost)]
    if pipeline.calibrations:
        shifts = len({s.layer for s in pipeline.calibrations})
        steps.append(Step(
            "uncertainty", "the slide again at each calibrated layer's E + std",
            "the calibrations' standard deviations reach the yield ratios, stresses, p0 and "
            "contact size (linearised with each layer's E-sigma_y correlation; a sigma_y + "
            "std changes its layer's yield ratio alone: the stresses are elastic)",
            "linearised", cost * shifts))
    return steps, {"sliding": True, "kind": kind.name, "shape": slider.shape,
                   "dimension": kind.dimension, "target": target, "layers": layers,
                   "field_grid": [FIELD_NX, FIELD_NZ], "normal_load": load,
                   "friction": pipeline.friction}


def plan_scene(pipeline: PipelineScene, calibrated: dict[int, ElasticPlastic] | None = None,
               h_star: dict[int, float] | None = None, slide_cost_s: float | None = None
               ) -> Plan:
    """The whole plan; impact steps wait for the calibrations unless all layers are known.
    The calibration steps stay in the plan once done, so that the stored plan is complete.
    ``decisions["std"]``, where set, says why the results carry no standard deviation. A
    sliding scene's steps are `plan_slide`'s (``slide_cost_s``: its measured cost)."""
    steps = []
    for sources in layer_sources(pipeline).values():
        steps += [_calibration_step(s, pipeline.base, len(sources) > 1, pipeline.tolerance)
                  for s in sources]
        if len(sources) > 1:
            steps.append(_joint_step(sources[0].name, sources))
    missing = [s for s in pipeline.calibrations if not calibrated or s.layer not in calibrated]
    if pipeline.sliding:
        stack = None if missing else pipeline.slide_scene(calibrated or {}).stack
        slide_steps, decisions = plan_slide(pipeline, stack, slide_cost_s)
        return Plan(tuple(steps + slide_steps), decisions)
    if missing:
        check_request(pipeline)
        pending, decisions = _pending_steps(pipeline)
        return Plan(tuple(steps + pending), decisions)
    scene = pipeline.completed(calibrated or {}, h_star)
    impact = plan_impact(scene, pipeline.outputs, pipeline.tolerance, pipeline.friction,
                         pipeline.angle)
    steps += impact.steps
    decisions = dict(impact.decisions)
    uncertainty = _uncertainty_step(pipeline, scene, decisions["target"])
    if uncertainty is not None:
        steps.append(uncertainty)
        decisions["std"] = f"not computed: {uncertainty.reason}"
    return Plan(tuple(steps), decisions)


def chosen_model(scene: Scene, target: str, law: str, kind: ModelKind | None = None):
    """The impact model the plan chose: of ``kind`` (default: the scene's), ``target``
    "substrate" or "layered", ``law`` the scene's law or "hertz"."""
    kind = kind or scene.kind
    chosen = contact_law("hertz") if law == "hertz" else scene.law
    return replace(scene, law=chosen).model(bare_substrate=target == "substrate", kind=kind)


#: the swept scene keys a plan's model does not read (`left_out`), by what leaves them out
_FILM_KEYS = ("target.layers", "target.profile")
_FRICTION_KEYS = ("contact.friction",)


def left_out(key: str, decisions: dict, angle: float) -> tuple[int, str, str] | None:
    """(the rule, why, how to keep it) when the plan of ``decisions`` (for an impactor at
    ``angle`` degrees) models nothing the dotted scene ``key`` sets, so that its value cannot
    change the impact results; None when it may (always for a sliding scene). Two cases are known: a key of the films (a
    layer or the measured profile) where the plan models the substrate alone (rule 3, or
    model.target), and the friction of a normal approach (rule 2: no tangential force)."""
    def under(prefixes):
        return any(key == p or key.startswith(p + ".") for p in prefixes)
    if decisions.get("sliding"):        # a slider's friction and films always count
        return None
    if under(_FILM_KEYS) and decisions.get("target") == "substrate":
        if decisions.get("model_target") == "substrate":
            return (3, 'the scene forces model.target = "substrate"',
                    'set model.target = "layered" (or "auto")')
        return (3, "rule 3 models the substrate alone: the films change the maxima by no more "
                "than the tolerance", 'set model.target = "layered", or an [outputs] '
                "tolerance below the films' change")
    if under(_FRICTION_KEYS) and angle == 0:
        return (2, "a normal approach has no tangential force, whatever the friction (rule 2)",
                "give impactor.angle above 0")
    return None
