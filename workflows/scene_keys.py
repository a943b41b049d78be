"""The keys of a scene file, declared once: name, SI unit, default, range and the impactor
shapes that read them. The scene parser checks each section against this table, the unit
conversion of quantities ("10 um") reads its units, and docs/scenes.md's key list is
written from it (`key_table`; tests/workflows/test_scene_keys.py keeps the two equal).

Keys of one model kind (a cylinder's length, a sphere's contact law) are declared by the kind
(`continuum.contact.kinds`) and join their section here, marked with the shapes that read
them.
"""

from __future__ import annotations

import math

from filmscale.continuum.contact.kinds import all_keys, shapes
from filmscale.continuum.contact.slider import SLIDING_KINDS
from filmscale.core.checks import MASS_RANGE, RADIUS_RANGE, THICKNESS_MAX, VELOCITY_RANGE
from filmscale.core.keys import REQUIRED, Key

#: the values of ``model.target``: rule 3 chooses, or the films are kept, or left out
TARGETS = ("auto", "layered", "substrate")

_NU = dict(low=-1.0, high=0.5, low_open=True, high_open=True)


def _material(required_yield: bool = True) -> tuple[Key, ...]:
    return (
        Key("name", doc="label"),
        Key("E", "Pa", REQUIRED, 0.0, 1e14, low_open=True, valid="[0.1 GPa, 2 TPa]",
            doc="Young's modulus"),
        Key("nu", "1", REQUIRED, **_NU, doc="Poisson ratio"),
        Key("sigma_y", "Pa", REQUIRED if required_yield else None, 0.0, math.inf,
            low_open=True, high_open=True, valid="(0, E)",
            doc="yield strength (above 0.1 E: a warning in the result)"),
        Key("n", "1", 0.0, 0.0, 1.0, high_open=True,
            doc="hardening exponent: carried, ignored by the impact laws (warning)"),
        Key("h_star", "m", 0.0, 0.0, 1e-3, doc="Nix-Gao length: the material's sigma_y "
            "becomes sigma_y sqrt(1 + h*/delta) at approach delta (Nix & Gao 1998, hardness "
            "taken proportional to sigma_y); not with `target.profile`"),
    )


#: the keys every scene may hold, by section ("" is the top level), before the kinds' own
GENERAL_KEYS: dict[str, tuple[Key, ...]] = {
    "": (Key("title", default="", doc="shown on plots"),
         Key("description", default="", doc="free text")),
    "impactor": (
        Key("shape", default="sphere", doc="the impactor's shape: a sphere (slider corner) "
            "or a cylinder of length `length` lying on the surface (slider edge, line "
            "contact, docs/physics.md section 6); each shape is a model kind "
            "(docs/architecture.md)"),
        Key("radius", "m", REQUIRED, *RADIUS_RANGE, low_open=True,
            doc="sphere (slider corner) or cylinder (edge) radius R"),
        Key("mass", "kg", REQUIRED, *MASS_RANGE, low_open=True,
            valid="(0, 1e6]; m/(4/3 pi R^3) >= 1 kg/m^3 (cylinder: m/(pi R^2 L) >= 1 kg/m^3)",
            doc="impacting mass m (may be a larger body's: no upper density bound)"),
        Key("velocity", "m/s", REQUIRED, *VELOCITY_RANGE, low_open=True,
            doc="normal impact velocity V (faster is shock physics)"),
        Key("E", "Pa", None, 0.0, 1e14, low_open=True, valid="[0.1 GPa, 2 TPa], with `nu`",
            doc="elastic impactor; leave `E` and `nu` out for a rigid one"),
        Key("nu", "1", None, **_NU, doc="the elastic impactor's Poisson ratio, with `E`"),
        Key("name", default="impactor", doc="label"),
    ),
    "target": (),
    "target.substrate": _material(),
    "target.layers": _material() + (
        Key("thickness", "m", REQUIRED, 0.0, THICKNESS_MAX, low_open=True,
            doc="film thickness"),),
    "target.profile": (
        Key("file", doc="table with header `h_c [nm], E_r [GPa], H [GPa]` (units in "
            "brackets; SI if none), relative to the scene; or the three arrays below",
            valid="path"),
        Key("h_c", "m", None, valid="list in (0, 1 mm]", doc="contact depth of each indent"),
        Key("E_r", "Pa", None, valid="list in [0.1 GPa, 2 TPa]", doc="reduced modulus"),
        Key("H", "Pa", None, valid="list, 0 < H < E_r", doc="hardness"),
        Key("breakpoints", "m", "layers", valid="`\"layers\"` or a list", doc="depths "
            "where the piecewise-linear fit may change slope; default: the layer interfaces"),
        Key("indenter", default="diamond", choices=("diamond", "rigid"), doc="what E_r was "
            "measured against (diamond: E = 1141 GPa, nu = 0.07)"),
        Key("nu", "1", None, **_NU, doc="Poisson ratio used by the laws' yield criteria "
            "(default: the substrate's)"),
    ),
    "model": (
        Key("path", default="fast", choices=("fast", "time"), doc="`filmscale impact`: "
            "energy quadrature, or time integration (also implied by `--history`/`--plot`)"),
        Key("rtol", "1", 1e-8, 1e-13, 1e-2, doc="relative tolerance of time integration"),
        Key("target", default="auto", choices=TARGETS, doc="the target the planner models "
            "(`filmscale plan`, `run`, `sweep`; docs/pipeline.md, rule 3): `auto` keeps the "
            "films (or `target.profile`) where leaving them out changes the maxima by more "
            "than `[outputs] tolerance`; `layered` keeps them whatever they change; "
            "`substrate` models the substrate alone. `filmscale impact` and `impact-map` "
            "model the whole target whatever it says"),
    ),
    "contact": (),
    "slider": (
        Key("shape", default="sphere", choices=("sphere", "cylinder"), section="slider",
            doc="a sliding scene (`filmscale slide`, `slide-map`; docs/sliding.md) holds "
            "[slider] instead of [impactor]: a sphere (the flying-height bump, a corner) or a "
            "cylinder of length `length` (an edge, plane strain); the friction is `[contact] "
            "friction`, or `[contact] friction_from = \"scratch.h5\"`: the friction a "
            "scratch record of `filmscale md scratch` or `particles scratch` measured"),
        Key("radius", "m", REQUIRED, 1e-12, 1.0, low_open=True, section="slider",
            doc="the protrusion's radius R"),
        Key("normal_load", "N", REQUIRED, 0.0, 1e6, low_open=True, section="slider",
            doc="the load P pressing it on the target (a cylinder's total load on L)"),
        Key("E", "Pa", None, 0.0, 1e14, low_open=True, section="slider",
            valid="[0.1 GPa, 2 TPa], with `nu`", doc="elastic slider; leave `E` and `nu` out "
            "for a rigid one"),
        Key("nu", "1", None, **_NU, section="slider", doc="the elastic slider's Poisson ratio"),
        Key("name", default="slider", section="slider", doc="label"),
    ),
    "map": (
        Key("velocity", "m/s", None, valid="`[min, max, count]`",
            doc="default velocity axis of `filmscale impact-map`"),
        Key("radius", "m", None, valid="`[min, max, count]`", doc="default radius axis; the "
            "largest with `impactor.mass` must be 1 kg/m^3 or denser"),
        Key("spacing", default="log", choices=("log", "linear"), doc="axis spacing"),
    ),
}


