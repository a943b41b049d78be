"""filmscale: multiscale contact, indentation and impact analysis of thin solid films.

The package follows the data flow of a study, from atoms to the impact of a slider on a disk:

- `filmscale.md`: LAMMPS runs (atomistic and particle-continuum) that produce
  load-displacement curves in SI units;
- `filmscale.continuum`: numpy/scipy physics. `continuum.indentation` analyses curves,
  `continuum.calibration` turns them into a material, `continuum.contact` predicts impacts of
  that material;
- `filmscale.workflows`: scenes, the planner, the unit store, reports and the command line;
- `filmscale.potentials`: the interatomic potentials the package knows;
- `filmscale.core`: the shared kernel (errors, input checks, atomic files, JSON, provenance).

See docs/architecture.md for the layers and docs/api.md for the public names.
"""

from importlib import metadata as _metadata

try:
    __version__ = _metadata.version("filmscale")
except _metadata.PackageNotFoundError:      # a source tree without an install
    __version__ = "0+unknown"

__all__ = ["__version__"]
