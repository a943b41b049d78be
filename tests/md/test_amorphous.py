"""`filmscale md amorphous`: amorphous carbon blocks by melt-quench.

Oracles from outside the routines under test: a brute-force neighbour count over explicit
periodic images (diamond: every atom sp3; graphite: every atom sp2; a random start: the same
counts atom by atom), the density of the box computed here from the carbon mass, the closed
form of an isotropic stiffness, md.elastic's own route (box relaxed, minimised states) on a
diamond crystal, the refusals of bad recipes before any LAMMPS work, and the reproducibility
of a run from its seed, interrupted or not. Real LAMMPS: a tiny recipe (a few seconds), the ci
preset through the command line with the store's reuse (about 25 s on one core), the diamond
check (a few seconds); the three-density sp3 trend is `slow` (about 60 s)."""

import json
import math
import re

import numpy as np
import pytest
from ase.build import bulk
from ase.lattice.hexagonal import Graphite

from filmscale.core.errors import InputError
from filmscale.md import amorphous_run
from filmscale.md.amorphous import (MIN_DISTANCE, PRESETS, STAGES, AmorphousRecipe,
                                    amorphous_preset, random_positions, recipe_from_mapping,
                                    stage_input, with_density)
from filmscale.md.amorphous_run import (block_elastic, coordination, elastic_of_block,
                                        hybridization, radial_distribution, run_amorphous)
from filmscale.md.elastic import elastic_input, parse_states
from filmscale.md.lammps_input import check_input
from filmscale.potentials import get_potential
from filmscale.workflows.cli import main

CARBON_KG = 12.011 * 1.66053906660e-27      # the mass of a carbon atom, kg
ANGSTROM = 1e-10
#: a recipe of 64 atoms that runs in seconds (not physics: a check of the machinery)
TINY = {"potential": {"name": "SiC_tersoff"}, "n_atoms": 64, "density": 3000.0,
        "melt_time": 2e-13, "quench_rate": 1e16, "relax_time": 1e-13, "seed": 7}


def brute_force_counts(positions: np.ndarray, cell: np.ndarray, cutoff: float) -> np.ndarray:
    """Neighbours within ``cutoff`` of each atom, every periodic image within +-2 cells tried
    one by one (no minimum image, no tree)."""
    counts = np.zeros(len(positions), int)
    shifts = [np.array([i, j, k]) @ cell for i in range(-2, 3) for j in range(-2, 3)
              for k in range(-2, 3)]
    for a, p in enumerate(positions):
        for b, q in enumerate(positions):
            for s in shifts:
                d = np.linalg.norm(q + s - p)
                if 1e-12 < d < cutoff:
                    counts[a] += 1
    return counts


def test_diamond_is_all_sp3_and_graphite_all_sp2():
    diamond = bulk("C", "diamond", a=3.567, cubic=True).repeat(2)
    graphite = Graphite("C", latticeconstant={"a": 2.46, "c": 6.70}, size=(2, 2, 1))
    for atoms, kind in ((diamond, "sp3"), (graphite, "sp2")):
        cell = np.asarray(atoms.cell)
        expected = brute_force_counts(atoms.positions, cell, 1.85)
        assert np.all(expected == (4 if kind == "sp3" else 3))
        if kind == "sp3":       # the routine takes an orthogonal box
            found = coordination(atoms.positions * ANGSTROM, np.diag(cell) * ANGSTROM,
                                 1.85 * ANGSTROM)
            assert np.array_equal(found, expected)
            assert hybridization(found)["sp3"] == 1.0
    # graphite's hexagonal cell as an orthogonal one: the rectangular 1 x sqrt(3) cell
    ortho = Graphite("C", latticeconstant={"a": 2.46, "c": 6.70}, size=(2, 2, 1),
                     directions=[[2, -1, -1, 0], [0, 1, -1, 0], [0, 0, 0, 1]])
    box = np.diag(np.asarray(ortho.cell))
    found = coordination(np.mod(ortho.positions, box) * ANGSTROM, box * ANGSTROM,
                         1.85 * ANGSTROM)
    assert np.array_equal(found, brute_force_counts(ortho.positions, np.asarray(ortho.cell),
                                                    1.85))
    assert hybridization(found) == {"sp3": 0.0, "sp2": 1.0, "sp": 0.0, "other": 0.0}


