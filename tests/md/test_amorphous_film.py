"""Amorphous films on crystalline substrates (`md.amorphous_film`, `md.structures`,
`md.film_relax`).

Oracles from outside the routines under test: diamond's bond length a sqrt(3) / 4 from the
potential's lattice constant (1.544 Angstrom for Tersoff's diamond), the film's density from
the carbon mass, its atom count and the box computed here, brute-force distances over the
lateral periodic images, the strain from the block's and the box's edges, and the refusal of
a stack no registry potential covers before any LAMMPS work. Real LAMMPS: a 64-atom block
quenched in seconds (machinery, not physics) and the relaxation of an 808-atom a-C on
diamond(001) slab (about 30 s on one core)."""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from ase.neighborlist import neighbor_list

from filmscale.core.errors import InputError
from filmscale.md import film_relax
from filmscale.md.amorphous import recipe_from_mapping
from filmscale.md.amorphous_film import DEFAULT_GAP, AmorphousBlock, AmorphousLayer
from filmscale.md.amorphous_run import (analyze_amorphous, read_block, run_amorphous,
                                        write_amorphous_record)
from filmscale.md.indentation import indentation_input
from filmscale.md.lammps_input import check_input
from filmscale.md.spec import load_spec, spec_from_mapping
from filmscale.md.structures import Crystal, SlabLayer, SlabSpec, build_slab
from filmscale.potentials import get_potential

CARBON_KG = 12.011 * 1.66053906660e-27      # the mass of a carbon atom, kg
ANGSTROM = 1e-10
#: no two atoms of a joined slab closer than this (the block's own closest pair is 1.34 A)
MIN_JOINED = 1.2 * ANGSTROM
TINY = {"potential": {"name": "SiC_tersoff"}, "n_atoms": 64, "density": 3000.0,
        "melt_time": 2e-13, "quench_rate": 1e16, "relax_time": 1e-13, "seed": 7}
#: four diamond cells (14.26 A) laterally, four along z; a 1 nm film; 0.36 nm fixed
SLAB = {"lateral_size": 1.43e-9, "fixed_thickness": 3.6e-10, "thermostat_thickness": 3.6e-10}
FILM, SUBSTRATE = 1.0e-9, 1.43e-9


@pytest.fixture(scope="module")
def unit(tmp_path_factory):
    """A quenched 64-atom block and its record, as `filmscale md amorphous` leaves them."""
    run = run_amorphous(recipe_from_mapping(dict(TINY)), tmp_path_factory.mktemp("block"))
    write_amorphous_record(run, analyze_amorphous(run))
    return run.run_dir


def diamond_on(block: AmorphousBlock, **changes) -> SlabSpec:
    a = get_potential("SiC_tersoff").lattice["C"][1]
    return SlabSpec(films=(AmorphousLayer(block, FILM),),
                    substrate=SlabLayer(Crystal("C", "diamond", a), SUBSTRATE),
                    **{**SLAB, **changes})


def closest_pair(positions: np.ndarray, Lx: float, Ly: float) -> float:
    """The smallest distance over every pair and every lateral image (brute force)."""
    best = math.inf
    for dx in (-Lx, 0.0, Lx):
        for dy in (-Ly, 0.0, Ly):
            d = positions[:, None, :] - (positions[None, :, :] + [dx, dy, 0.0])
            r = np.sqrt((d ** 2).sum(axis=2))
            if dx == dy == 0.0:
                r[np.diag_indices(len(positions))] = math.inf
            best = min(best, r.min())
    return best


@pytest.mark.parametrize("element", ["C", "Si"])
@pytest.mark.parametrize("orientation", ["001", "110", "111"])
def test_diamond_cells_have_four_bonds_of_a_sqrt3_over_4(element, orientation):
    a = get_potential("SiC_tersoff").lattice[element][1]
    cell = Crystal(element, "diamond", a).unit_cell(orientation)
    atoms = cell.repeat((3, 3, 3))
    i, d = neighbor_list("id", atoms, 0.5 * a / ANGSTROM)
    bond = a * math.sqrt(3) / 4 / ANGSTROM
    assert np.bincount(i, minlength=len(atoms)).tolist() == [4] * len(atoms)
    assert d == pytest.approx(bond, abs=1e-6)
    assert len(atoms) * 8 == pytest.approx(atoms.get_volume() / (a / ANGSTROM) ** 3 * 64)
    if element == "C":
        assert bond == pytest.approx(1.544, abs=1e-3)        # Tersoff's diamond, a = 3.566 A


