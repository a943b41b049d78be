"""Particle continuum models in LAMMPS: the complete input file of a particle spec
(`filmscale.md.particles`), TLSPH or PERI, and the timestep and step count it implies.

The rigid indenter is LAMMPS's ``fix indent`` (a penalty contact: an atom inside the sphere or
cone is pushed out with force K d^2). Quasi-static indentation drives it at constant speed
(displacement control, load-hold-unload); an impact lets a free rigid sphere of mass m hit
the target: a small unbonded particle cluster carries the sphere's mass, its height drives
the indenter, and the indenter's reaction is applied to it, so the sphere decelerates and
rebounds under the contact force.

Numbers given to LAMMPS are in the ``particle`` unit system of `filmscale.md.lammps_units` (um, GPa,
ns), converted here; everything here takes SI.
"""

from __future__ import annotations

import math

from filmscale.continuum.indentation.tips import Cone, Sphere, SphericalCone
from filmscale.continuum.materials import ElasticPlastic
from filmscale.md.particles import (PERI_HORIZON, PYRAMID_FACE_ANGLES, Grid, ParticleImpactSpec,
                                    ParticleIndentSpec, ParticleMaterial, contact_radius,
                                    is_pyramid)
from filmscale.md.lammps_units import si_to_lammps

#: TLSPH kernel diameter (interaction range) in spacings, as in the MACHDYN examples.
TLSPH_KERNEL = 2.01
#: CFL factor of ``fix smd/adjust_dt`` (the MACHDYN examples' 0.1).
CFL = 0.1
#: Penalty stiffness K of ``fix indent`` in units of the target's largest E*: an atom under a
#: contact pressure p sits dx sqrt(p / (K_FACTOR E*)) inside the indenter, 4 % of dx at
#: p = 0.2 E* (Hertz at 0.1 R depth).
K_FACTOR = 100.0
#: Artificial viscosity (linear, quadratic) and hourglass control of TLSPH (MACHDYN examples).
TLSPH_Q1, TLSPH_Q2, TLSPH_HOURGLASS = 0.06, 0.0, 10.0
#: Plastic strains between which a power-law hardening curve is matched by Johnson-Cook.
JC_STRAINS = (0.033, 0.1)
#: PERI timestep (fixed; PERI has no adaptive step) in spacings over the P-wave speed: 0.2 and
#: 0.4 give the same curve within 1 %; 0.8 loses the contact and 1.2 blows up (R/8 runs).
PERI_DT_FACTOR = 0.25

#: The record a run writes (``fix print``) and its columns.
RECORD = "particles.dat"
INDENT_COLUMNS = ("time", "depth", "load", "apex")
IMPACT_COLUMNS = ("time", "approach", "load", "velocity")


def lammps_number(x: float) -> str:
    """A number as written into a LAMMPS input: 10 significant digits."""
    return f"{x:.10g}"


def lammps_quantity(value: float, dimension: str) -> str:
    """An SI ``value`` of ``dimension`` converted to the ``particle`` units and written as
    `lammps_number`."""
    return lammps_number(si_to_lammps(value, dimension, "particle"))


def _clamp_min(a: str, b: str) -> str:
    """min(a, b) as an equal-style formula (LAMMPS's min() takes no numbers)."""
    return f"0.5*(({a})+({b})-abs(({a})-({b})))"


def particle_scales(spec) -> tuple[float, float, float | None, float]:
    """The spacing dx and block depth D (on the lattice), the sphere radius R (None for other
    tips) and the largest E* of the target's materials, in particle units."""
    g = spec.grid
    dx = si_to_lammps(g.spacing, "length", "particle")
    R = si_to_lammps(spec.tip.R, "length", "particle") if isinstance(spec.tip, Sphere) else None
    E_star = max(si_to_lammps(m.material.plane_strain_modulus, "pressure", "particle")
                 for m in spec.target.materials)
    return dx, round(g.depth / g.spacing) * dx, R, E_star


