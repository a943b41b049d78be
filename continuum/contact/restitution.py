"""Elastic unloading after an elastic-plastic loading, residual depth and normal restitution.

Unloading is Hertzian from the state at maximum approach (delta_max, P_max, contact area):
P = (4/3) E* R_new^(1/2) (delta - delta_res)^(3/2), which returns W_unload = (2/5) P_max delta_e
with delta_e = delta_max - delta_res. The restitution coefficient is the energy identity
e_y = sqrt(W_unload / W_load) (exact for a rate-independent law). Models of delta_res
(docs/physics.md section 4):

- ``crater`` [C2]: R_new = 4 E* a_max^3 / (3 P_max), delta_e = a_max^2 / R_new (Johnson 1985
  section 11.5; Thornton 1997).
- ``jackson-chusoipin-green`` [C1]: delta_res = 1.02 delta_max
  (1 - ((delta_max/delta_Y + 5.9)/6.9)^(-0.54)). The fit leaves no elastic recovery beyond
  delta_max/delta_Y of about 1e4 (delta_res >= delta_max); callers must check
  ``elastic_recovery > 0``.
- ``brake`` [C1]: delta_res = delta_max (1 - P_max / P_Hertz(delta_max)) (Brake 2015).

Units: m, N, Pa, J, m/s; all functions broadcast.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from filmscale.core.checks import check_choice

from .hertz import hertz_force_unchecked, checked

UNLOADING_MODELS = ("crater", "jackson-chusoipin-green", "brake")


@dataclass(frozen=True)
class Unloading:
    """Hertzian unloading from maximum approach; SI units."""

    residual_depth: np.ndarray      #: delta_res, m
    elastic_recovery: np.ndarray    #: delta_e = delta_max - delta_res, m
    radius: np.ndarray              #: R_new, radius of the unloading Hertz law, m
    work: np.ndarray                #: W_unload = (2/5) P_max delta_e, J

    def force(self, delta, E_star):
        """Unloading force at approach delta, N (0 once separated)."""
        gap = np.maximum(np.asarray(delta) - self.residual_depth, 0.0)
        return (4.0 / 3.0) * E_star * np.sqrt(self.radius) * gap**1.5


def unload(model: str, *, delta_max, force_max, area_max, E_star, R, yield_approach) -> Unloading:
    """Unloading from (delta_max, P_max, A_max) by the residual-depth ``model``.

    ``yield_approach`` (delta_Y, m) is read by jackson-chusoipin-green only, ``R`` by brake.
    """
    check_choice("unloading", model, UNLOADING_MODELS)
    delta_max = np.asarray(delta_max, dtype=float)
    force_max = np.asarray(force_max, dtype=float)
    if model == "crater":
        a = np.sqrt(np.asarray(area_max) / np.pi)
        radius = 4.0 * E_star * a**3 / (3.0 * force_max)
        recovery = a**2 / radius
    else:
        if model == "jackson-chusoipin-green":
            ratio = np.maximum(delta_max / yield_approach, 1.0)
            residual = 1.02 * delta_max * (1.0 - ((ratio + 5.9) / 6.9) ** -0.54)
        else:
            residual = delta_max * (1.0 - force_max / hertz_force_unchecked(delta_max, R, E_star))
        recovery = delta_max - residual
        with np.errstate(divide="ignore", invalid="ignore"):    # recovery <= 0: caller flags it
            radius = np.square(3.0 * force_max / (4.0 * E_star) / recovery**1.5)
    return Unloading(residual_depth=delta_max - recovery, elastic_recovery=recovery,
                     radius=radius, work=0.4 * force_max * recovery)


def thornton_restitution(V, V_y):
    """Thornton (1997) normal restitution of an elastic-perfectly plastic sphere [C2].

    With x = V_y / V (V > V_y): e = sqrt(6 sqrt(3)/5) sqrt(1 - x^2/6)
    (x / (x + 2 sqrt(6/5 - x^2/5)))^(1/4); e = 1 for V <= V_y. V_y is the velocity at which
    p0 reaches the limiting pressure p_y: V_y^2 = (pi^5/30) p_y^5 R^3 / (E*^4 m).
    """
    V, V_y = checked(V=V, V_y=V_y)
    x = np.minimum(V_y / V, 1.0)
    e = (np.sqrt(6.0 * np.sqrt(3.0) / 5.0) * np.sqrt(1.0 - x**2 / 6.0)
         * (x / (x + 2.0 * np.sqrt(1.2 - x**2 / 5.0))) ** 0.25)
    return np.where(x >= 1.0, 1.0, e)


def johnson_restitution(m, R, V, E_star, dynamic_pressure):
    """Fully plastic loading at constant pressure p_d with Hertz rebound (Johnson 1985
    section 11.5) [D]: (1/2) m V^2 = pi p_d a^4 / (4R), e^2 = (6 pi / 5) p_d R / (E* a).
    Meaningful only for V much larger than 30 V_Y. m in kg, R in m, V in m/s, E* and p_d in
    Pa."""
    m, R, V, E_star, dynamic_pressure = checked(m=m, R=R, V=V, E_star=E_star,
                                                p_d=dynamic_pressure)
    a = np.power(2.0 * m * np.square(V) * R / (np.pi * dynamic_pressure), 0.25)
    return np.sqrt(1.2 * np.pi * dynamic_pressure * R / (E_star * a))
