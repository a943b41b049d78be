"""Scene files (TOML): the physical question of an impact, validated into continuum objects.

A scene names the impactor, the target stack and the model. Every key is checked before any
work starts: an unknown key, a missing value or a value out of range raises InputError with
the key's full path, its value and the valid range. See docs/scenes.md for every key.
"""

from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from filmscale.continuum import (DIAMOND, ElasticPlastic, Layer, LayerStack,
                                 StackProfile)
from filmscale.continuum.contact.impact_map import axis
from filmscale.continuum.contact.kinds import ModelKind, all_keys, kind_for, shapes
from filmscale.continuum.contact.laws import DEFAULT_LAW, ContactLaw, contact_law
from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.indentation.io import read_table
from filmscale.continuum.materials import check_layer_count
from filmscale.core.checks import (MODULUS_MAX, RADIUS_RANGE, THICKNESS_MAX,
                                   VELOCITY_RANGE, check_choice, check_keys,
                                   check_modulus, check_path, check_positive, check_real,
                                   check_yield_strength, required)
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text
from filmscale.core.keys import read_keys
from filmscale.core.quantities import to_si

from .scene_keys import GENERAL_KEYS, key_names, quantity_units, section_keys

MATERIAL_KEYS = {"name", "E", "nu", "sigma_y", "n"}
#: the most points of an impact map (velocities x radii or angles): a 1000 x 1000 map of a
#: one-film scene (its layered target and the bare-substrate reference) takes 64 s and
#: 0.64 GB on two cores; 10^7 points would take over 10 minutes and 6 GB, and the axes alone
#: (100,000 values each, `impact_map.axis`) allow 10^10. A figure needs no more than 1000
#: values per axis
MAP_POINTS_MAX = 10**6
#: the most values of one map axis (`impact_map.axis` refuses more)
AXIS_COUNT_MAX = 100_000
#: a [[target.layers]] table header: counted in the text before it is parsed, so that a scene
#: of 10^5 layers is refused at once, not after seconds of TOML parsing
_LAYER_HEADER = re.compile(r"^[ \t]*\[\[[ \t]*target[ \t]*\.[ \t]*layers[ \t]*\]\]",
                           re.MULTILINE)
#: the quantities of a layer's calibration source (docs/pipeline.md), SI unit by key
_SOURCE_QUANTITIES = {
    "calibrate": {"film_thickness": "m", "density": "kg/m^3"},
    "calibrate.substrate": {"E": "Pa", "sigma_y": "Pa"},
}


def _h_star(where: str, table: dict) -> float:
    """The Nix-Gao length of a layer (m): its sigma_y becomes sigma_y sqrt(1 + h*/delta)."""
    return check_real(f"{where}.h_star", table.get("h_star", 0.0), low=0.0, high=1e-3,
                      unit="m")


def material(where: str, table: dict, require_yield: bool = True) -> ElasticPlastic:
    """A material table, checked: ranges, then plausibility (E of a real solid, sigma_y
    below E; the messages name the key and the likely unit slip)."""
    check_keys(where, table, MATERIAL_KEYS)
    E = check_real(f"{where}.E", required(where, table, "E"), low=0.0, low_open=True,
                   high=MODULUS_MAX, unit="Pa")
    check_modulus(f"{where}.E", E, "Young's modulus")
    nu = check_real(f"{where}.nu", required(where, table, "nu"), low=-1.0, high=0.5,
                    low_open=True, high_open=True)
    if require_yield:
        sigma_y = check_positive(f"{where}.sigma_y", required(where, table, "sigma_y"), "Pa")
        check_yield_strength(f"{where}.sigma_y", sigma_y, E, f"{where}.E")
    else:
        sigma_y = math.inf
    n = check_real(f"{where}.n", table.get("n", 0.0), low=0.0, high=1.0, high_open=True)
    name = table.get("name", where)
    if not isinstance(name, str):
        raise InputError(f"{where}.name must be a string, got {name!r}")
    return ElasticPlastic(E=E, nu=nu, sigma_y=sigma_y, n=n, name=name)


