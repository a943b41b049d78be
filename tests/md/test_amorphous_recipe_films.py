"""Films named by their melt-quench recipe (`md.spec`, `md.amorphous_film.AmorphousLayer.
named_by`, `workflows.amorphous_units`) and the scene source of an amorphous overcoat
(`workflows.pipeline_scene`: ``structure = "amorphous"``, ``density``).

Oracles from outside the code under test: the stand-in's atom count and box from the recipe's
density and the carbon mass computed here; the film made from the real block against the
geometry of the stand-in (the same box edges, an atom count within the block's density
noise); one store unit per recipe, counted on disk; the refusals before any LAMMPS work. Real
LAMMPS: a 64-atom block quenched in seconds (machinery, not physics)."""

import json

import pytest
import tomli_w

from filmscale.core.errors import InputError
from filmscale.md.engine import EngineOptions
from filmscale.md.run import run_indentation
from filmscale.md.spec import spec_from_mapping
from filmscale.workflows.amorphous_units import quench_cost_s, with_blocks
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.plan import quenched_recipes

CARBON_KG = 12.011 * 1.66053906660e-27
#: a 64-atom recipe that quenches in seconds
TINY = {"name": "tiny-aC", "potential": {"name": "SiC_tersoff"}, "n_atoms": 64,
        "density": "3.0 g/cm3", "melt_time": "0.2 ps", "quench_rate": 1e16,
        "relax_time": "0.1 ps", "seed": 7}


def spec_table(film: dict) -> dict:
    return {"name": "aC-on-diamond", "potential": {"name": "SiC_tersoff"},
            "slab": {"orientation": "001", "lateral_size": 1.43e-9,
                     "fixed_thickness": 3.6e-10, "thermostat_thickness": 3.6e-10,
                     "films": [{"structure": "amorphous", "thickness": 1.0e-9, **film}],
                     "substrate": {"element": "C", "thickness": 1.43e-9}},
            "indenter": {"shape": "sphere", "radius": 4e-10},
            "protocol": {"depth": 2e-10, "timestep": 1e-15}}


@pytest.fixture
def recipe_file(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(tomli_w.dumps(TINY))
    return path


def test_a_film_named_by_a_preset_recipe_has_its_recipes_geometry_before_the_quench():
    spec = spec_from_mapping(spec_table({"recipe": "ci", "density": "2.6 g/cm3"}))
    film = spec.slab.films[0]
    assert film.recipe.density == pytest.approx(2600.0) and film.recipe.n_atoms == 512
    # the stand-in: 8^3 atoms in the cube that holds 512 carbon atoms at 2.6 g/cm3
    edge = (512 * CARBON_KG / 2600.0) ** (1 / 3)
    assert film.block.stand_in and film.block.n_atoms == 512
    assert film.block.box == pytest.approx([edge] * 3, rel=1e-12)
    assert film.block.density == pytest.approx(2600.0, rel=1e-3)
    # the record and the unit hash hold the recipe, not the stand-in
    slab = spec.to_dict()["slab"]["films"][0]
    assert slab["block"] is None and slab["recipe"]["density"] == pytest.approx(2600.0)
    json.dumps(spec.to_dict(), default=str)


def test_a_run_on_a_stand_in_is_refused_before_lammps(tmp_path):
    spec = spec_from_mapping(spec_table({"recipe": "ci"}))
    with pytest.raises(InputError, match=r"films\[0\] is named by recipe 'ci-aC', whose block "
                                         "is not made yet"):
        run_indentation(spec, tmp_path / "run")
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("film, message", [
    ({"recipe": "ci", "block": "x.h5"}, "takes block .* or recipe .*, one of them"),
    ({}, "takes block .* or recipe .*, one of them"),
    ({"recipe": "ci", "density": "9 g/cm3"}, r"density = 9000 .*1000"),
    ({"recipe": "nope"}, r"recipe = 'nope' is neither a preset \(ci, quick, research\) nor a "
                         "recipe file"),
    ({"block": "x.h5", "density": 3000.0}, "density and seed change a recipe"),
])
def test_bad_amorphous_films_are_refused(film, message):
    with pytest.raises(InputError, match=message):
        spec_from_mapping(spec_table(film))


def test_the_block_is_quenched_once_and_the_film_is_cut_from_it(recipe_file, tmp_path):
    spec = spec_from_mapping(spec_table({"recipe": recipe_file.name}), recipe_file.parent)
    store = tmp_path / "store"
    made = with_blocks(spec, store, EngineOptions(), quiet=True)
    units = sorted(p for p in store.iterdir() if p.is_dir())
    assert [p.name[:13] for p in units] == ["md-amorphous-"]
    film, stand_in = made.slab.films[0], spec.slab.films[0]
    assert not film.block.stand_in and film.recipe == stand_in.recipe
    assert film.block.source == str(units[0] / "amorphous.h5")
    assert film.block.density == pytest.approx(3000.0, rel=1e-9)
    # the stand-in's lateral box; its surface within one mean interatomic spacing (the
    # cut's roughness) and, within the block's own density noise, its atoms
    assert made.slab_built.box[:2] == pytest.approx(spec.slab_built.box[:2], rel=1e-12)
    spacing = (CARBON_KG / 3000.0) ** (1 / 3)
    assert abs(made.slab_built.z_surface - spec.slab_built.z_surface) < spacing
    assert made.slab_built.n_atoms == pytest.approx(spec.slab_built.n_atoms, rel=0.05)
    assert made.to_dict()["slab"]["films"][0]["block"]["sha256"] == film.block.checksum
    # a second spec naming the recipe reuses the unit: no second quench
    again = with_blocks(spec, store, EngineOptions(), quiet=True)
    assert again.slab.films[0].block == film.block
    assert sorted(p for p in store.iterdir() if p.is_dir()) == units
    # a made spec is returned as it is
    assert with_blocks(made, store, EngineOptions(), quiet=True) is made


SCENE = """
title = "a-C overcoat"
[impactor]
radius = 1e-6
mass = 1e-12
velocity = 0.5
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
[[target.layers]]
name = "a-C"
thickness = 3e-9
nu = 0.14
[target.layers.calibrate]
md = "spec.toml"
{keys}
[outputs]
want = ["maxima"]
"""


def scene_with(tmp_path, film: dict, keys: str):
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(spec_table(film)))
    return parse_pipeline(SCENE.format(keys=keys), base=tmp_path)


