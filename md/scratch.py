"""Atomistic nanoscratch: the indentation spec extended with a lateral stroke, and the LAMMPS
input it becomes.

Constant depth (``scratch.depth``): after the minimisation and equilibration of an
indentation, the rigid indenter starts ``protocol.gap`` above the undeformed surface, moves
down at ``protocol.speed`` to ``scratch.depth``, holds there for ``protocol.hold_time``,
slides along +x at ``scratch.speed`` over ``scratch.length`` (``passes`` > 1: back along -x,
forth again, ...), withdraws at ``protocol.speed`` to where it started and the sample relaxes
for ``scratch.relax_time`` so that the residual groove can be measured. Its centre is two
closed-form functions of the absolute timestep (so a resumed run re-creates ``fix indent``
where it was):

    z_tip(step) = z_surface + gap - dz (clamp(step - s_load, 0, n_down)
                                        - clamp(step - s_unload, 0, n_up))
    x_tip(step) = x_start + dx sum_k (-1)^k clamp(step - s_stroke - k n_slide, 0, n_slide)

Constant load (``scratch.normal_load`` F with ``scratch.max_depth``): x_tip is the same
closed form; the indenter approaches at ``protocol.speed`` until its apex reaches the
undeformed surface (step s_contact), and from there its height follows a
proportional-integral feedback on the normal force F_n (the z force of ``fix indent``) toward
a target that rises linearly from 0 to F over the time ``max_depth / protocol.speed`` (the
loading), stays at F through the hold and every pass, and is switched off at the withdrawal.
With ``scratch.depth`` as well, the approach goes on to that depth (s_contact is then the
end of the approach) and the target is F from there, without the loading ramp. The law:

    e = F_n - F_target,    d(z_tip)/dt = K_p e + K_i integral(e dt)

(e > 0: too deep, the tip rises). The integral is the velocity v_a of one extra atom, the tip
atom, created far above the indenter (`TIP_CLEARANCE` over its top, out of reach of the
sample and of ``fix indent``) and driven by ``fix addforce`` with m_a K_i e alone; the tip
then sits at z_tip = z_a + (K_p / K_i) v_a - offset. The controller's state is the tip atom's
position and velocity, which restart files keep, so a resumed run continues the feedback from
its exact state (only its first step differs: it sees the full-step velocity where the run
had used the half step, about 0.002 A of apex at 4 fs). Linearised about the target with the contact stiffness k = dF/dh,
the loop is z'' + k K_p z' + k K_i z = 0: natural frequency omega = sqrt(k K_i) and damping
ratio zeta = k K_p / (2 omega). The gains put omega = 2 pi / `RESPONSE_PERIOD` and zeta =
`DAMPING_RATIO` (critical) at the elastic stiffness of the tip on the top layer at F (Hertz
for a sphere, k = (6 E*^2 R F)^(1/3); Sneddon for a cone, k = 2 sqrt(2 E* tan(alpha) F / pi);
E* the potential's own, `md.elastic`). Another stiffness k' scales omega by sqrt(k'/k) and
zeta likewise (a plastic contact, softer: zeta 0.71 at half the stiffness); the loop is
stable for every k' > 0. The step enters as omega dt (0.013 at 4 fs), far inside velocity
Verlet's limit of 2. The proportional term puts a zero at -omega / 2: a step of the contact
(the tip released off its equilibrium) is answered by (1 - omega t) exp(-omega t), which
dips e^-2 = 13.5 % past the equilibrium before it settles.
A ramp of the surface (the groove deepening at speed u) leaves no steady error: the integral
absorbs it. At the withdrawal the tip atom stops being integrated and the indenter rises by
gap + max_depth at ``protocol.speed``; a tip deeper than ``max_depth`` (for which the box and
the withdrawal are sized) stops the run (``fix halt``).

Forces are those of the indenter's fix (``fix indent`` for a sphere, the wall of
`RigidIndenter.fix_command` for a cone) on the indenter: the normal force is its z component, the
lateral force the x component with the sign that makes a force resisting the motion positive
(-F_x on a pass along +x, +F_x on a pass back).

The sample is the indentation slab (``slab.lateral_size`` its width in y) repeated along x to
``slab.length``; the stroke, the contact at both ends (at ``scratch.depth``, or at
``max_depth`` under load) and a far field of `FAR_FIELD` on either side must fit in it (the
box is periodic in x and y).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from filmscale.core.checks import (check_keys, check_path, check_real, check_table,
                                   preset_table, required)
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.core.quantities import to_si
from filmscale.continuum.indentation.tips import Sphere
from filmscale.md.indentation import (IndentSpec, derive_seeds, integration_lines, lammps_clamp,
                                      lammps_number, minimize_lines, setup_lines, start_lines)
from filmscale.md.indentation import DATA_FILE, SURFACE_FILE  # noqa: F401  (re-exported)
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.md.structures import Slab, SlabSpec
from filmscale.potentials.lammps_words import shown

#: Undisturbed surface kept on either side of the groove (in x beyond the stroke and its
#: contact, in y beyond the contact), m: the far field of the groove profile.
FAR_FIELD = 5e-10
RECORD_COLUMNS = ("step", "time", "x_tip", "z_tip", "depth", "fx", "fy", "fz", "temp")
#: a constant-load record adds the target normal force
LOAD_RECORD_COLUMNS = (*RECORD_COLUMNS, "fn_target")
RESPONSE_PERIOD = 2e-12  #: natural period of the constant-load loop at the design stiffness, s
DAMPING_RATIO = 1.0      #: of the constant-load loop at the design stiffness (critical)
TIP_CLEARANCE = 1e-9     #: the tip atom's height above the indenter's top, m
RECORD_FILE = "scratch.dat"
#: segments of the protocol, per step
APPROACH, HOLD, STROKE, UNLOAD, RELAX = range(5)


@dataclass(frozen=True)
class ScratchStroke:
    """The lateral stroke, SI: length (m) of one pass, speed (m/s) along x, passes (1: along
    +x; 2: and back; ...), relax_time (s) after the withdrawal; depth (m) below the
    undeformed surface, and for a constant-load stroke normal_load (N) with max_depth (m,
    the deepest the tip may go: the box and the withdrawal are sized for it). Under load,
    depth is where the indentation stops before the feedback takes over (without it the tip
    is indented to the load)."""

    length: float
    depth: float | None = None
    normal_load: float | None = None
    max_depth: float | None = None
    speed: float = 50.0
    passes: int = 1
    relax_time: float = 2e-12

    def __post_init__(self):
        if self.depth is None and self.normal_load is None:
            raise InputError(
                "scratch.depth and scratch.normal_load are both missing: give depth in "
                "[1e-11, 1e-06] m (a constant-depth scratch) or normal_load in [1e-10, "
                "1e-05] N with max_depth (a constant-load one)")
        if self.depth is not None:
            check_real("scratch.depth", self.depth, low=1e-11, high=1e-6, unit="m")
        if self.normal_load is None:
            if self.max_depth is not None:
                raise InputError(f"scratch.max_depth = {shown(self.max_depth)} belongs to a "
                                 "constant-load scratch (scratch.normal_load); a "
                                 "constant-depth one has scratch.depth alone")
        else:
            check_real("scratch.normal_load", self.normal_load, low=1e-10, high=1e-5,
                       unit="N")
            if self.max_depth is None:
                raise InputError("scratch.max_depth is missing: a constant-load scratch "
                                 "(scratch.normal_load) needs the deepest its tip may go, "
                                 "in [1e-11, 1e-06] m (the box and the withdrawal are sized "
                                 "for it)")
            check_real("scratch.max_depth", self.max_depth, low=max(1e-11, self.depth or 0),
                       high=1e-6, unit="m")
        check_real("scratch.length", self.length, low=1e-10, high=1e-6, unit="m")
        check_real("scratch.speed", self.speed, low=0.01, high=2000.0, unit="m/s")
        check_real("scratch.relax_time", self.relax_time, low=0.0, high=1e-6, unit="s")
        if isinstance(self.passes, bool) or not isinstance(self.passes, int) or \
                not 1 <= self.passes <= 10:
            raise InputError(f"scratch.passes = {shown(self.passes)} must be an integer in "
                             "[1, 10]")

    @property
    def load_controlled(self) -> bool:
        return self.normal_load is not None

    @property
    def reach(self) -> float:
        """The deepest the tip goes (m): the depth, or max_depth under load."""
        return self.max_depth if self.load_controlled else self.depth

    @property
    def approach_depth(self) -> float:
        """Where the closed-form approach stops (m): the depth, or 0 (the surface) when the
        tip is indented to the load."""
        return self.depth or 0.0

    def to_dict(self) -> dict:
        """The stroke's keys, those not given left out."""
        return {k: v for k, v in asdict(self).items() if v is not None}


