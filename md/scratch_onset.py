"""The onset of a residual groove in the particle scratch against the sliding model's first
yield (issue 35's cross-scale check; docs/particles.md, "Groove onset").

`groove_onset` runs one particle scratch spec (`filmscale.md.particle_scratch`) at a sequence
of depths, each in its own run directory, and records per depth the mean normal force of the
steady stroke (`analyze_scratch`'s ``normal_force_mean``), the residual groove depth and the
largest TLSPH equivalent plastic strain after the relaxation of the particles under the steady
stroke (initial x between `STEADY` 20 % and 80 % of its length: the descent's own indent at
x = 0 is left out). A depth has *yielded* when any of them has a plastic strain above
``threshold`` (`ONSET_THRESHOLD`, 1e-4);
the onset load is the midpoint of the normal forces of the last clean depth and the first
yielded one, its uncertainty half their difference.

`model_first_yield_load` is the sliding model's answer for the same target, sphere and
friction (`continuum.contact.slider.slide`: the largest von Mises stress over sigma_y scales
as p0 ~ P^(1/3) in a Hertz contact, so the first-yield load is P / ratio^3), and
`hertz_first_yield` the depth and contact radius there (Hertz: delta_y = a_y^2 / R).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError
from filmscale.md.engine import EngineOptions
from filmscale.md.particle_scratch import ParticleScratchSpec
from filmscale.md.particle_scratch_run import analyze_scratch, run_scratch
from filmscale.md.scratch_run import STEADY

#: equivalent plastic strain above which a particle has yielded (the onset criterion)
ONSET_THRESHOLD = 1e-4


@dataclass(frozen=True)
class OnsetPoint:
    """One depth of the sequence, SI."""

    depth: float
    normal_force: float       #: mean over the steady stroke, N
    groove_depth: float       #: residual, mid-stroke, m
    plastic_max: float        #: largest equivalent plastic strain under the steady stroke
    plastic_particles: int    #: particles there above the threshold
    plastic_max_block: float  #: largest equivalent plastic strain of the whole block
    yielded: bool
    wall_time: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class GrooveOnset:
    """The sequence and its onset: ``onset_load`` (N) the midpoint of the normal forces of the
    last clean and the first yielded depth, ``onset_error`` half their difference; NaN when the
    sequence does not bracket the onset."""

    points: tuple[OnsetPoint, ...]
    threshold: float
    onset_load: float
    onset_error: float
    onset_depth: float

    def to_dict(self) -> dict:
        return {"points": [p.to_dict() for p in self.points], "threshold": self.threshold,
                "onset_load": self.onset_load, "onset_error": self.onset_error,
                "onset_depth": self.onset_depth}


def at_depth(spec: ParticleScratchSpec, depth: float) -> ParticleScratchSpec:
    """``spec`` with the scratch at ``depth`` (m), everything else kept."""
    return dataclasses.replace(spec, stroke=dataclasses.replace(spec.stroke, depth=depth))


def _point(args) -> OnsetPoint:
    spec, run_dir, engine, threshold = args
    run = run_scratch(spec, run_dir, engine)
    a = analyze_scratch(run)
    ep = run.final.plastic_strain
    ep = np.zeros(run.initial.positions.shape[0]) if ep is None else ep
    x, L = run.initial.positions[:, 0], spec.stroke.length
    under = ep[(x >= STEADY[0] * L) & (x <= STEADY[1] * L)]
    hot = int(np.sum(under > threshold))
    return OnsetPoint(spec.stroke.depth, a.normal_force_mean, a.groove_depth,
                      float(np.max(under)), hot, float(np.max(ep)), hot > 0, run.wall_time)


def groove_onset(spec: ParticleScratchSpec, depths: Sequence[float], run_root: Path | str,
                 engine: EngineOptions = EngineOptions(), *, threshold: float = ONSET_THRESHOLD,
                 jobs: int = 1) -> GrooveOnset:
    """Scratch ``spec`` at each of ``depths`` (m, increasing) in ``run_root/depth_K`` (finished
    runs are read back), ``jobs`` at a time (processes), and find the onset (module
    docstring)."""
    depths = [float(d) for d in depths]
    if len(depths) < 2 or any(b <= a for a, b in zip(depths, depths[1:])):
        raise InputError(f"depths = {depths}: give at least two, increasing")
    if not isinstance(jobs, int) or not 1 <= jobs <= 64:
        raise InputError(f"jobs = {jobs!r} must be an integer in [1, 64]")
    root = Path(run_root)
    tasks = [(at_depth(spec, d), root / f"depth_{k}", engine, threshold)
             for k, d in enumerate(depths)]
    if jobs == 1:
        points = tuple(_point(t) for t in tasks)
    else:
        with ProcessPoolExecutor(jobs) as pool:
            points = tuple(pool.map(_point, tasks))
    first = next((k for k, p in enumerate(points) if p.yielded), None)
    nan = math.nan
    if first is None or first == 0:
        return GrooveOnset(points, threshold, nan, nan, nan)
    lo, hi = points[first - 1], points[first]
    return GrooveOnset(points, threshold, 0.5 * (lo.normal_force + hi.normal_force),
                       0.5 * (hi.normal_force - lo.normal_force), 0.5 * (lo.depth + hi.depth))


def model_first_yield_load(spec: ParticleScratchSpec, mu: float = 0.0) -> float:
    """The sliding model's first-yield load (N) of ``spec``'s target, sphere and friction
    ``mu``: `slide` at a trial load, then P / yield_ratio^3 (Hertz: the stresses scale with
    p0 ~ P^(1/3) at a given friction)."""
    from filmscale.continuum.contact.slider import Slider, slide

    stack, R = spec.target.stack, spec.tip.R
    if math.isinf(stack.substrate.sigma_y):
        raise InputError("the target is elastic (no sigma_y): it has no first yield")
    P = hertz_first_yield(spec)[0]      # a trial load near the answer
    ratio = slide(stack, Slider("sphere", R), P, mu).first_yield["yield_ratio"]
    return P / ratio**3


def hertz_first_yield(spec: ParticleScratchSpec, p0_over_sigma_y: float = 1.6
                      ) -> tuple[float, float, float]:
    """(P_y, a_y, delta_y), SI: the Hertz load, contact radius and depth at which the peak
    pressure reaches ``p0_over_sigma_y`` sigma_y (1.6: a frictionless sphere, nu = 0.3,
    von Mises; Johnson 1985)."""
    from filmscale.continuum.contact.hertz import load_at_peak_pressure
    E_star = spec.target.reduced_modulus()
    R = spec.tip.R
    p0 = p0_over_sigma_y * spec.target.substrate.material.sigma_y
    a = math.pi * p0 * R / (2 * E_star)
    return float(load_at_peak_pressure(p0, R, E_star)), a, a * a / R
