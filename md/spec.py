"""Indentation run specs from TOML tables, and the named presets.

A spec file (SI units throughout)::

    name = "cu-film-on-ni"
    [potential]
    name = "CuNi"                 # a registry entry; or file = "...", elements = [...], ...
    [slab]
    orientation = "001"
    lateral_size = 5.5e-9         # m
    [[slab.films]]                # top film first
    element = "Cu"                # structure and a default to the potential's own lattice
    thickness = 2.0e-9
    [slab.substrate]
    element = "Ni"
    thickness = 3.2e-9
    [indenter]
    shape = "sphere"              # or "cone" (half_angle in degrees, tip_radius in m)
    radius = 1.5e-9
    [protocol]
    depth = 8e-10
    speed = 100.0                 # m/s

An amorphous film is cut from the record of ``filmscale md amorphous`` (its potential must be
the spec's)::

    [[slab.films]]
    structure = "amorphous"
    block = "md_runs/md-amorphous-0123456789abcdef"   # the unit, or its amorphous.h5
    thickness = 1.0e-9            # m, cut to this height
    gap = 1.5e-10                 # m, above the highest atom below (default)

or names the recipe that makes its block (made, or reused, in a store before the run)::

    [[slab.films]]
    structure = "amorphous"
    recipe = "ci"                 # an `md amorphous` preset, or a recipe file
    density = "3.0 g/cm3"         # optional: the recipe at this density (and seed = ...)
    thickness = 1.0e-9

Presets: ``ci`` (the test suite's run, seconds), ``quick`` (a few-nm Cu film on Ni: a
Hertzian segment, a pop-in and an unloading within minutes on 2 cores) and ``research``
(sizes for a study, meant for MPI on many cores).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from filmscale.core.checks import (check_keys, check_path, check_table, preset_table,
                                   required)
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.md.amorphous_film import DEFAULT_GAP, AmorphousLayer
from filmscale.md.indentation import IndentProtocol, IndentSpec, RigidIndenter
from filmscale.md.structures import Crystal, SlabLayer, SlabSpec
from filmscale.potentials import Potential
from filmscale.potentials.lammps_words import check_element, shown
from filmscale.potentials.registry import potential_from_mapping

PRESETS: dict[str, dict] = {
    "ci": {
        "name": "ci-cu001",
        "potential": {"name": "Cu_mishin1"},
        "slab": {"orientation": "001", "lateral_size": 3.7e-9, "films": [],
                 "substrate": {"element": "Cu", "thickness": 2.2e-9}},
        "indenter": {"shape": "sphere", "radius": 8e-10},
        "protocol": {"depth": 4e-10, "speed": 200.0, "timestep": 4e-15,
                     "equilibration_time": 4e-13, "hold_time": 2e-13, "record_every": 5,
                     "restart_every": 200, "seed": 2026},
    },
    "quick": {
        "name": "quick-cu-on-ni001",
        "potential": {"name": "CuNi"},
        "slab": {"orientation": "001", "lateral_size": 5.5e-9,
                 "films": [{"element": "Cu", "thickness": 2.2e-9}],
                 "substrate": {"element": "Ni", "thickness": 2.8e-9}},
        "indenter": {"shape": "sphere", "radius": 1.5e-9},
        "protocol": {"depth": 8e-10, "speed": 100.0, "timestep": 4e-15,
                     "equilibration_time": 1e-12, "hold_time": 1e-12, "record_every": 10,
                     "restart_every": 1000, "seed": 2026,
                     "dump_depths": [2e-10, 4e-10, 6e-10]},
    },
    "research": {
        "name": "research-cu-on-ni001",
        "potential": {"name": "CuNi"},
        "slab": {"orientation": "001", "lateral_size": 2.0e-8,
                 "fixed_thickness": 1e-9, "thermostat_thickness": 1e-9,
                 "films": [{"element": "Cu", "thickness": 5e-9}],
                 "substrate": {"element": "Ni", "thickness": 1e-8}},
        "indenter": {"shape": "sphere", "radius": 4e-9},
        "protocol": {"depth": 2e-9, "speed": 20.0, "timestep": 2e-15,
                     "equilibration_time": 1e-11, "hold_time": 1e-11, "record_every": 20,
                     "thermo_every": 500, "restart_every": 10000, "seed": 2026,
                     "dump_depths": [5e-10, 1e-9, 1.5e-9]},
    },
}


def _crystal(where: str, table: dict, potential: Potential) -> SlabLayer:
    table = check_keys(where, table, {"element", "structure", "a", "c", "thickness"})
    element = check_element(f"{where}.element", required(where, table, "element"))
    required(where, table, "thickness")
    hint = potential.lattice.get(element)
    structure = table.get("structure", hint[0] if hint else None)
    a = table.get("a", hint[1] if hint else None)
    if structure is None or a is None:
        raise InputError(f"{where}: give structure and a for {shown(element)}: potential "
                         f"{potential.name} has no lattice for it")
    return SlabLayer(Crystal(element, structure, a, table.get("c")), table["thickness"])


def _film(where: str, table: dict, potential: Potential, base_dir: Path | None):
    """A film: a crystal, or ``structure = "amorphous"`` with ``thickness`` and ``gap`` (m)
    and either ``block`` (the record of `filmscale md amorphous`, or its unit folder;
    relative to the spec file) or ``recipe`` (an `md amorphous` preset or a recipe file,
    with ``density`` and ``seed`` to change the recipe's: the block is made in a store
    before the run, `workflows.amorphous_units`)."""
    if not isinstance(table, dict) or table.get("structure") != "amorphous":
        return _crystal(where, table, potential)
    table = check_keys(where, table, {"structure", "block", "recipe", "density", "seed",
                                      "thickness", "gap"})
    if ("block" in table) == ("recipe" in table):
        raise InputError(f"{where}: an amorphous film takes block (a made block's record) or "
                         "recipe (a preset or recipe file, made before the run), one of them")
    thickness, gap = required(where, table, "thickness"), table.get("gap", DEFAULT_GAP)
    if "recipe" in table:
        return AmorphousLayer.named_by(_recipe(where, table, base_dir), thickness, gap)
    if {"density", "seed"} & set(table):
        raise InputError(f"{where}: density and seed change a recipe; a made block has its own")
    block = table["block"]
    if not isinstance(block, str):
        raise InputError(f"{where}.block = {shown(block)} must be the path of an "
                         "amorphous-block record")
    from filmscale.md.amorphous_run import read_block    # h5py and scipy only for a film
    path = Path(block) if base_dir is None else Path(base_dir) / block
    return AmorphousLayer(read_block(path), thickness, gap)


def _recipe(where: str, table: dict, base_dir: Path | None):
    """The recipe a film names: a preset of `md amorphous` or a recipe file (relative to
    the spec file), at the film's ``density`` (kg/m^3, or a quantity) and ``seed``."""
    from filmscale.core.quantities import to_si
    from filmscale.md.amorphous import PRESETS as RECIPES, amorphous_preset, load_recipe
    name = table["recipe"]
    if not isinstance(name, str):
        raise InputError(f"{where}.recipe = {shown(name)} must be a preset "
                         f"({', '.join(RECIPES)}) or a recipe file")
    path = Path(name) if base_dir is None else Path(base_dir) / name
    if name not in RECIPES and not path.is_file():
        raise InputError(f"{where}.recipe = {name!r} is neither a preset ({', '.join(RECIPES)})"
                         f" nor a recipe file ({path} is not a file)")
    recipe = amorphous_preset(name) if name in RECIPES else load_recipe(path)
    changes = {}
    if "density" in table:
        changes["density"] = to_si(f"{where}.density", table["density"], "kg/m^3")
    if "seed" in table:
        changes["seed"] = table["seed"]
    return replace(recipe, **changes) if changes else recipe


