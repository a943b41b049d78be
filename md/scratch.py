"""Atomistic nanoscratch: the indentation spec extended with a lateral stroke, and the LAMMPS
input it becomes.

The stroke is displacement controlled at constant depth (constant load is not built yet).
After the minimisation and equilibration of an indentation, the rigid indenter starts
``protocol.gap`` above the undeformed surface, moves down at ``protocol.speed`` to
``scratch.depth``, holds there for ``protocol.hold_time``, slides along +x at
``scratch.speed`` over ``scratch.length`` (``passes`` > 1: back along -x, forth again, ...),
withdraws at ``protocol.speed`` to where it started and the sample relaxes for
``scratch.relax_time`` so that the residual groove can be measured. Its centre is two
closed-form functions of the absolute timestep (so a resumed run re-creates ``fix indent``
where it was):

    z_tip(step) = z_surface + gap - dz (clamp(step - s_load, 0, n_down)
                                        - clamp(step - s_unload, 0, n_up))
    x_tip(step) = x_start + dx sum_k (-1)^k clamp(step - s_stroke - k n_slide, 0, n_slide)

Forces are those of ``fix indent`` on the indenter: the normal force is its z component, the
lateral force the x component with the sign that makes a force resisting the motion positive
(-F_x on a pass along +x, +F_x on a pass back).

The sample is the indentation slab (``slab.lateral_size`` its width in y) repeated along x to
``slab.length``; the stroke, the contact at both ends and a far field of `FAR_FIELD` on
either side must fit in it (the box is periodic in x and y).
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from filmscale.core.checks import check_keys, check_path, check_real, check_table, required
from filmscale.core.errors import InputError
from filmscale.core.files import read_toml
from filmscale.core.quantities import to_si
from filmscale.md.indentation import (IndentSpec, derive_seeds, integration_lines, lammps_clamp,
                                      lammps_number, minimize_lines, setup_lines, start_lines)
from filmscale.md.indentation import DATA_FILE, SURFACE_FILE  # noqa: F401  (re-exported)
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.md.structures import Slab, SlabSpec, build_slab
from filmscale.potentials.lammps_words import shown

#: Undisturbed surface kept on either side of the groove (in x beyond the stroke and its
#: contact, in y beyond the contact), m: the far field of the groove profile.
FAR_FIELD = 5e-10
RECORD_COLUMNS = ("step", "time", "x_tip", "z_tip", "depth", "fx", "fy", "fz", "temp")
RECORD_FILE = "scratch.dat"
#: segments of the protocol, per step
APPROACH, HOLD, STROKE, UNLOAD, RELAX = range(5)


@dataclass(frozen=True)
class ScratchStroke:
    """The lateral stroke, SI: depth (m) below the undeformed surface, speed (m/s) along x,
    length (m) of one pass, passes (1: along +x; 2: and back; ...), relax_time (s) after
    the withdrawal."""

    depth: float
    length: float
    speed: float = 50.0
    passes: int = 1
    relax_time: float = 2e-12

    def __post_init__(self):
        check_real("scratch.depth", self.depth, low=1e-11, high=1e-6, unit="m")
        check_real("scratch.length", self.length, low=1e-10, high=1e-6, unit="m")
        check_real("scratch.speed", self.speed, low=0.01, high=2000.0, unit="m/s")
        check_real("scratch.relax_time", self.relax_time, low=0.0, high=1e-6, unit="s")
        if isinstance(self.passes, bool) or not isinstance(self.passes, int) or \
                not 1 <= self.passes <= 10:
            raise InputError(f"scratch.passes = {shown(self.passes)} must be an integer in "
                             "[1, 10]")


@dataclass(frozen=True)
class ScratchSchedule:
    """The protocol in timesteps; dz and dx (m) are the indenter's moves per step."""

    n_equilibrate: int
    n_down: int
    n_hold: int
    n_slide: int
    passes: int
    n_relax: int
    dz: float
    dx: float

    @property
    def s_load(self) -> int:
        return self.n_equilibrate

    @property
    def s_hold(self) -> int:
        return self.s_load + self.n_down

    @property
    def s_stroke(self) -> int:
        return self.s_hold + self.n_hold

    @property
    def s_unload(self) -> int:
        return self.s_stroke + self.passes * self.n_slide

    @property
    def s_relax(self) -> int:
        return self.s_unload + self.n_down

    @property
    def s_end(self) -> int:
        return self.s_relax + self.n_relax

    def pass_starts(self) -> list[int]:
        return [self.s_stroke + k * self.n_slide for k in range(self.passes)]

    def tip_height(self, step, z_surface: float, gap: float):
        """Indenter apex height at ``step`` (m)."""
        step = np.asarray(step, float)
        down = np.clip(step - self.s_load, 0, self.n_down)
        up = np.clip(step - self.s_unload, 0, self.n_down)
        return z_surface + gap - self.dz * (down - up)

    def tip_x(self, step, x_start: float):
        """Indenter centre along x at ``step`` (m)."""
        step = np.asarray(step, float)
        moved = sum((-1) ** k * np.clip(step - s, 0, self.n_slide)
                    for k, s in enumerate(self.pass_starts()))
        return x_start + self.dx * moved

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


