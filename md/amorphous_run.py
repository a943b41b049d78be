"""Running an amorphous block (`md.amorphous`), what it is, and its HDF5 record.

`run_amorphous` runs the four stages of a recipe in a run directory (``in.STAGE``,
``log.STAGE``, ``STAGE.dat``, ``STAGE.restart``, ``state.json``); a stage is done once
``state.json`` says so, and a killed run starts again at the stage it was in, from the
restart file of the one before (every stage reads its start from a restart file, so the
numbers are those of an uninterrupted run). A finished directory is read back without LAMMPS.

`analyze_amorphous` gives, in SI:

- ``density``: the atoms' mass over the box's volume (the box is fixed: this is the target
  up to the rounding of the box edge in the data file);
- ``sp3_fraction``, ``sp2_fraction``, ``sp_fraction``: the fractions of atoms with 4, 3 and
  2 neighbours closer than the recipe's ``bond_cutoff`` (1.85 Angstrom for C-C, as de Tomas,
  Suarez-Martinez & Marks, Carbon 109, 681 (2016)) in the final 0 K block; ``other_fraction``
  the rest (1, 5 or more neighbours);
- the radial distribution function g(r) of the final block;
- ``residual_stress``: the mean normal stress of the 0 K block at its fixed box, minus the
  LAMMPS pressure: positive in tension, negative in compression (Pa); ``stress`` the six
  Voigt components with the same sign;
- ``energy_per_atom``: the potential energy per atom of the 0 K block (J);
- the elastic constants of the block: the least-squares 6x6 C of the twelve +-strain states
  (`continuum.elasticity.stiffness_from_stress_strain`), its Voigt-Reuss-Hill average (Hill,
  Proc. Phys. Soc. A 65, 349 (1952)) for the isotropic ``E``, ``nu``, ``K``, ``G``, and
  their scatter over directions: ``E_std`` the standard deviation of the three directional
  Young's moduli 1/S11, 1/S22, 1/S33, ``nu_std`` that of the six Poisson ratios -S_ij/S_ii
  (S = C^-1); the isotropy of C: ``axial_spread`` (standard deviation of C11, C22, C33 over
  their mean) and ``shear_ratio`` (the mean of C44, C55, C66 over (C11 - C12)/2 with the
  means of the axial and the off-diagonal constants; 1 when isotropic).
"""

from __future__ import annotations

import json
import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from ase.io import write as ase_write
from scipy.spatial import cKDTree

from filmscale import __version__
from filmscale.continuum.elasticity import (IsotropicAverage, stiffness_from_stress_strain,
                                            voigt_reuss_hill)
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_h5, read_json, write_json
from filmscale.core.jsonable import to_jsonable
from filmscale.md.amorphous_film import AmorphousBlock
from filmscale.md.amorphous import (DATA_FILE, FINAL_DUMP, RECORD_COLUMNS, STAGES,
                                    AmorphousRecipe, final_input, stage_input, start_atoms)
from filmscale.md.elastic import ElasticConstants, parse_states
from filmscale.md.engine import EngineOptions, LammpsError, parse_table, run_input
from filmscale.md.lammps_input import write_input
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.md.record import run_provenance, write_attrs

STATE_FILE = "state.json"
RECORD_FORMAT = "filmscale.md_amorphous/1"
RECORD_NAME = "amorphous.h5"
#: the restart file kept once a run is finished: the block at the final temperature, with
#: its velocities (the start of a film cut from it)
KEPT_RESTART = "anneal.restart"
#: the radial distribution function: out to this distance (or half the box), in bins this wide
RDF_RANGE, RDF_BIN = 8e-10, 2e-12
_FINAL = re.compile(r"^FINAL ((?:[-+\deE.]+ ?){7})$", re.M)


