"""filmscale.md: everything that touches LAMMPS, returning continuum's data types in SI.

Atomistic nanoindentation with a rigid sphere or cone (`spec` presets and spec files,
`indentation` inputs, `run` with restarts, `analysis` and `record`), elastic constants of a
potential (`elastic`), contact geometry from dumps (`contact`), particle-continuum models
(`particles` specs, `particle_inputs`, `particle_run`), the engine (`engine`: library or
`mpirun`) and unit conversion in one table (`units`).

Importing the package loads no LAMMPS library (`engine.load_library` does, on first use), and
the public names below are imported on first use.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the module that defines it
_WHERE = {
    "IndentSpec": "indentation", "IndentProtocol": "indentation",
    "RigidIndenter": "indentation",
    "Crystal": "structures", "SlabSpec": "structures",
    "preset": "spec", "load_spec": "spec",
    "run_indentation": "run", "read_run": "run",
    "analyze_indentation": "analysis", "IndentAnalysis": "analysis",
    "write_record": "record",
    "elastic_constants": "elastic", "ElasticConstants": "elastic",
    "ContactAnalysis": "contact", "read_dumps": "contact",
    "ParticleIndentSpec": "particles", "ParticleImpactSpec": "particles",
    "run_particles": "particle_run",
    "EngineOptions": "engine", "LammpsError": "engine", "LammpsUnavailable": "engine",
    "lammps_to_si": "lammps_units", "si_to_lammps": "lammps_units",
}

__all__ = sorted(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