@dataclass(frozen=True)
class Impactor:
    """The moving body: its shape (a registered model kind's, `kinds.shapes`), radius R (m)
    and mass m (kg) at normal speed V (m/s); ``material`` None means rigid. ``options`` holds
    the values of the [impactor] keys that only its shape reads (a sphere's ``angle`` and
    ``inertia_factor``, a cylinder's ``length`` and ``datum_depth``), in SI."""

    radius: float
    mass: float
    velocity: float
    material: ElasticPlastic | None = None
    name: str = "impactor"
    shape: str = "sphere"
    options: dict = field(default_factory=dict)

    @property
    def angle(self) -> float:
        """Incidence from the normal, degrees (V stays normal); 0 for shapes without one."""
        return float(self.options.get("angle") or 0.0)

    @property
    def inertia_factor(self) -> float:
        """I / (m R^2) of a sphere in an oblique impact."""
        return float(self.options.get("inertia_factor", 0.4))

    @property
    def length(self) -> float | None:
        """L of a cylinder, m."""
        return self.options.get("length")


@dataclass(frozen=True)
class MapSpec:
    """Axes of an impact map: (min, max, count) for V (m/s) and R (m), and the spacing."""

    velocity: tuple[float, float, int] | None = None
    radius: tuple[float, float, int] | None = None
    spacing: str = "log"

    velocity_name: str = "map.velocity"
    radius_name: str = "map.radius"

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        if self.velocity is None or self.radius is None:
            raise InputError("an impact map needs velocity and radius ranges: give "
                             "--velocity MIN:MAX:N --radius MIN:MAX:N or a [map] section")
        check_map_points(self.velocity[2], self.radius[2], self.velocity_name, self.radius_name)
        return (axis(*self.velocity, self.spacing, self.velocity_name, VELOCITY_RANGE, "m/s"),
                axis(*self.radius, self.spacing, self.radius_name, RADIUS_RANGE, "m"))


@dataclass(frozen=True)
class Scene:
    """A validated impact scene; ``text`` is the TOML it came from (for provenance)."""

    impactor: Impactor
    stack: LayerStack
    law: ContactLaw
    unloading: str = "auto"
    path: str = "fast"
    rtol: float = 1e-8
    profile: TableProfile | None = None
    #: Nix-Gao length h* (m) of each layer, then the substrate (all 0: no size effect)
    h_star: tuple[float, ...] = ()
    map: MapSpec = field(default_factory=MapSpec)
    friction: float = 0.0           #: Coulomb coefficient of the contact (oblique impact)
    title: str = ""
    text: str = ""
    source: str = ""
    #: the values of the other [model] and [contact] keys the impactor's kind declares (its
    #: law, unloading and friction have the fields above)
    options: dict = field(default_factory=dict)
    #: ``model.target``: "auto" (the planner's rule 3 chooses), "layered" or "substrate"
    model_target: str = "auto"

    @property
    def layered(self) -> bool:
        return bool(self.stack.layers) or self.profile is not None

    @property
    def kind(self) -> ModelKind:
        """The registered model kind of the impactor: its shape's, oblique when the scene
        gives an incidence angle."""
        return kind_for(self.impactor.shape, oblique=self.impactor.angle > 0)

    def kind_options(self, kind: ModelKind | None = None) -> dict:
        """Everything a kind's model and maps read: its own keys' values, the scene's
        contact law (as the law object), ``path`` and ``rtol``."""
        kind = kind or self.kind
        values = {**self.options, **self.impactor.options, "friction": self.friction,
                  "contact_law": self.law, "unloading": self.unloading}
        return kind.options(values) | {"path": self.path, "rtol": self.rtol}

    def _target(self):
        """The full target: measured profile, else the Gao-weighted stack."""
        if self.profile is None and any(self.h_star):
            return StackProfile(self.stack, self.h_star)
        return self.profile if self.profile is not None else self.stack

    def model(self, bare_substrate: bool = False, kind: ModelKind | None = None):
        """The impact model of the full target (measured profile, else the Gao-weighted
        stack), or with ``bare_substrate`` of the substrate alone: built by the impactor's
        kind (`kind`), or by ``kind``."""
        kind = kind or self.kind
        target = self._bare_substrate() if bare_substrate else self._target()
        return kind.build(target, self.impactor.material, self.kind_options(kind))

    def substrate_model(self, kind: ModelKind | None = None):
        """The same impact on the bare substrate (the homogeneous reference)."""
        return self.model(bare_substrate=True, kind=kind)

    def _bare_substrate(self):
        """The substrate without its layers, with its own size effect (the last h*)."""
        target = self.stack.substrate
        if self.h_star and self.h_star[-1] > 0:
            target = StackProfile(LayerStack((), target), (self.h_star[-1],))
        return target


