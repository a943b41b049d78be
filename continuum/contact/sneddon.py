"""The exact frictionless rigid sphere on an elastic half-space (Sneddon 1965), and a contact
law whose elastic branch is it.

Hertz's law replaces the sphere by its paraboloid, which is exact only for a << R. For a rigid
sphere of radius R pressed into a half-space of reduced modulus E*, Sneddon (Int. J. Eng. Sci.
3 (1965) 47, eqs. for the spherical punch) gives, in terms of the contact radius a < R,

    delta = (a/2) ln((R + a)/(R - a)) = R x atanh(x),                        x = a / R,
    P     = (E*/2) [(a^2 + R^2) ln((R + a)/(R - a)) - 2 a R]
          = E* R^2 [(1 + x^2) atanh(x) - x].

Hertz limit (small x; atanh x = x + x^3/3 + x^5/5 + ...): delta = R (x^2 + x^4/3 + ...) ->
a^2 / R, and (1 + x^2) atanh x - x = sum_k>=1 4k/(4k^2 - 1) x^(2k+1) = (4/3) x^3 + (8/15) x^5
+ ..., so P -> 4 E* a^3 / (3R) = (4/3) E* R^(1/2) delta^(3/2). The ratio to Hertz at equal
delta is 1 - delta/(10 R) + O(delta^2): 1.2 % under Hertz at delta/R = 0.12 and 5 % under at
0.5 (the truncated-sphere elastic branch of Komvopoulos-Ye, (4/3) E* delta^1.5
(R - delta/2)^(1/2), is 3 % and 13 % under). a -> R as delta -> infinity, where
P -> E* R (2 delta - R).

The inverse a(delta) is solved for t = atanh(a/R) (t tanh t = delta/R), which has no
singularity as a -> R: a safeguarded, vectorised Newton iteration from x = sqrt(delta/R)
(clipped below 1), kept in the bracket max(d, sqrt d) <= t <= d + sqrt(d) with
d = delta/R (t^2/(1 + t) <= t tanh t <= min(t, t^2)), to machine precision.

`SneddonElastic` wraps any `ContactLaw`: its elastic branch is Sneddon's, its plastic
branches the wrapped law's, scaled so that force and area are continuous at first yield
(docs/physics.md section 3, "The exact elastic sphere"). SI units throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from filmscale.core.errors import InputError

from .hertz import checked
from .laws import ContactLaw

#: below this x = a/R the force uses the power series of (1 + x^2) atanh x - x, whose closed
#: form loses ~log10(1/x^2) digits to cancellation; 30 terms reach 1e-19 relative at x = 0.5
_SERIES_BELOW = 0.5
_SERIES = np.array([4.0 * k / (4.0 * k * k - 1.0) for k in range(30, 0, -1)])  # Horner order
#: the largest float below 1: where a Newton start in x is clipped
_X_MAX = np.nextafter(1.0, 0.0)


def _solve_t(d):
    """t = atanh(a/R) with t tanh t = d (d = delta/R >= 0; NaN for d < 0 or NaN, inf for
    inf), elementwise."""
    d = np.asarray(d, dtype=float)
    t = np.full(d.shape, np.nan)
    t[d == 0.0] = 0.0
    t[d == np.inf] = np.inf
    todo = np.isfinite(d) & (d > 0.0)
    if not np.any(todo):
        return t
    dd = d[todo]
    sqrt_d = np.sqrt(dd)
    lo = np.maximum(sqrt_d, dd)
    hi = dd + sqrt_d
    x = np.arctanh(np.minimum(sqrt_d, _X_MAX))            # start: x = sqrt(d), below 1
    s = np.clip(x, lo, hi)
    idx = np.arange(dd.size)             # the points still iterating
    for _ in range(200):                 # a handful of Newton steps; bisection is the guard
        si, di = s[idx], dd[idx]
        th = np.tanh(si)
        g = si * th - di
        lo[idx] = np.where(g < 0.0, si, lo[idx])
        hi[idx] = np.where(g > 0.0, si, hi[idx])
        new = si - g / (th + si * (1.0 - th * th))
        inside = (new >= lo[idx]) & (new <= hi[idx])
        new = np.where(inside, new, 0.5 * (lo[idx] + hi[idx]))
        tol = 4.0 * np.finfo(float).eps * new
        done = (g == 0.0) | (np.abs(new - si) <= tol) | (hi[idx] - lo[idx] <= tol)
        s[idx] = np.where(g == 0.0, si, new)
        idx = idx[~done]
        if not idx.size:
            break
    t[todo] = s
    return t


def _reduced_force(x, t):
    """(1 + x^2) t - x with x = tanh t: P / (E* R^2)."""
    with np.errstate(invalid="ignore"):
        closed = (1.0 + x * x) * t - x
    small = np.abs(x) < _SERIES_BELOW
    if not np.any(small):
        return closed
    x2 = x * x
    series = np.zeros(np.shape(x))
    for c in _SERIES:
        series = series * x2 + c
    return np.where(small, series * x2 * x, closed)


def _sneddon(delta, R, E_star):
    """(P, A) of the exact rigid sphere, unchecked and broadcast: P in N, A = pi a^2 in m^2."""
    delta, R, E_star = np.broadcast_arrays(np.asarray(delta, dtype=float),
                                           np.asarray(R, dtype=float),
                                           np.asarray(E_star, dtype=float))
    with np.errstate(invalid="ignore", divide="ignore"):
        t = _solve_t(delta / R)
    x = np.tanh(t)
    return E_star * R * R * _reduced_force(x, t), np.pi * np.square(R * x)


def _radius(delta, R):
    delta, R = np.broadcast_arrays(np.asarray(delta, dtype=float), np.asarray(R, dtype=float))
    with np.errstate(invalid="ignore", divide="ignore"):
        return R * np.tanh(_solve_t(delta / R))


def sneddon_contact_radius(delta, R):
    """Contact radius a (m) of a rigid sphere of radius R (m) at approach delta (m): the
    inverse of delta = (a/2) ln((R + a)/(R - a)); a < R for every finite delta, a -> R as
    delta -> infinity, a -> sqrt(R delta) (Hertz) as delta/R -> 0."""
    return _radius(*checked(delta=delta, R=R))


def sneddon_force(delta, R, E_star):
    """Force P (N) of a rigid sphere of radius R (m) at approach delta (m) on a half-space of
    reduced modulus E* (Pa): P = (E*/2) [(a^2 + R^2) ln((R + a)/(R - a)) - 2 a R] with a from
    `sneddon_contact_radius`; P -> (4/3) E* R^(1/2) delta^(3/2) (Hertz) as delta/R -> 0."""
    return _sneddon(*checked(delta=delta, R=R, E_star=E_star))[0]


def sneddon_area(delta, R):
    """Contact area pi a^2 (m^2) of a rigid sphere at approach delta (m); R in m."""
    return np.pi * np.square(sneddon_contact_radius(delta, R))


def _from_base(name: str) -> property:
    """A read-only property that is ``self.base``'s attribute ``name``."""
    return property(lambda self: getattr(self.base, name), doc=f"``base.{name}``")


