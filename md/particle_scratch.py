"""Particle scratch: the stroke of `filmscale.md.scratch` on the TLSPH continuum of
`filmscale particles indent`, its spec, presets and LAMMPS input.

A rigid frictionless sphere (``fix indent``, the penalty contact of the particle indentation)
moves on a closed-form path of the simulated time t (TLSPH's timestep adapts, so the path is
a function of ``f_dtfix``'s accumulated time, not of the step): down at ``scratch.load_speed``
to ``scratch.depth`` below the undeformed surface, along +x at ``scratch.speed`` over
``scratch.length`` (``passes`` > 1: back along -x, forth again, ...), up at the load speed to
where it started, then ``relax_time`` for the residual groove:

    depth(t) = v_n (clamp(t, 0, t_1) - clamp(t - t_u, 0, t_1)),     t_1 = depth / v_n
    x_tip(t) = v_s sum_k (-1)^k clamp(t - t_1 - k T, 0, T),          T = length / v_s

with t_u = t_1 + passes T and clamp(a, 0, c) = (|a| - |a - c| + c) / 2, written into the
input as equal-style variables of ``v_t`` (`path_formulas`; `tip_path` is the same path in
Python). Forces are those of ``fix indent`` on the indenter: normal = z, lateral = -F_x on a
pass along +x (+F_x on a pass back), so that a force resisting the motion is positive.

The block: a cube lattice of ``grid.spacing`` with its surface z = 0, from x = -width to
x = length + width along the stroke, y in [-width, width] (``half``: y >= 0 with the mirror
plane y = 0, the one symmetry a scratch keeps; particles on it carry half a cell and half the
penalty stiffness, forces are doubled), ``grid.depth`` down to the rigid base.

Two particle methods: ``tlsph`` (MACHDYN's total-Lagrangian SPH, one body: homogeneous
targets) and ``ulsph`` (updated-Lagrangian SPH with ``*CROSS`` pairs, `filmscale.md.ulsph_inputs`:
films bonded to their substrate, one particle type per layer, top film first). A film takes
round(t / spacing) lattice planes and must span at least `MIN_FILM_PLANES` of them.
"""

from __future__ import annotations

import copy
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation.tips import Sphere, Tip, parse_tip
from filmscale.core.checks import check_keys, check_path, check_real, required
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.md.lammps_units import si_to_lammps
from filmscale.md.particle_inputs import (CFL, K_FACTOR, TLSPH_KERNEL, lammps_number,
                                          lammps_quantity, smd_preamble, tlsph_material)
from filmscale.md.particle_spec import target_from_table
from filmscale.md.particle_inputs import layer_lines
from filmscale.md.particles import (MIN_RADIUS_SPACINGS, ParticleTarget, check_block,
                                    contact_radius)
from filmscale.md.ulsph_inputs import ULSPH_SETTINGS, ulsph_material
from filmscale.potentials.lammps_words import check_name, shown

#: The record (``fix print``) and its columns: time (ns), tip x and depth (um), the forces on
#: the indenter (mN, whole model).
RECORD = "scratch.dat"
COLUMNS = ("time", "x_tip", "depth", "fx", "fz")
#: The final field dump (after the relaxation): positions and plastic strain.
FINAL_DUMP = "final.dump"
METHODS = ("tlsph", "ulsph")
#: the fewest lattice planes a film may span (one plane is a skin, not a layer)
MIN_FILM_PLANES = 2


def _length(name: str, value) -> float:
    return check_real(name, value, low=1e-10, high=1e-1, low_open=False, unit="m")