def block_lines(spec, n_types: int, top: float) -> list[str]:
    """The lattice, the block region and a box reaching up to ``top`` (particle units):
    the target's surface is z = 0 with a lattice point on the axis."""
    g = spec.grid
    dx = si_to_lammps(g.spacing, "length", "particle")
    W = round(g.width / g.spacing) * dx
    D = round(g.depth / g.spacing) * dx
    x_lo = -0.5 * dx if g.symmetric else -W - 0.5 * dx
    y_lo = -0.5 * dx if g.quarter else -W - 0.5 * dx
    xy = (f"{lammps_number(x_lo)} {lammps_number(W + 0.5 * dx)} {lammps_number(y_lo)} "
          f"{lammps_number(W + 0.5 * dx)}")
    nx, ny, nz = g.counts()
    planes = (" (quarter model: symmetry planes x = 0 and y = 0)" if g.quarter else
              " (half model: symmetry plane x = 0)" if g.half else "")
    return [
        f"# ---- block: {nx} x {ny} x {nz} lattice points of spacing {g.spacing:g} m{planes}",
        f"lattice sc {lammps_number(dx)}",
        f"region block block {xy} {lammps_number(-D - 0.5 * dx)} {lammps_number(0.5 * dx)} "
        "units box",
        f"region world block {xy} {lammps_number(-D - 0.5 * dx)} "
        f"{lammps_number(max(top, 0.5 * dx))} units box",
        f"create_box {n_types} world",
    ]


def layer_lines(spec, dx: float) -> list[str]:
    """Particle types by layer, top first: type k for the lattice planes between the
    (k-1)-th and k-th interface; bounds half a spacing off the planes, so a film of
    thickness t gets round(t/dx) planes."""
    lines = []
    top = 0.0
    for k, (t, _) in enumerate(spec.target.films, start=1):
        bottom = top - si_to_lammps(t, "length", "particle")
        lines += [f"region layer{k} block INF INF INF INF {lammps_number(bottom + 0.5 * dx)} "
                  f"{lammps_number(top + 0.5 * dx)} units box",
                  f"set region layer{k} type {k}"]
        top = bottom
    return lines


def weight_group_lines(grid: Grid, member: str) -> list[str]:
    """Groups ``interior``, ``plane`` and ``axis`` of ``member``: in a symmetric model the
    particles on one symmetry plane own half a cell, those on the axis (quarter model) a
    quarter."""
    if not grid.symmetric:
        return [f"group interior union {member}", "group plane empty", "group axis empty"]
    dx = si_to_lammps(grid.spacing, "length", "particle")
    h = lammps_number(0.5 * dx)
    if grid.half:
        return [
            f"region xplane block INF {h} INF INF INF INF units box",
            "group on_x region xplane",
            f"group plane intersect on_x {member}",
            "group axis empty",
            f"group interior subtract {member} plane",
        ]
    return [
        f"region xplane block INF {h} INF INF INF INF units box",
        f"region yplane block INF INF INF {h} INF INF units box",
        "group on_x region xplane",
        "group on_y region yplane",
        f"group axis intersect on_x on_y {member}",
        "group plane_all union on_x on_y",
        f"group plane_m intersect plane_all {member}",
        "group plane subtract plane_m axis",
        f"group interior subtract {member} plane axis",
    ]


def smd_preamble(spec, version: str, dx: float) -> list[str]:
    """The first lines of a MACHDYN (TLSPH or ULSPH) input: SI units, shrink-wrapped
    boundaries (periodic ones delete particles or blow up), atom style ``smd``."""
    return [
        *_header(spec, version),
        "units si",
        "dimension 3",
        "boundary s s s",
        "atom_style smd",
        "atom_modify map array",
        "comm_modify vel yes",
        "newton off",
        f"neighbor {lammps_number(0.5 * dx)} bin",
        "neigh_modify every 10 delay 0 check yes",
    ]


