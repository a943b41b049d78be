"""Amorphous blocks by melt-quench: the recipe (SI), its presets and its LAMMPS inputs.

A recipe names the element (carbon), a potential of the registry, the target density and the
number of atoms; the cubic periodic box follows from them and stays fixed throughout, as in the
liquid-quench practice of de Tomas, Suarez-Martinez & Marks (Carbon 109, 681 (2016)): the
density is set, not found. The run has four stages, each its own LAMMPS input that starts from
the restart file of the stage before (so that a killed run restarts at the stage it was in,
and an interrupted run gives the very numbers of an uninterrupted one):

1. ``melt``: atoms placed at random with no two closer than `MIN_DISTANCE` (random
   sequential addition in Python from the recipe's seed), a short minimisation that removes
   the largest forces, then the liquid at ``melt_temperature`` for ``melt_time`` (Langevin
   thermostat, NVE integration: NVT at fixed volume);
2. ``quench``: the thermostat's target ramps linearly from the melt to ``temperature`` at
   ``quench_rate`` (K/s);
3. ``anneal``: ``anneal_time`` at ``anneal_temperature``, a cooling back to ``temperature``
   at the quench rate, then ``relax_time`` at ``temperature``;
4. ``final``: a minimisation at fixed box (0 K) that gives the energy per atom and the
   residual stress, the final positions, and the elastic constants of the block at that
   box: the twelve +-strain states of `md.elastic` (its own strain commands), each
   re-minimised at fixed box.

Seeds (positions, velocities and each stage's thermostat) derive from the master seed
(`md.indentation.derive_seeds`). The Langevin thermostat draws its random numbers per MPI
rank: a recipe is reproducible to the last digit on the same number of ranks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np
from ase import Atoms
from ase.data import atomic_masses, atomic_numbers

from filmscale.core.checks import (check_int, check_keys, check_path, check_real, check_table,
                                   preset_table)
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.core.quantities import to_si
from filmscale.md.elastic import MINIMIZE as ELASTIC_MINIMIZE, elastic_input
from filmscale.md.indentation import derive_seeds, lammps_number
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.potentials import Potential
from filmscale.potentials.lammps_words import shown
from filmscale.potentials.registry import potential_from_mapping

#: the elements a block is built of (the coordination analysis names carbon's hybridizations)
ELEMENTS = ("C",)
#: the density range accepted, kg/m^3: from porous a-C to just above diamond (3515)
DENSITY_RANGE = (1000.0, 3600.0)
#: the closest two atoms are placed at random, m: random sequential addition of 1.3 A
#: spheres jams at a packing fraction near 0.38; at 3.6 g/cm3 this asks for 0.21
MIN_DISTANCE = 1.3e-10
#: C-C bond cutoff of the coordination count, m (de Tomas et al. 2016 use 1.85 Angstrom)
BOND_CUTOFF = 1.85e-10
#: the stages, in order, and the file each leaves for the next
STAGES = ("melt", "quench", "anneal", "final")
DATA_FILE = "start.data"
FINAL_DUMP = "final.lammpstrj"
RECORD_COLUMNS = ("step", "time", "temp", "pe", "press")
#: rows of the temperature-energy-pressure record over the whole run (about)
RECORD_ROWS = 500
#: the relaxation of the final block and of each strained state (`relax_lines`)
RELAX_STEPS, RELAX_DAMPING, RELAX_CG = 1000, 5e-14, 100
#: the longest run accepted, steps (a recipe past it is a unit slip in a time or rate)
MAX_STEPS = 200_000_000


@dataclass(frozen=True)
class AmorphousRecipe:
    """A melt-quench recipe, SI: density kg/m^3, temperatures K, times and timestep s,
    quench_rate K/s, damping (the Langevin time constant) s, bond_cutoff m; strain the
    +-amplitude of the elastic-constant states; seed the master seed."""

    potential: Potential
    element: str = "C"
    density: float = 3000.0
    n_atoms: int = 512
    melt_temperature: float = 6000.0
    melt_time: float = 2e-12
    quench_rate: float = 1e15
    anneal_temperature: float = 300.0
    anneal_time: float = 0.0
    temperature: float = 300.0
    relax_time: float = 1e-12
    timestep: float = 1e-15
    damping: float = 1e-13
    seed: int = 2026
    strain: float = 1e-3
    bond_cutoff: float = BOND_CUTOFF
    name: str = field(default="amorphous", compare=False)

    def __post_init__(self):
        if not isinstance(self.potential, Potential):
            raise InputError(f"potential = {shown(self.potential)} must be a Potential")
        if self.element not in ELEMENTS:
            raise InputError(f"element = {shown(self.element)} is not one of "
                             f"{', '.join(ELEMENTS)} (amorphous blocks are built of carbon)")
        if self.element not in self.potential.elements:
            raise InputError(f"element = {shown(self.element)} is not in potential "
                             f"{self.potential.name!r}, which has "
                             f"{', '.join(self.potential.elements)}")
        if self.potential.units != "metal":
            raise InputError(f"potential {self.potential.name!r} is in {self.potential.units}"
                             " units; amorphous blocks run in metal units")
        check_real("density", self.density, low=DENSITY_RANGE[0], high=DENSITY_RANGE[1],
                   unit="kg/m^3")
        object.__setattr__(self, "n_atoms", check_int("n_atoms", self.n_atoms, 64, 1_000_000))
        check_real("temperature", self.temperature, low=1.0, high=1000.0, unit="K")
        check_real("melt_temperature", self.melt_temperature, low=2000.0, high=20000.0,
                   unit="K")
        check_real("anneal_temperature", self.anneal_temperature, low=self.temperature,
                   high=self.melt_temperature, unit="K")
        check_real("melt_time", self.melt_time, low=1e-13, high=1e-8, unit="s")
        check_real("quench_rate", self.quench_rate, low=1e10, high=1e16, unit="K/s")
        check_real("anneal_time", self.anneal_time, low=0.0, high=1e-8, unit="s")
        check_real("relax_time", self.relax_time, low=0.0, high=1e-8, unit="s")
        check_real("timestep", self.timestep, low=1e-17, high=2e-15, unit="s")
        check_real("damping", self.damping, low=1e-14, high=1e-11, unit="s")
        object.__setattr__(self, "seed", check_int("seed", self.seed, 1, 2**31 - 1))
        check_real("strain", self.strain, low=1e-4, high=1e-2)
        check_real("bond_cutoff", self.bond_cutoff, low=1e-10, high=3e-10, unit="m")
        if self.schedule().total > MAX_STEPS:
            raise InputError(f"the recipe takes {self.schedule().total} steps, more than "
                             f"{MAX_STEPS}: check melt_time, anneal_time, relax_time, "
                             f"quench_rate = {self.quench_rate:g} K/s and timestep = "
                             f"{self.timestep:g} s")

    @property
    def atom_mass(self) -> float:
        """Mass of one atom, kg."""
        return float(lammps_to_si(atomic_masses[atomic_numbers[self.element]], "mass"))

    @property
    def box_edge(self) -> float:
        """Edge of the cubic box that holds n_atoms at the density, m."""
        return (self.n_atoms * self.atom_mass / self.density) ** (1.0 / 3.0)

    def schedule(self) -> Schedule:
        dt = self.timestep
        cool = math.ceil((self.anneal_temperature - self.temperature) /
                         (self.quench_rate * dt)) if self.anneal_time > 0 else 0
        return Schedule(
            melt=max(1, round(self.melt_time / dt)),
            quench=max(1, math.ceil((self.melt_temperature - self.temperature) /
                                    (self.quench_rate * dt))),
            anneal=round(self.anneal_time / dt),
            cool=cool, relax=round(self.relax_time / dt))

    def seeds(self) -> dict[str, int]:
        return derive_seeds(self.seed, ("positions", "velocity", *STAGES[:3]))

    def to_dict(self) -> dict:
        """The recipe as the unit's hash and the record hold it: the potential by name,
        style and checksum (not by path, so that a hash survives a move)."""
        d = {f.name: getattr(self, f.name) for f in fields(self)
             if f.name not in ("potential", "name")}
        pot = self.potential
        d["potential"] = {"name": pot.name, "sha256": pot.sha256, "pair_style": pot.pair_style,
                          "pair_coeff": pot.pair_coeff, "elements": list(pot.elements)}
        return d


@dataclass(frozen=True)
class Schedule:
    """Steps of each segment: melt, quench, anneal (at the anneal temperature), cool (back to
    the final temperature) and relax (at it)."""

    melt: int
    quench: int
    anneal: int
    cool: int
    relax: int

    @property
    def total(self) -> int:
        return self.melt + self.quench + self.anneal + self.cool + self.relax

    def stage_end(self, stage: str) -> int:
        """The timestep at the end of ``stage`` (the final stage runs no dynamics)."""
        ends = {"melt": self.melt, "quench": self.melt + self.quench}
        return ends.get(stage, self.total)

    @property
    def record_every(self) -> int:
        return max(1, self.total // RECORD_ROWS)


# ---- the starting positions -------------------------------------------------------------------

def random_positions(recipe: AmorphousRecipe) -> np.ndarray:
    """n_atoms positions (Angstrom) in the cubic box, uniformly at random with none closer
    than `MIN_DISTANCE` (periodic images included): random sequential addition, each trial
    point drawn from the recipe's positions seed."""
    rng = np.random.default_rng(recipe.seeds()["positions"])
    L = si_to_lammps(recipe.box_edge, "length")
    d2 = si_to_lammps(MIN_DISTANCE, "length") ** 2
    placed = np.empty((recipe.n_atoms, 3))
    n, tries = 0, 0
    while n < recipe.n_atoms:
        tries += 1
        if tries > 1000 * recipe.n_atoms:
            raise InputError(f"density = {recipe.density:g} kg/m^3 leaves no room to place "
                             f"{recipe.n_atoms} atoms {MIN_DISTANCE:g} m apart")
        p = rng.uniform(0.0, L, 3)
        delta = placed[:n] - p
        delta -= L * np.round(delta / L)
        if n == 0 or np.min(np.einsum("ij,ij->i", delta, delta)) >= d2:
            placed[n] = p
            n += 1
    return placed