def test_film_keeps_the_block_density_and_thickness_on_a_true_diamond(unit):
    block = read_block(unit)
    slab = build_slab(diamond_on(block))
    Lx, Ly = (b / ANGSTROM for b in slab.box[:2])
    z = slab.atoms.positions[:, 2]
    substrate = z <= slab.layer_tops[-1] / ANGSTROM + 1e-9
    film = slab.atoms.positions[~substrate]
    # the strain: two block edges over four diamond cells; z keeps the volume
    edge = block.box[0] / ANGSTROM
    assert slab.misfit[0] == pytest.approx((Lx / (2 * edge) - 1, Ly / (2 * edge) - 1))
    # density: carbon mass over the film's volume (box area times the thickness asked)
    block_density = block.n_atoms * CARBON_KG / np.prod(block.box)
    film_density = len(film) * CARBON_KG / (Lx * Ly * FILM / ANGSTROM * ANGSTROM ** 3)
    print(f"block {block_density:.1f} kg/m^3, film {film_density:.1f} kg/m^3, "
          f"{len(film)} atoms, strain {slab.misfit[0]}")
    assert film_density == pytest.approx(block_density, rel=0.05)
    # thickness as asked; the lowest film atom DEFAULT_GAP above the substrate's highest
    assert film[:, 2].max() - film[:, 2].min() == pytest.approx(FILM / ANGSTROM, abs=1.0)
    assert film[:, 2].max() - film[:, 2].min() < FILM / ANGSTROM
    assert film[:, 2].min() - z[substrate].max() == pytest.approx(DEFAULT_GAP / ANGSTROM)
    # the substrate is diamond: four bonds of 1.544 A each, except on its two surfaces
    sub = slab.atoms[substrate]
    i, d = neighbor_list("id", sub, 1.8)
    assert d == pytest.approx(3.566 * math.sqrt(3) / 4, abs=1e-6)
    inner = (sub.positions[:, 2] > 0.5) & (sub.positions[:, 2] < sub.positions[:, 2].max() - 0.5)
    assert np.all(np.bincount(i, minlength=len(sub))[inner] == 4)
    assert closest_pair(slab.atoms.positions, Lx, Ly) >= MIN_JOINED / ANGSTROM
    assert slab.surface_layer_gap == pytest.approx((np.prod(block.box) / block.n_atoms) ** (1 / 3))


def test_the_spec_file_route_and_its_indentation_input(unit, tmp_path):
    table = {"name": "aC-on-diamond", "potential": {"name": "SiC_tersoff"},
             "slab": {"orientation": "001", **SLAB,
                      "films": [{"structure": "amorphous", "block": unit.name,
                                 "thickness": FILM}],
                      "substrate": {"element": "C", "thickness": SUBSTRATE}},
             "indenter": {"shape": "sphere", "radius": 4e-10},
             "protocol": {"depth": 2e-10, "timestep": 1e-15}}
    spec = spec_from_mapping(table, unit.parent)      # the block relative to the spec file
    assert spec.slab.films[0].block == read_block(unit / "amorphous.h5")
    assert spec.slab.substrate.crystal.structure == "diamond"      # the registry's lattice
    text = check_input(indentation_input(spec))
    assert "pair_coeff * * " in text and "# unloading done" in text
    json.dumps(spec.to_dict(), default=str)                        # as run.state holds it