def smd_boundary_lines(grid: Grid, D: float, dx: float) -> list[str]:
    """MACHDYN's boundary conditions: the rigid base at depth ``D`` and zero normal velocity
    on the symmetry planes (``smd/setvel``), particle units."""
    lines = [
        "# ---- boundary conditions: rigid base, symmetry planes (normal velocity zero)",
        f"region base block INF INF INF INF INF {lammps_number(-D + 0.5 * dx)} units box",
        "group base_all region base",
        "group base intersect base_all target",
        "fix base base smd/setvel 0 0 0",
    ]
    if grid.symmetric:
        lines += ["group sym_x intersect on_x target", "fix sym_x sym_x smd/setvel 0 NULL NULL"]
    if grid.quarter:
        lines += ["group sym_y intersect on_y target", "fix sym_y sym_y smd/setvel NULL 0 NULL"]
    return lines


def _indent_fix_lines(spec, K: float, geometries: dict[str, str],
                      scale: float = 1.0) -> list[str]:
    """One ``fix indent`` per geometry (named by its key) and weight group (K times the
    weight), and the total load ``v_load`` (mN, upward force on the indenter, times the
    symmetry factor). ``scale`` turns a fix's force into a force (the particle volume for
    PERI's force densities)."""
    lines = []
    terms = []
    groups = (("interior", 1.0), ("plane", 0.5), ("axis", 0.25))[:3 if spec.grid.quarter else
                                                                 2 if spec.grid.half else 1]
    for name, geometry in geometries.items():
        for group, w in groups:
            lines.append(f"fix {name}_{group} {group} indent {lammps_number(K * w / scale)} "
                         f"{geometry} units box")
            terms.append(f"f_{name}_{group}[3]")
    mult = spec.grid.symmetry_factor * scale
    lines.append(f"variable load equal {lammps_number(mult)}*({'+'.join(terms)})")
    return lines


def _sphere_geometry(R: float, centre: str) -> str:
    return f"sphere 0 0 {centre} {lammps_number(R)}"


def _cone_geometry(tip: Cone, apex: str, height: float, dx: float) -> str:
    # the tip's own apex flat; fix indent needs radlo > 0, so a sharp tip is truncated at
    # a radius of 1 % of a spacing
    r0 = si_to_lammps(tip.tip_radius, "length", "particle") if tip.tip_radius > 0 else 0.01 * dx
    r1 = r0 + height * math.tan(math.radians(tip.half_angle))
    return (f"cone z 0 0 {lammps_number(r0)} {lammps_number(r1)} v_{apex} "
            f"v_{apex}_top")


def _sphero_conical_lines(tip: SphericalCone, height: float) -> tuple[list[str], dict]:
    """A sphere of radius R at the apex and the cone frustum tangent to it from
    h_a = R (1 - sin theta) above the apex (radius R cos theta) upward: two ``fix indent``
    whose solids meet on the tangent circle, so a particle outside the tip feels one."""
    R = si_to_lammps(tip.R, "length", "particle")
    theta = math.radians(tip.half_angle)
    r_t = R * math.cos(theta)
    lines = [f"variable zc equal -v_depth+{lammps_number(R)}",
             f"variable tangent equal -v_depth+{lammps_number(R * (1 - math.sin(theta)))}",
             f"variable tangent_top equal v_tangent+{lammps_number(height)}"]
    return lines, {"ind": _sphere_geometry(R, "v_zc"),
                   "frustum": f"cone z 0 0 {lammps_number(r_t)} "
                              f"{lammps_number(r_t + height * math.tan(theta))}"
                              " v_tangent v_tangent_top"}