@dataclass(frozen=True)
class ScratchSchedule:
    """The protocol in timesteps; dz, dz_up and dx (m) are the indenter's moves per step down,
    up and along x. n_down reaches the depth (constant depth) or the surface (constant load,
    whose load then rises over n_load steps; 0 at constant depth and from a depth); n_up
    withdraws."""

    n_equilibrate: int
    n_down: int
    n_load: int
    n_hold: int
    n_slide: int
    passes: int
    n_up: int
    n_relax: int
    dz: float
    dz_up: float
    dx: float

    @property
    def s_load(self) -> int:
        return self.n_equilibrate

    @property
    def s_contact(self) -> int:
        return self.s_load + self.n_down

    @property
    def s_hold(self) -> int:
        return self.s_contact + self.n_load

    @property
    def s_stroke(self) -> int:
        return self.s_hold + self.n_hold

    @property
    def s_unload(self) -> int:
        return self.s_stroke + self.passes * self.n_slide

    @property
    def s_relax(self) -> int:
        return self.s_unload + self.n_up

    @property
    def s_end(self) -> int:
        return self.s_relax + self.n_relax

    def pass_starts(self) -> list[int]:
        return [self.s_stroke + k * self.n_slide for k in range(self.passes)]

    def tip_height(self, step, z_surface: float, gap: float):
        """Indenter apex height at ``step`` (m) of a constant-depth scratch."""
        step = np.asarray(step, float)
        down = np.clip(step - self.s_load, 0, self.n_down)
        up = np.clip(step - self.s_unload, 0, self.n_up)
        return z_surface + gap - self.dz * down + self.dz_up * up

    def tip_x(self, step, x_start: float):
        """Indenter centre along x at ``step`` (m)."""
        step = np.asarray(step, float)
        moved = sum((-1) ** k * np.clip(step - s, 0, self.n_slide)
                    for k, s in enumerate(self.pass_starts()))
        return x_start + self.dx * moved

    def load_fraction(self, step) -> np.ndarray:
        """The target's share of the normal load at ``step`` (constant load): 0 before the
        contact, rising linearly over the loading, 1 to the withdrawal, 0 after."""
        step = np.asarray(step, float)
        ramp = (np.clip(step - self.s_contact, 0, self.n_load) / self.n_load
                if self.n_load else 1.0)
        return np.where((step >= self.s_contact) & (step < self.s_unload), ramp, 0.0)

    def segment(self, step) -> np.ndarray:
        step = np.asarray(step)
        return np.select([step < self.s_hold, step < self.s_stroke, step < self.s_unload,
                          step < self.s_relax], [APPROACH, HOLD, STROKE, UNLOAD], RELAX)

    def direction(self, step) -> np.ndarray:
        """+1 on a pass along +x, -1 on one back, 0 off the stroke."""
        step = np.asarray(step)
        k = (step - self.s_stroke) // max(self.n_slide, 1)
        on = (step >= self.s_stroke) & (step < self.s_unload)
        return np.where(on, np.where(k % 2 == 0, 1, -1), 0)


