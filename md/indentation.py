"""Atomistic nanoindentation: the run specification and the LAMMPS input it becomes.

The protocol is displacement controlled. After an energy minimisation and an equilibration
at temperature T, the indenter starts ``gap`` above the undeformed surface, moves down at
constant ``speed`` to ``depth``, holds, and moves back up to where it started. Its height is
one closed-form function of the absolute timestep,

    z_tip(step) = z_surface + gap - dz * (clamp(step - s_load, 0, n_down)
                                          - clamp(step - s_unload, 0, n_up)),

so a run resumed from a restart file re-creates ``fix indent`` (which keeps nothing in restart
files) at exactly the position it had. ``z_surface`` is the mean height of the top atomic
layer after equilibration: the zero of depth, h = z_surface - z_tip.

Everything here is plain Python that writes text; nothing launches LAMMPS (see `md.run`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from filmscale.continuum.indentation.tips import Cone, Sphere
from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.md.structures import Slab, SlabSpec, build_slab, check_stack
from filmscale.md.lammps_units import si_to_lammps, lammps_to_si
from filmscale.potentials import Potential
from filmscale.potentials.lammps_words import check_name, shown

#: fix indent force constant, 100 eV/A^3 in N/m^2: an atom carrying 1 eV/A sits
#: sqrt(F/K) = 0.1 A inside the nominal sphere. Measured on Cu(001) (docs/md-indentation.md,
#: "What sets the elastic segment"): with the depth zero fitted, K = 10, 100 and 1000 give E
#: within 2.5 % of each other; 1000 doubles the load noise at a 4 fs step, and 10 lets atoms
#: sit 0.3 A inside the sphere, which with the zero held lowers E by 10 %.
DEFAULT_K = float(lammps_to_si(100.0, "indent_constant"))
#: A cone pushes through ``fix wall/region`` on a moving ``region cone`` (harmonic: the force
#: 2 eps (r_c - d) along the surface normal at distance d < r_c), not ``fix indent cone``:
#: LAMMPS's indent cone pushes each atom along the line from the cone's mid-axis point, which
#: no surface normal follows (measured: docs/md-indentation.md, "The cone's contact"). The
#: region is the cone shrunk by ``CONE_RANGE`` along its normals, so that the force starts at
#: the nominal surface; 2 A with the default K gives 40 eV/A at the region's surface, where
#: LAMMPS stops the run, and 2 eps is the sphere's stiffness at ``CONE_REFERENCE_FORCE``.
CONE_RANGE = 2e-10                                      #: m
CONE_REFERENCE_FORCE = float(lammps_to_si(1.0, "force"))  #: N, 1 eV/A on one atom
#: the region's axis sits this far off the indenter's y: LAMMPS's cone gives no force to an
#: atom exactly on its axis (measured), and a lattice puts atoms there
CONE_AXIS_OFFSET = 1e-13                                #: m
SEED_MAX = 900_000_000       #: LAMMPS random seeds are integers in [1, 900000000]


def derive_seeds(master: int, names: tuple[str, ...], part: int = 0) -> dict[str, int]:
    """LAMMPS seeds for ``names`` from one master seed; ``part`` > 0 gives the fresh streams
    of a resumed run."""
    states = np.random.SeedSequence(master, spawn_key=(part,)).generate_state(len(names))
    return {name: int(s % (SEED_MAX - 1)) + 1 for name, s in zip(names, states)}


def _radius(R) -> float:
    return check_real("indenter.radius", R, low=2e-10, high=1e-6, unit="m")


def min_tip_radius(half_angle: float) -> float:
    """The smallest apex flat (m) of a cone of ``half_angle`` (deg) whose region, shrunk by
    `CONE_RANGE` along its normals, keeps a flat: r_c (1 - sin a) / cos a."""
    a = math.radians(half_angle)
    return CONE_RANGE * (1.0 - math.sin(a)) / math.cos(a)


def _cone_geometry(half_angle, tip_radius) -> tuple[float, float]:
    return (check_real("indenter.half_angle", half_angle, low=10.0, high=85.0, unit="deg"),
            check_real("indenter.tip_radius", tip_radius, low=1e-11, high=1e-7, unit="m"))


@dataclass(frozen=True)
class RigidIndenter:
    """The rigid indenter of an MD run: a continuum `Tip` acting through its LAMMPS fix.

    ``tip`` is a `Sphere` of radius R (2e-10 to 1e-6 m) or a `Cone` of half-angle 10-85 deg
    (70.3 is the Berkovich equivalent) whose apex is a flat of ``tip_radius`` 1e-11 to 1e-7 m,
    at least what its region needs (`min_tip_radius`). The same object goes with the run's
    curve to the analysis, so a cone keeps its apex radius there. A sphere's repulsion is
    ``fix indent``'s F(r) = -K (r - R)^2 inside the surface; ``K`` in N/m^2 (default
    100 eV/A^3 = 1.6e13 N/m^2). A cone's is a spring of `wall_stiffness` along the surface
    normal (`CONE_RANGE`); ``height`` is its axial length (m), which must exceed depth + gap.
    """

    tip: Sphere | Cone
    K: float = DEFAULT_K
    height: float = 5e-9

    def __post_init__(self):
        tip = self.tip
        if isinstance(tip, Sphere):
            _radius(tip.R)
        elif isinstance(tip, Cone):
            _cone_geometry(tip.half_angle, tip.tip_radius)
            if tip.tip_radius <= min_tip_radius(tip.half_angle):
                raise InputError(
                    f"indenter.tip_radius = {tip.tip_radius:.4g} m must exceed "
                    f"{min_tip_radius(tip.half_angle):.4g} m at half_angle = "
                    f"{tip.half_angle:g} deg: the cone's contact region is the cone shrunk by "
                    f"{CONE_RANGE:g} m along its normals, and its apex flat must remain")
        else:
            raise InputError(f"indenter = {tip} must be a sphere or a cone")
        check_real("indenter.K", self.K, low=1e9, high=1e15, unit="N/m^2")
        check_positive("indenter.height", self.height, "m")

    @classmethod
    def sphere(cls, radius, K=DEFAULT_K) -> RigidIndenter:
        """A sphere of ``radius`` (m), checked before the tip is built."""
        return cls(Sphere(_radius(radius)), K)

    @classmethod
    def cone(cls, half_angle=70.3, tip_radius=2e-10, K=DEFAULT_K, height=5e-9) -> RigidIndenter:
        """A cone of ``half_angle`` (deg) with an apex flat of ``tip_radius`` (m)."""
        theta, r0 = _cone_geometry(half_angle, tip_radius)
        return cls(Cone(theta, tip_radius=r0), K, height)

    def footprint_radius(self, depth: float) -> float:
        """Radius of the indenter's cross-section at the surface plane, m."""
        tip = self.tip
        if isinstance(tip, Sphere):
            R = tip.R
            return math.sqrt(max(0.0, 2.0 * R * depth - depth**2)) if depth < R else R
        return tip.tip_radius + max(depth, 0.0) * math.tan(math.radians(tip.half_angle))

    @property
    def wall_stiffness(self) -> float:
        """A cone's contact spring, N/m: the slope of the sphere's law, 2 sqrt(K F), at
        F = `CONE_REFERENCE_FORCE` (20 eV/A^2 at the default K)."""
        return 2.0 * math.sqrt(self.K * CONE_REFERENCE_FORCE)

    def fix_command(self, x: float | str, y: float) -> str:
        """The indenter's fix, ``indenter`` (metal units, lengths in A; ``f_indenter[1..3]``
        the force on it): ``fix indent`` with a sphere centred on v_z_tip + R, or
        ``fix wall/region`` on a cone whose apex flat is at v_z_tip (its region moved there);
        ``x`` a number or the name of an equal-style variable (``v_x_tip``: a moving
        indenter)."""
        tip = self.tip
        if isinstance(tip, Sphere):
            x = x if isinstance(x, str) else f"{x:.10g}"
            K = si_to_lammps(self.K, "indent_constant")
            R = si_to_lammps(tip.R, "length")
            return (f"variable z_center equal v_z_tip+{R:.10g}\n"
                    f"fix indenter all indent {K:.10g} "
                    f"sphere {x} {y:.10g} v_z_center {R:.10g} units box")
        alpha = math.radians(tip.half_angle)
        rc, H = (si_to_lammps(v, "length") for v in (CONE_RANGE, self.height))
        shrink = rc / math.cos(alpha)            # the flank moved in by rc along its normal
        radius = [si_to_lammps(tip.tip_radius, "length") + z * math.tan(alpha) - shrink
                  for z in (rc, H)]
        eps = 0.5 * si_to_lammps(self.wall_stiffness, "stiffness")
        c2 = y + si_to_lammps(CONE_AXIS_OFFSET, "length")
        c1, move_x = (0.0, x) if isinstance(x, str) else (x, "NULL")
        return (f"region indenter_body cone z {c1:.10g} {c2:.10g} {radius[0]:.10g} "
                f"{radius[1]:.10g} {rc:.10g} {H:.10g} side out "
                f"move {move_x} NULL v_z_tip units box\n"
                f"fix indenter all wall/region indenter_body harmonic {eps:.10g} 1.0 {rc:.10g}")

    def to_dict(self) -> dict:
        return {"tip": self.tip.spec, "K": self.K, "height": self.height}