@dataclass(frozen=True)
class ScratchGrid:
    """The scratch block, SI: lattice ``spacing``, ``width`` from the scratch axis (y = 0) to
    the sides and ahead of and behind the stroke, ``depth`` from the surface to the rigid base;
    ``half`` keeps y >= 0 with the mirror plane y = 0. ``length`` (the stroke's) is set by
    the spec."""

    spacing: float
    width: float
    depth: float
    half: bool = True
    length: float = 0.0

    def __post_init__(self):
        check_block(self.spacing, self.width, self.depth)
        if not isinstance(self.half, bool):
            raise InputError(f"grid.half = {shown(self.half)} is not true or false")

    def lattice_bounds(self) -> tuple[int, int, int, int, int]:
        """Lattice indices: x from -i_lo to i_hi, y from -j (0 in a half model) to j, z from
        -k to 0 (the first three are (i_lo, i_hi, j, j_lo, k))."""
        dx = self.spacing
        i_lo = math.ceil(self.width / dx - 1e-9)
        i_hi = math.ceil((self.length + self.width) / dx - 1e-9)
        j = math.ceil(self.width / dx - 1e-9)
        return i_lo, i_hi, j, 0 if self.half else -j, round(self.depth / dx)

    @property
    def n_particles(self) -> int:
        i_lo, i_hi, j, j_lo, k = self.lattice_bounds()
        return (i_lo + i_hi + 1) * (j - j_lo + 1) * (k + 1)

    @property
    def symmetry_factor(self) -> float:
        return 2.0 if self.half else 1.0


@dataclass(frozen=True)
class ParticleStroke:
    """The stroke, SI: ``depth`` (m) below the undeformed surface, ``length`` (m) of a pass,
    ``speed`` (m/s) along x, ``load_speed`` (m/s) down and up (default ``speed``),
    ``passes``, ``relax_time`` (s) after the withdrawal, ``frames`` field snapshots."""

    depth: float
    length: float
    speed: float = 50.0
    load_speed: float | None = None
    passes: int = 1
    relax_time: float = 1e-9
    frames: int = 3

    def __post_init__(self):
        _length("scratch.depth", self.depth)
        _length("scratch.length", self.length)
        check_real("scratch.speed", self.speed, low=1e-6, high=1e4, unit="m/s")
        if self.load_speed is None:
            object.__setattr__(self, "load_speed", self.speed)
        check_real("scratch.load_speed", self.load_speed, low=1e-6, high=1e4, unit="m/s")
        check_real("scratch.relax_time", self.relax_time, low=0.0, high=1.0, unit="s")
        for key, high in (("passes", 10), ("frames", 1000)):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int) or \
                    not (1 if key == "passes" else 0) <= value <= high:
                raise InputError(f"scratch.{key} = {shown(value)} must be an integer in "
                                 f"[{1 if key == 'passes' else 0}, {high}]")

    @property
    def times(self) -> tuple[float, float, float, float]:
        """End of the descent t_1, the pass duration T, start of the withdrawal t_u and the
        end of the run, s."""
        t1 = self.depth / self.load_speed
        T = self.length / self.speed
        tu = t1 + self.passes * T
        return t1, T, tu, tu + t1 + self.relax_time


def _clamp(a: np.ndarray, c: float) -> np.ndarray:
    return 0.5 * (np.abs(a) - np.abs(a - c) + c)


def tip_path(stroke: ParticleStroke, t) -> tuple[np.ndarray, np.ndarray]:
    """(x_tip, depth) of the indenter at time ``t`` (s), m: the closed form of the module
    docstring."""
    t = np.asarray(t, dtype=float)
    t1, T, tu, _ = stroke.times
    depth = stroke.load_speed * (_clamp(t, t1) - _clamp(t - tu, t1))
    x = stroke.speed * sum((-1) ** k * _clamp(t - t1 - k * T, T) for k in range(stroke.passes))
    return x, depth


def path_direction(stroke: ParticleStroke, t) -> np.ndarray:
    """+1 on a pass along +x, -1 on a pass back, 0 off the stroke."""
    t = np.asarray(t, dtype=float)
    t1, T, tu, _ = stroke.times
    k = np.floor((t - t1) / T)
    on = (t > t1) & (t < tu)
    return np.where(on, np.where(k % 2 == 0, 1, -1), 0)