@dataclass(frozen=True)
class LoadControl:
    """The constant-load feedback (module docstring), SI: the target normal_load (N), the
    reduced modulus E_star (Pa) and the elastic contact stiffness (N/m) at that load it is
    designed with, the loop's natural angular frequency omega (rad/s) and damping ratio."""

    normal_load: float
    E_star: float
    stiffness: float
    omega: float
    zeta: float

    @property
    def K_i(self) -> float:
        """Integral gain, m/(N s^2): the tip atom's acceleration per newton of error."""
        return self.omega**2 / self.stiffness

    @property
    def K_p(self) -> float:
        """Proportional gain, m/(N s): the tip's velocity per newton of error."""
        return 2.0 * self.zeta * self.omega / self.stiffness

    def to_dict(self) -> dict:
        return {**asdict(self), "K_i": self.K_i, "K_p": self.K_p}


def load_control(spec: ScratchSpec, E_star: float) -> LoadControl:
    """The gains of ``spec``'s constant-load feedback for a top layer of reduced modulus
    ``E_star`` (Pa): the elastic stiffness of the tip at the load, omega = 2 pi /
    `RESPONSE_PERIOD`, zeta = `DAMPING_RATIO`."""
    F = spec.stroke.normal_load
    if F is None:
        raise InputError("load_control: the spec scratches at constant depth (scratch.depth "
                         f"= {spec.stroke.depth!r} m); a load control needs scratch.normal_load")
    E_star = check_real("E_star", E_star, low=1e9, high=1e13, unit="Pa")
    tip = spec.indent.indenter.tip
    if isinstance(tip, Sphere):
        k = (6.0 * E_star**2 * tip.R * F) ** (1.0 / 3.0)
    else:
        k = 2.0 * math.sqrt(2.0 * E_star * math.tan(math.radians(tip.half_angle)) * F
                            / math.pi)
    return LoadControl(F, E_star, k, 2.0 * math.pi / RESPONSE_PERIOD, DAMPING_RATIO)