@dataclass(frozen=True)
class IndentProtocol:
    """Displacement-controlled indentation, SI units.

    depth (m) below the undeformed surface, speed (m/s) of loading and unloading, hold_time
    (s) at depth, gap (m) between indenter and surface at the start, temperature (K),
    timestep (s), equilibration_time (s), damping (s) of the Langevin thermostat, record_every
    (steps between recorded points), thermo_every (steps between log lines), restart_every
    (steps between restart files; 0 for none), dump_depths (m, loading depths at which all
    atoms are dumped; the end of the hold and the end of the run are always dumped), seed (the
    master seed from which every LAMMPS seed derives), minimize (relax before heating).
    """

    depth: float
    speed: float = 50.0
    hold_time: float = 2e-12
    gap: float = 2e-10
    temperature: float = 10.0
    timestep: float = 2e-15
    equilibration_time: float = 2e-12
    damping: float = 1e-13
    record_every: int = 10
    thermo_every: int = 100
    restart_every: int = 1000
    dump_depths: tuple[float, ...] = ()
    seed: int = 1
    minimize: bool = True

    def __post_init__(self):
        object.__setattr__(self, "dump_depths", tuple(float(d) for d in self.dump_depths))
        check_real("protocol.depth", self.depth, low=1e-11, high=1e-6, unit="m")
        check_real("protocol.speed", self.speed, low=0.01, high=2000.0, unit="m/s")
        check_real("protocol.hold_time", self.hold_time, low=0.0, high=1e-6, unit="s")
        check_real("protocol.gap", self.gap, low=0.0, high=1e-8, unit="m")
        check_real("protocol.temperature", self.temperature, low=0.0, high=1e4, unit="K")
        check_real("protocol.timestep", self.timestep, low=1e-17, high=1e-14, unit="s")
        check_real("protocol.equilibration_time", self.equilibration_time, low=0.0,
                   high=1e-6, unit="s")
        check_positive("protocol.damping", self.damping, "s")
        for name in ("record_every", "thermo_every", "restart_every"):
            value = getattr(self, name)
            low = 0 if name == "restart_every" else 1
            if isinstance(value, bool) or not isinstance(value, int) or not \
                    low <= value <= 10**9:
                raise InputError(f"protocol.{name} = {shown(value)} must be an integer in "
                                 f"[{low}, 1e9]")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or \
                not 0 <= self.seed < 2**63:
            raise InputError(f"protocol.seed = {shown(self.seed)} must be an integer in "
                             "[0, 2^63)")
        for d in self.dump_depths:
            check_real("protocol.dump_depths", d, low=0.0, high=self.depth, unit="m")

    def schedule(self) -> Schedule:
        dt = self.timestep
        n_eq = round(self.equilibration_time / dt)
        n_down = max(1, math.ceil((self.gap + self.depth) / (self.speed * dt)))
        n_hold = round(self.hold_time / dt)
        return Schedule(n_eq, n_down, n_hold, n_down, (self.gap + self.depth) / n_down)


