"""An ensemble of MD indentations: one protocol run with several seeds.

A single MD trajectory carries thermal noise and one draw of the pop-in load, and its scatter
is not in a single fit's standard deviations. Each member is calibrated on its own (with its
own pop-in, E from Hertz before it and sigma_y after it), and the layer gets the members'
mean E and sigma_y with the seed-to-seed standard error of that mean. The ensemble's mean
curve is not fitted: where the members' pop-ins fall at different depths it has no pop-in of
its own, only a gradual bend, and the law, which has no pop-in, then trades E against the
averaged overshoot (113 GPa from 70 GPa members in the test). The seed-to-seed scatter of the
load (members of one protocol are sampled alike, so point by point) is the curves' noise
model, from which the cross-scale check takes its tolerance; the pop-in load, depth and shear
stress (0.31 p0, Johnson 1985) are given as mean and scatter over the members.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.materials import reduced_modulus
from filmscale.core.errors import InputError

from .pop_in import pop_in_statistics
from .result import Calibration, Parameter
from .route import calibrate, tip_counterpart
from .target import SphereTarget


def ensemble_mean(curves) -> tuple[LoadDisplacementCurve, np.ndarray]:
    """The point-by-point mean curve of members sampled alike (one protocol: the same number
    of points and the same segments) and the seed-to-seed standard deviation of the load (N)
    at each point."""
    curves = list(curves)
    if len(curves) < 2:
        raise InputError(f"an ensemble needs at least 2 curves, got {len(curves)}")
    first = curves[0]
    if any(c.h.size != first.h.size or not np.array_equal(c.segment, first.segment)
           for c in curves):
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
    """A layer from an ensemble of curves of one protocol (`calibrate`'s options): each
    member calibrated alone, the mean E and sigma_y with the seed-to-seed standard error of
    the mean, the seed-to-seed load scatter as the curves' noise, the pop-in statistics.
    The fitted curves are the members', each with its own parameters."""
    curves = list(curves)
    mean, P_std = ensemble_mean(curves)
    members = [calibrate(c, nu=nu, tip_material=tip_material, thickness=thickness,
                         substrate=substrate, **options) for c in curves]
    n = len(members)

    def averaged(name: str) -> Parameter:
        values = np.array([getattr(m, name).value for m in members])
        first = getattr(members[0], name)
        return replace(first, value=float(values.mean()),
                       std=float(values.std(ddof=1)) / math.sqrt(n),
                       identified=all(getattr(m, name).identified for m in members))

    load = mean.segment == 0
    noise = float(np.sqrt(np.mean((P_std[load] / np.max(mean.P[load]))**2)))
    E, sigma_y = averaged("E"), averaged("sigma_y")
    indenter = tip_counterpart(tip_material)[0]
    E_star = reduced_modulus(E.value / (1.0 - nu**2), indenter)
    stats = pop_in_statistics(curves, E_star, SphereTarget(nu, indenter, thickness,
                                                           substrate))
    spread = ", ".join(f"{m.E.value:.4g}" for m in members)
    return replace(
        members[0], E=E, sigma_y=sigma_y,
        uncertainty=f"mean of {n} members, each calibrated alone; standard error of the mean "
                    f"over the seeds (members' E: {spread} Pa)",
        rms=float(np.sqrt(np.mean([m.rms**2 for m in members]))),
        points=sum(m.points for m in members),
        sources=tuple(str(c.meta.get("source", f"seed {i}")) for i, c in enumerate(curves)),
        warnings=tuple(dict.fromkeys(w for m in members for w in m.warnings)),
        fitted_curves=tuple(f for m in members for f in m.fitted_curves),
        fit_roles=tuple(r for m in members for r in m.fit_roles)
        if all(m.fit_roles for m in members) else (),
        curve_noise=noise, pop_in=None if stats is None else stats.to_dict(),
        contact_zero=float(np.mean([m.contact_zero for m in members])),
        correlation=_member_correlation(members))


def _member_correlation(members) -> float:
    """The correlation of the members' E and sigma_y (the seed-to-seed scatter of both), 0
    with fewer than three members or a constant one."""
    E = np.array([m.E.value for m in members])
    sy = np.array([m.sigma_y.value for m in members])
    if E.size < 3 or np.ptp(E) == 0 or np.ptp(sy) == 0:
        return 0.0
    return float(np.corrcoef(E, sy)[0, 1])
