"""Closed-form Hertz contact, elastic impact and first yield of a sphere on a flat.

These are reference solutions: the impact solvers are tested against them. All functions take
SI values (m, N, Pa, kg, m/s) and broadcast over numpy arrays; each checks its inputs (range,
shapes) and raises InputError naming the parameter. The underscored kernels skip the checks:
the solvers call them in inner loops with values checked once at their own entry.

Sources: Johnson, Contact Mechanics (1985), sections 4.2 and 11.4; docs/physics.md sections 1-2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.core.checks import check_broadcast, check_real_array
from filmscale.core.errors import InputError

#: t_c V / delta_max for an elastic Hertz impact: (4/5) B(2/5, 1/2) = 2.943275...
#: (math.gamma rather than scipy.special.beta keeps scipy out of the command line's start-up)
HERTZ_DURATION_FACTOR = 0.8 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)

#: the valid range of each input: (low, high, low_open, high_open, unit)
_RANGES = {
    "delta": (0.0, math.inf, False, True, "m"),
    "delta_max": (0.0, math.inf, True, True, "m"),
    "R": (0.0, math.inf, True, True, "m"),
    "E_star": (0.0, math.inf, True, True, "Pa"),
    "sigma_y": (0.0, math.inf, True, False, "Pa"),     # inf: never yields
    "nu": (-1.0, 0.5, True, False, ""),
    "m": (0.0, math.inf, True, True, "kg"),
    "V": (0.0, math.inf, True, True, "m/s"),
    "V_y": (0.0, math.inf, False, False, "m/s"),      # inf: never yields
    "p_d": (0.0, math.inf, True, True, "Pa"),
    "p0": (0.0, math.inf, True, True, "Pa"),
}


def checked(**inputs) -> list[np.ndarray]:
    """Inputs named as in `_RANGES`, each checked against its range and broadcast together;
    InputError names the parameter or the shapes."""
    arrays = {}
    for name, value in inputs.items():
        low, high, low_open, high_open, unit = _RANGES[name]
        arrays[name] = check_real_array(name, value, low=low, high=high, low_open=low_open,
                                        high_open=high_open, unit=unit)
    return [a[()] for a in check_broadcast(**arrays)]    # a[()]: 0-d arrays as scalars


def hertz_force_unchecked(delta, R, E_star):
    """`hertz_force` without its input checks, for callers that checked them (laws, fits)."""
    return (4.0 / 3.0) * E_star * np.sqrt(R) * np.power(delta, 1.5)


def hertz_force(delta, R, E_star):
    """P = (4/3) E* R^(1/2) delta^(3/2), N (delta, R in m; E* in Pa)."""
    return hertz_force_unchecked(*checked(delta=delta, R=R, E_star=E_star))


def hertz_contact_radius(delta, R):
    """a = sqrt(R delta), m."""
    delta, R = checked(delta=delta, R=R)
    return np.sqrt(R * delta)


def hertz_mean_pressure(delta, R, E_star):
    """p_m = P / (pi a^2) = (4 E* / (3 pi)) sqrt(delta / R), Pa."""
    delta, R, E_star = checked(delta=delta, R=R, E_star=E_star)
    return (4.0 / (3.0 * np.pi)) * E_star * np.sqrt(delta / R)


@dataclass(frozen=True)
class ElasticImpact:
    """Maxima of an elastic (Hertz) impact of a sphere of mass m at speed V; SI units."""

    delta_max: np.ndarray       #: maximum approach, m
    force_max: np.ndarray       #: maximum force, N
    contact_radius_max: np.ndarray  #: m
    mean_pressure_max: np.ndarray   #: Pa
    contact_time: np.ndarray    #: s


def elastic_impact(m, R, V, E_star) -> ElasticImpact:
    """Hertz impact maxima (Johnson 1985 eq. 11.24-11.26).

    delta_max = (15 m V^2 / (16 E* R^(1/2)))^(2/5); t_c = 2.943275 delta_max / V.
    """
    m, R, V, E_star = checked(m=m, R=R, V=V, E_star=E_star)
    delta_max = np.power(15.0 * m * np.square(V) / (16.0 * E_star * np.sqrt(R)), 0.4)
    return ElasticImpact(
        delta_max=delta_max,
        force_max=hertz_force_unchecked(delta_max, R, E_star),
        contact_radius_max=np.sqrt(R * delta_max),
        mean_pressure_max=(4.0 / (3.0 * np.pi)) * E_star * np.sqrt(delta_max / R),
        contact_time=HERTZ_DURATION_FACTOR * delta_max / V,
    )


def elastic_impact_time(delta, delta_max, V):
    """Time to reach approach `delta` on the loading half of a Hertz impact, s.

    t(delta) = (delta / V) 2F1(1/2, 2/5; 7/5; (delta/delta_max)^(5/2)), from integrating
    dt = d(delta) / sqrt(V^2 (1 - (delta/delta_max)^(5/2))). Unloading mirrors it.
    """
    delta, delta_max, V = checked(delta=delta, delta_max=delta_max, V=V)
    beyond = np.asarray(delta > delta_max)
    if np.any(beyond):
        raise InputError(f"delta = {np.asarray(delta)[beyond].flat[0]:.6g} m is beyond "
                         f"delta_max = {np.asarray(delta_max)[beyond].flat[0]:.6g} m, where "
                         "the loading half ends")
    from scipy.special import hyp2f1
    x = np.power(delta / delta_max, 2.5)
    return (delta / V) * hyp2f1(0.5, 0.4, 1.4, x)


# --- first yield (docs/physics.md section 2) ------------------------------------------------------

def pressure_factor_unchecked(nu):
    """`yield_pressure_factor` without its input checks."""
    return 1.295 * np.exp(0.736 * np.asarray(nu, dtype=float))


def yield_pressure_factor(nu):
    """C(nu) = p0 / sigma_Y at first yield under a sphere: 1.295 exp(0.736 nu).

    Fit of the exact on-axis von Mises result (1.613 at nu = 0.3; within 0.35 % for nu in
    [0, 0.5]); Green (2005), Jackson & Green (2005).
    """
    return pressure_factor_unchecked(*checked(nu=nu))


@dataclass(frozen=True)
class FirstYield:
    """Onset of yield under an elastic sphere; SI units."""

    approach: np.ndarray        #: delta_Y, m
    contact_radius: np.ndarray  #: a_Y, m
    force: np.ndarray           #: P_Y, N
    max_pressure: np.ndarray    #: p0 at yield = C(nu) sigma_Y, Pa


def load_at_peak_pressure_unchecked(p0, R, E_star):
    """`load_at_peak_pressure` without its input checks."""
    return (np.pi**3 / 6.0) * p0**3 * np.square(R) / np.square(E_star)


def load_at_peak_pressure(p0, R, E_star):
    """P = (pi^3/6) p0^3 R^2 / E*^2 (N): the Hertz load under a sphere of radius R (m) on a
    reduced modulus E* (Pa) at which the peak pressure is p0 (Pa); the contact radius there
    is a = pi p0 R / (2 E*) (Johnson 1985, ch. 4; docs/physics.md section 2)."""
    return load_at_peak_pressure_unchecked(*checked(p0=p0, R=R, E_star=E_star))


def first_yield_unchecked(R, E_star, sigma_y, nu) -> FirstYield:
    """`first_yield` without its input checks."""
    p0 = pressure_factor_unchecked(nu) * sigma_y
    a_y = np.pi * p0 * R / (2.0 * E_star)
    return FirstYield(approach=a_y**2 / R, contact_radius=a_y,
                      force=load_at_peak_pressure_unchecked(p0, R, E_star), max_pressure=p0)


def first_yield(R, E_star, sigma_y, nu) -> FirstYield:
    """delta_Y = (pi C sigma_Y / (2E*))^2 R, a_Y = pi C sigma_Y R / (2E*),
    P_Y = (pi^3/6) (C sigma_Y)^3 R^2 / E*^2 (docs/physics.md section 2)."""
    return first_yield_unchecked(*checked(R=R, E_star=E_star, sigma_y=sigma_y, nu=nu))


def yield_velocity(m, R, E_star, sigma_y, nu):
    """Impact velocity at which first yield is just reached, m/s.

    V_Y^2 = (pi^5 / 30) (C sigma_Y)^5 R^3 / (E*^4 m): the kinetic energy equals the Hertz
    work (2/5) P_Y delta_Y.
    """
    m, R, E_star, sigma_y, nu = checked(m=m, R=R, E_star=E_star, sigma_y=sigma_y, nu=nu)
    p0 = pressure_factor_unchecked(nu) * sigma_y
    return np.sqrt((np.pi**5 / 30.0) * p0**5 * np.power(R, 3) / (np.power(E_star, 4) * m))