def _x_period(layer, orientation: str) -> float:
    """A layer's period along x before it is strained to the box, A: a crystal's cell, or
    the edge of the block an amorphous film is tiled from."""
    if layer.structure == "amorphous":
        return float(si_to_lammps(layer.block.box[0], "length"))
    return layer.crystal.unit_cell(orientation).cell[0, 0]


def elongated_slab(spec: SlabSpec, slab: Slab, length: float) -> Slab:
    """The built ``slab`` of ``spec`` (square in x and y) repeated along x and cut to the
    whole number of common periods nearest ``length`` (m): a period of every layer as it
    is strained to the box (for a pure substrate, its cell; for an amorphous film, the edge
    of its block as tiled)."""
    Lx = si_to_lammps(slab.box[0], "length")
    counts = [max(1, round(Lx / _x_period(layer, spec.orientation))) for _, layer in spec.layers()]
    period = Lx / math.gcd(*counts)
    n = max(1, round(si_to_lammps(length, "length") / period))
    atoms = slab.atoms.repeat((math.ceil(n * period / Lx - 1e-9), 1, 1))
    new_Lx = n * period
    atoms = atoms[atoms.positions[:, 0] < new_Lx - 1e-6]
    atoms.set_cell([new_Lx, *atoms.cell.lengths()[1:]])
    symbols = atoms.get_chemical_symbols()
    return dataclasses.replace(slab, atoms=atoms,
                               box=(float(lammps_to_si(new_Lx, "length")), *slab.box[1:]),
                               element_counts={e: symbols.count(e) for e in
                                               slab.element_counts})


@dataclass(frozen=True)
class ScratchSpec:
    """An indentation spec (sample, potential, indenter, integration; its protocol's depth is
    the scratch depth, or max_depth under load) with the stroke and the sample's length along
    x (m)."""

    indent: IndentSpec
    stroke: ScratchStroke
    length_x: float

    def __post_init__(self):
        slab, stroke = self.indent.slab_built, self.stroke
        a = self.contact_radius
        need_x = stroke.length + 2.0 * (a + FAR_FIELD)
        if slab.box[0] < need_x:
            raise InputError(
                f"slab.length = {self.length_x:.4g} m gives a box {slab.box[0]:.4g} m long in "
                f"x, shorter than scratch.length + 2 (contact radius + far field) = "
                f"{need_x:.4g} m: lengthen the slab or shorten the stroke")
        need_y = 2.0 * (a + FAR_FIELD)
        if slab.box[1] < need_y:
            raise InputError(
                f"slab.lateral_size = {self.indent.slab.lateral_size:.4g} m gives a box "
                f"{slab.box[1]:.4g} m wide in y, narrower than 2 (contact radius + far field)"
                f" = {need_y:.4g} m: widen the slab or scratch less deep")

    @property
    def name(self) -> str:
        return self.indent.name

    @property
    def contact_radius(self) -> float:
        """Radius of the indenter's cross-section at the surface plane at the depth (under
        load: at max_depth), m."""
        return self.indent.indenter.footprint_radius(self.stroke.reach)

    @property
    def x_start(self) -> float:
        """Indenter centre along x at the start of the stroke, m."""
        return self.contact_radius + FAR_FIELD

    @property
    def y_center(self) -> float:
        return self.indent.slab_built.box[1] / 2.0

    def schedule(self) -> ScratchSchedule:
        p, st = self.indent.protocol, self.stroke
        dt = p.timestep
        steps = lambda distance: max(1, math.ceil(distance / (p.speed * dt)))   # noqa: E731
        down, up = p.gap + st.approach_depth, p.gap + st.reach
        n_down, n_up = steps(down), steps(up)
        n_load = steps(st.max_depth) if st.load_controlled and st.depth is None else 0
        n_slide = max(1, math.ceil(st.length / (st.speed * dt)))
        return ScratchSchedule(round(p.equilibration_time / dt), n_down, n_load,
                               round(p.hold_time / dt), n_slide, st.passes, n_up,
                               round(st.relax_time / dt), down / n_down, up / n_up,
                               st.length / n_slide)

    @property
    def tip_offset(self) -> float:
        """Height of the tip atom above the indenter's apex (constant load), m."""
        ind = self.indent.indenter
        top = 2.0 * ind.tip.R if isinstance(ind.tip, Sphere) else ind.height
        return top + TIP_CLEARANCE

    def to_dict(self) -> dict:
        return {**self.indent.to_dict(), "scratch": self.stroke.to_dict(),
                "slab_length": self.length_x}


