"""An ensemble of MD indentations: one protocol run with several seeds.

A single MD trajectory carries thermal noise and one draw of the pop-in load, and its scatter
is not in a single fit's standard deviations. The members are fitted together, each with its
own pop-in and one contact zero (`calibrate` of the curves: E from the elastic points before
each pop-in, sigma_y after them), and each alone: the layer gets the joint fit's E and
sigma_y with the larger of its std and the seed-to-seed standard error of the members' mean.
The mean of the members' own values is not the estimate: each fit is nonlinear in its noise,
and at 1 % noise with the zero fitted their mean E is 3 % low (tests/continuum/
test_pop_in_law.py). Nor is the ensemble's mean curve fitted: where the members' pop-ins
fall at different depths it has no pop-in of its own, only a gradual bend, and the law then
trades E against the averaged overshoot (113 GPa from 70 GPa members in the test). The
seed-to-seed scatter of the load (members of one protocol are sampled alike, so point by
point) is the curves' noise model, from which the cross-scale check takes its tolerance; the
pop-in load, depth and shear stress (0.31 p0, Johnson 1985) are given as mean and scatter
over the members.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.core.errors import InputError

from .result import Calibration, Parameter
from .route import calibrate


def sampled_alike(curves) -> bool:
    """The curves have one protocol's sampling: the same number of points and the same
    segments (what `ensemble_mean` averages point by point)."""
    first = curves[0]
    return all(c.h.size == first.h.size and np.array_equal(c.segment, first.segment)
               for c in curves)


def ensemble_mean(curves) -> tuple[LoadDisplacementCurve, np.ndarray]:
    """The point-by-point mean curve of members sampled alike (one protocol: the same number
    of points and the same segments) and the seed-to-seed standard deviation of the load (N)
    at each point."""
    curves = list(curves)
    if len(curves) < 2:
        raise InputError(f"an ensemble needs at least 2 curves, got {len(curves)}")
    first = curves[0]
    if not sampled_alike(curves):
        raise InputError("the ensemble's curves are not sampled alike (number of points or "
                         "segments differ): they must come from one protocol")
    h = np.mean([c.h for c in curves], axis=0)
    P = np.array([c.P for c in curves])
    mean = LoadDisplacementCurve(h, P.mean(axis=0), segment=first.segment,
                                 indenter=first.indenter,
                                 meta={"source": f"mean of {len(curves)} seeds",
                                       "members": [str(c.meta.get("source", "")) for c in
                                                   curves]})
    return mean, P.std(axis=0, ddof=1)


def calibrate_ensemble(curves, *, nu: float, tip_material: str = "rigid",
                       thickness: float | None = None, substrate=None, **options
                       ) -> Calibration:
    """A layer from an ensemble of curves of one protocol (`calibrate`'s options): E and
    sigma_y of one fit of all members (each with its own pop-in), each std the larger of the
    fit's and the seed-to-seed standard error of the members' own values, the seed-to-seed
    load scatter as the curves' noise, the pop-in statistics. The fitted curves are the
    joint fit's."""
    curves = list(curves)
    mean, P_std = ensemble_mean(curves)
    members = [calibrate(c, nu=nu, tip_material=tip_material, thickness=thickness,
                         substrate=substrate, **options) for c in curves]
    # the values from one fit of all members (each with its own pop-in, one contact zero):
    # the mean of members fitted one by one is biased where each fit is nonlinear in its
    # noise (E 3 % low at 1 % noise with the zero fitted, tests/continuum/test_pop_in_law.py)
    together = calibrate(curves, nu=nu, tip_material=tip_material, thickness=thickness,
                         substrate=substrate, **options)
    n = len(members)

    def pooled(name: str) -> Parameter:
        """The joint fit's value; its std the larger of the joint fit's and the standard
        error of the members' mean (the seed-to-seed scatter)."""
        values = np.array([getattr(m, name).value for m in members])
        joint = getattr(together, name)
        sem = float(values.std(ddof=1)) / math.sqrt(n)
        std = max(sem, joint.std) if math.isfinite(joint.std) else sem
        return replace(joint, std=std, identified=joint.identified and all(
            getattr(m, name).identified for m in members))

    load = mean.segment == 0
    noise = float(np.sqrt(np.mean((P_std[load] / np.max(mean.P[load]))**2)))
    E, sigma_y = pooled("E"), pooled("sigma_y")
    spread = ", ".join(f"{m.E.value:.4g}" for m in members)
    return replace(
        together, E=E, sigma_y=sigma_y,
        uncertainty=f"one fit of {n} members"
                    + (" (each with its own pop-in)" if together.pop_in else "")
                    + "; std the larger of "
                    f"the fit's and the standard error of the members' mean over the seeds "
                    f"(members' E alone: {spread} Pa)",
        sources=tuple(str(c.meta.get("source", f"seed {i}")) for i, c in enumerate(curves)),
        warnings=tuple(dict.fromkeys(w for m in (together, *members) for w in m.warnings)),
        curve_noise=noise, correlation=_member_correlation(members))


def _member_correlation(members) -> float:
    """The correlation of the members' E and sigma_y (the seed-to-seed scatter of both), 0
    with fewer than three members or a constant one."""
    E = np.array([m.E.value for m in members])
    sy = np.array([m.sigma_y.value for m in members])
    if E.size < 3 or np.ptp(E) == 0 or np.ptp(sy) == 0:
        return 0.0
    return float(np.corrcoef(E, sy)[0, 1])
