"""The onset of a residual groove in the atomistic scratch against the Hertz first yield of the
film calibrated from its own indentation (issue 35, the MD ci item; docs/md-indentation.md,
"Groove onset against Hertz first yield"). `scratch_onset` is the particle counterpart.

`indentation_twin` is the scratch's sample (potential, slab cross-section and thickness,
lateral_size square), sphere and protocol as an indentation to a depth; `calibrate_twin`
calibrates it as the package calibrates a scene's ``md`` source
(`continuum.calibration.route.calibrate`, rigid tip, depth zero fitted; with a pop-in, the
pop-in law: E* from Hertz below half the pop-in load, and the pop-in's peak Hertz shear
stress tau_c = 0.31 p0 with that E*). `continuum.contact.hertz.load_at_peak_pressure` is the Hertz load at which
the peak pressure reaches p0: pi^3 R^2 p0^3 / (6 E*^2) (p0 = tau_c / 0.31 for the pop-in,
1.6 sigma_y for a von Mises sigma_y at nu = 0.3).

`load_ladder` scratches the spec at constant load (``scratch.normal_load``, ``max_depth``)
at each load, each in its own run directory (finished runs are read back, a stopped one
resumes and stops again), and records per load the steady normal force and depth, the
residual groove depth and the damaged atoms (`md.damage`, eta_Mises above 0.1) in the
groove's mid-stroke section and in the whole sample. A load has *grooved* when its groove is deeper than `GROOVE_FLOOR` or any atom of
the section is damaged, or when the tip ploughed past ``max_depth`` (the run stops,
`ModelRangeError`: the elastic contact at the ladder's loads sits well above it, so only
plastic flow takes it there; groove and damage are then not measured, NaN and -1). The
onset is the lowest grooved load, bracketed by the highest clean load below it.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from filmscale.core.errors import InputError, ModelRangeError
from filmscale.md.damage import THRESHOLD
from filmscale.md.engine import EngineOptions
from filmscale.md.indentation import IndentSpec
from filmscale.md.scratch import ScratchSpec
from filmscale.md.scratch_run import analyze_scratch, run_scratch

#: a residual groove shallower than this is no groove (m): elastic scratches of the ci film
#: leave 0.001 nm, the first plastic one 0.36 nm (docs/md-indentation.md)
GROOVE_FLOOR = 5e-11
#: the stroke of a held load (m): the shortest a scratch spec takes, a tenth of the ci
#: contact radius at 90 nN (0.95 nm)
HOLD_LENGTH = 1e-10
#: Hertz peak shear stress over p0 (Johnson 1985, nu = 0.3), as `pop_in_shear_stress`
SHEAR_OVER_P0 = 0.31


def indentation_twin(spec: ScratchSpec, depth: float, name: str | None = None) -> IndentSpec:
    """The indentation of ``spec``'s film: its potential, slab (square, lateral_size wide:
    the indentation slab the scratch repeats along x), sphere and protocol, to ``depth`` (m)."""
    ind = spec.indent
    return dataclasses.replace(ind, name=name or f"{ind.name}-indent", slab_built=None,
                               protocol=dataclasses.replace(ind.protocol, depth=depth))


@dataclass(frozen=True)
class FilmYield:
    """The calibrated film, SI: E_star (Pa) and the pop-in's load (N) and shear stress tau_c
    (Pa); sigma_y (Pa) and whether the calibration identified it (else a lower bound)."""

    E_star: float
    tau_c: float
    pop_in_load: float
    sigma_y: float
    sigma_y_identified: bool
    R: float

    @property
    def P_y(self) -> float:
        """The Hertz first-yield load from tau_c (N)."""
        from filmscale.continuum.contact.hertz import load_at_peak_pressure
        return float(load_at_peak_pressure(self.tau_c / SHEAR_OVER_P0, self.R, self.E_star))

    def to_dict(self) -> dict:
        return {**dataclasses.asdict(self), "P_y": self.P_y}


def calibrate_twin(curve, R: float, nu: float = 0.3) -> FilmYield:
    """Calibrate the twin's curve as a scene's ``md`` source (rigid tip; a half-space: the
    ci film is one crystal); InputError without a pop-in (no tau_c)."""
    from filmscale.continuum.calibration.route import calibrate
    cal = calibrate(curve, nu=nu, tip_material="rigid")
    if not cal.pop_in:
        raise InputError("the twin indentation has no pop-in: indent deeper")
    E_star = cal.E.value / (1.0 - nu**2)      # rigid tip: E = E* (1 - nu^2)
    return FilmYield(E_star, cal.pop_in["shear_stress"], cal.pop_in["load"],
                     cal.sigma_y.value, bool(cal.sigma_y.identified), R)


def held_film(film: FilmYield, hold: LadderOnset) -> FilmYield:
    """``film`` with its yield taken from a held-load ladder (``load_ladder(..., hold=True)``):
    tau_c (Pa) the Hertz peak shear stress 0.31 p0 (Johnson 1985, nu = 0.3) at the lowest
    load (N) that yielded in its hold, with the twin's E* (Pa), so that P_y is that load;
    ValueError when no held load yielded."""
    from filmscale.continuum.indentation.spherical import pop_in_shear_stress
    if not math.isfinite(hold.onset_load):
        raise ValueError("no held load yielded: hold heavier loads")
    tau_c = pop_in_shear_stress(hold.onset_load, film.E_star, film.R)
    return dataclasses.replace(film, tau_c=tau_c, pop_in_load=hold.onset_load)


def held(spec: ScratchSpec, load: float, max_depth: float) -> ScratchSpec:
    """`at_load` without the slide: the stroke shortened to `HOLD_LENGTH` and slowed so that
    it takes as long as ``spec``'s, so that the tip sits at the load for the scratch's time."""
    loaded = at_load(spec, load, max_depth)
    duration = spec.stroke.length / spec.stroke.speed
    stroke = dataclasses.replace(loaded.stroke, length=HOLD_LENGTH,
                                 speed=HOLD_LENGTH / duration)
    return dataclasses.replace(loaded, stroke=stroke)


def at_load(spec: ScratchSpec, load: float, max_depth: float) -> ScratchSpec:
    """``spec`` scratched at constant ``load`` (N), indented to it, tip at most
    ``max_depth`` (m) deep."""
    stroke = dataclasses.replace(spec.stroke, depth=None, normal_load=load,
                                 max_depth=max_depth)
    return dataclasses.replace(spec, stroke=stroke,
                               indent=spec.indent.with_protocol(depth=max_depth))


@dataclass(frozen=True)
class LadderPoint:
    """One load of the ladder, SI; groove NaN and damage -1 where the tip passed
    max_depth (``halted``)."""

    load: float
    normal_force: float       #: mean over the steady stroke, N
    depth: float              #: tip depth there, m
    groove_depth: float       #: m
    section_damaged: int      #: damaged atoms in the mid-stroke section
    damaged: int              #: damaged atoms in the sample
    halted: bool
    grooved: bool
    wall_time: float

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


@dataclass(frozen=True)
class LadderOnset:
    """The ladder and its onset: ``onset_load`` the lowest grooved load (N), ``clean_load``
    the highest clean one below it (NaN where none); ``ordered``: every load below the
    onset is clean (always, by construction) and every load above it grooved."""

    points: tuple[LadderPoint, ...]
    onset_load: float
    clean_load: float
    ordered: bool

    def to_dict(self) -> dict:
        return {"points": [p.to_dict() for p in self.points], "onset_load": self.onset_load,
                "clean_load": self.clean_load, "ordered": self.ordered}


def ladder_point(spec: ScratchSpec, run_dir: Path | str,
                 engine: EngineOptions = EngineOptions()) -> LadderPoint:
    """Scratch ``spec`` (constant load) in ``run_dir`` and judge its groove (module
    docstring)."""
    F = spec.stroke.normal_load
    if F is None:
        raise InputError("ladder_point: the spec scratches at constant depth; give it a "
                         "load (`at_load`)")
    start = time.perf_counter()
    nan = math.nan
    try:
        run = run_scratch(spec, run_dir, engine)
    except ModelRangeError:
        return LadderPoint(F, nan, nan, nan, -1, -1, True, True, time.perf_counter() - start)
    a = analyze_scratch(run)
    section = sum(d.atoms for d in a.damage)
    damaged = int(np.sum(np.nan_to_num(a.eta_mises, nan=0.0) > THRESHOLD))
    grooved = bool(a.groove_depth > GROOVE_FLOOR or section > 0)
    return LadderPoint(F, a.normal_force_mean, a.depth_mean, a.groove_depth, section, damaged,
                       False, grooved, time.perf_counter() - start)


def load_ladder(spec: ScratchSpec, loads: Sequence[float], max_depth: float,
                run_root: Path | str, engine: EngineOptions = EngineOptions(),
                hold: bool = False) -> LadderOnset:
    """Scratch ``spec`` at each of ``loads`` (N, increasing) in ``run_root/load_K`` and find
    the onset (module docstring); with ``hold`` each load is `held` instead (the film's
    first yield under a sustained load, for the scratch's time)."""
    loads = [float(F) for F in loads]
    if not loads or any(b <= a for a, b in zip(loads, loads[1:])):
        raise InputError(f"loads = {loads}: give one or more, increasing")
    root = Path(run_root)
    loaded = held if hold else at_load
    points = tuple(ladder_point(loaded(spec, F, max_depth), root / f"load_{k}", engine)
                   for k, F in enumerate(loads))
    first = next((k for k, p in enumerate(points) if p.grooved), None)
    if first is None:
        return LadderOnset(points, math.nan, points[-1].load, True)
    clean = points[first - 1].load if first else math.nan
    return LadderOnset(points, points[first].load, clean,
                       all(p.grooved for p in points[first:]))