def _pyramid_lines(spec, K: float, dx: float, scale: float = 1.0) -> list[str]:
    """A sharp three-sided pyramid with its apex at ``v_apex`` on the z axis, faces at the
    tip's face angle, one face normal along +y (so x = 0 is a mirror plane).

    ``fix indent`` has no pyramid, so the force is written out as per-atom variables: a particle inside the pyramid, at
    depth d under its nearest face (the face whose plane is closest, s_k = N_k . (x - apex)
    largest and negative), is pushed along that face's outward normal N_k with K d^2, fix
    indent's law, K weighted as in `_indent_fix_lines`. Only the particles the tip can reach
    (group ``near``) are evaluated."""
    tip = spec.tip
    face = math.radians(PYRAMID_FACE_ANGLES[tip.name])
    normals = [tuple(round(c, 12) for c in (math.cos(face) * math.cos(math.radians(phi)),
                                            math.cos(face) * math.sin(math.radians(phi)),
                                            -math.sin(face)))
               for phi in (90.0, 210.0, 330.0)]
    h_max = si_to_lammps(spec.loading.depth, "length", "particle")
    reach = si_to_lammps(contact_radius(tip, spec.loading.depth), "length", "particle") + 2 * dx
    lines = [
        "# ---- the pyramid: three faces through the apex; a particle inside is pushed out of",
        "#      its nearest face with K d^2 (fix indent's law)",
        f"region near cylinder z 0 0 {lammps_number(reach)} {lammps_number(-h_max - 2 * dx)} "
        f"{lammps_number(0.5 * dx)} units box",
        "group near_all region near    # the particles the tip can reach",
        "group near intersect near_all target",
    ]
    for k, (nx, ny, nz) in enumerate(normals, start=1):
        lines.append(f"variable s{k} atom {lammps_number(nx)}*x+{lammps_number(ny)}*y"
                     f"+{lammps_number(nz)}*(z-v_apex)")
    for k in range(1, 4):
        others = [j for j in range(1, 4) if j != k]
        # ties (measure zero) would count two faces; >= against the lower index only
        lines.append(f"variable d{k} atom (v_s{k}>{'=' if others[0] > k else ''}v_s{others[0]})"
                     f"*(v_s{k}>{'=' if others[1] > k else ''}v_s{others[1]})"
                     f"*(v_s{k}<0)*v_s{k}*v_s{k}")
    weight = "1"
    if spec.grid.symmetric:
        weight += "-0.5*gmask(plane)" + ("-0.75*gmask(axis)" if spec.grid.quarter else "")
    lines.append(f"variable kw atom {lammps_number(K / scale)}*({weight})")
    for axis, i in (("x", 0), ("y", 1), ("z", 2)):
        terms = "+".join(f"v_d{k}*({lammps_number(n[i])})" for k, n in enumerate(normals, start=1))
        lines.append(f"variable f{axis} atom v_kw*({terms})")
    mult = spec.grid.symmetry_factor * scale
    lines += ["fix pyramid near addforce v_fx v_fy v_fz",
              "compute pyramid_z near reduce sum v_fz",
              f"variable load equal {lammps_number(-mult)}*c_pyramid_z"]
    return lines


def _tlsph_material(m: ParticleMaterial) -> str:
    mat = m.material
    rho = si_to_lammps(m.density, "density", "particle")
    E = si_to_lammps(mat.E, "pressure", "particle")
    common = (f"*COMMON {lammps_number(rho)} {lammps_number(E)} {lammps_number(mat.nu)} "
              f"{TLSPH_Q1} {TLSPH_Q2} {TLSPH_HOURGLASS} 1.0")
    if m.elastic:
        strength = "*STRENGTH_LINEAR"
    elif mat.n == 0.0:
        strength = f"*STRENGTH_LINEAR_PLASTIC {lammps_quantity(mat.sigma_y, 'pressure')} 0"
    else:
        A, B, N = johnson_cook_hardening(mat)
        # no rate and no thermal term: C = 0 and the melting point far away
        strength = (f"*JOHNSON_COOK {lammps_quantity(A, 'pressure')} "
                    f"{lammps_quantity(B, 'pressure')} {lammps_number(N)} 0 1 0 1e30 1")
    return f"{common} {strength} *EOS_LINEAR *END"


def tlsph_material(m: ParticleMaterial) -> str:
    """The ``pair_coeff`` keywords of ``m`` for ``smd/tlsph`` (what the particle scratch,
    `filmscale.md.particle_scratch`, shares with the indentation)."""
    return _tlsph_material(m)


def johnson_cook_hardening(mat: ElasticPlastic) -> tuple[float, float, float]:
    """Johnson-Cook strain hardening A + B eps_p^N (Pa, Pa, -; Johnson & Cook 1983, without
    its rate and thermal factors) matching the power law sigma_y (1 + E eps_p / sigma_y)^n
    (Dao et al. 2001; docs/physics.md section 10) at A = sigma_y and at the plastic strains
    `JC_STRAINS` (MACHDYN has no power-law hardening of that form)."""
    sy, E, n = mat.sigma_y, mat.E, mat.n
    e1, e2 = JC_STRAINS
    d1, d2 = (sy * (1 + E * e / sy)**n - sy for e in (e1, e2))
    N = math.log(d2 / d1) / math.log(e2 / e1)
    return sy, d1 / e1**N, N