def elongated_slab(spec: SlabSpec, slab: Slab, length: float) -> Slab:
    """The built ``slab`` of ``spec`` (square in x and y) repeated along x and cut to the
    whole number of common periods nearest ``length`` (m): a period of every layer as it
    is strained to the box (for a pure substrate, its cell)."""
    Lx = si_to_lammps(slab.box[0], "length")
    counts = [max(1, round(Lx / layer.crystal.unit_cell(spec.orientation).cell[0, 0]))
              for _, layer in spec.layers()]
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
    the scratch depth) with the stroke and the sample's length along x (m)."""

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
        """Radius of the indenter's cross-section at the surface plane at the depth, m."""
        return self.indent.indenter.footprint_radius(self.stroke.depth)

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
        n_down = max(1, math.ceil((p.gap + st.depth) / (p.speed * dt)))
        n_slide = max(1, math.ceil(st.length / (st.speed * dt)))
        return ScratchSchedule(round(p.equilibration_time / dt), n_down,
                               round(p.hold_time / dt), n_slide, st.passes,
                               round(st.relax_time / dt), (p.gap + st.depth) / n_down,
                               st.length / n_slide)

    def to_dict(self) -> dict:
        return {**self.indent.to_dict(), "scratch": asdict(self.stroke),
                "slab_length": self.length_x}


# ---- the LAMMPS input -------------------------------------------------------------------------

def _indenter_lines(spec: ScratchSpec, z_surface: str, record: str) -> list[str]:
    """The moving indenter, its record file and the thermo output that shows it."""
    p = spec.indent.protocol
    s = spec.schedule()
    A = lambda v: lammps_number(si_to_lammps(v, "length"))     # noqa: E731
    moves = "".join(f"{('-' if k % 2 else '+') if k else ''}"
                    f"{lammps_clamp(f'step-{start}', s.n_slide)}"
                    for k, start in enumerate(s.pass_starts()))
    y = si_to_lammps(spec.y_center, "length")
    fields = " ".join(f"$(v_{c}:%.12g)" for c in RECORD_COLUMNS[2:8])
    return [
        "# ---- the indenter: its apex height and centre x are functions of the timestep",
        f"variable z_surface equal {z_surface}",
        f"variable z_tip equal v_z_surface+{A(p.gap)}-{A(s.dz)}*"
        f"({lammps_clamp(f'step-{s.s_load}', s.n_down)}-{lammps_clamp(f'step-{s.s_unload}', s.n_down)})",
        f"variable x_tip equal {A(spec.x_start)}+{A(s.dx)}*({moves})",
        spec.indent.indenter.fix_command("v_x_tip", y),
        "variable depth equal v_z_surface-v_z_tip",
        "variable fx equal f_indenter[1]",
        "variable fy equal f_indenter[2]",
        "variable fz equal f_indenter[3]",
        "variable temp equal c_mobile_temp",
        f'fix record all print {p.record_every} "$(step) $(time:%.10g) {fields} '
        f'$(v_temp:%.6g)" file {record} screen no title "# {" ".join(RECORD_COLUMNS)}"',
        "thermo_style custom step time temp c_mobile_temp pe v_x_tip v_depth v_fx v_fz",
        "thermo_modify flush yes",
    ]


def dump_name(step: int) -> str:
    return f"dumps/scratch.{step:09d}.lammpstrj"


