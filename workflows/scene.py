"""Scene files (TOML): the physical question of an impact, validated into continuum objects.

A scene names the impactor, the target stack and the model. Every key is checked before any
work starts: an unknown key, a missing value or a value out of range raises InputError with
the key's full path, its value and the valid range. See docs/scenes.md for every key.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from filmscale.continuum import (DIAMOND, ElasticPlastic, ImpactModel, Layer, LayerStack,
                                 StackProfile)
from filmscale.continuum.contact.impact_map import axis
from filmscale.continuum.contact.laws import ContactLaw, LAW_NAMES, contact_law
from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.contact.restitution import UNLOADING_MODELS
from filmscale.continuum.indentation.io import read_table
from filmscale.core.checks import (MASS_RANGE, MODULUS_MAX, RADIUS_RANGE, THICKNESS_MAX,
                                   VELOCITY_RANGE, check_choice, check_positive, check_real)
from filmscale.core.errors import InputError
from filmscale.core.files import read_text

_MATERIAL_KEYS = {"name", "E", "nu", "sigma_y", "n"}
_SECTIONS = {
    "impactor": {"shape", "radius", "mass", "velocity", "E", "nu", "name"},
    "target": {"substrate", "layers", "profile"},
    "target.substrate": _MATERIAL_KEYS | {"h_star"},
    "target.layers": _MATERIAL_KEYS | {"thickness", "h_star"},
    "target.profile": {"file", "h_c", "E_r", "H", "breakpoints", "indenter", "nu"},
    "model": {"contact_law", "unloading", "limiting_pressure_factor", "path", "rtol"},
    "map": {"velocity", "radius", "spacing"},
}
_TOP = {"impactor", "target", "model", "map", "title", "description"}


def _check_keys(where: str, table, allowed: set[str]) -> dict:
    if not isinstance(table, dict):
        raise InputError(f"[{where}] must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise InputError(f"unknown key {where}.{unknown[0]} (valid keys in [{where}]: "
                         f"{', '.join(sorted(allowed))})")
    return table


def _required(where: str, table: dict, key: str):
    if key not in table:
        raise InputError(f"{where}.{key} is missing")
    return table[key]


def _h_star(where: str, table: dict) -> float:
    """The Nix-Gao length of a layer (m): its sigma_y becomes sigma_y sqrt(1 + h*/delta)."""
    return check_real(f"{where}.h_star", table.get("h_star", 0.0), low=0.0, high=1e-3,
                      unit="m")


def _material(where: str, table: dict, require_yield: bool = True) -> ElasticPlastic:
    _check_keys(where, table, _MATERIAL_KEYS)
    E = check_real(f"{where}.E", _required(where, table, "E"), low=0.0, low_open=True,
                   high=MODULUS_MAX, unit="Pa")
    nu = check_real(f"{where}.nu", _required(where, table, "nu"), low=-1.0, high=0.5,
                    low_open=True, high_open=True)
    if require_yield:
        sigma_y = check_positive(f"{where}.sigma_y", _required(where, table, "sigma_y"), "Pa")
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
    title: str = ""
    text: str = ""
    source: str = ""

    @property
    def layered(self) -> bool:
        return bool(self.stack.layers) or self.profile is not None

    def model(self) -> ImpactModel:
        """The impact model of the full target (measured profile, else the Gao-weighted
        stack)."""
        target = self.profile if self.profile is not None else self.stack
        if self.profile is None and any(self.h_star):
            target = StackProfile(self.stack, self.h_star)
        return ImpactModel(target, self.law, self.impactor.material, self.unloading)

    def substrate_model(self) -> ImpactModel:
        """The same impact on the bare substrate (the homogeneous reference)."""
        target = self.stack.substrate
        if self.h_star and self.h_star[-1] > 0:
            target = StackProfile(LayerStack((), target), (self.h_star[-1],))
        return ImpactModel(target, self.law, self.impactor.material, self.unloading)


def _profile(table: dict, stack: LayerStack, law: ContactLaw, base: Path) -> TableProfile:
    _check_keys("target.profile", table, _SECTIONS["target.profile"])
    if "file" in table:
        if any(k in table for k in ("h_c", "E_r", "H")):
            raise InputError("target.profile takes either file or h_c/E_r/H arrays, not both")
        columns = read_table(base / str(table["file"]), required=("h_c", "E_r", "H"))
    else:
        columns = {k: _numbers(f"target.profile.{k}", _required("target.profile", table, k))
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
    if not (isinstance(value, list) and len(value) == 3):
        raise InputError(f"{where} must be [min, max, count], got {value!r}")
    return (check_positive(f"{where} minimum", value[0]),
            check_positive(f"{where} maximum", value[1]), value[2])


def _numbers(where: str, value) -> np.ndarray:
    """A non-empty list of numbers (checked one by one, so the error names the entry)."""
    if not isinstance(value, list) or not value:
        raise InputError(f"{where} must be a list of numbers, got {value!r}")
    return np.array([check_real(f"{where}[{i}]", v) for i, v in enumerate(value)])


def read_toml(text: str, source: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"scene {source} is not valid TOML: {err}") from None


def parse_scene(text: str, source: str = "<scene>", base: Path | None = None) -> Scene:
    """Validate a scene's TOML text. ``base`` is the folder that relative file names use."""
    return scene_from_data(read_toml(text, source), text, source, base)