def path_formulas(stroke: ParticleStroke) -> dict[str, str]:
    """``depth`` and ``x_tip`` (particle units: um of ``v_t`` in ns) as LAMMPS equal-style
    formulas: numbers, ``v_t``, ``abs``, + - * and parentheses only."""
    t1, T, tu, _ = (si_to_lammps(x, "time", "particle") for x in stroke.times)
    vn = si_to_lammps(stroke.load_speed, "velocity", "particle")
    vs = si_to_lammps(stroke.speed, "velocity", "particle")
    n = lammps_number

    def clamp(a: str, c: float) -> str:
        return f"0.5*(abs({a})-abs({a}-{n(c)})+{n(c)})"

    depth = f"{n(vn)}*({clamp('v_t', t1)}-{clamp(f'(v_t-{n(tu)})', t1)})"
    terms = [("+" if k % 2 == 0 else "-") + clamp(f"(v_t-{n(t1 + k * T)})", T)
             for k in range(stroke.passes)]
    return {"depth": depth, "x_tip": f"{n(vs)}*({''.join(terms).removeprefix('+')})"}


@dataclass(frozen=True)
class ParticleScratchSpec:
    """A particle scratch: the target (homogeneous for ``tlsph``, layered or not for
    ``ulsph``), a sphere, the block and the stroke."""

    name: str
    target: ParticleTarget
    tip: Tip
    grid: ScratchGrid
    stroke: ParticleStroke
    method: str = "tlsph"

    def __post_init__(self):
        check_name("name", self.name)
        tip = parse_tip(self.tip)
        if not isinstance(tip, Sphere):
            raise InputError(f"tip = {tip.spec!r}: the particle scratch takes a sphere "
                             "(sphere:R); LAMMPS's fix indent cone pushes particles away from "
                             "its mid-axis point, not along its flank, so a scratching cone's "
                             "lateral force would not be ploughing (docs/particles.md)")
        object.__setattr__(self, "tip", tip)
        if self.method not in METHODS:
            raise InputError(f"method = {shown(self.method)} is not one of {', '.join(METHODS)}")
        if self.method == "tlsph" and self.target.layered:
            raise InputError("target.films: TLSPH bonds one body of one material; a layered "
                             "target needs method = 'ulsph'")
        for k, (t, _) in enumerate(self.target.films):
            if round(t / self.grid.spacing) < MIN_FILM_PLANES:
                raise InputError(f"films[{k}].thickness = {t:g} m spans under "
                                 f"{MIN_FILM_PLANES} lattice planes of grid.spacing "
                                 f"{self.grid.spacing:g} m; valid: >= "
                                 f"{MIN_FILM_PLANES * self.grid.spacing:g} m")
        films = sum(t for t, _ in self.target.films)
        if films and self.grid.depth < films + 2 * self.grid.spacing:
            raise InputError(f"grid.depth = {self.grid.depth:g} m leaves under 2 spacings of "
                             f"substrate below the films ({films:g} m); valid: >= "
                             f"{films + 2 * self.grid.spacing:g} m")
        g = self.grid
        object.__setattr__(self, "grid", ScratchGrid(g.spacing, g.width, g.depth, g.half,
                                                     self.stroke.length))
        dx, a = g.spacing, self.contact_radius
        if tip.R < MIN_RADIUS_SPACINGS * dx:
            raise InputError(f"grid.spacing = {dx:g} m is too coarse for the sphere radius "
                             f"{tip.R:g} m; valid: spacing <= R/{MIN_RADIUS_SPACINGS:g}")
        if a < 2 * dx:
            raise InputError(f"grid.spacing = {dx:g} m: the contact radius at scratch.depth "
                             f"({a:g} m) spans under 2 spacings; valid: spacing <= {a / 2:g} m")
        if g.width < 2 * a:
            raise InputError(f"grid.width = {g.width:g} m is under twice the contact radius "
                             f"({2 * a:g} m); valid: >= {2 * a:g} m")
        if g.depth < 2 * max(a, self.stroke.depth):
            need = 2 * max(a, self.stroke.depth)
            raise InputError(f"grid.depth = {g.depth:g} m is under {need:g} m (twice the "
                             f"contact radius and the depth); valid: >= {need:g} m")
        c = min(m.wave_speed for m in self.target.materials)
        for key in ("speed", "load_speed"):
            v = getattr(self.stroke, key)
            if v > 0.05 * c:
                raise InputError(f"scratch.{key} = {v:g} m/s is not quasi-static; valid: "
                                 f"<= 5 % of the wave speed, {0.05 * c:.4g} m/s")

    @property
    def contact_radius(self) -> float:
        return contact_radius(self.tip, self.stroke.depth)

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": "scratch", "method": self.method,
                "target": self.target.to_dict(), "tip": self.tip.spec,
                "grid": asdict(self.grid), "scratch": asdict(self.stroke)}