@dataclass(frozen=True)
class AmorphousRun:
    """A finished run: the history of the dynamics and the final 0 K block, SI."""

    recipe: AmorphousRecipe
    run_dir: Path
    history: dict            #: step, time (s), temp (K), pe (J per atom), press (Pa)
    energy_per_atom: float   #: J, the 0 K block
    pressure: np.ndarray     #: LAMMPS pressure tensor of the 0 K block, Voigt order, Pa
    positions: np.ndarray    #: (n, 3) of the 0 K block, m, in the box [0, L)
    box: np.ndarray          #: the box edges, m
    strains: np.ndarray      #: (12, 6) Voigt strains of the elastic states
    stresses: np.ndarray     #: (12, 6) their stresses (tension positive), Pa
    stages: dict             #: stage -> its input, wall time
    wall_time: float
    engine: dict = field(default_factory=dict)

    @property
    def n_atoms(self) -> int:
        return len(self.positions)

    @property
    def n_steps(self) -> int:
        return self.recipe.schedule().total

    def inputs(self) -> dict[str, str]:
        return {f"in.{s}": (self.run_dir / f"in.{s}").read_text() for s in STAGES}


def _recipe_dict(recipe: AmorphousRecipe) -> dict:
    return to_jsonable(json.loads(json.dumps(recipe.to_dict())))


def _first_to_run(state: dict, run_dir: Path) -> int:
    """Index of the first stage to run: the first not done, or 0 when the restart file it
    starts from is gone (a stage is then redone from the random start)."""
    done = state["stages"]
    k = next((i for i, s in enumerate(STAGES) if s not in done), len(STAGES))
    if 0 < k < len(STAGES) and not (run_dir / f"{STAGES[k - 1]}.restart").is_file():
        done.clear()
        return 0
    return k


def run_amorphous(recipe: AmorphousRecipe, run_dir: Path | str,
                  engine: EngineOptions = EngineOptions(), *,
                  progress: Callable[[int, int], None] | None = None) -> AmorphousRun:
    """Run ``recipe`` in ``run_dir``, finish it there after an interruption (from the stage
    it was in), or read a finished run back (no LAMMPS). ``progress(step, total)`` reports
    the MD timestep; InputError for a directory that holds another recipe's run."""
    run_dir = Path(run_dir).resolve()
    run_dir.mkdir(parents=True, exist_ok=True)
    state_path = run_dir / STATE_FILE
    spec = _recipe_dict(recipe)
    state = read_json(state_path, "run state") if state_path.exists() else None
    if state is not None and to_jsonable(state.get("recipe")) != spec:
        raise InputError(f"run directory {run_dir} holds the run of another recipe; choose "
                         "another directory")
    if state is None:
        state = {"recipe": spec, "stages": {}, "engine": engine.to_dict()}
    total = recipe.schedule().total
    report = (lambda step: progress(min(step, total), total)) if progress else None
    for stage in STAGES[_first_to_run(state, run_dir):]:
        if stage == "melt":
            ase_write(run_dir / DATA_FILE, start_atoms(recipe), format="lammps-data",
                      specorder=[recipe.element], masses=True, units="metal",
                      atom_style="atomic")
        write_input(run_dir / f"in.{stage}", stage_input(recipe, stage, __version__))
        started = time.perf_counter()
        run_input(f"in.{stage}", run_dir, engine, log_name=f"log.{stage}", progress=report)
        state["stages"][stage] = {"input": f"in.{stage}",
                                  "wall_time": time.perf_counter() - started}
        write_json(state_path, state)
    for stage in STAGES[:-1]:           # a finished run keeps only the final block's restart
        restart = run_dir / f"{stage}.restart"
        if restart.name != KEPT_RESTART and restart.exists():
            restart.unlink()
    return read_amorphous(recipe, run_dir)