def spec_from_mapping(data: dict, base_dir: Path | None = None) -> IndentSpec:
    """An `IndentSpec` from a TOML-like mapping (see the module docstring)."""
    data = check_keys("spec", data, {"name", "potential", "slab", "indenter", "protocol"})
    for key in ("name", "potential", "slab", "indenter", "protocol"):
        required("spec", data, key)
    potential = potential_from_mapping(check_table("potential", data["potential"]), base_dir)
    slab = dict(check_table("slab", data["slab"]))
    films = slab.pop("films", [])
    if not isinstance(films, list):
        raise InputError("slab.films must be an array of tables ([[slab.films]])")
    substrate = _crystal("slab.substrate", required("slab", slab, "substrate"), potential)
    del slab["substrate"]
    check_keys("slab", slab, {"orientation", "lateral_size", "fixed_thickness",
                              "thermostat_thickness", "vacuum", "films", "substrate"})
    layers = tuple(_film(f"slab.films[{i}]", f, potential, base_dir)
                   for i, f in enumerate(films))
    slab_spec = SlabSpec(films=layers, substrate=substrate, **slab)
    indenter = dict(check_table("indenter", data["indenter"]))
    shape = indenter.pop("shape", "sphere")
    if shape == "sphere":
        check_keys("indenter", indenter, {"radius", "K"})
        required("indenter", indenter, "radius")
        indenter = RigidIndenter.sphere(**indenter)
    elif shape == "cone":
        check_keys("indenter", indenter, {"half_angle", "tip_radius", "K", "height"})
        indenter = RigidIndenter.cone(**indenter)
    else:
        raise InputError(f"indenter.shape = {shown(shape)} must be sphere or cone")
    protocol = dict(check_table("protocol", data["protocol"]))
    check_keys("protocol", protocol, set(IndentProtocol.__dataclass_fields__))
    required("protocol", protocol, "depth")
    try:
        proto = IndentProtocol(**protocol)
    except TypeError as exc:
        raise InputError(f"protocol: {exc}") from None
    return IndentSpec(str(data["name"]), potential, slab_spec, indenter, proto)


def load_spec(path: Path | str) -> IndentSpec:
    """Read a spec file; relative potential files are found beside it."""
    path = check_path("path", path)
    data = read_toml(path, "spec file")     # bounded: size, text, nesting
    return spec_from_mapping(data, path.parent)


def preset(name: str) -> IndentSpec:
    """The named preset's spec."""
    return spec_from_mapping(preset_table(PRESETS, name))
