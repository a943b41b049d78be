"""Running a particle model and reading what it wrote: curves and histories in SI, field
snapshots, and the figures compared with the continuum models.

A run directory holds the input (``in.tlsph`` or ``in.peri``), the LAMMPS log, the record
(``particles.dat``), the snapshots (``fields.STEP.dump``) and ``state.json``. A directory whose
run finished with the same input is read back without LAMMPS. MACHDYN cannot write restart
files, so an interrupted run starts again (the longest preset takes minutes).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from filmscale.continuum.contact.hertz import elastic_impact, hertz_force
from filmscale.continuum.indentation.curves import HOLD, LOAD, UNLOAD, LoadDisplacementCurve
from filmscale.continuum.indentation.tips import Cone, Sphere, SphericalCone
from filmscale.core.errors import InputError
from filmscale.core.files import read_json, write_json
from filmscale.core.jsonable import to_jsonable
from filmscale.core.quantities import eng
from filmscale.md.engine import EngineOptions, LammpsError, parse_table, run_input
from filmscale.md.lammps_input import write_input
from filmscale.md.particle_inputs import (IMPACT_COLUMNS, INDENT_COLUMNS, RECORD, estimated_steps,
                                          input_text)
from filmscale.md.particles import ParticleImpactSpec, ParticleIndentSpec
from filmscale.md.lammps_units import lammps_to_si

STATE_FILE = "state.json"
#: The unloading load below which the contact counts as open: 1 % of the peak load.
OPEN_FRACTION = 0.01


@dataclass(frozen=True)
class FieldSnapshot:
    """One dump of the particle fields, SI: positions (m); for TLSPH the von Mises stress (Pa)
    and the equivalent plastic strain, for PERI the bond damage (0 while elastic). Fields a
    method does not give are None."""

    step: int
    ids: np.ndarray
    positions: np.ndarray
    von_mises: np.ndarray | None
    plastic_strain: np.ndarray | None
    damage: np.ndarray | None
    types: np.ndarray | None = None     #: particle type (1 the top film of a layered target)


def read_snapshot(path: Path | str) -> FieldSnapshot:
    """A ``fields.STEP.dump`` text dump, read by its column names."""
    lines = Path(path).read_text().splitlines()
    step = int(lines[1])
    header = next(i for i, ln in enumerate(lines) if ln.startswith("ITEM: ATOMS"))
    names = lines[header].split()[2:]
    data = np.loadtxt(lines[header + 1:], ndmin=2)
    data = data[np.argsort(data[:, 0])]
    col = {name: data[:, k] for k, name in enumerate(names)}
    xyz = np.column_stack([col["x"], col["y"], col["z"]])
    return FieldSnapshot(
        step=step, ids=col["id"].astype(int), positions=lammps_to_si(xyz, "length", "particle"),
        von_mises=lammps_to_si(col["c_stress[7]"], "pressure", "particle")
        if "c_stress[7]" in col else None,
        plastic_strain=col.get("c_ep"), damage=col.get("c_damage"),
        types=col["type"].astype(int) if "type" in col else None)


@dataclass(frozen=True)
class ParticleRun:
    """A finished run: the record in SI, its files and its cost."""

    spec: ParticleIndentSpec | ParticleImpactSpec
    run_dir: Path
    time: np.ndarray          #: s
    depth: np.ndarray         #: indenter depth or sphere approach below the surface, m
    load: np.ndarray          #: contact force, N
    extra: np.ndarray         #: apex particle height (indent, m) or sphere velocity (m/s)
    snapshots: tuple[Path, ...]
    steps: int
    wall_time: float

    def curve(self) -> LoadDisplacementCurve:
        """The load-displacement curve with load/hold/unload segments."""
        spec = self.spec
        if isinstance(spec, ParticleIndentSpec):
            t1, t2, _ = spec.loading.times
            segment = np.where(self.time <= t1, LOAD, np.where(self.time <= t2, HOLD, UNLOAD))
        else:
            segment = np.where(np.arange(self.time.size) <= int(np.argmax(self.depth)),
                               LOAD, UNLOAD)
        return LoadDisplacementCurve(
            h=self.depth, P=self.load, t=self.time, segment=segment, indenter=spec.tip,
            meta={"source": f"filmscale.md particle model ({spec.method})", "name": spec.name,
                  "run_dir": str(self.run_dir), "base_depth": spec.grid.depth})


def run_particles(spec: ParticleIndentSpec | ParticleImpactSpec, run_dir: Path | str,
                  engine: EngineOptions = EngineOptions(), *,
                  progress: Callable[[int, int], None] | None = None,
                  version: str = "") -> ParticleRun:
    """Run ``spec`` in ``run_dir`` (or read back the finished run of the same input there).
    ``progress(step, estimated_total)`` reports the timestep.

    PERI runs in a process of its own (``mpirun``) unless a mode is forced: in a process that
    has run LAMMPS before, peri/lps gave a different load for the same input in 1 of 4
    repeats (0.99 against 1.12 x Hertz, ci preset), which separate processes never did."""
    if spec.method == "peri" and engine.mode == "auto":
        engine = replace(engine, mode="mpirun")
    run_dir = Path(run_dir).resolve()
    name = f"in.{spec.method}"
    # compared as written: JSON has no NaN or infinity (`to_jsonable` writes them as null;
    # an elastic material's sigma_y is infinite)
    run_particle_input(run_dir, name, input_text(spec, version), to_jsonable(spec.to_dict()),
                       [*run_dir.glob("fields.*.dump"), run_dir / RECORD],
                       estimated_steps(spec), engine, progress)
    return read_particles(spec, run_dir)


def run_particle_input(run_dir: Path, name: str, text: str, spec_dict: dict, stale: list[Path],
                       total: int, engine: EngineOptions,
                       progress: Callable[[int, int], None] | None = None) -> bool:
    """Run the particle-model input ``text`` (file ``name``) in ``run_dir`` to its
    ``finished.txt``, or leave a finished run of the very same input as it is (returns
    False: nothing ran). A directory holding another spec (``spec_dict``) is refused; the
    ``stale`` outputs of an unfinished run are removed first. ``progress(step, total)``
    reports the timestep. Shared by the indentation, impact and scratch runs."""
    run_dir.mkdir(parents=True, exist_ok=True)
    state_path = run_dir / STATE_FILE
    state = read_json(state_path, "run state") if state_path.exists() else {}
    if state.get("finished") and (run_dir / name).exists() \
            and (run_dir / name).read_text() == text:
        return False
    if state.get("spec") is not None and to_jsonable(state["spec"]) != spec_dict:
        raise InputError("the run directory holds a run of a different spec; choose another "
                         f"directory (run directory {run_dir})")
    for old in [*stale, run_dir / "finished.txt"]:
        old.unlink(missing_ok=True)
    write_input(run_dir / name, text)
    state = {"spec": spec_dict, "input": name, "finished": False, "engine": engine.to_dict()}
    write_json(state_path, state)
    report = (lambda step: progress(step, total)) if progress is not None else None
    started = time.perf_counter()
    run_input(name, run_dir, engine, log_name=f"log.{name}", progress=report)
    if not (run_dir / "finished.txt").exists():
        raise LammpsError("LAMMPS stopped before the end of the run (no finished.txt); see "
                          f"log.{name}", run_dir)
    state.update(finished=True, wall_time=time.perf_counter() - started)
    write_json(state_path, state)
    return True


def read_particles(spec: ParticleIndentSpec | ParticleImpactSpec,
                   run_dir: Path | str) -> ParticleRun:
    """The record of a finished run directory, in SI (no LAMMPS)."""
    run_dir = Path(run_dir).resolve()
    state = json.loads((run_dir / STATE_FILE).read_text())
    columns, data = parse_table((run_dir / RECORD).read_text())
    impact = isinstance(spec, ParticleImpactSpec)
    expected = IMPACT_COLUMNS if impact else INDENT_COLUMNS
    if columns != expected:
        raise LammpsError(f"{RECORD} has columns {columns}, expected {expected}", run_dir)
    data = data[np.unique(data[:, 0], return_index=True)[1]]   # a row repeats at run start
    col = dict(zip(expected, data.T))
    depth = col["approach"] if impact else col["depth"]
    extra = lammps_to_si(col["velocity"], "velocity", "particle") if impact else \
        -lammps_to_si(col["apex"], "length", "particle")
    log = (run_dir / f"log.{state['input']}").read_text(errors="replace")
    steps = [int(s) for s in _loop_steps(log)]
    snapshots = tuple(sorted(run_dir.glob("fields.*.dump"),
                             key=lambda p: int(p.stem.split(".")[1])))
    return ParticleRun(spec=spec, run_dir=run_dir, time=lammps_to_si(col["time"], "time", "particle"),
                       depth=lammps_to_si(depth, "length", "particle"),
                       load=lammps_to_si(col["load"], "force", "particle"), extra=extra,
                       snapshots=snapshots, steps=sum(steps),
                       wall_time=float(state.get("wall_time", 0.0)))


def _loop_steps(log: str):
    for line in log.splitlines():
        if line.startswith("Loop time of"):
            yield line.split(" for ")[1].split()[0]


# ---------------------------------------------------------------- analysis


def block_hertz_force(delta, R: float, E: float, nu: float, base_depth: float):
    """Hertz load on a finite elastic block of depth H on a rigid base, N, to first order:
    the base holds the point at depth H still, which in a half-space would move by the
    Boussinesq on-axis displacement u(H) = P (1 + nu)(3 - 2 nu) / (2 pi E H) (Johnson 1985,
    eq. 3.22); the indenter's approach is then delta = delta_Hertz(P) - u(H). Solved for P
    by fixed-point iteration; it explains the excess of a block over Hertz (about 18 % at
    0.1 R with H = 2 R)."""
    return block_elastic_force(delta, Sphere(R), E, nu, base_depth)


def sneddon_force(h, tip: Cone, E_star: float):
    """Elastic load of a sharp tip through its equivalent cone, N: P = beta (2/pi) E* tan(alpha)
    h^2 (Sneddon 1965) with alpha the equivalent half-angle (70.3 deg for Berkovich) and beta
    the tip's shape factor (1 for a cone, 1.034 for a three-sided pyramid, King 1987)."""
    C = tip.beta * 2 / math.pi * E_star * math.tan(math.radians(tip.half_angle))
    return C * np.asarray(h, dtype=float)**2