def _profile(table: dict, stack: LayerStack, law: ContactLaw, base: Path) -> TableProfile:
    check_keys("target.profile", table, key_names("target.profile"))
    if "file" in table:
        if any(k in table for k in ("h_c", "E_r", "H")):
            raise InputError("target.profile takes either file or h_c/E_r/H arrays, not both")
        columns = read_table(base / str(table["file"]), required=("h_c", "E_r", "H"))
    else:
        columns = {k: _numbers(f"target.profile.{k}", required("target.profile", table, k))
                   for k in ("h_c", "E_r", "H")}
    breakpoints = table.get("breakpoints", "layers")
    if breakpoints == "layers":
        breakpoints = stack.interface_depths
    elif isinstance(breakpoints, list):
        breakpoints = _numbers("target.profile.breakpoints", breakpoints) if breakpoints else []
    else:
        raise InputError(f"target.profile.breakpoints must be \"layers\" or a list of depths "
                         f"in m, got {breakpoints!r}")
    indenter = check_choice("target.profile.indenter", table.get("indenter", "diamond"),
                            ("diamond", "rigid"))
    return TableProfile.from_measurements(
        columns["h_c"], columns["E_r"], columns["H"], breakpoints=breakpoints,
        indenter=DIAMOND if indenter == "diamond" else None,
        nu=check_real("target.profile.nu", table.get("nu", stack.substrate.nu), low=-1.0,
                      high=0.5, low_open=True, high_open=True),
        hardness_factor=law.hardness_factor)


def _range(where: str, value) -> tuple[float, float, int]:
    """[min, max, count] of a map axis: finite positive bounds and a whole count (NaN and
    infinities refused here, before any use)."""
    if not (isinstance(value, list) and len(value) == 3):
        raise InputError(f"{where} must be [min, max, count], got {value!r}")
    return (check_positive(f"{where} minimum", value[0]),
            check_positive(f"{where} maximum", value[1]), _count(f"{where} count", value[2]))


def _count(name: str, value) -> int:
    """A whole number of axis values in [1, AXIS_COUNT_MAX] (as `impact_map.axis` words it);
    NaN, infinities, fractions, booleans and non-numbers are refused."""
    if (isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating))
            or not math.isfinite(value) or int(value) != value
            or not 1 <= value <= AXIS_COUNT_MAX):
        raise InputError(f"{name} = {value!r} must be an integer in [1, {AXIS_COUNT_MAX}]")
    return int(value)


def check_map_points(columns, rows, columns_name: str = "map.velocity",
                     rows_name: str = "map.radius") -> int:
    """The number of points of a map of ``columns`` x ``rows`` values, or InputError naming
    both axes when it is above `MAP_POINTS_MAX`."""
    columns, rows = _count(f"{columns_name} count", columns), _count(f"{rows_name} count", rows)
    if columns * rows > MAP_POINTS_MAX:
        raise InputError(f"the impact map has {columns} x {rows} = {columns * rows} points "
                         f"({columns_name} x {rows_name}), more than the limit of "
                         f"{MAP_POINTS_MAX} (a 1000 x 1000 map takes about a minute and "
                         "0.6 GB; split a larger one)")
    return columns * rows


def check_layer_headers(text: str) -> None:
    """InputError when the scene text holds more ``[[target.layers]]`` tables than a stack
    takes (`materials.MAX_LAYERS`): checked before the TOML is parsed."""
    if isinstance(text, str) and "layers" in text:
        check_layer_count("target.layers", len(_LAYER_HEADER.findall(text)))


