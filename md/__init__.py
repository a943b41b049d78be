"""filmscale.md: LAMMPS front ends (atomistic nanoindentation; SPH and peridynamics later).

Everything that touches LAMMPS lives here and returns the continuum package's data types in
SI. Importing the package loads no LAMMPS library; `engine.load_library` does, on first use.
"""
