"""The pop-in of a defect-free crystal as a calibrated parameter (issue 30).

A spherical tip on a pristine crystal (MD) loads elastically far beyond the continuum's first
yield, until dislocations nucleate: the pop-in, a load drop under displacement control and a
displacement burst under load control. No continuum contact law has one, so the sphere
calibration of such curves is a pop-in law: Hertz (the exact rigid sphere of Sneddon on deep
curves) up to the pop-in load P_pop, the burst, then the elastic-plastic law's flow branch
with the calibrated E* and sigma_y. P_pop and the largest shear stress under the tip at the
pop-in, tau_max = 0.31 p_0 (Johnson 1985, nu = 0.3; p_0 = (6 P E*^2 / (pi^3 R^2))^(1/3)),
are the law's third parameter, given as mean and standard deviation over the curves (one
curve: its own value, no scatter). The cross-scale check judges the whole curve except the
burst (`Calibration.cross_check(exclude="burst")`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from filmscale.continuum.indentation.spherical import elastic_limit, pop_in_shear_stress
from filmscale.continuum.indentation.tips import Sphere

from .target import SphereTarget


@dataclass(frozen=True)
class PopInStatistics:
    """Mean and curve-to-curve standard deviation (NaN for one curve) of the first pop-in."""

    members: int              #: curves with a pop-in
    load: float               #: N
    load_std: float
    depth: float              #: m
    depth_std: float
    shear_stress: float       #: Pa, 0.31 p0 of Hertz with the E* felt at the pop-in
    shear_stress_std: float

    def to_dict(self) -> dict:
        return asdict(self)


def pop_in_statistics(curves, E_star: float, target: SphereTarget) -> PopInStatistics | None:
    """The first pop-in of each spherical curve (`elastic_limit`) with the reduced modulus
    ``E_star`` of the layer felt there through ``target``; None when no curve has one."""
    rows = []
    for c in curves:
        peak = elastic_limit(c)
        if peak is None or not isinstance(c.indenter, Sphere):
            continue
        R, P, h = c.indenter.R, float(c.P[peak]), float(c.h[peak])
        felt = target.properties(h, R, E_star, 1.0)[0]
        rows.append((P, h, pop_in_shear_stress(P, float(felt), R)))
    if not rows:
        return None
    a = np.array(rows)
    std = a.std(axis=0, ddof=1) if len(rows) > 1 else np.full(3, math.nan)
    return PopInStatistics(len(rows), *(float(v) for pair in zip(a.mean(axis=0), std)
                                        for v in pair))