def _numbers(where: str, value) -> np.ndarray:
    """A non-empty list of numbers (checked one by one, so the error names the entry)."""
    if not isinstance(value, list) or not value:
        raise InputError(f"{where} must be a list of numbers, got {value!r}")
    return np.array([check_real(f"{where}[{i}]", v) for i, v in enumerate(value)])


def _in_si(where: str, table, units: dict[str, str]) -> None:
    """Convert, in place, each quantity with units in ``table`` to its SI number."""
    if isinstance(table, dict):
        for key, unit in units.items():
            if key in table:
                table[key] = to_si(f"{where}.{key}", table[key], unit, text_numbers=False)


def si_quantities(data: dict) -> dict:
    """A copy of scene ``data`` with every quantity written with units ("10 um", "90 GPa",
    the keys of `scene_keys` with a unit) replaced by its SI number, so that the checks and
    the unit store see numbers; other values are left for the checks to judge."""
    data = copy.deepcopy(data)
    for section in ("impactor", "model", "contact"):
        _in_si(section, data.get(section), quantity_units(section))
    target = data.get("target") if isinstance(data.get("target"), dict) else {}
    _in_si("target.substrate", target.get("substrate"), quantity_units("target.substrate"))
    layers = target.get("layers")
    for i, layer in enumerate(layers if isinstance(layers, list) else []):
        where = f"target.layers[{i}]"
        _in_si(where, layer, quantity_units("target.layers"))
        cal = layer.get("calibrate") if isinstance(layer, dict) else None
        for j, source in enumerate(cal if isinstance(cal, list) else [cal]):
            at = f"{where}.calibrate" + (f"[{j}]" if isinstance(cal, list) else "")
            _in_si(at, source, _SOURCE_QUANTITIES["calibrate"])
            if isinstance(source, dict):
                _in_si(f"{at}.substrate", source.get("substrate"),
                       _SOURCE_QUANTITIES["calibrate.substrate"])
    axes = data.get("map") if isinstance(data.get("map"), dict) else {}
    for key, unit in (("velocity", "m/s"), ("radius", "m")):
        if isinstance(axes.get(key), list) and len(axes[key]) == 3:
            axes[key][:2] = [to_si(f"map.{key} {end}", v, unit, text_numbers=False)
                             for end, v in zip(("minimum", "maximum"), axes[key][:2])]
    return data


def parse_scene(text: str, source: str = "<scene>", base: Path | None = None) -> Scene:
    """Validate a scene's TOML text. ``base`` is the folder that relative file names use."""
    check_layer_headers(text)
    return scene_from_data(parse_toml(text, "scene", source), text, source, base)


def _section(where: str, data: dict, shape: str) -> dict:
    """The table ``where`` of ``data``, its keys checked against `scene_keys`: a key of
    another shape's kind is refused naming the shapes that read it."""
    table = check_keys(where, data.get(where, {}), key_names(where))
    mine = {k.name for k in section_keys(where, shape)}
    for name in table:
        if name not in mine:
            used = [s for key, s in all_keys().values() if key.name == name
                    and key.section == where][0]
            raise InputError(f"{where}.{name} applies to {' and '.join(used)} impactors only "
                             f"(impactor.shape = \"{shape}\")")
    return table


def _kind_values(where: str, table: dict, shape: str) -> dict:
    """The values of the keys of ``shape``'s kinds in the section ``where``."""
    own = [k for k in section_keys(where, shape) if k not in GENERAL_KEYS[where]]
    return read_keys(where, table, own)