@dataclass(frozen=True)
class Schedule:
    """The protocol in timesteps: equilibration, descent, hold and ascent lengths, and the
    indenter displacement per step dz (m)."""

    n_equilibrate: int
    n_down: int
    n_hold: int
    n_up: int
    dz: float

    @property
    def s_load(self) -> int:
        return self.n_equilibrate

    @property
    def s_hold(self) -> int:
        return self.s_load + self.n_down

    @property
    def s_unload(self) -> int:
        return self.s_hold + self.n_hold

    @property
    def s_end(self) -> int:
        return self.s_unload + self.n_up

    def tip_height(self, step, z_surface: float, gap: float):
        """Indenter apex height at ``step`` (m), as the LAMMPS formula computes it."""
        step = np.asarray(step, float)
        down = np.clip(step - self.s_load, 0, self.n_down)
        up = np.clip(step - self.s_unload, 0, self.n_up)
        return z_surface + gap - self.dz * (down - up)

    def segment(self, step) -> np.ndarray:
        """0 load (approach and loading), 1 hold, 2 unload, per step."""
        step = np.asarray(step)
        return np.where(step < self.s_hold, 0, np.where(step < self.s_unload, 1, 2))


@dataclass(frozen=True)
class IndentSpec:
    """Everything that defines an indentation run: the name, the interatomic potential,
    the slab, the indenter and the protocol. Validated on creation, before LAMMPS starts."""

    name: str
    potential: Potential
    slab: SlabSpec
    indenter: RigidIndenter
    protocol: IndentProtocol
    slab_built: Slab | None = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        check_name("name", self.name)      # a folder name and a word of the input's comment
        check_stack(self.slab, self.potential)     # elements the potential lacks fail here
        self.potential.pair_commands(self.slab.elements)
        if self.slab_built is None:
            object.__setattr__(self, "slab_built", build_slab(self.slab))
        slab = self.slab_built
        p = self.protocol
        footprint = 2.0 * self.indenter.footprint_radius(p.depth)
        width = min(slab.box[:2])
        if footprint >= width:
            raise InputError(
                f"indenter footprint at depth {p.depth:.4g} m is {footprint:.4g} m wide, not "
                f"less than the box width {width:.4g} m: enlarge slab.lateral_size or reduce "
                "the indenter radius or depth")
        mobile = slab.z_surface - slab.z_thermostat
        if p.depth >= mobile:
            raise InputError(
                f"protocol.depth = {p.depth:.4g} m reaches below the mobile atoms "
                f"({mobile:.4g} m of the slab above the thermostatted layer): thicken the "
                "substrate or indent less deep")
        if isinstance(self.indenter.tip, Cone) and self.indenter.height <= p.depth + p.gap:
            raise InputError(f"indenter.height = {self.indenter.height:.4g} m must exceed "
                             f"depth + gap = {p.depth + p.gap:.4g} m")

    @property
    def type_elements(self) -> tuple[str, ...]:
        """Element of LAMMPS atom types 1, 2, ... in the data file."""
        return self.slab.elements

    def to_dict(self) -> dict:
        return {"name": self.name, "potential": self.potential.to_dict(),
                "slab": self.slab.to_dict(), "indenter": self.indenter.to_dict(),
                "protocol": asdict(self.protocol)}

    def with_protocol(self, **changes) -> IndentSpec:
        return replace(self, protocol=replace(self.protocol, **changes))