def start_atoms(recipe: AmorphousRecipe) -> Atoms:
    """The random start as ASE atoms (Angstrom), for the LAMMPS data file."""
    L = si_to_lammps(recipe.box_edge, "length")
    atoms = Atoms([recipe.element] * recipe.n_atoms, positions=random_positions(recipe),
                  cell=[L, L, L], pbc=True)
    atoms.set_masses([atomic_masses[atomic_numbers[recipe.element]]] * recipe.n_atoms)
    return atoms


# ---- the LAMMPS inputs ------------------------------------------------------------------------

def _head(recipe: AmorphousRecipe, stage: str, source: str, version: str) -> list[str]:
    s = recipe.schedule()
    read = (f"read_data {source}" if source.endswith(".data") else f"read_restart {source}")
    return [
        f"# filmscale {version} amorphous block, stage {stage}: {recipe.n_atoms} "
        f"{recipe.element} atoms at {recipe.density:g} kg/m^3 with {recipe.potential.name}; "
        f"master seed {recipe.seed}".replace("  ", " "),
        "units metal", "atom_style atomic", "boundary p p p", read,
        *recipe.potential.pair_commands([recipe.element]),
        "neighbor 2.0 bin", "neigh_modify delay 0 every 1 check yes",
        f"timestep {lammps_number(si_to_lammps(recipe.timestep, 'time'))}",
        "thermo_style custom step time temp pe press",
        f"thermo {s.record_every}", "thermo_modify flush yes",
    ]


