"""LAMMPS ``metal`` units to SI and back: the one place where LAMMPS units are converted.

Every quantity that crosses the boundary of ``filmscale.md`` goes through `to_si` or
`from_si` with the name of its dimension; nothing else in the package multiplies by a unit
factor. Factors are exact or CODATA 2018, as LAMMPS uses them (``update.cpp``).
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


def _factor(dimension: str) -> float:
    try:
        return METAL[dimension]
    except KeyError:
        raise KeyError(f"unknown dimension {dimension!r}; known: {', '.join(METAL)}") from None


def to_si(value, dimension: str):
    """A metal-unit value (scalar or array) in SI."""
    f = _factor(dimension)
    return value * f if np.ndim(value) == 0 else np.asarray(value, dtype=float) * f


def from_si(value, dimension: str):
    """An SI value (scalar or array) in metal units."""
    f = _factor(dimension)
    return value / f if np.ndim(value) == 0 else np.asarray(value, dtype=float) / f
