"""A potential's own elastic constants, from small-strain LAMMPS runs at 0 K.

The bulk crystal is relaxed (box and atoms), then strained by +-eps along each of the six
Voigt components with the atoms re-minimised at fixed box; C follows from the central
differences of the stress (least squares over the twelve states), and its Voigt-Reuss-Hill
average (Hill, Proc. Phys. Soc. A 65, 349 (1952)) gives the isotropic E and nu and the reduced modulus E* = E / (1 - nu^2) against a
rigid indenter: the modulus the Hertzian segment of an MD curve is compared with.
"""

from __future__ import annotations

import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from ase.io import write as ase_write

from filmscale.continuum.elasticity import (IsotropicAverage, stiffness_from_stress_strain,
                                            voigt_reuss_hill)
from filmscale.core.checks import check_real
from filmscale.md.engine import EngineOptions, LammpsError, run_input
from filmscale.md.lammps_input import write_input
from filmscale.md.structures import Crystal
from filmscale.md.lammps_units import lammps_to_si
from filmscale.potentials import Potential

#: LAMMPS pressure components in Voigt order (xx, yy, zz, yz, xz, xy); stress = -pressure.
_PRESSURE = ("pxx", "pyy", "pzz", "pyz", "pxz", "pxy")
_STATE = re.compile(r"^STATE (\d) ([-+\deE.]+)((?: [-+\deE.]+){6})$", re.M)
_LATTICE = re.compile(r"^LATTICE ([-+\deE.]+) ([-+\deE.]+) ([-+\deE.]+)$", re.M)


@dataclass(frozen=True)
class ElasticConstants:
    """Elastic constants of a potential for one crystal at 0 K, SI units."""

    potential: str
    element: str
    structure: str
    C: np.ndarray              #: 6x6 stiffness in Voigt notation, Pa (crystal axes)
    cell: tuple[float, float, float]   #: relaxed cell edges of the strained block, m
    strain: float              #: the +-strain amplitude used
    fit_rms: float             #: residual of the least-squares C, relative to max |C|
    average: IsotropicAverage  #: Voigt-Reuss-Hill average

    @property
    def E_star(self) -> float:
        """Reduced modulus against a rigid indenter, E / (1 - nu^2), Pa."""
        return self.average.plane_strain_modulus()

    def to_dict(self) -> dict:
        return {"potential": self.potential, "element": self.element,
                "structure": self.structure, "C": self.C.tolist(), "cell": list(self.cell),
                "strain": self.strain, "fit_rms": self.fit_rms, "E_star": self.E_star,
                "average": self.average.to_dict()}

    def summary(self) -> str:
        c = self.C / 1e9
        avg = self.average
        return (f"{self.element} ({self.structure}) with {self.potential}: "
                f"C11 {c[0, 0]:.1f}, C12 {c[0, 1]:.1f}, C44 {c[3, 3]:.1f} GPa; Hill E "
                f"{avg.E / 1e9:.1f} GPa, nu {avg.nu:.3f}, E* {self.E_star / 1e9:.1f} GPa")


def _strain_commands(component: int, amount: float) -> str:
    """change_box for a Voigt strain increment (engineering shear for 4-6)."""
    if component < 3:
        axis = "xyz"[component]
        return f"change_box all {axis} scale {1.0 + amount:.15g} remap"
    tilt, edge = {3: ("yz", "lz"), 4: ("xz", "lz"), 5: ("xy", "ly")}[component]
    return f"change_box all {tilt} delta $({amount:.15g}*{edge}) remap"


#: each state's minimisation: a force tolerance (two-norm, eV/A) of 1e-10, not 1e-12. A strained
#: Tersoff diamond starts at 5e-12 and ground through all 10 000 iterations towards 1e-12: 188 s
#: a crystal instead of 1.2 s, for a change of C below 1e-12 of C11 (docs/md-indentation.md)
MINIMIZE = "minimize 0 1e-10 10000 100000"