def _read_dump(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Positions (m, sorted by id, wrapped into [0, L)) and box edges (m) of the final dump."""
    lines = path.read_text().splitlines()
    at = lines.index(next(x for x in lines if x.startswith("ITEM: BOX BOUNDS")))
    bounds = np.array([lines[at + 1 + i].split()[:2] for i in range(3)], float)
    head = next(i for i, x in enumerate(lines) if x.startswith("ITEM: ATOMS"))
    cols = lines[head].split()[2:]
    data = np.loadtxt(lines[head + 1:], ndmin=2)
    data = data[np.argsort(data[:, cols.index("id")])]
    xyz = data[:, [cols.index(c) for c in ("x", "y", "z")]] - bounds[:, 0]
    box = bounds[:, 1] - bounds[:, 0]
    xyz = np.mod(xyz, box)
    xyz[xyz >= box] = 0.0
    return lammps_to_si(xyz, "length"), lammps_to_si(box, "length")


def read_final(run_dir: Path, log_name: str = "log.final") -> dict:
    """What the final stage's log says, SI: energy per atom (J), the LAMMPS pressure tensor
    (Pa, Voigt order), the strained states (strains, stresses tension positive, Pa)."""
    log = (run_dir / log_name).read_text()
    final = _FINAL.search(log)
    if final is None:
        raise LammpsError(f"{log_name} has no FINAL line", run_dir)
    values = np.array(final.group(1).split(), float)
    strains, stresses, _ = parse_states(log)
    return {"energy_per_atom": float(lammps_to_si(values[0], "energy")),
            "pressure": lammps_to_si(values[1:], "pressure"), "strains": strains,
            "stresses": stresses}


def read_amorphous(recipe: AmorphousRecipe, run_dir: Path | str) -> AmorphousRun:
    """The history and the final block of a finished run directory (no LAMMPS)."""
    run_dir = Path(run_dir).resolve()
    state = read_json(run_dir / STATE_FILE, "run state")
    rows = []
    for stage in STAGES[:-1]:
        columns, data = parse_table((run_dir / f"{stage}.dat").read_text())
        if columns != RECORD_COLUMNS:
            raise LammpsError(f"{stage}.dat has columns {columns}, expected {RECORD_COLUMNS}",
                              run_dir)
        rows.append(data)
    data = np.concatenate(rows)
    data = data[np.unique(data[:, 0], return_index=True)[1]]
    c = {name: data[:, i] for i, name in enumerate(RECORD_COLUMNS)}
    history = {"step": c["step"].astype(int), "time": lammps_to_si(c["time"], "time"),
               "temp": c["temp"], "pe": lammps_to_si(c["pe"], "energy"),
               "press": lammps_to_si(c["press"], "pressure")}
    positions, box = _read_dump(run_dir / FINAL_DUMP)
    stages = state["stages"]
    return AmorphousRun(recipe=recipe, run_dir=run_dir, history=history, positions=positions,
                        box=box, stages=stages, **read_final(run_dir),
                        wall_time=sum(s["wall_time"] for s in stages.values()),
                        engine=state.get("engine", {}))


def elastic_of_block(recipe: AmorphousRecipe, atoms, run_dir: Path | str,
                     engine: EngineOptions = EngineOptions()) -> tuple[BlockElastic, dict]:
    """The final stage on the ASE ``atoms`` (Angstrom, an orthogonal periodic box of the
    recipe's element, e.g. a crystal): its `BlockElastic` at that box and what
    `read_final` reads, by the very route of a quenched block."""
    run_dir = Path(run_dir).resolve()
    run_dir.mkdir(parents=True, exist_ok=True)
    ase_write(run_dir / "block.data", atoms, format="lammps-data", specorder=[recipe.element],
              masses=True, units="metal", atom_style="atomic")
    write_input(run_dir / "in.block", final_input(recipe, "block.data", __version__))
    run_input("in.block", run_dir, engine, log_name="log.block")
    final = read_final(run_dir, "log.block")
    return elastic_from_states(final["strains"], final["stresses"] + final["pressure"]), final


def read_block(path: Path | str) -> AmorphousBlock:
    """The final 0 K block of an ``amorphous.h5`` record (or of the unit folder that holds
    one), the source of an amorphous film; InputError for a path that is not one."""
    import h5py
    path = Path(path)
    path = path / RECORD_NAME if path.is_dir() else path
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != RECORD_FORMAT:
                raise InputError(f"block = {str(path)!r} is not an amorphous-block record")
            recipe = json.loads(f["inputs/recipe.json"][()])
            positions, box = f["block/positions"][()], f["block/box"][()]
    except OSError as err:
        raise InputError(f"block = {str(path)!r} cannot be read: {err}") from None
    return AmorphousBlock(recipe["element"], positions, box, recipe["potential"]["name"],
                          recipe["potential"]["sha256"], str(path))


# ---- analysis ---------------------------------------------------------------------------------

def _pairs(positions: np.ndarray, box: np.ndarray, cutoff: float) -> tuple[np.ndarray,
                                                                          np.ndarray]:
    """(i, j) index pairs closer than ``cutoff`` in the periodic orthogonal ``box`` (every
    pair once) and their distances; ``cutoff`` below half the smallest edge."""
    if not cutoff < 0.5 * np.min(box):
        raise InputError(f"cutoff = {cutoff:g} m is not below half the box edge "
                         f"{0.5 * np.min(box):g} m")
    tree = cKDTree(positions, boxsize=box)
    pairs = tree.query_pairs(cutoff, output_type="ndarray")
    d = positions[pairs[:, 0]] - positions[pairs[:, 1]]
    d -= box * np.round(d / box)
    return pairs, np.sqrt(np.einsum("ij,ij->i", d, d))


def coordination(positions: np.ndarray, box: np.ndarray, cutoff: float) -> np.ndarray:
    """Neighbours of each atom closer than ``cutoff`` (m), periodic images included."""
    pairs, _ = _pairs(positions, box, cutoff)
    return np.bincount(pairs.ravel(), minlength=len(positions))


def hybridization(counts: np.ndarray) -> dict[str, float]:
    """Fractions of atoms by coordination: sp3 (4), sp2 (3), sp (2), other."""
    counts = np.asarray(counts)
    f = {name: float(np.mean(counts == k)) for name, k in (("sp3", 4), ("sp2", 3), ("sp", 2))}
    f["other"] = 1.0 - sum(f.values())
    return f


def radial_distribution(positions: np.ndarray, box: np.ndarray, r_max: float = RDF_RANGE,
                        width: float = RDF_BIN) -> tuple[np.ndarray, np.ndarray]:
    """g(r) at bin centres r (m) out to ``r_max`` (at most just under half the box), the
    pair count in each shell over that of an ideal gas of the same density."""
    r_max = min(r_max, 0.5 * float(np.min(box)) * (1 - 1e-9))
    _, d = _pairs(positions, box, r_max)
    edges = np.arange(0.0, r_max + 0.5 * width, width)
    hist, edges = np.histogram(d, bins=edges)
    n = len(positions)
    shells = 4.0 / 3.0 * math.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    ideal = 0.5 * n * (n - 1) / float(np.prod(box)) * shells
    return 0.5 * (edges[1:] + edges[:-1]), hist / ideal


@dataclass(frozen=True)
class BlockElastic:
    """The block's 6x6 C (Pa), its Voigt-Reuss-Hill average and the scatter over
    directions; see the module docstring."""

    C: np.ndarray
    fit_rms: float
    average: IsotropicAverage
    E_std: float
    nu_std: float
    axial_spread: float
    shear_ratio: float

    @property
    def E(self) -> float:
        return self.average.E

    @property
    def nu(self) -> float:
        return self.average.nu

    def to_dict(self) -> dict:
        return {"C": self.C.tolist(), "fit_rms": self.fit_rms, "E": self.E, "nu": self.nu,
                "K": self.average.K, "G": self.average.G, "E_std": self.E_std,
                "nu_std": self.nu_std, "axial_spread": self.axial_spread,
                "shear_ratio": self.shear_ratio, "A_U": self.average.A_U}


def block_elastic(C: np.ndarray, fit_rms: float = 0.0) -> BlockElastic:
    """Hill's isotropic moduli of ``C`` (Pa) with their directional scatter and the
    isotropy measures (module docstring)."""
    C = np.asarray(C, float)
    average = voigt_reuss_hill(C)
    S = np.linalg.inv(C)
    E_dir = 1.0 / np.diag(S)[:3]
    nu_dir = [-S[i, j] / S[i, i] for i in range(3) for j in range(3) if i != j]
    axial, shear = np.diag(C)[:3], np.diag(C)[3:]
    off = np.array([C[0, 1], C[0, 2], C[1, 2]])
    return BlockElastic(C=C, fit_rms=float(fit_rms), average=average,
                        E_std=float(np.std(E_dir, ddof=1)), nu_std=float(np.std(nu_dir, ddof=1)),
                        axial_spread=float(np.std(axial) / np.mean(axial)),
                        shear_ratio=float(np.mean(shear) / (0.5 * (axial.mean() - off.mean()))))


def elastic_from_states(strains: np.ndarray, stresses: np.ndarray) -> BlockElastic:
    """`block_elastic` of the least-squares C of the strained states; ``stresses`` relative
    to the unstrained block's, so that the fit's residual measures the misfit alone."""
    fit = stiffness_from_stress_strain(strains, stresses)
    return block_elastic(fit.C, fit.residual)


@dataclass(frozen=True)
class AmorphousAnalysis:
    """What the block is, SI (module docstring)."""

    density: float
    bond_cutoff: float
    fractions: dict
    mean_coordination: float
    coordination: np.ndarray
    rdf_r: np.ndarray
    rdf_g: np.ndarray
    residual_stress: float
    stress: np.ndarray
    energy_per_atom: float
    elastic: BlockElastic

    def summary(self) -> dict:
        """The figures (no arrays), SI."""
        f = self.fractions
        return {"density": self.density, "sp3_fraction": f["sp3"], "sp2_fraction": f["sp2"],
                "sp_fraction": f["sp"], "other_fraction": f["other"],
                "mean_coordination": self.mean_coordination, "bond_cutoff": self.bond_cutoff,
                "residual_stress": self.residual_stress, "stress": self.stress.tolist(),
                "energy_per_atom": self.energy_per_atom, **self.elastic.to_dict()}


def analyze_amorphous(run: AmorphousRun) -> AmorphousAnalysis:
    recipe = run.recipe
    counts = coordination(run.positions, run.box, recipe.bond_cutoff)
    r, g = radial_distribution(run.positions, run.box)
    stress = -run.pressure
    return AmorphousAnalysis(
        density=run.n_atoms * recipe.atom_mass / float(np.prod(run.box)),
        bond_cutoff=recipe.bond_cutoff, fractions=hybridization(counts),
        mean_coordination=float(counts.mean()), coordination=counts, rdf_r=r, rdf_g=g,
        residual_stress=float(stress[:3].mean()), stress=stress,
        energy_per_atom=run.energy_per_atom,
        elastic=elastic_from_states(run.strains, run.stresses - stress))


# ---- the record -------------------------------------------------------------------------------

def _provenance(run: AmorphousRun, extra: dict | None) -> dict:
    """`md.record.run_provenance` of the recipe: potential, seeds, engine, LAMMPS."""
    recipe = run.recipe
    spec = SimpleNamespace(potential=recipe.potential, protocol=SimpleNamespace(seed=recipe.seed))
    return run_provenance(SimpleNamespace(spec=spec, parts=[{"seeds": recipe.seeds()}],
                                          engine=run.engine), extra)


def write_amorphous_record(run: AmorphousRun, analysis: AmorphousAnalysis,
                           path: Path | str | None = None,
                           provenance: dict | None = None) -> Path:
    """Write ``amorphous.h5`` (or ``path``), SI: root attributes the figures of
    `AmorphousAnalysis.summary` and the provenance; ``history`` (step, time s, temp K, pe J
    per atom, press Pa); ``block`` (positions m, box m, coordination); ``rdf`` (r m, g);
    ``elastic`` (C Pa, strains, stresses Pa); ``inputs`` (each stage's input, the recipe)."""
    path = Path(path) if path is not None else run.run_dir / RECORD_NAME
    summary = analysis.summary()
    with atomic_h5(path) as f:
        f.attrs["format"] = RECORD_FORMAT
        write_attrs(f, _provenance(run, provenance))
        write_attrs(f, {"run_dir": str(run.run_dir), "n_atoms": run.n_atoms,
                        "n_steps": run.n_steps, "wall_time": run.wall_time, "units": "SI",
                        "stress_sign": "tension positive (minus the LAMMPS pressure)",
                        "hybridization": "coordination within bond_cutoff: sp3 4, sp2 3, "
                                         "sp 2 neighbours",
                        "average": "Voigt-Reuss-Hill (Hill 1952); E_std, nu_std over "
                                   "directions of S = C^-1", **summary})
        h = f.create_group("history")
        for key, unit in (("step", "1"), ("time", "s"), ("temp", "K"), ("pe", "J"),
                          ("press", "Pa")):
            h[key] = run.history[key]
            h[key].attrs["units"] = unit
        b = f.create_group("block")
        b["positions"], b["box"] = run.positions, run.box
        b["positions"].attrs["units"] = b["box"].attrs["units"] = "m"
        b["coordination"] = analysis.coordination
        g = f.create_group("rdf")
        g["r"], g["g"] = analysis.rdf_r, analysis.rdf_g
        g["r"].attrs["units"] = "m"
        e = f.create_group("elastic")
        e["C"], e["strains"], e["stresses"] = analysis.elastic.C, run.strains, run.stresses
        e["C"].attrs["units"] = e["stresses"].attrs["units"] = "Pa"
        inputs = f.create_group("inputs")
        for name, text in run.inputs().items():
            inputs[name] = text
        inputs["recipe.json"] = json.dumps(run.recipe.to_dict())
    return path


def read_amorphous_summary(path: Path | str) -> dict:
    """The figures of an ``amorphous.h5`` (root attributes), SI; InputError for a file that
    is not one."""
    import h5py
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != RECORD_FORMAT:
                raise InputError(f"record = {str(path)!r} is not an amorphous-block record")
            return {k: (json.loads(v) if k in ("stress", "C") else
                        v.item() if hasattr(v, "item") else v) for k, v in f.attrs.items()}
    except OSError as err:
        raise InputError(f"record = {str(path)!r} cannot be read: {err}") from None



def summary_lines(summary: dict, recipe: AmorphousRecipe) -> list[str]:
    """The figures of a block for people (eV beside J, GPa beside Pa)."""
    s = summary
    ev = si_to_lammps(s["energy_per_atom"], "energy")
    cutoff = si_to_lammps(s["bond_cutoff"], "length")
    return [
        f"{recipe.n_atoms} {recipe.element} atoms with {recipe.potential.name} at "
        f"{s['density']:.1f} kg/m^3 ({s['density'] / 1000:.3f} g/cm3)",
        f"hybridization (neighbours within {cutoff:g} Angstrom): sp3 {s['sp3_fraction']:.3f}, "
        f"sp2 {s['sp2_fraction']:.3f}, sp {s['sp_fraction']:.3f}, other "
        f"{s['other_fraction']:.3f}; mean coordination {s['mean_coordination']:.3f}",
        f"0 K at the fixed box: residual stress {s['residual_stress'] / 1e9:.2f} GPa (tension "
        f"positive), energy per atom {ev:.4f} eV ({s['energy_per_atom']:.6g} J)",
        f"elastic (Voigt-Reuss-Hill of the 6x6 C; +- over directions): E "
        f"{s['E'] / 1e9:.1f} +- {s['E_std'] / 1e9:.1f} GPa, nu {s['nu']:.3f} +- "
        f"{s['nu_std']:.3f}, K {s['K'] / 1e9:.1f} GPa, G {s['G'] / 1e9:.1f} GPa",
        f"isotropy: C11, C22, C33 spread {100 * s['axial_spread']:.1f} %, C44 / ((C11 - C12)"
        f" / 2) = {s['shear_ratio']:.3f}, A_U {s['A_U']:.3f}",
    ]


def block_elastic_constants(block: AmorphousBlock) -> ElasticConstants:
    """The elastic constants of the block a film was cut from, as `md.elastic` gives a
    crystal's: its record's C (the block's own, `block_elastic`), the recipe's strain and
    their Hill average; what an indentation of the film compares its Hertz fit with."""
    import h5py
    with h5py.File(block.source, "r") as f:     # a record: read_block checked its format
        C = np.asarray(json.loads(f.attrs["C"]), float)
        fit_rms = float(f.attrs["fit_rms"])
        strain = float(json.loads(f["inputs/recipe.json"][()])["strain"])
    return ElasticConstants(potential=block.potential, element=block.element,
                            structure="amorphous", C=C, cell=tuple(float(x) for x in block.box),
                            strain=strain, fit_rms=fit_rms, average=voigt_reuss_hill(C))


def layer_elastic_constants(potential, layer, run_dir: Path | str,
                            engine: EngineOptions = EngineOptions()) -> ElasticConstants:
    """The elastic constants of one slab layer: a crystal's from the potential (`md.elastic`,
    run in ``run_dir``), an amorphous film's from its block's record."""
    if layer.structure == "amorphous":
        return block_elastic_constants(layer.block)
    from filmscale.md.elastic import elastic_constants
    return elastic_constants(potential, layer.crystal, run_dir=run_dir, engine=engine)