# ---- the LAMMPS input -------------------------------------------------------------------------

DATA_FILE = "slab.data"
SURFACE_FILE = "surface_z.txt"
RECORD_COLUMNS = ("step", "time", "z_tip", "depth", "load", "temp")


def lammps_number(x: float) -> str:
    """A number as a LAMMPS input writes it (12 significant digits)."""
    return f"{x:.12g}"


def setup_lines(spec: IndentSpec) -> list[str]:
    """Potential, neighbour lists, thermo and timestep: shared by fresh and resumed inputs."""
    p = spec.protocol
    return [
        *spec.potential.pair_commands(spec.type_elements),
        "neighbor 2.0 bin",
        "neigh_modify delay 0 every 1 check yes",
        f"timestep {lammps_number(si_to_lammps(p.timestep, 'time'))}",
    ]


def lammps_clamp(u: str, n: int) -> str:
    """clamp(u, 0, n) as a LAMMPS formula: (|u| - |u - n| + n) / 2 (LAMMPS's min and max
    apply to computes and fixes, not to numbers)."""
    return f"0.5*(abs({u})-abs({u}-{n})+{n})"


def integration_lines(spec: IndentSpec, seed: int) -> list[str]:
    """Fixed bottom, Langevin layer above it, NVE for all mobile atoms (restart files keep
    none of these fixes)."""
    p = spec.protocol
    return [
        "# ---- integration: fixed bottom, Langevin layer above it, NVE for all mobile atoms",
        "fix freeze fixed setforce 0.0 0.0 0.0",
        "fix integrate mobile nve",
        f"fix thermostat thermostat langevin {lammps_number(p.temperature)} {lammps_number(p.temperature)} "
        f"{lammps_number(si_to_lammps(p.damping, 'time'))} {seed} zero yes",
        "compute mobile_temp mobile temp",
        "thermo_style custom step time temp c_mobile_temp pe",
        "thermo_modify flush yes",
        f"thermo {spec.protocol.thermo_every}",
    ]