@dataclass(frozen=True)
class SneddonElastic(ContactLaw):
    """``base`` with Sneddon's exact rigid sphere as its elastic branch.

    The branches below ``base.reversible_branches`` (branch 0; every branch of `Hertz`) use
    Sneddon's force and area. The plastic branches are the base law's, their force multiplied
    by P_Sneddon / P_base,elastic and their area by A_Sneddon / A_base,elastic, both ratios
    taken at the first-yield approach delta_Y = base.approach_at_severity(base.thresholds[0],
    ...) with the properties of each point (arrays, as in a layered target): force and area
    are continuous at the first threshold wherever the base law is, and the base law's own
    jumps (literal Komvopoulos-Ye, Kogut-Etsion, Jackson-Green at w* = 1.9) keep their
    relative size. Severity, thresholds, regimes, hardness factor and unloading are the base
    law's; the name is ``base.name + "+sneddon"``.
    """

    base: ContactLaw

    def __post_init__(self):
        if isinstance(self.base, SneddonElastic):           # wrapping twice changes nothing
            object.__setattr__(self, "base", self.base.base)
        if not isinstance(self.base, ContactLaw):
            raise InputError(f"SneddonElastic wraps a ContactLaw, got {self.base!r}")

    @property
    def name(self) -> str:
        return self.base.name + "+sneddon"

    # severity, thresholds, regimes, hardness factor and unloading are the base law's
    thresholds = _from_base("thresholds")
    regime_names = _from_base("regime_names")
    continuous = _from_base("continuous")
    hardness_factor = _from_base("hardness_factor")
    default_unloading = _from_base("default_unloading")
    reversible_branches = _from_base("reversible_branches")

    def critical_approach(self, R, E_star, sigma_y, nu):
        return self.base.critical_approach(R, E_star, sigma_y, nu)

    def severity(self, delta, R, E_star, sigma_y, nu):
        return self.base.severity(delta, R, E_star, sigma_y, nu)

    def approach_at_severity(self, value, R, E_star, sigma_y, nu):
        return self.base.approach_at_severity(value, R, E_star, sigma_y, nu)

    def branch_of(self, severity):
        return self.base.branch_of(severity)

    def joins(self, R, E_star, sigma_y, nu):
        """(P_Sneddon / P_base, A_Sneddon / A_base) on the elastic branch at the first-yield
        approach: the factors of the base law's plastic force and area."""
        base = self.base
        d_y = base.approach_at_severity(base.thresholds[0], R, E_star, sigma_y, nu)
        force, area = _sneddon(d_y, R, E_star)
        base_force, base_area = base.force_area(d_y, R, E_star, sigma_y, nu, 0)
        return force / base_force, area / base_area

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        delta = np.asarray(delta, dtype=float)
        elastic_below = self.base.reversible_branches
        if np.ndim(branch) == 0 and branch < elastic_below:
            return _sneddon(delta, R, E_star)

        def plastic():
            force, area = self.base.force_area(delta, R, E_star, sigma_y, nu, branch)
            f_ratio, a_ratio = self.joins(R, E_star, sigma_y, nu)
            return force * f_ratio, area * a_ratio

        if np.ndim(branch) == 0:
            return plastic()
        elastic = np.asarray(branch) < elastic_below
        f_e, a_e = _sneddon(delta, R, E_star)
        if np.all(elastic):                 # a fit's elastic stage: no plastic formula
            return f_e, a_e
        with np.errstate(all="ignore"):     # the plastic formula also runs on elastic points
            f_p, a_p = plastic()
        return np.where(elastic, f_e, f_p), np.where(elastic, a_e, a_p)

    def describe(self) -> dict:
        d = self.base.describe()
        d["contact_law"] = self.name
        d["base_law"] = self.base.name
        d["elastic_branch"] = ("Sneddon (1965) exact rigid sphere; plastic branches scaled "
                               "to join it at first yield")
        return d
