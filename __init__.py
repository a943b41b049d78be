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

__all__ = ["__version__"]


def __getattr__(name: str):
    # the version is read on first use: importlib.metadata costs a tenth of `filmscale --help`
    if name != "__version__":
        raise AttributeError(f"module 'filmscale' has no attribute {name!r}")
    from importlib import metadata
    try:
        version = metadata.version("filmscale")
    except metadata.PackageNotFoundError:      # a source tree without an install
        version = "0+unknown"
    globals()["__version__"] = version
    return version