def _header(spec, version: str) -> list[str]:
    g = spec.grid
    return [
        f"# filmscale {version} particle model ({spec.method}): {spec.name}".replace("  ", " "),
        f"# {g.n_particles} target particles, spacing {g.spacing:g} m",
        "# units: LAMMPS 'si' carrying um, GPa, ns (mass pg, force mN, density pg/um^3);",
        "#        filmscale.md.lammps_units.PARTICLE converts them",
        f"# replay: lmp -in in.{spec.method}  (in this directory)",
    ]


def _impactor_top(spec, dx: float) -> float:
    """Height of the box's top in an impact: above the cluster, which starts at the sphere
    centre (particle units)."""
    return si_to_lammps(spec.tip.R, "length", "particle") + 2.0 * dx


def _impactor_lines(spec: ParticleImpactSpec, dx: float, create: str) -> list[str]:
    """A 3 x 3 x 3 cluster, unbonded to the target, at the sphere centre's height above the
    block's far corner (it never comes near the target): its height carries the sphere
    centre, its mass the sphere's (a quarter in a quarter model)."""
    g = spec.grid
    W = round(g.width / g.spacing) * dx
    x0 = W - dx
    z0 = si_to_lammps(spec.tip.R, "length", "particle")
    return [
        "# ---- the impactor: an unbonded particle cluster carries the sphere's mass; its",
        "#      height drives the indenter and the indenter's reaction drives it",
        f"region imp block {lammps_number(x0 - 1.5 * dx)} {lammps_number(x0 + 1.5 * dx)} "
        f"{lammps_number(x0 - 1.5 * dx)} {lammps_number(x0 + 1.5 * dx)} "
        f"{lammps_number(z0 - 1.5 * dx)} {lammps_number(z0 + 1.5 * dx)} units box",
        create,
        "group imp region imp",
    ]


def _tlsph_input(spec, version: str) -> str:
    impact = isinstance(spec, ParticleImpactSpec)
    g = spec.grid
    mat = spec.target.substrate
    dx, D, R, E_star = particle_scales(spec)
    vol = dx**3
    lines = [
        *smd_preamble(spec, version, dx),
        *block_lines(spec, 2 if impact else 1, _impactor_top(spec, dx) if impact else 0.0),
        "create_atoms 1 region block",
        "group target type 1",
        "set group target mol 1",
    ]
    if impact:
        # the cluster is type 2, outside TLSPH (pair none, integrated by nve): as a TLSPH
        # body of 27 heavy particles it drifted into its zero-energy modes, and the
        # particles TLSPH then failed lost their velocity (e = 0.88 at R/10)
        lines += _impactor_lines(spec, dx, "create_atoms 2 region imp")
        lines += ["set group imp mol 2", "group target subtract all imp"]
    lines += [
        *weight_group_lines(g, "target"),
        f"set group all volume {lammps_number(vol)}",
        f"set group plane volume {lammps_number(vol / 2)}",
        f"set group axis volume {lammps_number(vol / 4)}",
        f"set group all smd/mass/density {lammps_quantity(mat.density, 'density')}",
        f"set group all diameter {lammps_number(TLSPH_KERNEL * dx)}",
        f"set group all smd/contact/radius {lammps_number(0.5 * dx)}",
        "group tlsph type 1    # the name MACHDYN requires",
        "",
        "# ---- material (SI values converted to um, GPa, ns)",
        *(["pair_style hybrid smd/tlsph", f"pair_coeff 1 1 smd/tlsph {_tlsph_material(mat)}",
           "pair_coeff 1 2 none", "pair_coeff 2 2 none"] if impact else
          ["pair_style smd/tlsph", f"pair_coeff 1 1 {_tlsph_material(mat)}"]),
        "",
        *smd_boundary_lines(g, D, dx),
        f"fix dtfix all smd/adjust_dt {CFL}",
        "fix integration tlsph smd/integrate_tlsph",
        *(["fix impactor imp nve"] if impact else []),
        "variable t equal f_dtfix    # simulated time (the timestep adapts)",
        "compute stress all smd/tlsph/stress",
        "compute ep all smd/plastic/strain",
        "",
    ]
    K = K_FACTOR * E_star
    if impact:
        lines += _impact_driver(spec, dx, R, K)
    else:
        lines += indent_driver_lines(spec, dx, R, K, D)
    lines += run_lines(spec, "mol x y z c_stress[7] c_ep")
    return assemble_input(spec, lines)


