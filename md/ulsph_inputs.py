"""The LAMMPS input of an updated-Lagrangian SPH (``pair_style smd/ulsph``, MACHDYN;
Ganzenmüller 2015) indentation: the particle method that bonds a film to its substrate.

Unlike TLSPH, ULSPH lets particles of different types interact (``pair_coeff i j *CROSS``):
each particle's stress comes from its own material (linear EOS for the pressure, a linear
elastic or elastic-perfectly plastic deviator with linear hardening), and the pair forces
between a film particle and a substrate particle carry both stresses, so the interface is a
bonded continuum with no contact law of its own. Each material is one particle type, the
films top first as in the PERI model.

Numbers given to LAMMPS are in the ``particle`` unit system of `filmscale.md.lammps_units` (um, GPa,
ns), converted here; everything here takes SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from filmscale.core.checks import check_choice, check_real
from filmscale.md.particle_inputs import (CFL, K_FACTOR, assemble_input, block_lines,
                                          indent_driver_lines, lammps_number, lammps_quantity,
                                          layer_lines, particle_scales, run_lines,
                                          smd_boundary_lines, smd_preamble, weight_group_lines)
from filmscale.md.particles import ParticleMaterial


@dataclass(frozen=True)
class UlsphSettings:
    """The numerical settings of ``pair_style smd/ulsph`` (documented in the MACHDYN user
    guide): artificial viscosity ``q1`` (Monaghan's linear term; MACHDYN also uses it as the
    hourglass amplitude), hourglass control on/off, first-order kernel gradient correction,
    density by continuity (integrated velocity divergence) or by kernel summation, and the
    kernel diameter in spacings."""

    q1: float = 0.06
    hourglass: bool = True
    gradient_correction: bool = True
    density: str = "continuity"
    kernel: float = 2.01

    def __post_init__(self):
        check_real("ulsph.q1", self.q1, low=0.0, high=10.0)
        check_choice("ulsph.density", self.density, ("continuity", "summation"))
        check_real("ulsph.kernel", self.kernel, low=1.5, high=4.0, unit="spacings")


#: The settings filmscale writes (docs/particles.md, ULSPH table).
ULSPH_SETTINGS = UlsphSettings()


def ulsph_material(m: ParticleMaterial, settings: UlsphSettings = ULSPH_SETTINGS) -> str:
    """``pair_coeff`` keywords of one material: ``*COMMON rho0 c0 Q1 Cp hg`` with the bulk
    sound speed c0 = sqrt(K/rho0) (ULSPH's linear EOS takes K = rho0 c0^2), then
    ``*EOS_LINEAR`` and ``*STRENGTH_LINEAR G`` or ``*STRENGTH_LINEAR_PLASTIC G sigma_y 0``."""
    mat = m.material
    K, G = mat.bulk_modulus, mat.shear_modulus
    c0 = math.sqrt(K / m.density)
    # heat capacity Cp is only used by thermal models (none here): 1
    common = (f"*COMMON {lammps_quantity(m.density, 'density')} "
              f"{lammps_quantity(c0, 'velocity')} {lammps_number(settings.q1)} "
              f"1.0 {1.0 if settings.hourglass else 0.0}")
    if m.elastic:
        strength = f"*STRENGTH_LINEAR {lammps_quantity(G, 'pressure')}"
    else:
        strength = (f"*STRENGTH_LINEAR_PLASTIC {lammps_quantity(G, 'pressure')} "
                    f"{lammps_quantity(mat.sigma_y, 'pressure')} 0")
    return f"{common} *EOS_LINEAR {strength} *END"


def ulsph_input(spec, version: str = "", settings: UlsphSettings = ULSPH_SETTINGS) -> str:
    """The complete LAMMPS input of a ULSPH indentation of ``spec`` (a `ParticleIndentSpec`
    of method ``ulsph``), homogeneous or layered, elastic or elastic-plastic."""
    g = spec.grid
    dx, D, R, E_star = particle_scales(spec)
    vol = dx**3
    mats = spec.target.materials
    n_types = len(mats)
    lines = [
        *smd_preamble(spec, version, dx),
        *block_lines(spec, n_types, 0.0),
        f"create_atoms {n_types} region block",
    ]
    lines += [
        *layer_lines(spec, dx),
        "group target union all",
        *weight_group_lines(g, "target"),
        f"set group all volume {lammps_number(vol)}",
        f"set group plane volume {lammps_number(vol / 2)}",
        f"set group axis volume {lammps_number(vol / 4)}",
    ]
    for k, m in enumerate(mats, start=1):
        lines.append(f"set type {k} smd/mass/density {lammps_quantity(m.density, 'density')}")
    lines += [
        f"set group all diameter {lammps_number(settings.kernel * dx)}",
        f"set group all smd/contact/radius {lammps_number(0.5 * dx)}",
        "",
        "# ---- materials (SI values converted to um, GPa, ns); *CROSS bonds the layers",
        f"pair_style smd/ulsph *DENSITY_{settings.density.upper()} *VELOCITY_GRADIENT "
        f"*{'' if settings.gradient_correction else 'NO_'}GRADIENT_CORRECTION",
    ]
    for k, m in enumerate(mats, start=1):
        lines.append(f"pair_coeff {k} {k} {ulsph_material(m, settings)}")
    for i in range(1, n_types + 1):
        for j in range(i + 1, n_types + 1):
            lines.append(f"pair_coeff {i} {j} *CROSS")
    lines += [
        "",
        *smd_boundary_lines(g, D, dx),
        f"fix dtfix all smd/adjust_dt {CFL}",
        "fix integration target smd/integrate_ulsph",
        "variable t equal f_dtfix    # simulated time (the timestep adapts)",
        "compute stress all smd/ulsph/stress",
        "compute ep all smd/plastic/strain",
        "",
    ]
    lines += indent_driver_lines(spec, dx, R, K_FACTOR * E_star, D)
    lines += run_lines(spec, "x y z c_stress[7] c_ep")
    return assemble_input(spec, lines)