def sphero_conical_force(h, tip: SphericalCone, E_star: float):
    """Elastic load of a sphero-conical tip, N, from Sneddon's (1965) solution for a rigid
    axisymmetric punch of profile f(r): h = a int_0^a f'(r) / sqrt(a^2 - r^2) dr and
    P = 2 E* int_0^a r^2 f'(r) / sqrt(a^2 - r^2) dr, with f' = r / sqrt(R^2 - r^2) on the
    spherical cap (r <= R cos theta) and cot(theta) on the cone. Both integrals are taken
    in r = a sin(phi), which removes the end singularity."""
    from scipy.optimize import brentq
    theta = math.radians(tip.half_angle)
    b, cot = tip.R * math.cos(theta), 1 / math.tan(theta)

    def slope(r):
        return np.where(r <= b, r / np.sqrt(np.maximum(tip.R**2 - r**2, 1e-300)), cot)

    phi, w = np.polynomial.legendre.leggauss(400)
    phi, w = 0.25 * math.pi * (phi + 1), 0.25 * math.pi * w       # Gauss-Legendre on [0, pi/2]

    def depth(a):
        return a * np.sum(w * slope(a * np.sin(phi)))

    def load(a):
        r = a * np.sin(phi)
        return 2 * E_star * np.sum(w * r**2 * slope(r))

    out = []
    for target in np.atleast_1d(np.asarray(h, dtype=float)):
        if target <= 0:
            out.append(0.0)
            continue
        hi = 1.0 * tip.R
        while depth(hi) < target:
            hi *= 2
        out.append(load(brentq(lambda a: depth(a) - target, 0.0, hi, xtol=1e-15,
                               rtol=1e-12)))
    return np.asarray(out).reshape(np.shape(h))


