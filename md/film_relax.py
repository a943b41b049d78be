"""Relaxing a joined slab (films on a substrate, `md.structures.build_slab`) in LAMMPS.

The input (``in.relax``, replayable in its run directory) holds the bottom ``z_fixed`` of
the slab rigid and relaxes the rest in four steps: a minimisation of the slab as built (the
cut surfaces and the interface), ``anneal_time`` of dynamics at ``temperature`` (Langevin
thermostat on every mobile atom, NVE integration), `COOL_STEPS` of damped dynamics at 0 K
(a Langevin thermostat, time constant `COOL_DAMPING`), and a final minimisation. What comes
back (`FilmRelaxation`, SI) is the relaxed `Slab` (its surface height moved by the mean
displacement of the atoms of its top layer) and how well the layers hold together: the
bonds across the top of the substrate (atom pairs closer than ``bond_cutoff``, one atom
of the substrate as built and one of the films), the atoms with no neighbour within
``bond_cutoff`` and the largest displacement.

The indentation run relaxes a slab by itself (its minimisation and equilibration); this is
the check that a film stays bonded, and a relaxed slab can be handed to an indentation spec
as ``slab_built``.
"""

from __future__ import annotations

import dataclasses
import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from ase.io import write as ase_write
from ase.neighborlist import neighbor_list

from filmscale import __version__
from filmscale.core.checks import check_int, check_real
from filmscale.md.engine import EngineOptions, LammpsError, run_input
from filmscale.md.indentation import derive_seeds, lammps_number
from filmscale.md.lammps_input import write_input
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.md.structures import Slab
from filmscale.potentials import Potential

DATA_FILE, DUMP_FILE, INPUT_FILE = "slab.data", "relaxed.lammpstrj", "in.relax"
#: the damped dynamics that takes the annealed slab to 0 K before the last minimisation
COOL_STEPS, COOL_DAMPING = 1000, 5e-14
#: the minimisations, capped: conjugate gradients crawl on an amorphous film (on an 808-atom
#: a-C on diamond slab, 2000 iterations took 43 s and stopped at the cap, not the tolerance);
#: the damped dynamics before the last one does the relaxing
MINIMIZE = "minimize 0 1e-6 200 2000"
#: C-C bond length cutoff of the bond counts, m (as `md.amorphous.BOND_CUTOFF`)
BOND_CUTOFF = 1.85e-10
_ENERGY = re.compile(r"^(BUILT|RELAXED) ([-+\deE.]+)$", re.M)


@dataclass(frozen=True)
class FilmRelaxation:
    """A relaxed slab and how it holds together, SI (module docstring)."""

    slab: Slab
    energy_built: float         #: J per atom after the first minimisation
    energy_relaxed: float       #: J per atom at the end
    interface_bonds: int        #: pairs closer than bond_cutoff across the substrate's top
    interface_bonds_built: int  #: the same count as built
    isolated: int               #: atoms with no neighbour within bond_cutoff
    max_displacement: float     #: m, in-plane wrapped
    z_max: float                #: height of the highest atom, m
    bond_cutoff: float
    run_dir: Path
    wall_time: float

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in (
            "energy_built", "energy_relaxed", "interface_bonds", "interface_bonds_built",
            "isolated", "max_displacement", "z_max", "bond_cutoff", "wall_time")}


def relax_input(slab: Slab, potential: Potential, elements: tuple[str, ...], *,
                temperature: float, anneal_steps: int, timestep: float, damping: float,
                seed: int) -> str:
    """The LAMMPS input of the relaxation (module docstring); ``elements`` of the atom
    types 1, 2, ..."""
    seeds = derive_seeds(seed, ("velocity", "anneal", "cool"))
    z_fixed = lammps_number(si_to_lammps(slab.z_fixed, "length"))
    lines = [
        f"# filmscale {__version__} relaxation of a joined slab: {slab.n_atoms} atoms, "
        f"{potential.name}; master seed {seed}",
        "units metal", "atom_style atomic", "boundary p p m",
        f"read_data {DATA_FILE}", *potential.pair_commands(elements),
        "neighbor 2.0 bin", "neigh_modify delay 0 every 1 check yes",
        f"timestep {lammps_number(si_to_lammps(timestep, 'time'))}",
        f"region fixed block INF INF INF INF INF {z_fixed} units box",
        "group fixed region fixed", "group mobile subtract all fixed",
        "fix freeze fixed setforce 0.0 0.0 0.0",
        "thermo_style custom step temp pe", "thermo 100", "thermo_modify flush yes",
        "# the slab as built: cut surfaces and interface", MINIMIZE,
        'print "BUILT $(pe/atoms:%.12g)"', "reset_timestep 0",
        "fix integrate mobile nve",
    ]
    if anneal_steps and temperature > 0:
        lines += [f"velocity mobile create {lammps_number(2.0 * temperature)} "
                  f"{seeds['velocity']} mom yes rot no dist gaussian",
                  f"fix anneal mobile langevin {lammps_number(temperature)} "
                  f"{lammps_number(temperature)} "
                  f"{lammps_number(si_to_lammps(damping, 'time'))} {seeds['anneal']} zero yes",
                  f"run {anneal_steps}", "unfix anneal"]
    lines += [f"fix cool mobile langevin 0 0 "
              f"{lammps_number(si_to_lammps(COOL_DAMPING, 'time'))} {seeds['cool']} zero yes",
              f"run {COOL_STEPS}", "unfix cool", "unfix integrate", MINIMIZE,
              'print "RELAXED $(pe/atoms:%.12g)"',
              f"write_dump all custom {DUMP_FILE} id x y z modify sort id "
              "format float %.12g"]
    return "\n".join(lines) + "\n"