def test_a_scene_source_quenches_its_overcoat_at_the_density_it_states(tmp_path):
    scene = scene_with(tmp_path, {"recipe": "ci"},
                       'structure = "amorphous"\ndensity = "2.6 g/cm3"\nseeds = 3')
    src = scene.calibrations[0]
    assert src.structure == "amorphous" and src.density == pytest.approx(2600.0)
    members = src.member_specs(tmp_path)
    recipes = [m.slab.films[0].recipe for m in members]
    assert [r.density for r in recipes] == pytest.approx([2600.0] * 3)
    # each member its own quench seed (its own block) and its own MD seed
    assert [r.seed for r in recipes] == [2026, 2027, 2028]
    assert len({m.protocol.seed for m in members}) == 3
    # the plan's cost holds the quench, from the throughput constant and the recipe's steps
    assert quenched_recipes(members[0]) == [recipes[0]]
    steps = recipes[0].schedule().total + 13 * 1000
    assert quench_cost_s(recipes[0], 2) == pytest.approx(512 * steps / (4.9e5 * 2))


@pytest.mark.parametrize("film, keys, message", [
    ({"recipe": "ci"}, 'density = "2.6 g/cm3"', r"density .* give structure = \"amorphous\""),
    ({"recipe": "ci"}, 'structure = "glass"', r"structure = 'glass' is not one of: amorphous"),
    ({"recipe": "ci"}, 'structure = "amorphous"\ndensity = "0.5 g/cm3"',
     r"calibrate.density = 500 .*\[1000, 3600\]"),
])
def test_bad_scene_sources_are_refused_before_any_run(tmp_path, film, keys, message):
    with pytest.raises(InputError, match=message):
        scene_with(tmp_path, film, keys)


def test_structure_amorphous_needs_a_film_named_by_its_recipe(tmp_path):
    table = spec_table({"recipe": "ci"})
    table["slab"]["films"] = [{"element": "C", "thickness": 1.0e-9}]
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(table))
    with pytest.raises(InputError, match=r"top film of the MD spec spec.toml must be amorphous "
                                         "and name its recipe"):
        parse_pipeline(SCENE.format(keys='structure = "amorphous"'), base=tmp_path)



def test_a_scratch_spec_gets_its_block_and_keeps_its_length(recipe_file, tmp_path):
    """`md scratch` on a film named by recipe: the block made in the store, the slab cut from
    it and lengthened along x to the spec's length (whole periods of the block as tiled)."""
    from filmscale.md.scratch import scratch_spec_from_mapping
    table = spec_table({"recipe": recipe_file.name})
    table["slab"].update(lateral_size=2.14e-9, length="3.6 nm")
    del table["protocol"]["depth"]
    table["scratch"] = {"depth": "0.2 nm", "length": "0.8 nm", "speed": "100 m/s"}
    spec = scratch_spec_from_mapping(table, recipe_file.parent)
    made = with_blocks(spec, tmp_path / "store", EngineOptions(), quiet=True)
    film = made.indent.slab.films[0]
    assert not film.block.stand_in and made.stroke == spec.stroke
    assert made.indent.slab_built.box[:2] == pytest.approx(spec.indent.slab_built.box[:2],
                                                            rel=1e-12)
    # the made slab: whole copies of the block's edge along x, as the stand-in's
    edge = film.block.box[0] * (1 + made.indent.slab_built.misfit[0][0])
    copies = made.indent.slab_built.box[0] / edge
    assert copies == pytest.approx(round(copies), abs=1e-6)