def elastic_input(potential: Potential, element: str, *, strain: float) -> str:
    """The LAMMPS input: relax, then the twelve strained states, each printed as a STATE line."""
    state = ('print "STATE {k} {e:+.3e} ' +
             " ".join(f"$({p}:%.12g)" for p in _PRESSURE) + '"')
    lines = [
        f"# filmscale: elastic constants of {element} with {potential.name} (0 K, "
        f"+-{strain:g} strains)",
        "units metal", "atom_style atomic", "boundary p p p", "read_data crystal.data",
        *potential.pair_commands([element]),
        "neighbor 1.0 bin",
        "thermo_style custom step pe press pxx pyy pzz pyz pxz pxy",
        "# relax cell and atoms to zero stress",
        "fix relax all box/relax aniso 0.0 vmax 0.001",
        MINIMIZE,
        "unfix relax",
        MINIMIZE,
        'print "LATTICE $(lx:%.12g) $(ly:%.12g) $(lz:%.12g)"',
        "change_box all triclinic",
    ]
    for k in range(6):
        lines += [f"# Voigt component {k + 1}: +{strain:g} then -{strain:g}",
                  _strain_commands(k, strain), MINIMIZE,
                  state.format(k=k, e=strain),
                  _strain_commands(k, -2.0 * strain if k >= 3 else
                                   (1.0 - strain) / (1.0 + strain) - 1.0),
                  MINIMIZE,
                  state.format(k=k, e=-strain),
                  _strain_commands(k, strain if k >= 3 else 1.0 / (1.0 - strain) - 1.0)]
    return "\n".join(lines) + "\n"


def parse_states(log: str) -> tuple[np.ndarray, np.ndarray, tuple[float, float, float]]:
    """Voigt strains, stresses (Pa) and relaxed cell edges (A) from the run's log."""
    states = _STATE.findall(log)
    lattice = _LATTICE.search(log)
    if len(states) != 12 or lattice is None:
        raise LammpsError(f"elastic-constant log has {len(states)} of 12 strained states")
    strains = np.zeros((12, 6))
    stresses = np.zeros((12, 6))
    for i, (k, e, p) in enumerate(states):
        strains[i, int(k)] = float(e)
        stresses[i] = -lammps_to_si(np.array(p.split(), float), "pressure")
    return strains, stresses, tuple(float(x) for x in lattice.groups())


def elastic_constants(potential: Potential, crystal: Crystal, *, strain: float = 1e-3,
                      repeat: int = 4, run_dir: Path | str | None = None,
                      engine: EngineOptions = EngineOptions()) -> ElasticConstants:
    """C, its Hill average and E* of ``crystal`` (element, structure, starting lattice
    constant) under ``potential``; strain is the +- amplitude (1e-4 to 1e-2: small enough
    for linearity, large enough above the minimiser's tolerance); ``repeat`` unit cells per
    edge. The input and log stay in ``run_dir`` (a temporary folder when None), where a
    finished run of the same input is reused."""
    strain = check_real("strain", strain, low=1e-4, high=1e-2)
    potential.pair_commands([crystal.element])
    cell = crystal.unit_cell("001" if crystal.structure != "hcp" else "0001")
    text = (f"# crystal: {crystal.structure} {crystal.element}, a = {crystal.a:.12g} m, "
            f"c = {crystal.c}, {repeat}^3 cells\n"
            + elastic_input(potential, crystal.element, strain=strain))
    with tempfile.TemporaryDirectory(prefix="filmscale-elastic-") as tmp:
        folder = Path(run_dir) if run_dir is not None else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        done = folder / "log.elastic"
        # a finished run of the same input in run_dir is read back, not run again
        if not ((folder / "in.elastic").exists() and (folder / "in.elastic").read_text() == text
                and done.exists() and len(_STATE.findall(done.read_text())) == 12):
            ase_write(folder / "crystal.data", cell.repeat(repeat), format="lammps-data",
                      specorder=[crystal.element], masses=True, units="metal",
                      atom_style="atomic")
            write_input(folder / "in.elastic", text)
            run_input("in.elastic", folder, engine, log_name="log.elastic")
        log = done.read_text()
    strains, stresses, edges = parse_states(log)
    fit = stiffness_from_stress_strain(strains, stresses)
    return ElasticConstants(potential=potential.name, element=crystal.element,
                            structure=crystal.structure, C=fit.C,
                            cell=tuple(float(lammps_to_si(x, "length")) for x in edges),
                            strain=strain, fit_rms=fit.residual, average=voigt_reuss_hill(fit.C))