def _record(stage: str, every: int) -> str:
    values = "$(step) $(time:%.10g) $(temp:%.8g) $(pe/atoms:%.12g) $(press:%.8g)"
    return (f'fix record all print {every} "{values}" file {stage}.dat screen no '
            f'title "# {" ".join(RECORD_COLUMNS)}"')


def _thermostat(recipe: AmorphousRecipe, start: float, stop: float, seed: int) -> str:
    damp = lammps_number(si_to_lammps(recipe.damping, "time"))
    return (f"fix thermostat all langevin {lammps_number(start)} {lammps_number(stop)} "
            f"{damp} {seed} zero yes")


def stage_input(recipe: AmorphousRecipe, stage: str, version: str = "") -> str:
    """The LAMMPS input of one stage (replayable with ``lmp -in`` in the run directory)."""
    s, seeds = recipe.schedule(), recipe.seeds()
    T, Tm, Ta = recipe.temperature, recipe.melt_temperature, recipe.anneal_temperature
    source = DATA_FILE if stage == "melt" else f"{STAGES[STAGES.index(stage) - 1]}.restart"
    lines = _head(recipe, stage, source, version)
    if stage == "final":
        return final_input(recipe, source, version)
    lines += ["fix integrate all nve", _record(stage, s.record_every)]
    if stage == "melt":
        lines += ["# push apart the closest random neighbours before the dynamics",
                  "minimize 0 1e-3 200 2000", "reset_timestep 0",
                  f"velocity all create {lammps_number(Tm)} {seeds['velocity']} mom yes "
                  "rot no dist gaussian",
                  _thermostat(recipe, Tm, Tm, seeds["melt"]), f"run {s.melt}"]
    elif stage == "quench":
        lines += [f"# linear quench {Tm:g} K -> {T:g} K at {recipe.quench_rate:g} K/s",
                  _thermostat(recipe, Tm, T, seeds["quench"]), f"run {s.quench}"]
    else:
        if s.anneal:
            lines += [_thermostat(recipe, Ta, Ta, seeds["anneal"]), f"run {s.anneal}",
                      "unfix thermostat"]
        if s.cool:
            lines += [_thermostat(recipe, Ta, T, seeds["anneal"] + 1), f"run {s.cool}",
                      "unfix thermostat"]
        lines += [_thermostat(recipe, T, T, seeds["anneal"] + 2), f"run {s.relax}"]
    lines.append(f"write_restart {stage}.restart")
    return "\n".join(lines) + "\n"