def test_random_start_counts_match_the_brute_force_and_keep_their_distance():
    recipe = recipe_from_mapping(dict(TINY))
    positions = random_positions(recipe)
    L = recipe.box_edge / ANGSTROM
    counts = brute_force_counts(positions, np.eye(3) * L, 2.2)
    found = coordination(positions * ANGSTROM, np.full(3, L * ANGSTROM), 2.2 * ANGSTROM)
    assert np.array_equal(found, counts) and counts.sum() > 0
    assert np.all(brute_force_counts(positions, np.eye(3) * L, MIN_DISTANCE / ANGSTROM) == 0)
    # the box holds the target density: 64 carbon atoms over L^3
    assert 64 * CARBON_KG / (L * ANGSTROM) ** 3 == pytest.approx(3000.0, rel=1e-4)


def test_radial_distribution_of_diamond_starts_at_its_bond_length():
    atoms = bulk("C", "diamond", a=3.567, cubic=True).repeat(4)
    r, g = radial_distribution(atoms.positions * ANGSTROM,
                               np.diag(np.asarray(atoms.cell)) * ANGSTROM)
    box = np.diag(np.asarray(atoms.cell)) * ANGSTROM
    assert r[np.nonzero(g)[0][0]] == pytest.approx(3.567 * math.sqrt(3) / 4 * ANGSTROM,
                                                   abs=2e-12)
    # the first shell holds the four bonds: rho * integral of g 4 pi r^2 dr up to 1.85 A
    rho = len(atoms) / np.prod(box)
    width = r[1] - r[0]
    first = r < 1.85 * ANGSTROM
    assert rho * np.sum(g[first] * 4 * math.pi * r[first] ** 2) * width == \
        pytest.approx(4.0, rel=0.01)


def test_isotropic_stiffness_gives_its_own_E_and_nu():
    E, nu = 700e9, 0.15
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[range(3), range(3)] = lam + 2 * mu
    C[range(3, 6), range(3, 6)] = mu
    el = block_elastic(C)
    assert el.E == pytest.approx(E, rel=1e-12) and el.nu == pytest.approx(nu, rel=1e-12)
    assert el.E_std == pytest.approx(0, abs=1e-3) and el.nu_std == pytest.approx(0, abs=1e-12)
    assert el.axial_spread == pytest.approx(0, abs=1e-12)
    assert el.shear_ratio == pytest.approx(1, rel=1e-12)


@pytest.mark.parametrize("change, words", [
    ({"density": 900.0}, "density = 900 kg/m^3 is outside the valid range [1000, 3600]"),
    ({"density": 3700.0}, "density = 3700 kg/m^3 is outside the valid range [1000, 3600]"),
    ({"element": "Si"}, "element = 'Si' is not one of C"),
    ({"potential": {"name": "Cu_mishin1"}}, "element = 'C' is not in potential 'Cu_mishin1'"),
    ({"melt_temperature": 1500.0}, "melt_temperature = 1500 K is outside"),
    ({"quench_rate": 1e20}, "quench_rate = 1e+20 K/s is outside"),
    ({"n_atoms": 10}, "n_atoms = 10 is outside the valid range [64, 1e+06]"),
    ({"anneal_temperature": 100.0}, "anneal_temperature = 100 K is outside"),
    ({"colour": "red"}, "unknown key recipe.colour"),
    ({"density": "3 GPa"}, "density = '3 GPa' is not a density"),
])
def test_bad_recipes_are_refused_naming_the_parameter(change, words):
    with pytest.raises(InputError, match=re.escape(words)):
        recipe_from_mapping({**TINY, **change})