def read_impactor(data: dict) -> Impactor:
    """The [impactor] section: the general keys, then those of its shape's kinds."""
    imp = check_keys("impactor", required("scene", data, "impactor"), key_names("impactor"))
    shape = check_choice("impactor.shape", imp.get("shape", "sphere"), shapes())
    imp = _section("impactor", data, shape)
    if ("E" in imp) != ("nu" in imp):
        raise InputError("impactor.E and impactor.nu go together: give both for an elastic "
                         "impactor, neither for a rigid one")
    imp_material = None
    if "E" in imp:
        imp_material = material("impactor", {k: imp[k] for k in ("E", "nu")},
                                require_yield=False)
    general = read_keys("impactor", imp, [k for k in GENERAL_KEYS["impactor"]
                                          if k.name not in ("E", "nu", "name", "shape")])
    impactor = Impactor(**general, material=imp_material, name=str(imp.get("name", "impactor")),
                        shape=shape, options=_kind_values("impactor", imp, shape))
    # the shape has a model for the angle, and the body is not lighter than itself
    kind_for(shape, oblique=impactor.angle > 0).check_body(
        impactor.radius, impactor.mass, impactor.options,
        {"radius": "impactor.radius", "mass": "impactor.mass", "length": "impactor.length"})
    return impactor


def _layer(where: str, raw, pending: bool) -> tuple[Layer | None, float]:
    """One [[target.layers]] table: the layer (None when ``pending``: its E and sigma_y
    come from a calibration) and its Nix-Gao length."""
    check_keys(where, raw, key_names("target.layers"))
    thickness = check_real(f"{where}.thickness", required(where, raw, "thickness"),
                           low=0.0, low_open=True, high=THICKNESS_MAX, unit="m")
    props = {k: v for k, v in raw.items() if k not in ("thickness", "h_star")}
    if pending and not {"E", "sigma_y"} <= set(props):
        read_keys(where, props, [k for k in GENERAL_KEYS["target.layers"]
                                 if k.name in ("nu", "n") and k.name in props])
        return None, _h_star(where, raw)
    return Layer(thickness, material(where, props)), _h_star(where, raw)


def _stack(data: dict, pending=frozenset()) -> tuple[LayerStack | None, list[float], dict]:
    """The [target] section: its stack (None while a layer in ``pending`` awaits its
    calibration), the Nix-Gao lengths (layers, then substrate) and the raw table."""
    target = check_keys("target", required("scene", data, "target"), key_names("target"))
    raw_sub = check_keys("target.substrate", required("target", target, "substrate"),
                         key_names("target.substrate"))
    substrate = material("target.substrate",
                         {k: v for k, v in raw_sub.items() if k != "h_star"})
    raw_layers = target.get("layers", [])
    if not isinstance(raw_layers, list):
        raise InputError("target.layers must be an array of tables ([[target.layers]])")
    check_layer_count("target.layers", len(raw_layers))
    parsed = [_layer(f"target.layers[{i}]", raw, i in pending)
              for i, raw in enumerate(raw_layers)]
    h_star = [h for _, h in parsed] + [_h_star("target.substrate", raw_sub)]
    layers = [layer for layer, _ in parsed]
    stack = None if None in layers else LayerStack(tuple(layers), substrate)
    return stack, h_star, target


def read_stack(data: dict, pending=frozenset()) -> LayerStack | None:
    """The [target] section of a scene (quantities with units allowed) as its layer stack
    (None while a layer in ``pending`` awaits the E and sigma_y of its calibration; such a
    layer must state nu); a sliding scene's target is its films and substrate, so a measured
    profile and Nix-Gao lengths are refused."""
    check_pending_nu(data, pending)
    stack, h_star, target = _stack(si_quantities(data), pending)
    if "profile" in target:
        raise InputError("target.profile (a measured depth profile) does not give the "
                         "stresses of a sliding contact: give the layers")
    if any(h_star):
        raise InputError("h_star (the Nix-Gao size effect) applies to impact scenes only")
    return stack


def check_pending_nu(data: dict, pending) -> None:
    """InputError for a layer awaiting calibration that does not state nu: the calibration
    of E from a curve takes the film's Poisson ratio."""
    target = data.get("target") if isinstance(data.get("target"), dict) else {}
    layers = target.get("layers") if isinstance(target.get("layers"), list) else []
    for k in sorted(pending):
        if k < len(layers) and isinstance(layers[k], dict) and "nu" not in layers[k]:
            raise InputError(f"target.layers[{k}].nu is missing: a calibrated layer states "
                             "its Poisson ratio (the calibration of E takes it)")


