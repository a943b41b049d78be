"""LAMMPS units to SI and back: the one place where LAMMPS units are converted.

Every quantity that crosses the boundary of ``filmscale.md`` goes through `lammps_to_si` or
`si_to_lammps` with the name of its dimension and of the unit system; nothing else in the package
multiplies by a unit factor.

Two systems are used:

- ``metal`` (atomistic runs): LAMMPS's own metal units. Factors are exact or CODATA 2018, as
  LAMMPS uses them (``update.cpp``).
- ``particle`` (SPH and peridynamics runs): micrometre, gigapascal, nanosecond, a consistent
  system given to LAMMPS under ``units si`` (MACHDYN and PERI have no unit-dependent constants;
  the MACHDYN examples do the same with mm, GPa, ms). It keeps the numbers of micrometre-scale
  contact near one: a 1 um sphere, E = 70 (GPa), density 2.7 (pg/um^3), wave speed 5 (um/ns),
  loads in mN, where SI would mix 1e-6 m with 1e11 Pa.
"""

from __future__ import annotations

import numpy as np

EV = 1.602176634e-19          # J
ANGSTROM = 1e-10              # m
PICOSECOND = 1e-12            # s
BAR = 1e5                     # Pa
GRAM_PER_MOLE = 1e-3 / 6.02214076e23   # kg

#: SI value of one metal unit of each dimension.
METAL = {
    "length": ANGSTROM,
    "area": ANGSTROM**2,
    "volume": ANGSTROM**3,
    "time": PICOSECOND,
    "velocity": ANGSTROM / PICOSECOND,
    "energy": EV,
    "force": EV / ANGSTROM,
    "stiffness": EV / ANGSTROM**2,             # force per length (contact stiffness S)
    "indent_constant": EV / ANGSTROM**3,       # fix indent K: force per length squared
    "pressure": BAR,                           # LAMMPS metal pressure and stress
    "mass": GRAM_PER_MOLE,
    "temperature": 1.0,                        # K
}

MICROMETRE = 1e-6             # m
GIGAPASCAL = 1e9              # Pa
NANOSECOND = 1e-9             # s

#: SI value of one particle-model unit of each dimension (um, GPa, ns and what follows).
PARTICLE = {
    "length": MICROMETRE,
    "area": MICROMETRE**2,
    "volume": MICROMETRE**3,
    "time": NANOSECOND,
    "velocity": MICROMETRE / NANOSECOND,                     # 1000 m/s
    "pressure": GIGAPASCAL,
    "force": GIGAPASCAL * MICROMETRE**2,                     # 1 mN
    "energy": GIGAPASCAL * MICROMETRE**3,                    # 1 nJ
    "stiffness": GIGAPASCAL * MICROMETRE,                    # force per length
    "indent_constant": GIGAPASCAL,                           # fix indent K: force per length^2
    "mass": GIGAPASCAL * MICROMETRE * NANOSECOND**2,         # 1 pg
    "density": GIGAPASCAL * NANOSECOND**2 / MICROMETRE**2,   # 1000 kg/m^3
}

SYSTEMS = {"metal": METAL, "particle": PARTICLE}


def _factor(dimension: str, system: str) -> float:
    try:
        table = SYSTEMS[system]
    except KeyError:
        raise KeyError(f"unknown unit system {system!r}; known: {', '.join(SYSTEMS)}") from None
    try:
        return table[dimension]
    except KeyError:
        raise KeyError(f"unknown dimension {dimension!r} in {system} units; "
                       f"known: {', '.join(table)}") from None


def lammps_to_si(value, dimension: str, system: str = "metal"):
    """A value (scalar or array) in the given LAMMPS unit system, in SI."""
    f = _factor(dimension, system)
    return value * f if np.ndim(value) == 0 else np.asarray(value, dtype=float) * f


def si_to_lammps(value, dimension: str, system: str = "metal"):
    """An SI value (scalar or array) in the given LAMMPS unit system."""
    f = _factor(dimension, system)
    return value / f if np.ndim(value) == 0 else np.asarray(value, dtype=float) / f