def test_the_command_refuses_before_any_lammps_work(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(amorphous_run, "run_input", lambda *a, **k: pytest.fail("LAMMPS ran"))
    for args in (["--density", "0.9g/cm3"], ["--density", "3.7 g/cm3"],
                 ["--density", "3 GPa"], ["--preset", "fast"]):
        preset = [] if "--preset" in args else ["--preset", "ci"]
        code = main(["md", "amorphous", *preset, *args, "--out", str(tmp_path / "store")])
        err = capsys.readouterr().err.strip()
        assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "store").exists()


def test_every_stage_input_passes_the_input_check():
    for name in PRESETS:
        recipe = amorphous_preset(name)
        for stage in STAGES:
            check_input(stage_input(recipe, stage))
    assert with_density(amorphous_preset("ci"), 2000.0).density == 2000.0


def test_tiny_run_is_reproducible_and_restarts_at_its_stage(tmp_path, monkeypatch):
    recipe = recipe_from_mapping(dict(TINY))
    first = run_amorphous(recipe, tmp_path / "a")
    # a second directory, killed as it starts the anneal, then run again
    real = amorphous_run.run_input
    stages_run = []

    def killed(input_file, *args, **kwargs):
        stages_run.append(input_file)
        if input_file == "in.anneal" and stages_run.count("in.anneal") == 1:
            raise KeyboardInterrupt
        return real(input_file, *args, **kwargs)

    monkeypatch.setattr(amorphous_run, "run_input", killed)
    with pytest.raises(KeyboardInterrupt):
        run_amorphous(recipe, tmp_path / "b")
    second = run_amorphous(recipe, tmp_path / "b")
    assert stages_run == ["in.melt", "in.quench", "in.anneal", "in.anneal", "in.final"]
    assert np.array_equal(first.positions, second.positions)
    assert first.energy_per_atom == second.energy_per_atom
    assert np.array_equal(first.stresses, second.stresses)
    # a finished directory is read back without LAMMPS
    monkeypatch.setattr(amorphous_run, "run_input", lambda *a, **k: pytest.fail("LAMMPS ran"))
    assert run_amorphous(recipe, tmp_path / "b").energy_per_atom == first.energy_per_atom


def test_elastic_route_on_diamond_matches_md_elastic(tmp_path):
    """The block's route (fixed box, damped relaxation) against md.elastic's (box relaxed,
    states minimised to 1e-12 eV/A), both on a 64-atom Tersoff diamond."""
    potential = get_potential("SiC_tersoff")
    a = potential.lattice["C"][1] / ANGSTROM
    diamond = bulk("C", "diamond", a=a, cubic=True).repeat(2)
    recipe = AmorphousRecipe(potential=potential)
    ours, final = elastic_of_block(recipe, diamond, tmp_path / "block")

    from ase.io import write
    from filmscale.md.engine import run_input
    from filmscale.md.lammps_input import write_input
    from filmscale.continuum.elasticity import stiffness_from_stress_strain
    folder = tmp_path / "elastic"
    folder.mkdir()
    write(folder / "crystal.data", diamond, format="lammps-data", specorder=["C"],
          masses=True, units="metal", atom_style="atomic")
    write_input(folder / "in.elastic", elastic_input(potential, "C", strain=1e-3))
    strains, stresses, _ = parse_states(run_input("in.elastic", folder))
    theirs = stiffness_from_stress_strain(strains, stresses).C
    c = lambda C: np.array([C[:3, :3].diagonal().mean(),                   # noqa: E731
                            np.mean([C[0, 1], C[0, 2], C[1, 2]]), C[3:, 3:].diagonal().mean()])
    print("C11, C12, C44 (GPa): block route", c(ours.C) / 1e9, "md.elastic", c(theirs) / 1e9)
    assert c(ours.C) == pytest.approx(c(theirs), rel=0.01)
    assert abs(final["pressure"]).max() < 1e8        # the relaxed lattice: near zero stress


