"""filmscale.md: LAMMPS front ends (atomistic nanoindentation, SPH and peridynamics).

Everything that touches LAMMPS lives here and returns the continuum package's data types in SI.
The engine layer arrives with the atomistic issue; importing this package loads nothing yet.
"""