# ---- the LAMMPS input -------------------------------------------------------------------------

def _A(v: float) -> str:
    return lammps_number(si_to_lammps(v, "length"))


def _tip_atom_mass(spec: ScratchSpec) -> float:
    """Mass (kg) of the tip atom: an atom of type 1, as the data file gives it."""
    atoms = spec.indent.slab_built.atoms
    i = atoms.get_chemical_symbols().index(spec.indent.type_elements[0])
    return float(lammps_to_si(atoms.get_masses()[i], "mass"))


def _height_lines(spec: ScratchSpec, control: LoadControl | None) -> list[str]:
    """``v_z_tip``: closed form at constant depth; under load the approach, then the tip
    atom's z + (K_p / K_i) v_z (the feedback), then the withdrawal; ``v_fn_target``."""
    p, s = spec.indent.protocol, spec.schedule()
    down = lammps_clamp(f"step-{s.s_load}", s.n_down)
    if control is None:
        return [f"variable z_tip equal v_z_surface+{_A(p.gap)}-{_A(s.dz)}*"
                f"({down}-{lammps_clamp(f'step-{s.s_unload}', s.n_up)})"]
    tau = lammps_number(si_to_lammps(control.K_p / control.K_i, "time"))
    F = lammps_number(si_to_lammps(control.normal_load, "force"))
    ramp = f"*{lammps_clamp(f'step-{s.s_contact}', s.n_load)}/{s.n_load}" if s.n_load else ""
    atom = (f"c_tip_state[1]+{tau}*c_tip_state[2]-{_A(spec.tip_offset)}-v_z_surface"
            f"+{_A(spec.stroke.approach_depth)}")
    return [
        # z and v_z of the tip atom in one reduction a step (a compute is evaluated once per
        # step however often the variables ask; group functions such as xcm would reduce
        # at each use)
        "compute tip_state tip reduce sum z vz",
        f"variable load_on equal (step>={s.s_contact})*(step<{s.s_unload})",
        f"variable fn_target equal {F}*v_load_on{ramp}",
        f"variable z_tip equal v_z_surface+{_A(p.gap)}-{_A(s.dz)}*{down}"
        f"+(step>={s.s_contact})*({atom})"
        f"+{_A(s.dz_up)}*{lammps_clamp(f'step-{s.s_unload}', s.n_up)}",
    ]


def _feedback_lines(spec: ScratchSpec, control: LoadControl, moving: bool) -> list[str]:
    """The force on the tip atom (m_a K_i e, metal units), its integration while ``moving``
    (to the withdrawal) and the stop at max_depth."""
    gain = lammps_number(_tip_atom_mass(spec) * control.K_i)   # force per force: no unit
    lines = [f"variable f_tip equal {gain}*v_load_on*(f_indenter[3]-v_fn_target)",
             "fix tip_load tip addforce 0.0 0.0 v_f_tip"]
    if moving:
        lines.append("fix tip_motion tip nve")
    every = spec.indent.protocol.record_every
    return lines + [f"fix depth_limit all halt {every} v_depth > {_A(spec.stroke.max_depth)} "
                    "error hard message yes"]