def _read_positions(path: Path, n: int) -> np.ndarray:
    """Positions (A, sorted by id) of the dump."""
    lines = path.read_text().splitlines()
    head = next(i for i, x in enumerate(lines) if x.startswith("ITEM: ATOMS"))
    data = np.loadtxt(lines[head + 1:], ndmin=2)
    if len(data) != n:
        raise LammpsError(f"{path.name} holds {len(data)} atoms, not {n}", path.parent)
    return data[np.argsort(data[:, 0]), 1:4]


def interface_bonds(atoms, substrate: np.ndarray, cutoff: float) -> tuple[int, int]:
    """(pairs closer than ``cutoff`` (m) with one atom of ``substrate`` (a mask) and one not,
    atoms with no neighbour within ``cutoff``); ``atoms`` in A."""
    i, j = neighbor_list("ij", atoms, si_to_lammps(cutoff, "length"))
    across = int(np.count_nonzero(substrate[i] & ~substrate[j]))
    return across, int(len(atoms) - len(np.unique(i)))


def relax_slab(slab: Slab, potential: Potential, elements: tuple[str, ...],
               run_dir: Path | str, engine: EngineOptions = EngineOptions(), *,
               temperature: float = 300.0, anneal_time: float = 1e-12,
               timestep: float = 1e-15, damping: float = 1e-13, seed: int = 1,
               bond_cutoff: float = BOND_CUTOFF) -> FilmRelaxation:
    """Relax ``slab`` (`relax_input`) in ``run_dir``; ``elements`` are the slab spec's
    (`SlabSpec.elements`, the atom types' order); temperature K, times s, bond_cutoff m."""
    check_real("temperature", temperature, low=0.0, high=3000.0, unit="K")
    check_real("anneal_time", anneal_time, low=0.0, high=1e-9, unit="s")
    check_real("timestep", timestep, low=1e-17, high=2e-15, unit="s")
    check_real("damping", damping, low=1e-14, high=1e-11, unit="s")
    check_real("bond_cutoff", bond_cutoff, low=1e-10, high=3e-10, unit="m")
    seed = check_int("seed", seed, 1, 2**31 - 1)
    run_dir = Path(run_dir).resolve()
    run_dir.mkdir(parents=True, exist_ok=True)
    ase_write(run_dir / DATA_FILE, slab.atoms, format="lammps-data", specorder=list(elements),
              masses=True, units="metal", atom_style="atomic")
    write_input(run_dir / INPUT_FILE, relax_input(
        slab, potential, elements, temperature=temperature,
        anneal_steps=round(anneal_time / timestep), timestep=timestep, damping=damping,
        seed=seed))
    started = time.perf_counter()
    log = run_input(INPUT_FILE, run_dir, engine, log_name="log.relax")
    wall = time.perf_counter() - started
    energies = dict(_ENERGY.findall(log))
    if set(energies) != {"BUILT", "RELAXED"}:
        raise LammpsError("log.relax lacks its BUILT and RELAXED energies", run_dir)

    atoms = slab.atoms.copy()
    new = _read_positions(run_dir / DUMP_FILE, len(atoms))
    box = np.asarray(atoms.cell.lengths())
    new[:, :2] = np.mod(new[:, :2], box[:2])
    delta = new - atoms.positions
    delta[:, :2] -= box[:2] * np.round(delta[:, :2] / box[:2])
    gap = si_to_lammps(slab.surface_layer_gap, "length")
    top = atoms.positions[:, 2] > si_to_lammps(slab.z_surface, "length") - 0.5 * gap
    atoms.positions = new
    relaxed = dataclasses.replace(
        slab, atoms=atoms,
        z_surface=slab.z_surface + float(lammps_to_si(delta[top, 2].mean(), "length")))
    substrate = slab.atoms.positions[:, 2] <= si_to_lammps(slab.layer_tops[-1], "length")
    built_bonds, _ = interface_bonds(slab.atoms, substrate, bond_cutoff)
    bonds, isolated = interface_bonds(atoms, substrate, bond_cutoff)
    return FilmRelaxation(
        slab=relaxed, energy_built=float(lammps_to_si(float(energies["BUILT"]), "energy")),
        energy_relaxed=float(lammps_to_si(float(energies["RELAXED"]), "energy")),
        interface_bonds=bonds, interface_bonds_built=built_bonds, isolated=isolated,
        max_displacement=float(lammps_to_si(np.linalg.norm(delta, axis=1).max(), "length")),
        z_max=float(lammps_to_si(new[:, 2].max(), "length")), bond_cutoff=bond_cutoff,
        run_dir=run_dir, wall_time=wall)