# ---- spec files and presets -------------------------------------------------------------------

_R = 1e-6
#: the two-layer target of the quick and research presets: a hard elastic-plastic film on a
#: softer layer (the chapter 7 case; docs/particles.md, "Layered scratch")
_HARD_ON_SOFT = {
    "substrate": {"name": "soft", "E": 70e9, "nu": 0.3, "sigma_y": 1.5e9, "density": 2700.0},
    "films": [{"name": "hard", "thickness": 0.375 * _R, "E": 200e9, "nu": 0.25,
               "sigma_y": 10e9, "density": 7800.0}]}
PRESETS = {
    # elastic Al, the indentation ci preset's material, spacing, depth and speed
    "ci": {"name": "ci-elastic-scratch", "tip": "sphere:1um",
           "target": {"substrate": {"E": 70e9, "nu": 0.3, "density": 2700.0}},
           "grid": {"spacing": _R / 5, "width": 1.2 * _R, "depth": 1.2 * _R},
           "scratch": {"depth": 0.1 * _R, "length": 1.0 * _R, "speed": 100.0,
                       "load_speed": 50.0, "relax_time": 1e-9, "frames": 0}},
    # the hard film on a softer layer, R/8, 7 215 particles (the measured case)
    "quick": {"name": "quick-hard-film-scratch", "method": "ulsph", "tip": "sphere:1um",
              "target": _HARD_ON_SOFT,
              "grid": {"spacing": _R / 8, "width": 1.75 * _R, "depth": 1.5 * _R},
              "scratch": {"depth": 0.15 * _R, "length": 1.0 * _R, "speed": 100.0,
                          "load_speed": 50.0, "relax_time": 1e-9, "frames": 2}},
    # the same at R/16 on a wider, deeper block and a longer stroke, for MPI on many cores
    "research": {"name": "research-hard-film-scratch", "method": "ulsph",
                 "tip": "sphere:1um", "target": _HARD_ON_SOFT,
                 "grid": {"spacing": _R / 16, "width": 2.5 * _R, "depth": 2.5 * _R},
                 "scratch": {"depth": 0.15 * _R, "length": 2.0 * _R, "speed": 100.0,
                             "load_speed": 50.0, "relax_time": 2e-9, "frames": 10}},
}


def spec_from_mapping(data: dict) -> ParticleScratchSpec:
    """A spec from a parsed TOML table: name, method, tip, [target], [grid] (spacing, width,
    depth, half), [scratch] (depth, length, speed, load_speed, passes, relax_time, frames)."""
    data = check_keys("spec", data, {"name", "method", "tip", "target", "grid", "scratch"})
    for key in ("target", "grid", "scratch"):
        required("spec", data, key)
    grid = check_keys("grid", data["grid"], {"spacing", "width", "depth", "half"})
    for key in ("spacing", "width", "depth"):
        required("grid", grid, key)
    body = check_keys("scratch", data["scratch"], {"depth", "length", "speed", "load_speed",
                                                   "passes", "relax_time", "frames"})
    for key in ("depth", "length"):
        required("scratch", body, key)
    return ParticleScratchSpec(name=str(data.get("name", "scratch")),
                               method=data.get("method", "tlsph"),
                               target=target_from_table(data["target"]),
                               tip=data.get("tip", "sphere:1um"), grid=ScratchGrid(**grid),
                               stroke=ParticleStroke(**body))


def load_spec(path: Path | str) -> ParticleScratchSpec:
    path = check_path("path", path)
    return spec_from_mapping(read_toml(path, "spec file"))


def preset(name: str) -> ParticleScratchSpec:
    if name not in PRESETS:
        raise InputError(f"preset = {shown(name)} is not one of {sorted(PRESETS)}")
    return spec_from_mapping(copy.deepcopy(PRESETS[name]))


# ---- the LAMMPS input -------------------------------------------------------------------------

