"""Multi-cycle indents (load, partial unload, reload, ...): every unloading analysed.

A multi-cycle test gives a depth profile from one indent: each partial unloading is fitted by
Oliver-Pharr as if it ended its own test (Oliver & Pharr, J. Mater. Res. 19 (2004) 3, on
multi-cycle loading; docs/indentation.md, "Multi-cycle tests"). The unloading of cycle k
starts at the largest load reached before it; the loading that precedes it is everything
from the start of the test, or from the end of the previous unloading when an earlier cycle
went deeper (decreasing-load cycles).
"""

from __future__ import annotations

import math

import numpy as np

from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.core.noise import noise_sigma

from .curves import (HOLD, LOAD, SEGMENTS_FROM_CYCLE, UNLOAD, UNLOADING_MIN_DROP,
                     LoadDisplacementCurve)
from .oliver_pharr import OliverPharrResult, oliver_pharr
from .tips import Tip, parse_tip

NOISE_DROPS = 10.0      #: an unloading sheds at least this many standard deviations of noise


def unloading_ranges(P, drop: float = UNLOADING_MIN_DROP) -> list[tuple[int, int]]:
    """(peak, end) index pairs, end exclusive, of every unloading in a load record.

    An unloading starts at the largest load since the previous one ended and counts once the
    load falls below (1 - drop) of it; it ends at the lowest load before the load rises
    again by ``drop`` of the peak. Both changes must also exceed ten times the load noise
    (`core.noise.noise_sigma`), so noise at first contact makes no cycles. The hysteresis
    makes this independent of the load rate (early cycles at 1 % of the final load unload
    slowly, which the rate-based labels of `curves.detect_segments` read as holds).
    """
    P = np.asarray(P, dtype=float)
    floor = NOISE_DROPS * noise_sigma(P)
    out, top, k, n = [], 0, 0, P.size
    while k < n:
        if P[k] > P[top]:
            top = k
        elif P[top] - P[k] >= max(drop * P[top], floor) and P[top] > 0:
            low = j = k
            while j < n and P[j] <= P[low] + max(drop * P[top], floor):
                low = j if P[j] < P[low] else low
                j += 1
            out.append((top, low + 1))
            top = k = low + 1
            continue
        k += 1
    return out


def cycle_curves(curve: LoadDisplacementCurve) -> list[LoadDisplacementCurve]:
    """One curve per unloading cycle: the loading envelope up to the cycle's peak (labelled
    load and hold) and the cycle's unloading (labelled unload); one curve for a
    single-cycle test. Unloadings are found from the loads alone (`unloading_ranges`); a
    hold at the peak stays before the unloading, however its load sags
    (`LoadDisplacementCurve.unloading_begin`)."""
    c = curve.finite()
    out, begin = [], 0
    for top, stop in unloading_ranges(c.P):
        top = c.unloading_begin(top, stop)
        # from the start when this cycle goes highest so far, else from its own reloading;
        # the loading keeps its envelope (points at the deepest depth so far), so earlier
        # unload-reload loops are not read as a loading that falls back
        first = 0 if c.P[top] >= np.max(c.P[:stop]) else begin
        h_load = c.h[first:top + 1]
        keep = np.concatenate([np.flatnonzero(h_load >= np.maximum.accumulate(h_load)) + first,
                               np.arange(top + 1, stop)])
        seg = np.where(c.segment[keep] == HOLD, HOLD, LOAD).astype(np.int8)
        seg[keep > top] = UNLOAD
        meta = {**c.meta, "cycle": len(out) + 1, "segment_source": SEGMENTS_FROM_CYCLE}
        out.append(LoadDisplacementCurve(
            c.h[keep], c.P[keep], None if c.t is None else c.t[keep], seg,
            indenter=c.indenter, meta=meta,
            channels={k: v[keep] for k, v in c.channels.items()}))
        begin = stop
    return out


def analyse_cycles(curve: LoadDisplacementCurve, tip: Tip | str,
                   **kwargs) -> list[OliverPharrResult]:
    """Oliver-Pharr result of every unloading cycle of ``curve``, in test order; ``kwargs``
    go to `oliver_pharr` (window, epsilon, beta, nu, ...). InputError when there is no
    unloading."""
    parts = cycle_curves(curve)
    if not parts:
        raise InputError("the curve has no unloading that sheds 10 % of its load")
    return [oliver_pharr(part, tip, **kwargs) for part in parts]