def elastic_tip_force(h, tip, E_star: float):
    """Elastic load of ``tip`` on a half-space of reduced modulus E*, N: Hertz for a sphere,
    `sneddon_force` for a sharp cone or pyramid, `sphero_conical_force` for a rounded cone."""
    if isinstance(tip, Sphere):
        return hertz_force(h, tip.R, E_star)
    if isinstance(tip, SphericalCone):
        return sphero_conical_force(h, tip, E_star)
    return sneddon_force(h, tip, E_star)


def block_elastic_force(h, tip, E: float, nu: float, base_depth: float):
    """`elastic_tip_force` on a finite block of depth H on a rigid base, N, to the first order
    of `block_hertz_force`: P(h) = P_half-space(h + c P), c = (1 + nu)(3 - 2 nu)/(2 pi E H),
    solved by fixed-point iteration."""
    h = np.asarray(h, dtype=float)
    E_star = E / (1 - nu**2)
    c = (1 + nu) * (3 - 2 * nu) / (2 * math.pi * E * base_depth)
    P = elastic_tip_force(h, tip, E_star)
    for _ in range(200):
        P_new = elastic_tip_force(h + c * P, tip, E_star)
        if np.allclose(P_new, P, rtol=1e-12, atol=0.0):
            break
        P = P_new
    return P_new


