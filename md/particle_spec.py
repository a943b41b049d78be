"""Particle-model run specs from TOML tables, and the named presets.

A spec file (SI units throughout)::

    name = "al6061-sphere"
    method = "tlsph"              # or "peri" (layered, elastic), "ulsph" (layered, plastic)
    tip = "sphere:1um"            # indentation also: "cone:70.3", "berkovich",
                                  # "cube-corner", "sphero-conical:100nm:70.3"
    [target.substrate]
    E = 66.8e9
    nu = 0.33
    sigma_y = 284e6               # leave out for an elastic target
    n = 0.08
    density = 2700                # kg/m^3
    [[target.films]]              # optional, top first (method "peri" or "ulsph")
    thickness = 0.25e-6
    E = 200e9
    nu = 0.25
    density = 3500
    [grid]
    spacing = 1.333e-7            # m
    width = 2e-6                  # m, from the axis to the sides
    depth = 2e-6                  # m, from the surface to the rigid base
    quarter = true                # symmetry planes x = 0 and y = 0 through the axis
    half = false                  # or the one plane x = 0 (what a Berkovich tip allows)
    [loading]                     # indentation
    depth = 1e-7
    speed = 50.0                  # m/s
    hold_time = 0.0
    unload = true                 # false: stop after the hold (loading curvature only)
    [impact]                      # impact
    mass = 2.6e-14                # kg
    velocity = 50.0               # m/s

Presets (the settings `benchmarks/particles_convergence.py` picks; times in the README):
``ci`` (elastic, seconds; 13 % rms against Hertz on the block), ``quick`` (the cheapest
within 5 %: 4.6 %) and ``research`` (3.4 %; 2 % was not reached at the sizes measured).
"""

from __future__ import annotations

import math
from pathlib import Path

from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.checks import check_keys, check_path, check_table, preset_table, required
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.md.particles import (Grid, IndentLoading, ParticleImpactSpec, ParticleIndentSpec,
                                    ParticleMaterial, ParticleTarget)

_AL = {"E": 70e9, "nu": 0.3, "density": 2700.0}
_R = 1e-6


def hertz_mass(depth: float, velocity: float, material: dict, R: float = _R) -> float:
    """Mass (kg) of a rigid sphere of radius R (m) whose elastic Hertz impact at ``velocity``
    (m/s) reaches the approach ``depth`` (m) on ``material`` (E, nu in Pa): the inverse of
    delta_max = (15 m V^2 / (16 E* R^(1/2)))^(2/5) (docs/physics.md section 1)."""
    E_star = material["E"] / (1 - material["nu"]**2)
    return depth**2.5 * 16 * E_star * math.sqrt(R) / (15 * velocity**2)


PRESETS: dict[str, dict[str, dict]] = {
    "indent": {
        "ci": {"name": "ci-elastic-sphere", "method": "tlsph", "tip": "sphere:1um",
               "target": {"substrate": dict(_AL)},
               "grid": {"spacing": _R / 5, "width": 2 * _R, "depth": 2 * _R},
               "loading": {"depth": 0.1 * _R, "speed": 50.0, "frames": 3}},
        "quick": {"name": "quick-elastic-sphere", "method": "tlsph", "tip": "sphere:1um",
                  "target": {"substrate": dict(_AL)},
                  "grid": {"spacing": _R / 10, "width": 2 * _R, "depth": 2 * _R},
                  "loading": {"depth": 0.1 * _R, "speed": 50.0}},
        "research": {"name": "research-elastic-sphere", "method": "tlsph", "tip": "sphere:1um",
                     "target": {"substrate": dict(_AL)},
                     "grid": {"spacing": _R / 12.5, "width": 2 * _R, "depth": 2 * _R},
                     "loading": {"depth": 0.1 * _R, "speed": 50.0}},
    },
    "impact": {
        "ci": {"name": "ci-elastic-impact", "method": "tlsph", "tip": "sphere:1um",
               "target": {"substrate": dict(_AL)},
               "grid": {"spacing": _R / 5, "width": 2 * _R, "depth": 2 * _R},
               "impact": {"mass": hertz_mass(0.1 * _R, 50.0, _AL), "velocity": 50.0,
                          "frames": 3}},
        "quick": {"name": "quick-elastic-impact", "method": "tlsph", "tip": "sphere:1um",
                  "target": {"substrate": dict(_AL)},
                  "grid": {"spacing": _R / 7.5, "width": 2 * _R, "depth": 2 * _R},
                  "impact": {"mass": hertz_mass(0.1 * _R, 50.0, _AL), "velocity": 50.0}},
        "research": {"name": "research-elastic-impact", "method": "tlsph",
                     "tip": "sphere:1um", "target": {"substrate": dict(_AL)},
                     "grid": {"spacing": _R / 12, "width": 3 * _R, "depth": 3 * _R},
                     "impact": {"mass": hertz_mass(0.1 * _R, 50.0, _AL),
                                "velocity": 50.0}},
    },
}

