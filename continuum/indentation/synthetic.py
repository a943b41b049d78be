"""Synthetic load-displacement curves whose Oliver-Pharr answer is known exactly: the
oracles of tests, demos and benchmarks."""

from __future__ import annotations

import math

import numpy as np

from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError

from .curves import HOLD, LOAD, UNLOAD, LoadDisplacementCurve


def synthetic_curve(E_r, H, tip, *, h_c, m=1.5, epsilon=None, beta=None, n_load=200,
                    n_hold=50, n_unload=200, loading_time=10.0, hold_time=5.0,
                    unloading_time=10.0, noise=0.0, seed=None) -> LoadDisplacementCurve:
    """A curve whose Oliver-Pharr answer is known exactly.

    Loading P = P_max (h / h_max)^2 (Kick's law), a hold at P_max, unloading
    P = B (h - h_f)^m with B and h_f set so that H = P_max / A(h_c) and
    E_r = sqrt(pi) S / (2 beta sqrt(A(h_c))) with S = m P_max / (h_max - h_f),
    h_max = h_c + eps P_max / S: the relations of Oliver & Pharr, J. Mater. Res. 7 (1992)
    1564, inverted. Depths in m, loads in N, stiffness in N/m, time in s.

    Parameters
    ----------
    E_r, H : float
        Reduced modulus and hardness, Pa.
    tip : Tip
        Area function (and default eps, beta).
    h_c : float
        Contact depth, m.
    m : float
        Unloading exponent, > 1.
    noise : float
        Standard deviation of Gaussian load noise as a fraction of P_max (needs ``seed``).
    """
    E_r, H = check_positive("E_r", E_r, "Pa"), check_positive("H", H, "Pa")
    h_c = check_positive("h_c", h_c, "m")
    m = check_real("m", m, low=1.0, high=10.0, low_open=True)
    eps = tip.epsilon if epsilon is None else epsilon
    beta = tip.beta if beta is None else beta
    A = float(tip.area(h_c))
    P_max = H * A
    S = 2.0 * beta * E_r * math.sqrt(A) / math.sqrt(math.pi)
    h_max = h_c + eps * P_max / S
    h_f = h_max - m * P_max / S
    if h_f < 0:
        raise InputError(f"E_r = {E_r:.4g} Pa and H = {H:.4g} Pa give a negative final depth "
                         f"with m = {m}: not a possible elastic-plastic curve")
    B = P_max / (h_max - h_f)**m
    h_load = np.linspace(0.0, h_max, n_load)
    P_load = P_max * (h_load / h_max)**2
    h_hold = np.full(n_hold, h_max)
    P_hold = np.full(n_hold, P_max)
    P_unl = np.linspace(P_max, 0.0, n_unload + 1)[1:]
    h_unl = h_f + (P_unl / B)**(1.0 / m)
    t = np.concatenate([np.linspace(0.0, loading_time, n_load),
                        loading_time + np.linspace(0.0, hold_time, n_hold + 1)[1:],
                        loading_time + hold_time
                        + np.linspace(0.0, unloading_time, n_unload + 1)[1:]])
    P = np.concatenate([P_load, P_hold, P_unl])
    if noise:
        if seed is None:
            raise InputError("synthetic noise needs an explicit seed")
        P = P + np.random.default_rng(seed).normal(0.0, noise * P_max, P.size)
    seg = np.concatenate([np.full(n_load, LOAD), np.full(n_hold, HOLD),
                          np.full(n_unload, UNLOAD)])
    return LoadDisplacementCurve(np.concatenate([h_load, h_hold, h_unl]), P, t, seg,
                                 indenter=tip,
                                 meta={"synthetic": True, "E_r": E_r, "H": H, "h_c": h_c,
                                       "m": m, "seed": seed})