def estimated_steps(spec: ParticleScratchSpec) -> int:
    """The CFL step count of the run (`particle_inputs.estimated_timestep`'s SPH step, on the
    stiffest material)."""
    c = max(m.wave_speed for m in spec.target.materials)
    kernel = TLSPH_KERNEL if spec.method == "tlsph" else ULSPH_SETTINGS.kernel
    dt = CFL * kernel * spec.grid.spacing / c
    return max(1, math.ceil(spec.stroke.times[3] / dt))


def _material_lines(spec: ParticleScratchSpec, dx: float) -> list[str]:
    """The particle types, masses, kernels, pair style and time integration of the method."""
    n = lammps_number
    if spec.method == "tlsph":
        return [
            f"set group all smd/mass/density "
            f"{lammps_quantity(spec.target.substrate.density, 'density')}",
            f"set group all diameter {n(TLSPH_KERNEL * dx)}",
            f"set group all smd/contact/radius {n(0.5 * dx)}",
            "group tlsph type 1    # the name MACHDYN requires",
            "",
            "# ---- material (SI values converted to um, GPa, ns)",
            "pair_style smd/tlsph",
            f"pair_coeff 1 1 {tlsph_material(spec.target.substrate)}",
        ]
    mats, u = spec.target.materials, ULSPH_SETTINGS
    lines = [f"set type {k} smd/mass/density {lammps_quantity(m.density, 'density')}"
             for k, m in enumerate(mats, start=1)]
    lines += [
        f"set group all diameter {n(u.kernel * dx)}",
        f"set group all smd/contact/radius {n(0.5 * dx)}",
        "",
        "# ---- materials (SI values converted to um, GPa, ns); *CROSS bonds the layers",
        f"pair_style smd/ulsph *DENSITY_{u.density.upper()} *VELOCITY_GRADIENT "
        f"*{'' if u.gradient_correction else 'NO_'}GRADIENT_CORRECTION",
        *(f"pair_coeff {k} {k} {ulsph_material(m, u)}" for k, m in enumerate(mats, start=1)),
        *(f"pair_coeff {i} {j} *CROSS" for i in range(1, len(mats) + 1)
          for j in range(i + 1, len(mats) + 1)),
    ]
    return lines


def _roller_lines(g: ScratchGrid, dx: float) -> list[str]:
    """Zero normal velocity on the block's sides (ULSPH: a free side face, its kernel
    truncated, flows plastically on its own)."""
    i_lo, i_hi, j, j_lo, _ = g.lattice_bounds()
    n = lammps_number
    lines = [f"region x_ends block {n((-i_lo + 0.5) * dx)} {n((i_hi - 0.5) * dx)} INF INF INF INF "
             "side out units box",
             "group x_ends region x_ends",
             "fix roll_x x_ends smd/setvel 0 NULL NULL",
             f"region y_far block INF INF {n((j_lo + 0.5) * dx if not g.half else -1e9)} "
             f"{n((j - 0.5) * dx)} INF INF side out units box",
             "group y_far region y_far",
             "fix roll_y y_far smd/setvel NULL 0 NULL"]
    return lines