def test_uncovered_stacks_and_misfit_blocks_are_refused_before_lammps(unit, monkeypatch):
    monkeypatch.setattr(film_relax, "run_input", lambda *a, **k: pytest.fail("LAMMPS ran"))
    table = {"name": "aC-on-Cu", "potential": {"name": "SiC_tersoff"},
             "slab": {"films": [{"structure": "amorphous", "block": str(unit),
                                 "thickness": FILM}],
                      "substrate": {"element": "Cu", "structure": "fcc", "a": 3.615e-10,
                                    "thickness": 1.5e-9}},
             "indenter": {"radius": 4e-10}, "protocol": {"depth": 2e-10}}
    with pytest.raises(InputError) as err:
        spec_from_mapping(table)
    message = str(err.value)
    print(message)
    assert "\n" not in message
    for words in ("films[0] amorphous C", "substrate fcc Cu", "'SiC_tersoff'", "not Cu",
                  "no potential of the registry covers them all"):
        assert words in message
    # a block quenched with another potential
    block = read_block(unit)
    airebo = get_potential("CH_airebo")
    other = AmorphousBlock("C", block.positions, block.box, airebo.name, airebo.sha256)
    table["slab"]["substrate"] = {"element": "C", "thickness": SUBSTRATE}
    from filmscale.md.indentation import IndentSpec
    spec = spec_from_mapping({**table, "slab": {**table["slab"], "films": [], **SLAB}})
    with pytest.raises(InputError, match=re.escape(
            "films[0].block = the block was quenched with potential 'CH_airebo', not with "
            "'SiC_tersoff'")):
        IndentSpec(spec.name, spec.potential, diamond_on(other), spec.indenter, spec.protocol)
    # a box the block fits only with a large strain: 1.07 nm over one 0.75 nm block
    with pytest.raises(InputError, match=r"films\[0\]: the block's edge .* strain of \+0\.42"):
        build_slab(diamond_on(block, lateral_size=1.07e-9))
    with pytest.raises(InputError, match=re.escape("gap = 0 m is outside")):
        AmorphousLayer(block, FILM, gap=0.0)


def test_relaxed_film_stays_bonded_to_diamond(unit, tmp_path):
    spec = diamond_on(read_block(unit))
    slab = build_slab(spec)
    result = film_relax.relax_slab(slab, get_potential("SiC_tersoff"), spec.elements,
                                   tmp_path / "relax", anneal_time=5e-13)
    print(result.to_dict())
    atoms = result.slab.atoms
    built = slab.atoms.positions
    substrate = built[:, 2] <= slab.layer_tops[-1] / ANGSTROM + 1e-9
    # the fixed bottom did not move; nothing flew off (every atom within 2 A of the top
    # as built, none without a neighbour within 1.85 A)
    fixed = built[:, 2] < slab.z_fixed / ANGSTROM
    assert atoms.positions[fixed] == pytest.approx(built[fixed], abs=1e-9)
    assert atoms.positions[:, 2].max() < built[:, 2].max() + 2.0
    assert result.isolated == 0
    # interface bonds: film-substrate pairs within 1.85 A, counted here by brute force
    Lx, Ly = (b / ANGSTROM for b in slab.box[:2])
    d = atoms.positions[substrate][:, None, :] - atoms.positions[~substrate][None, :, :]
    d[..., 0] -= Lx * np.round(d[..., 0] / Lx)
    d[..., 1] -= Ly * np.round(d[..., 1] / Ly)
    bonds = int(np.count_nonzero(np.sqrt((d ** 2).sum(axis=2)) < 1.85))
    assert bonds == result.interface_bonds >= 8
    assert result.interface_bonds > result.interface_bonds_built
    assert result.energy_relaxed < result.energy_built
    assert closest_pair(atoms.positions, Lx, Ly) > MIN_JOINED / ANGSTROM


def test_the_films_elastic_constants_are_its_blocks(unit):
    """`md indent` on an amorphous film compares its Hertz fit with the block's constants:
    the record's C, and a Voigt average written here within the block's small anisotropy."""
    import h5py

    from filmscale.md.amorphous_run import block_elastic_constants
    elastic = block_elastic_constants(read_block(unit))
    with h5py.File(unit / "amorphous.h5") as f:
        C = f["elastic/C"][()]
    assert elastic.structure == "amorphous" and np.array_equal(elastic.C, C)
    K = (C[0, 0] + C[1, 1] + C[2, 2] + 2 * (C[0, 1] + C[0, 2] + C[1, 2])) / 9
    G = (C[0, 0] + C[1, 1] + C[2, 2] - (C[0, 1] + C[0, 2] + C[1, 2])
         + 3 * (C[3, 3] + C[4, 4] + C[5, 5])) / 15
    E_voigt, nu_voigt = 9 * K * G / (3 * K + G), (3 * K - 2 * G) / (2 * (3 * K + G))
    assert elastic.average.E == pytest.approx(E_voigt, rel=0.05)
    assert elastic.E_star == pytest.approx(elastic.average.E / (1 - elastic.average.nu**2))
    assert elastic.average.nu == pytest.approx(nu_voigt, abs=0.03)