def _indenter_lines(spec: IndentSpec, z_surface: str, record: str) -> list[str]:
    """The indenter, its record file and the thermo output that shows it."""
    p, slab = spec.protocol, spec.slab_built
    s = p.schedule()
    lx, ly = (si_to_lammps(v, "length") for v in slab.box[:2])
    return [
        "# ---- the indenter: its apex height is a function of the absolute timestep",
        f"variable z_surface equal {z_surface}",
        f"variable z_tip equal v_z_surface+{lammps_number(si_to_lammps(p.gap, 'length'))}"
        f"-{lammps_number(si_to_lammps(s.dz, 'length'))}*"
        f"({lammps_clamp(f'step-{s.s_load}', s.n_down)}-{lammps_clamp(f'step-{s.s_unload}', s.n_up)})",
        spec.indenter.fix_command(lx / 2.0, ly / 2.0),
        "variable depth equal v_z_surface-v_z_tip",
        "variable load equal f_indenter[3]",
        "variable temp_mobile equal c_mobile_temp",
        f'fix record all print {p.record_every} "$(step) $(time:%.10g) $(v_z_tip:%.12g) '
        f'$(v_depth:%.12g) $(v_load:%.12g) $(v_temp_mobile:%.6g)" file {record} '
        f'screen no title "# {" ".join(RECORD_COLUMNS)}"',
        "thermo_style custom step time temp c_mobile_temp pe v_depth v_load",
        "thermo_modify flush yes",
    ]


def _segment_lines(spec: IndentSpec, after_step: int) -> list[str]:
    """``run N upto`` for every phase end and dump step beyond ``after_step``."""
    p = spec.protocol
    s = p.schedule()
    dump_steps = {s.s_load + round((p.gap + d) / s.dz): f"depth {d:.4g} m"
                  for d in p.dump_depths}
    dump_steps[s.s_unload] = "end of hold"
    dump_steps[s.s_end] = "end of unloading"
    phases = {s.s_hold: "loading done", s.s_unload: "hold done", s.s_end: "unloading done"}
    lines = []
    for step in sorted(set(dump_steps) | set(phases)):
        if step <= after_step:
            continue
        lines.append(f"run {step} upto    # {phases.get(step, dump_steps.get(step))}")
        if step in dump_steps:
            lines.append(f"write_dump all custom dumps/indent.{step:09d}.lammpstrj "
                         "id type x y z c_pe_atom modify sort id")
    return lines


def start_lines(spec: IndentSpec) -> list[str]:
    """Units, the data file, the setup and the regions and groups of a fresh run (shared by
    the indentation and the scratch inputs)."""
    slab = spec.slab_built
    top = si_to_lammps(slab.z_surface - 0.5 * slab.surface_layer_gap, "length")
    return [
        "units metal",
        "atom_style atomic",
        "boundary p p m",
        "processors * * 1    # split laterally: along z the ranks would share vacuum",
        f"read_data {DATA_FILE}",
        *setup_lines(spec),
        "",
        "# ---- regions (A): rigid bottom, thermostatted layer, mobile atoms, top atomic layer",
        f"region fixed block INF INF INF INF INF {lammps_number(si_to_lammps(slab.z_fixed, 'length'))} "
        "units box",
        f"region thermostat block INF INF INF INF {lammps_number(si_to_lammps(slab.z_fixed, 'length'))} "
        f"{lammps_number(si_to_lammps(slab.z_thermostat, 'length'))} units box",
        f"region surface block INF INF INF INF {lammps_number(top)} INF units box",
        "group fixed region fixed",
        "group thermostat region thermostat",
        "group mobile subtract all fixed",
        "group surface region surface",
        "compute pe_atom all pe/atom",
        "",
    ]


