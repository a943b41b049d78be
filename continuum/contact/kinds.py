"""Model kinds: the impact models of the package as peers behind one protocol.

A kind is one contact model (a sphere's normal impact, a sphere's oblique impact, a
cylinder's line contact, ...) with everything the command line, the scene parser, the
planner, the result files, the report and the plots need to know about it: the impactor
shape it models, the scene keys it reads, how its model is built on a target, one impact, its
time history, its map over (V, R) and the fields and units of its results. Those callers ask
this registry (`KINDS`, `kind_named`, `kind_for`) instead of testing types, so that a new kind
is one `register` call (docs/architecture.md, "How to add a model kind"); the contract test
(tests/continuum/test_model_kinds.py) runs over every registered kind.

The protocol of a kind's model (what `ModelKind.build` returns): ``describe()`` (a dict for
provenance) and ``maxima(V, R, m)``, vectorised over broadcast arrays, returning an object
with ``result(index)`` (one impact with ``summary()`` and ``to_dict()``) and the arrays of
``ModelKind.units``, ``status``, ``regime`` and ``yielded``; with a ``history``, also
``history(V, R, m, rtol=...)`` returning an object with ``result``, ``time``, ``delta``,
``velocity``, ``force``, ``mean_pressure``, ``phase``, ``branch`` and the column named by
``ModelKind.size`` (SI units throughout).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from filmscale.core.checks import check_density
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.keys import REQUIRED, Key
from filmscale.core.quantities import eng

from .impact_map import GridMap, grid_map
from .results import EXCEEDS_RADIUS, OK, STATUS_MESSAGES


@dataclass(frozen=True, eq=False)
class ModelKind:
    """One registered contact model.

    ``build(target, impactor, options)`` makes the model of ``target`` (a DepthProfile,
    LayerStack or ElasticPlastic) for an impactor material (None: rigid) and ``options``, the
    values of the kind's own scene keys (``keys``) by name. ``map(model, velocity, rows, mass,
    options, progress)`` computes its map over the 1-D ``velocity`` (columns) and rows (the
    radii) and returns an object of the map protocol (`impact_map.ImpactMap`, `GridMap`).
    ``solve(model, V, R, m, options)`` gives one impact; ``history`` (None when the kind has
    no time history) its integrated history. ``check_body(radius, mass, options, names)``
    refuses an impactor lighter than its own body (``names``: the words for "radius",
    "mass" and the kind's own keys in the message).
    """

    name: str                       #: registry key, shown to users
    shape: str                      #: the ``impactor.shape`` of the scenes it models
    summary: str                    #: one line for help texts and docs
    build: Callable
    solve: Callable
    check_body: Callable
    fields: Mapping[str, str]       #: the map fields a plot shows, with SI units
    units: Mapping[str, str]        #: every float result of its maps, with SI units
    #: None: `point_map`, one ``model.maxima`` call per point
    map: Callable | None = None
    history: Callable | None = None
    #: the regimes a result's ``regime`` names (for kinds whose model does not say them)
    regime_names: tuple[str, ...] = ("elastic",)
    #: what a point out of the model's range exceeds, in words
    range_limit: str = "outside the model's range"
    #: status code -> message of its results (None: `results.STATUS_MESSAGES`)
    status_messages: Mapping | None = None
    #: a map of this kind from its ``to_dict`` arrays and the file's regime names (None:
    #: the `GridMap` of `point_map`)
    read_map: Callable | None = None
    keys: tuple[Key, ...] = ()      #: scene keys only this kind reads
    oblique: bool = False           #: models an incidence angle (tangential results)
    size: str = "contact_radius"    #: the history's contact-size column
    #: the history plot's approach label and title prefix for a result
    history_labels: Callable | None = None
    #: its model's ``maxima`` takes arrays (else `maxima` calls it point by point)
    vectorised: bool = False
    #: the model in a few words for plot titles, from the options (None: the kind's name)
    label: Callable | None = None

    def options(self, values: Mapping) -> dict:
        """The kind's own options from a mapping of key name -> value (absent: default)."""
        return {k.name: values.get(k.name, k.default) for k in self.keys}

    def maxima(self, model, velocity, radius, mass) -> dict[str, np.ndarray]:
        """The maxima at the broadcast points (V, R) of one mass: every field of ``units``
        the model computes, ``yielded`` and ``status`` (NaN and `results.EXCEEDS_RADIUS`
        where a point is beyond the model's range), as arrays."""
        if self.vectorised:
            found = model.maxima(velocity, radius, mass)
            return ({k: np.asarray(getattr(found, k), dtype=float) for k in self.units
                     if hasattr(found, k)}
                    | {"yielded": np.asarray(found.yielded), "status": np.asarray(found.status)})
        V, R = np.broadcast_arrays(np.asarray(velocity, float), np.asarray(radius, float))
        out = {k: np.full(V.shape, np.nan) for k in self.units}
        out |= {"yielded": np.zeros(V.shape, bool), "status": np.full(V.shape, EXCEEDS_RADIUS)}
        for index in np.ndindex(V.shape):
            try:
                res = model.maxima(float(V[index]), float(R[index]), mass)
            except ModelRangeError:
                continue
            for k in self.units:
                out[k][index] = getattr(res, k)
            out["yielded"][index], out["status"][index] = res.yielded, OK
        return out

    def impact_map(self, model, velocity, rows, mass, options: Mapping, progress=None):
        """The kind's map over the 1-D ``velocity`` (columns) and ``rows`` (radii)."""
        if self.map is not None:
            return self.map(model, velocity, rows, mass, options, progress)
        return point_map(self, model, velocity, rows, mass, progress)

    def map_from_arrays(self, arrays: Mapping, regime_names=(), attrs: Mapping | None = None):
        """A map of this kind read back from its ``to_dict`` arrays (a file's group)."""
        if self.read_map is not None:
            return self.read_map(arrays, tuple(regime_names))
        values = {k: np.asarray(arrays[k], dtype=float) for k in self.units if k in arrays}
        return GridMap(velocity=np.asarray(arrays["velocity"]),
                       radius=np.asarray(arrays["radius"]), mass=float(arrays["mass"]),
                       values=values, regime=np.asarray(arrays["regime"]),
                       status=np.asarray(arrays["status"]), kind=self.name, shape=self.shape,
                       fields=dict(self.fields), units=dict(self.units),
                       regime_names=tuple(regime_names) or self.regime_names,
                       status_messages=self.messages(), range_limit=self.range_limit,
                       attrs=dict(attrs or {}))

    def messages(self) -> dict:
        """Status code -> message of the kind's results."""
        return dict(STATUS_MESSAGES if self.status_messages is None else self.status_messages)


def point_map(kind: ModelKind, model, velocity, rows, mass, progress=None):
    """The `GridMap` of ``kind``: ``model.maxima`` one point at a time over the 1-D
    ``velocity`` (columns) and ``rows`` (radii)."""
    return grid_map(model, velocity, rows, mass, kind=kind.name, shape=kind.shape,
                    fields=kind.fields, units=kind.units, regime_names=kind.regime_names,
                    status_messages=kind.messages(), range_limit=kind.range_limit,
                    progress=progress)


KINDS: dict[str, ModelKind] = {}


def register(kind: ModelKind) -> ModelKind:
    """Add ``kind`` to the registry (a name already there is replaced: a test's throw-away
    kind may be registered twice)."""
    if not isinstance(kind, ModelKind):
        raise InputError(f"kind must be a ModelKind, got {type(kind).__name__}")
    KINDS[kind.name] = kind
    return kind


def unregister(name: str) -> None:
    """Remove a kind (the throw-away kinds of tests)."""
    KINDS.pop(name, None)


def kind_named(name: str) -> ModelKind:
    """The kind registered as ``name``; InputError listing the kinds otherwise."""
    if name not in KINDS:
        raise InputError(f"model kind {name!r} is not one of: {', '.join(KINDS)}")
    return KINDS[name]


def shapes() -> tuple[str, ...]:
    """The impactor shapes the registered kinds model, in registration order."""
    return tuple(dict.fromkeys(k.shape for k in KINDS.values()))


def kind_for(shape: str, oblique: bool = False) -> ModelKind:
    """The kind that models ``shape``, the oblique one when ``oblique``; InputError naming
    what exists otherwise."""
    found = [k for k in KINDS.values() if k.shape == shape]
    if not found:
        raise InputError(f"impactor.shape = {shape!r} is not one of: {', '.join(shapes())}")
    chosen = [k for k in found if k.oblique == oblique]
    if not chosen:
        raise InputError(f"impactor.shape = {shape!r} has no "
                         f"{'oblique' if oblique else 'normal'} impact model: an incidence "
                         "angle applies to " + ", ".join(
                             sorted({k.shape for k in KINDS.values() if k.oblique})))
    return chosen[0]


def shape_keys(shape: str) -> tuple[Key, ...]:
    """Every key the kinds of ``shape`` read (a sphere's normal and oblique kinds share
    theirs), once each, in declaration order."""
    out: dict[str, Key] = {}
    for kind in KINDS.values():
        if kind.shape == shape:
            out.update({k.name: k for k in kind.keys})
    return tuple(out.values())


def all_keys() -> dict[str, tuple[Key, tuple[str, ...]]]:
    """Every kind-specific key name -> (its Key, the shapes that read it)."""
    out: dict[str, tuple[Key, tuple[str, ...]]] = {}
    for kind in KINDS.values():
        for key in kind.keys:
            old = out.get(key.name, (key, ()))[1]
            out[key.name] = (key, old if kind.shape in old else old + (kind.shape,))
    return out


def map_units() -> dict[str, str]:
    """The unit of every array a map of any registered kind may hold; status, regime and
    flags are "1", the axes and the mass their own."""
    units = {"velocity": "m/s", "radius": "m", "mass": "kg", "angle": "degrees"}
    for kind in KINDS.values():
        units.update(kind.units)
    return units | {"status": "1", "regime": "1", "yielded": "1"}


# --- the kinds of the package ------------------------------------------------------------

def _rtol(options: Mapping) -> dict:
    """The scene's integration tolerance where it gives one, else the model's own default."""
    return {"rtol": options["rtol"]} if options.get("rtol") is not None else {}


def _sphere_kinds() -> tuple[ModelKind, ModelKind]:
    from .impact import ImpactModel
    from .impact_map import MAP_FIELDS, ImpactMap, impact_map
    from .laws import DEFAULT_LAW, LAW_NAMES, ContactLaw, contact_law
    from .oblique import (
        INERTIA_FACTOR_MAX, OBLIQUE_FIELDS, SOLID_SPHERE, oblique_map, solve_oblique)
    from .restitution import UNLOADING_MODELS
    from .results import ImpactMaxima

    keys = (
        Key("contact_law", default=DEFAULT_LAW, choices=LAW_NAMES, section="model",
            doc="loading law"),
        Key("unloading", default="auto", choices=("auto",) + UNLOADING_MODELS,
            section="model", doc="residual-depth model; `auto` takes the law's default"),
        Key("limiting_pressure_factor", "1", None, 1.0, 5.0, section="model",
            valid="[1, 5]", doc="Thornton only: p_y / sigma_Y (default 2.8)"),
    )
    oblique_keys = keys + (
        Key("angle", "degree", 0.0, 0.0, 90.0, high_open=True,
            doc="incidence from the normal: an oblique impact with tangential speed "
            "V tan(angle), V staying the normal speed (docs/physics.md section 5)"),
        Key("inertia_factor", "1", SOLID_SPHERE, 0.0, INERTIA_FACTOR_MAX, low_open=True,
            doc="I / (m R^2) of an oblique impact, I the impactor's own moment of inertia "
            "about the tip's centre: 0.4 solid sphere, 2/3 thin shell, > 1 with mass beyond R, "
            "1e8 a body that does not turn (a slider corner: docs/slider-dynamics.md)"),
        Key("friction", "1", 0.0, 0.0, 10.0, section="contact",
            doc="Coulomb coefficient mu of an oblique impact"),
    )

    def build(target, impactor, options):
        law = options["contact_law"]
        if not isinstance(law, ContactLaw):
            factor = options.get("limiting_pressure_factor")
            law = contact_law(law, **({} if factor is None else
                                      {"limiting_pressure_factor": factor}))
        return ImpactModel(target, law, impactor, options["unloading"])

    def solve(model, V, R, m, options):
        return model.maxima(V, R, m).result(())

    def history(model, V, R, m, options):
        return model.history(V, R, m, **_rtol(options))

    def sphere_map(model, velocity, rows, mass, options, progress=None):
        return impact_map(model, velocity, rows, mass, progress=progress)

    def oblique_solve(model, V, R, m, options):
        return solve_oblique(model, V, R, m, options["angle"], options["friction"],
                             inertia_factor=options["inertia_factor"],
                             path=options.get("path", "fast"), **_rtol(options))

    def oblique_rows(model, velocity, rows, mass, options, progress=None):
        return oblique_map(model, velocity, rows, mass, options["angle"], options["friction"],
                           inertia_factor=options["inertia_factor"],
                           progress=progress, **_rtol(options))

    def body(radius, mass, options, names):
        check_density(radius, mass, names["radius"], names["mass"])

    def labels(result):
        return "approach δ (nm)", result.contact_law

    def law_name(options):
        return options["contact_law"].name

    def read(arrays, regime_names):
        return ImpactMap.from_arrays(arrays, regime_names, tangential_units=OBLIQUE_FIELDS)

    units = {k: v for k, v in ImpactMaxima.UNITS.items()
             if k not in ("velocity", "radius", "mass")}
    sphere = ModelKind(
        name="sphere", shape="sphere", summary="normal impact of a sphere (slider corner) "
        "by an elastic-plastic contact law (docs/physics.md sections 1-4)",
        build=build, solve=solve, history=history, map=sphere_map, check_body=body,
        fields=MAP_FIELDS, units=units, keys=keys, history_labels=labels,
        range_limit="approach > R", read_map=read, vectorised=True, label=law_name)
    shown = ("restitution_tangential", "restitution_contact_point", "rebound_angle", "spin")
    oblique = ModelKind(
        name="sphere-oblique", shape="sphere", summary="oblique impact of a sphere: "
        "Mindlin-Deresiewicz tangential compliance, Coulomb friction, rotation "
        "(docs/physics.md section 5)",
        build=build, solve=oblique_solve, history=history, map=oblique_rows, check_body=body,
        fields={**MAP_FIELDS, **{k: OBLIQUE_FIELDS[k] for k in shown}},
        units={**units, **OBLIQUE_FIELDS}, keys=oblique_keys, oblique=True,
        history_labels=labels, range_limit="approach > R", read_map=read, label=law_name,
        vectorised=True)
    return sphere, oblique


def _cylinder_kind() -> ModelKind:
    from .cylinder import REGIME_NAMES, CylinderImpactModel, check_cylinder_mass
    from .impact_map import (CYLINDER_MAP_FIELDS, CYLINDER_STATUS_MESSAGES, CYLINDER_UNITS,
                             cylinder_map)

    keys = (
        Key("length", "m", REQUIRED, 1e-12, 1e3, low_open=True,
            doc="contact length L of the cylinder"),
        Key("datum_depth", "m", None, 0.0, math.inf, low_open=True, high_open=True,
            valid="> 0", doc="depth d of the datum of the line-contact approach "
            "(docs/physics.md section 6; default: d = L)"),
    )

    def build(target, impactor, options):
        return CylinderImpactModel(target, options["length"], impactor,
                                   options["datum_depth"])

    def solve(model, V, R, m, options):
        return model.maxima(V, R, m)

    def history(model, V, R, m, options):
        return model.history(V, R, m, **_rtol(options))

    def rows_map(model, velocity, rows, mass, options, progress=None):
        return cylinder_map(model, velocity, rows, mass, progress=progress)

    def body(radius, mass, options, names):
        check_cylinder_mass(radius, options["length"], mass,
                            (names["radius"], names.get("length", "length"), names["mass"]))

    def labels(result):
        # a line contact's approach is measured from the datum depth d
        return (f"approach δ from d = {result.datum_depth * 1e3:.3g} mm (nm)",
                f"cylinder L = {result.length * 1e3:.3g} mm")

    return ModelKind(
        name="cylinder", shape="cylinder", summary="normal impact of a finite cylinder "
        "(slider edge): line contact in plane strain (docs/physics.md section 6)",
        build=build, solve=solve, history=history, map=rows_map, check_body=body,
        fields=CYLINDER_MAP_FIELDS, units=CYLINDER_UNITS, keys=keys,
        size="contact_half_width", history_labels=labels, regime_names=REGIME_NAMES,
        range_limit="half-width > min(R, d/5)", status_messages=CYLINDER_STATUS_MESSAGES,
        label=lambda options: f"cylinder L = {eng(options['length'], 'm')}")


# the package's own kinds, in this order; others join with `register`
for _kind in (*_sphere_kinds(), _cylinder_kind()):
    register(_kind)