def _model(data: dict, shape: str) -> tuple[dict, dict]:
    """The [model] and [contact] sections: the general keys' values and the kind's own."""
    model = _section("model", data, shape)
    general = read_keys("model", model, GENERAL_KEYS["model"])
    contact = _section("contact", data, shape)
    options = _kind_values("model", model, shape) | _kind_values("contact", contact, shape)
    if options.get("limiting_pressure_factor") is not None and \
            options.get("contact_law") != "thornton":
        raise InputError("model.limiting_pressure_factor applies to contact_law = "
                         "\"thornton\" only")
    return general, options


def _law(options: dict) -> ContactLaw:
    """The scene's contact law: its kind's, else the package default (what a calibration
    fits when the scene names none)."""
    factor = options.get("limiting_pressure_factor")
    return contact_law(options.get("contact_law", DEFAULT_LAW),
                       **({} if factor is None else {"limiting_pressure_factor": factor}))


def read_map_spec(data: dict, mass: float, impactor: Impactor) -> MapSpec:
    """The [map] section, its size and its largest body checked."""
    mp = check_keys("map", data.get("map", {}), key_names("map"))
    spec = MapSpec(
        velocity=_range("map.velocity", mp["velocity"]) if "velocity" in mp else None,
        radius=_range("map.radius", mp["radius"]) if "radius" in mp else None,
        spacing=check_choice("map.spacing", mp.get("spacing", "log"), ("log", "linear")))
    if spec.velocity is not None and spec.radius is not None:
        check_map_points(spec.velocity[2], spec.radius[2])
    if spec.radius is not None:     # the map's largest body carries the scene's mass
        kind_for(impactor.shape).check_body(
            max(spec.radius[:2]), mass, impactor.options,
            {"radius": "map.radius maximum", "mass": "impactor.mass",
             "length": "impactor.length"})
    return spec


def refuse_slider(data: dict) -> None:
    """InputError for a sliding scene given to an impact command."""
    if "slider" in data:
        raise InputError("the scene has a [slider]: a sliding scene is read by `filmscale "
                         "slide` and `filmscale slide-map`; an impact scene has an [impactor]")


def check_scene_data(data: dict, pending=frozenset()) -> None:
    """Every check of `scene_from_data` on ``data`` (already in SI) whose layers in
    ``pending`` may still lack the E and sigma_y that their calibration will give."""
    check_keys("scene", data, key_names(""))
    refuse_slider(data)
    impactor = read_impactor(data)
    check_pending_nu(data, pending)
    _stack(data, pending)
    _model(data, impactor.shape)
    read_map_spec(data, impactor.mass, impactor)


def scene_from_data(data: dict, text: str = "", source: str = "<scene>",
                    base: Path | None = None) -> Scene:
    """Validate a scene already read from TOML (``text`` is kept for provenance)."""
    base = Path(".") if base is None else base
    data = si_quantities(data)
    check_keys("scene", data, key_names(""))
    refuse_slider(data)
    impactor = read_impactor(data)
    stack, h_star, target = _stack(data)
    general, options = _model(data, impactor.shape)
    law = _law(options)
    profile = None
    if "profile" in target:
        profile = _profile(target["profile"], stack, law, base)
        if any(h_star):
            raise InputError("h_star (the Nix-Gao size effect of a layer) does not apply to a "
                             "measured target.profile, which holds its depth dependence")
    return Scene(impactor=impactor, stack=stack, law=law,
                 unloading=options.get("unloading", "auto"), path=general["path"],
                 rtol=general["rtol"], model_target=general["target"], profile=profile,
                 h_star=tuple(h_star) if any(h_star) else (),
                 map=read_map_spec(data, impactor.mass, impactor),
                 friction=float(options.get("friction", 0.0)),
                 title=str(data.get("title", "")), text=text, source=source,
                 options={k: v for k, v in options.items()
                          if k not in ("contact_law", "unloading", "friction",
                                       "limiting_pressure_factor")})


def load_scene(path) -> Scene:
    """Read and validate a scene file."""
    path = check_path("path", path)
    return parse_scene(read_text(path, "scene"), source=str(path), base=path.parent)
