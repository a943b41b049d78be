"""Elastic frictionless contact of a rigid sphere on a film bonded to a half-space: the
layered-elasticity solution that the Gao weighting (`profiles.StackProfile`) approximates.

The surface of a coated half-space answers an axisymmetric pressure with the displacement
(Hankel transforms, Perriot & Barthel 2004)

    u(r) = (2 / E'_f) int_0^inf p^(k) C(k t) J0(k r) dk,

E'_f = E_f / (1 - nu_f^2) the film's plane-strain modulus and C the compliance kernel of a
perfectly bonded layer, C(0) = mu_f/mu_s for equal Poisson ratios and C(inf) = 1. The pressure
is a sum of (1 - r^2/a^2)^(1/2) and (1 - r^2/a^2)^(3/2), which vanish at the contact edge;
their coefficients and the approach delta make u(r) = delta - r^2/(2R) inside the contact, in
the least-squares sense. The homogeneous part of u is closed form (Johnson 1985, section 3.3),
the kernel's correction C - 1 decays as exp(-2 k t) and is integrated numerically.

Checked: with film = substrate the load is Hertz's to 1e-6; a vanishing film gives the
substrate's Hertz load and a thick film the film's (tests/continuum).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import gamma, j0, jv

from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.checks import check_positive

#: Exponents of the pressure terms (1 - r^2/a^2)^nu.
_NUS = (0.5, 1.5)
#: Collocation points over the contact radius and the wavenumber cut-off k t of C - 1,
#: where (C - 1) ~ (k t)^2 exp(-2 k t) is below 1e-40.
_N_R, _KT_MAX = 24, 60.0


def _kernel(x, film: ElasticPlastic, substrate: ElasticPlastic):
    """C(k t) of a bonded layer (Perriot & Barthel 2004), with its Dundurs-type a and b."""
    ratio = (film.E / (1 + film.nu)) / (substrate.E / (1 + substrate.nu))
    kf, ks = 3 - 4 * film.nu, 3 - 4 * substrate.nu
    a = (ratio * ks - kf) / (ratio * ks + 1)
    b = (ratio - 1) / (ratio + kf)
    e2 = np.exp(-2 * x)
    return (1 + 4 * b * x * e2 - a * b * e2**2) / \
        (1 - (a + b + 4 * b * x**2) * e2 + a * b * e2**2)


def _transform(k, a, nu):
    """Zeroth-order Hankel transform of (1 - r^2/a^2)^nu on r < a."""
    return a * a * 2**nu * gamma(nu + 1) * jv(nu + 1, k * a) / (k * a)**(nu + 1)


def _homogeneous(r, a, nu, E_p):
    """Surface displacement of a homogeneous half-space under (1 - r^2/a^2)^nu, r <= a."""
    if nu == 0.5:
        return math.pi * (2 * a * a - r * r) / (4 * a * E_p)
    return 3 * math.pi * (8 * a**4 - 8 * a * a * r * r + 3 * r**4) / (64 * a**3 * E_p)


def coated_contact(a: float, R: float, thickness: float, film: ElasticPlastic,
                   substrate: ElasticPlastic) -> tuple[float, float]:
    """Approach delta (m) and load P (N) of a rigid sphere of radius R (m) at contact
    radius ``a`` (m) on a film of ``thickness`` (m) bonded to ``substrate``."""
    for name, value in (("a", a), ("R", R), ("thickness", thickness)):
        check_positive(name, value)
    E_p = film.plane_strain_modulus
    r = np.linspace(0.0, a, _N_R)
    # C - 1 vanishes beyond k t = _KT_MAX; steps resolve both the kernel (scale 1/t) and
    # the pressure's transform and J0 (scale 1/a)
    dk = 0.05 / max(a, thickness)
    k = np.arange(0.5 * dk, _KT_MAX / thickness, dk)
    correction = _kernel(k * thickness, film, substrate) - 1.0
    bessel = j0(np.outer(r, k))
    cols = [_homogeneous(r, a, nu, E_p)
            + (2 / E_p) * np.trapezoid(bessel * (_transform(k, a, nu) * correction), k, axis=1)
            for nu in _NUS]
    # dimensionless unknowns: the coefficients over E'_f, the approach over a
    A = np.column_stack([c * (E_p / a) for c in cols] + [-np.ones_like(r)])
    x, *_ = np.linalg.lstsq(A, -r * r / (2 * R * a), rcond=None)
    load = math.pi * a * a * E_p * sum(c / (nu + 1) for c, nu in zip(x[:-1], _NUS))
    return float(x[-1] * a), float(load)


def coated_sphere_load(delta, R: float, thickness: float, film: ElasticPlastic,
                       substrate: ElasticPlastic) -> np.ndarray:
    """Elastic load (N) of a rigid sphere pressed to approach ``delta`` (m) into the coated
    half-space, interpolated (log-log) over 40 contact radii spanning sqrt(R delta)/3 to
    1.5 sqrt(R delta)."""
    delta = np.atleast_1d(np.asarray(delta, dtype=float))
    check_positive("delta", float(delta.min()))
    lo, hi = math.sqrt(R * delta.min()) / 3, math.sqrt(R * delta.max()) * 1.5
    radii = np.geomspace(lo, hi, 40)
    d, P = np.array([coated_contact(a, R, thickness, film, substrate) for a in radii]).T
    return np.exp(np.interp(np.log(delta), np.log(d), np.log(P)))