def final_input(recipe: AmorphousRecipe, source: str, version: str = "") -> str:
    """The final stage's input on the block of ``source`` (the anneal's restart file, or
    any block as a ``.data`` file: a crystal for a check of the elastic route)."""
    return "\n".join(_head(recipe, "final", source, version) + final_lines(recipe)) + "\n"


def relax_lines(recipe: AmorphousRecipe) -> list[str]:
    """Relaxation at fixed box: `RELAX_STEPS` of damped dynamics (a Langevin thermostat at
    0 K, time constant `RELAX_DAMPING`), then at most `RELAX_CG` conjugate-gradient
    iterations. Conjugate gradients alone crawl on an amorphous block (Tersoff's cutoff
    function makes the landscape rough): on the ci block they stopped at force norms of
    1e-3 eV/A after 400-8900 iterations each (565 s for the thirteen states), where this
    gives E within 0.1 % of the longest relaxation tried in 16 s."""
    damp = lammps_number(si_to_lammps(RELAX_DAMPING, "time"))
    return ["fix integrate all nve",
            f"fix damp all langevin 0 0 {damp} {recipe.seeds()['anneal']} zero yes",
            f"run {RELAX_STEPS}", "unfix damp", "unfix integrate",
            f"minimize 0 1e-12 {RELAX_CG} {10 * RELAX_CG}"]


def final_lines(recipe: AmorphousRecipe) -> list[str]:
    """Relax at fixed box (`relax_lines`), print the energy per atom and the pressure tensor
    (FINAL), dump the positions, then the twelve strained states of `md.elastic` (its strain
    commands and STATE lines, each state relaxed by `relax_lines` instead of its
    minimisation; the box edges as its LATTICE line)."""
    states = elastic_input(recipe.potential, recipe.element, strain=recipe.strain)
    marker = "change_box all triclinic\n"
    if marker not in states or states.count(ELASTIC_MINIMIZE) != 14:
        raise RuntimeError("md.elastic's input no longer has its strained states after "
                           f"{marker.strip()!r}, each relaxed by {ELASTIC_MINIMIZE!r}")
    relax = relax_lines(recipe)
    strained = []
    for line in states.split(marker, 1)[1].strip().split("\n"):
        strained += relax if line == ELASTIC_MINIMIZE else [line]
    pressures = " ".join(f"$({p}:%.12g)" for p in ("pxx", "pyy", "pzz", "pyz", "pxz", "pxy"))
    return [
        "thermo_style custom step pe press pxx pyy pzz pyz pxz pxy",
        "# 0 K at the fixed box: energy per atom and residual stress", *relax,
        f'print "FINAL $(pe/atoms:%.12g) {pressures}"',
        f"write_dump all custom {FINAL_DUMP} id type x y z modify sort id",
        'print "LATTICE $(lx:%.12g) $(ly:%.12g) $(lz:%.12g)"',
        "# the elastic constants at this box: md.elastic's strained states",
        marker.strip(), *strained,
    ]


