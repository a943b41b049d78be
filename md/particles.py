"""Particle continuum models in LAMMPS: the run specs (materials, target, particle grid,
loading) and their validation before any run.

Two discretisations of an elastic(-plastic) solid, both run by LAMMPS from a complete input
file (written by `filmscale.md.particle_inputs`):

- ``tlsph``: total-Lagrangian SPH of the MACHDYN package (``pair_style smd/tlsph``), elastic or
  elastic-plastic (linear or power-law hardening). One bonded body per particle type, so it
  takes homogeneous targets only.
- ``peri``: linear peridynamic solid of the PERI package (``pair_style peri/lps``), elastic,
  with the film and substrate bonded across their interface: the layered targets.
- ``ulsph``: updated-Lagrangian SPH of MACHDYN (``pair_style smd/ulsph``), elastic or
  elastic-perfectly plastic, homogeneous or layered (particles of different types interact,
  so a film is bonded to its substrate); indentation only.

Cost: the block is a cube lattice of spacing dx; a quarter model (symmetry planes x = 0 and
y = 0, particles on them carrying half or a quarter of a cell) cuts the particle count by
about four. Everything here takes SI.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from filmscale.continuum.indentation.tips import Cone, Sphere, SphericalCone, Tip, parse_tip
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError
from filmscale.potentials.lammps_words import check_name

METHODS = ("tlsph", "peri", "ulsph")

#: Coarsest spacing accepted: the sphere radius over at least this many spacings. Below it the
#: contact at 0.1 R spans fewer than two particles and the load is lattice noise.
MIN_RADIUS_SPACINGS = 5.0
#: Peridynamic horizon in spacings (the usual 3 dx; 3.015 avoids lattice round-off).
PERI_HORIZON = 3.015
#: Shallowest pyramid indent in spacings: an elastic Berkovich 1.2 spacings deep came 11 %
#: under Sneddon's load, 2 spacings deep 2.6 % and 2.4 spacings 0.8 % (docs/particles.md).
MIN_PYRAMID_DEPTH_SPACINGS = 2.0
#: Face angles (between the axis and a face, degrees) of the three-sided pyramids the particle
#: models build face by face: Berkovich 65.27 (A = 24.5 h^2) and the cube corner 35.26
#: (arctan(1/sqrt 2), the cube's body diagonal as the axis).
PYRAMID_FACE_ANGLES = {"berkovich": 65.27, "cube-corner": 35.2644}



def _length(name: str, value) -> float:
    return check_real(name, value, low=1e-10, high=1e-1, low_open=False, unit="m")


def check_block(spacing, width, depth) -> None:
    """A particle block's lattice spacing, and its width and depth of at least 4 spacings
    (InputError naming the ``grid.`` key otherwise)."""
    dx = _length("grid.spacing", spacing)
    for name, value in (("width", width), ("depth", depth)):
        value = _length(f"grid.{name}", value)
        if value < 4 * dx:
            raise InputError(f"grid.{name} = {value:g} m is under 4 spacings "
                             f"({4 * dx:g} m); valid: >= 4 * grid.spacing")


@dataclass(frozen=True)
class ParticleMaterial:
    """A material of a particle model: the continuum package's `ElasticPlastic` and a mass
    density (kg/m^3)."""

    material: ElasticPlastic
    density: float = 2700.0

    def __post_init__(self):
        if not isinstance(self.material, ElasticPlastic):
            raise InputError(f"material must be an ElasticPlastic, got {self.material!r}")
        object.__setattr__(self, "density", check_real(
            f"{self.material.name or 'material'}.density", self.density, low=1.0, high=1e5,
            unit="kg/m^3"))

    @property
    def elastic(self) -> bool:
        return math.isinf(self.material.sigma_y)

    @property
    def wave_speed(self) -> float:
        """P-wave speed sqrt(M / rho), m/s: the CFL speed of both solvers."""
        E, nu = self.material.E, self.material.nu
        M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        return math.sqrt(M / self.density)


@dataclass(frozen=True)
class ParticleTarget:
    """A homogeneous or layered half-space: films top first on a substrate, each with its
    density. ``stack`` gives the `LayerStack` the continuum models take."""

    substrate: ParticleMaterial
    films: tuple[tuple[float, ParticleMaterial], ...] = ()

    def __post_init__(self):
        films = tuple(self.films)
        for k, (t, m) in enumerate(films):
            _length(f"films[{k}].thickness", t)
            if not isinstance(m, ParticleMaterial):
                raise InputError(f"films[{k}] must be a ParticleMaterial, got {m!r}")
        object.__setattr__(self, "films", films)

    @property
    def stack(self) -> LayerStack:
        return LayerStack(tuple(Layer(t, m.material) for t, m in self.films),
                          self.substrate.material)

    @property
    def materials(self) -> tuple[ParticleMaterial, ...]:
        return (*(m for _, m in self.films), self.substrate)

    @property
    def layered(self) -> bool:
        return bool(self.films)

    @property
    def elastic(self) -> bool:
        return all(m.elastic for m in self.materials)

    def reduced_modulus(self, layer: int = -1) -> float:
        """E* = E/(1 - nu^2) of one material (default the substrate) against a rigid tip."""
        return self.materials[layer].material.plane_strain_modulus

    def to_dict(self) -> dict:
        def mat(m: ParticleMaterial) -> dict:
            d = asdict(m.material)
            d["density"] = m.density
            return d
        return {"substrate": mat(self.substrate),
                "films": [{"thickness": t, **mat(m)} for t, m in self.films]}


def is_pyramid(tip: Tip) -> bool:
    """Whether the particle models build ``tip`` as a three-sided pyramid (Berkovich, cube
    corner) rather than through its equivalent cone."""
    return isinstance(tip, Cone) and tip.name in PYRAMID_FACE_ANGLES


@dataclass(frozen=True)
class Grid:
    """The particle block: cube lattice of ``spacing`` (m), ``width`` (m) from the axis to the
    lateral sides, ``depth`` (m) from the surface to the rigid base. ``quarter`` keeps one
    quarter of the block (x, y >= 0) with symmetry planes through the axis; ``half`` keeps
    x >= 0 with the one symmetry plane x = 0, which is also a mirror plane of a Berkovich
    pyramid (it holds one edge and bisects the opposite face)."""

    spacing: float
    width: float
    depth: float
    quarter: bool = True
    half: bool = False

    def __post_init__(self):
        check_block(self.spacing, self.width, self.depth)
        object.__setattr__(self, "quarter", bool(self.quarter))
        object.__setattr__(self, "half", bool(self.half))
        if self.quarter and self.half:
            raise InputError("grid.quarter = true and grid.half = true: a block has one "
                             "symmetry; valid: at most one of them true")

    @property
    def symmetry_factor(self) -> float:
        """How many copies of the modelled block make the whole: 4 for a quarter model, 2 for
        a half model."""
        return 4.0 if self.quarter else 2.0 if self.half else 1.0

    @property
    def symmetric(self) -> bool:
        return self.quarter or self.half

    def counts(self) -> tuple[int, int, int]:
        """Lattice points along x, y and z."""
        n_side = round(self.width / self.spacing)
        full = 2 * n_side + 1
        nx = n_side + 1 if self.symmetric else full
        ny = n_side + 1 if self.quarter else full
        return nx, ny, round(self.depth / self.spacing) + 1

    @property
    def n_particles(self) -> int:
        nx, ny, nz = self.counts()
        return nx * ny * nz


def _tip(tip) -> Tip:
    tip = parse_tip(tip)
    if not isinstance(tip, (Sphere, Cone, SphericalCone)):
        raise InputError(f"tip = {tip.spec!r}: particle models take a sphere, a cone, a "
                         "sphero-conical tip or a sharp Berkovich or cube-corner pyramid")
    if is_pyramid(tip) and tip.tip_radius > 0:
        raise InputError(f"tip = {tip.spec!r}: particle models build sharp pyramids only; "
                         "for a blunted tip use sphero-conical:R:THETA")
    return tip


def contact_radius(tip: Tip, depth: float) -> float:
    """The largest radius of the tip's cross-section at ``depth`` below its apex, m: for a
    pyramid its edge (circumscribed) radius, twice the face (inscribed) one."""
    if isinstance(tip, Sphere):
        return math.sqrt(max(2 * tip.R * depth - depth**2, 0.0))
    if is_pyramid(tip):
        return 2 * depth * math.tan(math.radians(PYRAMID_FACE_ANGLES[tip.name]))
    if isinstance(tip, SphericalCone):
        if depth <= tip.transition_depth:
            return math.sqrt(max(2 * tip.R * depth - depth**2, 0.0))
        theta = math.radians(tip.half_angle)
        return (depth + tip.R * (1 / math.sin(theta) - 1)) * math.tan(theta)
    return depth * math.tan(math.radians(tip.half_angle))


def _check_resolution(tip: Tip, grid: Grid, depth: float, method: str):
    dx = grid.spacing
    if isinstance(tip, Sphere):
        if tip.R < MIN_RADIUS_SPACINGS * dx:
            raise InputError(
                f"grid.spacing = {dx:g} m is too coarse for the sphere radius {tip.R:g} m; "
                f"valid: spacing <= R/{MIN_RADIUS_SPACINGS:g} = {tip.R / MIN_RADIUS_SPACINGS:g} m")
    if is_pyramid(tip) and depth < MIN_PYRAMID_DEPTH_SPACINGS * dx:
        raise InputError(
            f"grid.spacing = {dx:g} m is too coarse for a {tip.name} indent {depth:g} m deep: "
            f"its faces are sampled by too few particles; valid: spacing <= depth/"
            f"{MIN_PYRAMID_DEPTH_SPACINGS:g} = {depth / MIN_PYRAMID_DEPTH_SPACINGS:g} m")
    contact = contact_radius(tip, depth)
    if method == "peri" and contact < PERI_HORIZON * dx:
        raise InputError(
            f"grid.spacing = {dx:g} m: the peridynamic horizon ({PERI_HORIZON:g} spacings = "
            f"{PERI_HORIZON * dx:g} m) exceeds the contact radius {contact:g} m at the "
            f"maximum depth; valid: spacing <= {contact / PERI_HORIZON:g} m")
    if contact < 2 * dx:
        raise InputError(
            f"grid.spacing = {dx:g} m: the contact radius at the maximum depth ({contact:g} m)"
            f" spans under 2 spacings; valid: spacing <= {contact / 2:g} m")
    if grid.width < 2 * contact:
        raise InputError(f"grid.width = {grid.width:g} m is under twice the contact radius "
                         f"({2 * contact:g} m); valid: >= {2 * contact:g} m")
    if grid.depth < 2 * contact or grid.depth < 2 * depth:
        need = 2 * max(contact, depth)
        raise InputError(f"grid.depth = {grid.depth:g} m is under {need:g} m (twice the "
                         f"contact radius and the depth); valid: >= {need:g} m")


def _check_method(method: str, target: ParticleTarget, grid: Grid) -> str:
    method = check_choice("method", method, METHODS)
    if method == "tlsph" and target.layered:
        raise InputError("method = 'tlsph' cannot bond a film to a substrate (TLSPH bonds "
                         "one particle type per body); use method 'ulsph' or 'peri' for a "
                         "layered target")
    if method == "peri" and grid.symmetric:
        name = "quarter" if grid.quarter else "half"
        raise InputError(f"grid.{name} = true: the peridynamic model needs the full block "
                         f"(a symmetry plane cuts its bond families); set {name} = false")
    if method == "peri" and target.layered:
        off = [m.material.nu for m in target.materials if abs(m.material.nu - 0.25) > 0.03]
        if off:
            raise InputError(f"nu = {off[0]:g}: the bonded layered peridynamic model "
                             "(peri/pmb) has Poisson's ratio 1/4; valid: nu in [0.22, 0.28] "
                             "for every layer")
    if method == "ulsph":
        hardening = [m.material for m in target.materials if not m.elastic and m.material.n > 0]
        if hardening:
            raise InputError(f"{hardening[0].name or 'material'}.n = {hardening[0].n:g}: "
                             "method 'ulsph' models elastic-perfectly plastic materials "
                             "(MACHDYN's ULSPH strength is linear plastic); valid: n = 0")
    if method == "peri" and not target.elastic:
        raise InputError("method = 'peri' models elastic targets only: peri/eps, its "
                         "elastic-plastic solid, returns NaN at the onset of yield in this "
                         "LAMMPS version; use method 'tlsph' (homogeneous) or 'ulsph' "
                         "(layered) for an elastic-plastic target")
    return method


@dataclass(frozen=True)
class IndentLoading:
    """Displacement control: down at ``speed`` (m/s) to ``depth`` (m), hold ``hold_time``
    (s), back up at the same speed to the starting height (``unload = False`` ends the run
    after the hold: what a loading curvature or an elastic check needs, at half the cost).
    ``frames`` field snapshots are written over the run."""

    depth: float
    speed: float
    hold_time: float = 0.0
    frames: int = 6
    unload: bool = True

    def __post_init__(self):
        _length("loading.depth", self.depth)
        check_real("loading.speed", self.speed, low=1e-6, high=1e4, unit="m/s")
        check_real("loading.hold_time", self.hold_time, low=0.0, high=1.0, unit="s")
        object.__setattr__(self, "frames", int(check_real("loading.frames", self.frames,
                                                          low=0, high=1000)))
        if not isinstance(self.unload, bool):
            raise InputError(f"loading.unload = {self.unload!r} is not true or false")

    @property
    def times(self) -> tuple[float, float, float]:
        """End of loading, of the hold and of unloading (of the hold without one), s."""
        t1 = self.depth / self.speed
        t2 = t1 + self.hold_time
        return t1, t2, t2 + t1 if self.unload else t2


@dataclass(frozen=True)
class ParticleIndentSpec:
    """A quasi-static indentation of a particle model. ``tip``: a `Sphere`, `Cone` or
    `SphericalCone` of the continuum package, or its text (``sphere:1um``, ``cone:70.3``,
    ``sphero-conical:100nm:70.3``, ``berkovich``, ``cube-corner``); the two pyramids are
    built face by face, not as their equivalent cones."""

    name: str
    method: str
    target: ParticleTarget
    tip: Tip
    loading: IndentLoading
    grid: Grid

    def __post_init__(self):
        check_name("name", self.name)      # a folder name and a word of the input's comment
        object.__setattr__(self, "tip", _tip(self.tip))
        if is_pyramid(self.tip) and self.grid.quarter:
            raise InputError(f"grid.quarter = true: a {self.tip.name} pyramid has no quarter "
                             "symmetry; valid: grid.half = true (the mirror plane x = 0) or "
                             "the full block (quarter = false)")
        object.__setattr__(self, "method", _check_method(self.method, self.target,
                                                                self.grid))
        _check_resolution(self.tip, self.grid, self.loading.depth, self.method)
        c = min(m.wave_speed for m in self.target.materials)
        if self.loading.speed > 0.05 * c:
            raise InputError(f"loading.speed = {self.loading.speed:g} m/s is not quasi-static"
                             f"; valid: <= 5 % of the slowest wave speed, {0.05 * c:.4g} m/s")

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": "indent", "method": self.method,
                "target": self.target.to_dict(), "tip": self.tip.spec,
                "loading": asdict(self.loading), "grid": asdict(self.grid)}


@dataclass(frozen=True)
class ParticleImpactSpec:
    """A free rigid sphere of ``mass`` (kg) and radius ``tip.R`` hitting the target at
    ``velocity`` (m/s, normal). The run ends when the sphere leaves the surface or after
    ``duration`` (s; default three elastic Hertz contact times)."""

    name: str
    method: str
    target: ParticleTarget
    tip: Tip
    mass: float
    velocity: float
    grid: Grid
    duration: float | None = None
    frames: int = 6

    def __post_init__(self):
        check_name("name", self.name)
        tip = _tip(self.tip)
        if not isinstance(tip, Sphere):
            raise InputError(f"tip = {tip.spec!r}: the impactor is a sphere")
        object.__setattr__(self, "tip", tip)
        object.__setattr__(self, "method", _check_method(self.method, self.target,
                                                                self.grid))
        if self.method == "ulsph":
            raise InputError("method = 'ulsph' models indentation only; valid for an impact: "
                             "'tlsph' or 'peri'")
        check_real("mass", self.mass, low=1e-20, high=1e3, unit="kg")
        check_real("velocity", self.velocity, low=1e-6, high=1e3, unit="m/s")
        _check_resolution(tip, self.grid, self.hertz_approach, self.method)
        if self.duration is not None:
            check_real("duration", self.duration, low=0.0, high=1.0, low_open=True, unit="s")
        object.__setattr__(self, "frames", int(check_real("frames", self.frames,
                                                          low=0, high=1000)))

    @property
    def hertz_approach(self) -> float:
        """Elastic Hertz maximum approach on the top material, m (docs/physics.md section 1)."""
        E = self.target.reduced_modulus(0)
        return (15 * self.mass * self.velocity**2 / (16 * E * math.sqrt(self.tip.R)))**0.4

    @property
    def end_time(self) -> float:
        if self.duration is not None:
            return self.duration
        return 3 * 2.943275 * self.hertz_approach / self.velocity

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": "impact", "method": self.method,
                "target": self.target.to_dict(), "tip": self.tip.spec, "mass": self.mass,
                "velocity": self.velocity, "duration": self.duration, "frames": self.frames,
                "grid": asdict(self.grid)}