def test_ci_block_through_the_command_and_its_reuse(tmp_path, monkeypatch, capsys):
    store = tmp_path / "store"
    assert main(["md", "amorphous", "--preset", "ci", "--density", "3.0g/cm3", "--out",
                 str(store), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    units = [p for p in store.iterdir() if p.is_dir()]
    assert len(units) == 1 and out["unit"] == str(units[0]) and not out["reused"]
    import h5py
    with h5py.File(out["result"], "r") as f:
        box = f["block/box"][()]
        n = len(f["block/positions"])
        C = f["elastic/C"][()]
    assert n * CARBON_KG / np.prod(box) == pytest.approx(3000.0, rel=0.01)
    assert out["density"] == pytest.approx(3000.0, rel=0.01)
    assert 0 < out["sp3_fraction"] < 1 and 0 < out["sp2_fraction"] < 1
    assert out["sp3_fraction"] + out["sp2_fraction"] + out["sp_fraction"] <= 1
    assert 100e9 < out["E"] < 1200e9 and 0 < out["nu"] < 0.5 and out["E_std"] > 0
    # isotropic within 10 %: C11 ~ C22 ~ C33 and C44 ~ (C11 - C12)/2
    axial, shear = C.diagonal()[:3], C.diagonal()[3:]
    assert np.all(abs(axial / axial.mean() - 1) < 0.10)
    assert np.all(abs(shear / (0.5 * (axial.mean() - np.mean([C[0, 1], C[0, 2], C[1, 2]])))
                      - 1) < 0.10)
    # the same recipe again: the unit is reused, LAMMPS does not run
    monkeypatch.setattr(amorphous_run, "run_input", lambda *a, **k: pytest.fail("LAMMPS ran"))
    assert main(["md", "amorphous", "--preset", "ci", "--out", str(store), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["reused"] and again["unit"] == out["unit"]
    assert {k: again[k] for k in ("density", "sp3_fraction", "E")} == \
        {k: out[k] for k in ("density", "sp3_fraction", "E")}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["store"]


@pytest.mark.slow
def test_sp3_fraction_rises_with_density(tmp_path):
    found = []
    for density in (2000.0, 2600.0, 3200.0):
        recipe = with_density(amorphous_preset("ci"), density)
        run = run_amorphous(recipe, tmp_path / f"d{density:.0f}")
        found.append(amorphous_run.analyze_amorphous(run).fractions["sp3"])
    print("sp3 at 2.0, 2.6, 3.2 g/cm3:", found)
    assert found[0] < found[1] < found[2]


def test_seed_ensemble_is_one_unit_a_seed_and_their_statistics(tmp_path, capsys):
    """`--seeds 3` on the tiny recipe: three units (seeds 7, 8, 9), different blocks, the
    mean and the sample standard deviation over them as written out here; a second call
    reuses all three."""
    import tomli_w
    (tmp_path / "tiny.toml").write_text(tomli_w.dumps(TINY))
    args = ["md", "amorphous", str(tmp_path / "tiny.toml"), "--seeds", "3", "--out",
            str(tmp_path / "store"), "--json"]
    assert main(args) == 0
    d = json.loads(capsys.readouterr().out)
    seeds = d["seeds"]
    assert [s["seed"] for s in seeds] == [7, 8, 9] and not any(s["reused"] for s in seeds)
    assert len({s["unit"] for s in seeds}) == 3
    assert len({s["energy_per_atom"] for s in seeds}) == 3        # three different quenches
    for key in ("E", "sp3_fraction", "density", "residual_stress"):
        values = [s[key] for s in seeds]
        mean = sum(values) / 3
        std = (sum((v - mean) ** 2 for v in values) / 2) ** 0.5
        assert d[key] == pytest.approx(mean, rel=1e-12)
        assert d["ensemble_std"][key] == pytest.approx(std, rel=1e-9, abs=1e-12)
    assert d["E_std"] == d["ensemble_std"]["E"]
    assert main(args) == 0
    assert all(s["reused"] for s in json.loads(capsys.readouterr().out)["seeds"])
    assert main([*args[:-1], "--seeds", "0"]) == 2
