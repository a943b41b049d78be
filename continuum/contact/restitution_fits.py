"""Published closed forms of the normal restitution of an elastic-perfectly plastic sphere
impact, as pure functions of the impact speed over a yield speed.

They are the references of the restitution validation (docs/impact-model.md, "Restitution
validation"; benchmarks/restitution_validation.py). Two yield speeds appear, and they differ:

- V_Y, the package's (docs/physics.md section 2): the Hertz peak pressure reaches
  C(nu) sigma_Y, C = 1.295 exp(0.736 nu), at V_Y^2 = (pi^5/30) (C sigma_Y)^5 R^3 / (E*^4 m);
- V_y, Thornton's (1997): p0 reaches his limiting pressure p_y, at
  V_y^2 = (pi^5/30) p_y^5 R^3 / (E*^4 m).

For equal m, R and E*, V_y / V_Y = (p_y / (C sigma_Y))^(5/2) (`thornton_yield_ratio`).

Not implemented, because their exact published forms could not be confirmed from the papers
here (no coefficients are guessed): the finite-element fits of Jackson, Green & Marghitu
(2010), Nonlinear Dyn. 60, 217 (elastic-perfectly plastic sphere on a rigid flat), and of Wu,
Li & Thornton (2005), Int. J. Impact Eng. 32, 593.

Speed ratios are dimensionless; all functions broadcast.
"""

from __future__ import annotations

import numpy as np

from filmscale.core.checks import check_positive_array

from .hertz import pressure_factor_unchecked, checked
from .restitution import thornton_restitution

#: e (V/V_y)^(1/4) as V/V_y -> inf in Thornton's closed form:
#: sqrt(6 sqrt(3) / 5) (2 sqrt(6/5))^(-1/4) = 1.18499
THORNTON_HIGH_SPEED_FACTOR = float(np.sqrt(6.0 * np.sqrt(3.0) / 5.0)
                                   * (2.0 * np.sqrt(1.2)) ** -0.25)


def thornton_1997(speed_ratio):
    """Thornton (1997) normal restitution of an elastic-perfectly plastic sphere [C2].

    Parameters
    ----------
    speed_ratio : array_like
        V / V_y, with V_y Thornton's yield speed (p0 = p_y); positive.

    Returns
    -------
    ndarray
        e = sqrt(6 sqrt(3)/5) sqrt(1 - x^2/6) (x / (x + 2 sqrt(6/5 - x^2/5)))^(1/4) with
        x = V_y / V, and e = 1 for V <= V_y (Thornton 1997, J. Appl. Mech. 64, 383;
        docs/physics.md section 4). Analytical (truncated Hertz loading, Hertz unloading
        from the crater), valid for every V / V_y >= 1.
    """
    return thornton_restitution(speed_ratio, 1.0)


def thornton_high_speed(speed_ratio):
    """Leading term of `thornton_1997` for V >> V_y: e = 1.18499 (V_y / V)^(1/4).

    The exponent 1/4 is also Johnson's (1985, section 11.5) for fully plastic loading with an
    elastic rebound. It lies above the closed form, by less than 1 % for V / V_y >= 12.
    ``speed_ratio`` is V / V_y, positive.
    """
    return (THORNTON_HIGH_SPEED_FACTOR
            * check_positive_array("speed_ratio", speed_ratio) ** -0.25)[()]


def thornton_yield_ratio(limiting_pressure_factor, nu):
    """V_y / V_Y = (f / C(nu))^(5/2): Thornton's yield speed, at p0 = p_y = f sigma_Y, over the
    package's V_Y, at p0 = C(nu) sigma_Y (same m, R, E*). f = 2.8 and nu = 0.3 give 3.958;
    f = C(nu) gives 1. Multiply V / V_Y by its inverse to enter `thornton_1997`."""
    f = check_positive_array("limiting_pressure_factor", limiting_pressure_factor)
    (nu,) = checked(nu=nu)
    return ((f / pressure_factor_unchecked(nu)) ** 2.5)[()]