def section_keys(section: str, shape: str | None = None) -> tuple[Key, ...]:
    """The keys of ``section``: the general ones, then those of the model kinds (of
    ``shape`` only, when given)."""
    own = tuple(key for key, used in all_keys().values()
                if key.section == section and (shape is None or shape in used))
    if section == "slider":
        own = tuple(key for kind in SLIDING_KINDS.values() for key in kind.keys
                    if shape is None or kind.shape == shape)
    return GENERAL_KEYS[section] + own


def key_names(section: str) -> set[str]:
    """Every key name ``section`` may hold (for any shape)."""
    names = {k.name for k in section_keys(section)}
    if section == "":
        names |= {s for s in GENERAL_KEYS if s and "." not in s}
    if section == "target":
        names |= {"substrate", "layers", "profile"}
    return names


def quantity_units(section: str) -> dict[str, str]:
    """The keys of ``section`` that take a quantity with units, with their SI unit."""
    return {k.name: k.unit for k in section_keys(section) if k.quantity and section != "map"}


def _unit_column(key: Key) -> str:
    return {"1": "-", "degree": "degrees"}.get(key.unit, key.unit)


def key_table() -> str:
    """The key list of docs/scenes.md, as Markdown."""
    used = {key.name + key.section: shapes_ for key, shapes_ in all_keys().values()}
    sliding = {"slider": tuple(k for kind in SLIDING_KINDS.values() for k in kind.keys)}
    used |= {k.name + k.section: (kind.shape,) for kind in SLIDING_KINDS.values()
             for k in kind.keys}
    rows = ["| key | unit | required | valid | meaning |", "|---|---|---|---|---|"]
    for section, keys in GENERAL_KEYS.items():
        if section and section != "target":
            rows.append(f"| **`[{'[' if section == 'target.layers' else ''}{section}"
                        f"{']' if section == 'target.layers' else ''}]`** | | | | |")
        for key in keys + tuple(k for k, _ in all_keys().values() if k.section == section) \
                + sliding.get(section, ()):
            kinds = used.get(key.name + key.section)
            only = f"{', '.join(kinds)} only; " if kinds and len(kinds) < len(shapes()) else ""
            valid = key.valid_text()
            if key.name == "shape" and section == "impactor":
                valid = ", ".join(f"`{s}`" for s in shapes())
            rows.append(f"| `{key.name}` | {_unit_column(key)} | {only}{key.default_text()} "
                        f"| {valid} | {key.doc} |")
    return "\n".join(rows)