def minimize_lines(spec: IndentSpec, velocity_seed: int) -> list[str]:
    """The relaxation, if asked for, and the initial velocities."""
    p = spec.protocol
    lines = []
    if p.minimize:
        lines += ["# ---- relax the as-built structure (surface and interface)",
                  "fix freeze_min fixed setforce 0.0 0.0 0.0",
                  "minimize 0 1e-6 2000 20000",
                  "unfix freeze_min",
                  "reset_timestep 0", ""]
    return lines + [f"velocity mobile create {lammps_number(2.0 * p.temperature)} {velocity_seed} "
                    "mom yes rot yes dist gaussian" if p.temperature > 0 else "",
                    "velocity fixed set 0.0 0.0 0.0"]


def indentation_input(spec: IndentSpec, *, record: str = "indent.dat",
                      version: str = "") -> str:
    """The complete LAMMPS input of a fresh run (replayable with ``lmp -in`` in the run
    directory that holds the data file)."""
    p, slab = spec.protocol, spec.slab_built
    s = p.schedule()
    seeds = derive_seeds(p.seed, ("velocity", "langevin"))
    lines = [
        f"# filmscale {version} atomistic nanoindentation: {spec.name}".replace("  ", " "),
        f"# {slab.n_atoms} atoms; {s.s_end} steps; master seed {p.seed}, derived seeds "
        f"velocity {seeds['velocity']}, langevin {seeds['langevin']}",
        "# replay: lmp -in in.indent  (in this directory)",
        *start_lines(spec),
        *minimize_lines(spec, seeds["velocity"]),
    ]
    lines += integration_lines(spec, seeds["langevin"])
    lines += [
        f"run {s.s_load}    # equilibration",
        "",
        "# ---- the undeformed surface (zero of depth): mean height of the top atomic layer",
        *_indenter_lines(spec, "$(xcm(surface,z):%.12g)", record),
        f'print "${{z_surface}}" file {SURFACE_FILE} screen no',
        f"write_restart restart.{s.s_load}.bin",
    ]
    if p.restart_every:
        lines.append(f"restart {p.restart_every} restart.*.bin")
    lines += ["", *_segment_lines(spec, s.s_load)]
    return "\n".join(lines) + "\n"


def resume_input(spec: IndentSpec, *, restart_file: str, restart_step: int, z_surface: float,
                 part: int, record: str, version: str = "") -> str:
    """The input that continues a run from ``restart_file`` (written at ``restart_step``),
    with the indenter and every fix re-created; ``z_surface`` in A as the run measured it;
    ``part`` (1, 2, ...) numbers the resumption and picks fresh thermostat seeds."""
    p = spec.protocol
    seeds = derive_seeds(p.seed, ("langevin",), part=part)
    lines = [
        f"# filmscale {version} atomistic nanoindentation: {spec.name}, resumed (part "
        f"{part}) from {restart_file} at step {restart_step}".replace("  ", " "),
        f"# master seed {p.seed}, derived seed langevin {seeds['langevin']}",
        f"# replay: lmp -in in.resume.{part}  (in this directory)",
        "units metal",
        "atom_style atomic",
        "boundary p p m",
        "processors * * 1",
        f"read_restart {restart_file}",
        *setup_lines(spec),
        "compute pe_atom all pe/atom",
        "",
        *integration_lines(spec, seeds["langevin"]),
        *_indenter_lines(spec, f"{z_surface:.12g}", record),
    ]
    if p.restart_every:
        lines.append(f"restart {p.restart_every} restart.*.bin")
    lines += ["", *_segment_lines(spec, restart_step)]
    return "\n".join(lines) + "\n"