@pytest.mark.slow
def test_md_indent_runs_on_an_amorphous_film(unit, tmp_path, capsys):
    """`filmscale md indent` on a 1 nm film of the block on diamond(001) (808 atoms, about
    80 s): the run finishes and compares its Hertz fit with the block's own E*."""
    import tomli_w

    from filmscale.md.amorphous_run import block_elastic_constants
    from filmscale.workflows.cli import main
    table = {"name": "aC-on-diamond", "potential": {"name": "SiC_tersoff"},
             "slab": {"orientation": "001", **SLAB,
                      "films": [{"structure": "amorphous", "block": str(unit),
                                 "thickness": FILM}],
                      "substrate": {"element": "C", "thickness": SUBSTRATE}},
             "indenter": {"shape": "sphere", "radius": 4e-10},
             "protocol": {"depth": 2e-10, "timestep": 1e-15}}
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(table))
    assert main(["md", "indent", str(tmp_path / "spec.toml"), "--out", str(tmp_path / "run"),
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["E_star"] == pytest.approx(block_elastic_constants(read_block(unit)).E_star)
    assert d["P_max"] > 0 and d["n_atoms"] > 500


def test_a_scratch_slab_repeats_the_film_without_a_seam(unit):
    """`md scratch` lengthens the slab along x by whole periods of every layer: for the film
    the edge of its block as tiled. Twice the slab holds twice its atoms, and no pair across
    the new seams comes closer than the joined slab's own closest pair allows."""
    from filmscale.md.scratch import elongated_slab
    spec = diamond_on(read_block(unit))
    slab = build_slab(spec)
    longer = elongated_slab(spec, slab, 2 * slab.box[0])
    assert longer.box[0] == pytest.approx(2 * slab.box[0], rel=1e-9)
    assert longer.n_atoms == 2 * slab.n_atoms
    Lx, Ly = (float(x) / ANGSTROM for x in longer.box[:2])
    assert closest_pair(longer.atoms.positions, Lx, Ly) >= MIN_JOINED / ANGSTROM


@pytest.mark.slow
def test_md_scratch_of_an_amorphous_film_damages_it_under_the_tip_only(unit, tmp_path, capsys):
    """`filmscale md scratch` on the film (3 030 atoms, 0.2 nm deep, 0.8 nm; about 3 min):
    against the equilibrated sample, the film's damage lies under the tip (measured: 0.69 nm
    of the 2.14 nm box, 0.34 nm deep) and the diamond below is untouched; against the
    as-built slab the whole film read as damaged (its cut surfaces rebond)."""
    import tomli_w

    from filmscale.workflows.cli import main
    table = {"name": "aC-scratch", "potential": {"name": "SiC_tersoff"},
             "slab": {"orientation": "001", "lateral_size": 2.14e-9, "length": 3.6e-9,
                      "fixed_thickness": 3.6e-10, "thermostat_thickness": 3.6e-10,
                      "films": [{"structure": "amorphous", "block": str(unit),
                                 "thickness": FILM}],
                      "substrate": {"element": "C", "thickness": SUBSTRATE}},
             "indenter": {"shape": "sphere", "radius": 4e-10},
             "protocol": {"timestep": 1e-15},
             "scratch": {"depth": "0.2 nm", "length": "0.8 nm", "speed": "100 m/s"}}
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(table))
    assert main(["md", "scratch", str(tmp_path / "spec.toml"), "--out", str(tmp_path / "run"),
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    film, substrate = d["damage"]
    assert 0 < film["width"] < 0.6 * 2.14e-9 and film["depth"] < FILM
    assert substrate["width"] == 0.0
    assert math.isfinite(d["friction_mean"]) and d["normal_force_mean"] > 0


@pytest.mark.parametrize("name", ["aC_on_diamond.toml", "aC_on_diamond_quick.toml",
                                  "aC_on_diamond_closure.toml"])
def test_the_shipped_amorphous_specs_load(name):
    """The docs run these files (docs/amorphous.md): each loads as an amorphous film on
    diamond under a sphere, its film a recipe's."""
    spec = load_spec(Path(__file__).resolve().parents[2] / "examples" / "md" / name)
    film = spec.slab.films[0]
    assert film.recipe is not None and film.recipe.element == "C"
    assert spec.indenter.tip.spec.startswith("sphere:")