def synthetic_multicycle(E_r, H, tip, *, h_c, m=1.5, unload_to=0.3, frame_compliance=0.0,
                         n_load=80, n_unload=60, dt=0.05, noise=0.0,
                         seed=None) -> LoadDisplacementCurve:
    """A load - partial unload - reload curve whose every cycle has a known Oliver-Pharr
    answer.

    Cycle k peaks at P_k = H A(h_c,k) and unloads along P = B_k (h - h_f,k)^m (as
    `synthetic.synthetic_curve`) down to ``unload_to`` P_k (the last cycle to zero); reloading
    retraces that elastic unloading to P_k, then loads on to the next peak with sqrt(P)
    linear in h (Kick's law between peaks). ``frame_compliance`` (m/N) adds C_f P to every
    depth, as an instrument frame does.

    Parameters
    ----------
    E_r, H : float
        Reduced modulus and hardness, Pa.
    tip : Tip or str
        Area function (and eps, beta).
    h_c : sequence of float
        Contact depth of each cycle, m, increasing.
    m : float
        Unloading exponent, > 1.
    unload_to : float
        Fraction of each cycle's peak load the partial unloadings go down to, in [0, 0.9).
    noise : float
        Gaussian load noise as a fraction of the largest load (needs ``seed``).
    """
    tip = parse_tip(tip)
    E_r, H = check_positive("E_r", E_r, "Pa"), check_positive("H", H, "Pa")
    m = check_real("m", m, low=1.0, high=10.0, low_open=True)
    unload_to = check_real("unload_to", unload_to, low=0.0, high=0.9, high_open=True)
    C_f = check_real("frame_compliance", frame_compliance, low=0.0, high=1.0, unit="m/N")
    h_c = np.asarray(h_c, dtype=float)
    if h_c.ndim != 1 or h_c.size < 1 or np.any(h_c <= 0) or np.any(np.diff(h_c) <= 0):
        raise InputError(f"h_c = {h_c!r} must be increasing positive contact depths, m")
    A = np.asarray(tip.area(h_c), dtype=float)
    P_max = H * A
    S = 2.0 * tip.beta * E_r * np.sqrt(A) / math.sqrt(math.pi)
    h_max = h_c + tip.epsilon * P_max / S
    h_f = h_max - m * P_max / S
    if np.any(h_f < 0):
        raise InputError(f"E_r = {E_r:.4g} Pa and H = {H:.4g} Pa give a negative final depth "
                         f"with m = {m}")
    B = P_max / (h_max - h_f)**m
    h_parts, P_parts, seg_parts = [], [], []
    h_at, P_at = 0.0, 0.0
    for k in range(h_c.size):
        if k > 0:       # reload elastically up the previous unloading, to its peak
            P_up = np.linspace(P_at, P_max[k - 1], n_unload + 1)[1:]
            h_parts.append(h_f[k - 1] + (P_up / B[k - 1])**(1.0 / m))
            P_parts.append(P_up)
            seg_parts.append(np.full(n_unload, LOAD))
            h_at, P_at = h_max[k - 1], P_max[k - 1]
        s = np.linspace(0.0, 1.0, n_load + 1)[1:]
        if k == 0:      # Kick's law from the surface to the first peak
            h_new, P_new = s * h_max[0], P_max[0] * s**2
        else:
            # sqrt(P) linear in h: Kick's law P ~ h^2 where the peaks lie on one parabola
            h_new = h_at + s * (h_max[k] - h_at)
            P_new = (math.sqrt(P_at) + s * (math.sqrt(P_max[k]) - math.sqrt(P_at)))**2
        h_parts += [h_new, np.full(5, h_max[k])]          # a short hold at the peak
        P_parts += [P_new, np.full(5, P_max[k])]
        seg_parts += [np.full(n_load, LOAD), np.full(5, HOLD)]
        low = 0.0 if k == h_c.size - 1 else unload_to * P_max[k]
        P_down = np.linspace(P_max[k], low, n_unload + 1)[1:]
        h_parts.append(h_f[k] + (P_down / B[k])**(1.0 / m))
        P_parts.append(P_down)
        seg_parts.append(np.full(n_unload, UNLOAD))
        h_at, P_at = h_parts[-1][-1], P_down[-1]
    h = np.concatenate([[0.0], *h_parts])
    P = np.concatenate([[0.0], *P_parts])
    seg = np.concatenate([[LOAD], *seg_parts])
    if noise:
        if seed is None:
            raise InputError("synthetic noise needs an explicit seed")
        P = P + np.random.default_rng(seed).normal(0.0, noise * P_max.max(), P.size)
    return LoadDisplacementCurve(h + C_f * P, P, dt * np.arange(h.size), seg, indenter=tip,
                                 meta={"synthetic": True, "E_r": E_r, "H": H,
                                       "h_c": h_c.tolist(), "m": m, "seed": seed,
                                       "frame_compliance": C_f})