def _indenter_lines(spec: ScratchSpec, z_surface: str, record: str,
                    control: LoadControl | None = None,
                    restart_step: int | None = None) -> list[str]:
    """The moving indenter, its record file and the thermo output that shows it; under load
    the tip atom is created (a fresh run: ``restart_step`` None) or comes with the restart."""
    p = spec.indent.protocol
    s = spec.schedule()
    moves = "".join(f"{('-' if k % 2 else '+') if k else ''}"
                    f"{lammps_clamp(f'step-{start}', s.n_slide)}"
                    for k, start in enumerate(s.pass_starts()))
    y = si_to_lammps(spec.y_center, "length")
    columns = RECORD_COLUMNS if control is None else LOAD_RECORD_COLUMNS
    fields = " ".join(f"$(v_{c}:%.12g)" for c in RECORD_COLUMNS[2:8])
    target = "" if control is None else " $(v_fn_target:%.12g)"
    lines = [
        "# ---- the indenter: its apex height and centre x are functions of the timestep"
        + ("" if control is None else " and, under load, of the tip atom (the feedback)"),
        f"variable z_surface equal {z_surface}",
        *(_tip_atom_lines(spec) if control is not None and restart_step is None else []),
        *_height_lines(spec, control),
        f"variable x_tip equal {_A(spec.x_start)}+{_A(s.dx)}*({moves})",
        spec.indent.indenter.fix_command("v_x_tip", y),
        "variable depth equal v_z_surface-v_z_tip",
        "variable fx equal f_indenter[1]",
        "variable fy equal f_indenter[2]",
        "variable fz equal f_indenter[3]",
        "variable temp equal c_mobile_temp",
    ]
    if control is not None:
        lines += _feedback_lines(spec, control,
                                 restart_step is None or restart_step < s.s_unload)
    return lines + [
        f'fix record all print {p.record_every} "$(step) $(time:%.10g) {fields} '
        f'$(v_temp:%.6g){target}" file {record} screen no title "# {" ".join(columns)}"',
        "thermo_style custom step time temp c_mobile_temp pe v_x_tip v_depth v_fx v_fz"
        + ("" if control is None else " v_fn_target"),
        "thermo_modify flush yes",
    ]


def _tip_atom_lines(spec: ScratchSpec) -> list[str]:
    """The tip atom (constant load), at rest where the approach leaves the indenter's apex."""
    y = si_to_lammps(spec.y_center, "length")
    return [
        "# ---- the tip atom: the feedback's integrator, far above the indenter and the sample",
        "# (the box is raised to hold it; shrink-wrapping keeps it inside from then on)",
        f"change_box all z final $(zlo:%.12g) $(v_z_surface+{_A(2 * spec.tip_offset)}:%.12g) "
        "units box",
        f"create_atoms 1 single {_A(spec.x_start)} {lammps_number(y)} "
        f"$(v_z_surface+{_A(spec.tip_offset - spec.stroke.approach_depth)}:%.12g) units box",
        f"group tip id {spec.indent.slab_built.n_atoms + 1}",
        "group sample subtract all tip",
    ]


def dump_name(step: int) -> str:
    return f"dumps/scratch.{step:09d}.lammpstrj"


def _segment_lines(spec: ScratchSpec, after_step: int) -> list[str]:
    s = spec.schedule()
    load = spec.stroke.load_controlled
    ends = {s.s_hold: "loading done", s.s_stroke: "hold done",
            **{start + s.n_slide: f"pass {k + 1} done"
               for k, start in enumerate(s.pass_starts())},
            s.s_relax: "withdrawn", s.s_end: "relaxed"}
    dumps = {s.s_unload, s.s_end}
    lines = []
    for step in sorted(ends):
        if step <= after_step:
            continue
        lines.append(f"run {step} upto    # {ends[step]}")
        if step in dumps:
            lines.append(f"write_dump {'sample' if load else 'all'} custom {dump_name(step)} "
                         "id type x y z c_pe_atom modify sort id")
        if load and step == s.s_unload:
            lines.append("unfix tip_motion    # the tip atom stops: the feedback is over")
    return lines


def _control(spec: ScratchSpec, control: LoadControl | None) -> LoadControl | None:
    if spec.stroke.load_controlled and control is None:
        raise InputError("control = None: a constant-load scratch's input needs its "
                         "LoadControl (load_control(spec, E_star))")
    return control if spec.stroke.load_controlled else None


