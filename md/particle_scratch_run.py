"""Running a particle scratch (`filmscale.md.particle_scratch`), what it says, and its record.

The run directory holds ``in.tlsph``, its log, the record ``scratch.dat``, the field dumps
(``fields.STEP.dump``; the first one is the undeformed block) and ``final.dump`` (after the
relaxation), and ``state.json``; a directory whose run finished with the same input is read
back without LAMMPS (MACHDYN writes no restart files: an interrupted run starts again).

Friction, as `md scratch` (`filmscale.md.scratch_run`): over the steady part of the first
pass, the tip's x between `scratch_run.STEADY` 20 % and 80 % of the stroke length, mu_i = F_lat,i / F_n,i
at every recorded point; ``friction_mean``, ``friction_std`` their mean and standard
deviation, ``normal_force_mean``, ``lateral_force_mean`` the mean forces there (N).

Groove: the surface particles (the top lattice plane) of the lattice column nearest mid-stroke
x; the height of each is its final z minus its initial z (0), against its final y, mirrored to
-y in a half model. ``groove_depth`` is minus the lowest height within the contact radius of
the axis, ``groove_width`` the distance between the points either side of it where the
profile first rises through zero (linear interpolation; 0 when no height is below zero),
``pileup_height`` the highest height, ``edge_height`` the mean height of the particles
farther than twice the contact radius from the axis.

Plastic zone, per layer: the particles of that mid-stroke cross-section whose equivalent
plastic strain (``smd/plastic/strain``) exceeds `PLASTIC_THRESHOLD`: its ``width`` (y extent,
both sides) and ``depth`` (below the undeformed surface) in each layer (a particle's layer is
its type: films top first, then the substrate; a layer is named by its material's ``name``,
else ``film1``, ``film2``, ..., ``substrate``); 0 and 0 where no particle of a layer yielded.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from filmscale.core.jsonable import to_jsonable
from filmscale.md.engine import EngineOptions, LammpsError, parse_table
from filmscale.md.lammps_units import lammps_to_si
from filmscale.md.particle_run import FieldSnapshot, read_snapshot, run_particle_input
from filmscale.md.scratch_run import (PassFigures, groove_depth_width, pass_figures,
                                      scratch_hardness)
from filmscale.md.particle_scratch import (COLUMNS, FINAL_DUMP, RECORD, ParticleScratchSpec,
                                           estimated_steps, path_direction, scratch_input)

STATE_FILE = "state.json"
PLASTIC_THRESHOLD = 1e-3      #: equivalent plastic strain that marks the plastic zone
#: the figures of `particles scratch --json` (SI), those of `md scratch --json`
JSON_KEYS = ("friction_mean", "friction_std", "normal_force_mean", "lateral_force_mean",
             "groove_depth", "groove_width", "pileup_height", "edge_height",
             "scratch_hardness", "steady_points")


@dataclass(frozen=True)
class ParticleScratchRun:
    """A finished run, SI: the record's columns, the first and final field dumps."""

    spec: ParticleScratchSpec
    run_dir: Path
    time: np.ndarray
    x_tip: np.ndarray
    depth: np.ndarray
    fx: np.ndarray        #: force on the indenter along x, N (whole model)
    fz: np.ndarray        #: force on the indenter along z (the normal force), N
    initial: FieldSnapshot
    final: FieldSnapshot
    steps: int
    wall_time: float

    @property
    def lateral_force(self) -> np.ndarray:
        """Against the motion positive: -F_x on a pass along +x, +F_x on one back."""
        return -self.fx * path_direction(self.spec.stroke, self.time)


def run_scratch(spec: ParticleScratchSpec, run_dir: Path | str,
                engine: EngineOptions = EngineOptions(), *,
                progress: Callable[[int, int], None] | None = None,
                version: str = "") -> ParticleScratchRun:
    """Run ``spec`` in ``run_dir`` (or read back the finished run of the same input)."""
    run_dir = Path(run_dir).resolve()
    run_particle_input(run_dir, f"in.{spec.method}", scratch_input(spec, version),
                       to_jsonable(spec.to_dict()),
                       [*run_dir.glob("fields.*.dump"), run_dir / RECORD, run_dir / FINAL_DUMP],
                       estimated_steps(spec), engine, progress)
    return read_scratch(spec, run_dir)