def scene_from_data(data: dict, text: str = "", source: str = "<scene>",
                    base: Path | None = None) -> Scene:
    """Validate a scene already read from TOML (``text`` is kept for provenance)."""
    base = Path(".") if base is None else base
    _check_keys("scene", data, _TOP)

    imp = _check_keys("impactor", _required("scene", data, "impactor"), _SECTIONS["impactor"])
    check_choice("impactor.shape", imp.get("shape", "sphere"), ("sphere",))
    if ("E" in imp) != ("nu" in imp):
        raise InputError("impactor.E and impactor.nu go together: give both for an elastic "
                         "impactor, neither for a rigid one")
    imp_material = None
    if "E" in imp:
        imp_material = _material("impactor", {k: imp[k] for k in ("E", "nu")},
                                 require_yield=False)

    def ranged(key, bounds, unit):
        return check_real(f"impactor.{key}", _required("impactor", imp, key), low=bounds[0],
                          high=bounds[1], low_open=True, unit=unit)

    impactor = Impactor(
        radius=ranged("radius", RADIUS_RANGE, "m"), mass=ranged("mass", MASS_RANGE, "kg"),
        velocity=ranged("velocity", VELOCITY_RANGE, "m/s"),
        material=imp_material, name=str(imp.get("name", "impactor")))

    target = _check_keys("target", _required("scene", data, "target"), _SECTIONS["target"])
    raw_sub = _check_keys("target.substrate", _required("target", target, "substrate"),
                          _SECTIONS["target.substrate"])
    substrate = _material("target.substrate",
                          {k: v for k, v in raw_sub.items() if k != "h_star"})
    raw_layers = target.get("layers", [])
    if not isinstance(raw_layers, list):
        raise InputError("target.layers must be an array of tables ([[target.layers]])")
    layers, h_star = [], []
    for i, raw in enumerate(raw_layers):
        where = f"target.layers[{i}]"
        _check_keys(where, raw, _SECTIONS["target.layers"])
        thickness = check_real(f"{where}.thickness", _required(where, raw, "thickness"),
                               low=0.0, low_open=True, high=THICKNESS_MAX, unit="m")
        mat = _material(where, {k: v for k, v in raw.items()
                                if k not in ("thickness", "h_star")})
        layers.append(Layer(thickness, mat))
        h_star.append(_h_star(where, raw))
    stack = LayerStack(tuple(layers), substrate)
    h_star.append(_h_star("target.substrate", raw_sub))

    model = _check_keys("model", data.get("model", {}), _SECTIONS["model"])
    law_name = check_choice("model.contact_law", model.get("contact_law", "komvopoulos-ye"),
                            LAW_NAMES)
    options = {}
    if "limiting_pressure_factor" in model:
        if law_name != "thornton":
            raise InputError("model.limiting_pressure_factor applies to contact_law = "
                             "\"thornton\" only")
        options["limiting_pressure_factor"] = model["limiting_pressure_factor"]
    law = contact_law(law_name, **options)
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

    mp = _check_keys("map", data.get("map", {}), _SECTIONS["map"])
    map_spec = MapSpec(
        velocity=_range("map.velocity", mp["velocity"]) if "velocity" in mp else None,
        radius=_range("map.radius", mp["radius"]) if "radius" in mp else None,
        spacing=check_choice("map.spacing", mp.get("spacing", "log"), ("log", "linear")))
    return Scene(impactor=impactor, stack=stack, law=law, unloading=unloading, path=path,
                 rtol=rtol, profile=profile, h_star=tuple(h_star) if any(h_star) else (),
                 map=map_spec, title=str(data.get("title", "")),
                 text=text, source=source)


def load_scene(path) -> Scene:
    """Read and validate a scene file."""
    path = Path(path)
    return parse_scene(read_text(path, "scene"), source=str(path), base=path.parent)