def scratch_input(spec: ScratchSpec, *, record: str = RECORD_FILE, version: str = "",
                  control: LoadControl | None = None) -> str:
    """The complete LAMMPS input of a fresh scratch run (replayable with ``lmp -in``);
    ``control``: the feedback of a constant-load scratch (`load_control`)."""
    ind = spec.indent
    p, s = ind.protocol, spec.schedule()
    control = _control(spec, control)
    seeds = derive_seeds(p.seed, ("velocity", "langevin"))
    lines = [
        f"# filmscale {version} atomistic nanoscratch: {spec.name}".replace("  ", " "),
        f"# {ind.slab_built.n_atoms} atoms{'' if control is None else ' and the tip atom'}; "
        f"{s.s_end} steps; master seed {p.seed}, derived "
        f"seeds velocity {seeds['velocity']}, langevin {seeds['langevin']}",
        "# replay: lmp -in in.scratch  (in this directory)",
        *start_lines(ind),
        *minimize_lines(ind, seeds["velocity"]),
        *integration_lines(ind, seeds["langevin"]),
        f"run {s.s_load}    # equilibration",
        # the relaxed, equilibrated sample: the damage reference of an amorphous film, whose
        # cut surfaces rebond in the minimisation (a crystal's reference is its lattice)
        f"write_dump all custom {dump_name(s.s_load)} id type x y z c_pe_atom modify sort id",
        "",
        "# ---- the undeformed surface (zero of depth): mean height of the top atomic layer",
        *_indenter_lines(spec, "$(xcm(surface,z):%.12g)", record, control),
        f'print "${{z_surface}}" file {SURFACE_FILE} screen no',
        f"write_restart restart.{s.s_load}.bin",
    ]
    if p.restart_every:
        lines.append(f"restart {p.restart_every} restart.*.bin")
    lines += ["", *_segment_lines(spec, s.s_load)]
    return "\n".join(lines) + "\n"


def scratch_resume_input(spec: ScratchSpec, *, restart_file: str, restart_step: int,
                         z_surface: float, part: int, record: str, version: str = "",
                         control: LoadControl | None = None) -> str:
    """The input that continues a scratch from ``restart_file`` (``z_surface`` in A); the
    tip atom of a constant-load scratch comes back with the restart file, its fixes are
    re-created."""
    ind = spec.indent
    p = ind.protocol
    control = _control(spec, control)
    seeds = derive_seeds(p.seed, ("langevin",), part=part)
    lines = [
        f"# filmscale {version} atomistic nanoscratch: {spec.name}, resumed (part {part}) "
        f"from {restart_file} at step {restart_step}".replace("  ", " "),
        f"# master seed {p.seed}, derived seed langevin {seeds['langevin']}",
        f"# replay: lmp -in in.resume.{part}  (in this directory)",
        "units metal", "atom_style atomic", "boundary p p m", "processors * * 1",
        f"read_restart {restart_file}",
        *setup_lines(ind),
        "compute pe_atom all pe/atom",
        "",
        *integration_lines(ind, seeds["langevin"]),
        *_indenter_lines(spec, f"{z_surface:.12g}", record, control, restart_step),
    ]
    if p.restart_every:
        lines.append(f"restart {p.restart_every} restart.*.bin")
    lines += ["", *_segment_lines(spec, restart_step)]
    return "\n".join(lines) + "\n"


# ---- specs from TOML and presets -------------------------------------------------------------

#: [scratch] keys: name -> SI unit (quantities such as "1 nm" or "20 m/s" are converted)
SCRATCH_UNITS = {"depth": "m", "normal_load": "N", "max_depth": "m", "length": "m",
                 "speed": "m/s", "relax_time": "s"}