def assemble_input(spec, lines: list[str]) -> str:
    """The input text of ``lines``, with the record interval (~1/400 of the run's estimated
    steps) filled in for ``{every}``."""
    every = max(1, estimated_steps(spec) // 400)
    return "\n".join(ln.replace("{every}", str(every)) for ln in lines) + "\n"


def _record_row(impact: bool) -> str:
    """One record line: the LAMMPS variables behind IMPACT_COLUMNS or INDENT_COLUMNS."""
    names = ("t", "approach", "load", "vz") if impact else ("t", "depth", "load", "apex_z")
    return " ".join(f"$(v_{n}:%.10g)" for n in names)


def indent_driver_lines(spec: ParticleIndentSpec, dx: float, R: float | None, K: float,
                        D: float, scale: float = 1.0) -> list[str]:
    """The displacement-controlled indenter of ``spec`` (down, hold, up), its penalty
    contact of stiffness ``K`` and the record of depth, load and apex (particle units)."""
    p = spec.loading
    v = si_to_lammps(p.speed, "velocity", "particle")
    t1, t2, _ = (si_to_lammps(t, "time", "particle") for t in p.times)
    down = _clamp_min("v_t", lammps_number(t1))
    up = f"0.5*((v_t-{lammps_number(t2)})+abs(v_t-{lammps_number(t2)}))"
    lines = [
        "# ---- displacement control: down at constant speed, hold, up",
        f"variable depth equal {lammps_number(v)}*({down})-{lammps_number(v)}*({up})",
    ]
    if isinstance(spec.tip, Sphere):
        lines.append(f"variable zc equal {lammps_number(R)}-v_depth")
        lines += _indent_fix_lines(spec, K, {"ind": _sphere_geometry(R, "v_zc")}, scale)
    elif is_pyramid(spec.tip):
        lines += ["variable apex equal -v_depth", *_pyramid_lines(spec, K, dx, scale)]
    elif isinstance(spec.tip, SphericalCone):
        tip_lines, geometries = _sphero_conical_lines(spec.tip, D)
        lines += [*tip_lines, *_indent_fix_lines(spec, K, geometries, scale)]
    else:
        lines += ["variable apex equal -v_depth",
                  f"variable apex_top equal v_apex+{lammps_number(D)}"]
        lines += _indent_fix_lines(spec, K, {"ind": _cone_geometry(spec.tip, "apex", D, dx)},
                                   scale)
    lines += [
        f"region apex sphere 0 0 0 {lammps_number(0.25 * dx)} units box",
        "group apex region apex",
        "variable apex_z equal xcm(apex,z)    # the surface particle on the axis",
        f'fix record all print {{every}} "{_record_row(False)}" file {RECORD} screen no '
        f'title "# {" ".join(INDENT_COLUMNS)}"',
        "thermo_style custom step dt v_t v_depth v_load",
        "thermo_modify flush yes",
    ]
    return lines


def _impact_driver(spec: ParticleImpactSpec, dx: float, R: float, K: float,
                   scale: float = 1.0, imp_mass_scale: float = 1.0) -> list[str]:
    m = si_to_lammps(spec.mass, "mass", "particle") / spec.grid.symmetry_factor
    V = si_to_lammps(spec.velocity, "velocity", "particle")
    return [
        "# ---- the free sphere: touching the surface at t = 0, moving down at V",
        "variable n_imp equal count(imp)",
        f"variable m_imp equal {lammps_number(m * imp_mass_scale)}/v_n_imp",
        "set group imp mass ${m_imp}",
        "variable z_imp0 equal $(xcm(imp,z))",
        f"variable zc equal {lammps_number(R)}+xcm(imp,z)-v_z_imp0",
        f"variable approach equal {lammps_number(R)}-v_zc",
        f"velocity imp set 0 0 {lammps_number(-V)} units box",
        *_indent_fix_lines(spec, K, {"ind": _sphere_geometry(R, "v_zc")}, scale),
        "# the reaction on the sphere, spread over the cluster (defined after the indenter",
        "# fixes, so that it reads their force of the same step)",
        f"variable push equal v_load/{lammps_number(spec.grid.symmetry_factor)}/v_n_imp"
        + (f"/{lammps_number(scale)}" if scale != 1.0 else ""),
        "fix push imp addforce 0 0 v_push",
        "variable vz equal vcm(imp,z)",
        f'fix record all print {{every}} "{_record_row(True)}" file {RECORD} screen no '
        f'title "# {" ".join(IMPACT_COLUMNS)}"',
        "thermo_style custom step dt v_t v_approach v_load v_vz",
        "thermo_modify flush yes",
    ]


def estimated_timestep(spec) -> float:
    """The CFL timestep, s: CFL * kernel / P-wave speed for TLSPH (``smd/adjust_dt`` chose
    0.75-1.0 of it in the R/8 runs), or the fixed PERI step. It sizes the record interval,
    the snapshot interval and the step bound of the run, not the integration."""
    c = max(m.wave_speed for m in spec.target.materials)
    if spec.method in ("tlsph", "ulsph"):
        return CFL * TLSPH_KERNEL * spec.grid.spacing / c
    return PERI_DT_FACTOR * spec.grid.spacing / c


def estimated_steps(spec) -> int:
    end = spec.loading.times[2] if isinstance(spec, ParticleIndentSpec) else spec.end_time
    return max(1, math.ceil(end / estimated_timestep(spec)))


def run_lines(spec, fields: str) -> list[str]:
    """Record every ~1/400 of the run, snapshots ``frames`` times, stop at the end time
    (a simulated time: the step count is a bound) or when the contact has ended."""
    impact = isinstance(spec, ParticleImpactSpec)
    steps = estimated_steps(spec)
    frames = spec.frames if impact else spec.loading.frames
    end = si_to_lammps(spec.end_time if impact else spec.loading.times[2], "time", "particle")
    lines = [f"thermo {max(1, steps // 50)}"]
    if frames:
        lines.append(f"dump fields all custom {max(1, steps // frames)} fields.*.dump id type "
                     f"{fields}")
        lines.append("dump_modify fields first yes")
    lines.append(f"variable finished equal v_t>={lammps_number(end)}")
    if impact:
        # the sphere has left: moving up with no contact force
        lines.append("variable stop equal v_finished+(v_vz>0)*(v_load<=0)")
    else:
        # or the tip has left the surface while unloading (a plastic residual impression
        # would otherwise cost up to half the run)
        t2 = si_to_lammps(spec.loading.times[1], "time", "particle")
        lines.append(f"variable stop equal v_finished+(v_t>{lammps_number(t2)})*(v_load<=0)")
    # the state where the run halted closes the record (the halt test and the record
    # interval differ, so the last recorded point may still carry load)
    lines += [
        "fix halt all halt 10 v_stop > 0.5 error continue message no",
        f"run {3 * steps + 1000}",
        f'print "{_record_row(impact)}" append {RECORD} screen no',
        'print "finished $(v_t:%.10g)" file finished.txt screen no',
    ]
    return lines


def input_text(spec, version: str = "") -> str:
    """The complete LAMMPS input of ``spec`` (an indentation or an impact, either method)."""
    if spec.method == "tlsph":
        return _tlsph_input(spec, version)
    if spec.method == "ulsph":
        from filmscale.md.ulsph_inputs import ulsph_input
        return ulsph_input(spec, version)
    return peri_input(spec, version)


def _peri_coeff(m: ParticleMaterial, horizon: float) -> str:
    """``K G horizon s00 alpha`` of peri/lps: bulk and shear modulus from E and nu; a critical
    stretch s00 = 1 so that no bond breaks (the model is elastic)."""
    K, G = m.material.bulk_modulus, m.material.shear_modulus
    return (f"{lammps_quantity(K, 'pressure')} {lammps_quantity(G, 'pressure')} "
            f"{lammps_number(horizon)} 1.0 0.0")


def peri_input(spec, version: str = "") -> str:
    """The complete LAMMPS input of a peridynamic (peri/lps) indentation or impact.

    PERI integrates force densities with rmass = density: ``fix indent``'s K is divided by
    the particle volume V and its force multiplied by V (docs/lammps.md, particle traps)."""
    impact = isinstance(spec, ParticleImpactSpec)
    g = spec.grid
    dx, D, R, E_star = particle_scales(spec)
    vol = dx**3
    horizon = PERI_HORIZON * dx
    mats = spec.target.materials
    n_types = len(mats)
    lines = [
        *_header(spec, version),
        "units si",
        "dimension 3",
        "boundary s s s",
        "atom_style peri",
        "atom_modify map array",
        f"neighbor {lammps_number(0.5 * dx)} bin"
        "    # the SI default skin (1 mm) would be everything",
        "neigh_modify every 1 delay 0 check yes",
        *block_lines(spec, n_types, _impactor_top(spec, dx) if impact else 0.0),
        f"create_atoms {n_types} region block",
    ]
    lines += [*layer_lines(spec, dx), "group target union all"]
    if impact:
        lines += _impactor_lines(spec, dx, f"create_atoms {n_types} region imp")
        lines += ["group target subtract all imp"]
    lines += [
        *weight_group_lines(g, "target"),
        f"set group all volume {lammps_number(vol)}",
        "",
        "# ---- materials (SI values converted to um, GPa, ns); rmass is the density",
    ]
    for k, m in enumerate(mats, start=1):
        lines.append(f"set type {k} density {lammps_quantity(m.density, 'density')}")
    if n_types == 1:
        lines += ["pair_style peri/lps", f"pair_coeff 1 1 {_peri_coeff(mats[0], horizon)}"]
    else:
        # peri/lps takes each particle's own type for a bond and ignores the cross
        # coefficients, so bonds across an interface break Newton's third law; the bond-based
        # peri/pmb has true cross springs (harmonic mean of the two bulk moduli)
        lines.append("pair_style peri/pmb")
        for i in range(1, n_types + 1):
            for j in range(i, n_types + 1):
                Ki, Kj = mats[i - 1].material.bulk_modulus, mats[j - 1].material.bulk_modulus
                K = si_to_lammps(2 * Ki * Kj / (Ki + Kj), "pressure", "particle")
                spring = 18 * K / (math.pi * horizon**4)
                lines.append(f"pair_coeff {i} {j} {lammps_number(spring)} "
                             f"{lammps_number(horizon)} 1.0 0.0")
    c = max(m.wave_speed for m in mats)
    dt = si_to_lammps(PERI_DT_FACTOR * g.spacing / c, "time", "particle")
    lines += [
        "",
        "# ---- rigid base; fixed timestep (PERI has no adaptive step)",
        f"region base block INF INF INF INF INF {lammps_number(-D + 0.5 * dx)} units box",
        "group base_all region base",
        "group base intersect base_all target",
        "velocity all set 0 0 0",
        "fix integration all nve",
        "fix base base setforce 0 0 0",
        f"timestep {lammps_number(dt)}",
        "variable t equal time",
        "compute damage all damage/atom",
        "",
    ]
    K = K_FACTOR * E_star
    if impact:
        lines += _impact_driver(spec, dx, R, K, scale=vol, imp_mass_scale=1.0 / vol)
    else:
        lines += indent_driver_lines(spec, dx, R, K, D, scale=vol)
    # the snapshot carries the bond damage (0 while elastic); PERI has no stress compute
    lines += run_lines(spec, "x y z c_damage")
    return assemble_input(spec, lines)