def read_scratch(spec: ParticleScratchSpec, run_dir: Path | str) -> ParticleScratchRun:
    """The record of a finished run directory, in SI (no LAMMPS)."""
    run_dir = Path(run_dir).resolve()
    state = json.loads((run_dir / STATE_FILE).read_text())
    columns, data = parse_table((run_dir / RECORD).read_text())
    if columns != COLUMNS:
        raise LammpsError(f"{RECORD} has columns {columns}, expected {COLUMNS}", run_dir)
    data = data[np.unique(data[:, 0], return_index=True)[1]]   # a row repeats at run start
    col = dict(zip(COLUMNS, data.T))
    dumps = sorted(run_dir.glob("fields.*.dump"), key=lambda p: int(p.stem.split(".")[1]))
    log = (run_dir / f"log.{state['input']}").read_text(errors="replace")
    steps = sum(int(ln.split(" for ")[1].split()[0]) for ln in log.splitlines()
                if ln.startswith("Loop time of"))
    length, force = ("length", "particle"), ("force", "particle")
    return ParticleScratchRun(
        spec=spec, run_dir=run_dir, time=lammps_to_si(col["time"], "time", "particle"),
        x_tip=lammps_to_si(col["x_tip"], *length), depth=lammps_to_si(col["depth"], *length),
        fx=lammps_to_si(col["fx"], *force), fz=lammps_to_si(col["fz"], *force),
        initial=read_snapshot(dumps[0]), final=read_snapshot(run_dir / FINAL_DUMP),
        steps=steps, wall_time=float(state.get("wall_time", 0.0)))


# ---- analysis ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class PlasticZone:
    layer: str
    width: float     #: m, y extent of the plastic particles in the mid-stroke section
    depth: float     #: m, below the undeformed surface
    particles: int

    def to_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class ParticleScratchAnalysis:
    """The figures of a particle scratch, SI; NaN where a figure cannot be found."""

    friction_mean: float
    friction_std: float
    normal_force_mean: float
    lateral_force_mean: float
    steady_points: int
    groove_depth: float
    groove_width: float
    pileup_height: float
    edge_height: float
    profile_y: np.ndarray
    profile_h: np.ndarray
    damage: tuple[PlasticZone, ...]
    particles: int
    steps: int
    wall_time: float
    plastic_threshold: float = PLASTIC_THRESHOLD
    scratch_hardness: float = math.nan     #: 8 F_n / (pi w^2), Pa (`scratch_hardness`)
    passes: tuple[PassFigures, ...] = ()   #: per pass (the first is the figures above)

    def to_dict(self) -> dict:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        d["profile_y"], d["profile_h"] = self.profile_y.tolist(), self.profile_h.tolist()
        d["damage"] = [z.to_dict() for z in self.damage]
        d["passes"] = [x.to_dict() for x in self.passes]
        return d

    def summary(self) -> str:
        lines = [f"friction {self.friction_mean:.4f} +- {self.friction_std:.4f} over "
                 f"{self.steady_points} points of the steady stroke; normal force "
                 f"{self.normal_force_mean:.4g} N, lateral force {self.lateral_force_mean:.4g} N",
                 f"residual groove at mid-stroke: depth {self.groove_depth:.4g} m, width "
                 f"{self.groove_width:.4g} m, pile-up {self.pileup_height:.4g} m (edge "
                 f"{self.edge_height:+.3g} m)"]
        for z in self.damage:
            lines.append(f"plastic zone (eps_p > {self.plastic_threshold:g}) in {z.layer}: "
                         f"width {z.width:.4g} m, depth {z.depth:.4g} m ({z.particles} "
                         "particles)")
        if len(self.passes) > 1:
            lines += [f"pass {x.number}: friction {x.friction_mean:.4f} +- {x.friction_std:.4f}, "
                      f"normal force {x.normal_force_mean:.4g} N" for x in self.passes]
        if math.isfinite(self.scratch_hardness):
            lines.append(f"scratch hardness 8 F_n / (pi w^2): {self.scratch_hardness:.4g} Pa")
        lines.append(f"{self.particles} particles, {self.steps} steps, {self.wall_time:.1f} s")
        return "\n".join(lines)


def particle_passes(run: ParticleScratchRun) -> tuple[PassFigures, ...]:
    """The friction and forces over the steady part of every pass."""
    s = run.spec.stroke
    t1, T, _, _ = s.times
    on_pass = [(run.time > t1 + k * T) & (run.time <= t1 + (k + 1) * T)
               for k in range(s.passes)]
    travel = np.zeros_like(run.x_tip)
    for k, on in enumerate(on_pass):
        travel[on] = run.x_tip[on] if k % 2 == 0 else s.length - run.x_tip[on]
    return pass_figures(on_pass, travel, s.length, run.fz, run.lateral_force)


def mid_section(run: ParticleScratchRun) -> np.ndarray:
    """The particles (final snapshot order) of the lattice column nearest mid-stroke x."""
    dx = run.spec.grid.spacing
    x0 = run.initial.positions[:, 0]
    x_col = round(0.5 * run.spec.stroke.length / dx) * dx
    if not np.array_equal(run.initial.ids, run.final.ids):
        raise LammpsError("the first and final dumps hold different particles", run.run_dir)
    return np.abs(x0 - x_col) <= 0.25 * dx


def groove_profile(run: ParticleScratchRun) -> tuple[np.ndarray, np.ndarray]:
    """(y, height) of the mid-stroke surface particles, sorted by y, m."""
    dx = run.spec.grid.spacing
    top = run.initial.positions[:, 2] > -0.25 * dx
    sel = mid_section(run) & top
    y = run.final.positions[sel, 1]
    h = run.final.positions[sel, 2] - run.initial.positions[sel, 2]
    if run.spec.grid.half:
        off = y > 0.25 * dx
        y, h = np.concatenate([-y[off], y]), np.concatenate([h[off], h])
    order = np.argsort(y)
    return y[order], h[order]