def scratch_input(spec: ParticleScratchSpec, version: str = "") -> str:
    """The complete TLSPH or ULSPH input of ``spec`` (particle units)."""
    g, s = spec.grid, spec.stroke
    dx = si_to_lammps(g.spacing, "length", "particle")
    i_lo, i_hi, j, j_lo, k = g.lattice_bounds()
    n = lammps_number
    lo = (-i_lo - 0.5) * dx, (j_lo - 0.5) * dx, (-k - 0.5) * dx
    hi = (i_hi + 0.5) * dx, (j + 0.5) * dx, 0.5 * dx
    R = si_to_lammps(spec.tip.R, "length", "particle")
    E_star = max(si_to_lammps(m.material.plane_strain_modulus, "pressure", "particle")
                 for m in spec.target.materials)
    K = K_FACTOR * E_star
    vol = dx**3
    steps = estimated_steps(spec)
    every = max(1, steps // 400)
    f = path_formulas(s)
    end = si_to_lammps(s.times[3], "time", "particle")
    half = ("(half model: mirror plane y = 0)" if g.half else "(full block)")
    n_types = len(spec.target.materials)
    integrated = "tlsph" if spec.method == "tlsph" else "target"   # the group MACHDYN needs
    lines = [
        *smd_preamble(spec, version, dx),
        f"# ---- block {half}: x from {-i_lo} to {i_hi}, y from {j_lo} to {j}, z from {-k} to 0 "
        "spacings",
        f"lattice sc {n(dx)}",
        f"region block block {n(lo[0])} {n(hi[0])} {n(lo[1])} {n(hi[1])} {n(lo[2])} "
        f"{n(hi[2])} units box",
        f"region world block {n(lo[0])} {n(hi[0])} {n(lo[1])} {n(hi[1])} {n(lo[2])} "
        f"{n(R + 2 * dx)} units box",
        f"create_box {n_types} world",
        f"create_atoms {n_types} region block",
        *layer_lines(spec, dx),
        "group target union all",
        "set group target mol 1",
    ]
    if g.half:
        lines += [f"region yplane block INF INF INF {n(0.5 * dx)} INF INF units box",
                  "group on_y region yplane",
                  "group plane intersect on_y target",
                  "group interior subtract target plane"]
    else:
        lines += ["group interior union target", "group plane empty"]
    lines += [
        f"set group all volume {n(vol)}",
        f"set group plane volume {n(vol / 2)}",
        *_material_lines(spec, dx),
        "",
        "# ---- rigid base; mirror plane y = 0 (normal velocity zero)",
        f"region base block INF INF INF INF INF {n(-k * dx + 0.5 * dx)} units box",
        "group base_all region base",
        "group base intersect base_all target",
        "fix base base smd/setvel 0 0 0",
        *(["group sym_y intersect on_y target", "fix sym_y sym_y smd/setvel NULL 0 NULL"]
          if g.half else []),
        *(_roller_lines(g, dx) if spec.method == "ulsph" else []),
        f"fix dtfix all smd/adjust_dt {CFL}",
        f"fix integration {integrated} smd/integrate_{spec.method}",
        "variable t equal f_dtfix    # simulated time (the timestep adapts)",
        f"compute stress all smd/{spec.method}/stress",
        "compute ep all smd/plastic/strain",
        "",
        "# ---- the indenter path: closed-form functions of the simulated time",
        f"variable depth equal {f['depth']}",
        f"variable x_tip equal {f['x_tip']}",
        f"variable zc equal {n(R)}-v_depth",
    ]
    groups = (("interior", 1.0), ("plane", 0.5)) if g.half else (("interior", 1.0),)
    for group, w in groups:
        lines.append(f"fix ind_{group} {group} indent {n(K * w)} sphere v_x_tip 0 v_zc {n(R)} "
                     "units box")
    mult = n(g.symmetry_factor)
    for c, i in (("fx", 1), ("fz", 3)):
        lines.append(f"variable {c} equal {mult}*({'+'.join(f'f_ind_{gr}[{i}]' for gr, _ in groups)})")
    row = " ".join(f"$(v_{name}:%.10g)" for name in ("t", "x_tip", "depth", "fx", "fz"))
    lines += [
        f'fix record all print {every} "{row}" file {RECORD} screen no '
        f'title "# {" ".join(COLUMNS)}"',
        "thermo_style custom step dt v_t v_x_tip v_depth v_fx v_fz",
        "thermo_modify flush yes",
        f"thermo {max(1, steps // 50)}",
        "dump fields all custom "
        f"{max(1, steps // s.frames) if s.frames else 10 * steps + 10000} fields.*.dump id "
        "type x y z c_stress[7] c_ep",
        "dump_modify fields first yes",
        f"variable stop equal v_t>={n(end)}",
        "fix halt all halt 10 v_stop > 0.5 error continue message no",
        f"run {3 * steps + 1000}",
        f'print "{row}" append {RECORD} screen no',
        f"write_dump all custom {FINAL_DUMP} id type x y z c_stress[7] c_ep",
        'print "finished $(v_t:%.10g)" file finished.txt screen no',
    ]
    return "\n".join(lines) + "\n"
