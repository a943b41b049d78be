"""filmscale.continuum: contact, impact and indentation models in numpy/scipy (no LAMMPS)."""