def layer_names(spec: ParticleScratchSpec) -> tuple[str, ...]:
    """The layers' names, top film first (their particle types are 1, 2, ...)."""
    films = [m.material.name for _, m in spec.target.films]
    names = [name if name and not name.startswith("target.") else f"film{k}"
             for k, name in enumerate(films, start=1)]
    sub = spec.target.substrate.material.name
    return (*names, sub if sub and not sub.startswith("target.") else "substrate")


def plastic_zones(run: ParticleScratchRun,
                  threshold: float = PLASTIC_THRESHOLD) -> tuple[PlasticZone, ...]:
    """The plastic zone of each layer in the mid-stroke section (module docstring)."""
    sel = mid_section(run)
    ep = run.final.plastic_strain
    hot = sel & (ep > threshold) if ep is not None else np.zeros_like(sel)
    types = run.final.types if run.final.types is not None else np.ones(sel.size, dtype=int)
    zones = []
    for k, name in enumerate(layer_names(run.spec), start=1):
        mine = hot & (types == k)
        if not np.any(mine):
            zones.append(PlasticZone(name, 0.0, 0.0, 0))
            continue
        y = run.initial.positions[mine, 1]
        width = 2 * float(np.max(np.abs(y))) if run.spec.grid.half else float(np.ptp(y))
        zones.append(PlasticZone(name, width, float(-np.min(run.initial.positions[mine, 2])),
                                 int(mine.sum())))
    return tuple(zones)


def analyze_scratch(run: ParticleScratchRun) -> ParticleScratchAnalysis:
    """Friction over the steady stroke, the residual groove and the plastic zone (module
    docstring)."""
    passes = particle_passes(run)
    first = passes[0]                  # the steady stroke: the first pass's steady part
    nan = math.nan
    y, h = groove_profile(run)
    a = run.spec.contact_radius
    depth, width = groove_depth_width(y, h, a)
    far = np.abs(y) > 2 * a
    zones = plastic_zones(run)
    return ParticleScratchAnalysis(
        friction_mean=first.friction_mean, friction_std=first.friction_std,
        normal_force_mean=first.normal_force_mean,
        lateral_force_mean=first.lateral_force_mean, steady_points=first.points,
        groove_depth=depth, groove_width=width,
        pileup_height=float(np.max(h)) if h.size else nan,
        edge_height=float(np.mean(h[far])) if np.any(far) else nan,
        profile_y=y, profile_h=h, damage=zones,
        particles=run.spec.grid.n_particles, steps=run.steps, wall_time=run.wall_time,
        scratch_hardness=scratch_hardness(first.normal_force_mean, width, depth > 0 and
                                          any(z.particles for z in zones), a),
        passes=passes)


# ---- record -----------------------------------------------------------------------------------

RECORD_FORMAT = "filmscale.md_particle_scratch/1"
RECORD_NAME = "particle_scratch.h5"


def write_scratch_record(run: ParticleScratchRun, analysis: ParticleScratchAnalysis,
                         provenance: dict | None = None) -> Path:
    """Write ``particle_scratch.h5`` atomically: ``history`` (time, x_tip, depth, normal and
    lateral force, SI), ``analysis`` (the figures as attributes, the groove profile and the
    plastic zone as datasets), ``inputs`` (the LAMMPS input and the spec), provenance as root
    attributes."""
    from filmscale.core.files import atomic_h5
    from filmscale.core.provenance import provenance as base_provenance
    from filmscale.md.engine import lammps_info

    path = run.run_dir / RECORD_NAME
    state = json.loads((run.run_dir / STATE_FILE).read_text())
    info = base_provenance(**{**lammps_info(), "engine": json.dumps(state.get("engine", {})),
                              **(provenance or {})})
    with atomic_h5(path) as f:
        f.attrs["format"] = RECORD_FORMAT
        f.attrs["kind"] = "scratch"
        f.attrs["method"] = run.spec.method
        for key, value in info.items():
            f.attrs[key] = value
        hist = f.create_group("history")
        for name, values, unit in (("time", run.time, "s"), ("x_tip", run.x_tip, "m"),
                                   ("depth", run.depth, "m"), ("normal_force", run.fz, "N"),
                                   ("lateral_force", run.lateral_force, "N")):
            hist[name] = values
            hist[name].attrs["units"] = unit
        res = f.create_group("analysis")
        d = analysis.to_dict()
        for key in (*JSON_KEYS, "particles", "steps", "wall_time", "plastic_threshold"):
            res.attrs[key] = d[key]
        res["profile_y"], res["profile_h"] = analysis.profile_y, analysis.profile_h
        res.attrs["damage"] = json.dumps(d["damage"])
        res.attrs["passes"] = json.dumps(d["passes"])
        inputs = f.create_group("inputs")
        inputs[state["input"]] = (run.run_dir / state["input"]).read_text()
        inputs["spec.json"] = json.dumps(to_jsonable(run.spec.to_dict()))
    return path