class _Figures:
    """``to_dict`` of the result dataclasses below: their fields are plain scalars."""

    def to_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class IndentResult(_Figures):
    """Figures of a particle indentation, SI: the largest load and the largest indenter depth;
    ``C`` the least-squares Kick's-law curvature P = C h^2 over the whole loading (Pa; for
    sharp tips); ``hertz_ratio`` = P_max / Hertz load at h_max
    with the top material's E* (elastic targets; NaN otherwise); ``sneddon_ratio`` for a
    sharp cone, pyramid or sphero-conical tip the least-squares ratio of the load to
    `elastic_tip_force` over the second half of the loading; ``block_ratio`` the same
    against the finite-block forms `block_hertz_force` (at h_max) or `block_elastic_force`
    (homogeneous elastic targets)."""

    P_max: float
    h_max: float
    C: float
    residual_depth: float
    hertz_ratio: float
    block_ratio: float
    particles: int
    steps: int
    wall_time: float
    sneddon_ratio: float = float("nan")

    def summary(self) -> str:
        closed = "Hertz" if math.isfinite(self.hertz_ratio) else "Sneddon"
        ratio = self.hertz_ratio if closed == "Hertz" else self.sneddon_ratio
        return (f"P_max {eng(self.P_max, 'N')} at h_max {eng(self.h_max, 'm')}; loading "
                f"curvature C = P/h^2 {eng(self.C, 'Pa')}; residual depth "
                f"{eng(self.residual_depth, 'm')}; {closed} ratio {ratio:.3f} "
                f"(finite block {self.block_ratio:.3f}); {self.particles} particles, "
                f"{self.steps} steps, {self.wall_time:.1f} s")


def residual_from_unloading(depth, load, unloading) -> float:
    """Depth where the unloading load first falls below `OPEN_FRACTION` of the peak, m."""
    P_max = float(np.max(load))
    idx = np.flatnonzero(unloading & (load <= OPEN_FRACTION * P_max))
    return float(depth[idx[0]]) if idx.size else float("nan")


def _fit_ratio(P, reference) -> float:
    """The least-squares factor k of P = k * reference."""
    reference = np.asarray(reference, dtype=float)
    return float(np.sum(P * reference) / np.sum(reference**2)) if reference.size else math.nan


def analyze_indent(run: ParticleRun) -> IndentResult:
    spec = run.spec
    curve = run.curve()
    P_max, h_max = float(np.max(run.load)), float(np.max(run.depth))
    hertz = sneddon = block = float("nan")
    m = spec.target.substrate.material
    homogeneous = spec.target.elastic and not spec.target.layered
    if isinstance(spec.tip, Sphere) and spec.target.elastic:
        hertz = P_max / float(hertz_force(h_max, spec.tip.R, spec.target.reduced_modulus(0)))
        if homogeneous:
            block = P_max / float(block_hertz_force(h_max, spec.tip.R, m.E, m.nu,
                                                    spec.grid.depth))
    elif spec.target.elastic and (isinstance(spec.tip, SphericalCone) or (
            isinstance(spec.tip, Cone) and spec.tip.tip_radius == 0)):
        # a single point of a sharp tip's curve is lattice noise (5-8 % here): the ratio is
        # the least-squares one over the second half of the loading
        sel = (curve.segment == LOAD) & (run.depth >= 0.5 * h_max)
        h, P = run.depth[sel], run.load[sel]
        sneddon = _fit_ratio(P, elastic_tip_force(h, spec.tip, spec.target.reduced_modulus(0)))
        if homogeneous:
            block = _fit_ratio(P, block_elastic_force(h, spec.tip, m.E, m.nu, spec.grid.depth))
    return IndentResult(P_max=P_max, h_max=h_max, C=curve.loading_curvature(),
                        residual_depth=residual_from_unloading(
                            run.depth, run.load, curve.segment == UNLOAD),
                        hertz_ratio=hertz, block_ratio=block, sneddon_ratio=sneddon,
                        particles=spec.grid.n_particles, steps=run.steps,
                        wall_time=run.wall_time)