#: The presets' blocks for ``--method peri``: full blocks (no symmetry planes), spacings whose
#: horizon (3 dx) fits in the contact radius at 0.1 R (0.44 R).
PERI_GRIDS = {
    "ci": {"spacing": _R / 8, "width": _R, "depth": 1.5 * _R, "quarter": False},
    "quick": {"spacing": _R / 10, "width": 1.5 * _R, "depth": 1.5 * _R, "quarter": False},
    "research": {"spacing": _R / 14, "width": 2 * _R, "depth": 2 * _R, "quarter": False},
}

_MATERIAL_KEYS = {"name", "E", "nu", "sigma_y", "n", "density"}


def _material(where: str, table: dict) -> ParticleMaterial:
    table = check_keys(where, table,
                       _MATERIAL_KEYS | ({"thickness"} if "films" in where else set()))
    for key in ("E", "nu"):
        if key not in table:
            raise InputError(f"{where}.{key} is missing: a material needs E (Pa) and nu")
    mat = ElasticPlastic(table["E"], table["nu"], table.get("sigma_y", math.inf),
                         table.get("n", 0.0), table.get("name", where))
    return ParticleMaterial(mat, table.get("density", 2700.0))


def _target(table: dict) -> ParticleTarget:
    table = check_keys("target", table, {"substrate", "films"})
    substrate = required("target", table, "substrate")
    films = []
    for k, film in enumerate(table.get("films", [])):
        where = f"target.films[{k}]"
        thickness = required(where, check_table(where, film), "thickness")
        films.append((thickness, _material(where, film)))
    return ParticleTarget(_material("target.substrate", substrate), tuple(films))


def target_from_table(table: dict) -> ParticleTarget:
    """The ``[target]`` table of a spec (substrate, films) as a `ParticleTarget`: what the
    particle scratch spec (`filmscale.md.particle_scratch`) shares with this one."""
    return _target(table)


def spec_from_mapping(data: dict, kind: str) -> ParticleIndentSpec | ParticleImpactSpec:
    """A spec from a parsed TOML table; ``kind`` is ``indent`` or ``impact``."""
    section = "loading" if kind == "indent" else "impact"
    data = check_keys("spec", data, {"name", "method", "tip", "target", "grid", section})
    for key in ("target", "grid", section):
        required("spec", data, key)
    grid = check_keys("grid", data["grid"], {"spacing", "width", "depth", "quarter", "half"})
    for key in ("spacing", "width", "depth"):
        required("grid", grid, key)
    grid = Grid(**grid)
    common = dict(name=str(data.get("name", kind)), method=data.get("method", "tlsph"),
                  target=_target(data["target"]), tip=data.get("tip", "sphere:1um"), grid=grid)
    if kind == "indent":
        body = check_keys("loading", data[section],
                          {"depth", "speed", "hold_time", "frames", "unload"})
        for key in ("depth", "speed"):
            required("loading", body, key)
        return ParticleIndentSpec(loading=IndentLoading(**body), **common)
    body = check_keys("impact", data[section], {"mass", "velocity", "duration", "frames"})
    for key in ("mass", "velocity"):
        required("impact", body, key)
    return ParticleImpactSpec(**common, **body)


def load_spec(path: Path | str, kind: str, method: str | None = None):
    """A spec from a TOML file; ``method`` overrides the file's."""
    path = check_path("path", path)
    data = read_toml(path, "spec file")     # bounded: size, text, nesting
    if method is not None:
        data["method"] = method
    return spec_from_mapping(data, kind)


def preset(name: str, kind: str, method: str | None = None):
    """A named preset (``ci``, ``quick``, ``research``) of ``kind`` (indent or impact)."""
    data = preset_table(PRESETS[kind], name)
    if method is not None:
        data["method"] = method
    if data["method"] == "peri":
        data["grid"].update(PERI_GRIDS[name])
    return spec_from_mapping(data, kind)
