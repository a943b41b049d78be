"""filmscale.potentials: the registry of interatomic potentials (files, checksums, citations).

The registry arrives with the atomistic issue; this package imports no other scale.
"""
