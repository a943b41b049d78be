"""Where a loaded MD cone touches, from the atoms' positions alone: the atoms inside its
nominal surface and the force its wall puts on each (docs/md-indentation.md, "The cone's
contact"), so that a snapshot gives the contact's width and how its load is shared.

The wall is LAMMPS's: the region is the cone shrunk by r_c = `CONE_RANGE` along its normals
(apex flat r0' = r0 - r_c (1 - sin a) / cos a at height r_c, flank at the cone's angle a), and
an atom d < r_c from it is pushed k_w (r_c - d) along the line from the region's nearest
point (`RigidIndenter.wall_stiffness`). The region is convex and axisymmetric, so the nearest
point lies in the atom's meridional plane: on the flat (straight down), on the flank (along
(cos(a) r_hat, -sin(a))), or the flat's rim (which rounds the contact there by r_c).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.indentation.tips import Cone
from filmscale.core.errors import InputError
from filmscale.md.indentation import CONE_AXIS_OFFSET, CONE_RANGE
from filmscale.md.run import IndentRun
from filmscale.md.scratch import dump_name
from filmscale.md.scratch_run import ScratchRun, read_dump_atoms


@dataclass(frozen=True)
class ConeContact:
    """The atoms inside the nominal cone (SI): their offsets from the axis (dx, dy, m) and
    the wall's force on each (N, 3 columns: the force on the atom)."""

    dx: np.ndarray
    dy: np.ndarray
    force: np.ndarray

    @property
    def normal_force(self) -> float:
        """The load the atoms put on the cone, N (upward positive)."""
        return float(-self.force[:, 2].sum())

    @property
    def lateral_force(self) -> float:
        """The x force the atoms put on the cone, N (positive resists a move along +x)."""
        return float(self.force[:, 0].sum())

    @property
    def width(self) -> float:
        """The contact's extent across the axis (y), m; 0 without contact."""
        return float(self.dy.max() - self.dy.min()) if self.dy.size else 0.0

    @property
    def radius(self) -> float:
        """The farthest contacting atom from the axis, m; 0 without contact."""
        return float(np.hypot(self.dx, self.dy).max()) if self.dx.size else 0.0

    def rear_share(self) -> float:
        """The share of the load carried behind the axis (dx < 0: the groove a tip moving
        along +x leaves), which Williams' scratch hardness takes as none; NaN without load."""
        total = self.normal_force
        if total <= 0:
            return math.nan
        return float(-self.force[self.dx < 0, 2].sum() / total)


def cone_contact(atoms: dict, tip: Cone, apex: tuple[float, float, float], stiffness: float,
                 box: tuple[float, float]) -> ConeContact:
    """The contact of ``tip`` with its apex flat centred at ``apex`` (x, y, z, m) on
    ``atoms`` (x, y, z arrays, m; periodic in x and y over ``box``), the wall a spring of
    ``stiffness`` (N/m)."""
    if not isinstance(tip, Cone):
        raise InputError(f"tip = {tip!r}: the contact of a cone needs a Cone")
    a = math.radians(tip.half_angle)
    rc = CONE_RANGE
    rim = np.array([tip.tip_radius - rc * (1.0 - math.sin(a)) / math.cos(a), rc])
    flank_normal = np.array([math.cos(a), -math.sin(a)])      # (r, s), out of the cone
    Lx, Ly = box
    dx = (atoms["x"] - apex[0] + 0.5 * Lx) % Lx - 0.5 * Lx
    dy = (atoms["y"] - apex[1] + 0.5 * Ly) % Ly - 0.5 * Ly
    r = np.hypot(dx, dy)
    v = np.column_stack([r - rim[0], atoms["z"] - apex[2] - rim[1]])   # from the rim
    beyond_flank = v @ flank_normal
    under_flat = (v[:, 0] <= 0) & (v[:, 1] < 0)
    on_flank = ~under_flat & (v @ np.array([math.sin(a), math.cos(a)]) > 0) \
        & (beyond_flank > 0)
    rim_distance = np.hypot(v[:, 0], v[:, 1])
    d = np.where(under_flat, -v[:, 1], np.where(on_flank, beyond_flank, rim_distance))
    with np.errstate(invalid="ignore", divide="ignore"):
        n = np.where(under_flat[:, None], np.array([0.0, -1.0]),
                     np.where(on_flank[:, None], flank_normal, v / rim_distance[:, None]))
    touch = d < rc
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(r > 0, dx / r, 0.0)[touch]
        uy = np.where(r > 0, dy / r, 0.0)[touch]
    push = stiffness * (rc - d[touch])
    n = n[touch]
    force = np.column_stack([push * n[:, 0] * ux, push * n[:, 0] * uy, push * n[:, 1]])
    return ConeContact(dx[touch], dy[touch], force)


def scratch_contact(run: ScratchRun) -> ConeContact:
    """The contact of a constant-depth cone scratch at the end of its stroke, still at depth
    (the run's dump there): the steady stroke's contact where the groove behind it is
    complete. Under load the apex's height is the feedback's, which no formula gives."""
    spec = run.spec
    if spec.stroke.normal_load is not None:
        raise InputError(f"scratch.normal_load = {spec.stroke.normal_load:.4g} N: the contact "
                         "is read from a constant-depth scratch (scratch.depth), whose apex "
                         "height the schedule gives")
    s = spec.schedule()
    step = s.s_unload
    apex = (float(s.tip_x(step, spec.x_start)), spec.y_center + CONE_AXIS_OFFSET,
            float(s.tip_height(step, run.z_surface, spec.indent.protocol.gap)))
    ind = spec.indent.indenter
    return cone_contact(read_dump_atoms(run.run_dir / dump_name(step)), ind.tip, apex,
                        ind.wall_stiffness, spec.indent.slab_built.box[:2])


def indentation_contact(run: IndentRun) -> ConeContact:
    """The contact of a cone indentation at the end of its hold (the run's dump there)."""
    spec = run.spec
    schedule = spec.protocol.schedule()
    at_hold_end = [path for step, path in run.dumps if step == schedule.s_unload]
    if not at_hold_end:
        raise InputError(f"run directory {run.run_dir} holds no dump at the end of the hold "
                         f"(step {schedule.s_unload})")
    box = spec.slab_built.box
    apex = (box[0] / 2, box[1] / 2 + CONE_AXIS_OFFSET,
            float(schedule.tip_height(schedule.s_unload, run.z_surface, spec.protocol.gap)))
    return cone_contact(read_dump_atoms(at_hold_end[0]), spec.indenter.tip, apex,
                        spec.indenter.wall_stiffness, box[:2])