@dataclass(frozen=True)
class ImpactOutcome(_Figures):
    """Figures of a particle impact, SI, beside the elastic Hertz closed forms on the top
    material (`elastic_impact`)."""

    delta_max: float
    P_max: float
    contact_time: float
    residual_depth: float
    restitution: float
    rebound_velocity: float
    separated: bool
    hertz_delta_max: float
    hertz_force_max: float
    hertz_contact_time: float
    particles: int
    steps: int
    wall_time: float

    def summary(self) -> str:
        return (f"delta_max {eng(self.delta_max, 'm')} (Hertz {eng(self.hertz_delta_max, 'm')}); "
                f"P_max {eng(self.P_max, 'N')} (Hertz {eng(self.hertz_force_max, 'N')}); "
                f"restitution {self.restitution:.3f}; residual depth "
                f"{eng(self.residual_depth, 'm', 3)}; contact {eng(self.contact_time, 's')} "
                f"(Hertz {eng(self.hertz_contact_time, 's')}); "
                f"{self.particles} particles, {self.steps} steps, {self.wall_time:.1f} s")


def analyze_impact(run: ParticleRun) -> ImpactOutcome:
    spec = run.spec
    V = spec.velocity
    in_contact = np.flatnonzero(run.load > 0)
    i_max = int(np.argmax(run.depth))
    after = np.flatnonzero((np.arange(run.load.size) > i_max) & (run.load <= 0))
    separated = after.size > 0
    end = after[0] if separated else run.load.size - 1
    t_end = run.time[end]
    t_start = run.time[in_contact[0]] if in_contact.size else 0.0
    v_out = float(run.extra[-1])
    hertz = elastic_impact(spec.mass, spec.tip.R, V, spec.target.reduced_modulus(0))
    return ImpactOutcome(
        delta_max=float(run.depth[i_max]), P_max=float(np.max(run.load)),
        contact_time=float(t_end - t_start) if separated else float("nan"),
        residual_depth=float(run.depth[end]) if separated else float("nan"),
        restitution=v_out / V if separated else float("nan"),
        rebound_velocity=v_out, separated=separated,
        hertz_delta_max=float(hertz.delta_max), hertz_force_max=float(hertz.force_max),
        hertz_contact_time=float(hertz.contact_time),
        particles=spec.grid.n_particles, steps=run.steps, wall_time=run.wall_time)


# ---------------------------------------------------------------- record

RECORD_FORMAT = "filmscale.md_particles/1"
RECORD_NAME = "particles.h5"


def write_particle_record(run: ParticleRun, result: IndentResult | ImpactOutcome,
                          provenance: dict | None = None,
                          path: Path | str | None = None) -> Path:
    """Write ``particles.h5`` atomically: ``curve`` (filmscale.curve/1: depth or approach
    against load, with time), ``result`` (attributes, SI), ``inputs`` (the LAMMPS input and
    the spec as JSON), ``snapshots`` (the field dump files); provenance (filmscale and LAMMPS
    versions and packages, the command) as root attributes."""
    from filmscale.continuum.indentation.io import write_curve_group
    from filmscale.core.files import atomic_h5
    from filmscale.core.provenance import provenance as base_provenance
    from filmscale.md.engine import lammps_info

    path = Path(path) if path is not None else run.run_dir / RECORD_NAME
    state = json.loads((run.run_dir / STATE_FILE).read_text())
    info = base_provenance(**{**lammps_info(), "engine": json.dumps(state.get("engine", {})),
                              **(provenance or {})})
    with atomic_h5(path) as f:
        f.attrs["format"] = RECORD_FORMAT
        f.attrs["kind"] = "impact" if isinstance(run.spec, ParticleImpactSpec) else "indent"
        f.attrs["method"] = run.spec.method
        for key, value in info.items():
            f.attrs[key] = value
        write_curve_group(f.create_group("curve"), run.curve())
        name = "velocity" if isinstance(run.spec, ParticleImpactSpec) else "apex_depth"
        f["curve"][name] = run.extra
        f["curve"][name].attrs["units"] = "m/s" if name == "velocity" else "m"
        res = f.create_group("result")
        for key, value in result.to_dict().items():
            res.attrs[key] = value
        inputs = f.create_group("inputs")
        inputs[state["input"]] = (run.run_dir / state["input"]).read_text()
        inputs["spec.json"] = json.dumps(run.spec.to_dict(), default=str)
        snaps = f.create_group("snapshots")
        for p in run.snapshots:
            snaps.attrs[p.name] = str(p)
    return path