# ---- recipes from files and presets -----------------------------------------------------------

PRESETS: dict[str, dict] = {
    # 512 atoms, 2 ps of liquid, 5.7 ps of quench at 1e15 K/s, 1 ps at 300 K
    "ci": {"name": "ci-aC", "potential": {"name": "SiC_tersoff"}, "n_atoms": 512,
           "density": 3000.0, "melt_temperature": 6000.0, "melt_time": 2e-12,
           "quench_rate": 1e15, "relax_time": 1e-12, "timestep": 1e-15},
    # 4096 atoms, 10x slower quench, an anneal at 1500 K
    "quick": {"name": "quick-aC", "potential": {"name": "SiC_tersoff"}, "n_atoms": 4096,
              "density": 3000.0, "melt_temperature": 6000.0, "melt_time": 5e-12,
              "quench_rate": 1e14, "anneal_temperature": 1500.0, "anneal_time": 5e-12,
              "relax_time": 5e-12, "timestep": 1e-15},
    # 32768 atoms as de Tomas et al. 2016, 1e13 K/s (for SLURM)
    "research": {"name": "research-aC", "potential": {"name": "SiC_tersoff"},
                 "n_atoms": 32768, "density": 3000.0, "melt_temperature": 6000.0,
                 "melt_time": 2e-11, "quench_rate": 1e13, "anneal_temperature": 1500.0,
                 "anneal_time": 2e-11, "relax_time": 2e-11, "timestep": 1e-15},
}
#: the keys of a recipe file (SI numbers, or quantities with units where a unit is given)
QUANTITIES = {"density": "kg/m^3", "melt_time": "s", "quench_rate": "K/s", "anneal_time": "s",
              "relax_time": "s", "timestep": "s", "damping": "s", "bond_cutoff": "m"}
KEYS = {"name", "potential", "element", "n_atoms", "melt_temperature", "anneal_temperature",
        "temperature", "seed", "strain", *QUANTITIES}


def recipe_from_mapping(data: dict, base_dir: Path | None = None) -> AmorphousRecipe:
    """An `AmorphousRecipe` from a TOML-like mapping: a ``[potential]`` table (a registry
    ``name``, or a user file as in an indentation spec; SiC_tersoff when absent) and the
    recipe's fields at the top level, each a number in SI or, for those of `QUANTITIES`, a
    quantity with units ("3.0 g/cm3", "2 ps")."""
    data = dict(check_keys("recipe", data, KEYS))
    table = check_table("potential", data.pop("potential", {"name": "SiC_tersoff"}))
    potential = potential_from_mapping(table, base_dir)
    for key, unit in QUANTITIES.items():
        if key in data:
            data[key] = to_si(key, data[key], unit)
    name = data.pop("name", "amorphous")
    if not isinstance(name, str):
        raise InputError(f"name = {shown(name)} must be text")
    return AmorphousRecipe(potential=potential, name=name, **data)


def load_recipe(path: Path | str) -> AmorphousRecipe:
    """Read a recipe file (TOML); a relative potential file is found beside it."""
    path = check_path("path", path)
    return recipe_from_mapping(read_toml(path, "recipe file"), path.parent)


def amorphous_preset(name: str) -> AmorphousRecipe:
    return recipe_from_mapping(preset_table(PRESETS, name))


def with_density(recipe: AmorphousRecipe, density: float) -> AmorphousRecipe:
    """The recipe at another density (kg/m^3), checked as any recipe."""
    return replace(recipe, density=density)
