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

from filmscale.continuum import (DIAMOND, ElasticPlastic, ImpactModel, Layer, LayerStack,
                                 StackProfile)
from filmscale.continuum.contact.cylinder import CylinderImpactModel, check_cylinder_mass
from filmscale.continuum.contact.impact_map import axis
from filmscale.continuum.contact.laws import LAW_NAMES, ContactLaw, contact_law
from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.contact.restitution import UNLOADING_MODELS
from filmscale.continuum.indentation.io import read_table
from filmscale.continuum.materials import check_layer_count
from filmscale.core.checks import (MASS_RANGE, MODULUS_MAX, RADIUS_RANGE, THICKNESS_MAX,
                                   VELOCITY_RANGE, check_choice, check_density, check_keys,
                                   check_modulus, check_path, check_positive, check_real,
                                   check_yield_strength, required)
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text
from filmscale.core.quantities import to_si

MATERIAL_KEYS = {"name", "E", "nu", "sigma_y", "n"}
_SECTIONS = {
    "impactor": {"shape", "radius", "mass", "velocity", "E", "nu", "name", "angle",
                 "inertia_factor", "length", "datum_depth"},
    "target": {"substrate", "layers", "profile"},
    "target.substrate": MATERIAL_KEYS | {"h_star"},
    "target.layers": MATERIAL_KEYS | {"thickness", "h_star"},
    "target.profile": {"file", "h_c", "E_r", "H", "breakpoints", "indenter", "nu"},
    "model": {"contact_law", "unloading", "limiting_pressure_factor", "path", "rtol"},
    "map": {"velocity", "radius", "spacing"},
    "contact": {"friction"},
}
_TOP = {"impactor", "target", "model", "map", "contact", "title", "description"}
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
_MATERIAL_UNITS = {"E": "Pa", "sigma_y": "Pa"}
#: the keys that take a quantity with units ("10 um", "90 GPa") as well as a bare SI number,
#: with their SI unit, by table; a [map] axis [min, max, count] takes them for min and max
_QUANTITIES = {
    "impactor": {"radius": "m", "mass": "kg", "velocity": "m/s", "E": "Pa", "length": "m",
                 "datum_depth": "m", "angle": "degree"},
    "target.substrate": _MATERIAL_UNITS | {"h_star": "m"},
    "target.layers": _MATERIAL_UNITS | {"thickness": "m", "h_star": "m"},
    "calibrate": {"film_thickness": "m"},
    "calibrate.substrate": _MATERIAL_UNITS,
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
    """The moving body: a sphere of radius R (m) and mass m (kg) at normal speed V (m/s);
    ``material`` None means rigid."""

    radius: float
    mass: float
    velocity: float
    material: ElasticPlastic | None = None
    name: str = "impactor"
    angle: float = 0.0              #: incidence from the normal, degrees (V stays normal)
    inertia_factor: float = 0.4     #: I / (m R^2), 0.4 for a solid sphere
    shape: str = "sphere"           #: "sphere" or "cylinder" (line contact over ``length``)
    length: float | None = None     #: L of a cylinder, m
    datum_depth: float | None = None  #: d of a cylinder's approach, m (None: d = L)


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

    @property
    def layered(self) -> bool:
        return bool(self.stack.layers) or self.profile is not None

    def _target(self):
        """The full target: measured profile, else the Gao-weighted stack."""
        if self.profile is None and any(self.h_star):
            return StackProfile(self.stack, self.h_star)
        return self.profile if self.profile is not None else self.stack

    def require_sphere(self):
        """InputError unless the impactor is a sphere (the models other than `impact`)."""
        if self.impactor.shape != "sphere":
            raise InputError(f"this command models sphere impactors only; impactor.shape = "
                             f"\"{self.impactor.shape}\" runs with `filmscale impact`")

    def model(self) -> ImpactModel:
        """The impact model of the full target (measured profile, else the Gao-weighted
        stack)."""
        self.require_sphere()
        return ImpactModel(self._target(), self.law, self.impactor.material, self.unloading)

    def cylinder_model(self, bare_substrate: bool = False) -> CylinderImpactModel:
        """The line-contact model (docs/physics.md section 6) of a cylinder scene; with
        ``bare_substrate``, of the substrate alone (see `substrate_model`)."""
        imp = self.impactor
        target = self._bare_substrate() if bare_substrate else self._target()
        return CylinderImpactModel(target, imp.length, imp.material, imp.datum_depth)

    def substrate_model(self) -> ImpactModel:
        """The same impact on the bare substrate (the homogeneous reference)."""
        self.require_sphere()
        return ImpactModel(self._bare_substrate(), self.law, self.impactor.material,
                           self.unloading)

    def _bare_substrate(self):
        """The substrate without its layers, with its own size effect (the last h*)."""
        target = self.stack.substrate
        if self.h_star and self.h_star[-1] > 0:
            target = StackProfile(LayerStack((), target), (self.h_star[-1],))
        return target


def _profile(table: dict, stack: LayerStack, law: ContactLaw, base: Path) -> TableProfile:
    check_keys("target.profile", table, _SECTIONS["target.profile"])
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
    see `_QUANTITIES`) replaced by its SI number, so that the checks and the unit store see
    numbers; other values are left for the checks to judge."""
    data = copy.deepcopy(data)
    _in_si("impactor", data.get("impactor"), _QUANTITIES["impactor"])
    target = data.get("target") if isinstance(data.get("target"), dict) else {}
    _in_si("target.substrate", target.get("substrate"), _QUANTITIES["target.substrate"])
    layers = target.get("layers")
    for i, layer in enumerate(layers if isinstance(layers, list) else []):
        where = f"target.layers[{i}]"
        _in_si(where, layer, _QUANTITIES["target.layers"])
        cal = layer.get("calibrate") if isinstance(layer, dict) else None
        for j, source in enumerate(cal if isinstance(cal, list) else [cal]):
            at = f"{where}.calibrate" + (f"[{j}]" if isinstance(cal, list) else "")
            _in_si(at, source, _QUANTITIES["calibrate"])
            if isinstance(source, dict):
                _in_si(f"{at}.substrate", source.get("substrate"),
                       _QUANTITIES["calibrate.substrate"])
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


def scene_from_data(data: dict, text: str = "", source: str = "<scene>",
                    base: Path | None = None) -> Scene:
    """Validate a scene already read from TOML (``text`` is kept for provenance)."""
    base = Path(".") if base is None else base
    data = si_quantities(data)
    check_keys("scene", data, _TOP)

    imp = check_keys("impactor", required("scene", data, "impactor"), _SECTIONS["impactor"])
    shape = check_choice("impactor.shape", imp.get("shape", "sphere"), ("sphere", "cylinder"))
    if ("E" in imp) != ("nu" in imp):
        raise InputError("impactor.E and impactor.nu go together: give both for an elastic "
                         "impactor, neither for a rigid one")
    imp_material = None
    if "E" in imp:
        imp_material = material("impactor", {k: imp[k] for k in ("E", "nu")},
                                 require_yield=False)

    def ranged(key, bounds, unit):
        return check_real(f"impactor.{key}", required("impactor", imp, key), low=bounds[0],
                          high=bounds[1], low_open=True, unit=unit)

    length = datum = None
    if shape == "cylinder":
        length = ranged("length", RADIUS_RANGE, "m")
        if "datum_depth" in imp:
            datum = check_real("impactor.datum_depth", imp["datum_depth"], low=0.0,
                               high=math.inf, low_open=True, high_open=True, unit="m")
    for key in ("length", "datum_depth"):
        if key in imp and shape != "cylinder":
            raise InputError(f"impactor.{key} applies to shape = \"cylinder\" only")
    impactor = Impactor(
        radius=ranged("radius", RADIUS_RANGE, "m"), mass=ranged("mass", MASS_RANGE, "kg"),
        velocity=ranged("velocity", VELOCITY_RANGE, "m/s"),
        material=imp_material, name=str(imp.get("name", "impactor")),
        angle=check_real("impactor.angle", imp.get("angle", 0.0), low=0.0, high=90.0,
                         high_open=True, unit="degrees"),
        inertia_factor=check_real("impactor.inertia_factor", imp.get("inertia_factor", 0.4),
                                  low=0.0, high=1.0, low_open=True),
        shape=shape, length=length, datum_depth=datum)
    contact = check_keys("contact", data.get("contact", {}), _SECTIONS["contact"])
    friction = check_real("contact.friction", contact.get("friction", 0.0), low=0.0, high=10.0)
    if shape == "cylinder":
        check_cylinder_mass(impactor.radius, length, impactor.mass,
                            ("impactor.radius", "impactor.length", "impactor.mass"))
        if impactor.angle > 0:
            raise InputError("impactor.angle applies to sphere impactors only: the cylinder "
                             "model is a normal impact")
    else:
        check_density(impactor.radius, impactor.mass, "impactor.radius", "impactor.mass")

    target = check_keys("target", required("scene", data, "target"), _SECTIONS["target"])
    raw_sub = check_keys("target.substrate", required("target", target, "substrate"),
                          _SECTIONS["target.substrate"])
    substrate = material("target.substrate",
                          {k: v for k, v in raw_sub.items() if k != "h_star"})
    raw_layers = target.get("layers", [])
    if not isinstance(raw_layers, list):
        raise InputError("target.layers must be an array of tables ([[target.layers]])")
    check_layer_count("target.layers", len(raw_layers))
    layers, h_star = [], []
    for i, raw in enumerate(raw_layers):
        where = f"target.layers[{i}]"
        check_keys(where, raw, _SECTIONS["target.layers"])
        thickness = check_real(f"{where}.thickness", required(where, raw, "thickness"),
                               low=0.0, low_open=True, high=THICKNESS_MAX, unit="m")
        mat = material(where, {k: v for k, v in raw.items()
                                if k not in ("thickness", "h_star")})
        layers.append(Layer(thickness, mat))
        h_star.append(_h_star(where, raw))
    stack = LayerStack(tuple(layers), substrate)
    h_star.append(_h_star("target.substrate", raw_sub))

    model = check_keys("model", data.get("model", {}), _SECTIONS["model"])
    law_name = check_choice("model.contact_law", model.get("contact_law", "komvopoulos-ye"),
                            LAW_NAMES)
    options = {}
    if "limiting_pressure_factor" in model:
        if law_name != "thornton":
            raise InputError("model.limiting_pressure_factor applies to contact_law = "
                             "\"thornton\" only")
        options["limiting_pressure_factor"] = model["limiting_pressure_factor"]
    law = contact_law(law_name, **options)
    sphere_keys = {"contact_law", "unloading", "limiting_pressure_factor"} & set(model)
    if shape == "cylinder" and sphere_keys:
        raise InputError(f"model.{sorted(sphere_keys)[0]} applies to sphere impactors: a "
                         f"cylinder uses the line-contact law of docs/physics.md section 6")
    unloading = check_choice("model.unloading", model.get("unloading", "auto"),
                             ("auto",) + UNLOADING_MODELS)
    path = check_choice("model.path", model.get("path", "fast"), ("fast", "time"))
    rtol = check_real("model.rtol", model.get("rtol", 1e-8), low=1e-13, high=1e-2)

    profile = None
    if "profile" in target:
        profile = _profile(target["profile"], stack, law, base)
        if any(h_star):
            raise InputError("h_star (the Nix-Gao size effect of a layer) does not apply to a "
                             "measured target.profile, which holds its depth dependence")

    mp = check_keys("map", data.get("map", {}), _SECTIONS["map"])
    map_spec = MapSpec(
        velocity=_range("map.velocity", mp["velocity"]) if "velocity" in mp else None,
        radius=_range("map.radius", mp["radius"]) if "radius" in mp else None,
        spacing=check_choice("map.spacing", mp.get("spacing", "log"), ("log", "linear")))
    if map_spec.velocity is not None and map_spec.radius is not None:
        check_map_points(map_spec.velocity[2], map_spec.radius[2])
    if map_spec.radius is not None:     # the map's largest sphere carries the scene's mass
        check_density(max(map_spec.radius[:2]), impactor.mass, "map.radius maximum",
                      "impactor.mass")
    return Scene(impactor=impactor, stack=stack, law=law, unloading=unloading, path=path,
                 rtol=rtol, profile=profile, h_star=tuple(h_star) if any(h_star) else (),
                 map=map_spec, friction=friction, title=str(data.get("title", "")),
                 text=text, source=source)


def load_scene(path) -> Scene:
    """Read and validate a scene file."""
    path = check_path("path", path)
    return parse_scene(read_text(path, "scene"), source=str(path), base=path.parent)