PRESETS: dict[str, dict] = {
    "ci": {
        "name": "ci-scratch-cu001",
        "potential": {"name": "Cu_mishin1"},
        "slab": {"orientation": "001", "lateral_size": 4.3e-9, "length": 5.1e-9, "films": [],
                 "substrate": {"element": "Cu", "thickness": 2.2e-9}},
        "indenter": {"shape": "sphere", "radius": 2e-9},
        "protocol": {"speed": 200.0, "timestep": 4e-15, "equilibration_time": 4e-13,
                     "hold_time": 4e-13, "record_every": 10, "restart_every": 500,
                     "seed": 2026},
        "scratch": {"depth": 5e-10, "length": 1.2e-9, "speed": 100.0, "relax_time": 1e-12},
    },
    "quick": {
        "name": "quick-scratch-cu001",
        "potential": {"name": "Cu_mishin1"},
        "slab": {"orientation": "001", "lateral_size": 5.1e-9, "length": 8e-9, "films": [],
                 "substrate": {"element": "Cu", "thickness": 3.2e-9},
                 "thermostat_thickness": 5e-10, "fixed_thickness": 5e-10},
        "indenter": {"shape": "sphere", "radius": 2e-9},
        "protocol": {"speed": 100.0, "timestep": 4e-15, "equilibration_time": 1e-12,
                     "hold_time": 1e-12, "record_every": 10, "restart_every": 1000,
                     "seed": 2026},
        "scratch": {"depth": 6e-10, "length": 3e-9, "speed": 50.0, "relax_time": 4e-12},
    },
    # for MPI under SLURM (docs/md-indentation.md: atoms, steps, cost); never run in the tests
    "research": {
        "name": "research-scratch-cu001",
        "potential": {"name": "Cu_mishin1"},
        "slab": {"orientation": "001", "lateral_size": 1.5e-8, "length": 2.2e-8, "films": [],
                 "substrate": {"element": "Cu", "thickness": 8e-9},
                 "thermostat_thickness": 1e-9, "fixed_thickness": 1e-9},
        "indenter": {"shape": "sphere", "radius": 4e-9},
        "protocol": {"speed": 50.0, "timestep": 2e-15, "equilibration_time": 1e-11,
                     "hold_time": 1e-11, "record_every": 50, "thermo_every": 1000,
                     "restart_every": 10000, "seed": 2026},
        "scratch": {"depth": 1.5e-9, "length": 1e-8, "speed": 20.0, "relax_time": 2e-11},
    },
}


def _stroke(table) -> ScratchStroke:
    table = dict(check_keys("scratch", table, {*SCRATCH_UNITS, "passes"}))
    required("scratch", table, "length")
    for key, unit in SCRATCH_UNITS.items():
        if key in table:
            table[key] = to_si(f"scratch.{key}", table[key], unit)
    return ScratchStroke(**table)


def scratch_spec_from_mapping(data: dict, base_dir: Path | None = None) -> ScratchSpec:
    """A `ScratchSpec` from a TOML-like mapping: the indentation spec's tables (``[protocol]``
    without depth and dump_depths; ``slab.length`` the sample's length along x) and
    ``[scratch]`` (depth or normal_load with max_depth, length, speed, passes, relax_time;
    SI or quantities)."""
    from filmscale.md.spec import spec_from_mapping
    data = dict(check_keys("spec", data, {"name", "potential", "slab", "indenter",
                                          "protocol", "scratch"}))
    stroke = _stroke(required("spec", data, "scratch"))
    slab = dict(check_table("slab", required("spec", data, "slab")))
    length = to_si("slab.length", required("slab", slab, "length"), "m")
    length = check_real("slab.length", length, low=5e-10, high=1e-6, unit="m")
    del slab["length"]
    protocol = dict(check_table("protocol", data.get("protocol", {})))
    for key in ("depth", "dump_depths"):
        if key in protocol:
            raise InputError(f"protocol.{key} is not a scratch key: the depth is "
                             "scratch.depth (or scratch.max_depth under scratch.normal_load)")
    data.update(slab=slab, protocol={**protocol, "depth": stroke.reach})
    del data["scratch"]
    # the sample check of the indentation applies to the width; the length is checked here
    return scratch_of(spec_from_mapping(data, base_dir), stroke, length)


def scratch_of(indent: IndentSpec, stroke: ScratchStroke, length: float) -> ScratchSpec:
    """The scratch of ``indent``'s sample lengthened along x to ``length`` (m)."""
    built = elongated_slab(indent.slab, indent.slab_built, length)
    return ScratchSpec(dataclasses.replace(indent, slab_built=built), stroke, length)


def load_scratch_spec(path: Path | str) -> ScratchSpec:
    """Read a scratch spec file; relative potential files are found beside it."""
    path = check_path("path", path)
    return scratch_spec_from_mapping(read_toml(path, "spec file"), path.parent)


def scratch_preset(name: str) -> ScratchSpec:
    return scratch_spec_from_mapping(preset_table(PRESETS, name))


def record_to_si(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The record file's columns (metal units) in SI: time s, x_tip/z_tip/depth m, forces
    on the indenter and the target normal force (constant load) N."""
    out = {"step": columns["step"].astype(int), "temp": columns["temp"]}
    out["time"] = lammps_to_si(columns["time"], "time")
    for key in ("x_tip", "z_tip", "depth"):
        out[key] = lammps_to_si(columns[key], "length")
    for key in ("fx", "fy", "fz", "fn_target"):
        if key in columns:
            out[key] = lammps_to_si(columns[key], "force")
    return out