def _segment_lines(spec: ScratchSpec, after_step: int) -> list[str]:
    s = spec.schedule()
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
            lines.append(f"write_dump all custom {dump_name(step)} id type x y z c_pe_atom "
                         "modify sort id")
    return lines


def scratch_input(spec: ScratchSpec, *, record: str = RECORD_FILE, version: str = "") -> str:
    """The complete LAMMPS input of a fresh scratch run (replayable with ``lmp -in``)."""
    ind = spec.indent
    p, s = ind.protocol, spec.schedule()
    seeds = derive_seeds(p.seed, ("velocity", "langevin"))
    lines = [
        f"# filmscale {version} atomistic nanoscratch: {spec.name}".replace("  ", " "),
        f"# {ind.slab_built.n_atoms} atoms; {s.s_end} steps; master seed {p.seed}, derived "
        f"seeds velocity {seeds['velocity']}, langevin {seeds['langevin']}",
        "# replay: lmp -in in.scratch  (in this directory)",
        *start_lines(ind),
        *minimize_lines(ind, seeds["velocity"]),
        *integration_lines(ind, seeds["langevin"]),
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


def scratch_resume_input(spec: ScratchSpec, *, restart_file: str, restart_step: int,
                         z_surface: float, part: int, record: str, version: str = "") -> str:
    """The input that continues a scratch from ``restart_file`` (``z_surface`` in A)."""
    ind = spec.indent
    p = ind.protocol
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
        *_indenter_lines(spec, f"{z_surface:.12g}", record),
    ]
    if p.restart_every:
        lines.append(f"restart {p.restart_every} restart.*.bin")
    lines += ["", *_segment_lines(spec, restart_step)]
    return "\n".join(lines) + "\n"


# ---- specs from TOML and presets -------------------------------------------------------------

#: [scratch] keys: name -> SI unit (quantities such as "1 nm" or "20 m/s" are converted)
SCRATCH_UNITS = {"depth": "m", "length": "m", "speed": "m/s", "relax_time": "s"}

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
}


def _stroke(table) -> ScratchStroke:
    table = dict(check_keys("scratch", table, {*SCRATCH_UNITS, "passes"}))
    for key in ("depth", "length"):
        required("scratch", table, key)
    for key, unit in SCRATCH_UNITS.items():
        if key in table:
            table[key] = to_si(f"scratch.{key}", table[key], unit)
    return ScratchStroke(**table)


def scratch_spec_from_mapping(data: dict, base_dir: Path | None = None) -> ScratchSpec:
    """A `ScratchSpec` from a TOML-like mapping: the indentation spec's tables (``[protocol]``
    without depth and dump_depths; ``slab.length`` the sample's length along x) and
    ``[scratch]`` (depth, length, speed, passes, relax_time; SI or quantities)."""
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
                             "scratch.depth")
    data.update(slab=slab, protocol={**protocol, "depth": stroke.depth})
    del data["scratch"]
    # the sample check of the indentation applies to the width; the length is checked here
    indent = spec_from_mapping(data, base_dir)
    built = elongated_slab(indent.slab, build_slab(indent.slab), length)
    indent = dataclasses.replace(indent, slab_built=built)
    return ScratchSpec(indent, stroke, length)


def load_scratch_spec(path: Path | str) -> ScratchSpec:
    """Read a scratch spec file; relative potential files are found beside it."""
    path = check_path("path", path)
    return scratch_spec_from_mapping(read_toml(path, "spec file"), path.parent)


def scratch_preset(name: str) -> ScratchSpec:
    if name not in PRESETS:
        raise InputError(f"preset = {shown(name)} is not one of {', '.join(PRESETS)}")
    return scratch_spec_from_mapping(copy.deepcopy(PRESETS[name]))


def record_to_si(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The record file's columns (metal units) in SI: time s, x_tip/z_tip/depth m, forces
    on the indenter N."""
    out = {"step": columns["step"].astype(int), "temp": columns["temp"]}
    out["time"] = lammps_to_si(columns["time"], "time")
    for key in ("x_tip", "z_tip", "depth"):
        out[key] = lammps_to_si(columns[key], "length")
    for key in ("fx", "fy", "fz"):
        out[key] = lammps_to_si(columns[key], "force")
    return out
