"""Spherical tips: Hertz fit of the elastic loading, pop-in and load-drop detection, the
shear stress at pop-in (Johnson 1985, Contact Mechanics; docs/physics.md section 9)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from filmscale.continuum.indentation.curves import LOAD
from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.core.noise import noise_sigma

from .curves import LoadDisplacementCurve


@dataclass(frozen=True)
class HertzFit:
    """P = (4/3) E_r sqrt(R) (h - h_0)^(3/2) fitted to an elastic loading segment."""

    E_r: float        #: reduced modulus, Pa
    R: float          #: tip radius, m
    h_0: float        #: depth offset, m (0 unless fitted)
    rms: float        #: rms residual / largest load fitted
    n: int            #: points fitted
    P_limit: float    #: largest load fitted, N

    def to_dict(self) -> dict:
        return asdict(self)


def hertz_fit(curve: LoadDisplacementCurve, *, R=None, E_r=None, P_limit=None,
              fit_offset=False) -> HertzFit:
    """Fit the Hertz law to the elastic loading of a spherical tip.

    Give R (m) to get E_r, or E_r (Pa) to get R. Points are loading points up to P_limit (N);
    by default up to the first pop-in (`elastic_limit`), else the whole loading.
    ``fit_offset`` also fits a depth offset h_0 (m) for a misplaced surface.
    """
    from scipy.optimize import least_squares
    if (R is None) == (E_r is None):
        raise InputError("hertz_fit needs exactly one of R (to fit E_r) or E_r (to fit R)")
    if R is not None:
        R = check_positive("R", R, "m")
    if E_r is not None:
        E_r = check_positive("E_r", E_r, "Pa")
    c = curve.finite()
    load = c.loading()
    h, P = c.h[load], c.P[load]
    keep = c.segment[load] == LOAD
    if P_limit is None:
        end = elastic_limit(c)
        P_limit = float(P.max()) if end is None else float(c.P[end])
        if end is not None:
            keep &= np.arange(h.size) <= end
    P_limit = check_positive("P_limit", P_limit, "N")
    keep &= (P > 0) & (P <= P_limit)
    h, P = h[keep], P[keep]
    if h.size < 3 + fit_offset:
        raise InputError(f"only {h.size} loading points below P_limit = {P_limit:.4g} N")

    def amplitude(h0):
        x = np.clip(h - h0, 0.0, None)**1.5
        return float(P @ x / (x @ x)), x

    h0 = 0.0
    if fit_offset:
        # unknowns scaled to order one for the solver's tolerances; the contact starts below
        # the first loaded point, which may lie above the nominal surface (h <= 0: a surface
        # placed too deep, as on a rough or amorphous top)
        low = min(float(h.min()), 0.0)
        span = float(h.max()) - low
        upper = (float(h.min()) - 1e-3 * abs(float(h.min()))) / span if h.min() > 0 else \
            (float(h.min()) - 1e-3 * span) / span
        lower = low / span - 1.0

        def misfit(v):
            K, x = amplitude(v[0] * span)
            return (K * x - P) / P.max()
        fit = least_squares(misfit, [0.0 if upper > 0 else upper - 1e-2], bounds=([lower], [upper]),
                            xtol=1e-14, ftol=1e-14, gtol=1e-14)
        h0 = float(fit.x[0]) * span
    K, x = amplitude(h0)
    rms = float(np.sqrt(np.mean((K * x - P)**2)) / P.max())
    if R is not None:
        E_r = 3.0 * K / (4.0 * math.sqrt(R))
    else:
        R = (3.0 * K / (4.0 * E_r))**2
    return HertzFit(E_r, R, h0, rms, int(h.size), float(P.max()))


@dataclass(frozen=True)
class PopIn:
    """A displacement burst on loading."""

    index: int        #: curve index of the last point before the burst
    P: float          #: load at the burst, N
    h: float          #: depth before the burst, m
    jump: float       #: depth increase across the burst, m
    significance: float  #: jump over the robust scatter of the increments

    def to_dict(self) -> dict:
        return asdict(self)


def detect_pop_in(curve: LoadDisplacementCurve, *, threshold=8.0) -> PopIn | None:
    """The largest displacement burst on loading, or None.

    Depth increments along the loading are compared with their smooth trend (a running
    median); a burst is an increment more than ``threshold`` robust standard deviations
    (1.4826 MAD) above it and more than twice the trend. Returns the largest such burst.
    """
    threshold = check_positive("threshold", threshold)
    c = curve.finite()
    load = c.loading()
    idx = np.flatnonzero(c.segment[load] == LOAD)
    if idx.size < 8:
        return None
    dh = np.diff(c.h[idx])
    width = max(5, (dh.size // 20) | 1)
    pad = np.pad(dh, width // 2, mode="edge")
    trend = np.median(np.lib.stride_tricks.sliding_window_view(pad, width), axis=1)
    resid = dh - trend
    scale = 1.4826 * float(np.median(np.abs(resid - np.median(resid))))
    k = int(np.argmax(resid))
    score = resid[k] / scale if scale > 0 else math.inf
    if resid[k] <= 0 or score < threshold or dh[k] < 2.0 * abs(trend[k]):
        return None
    i = int(idx[k])
    return PopIn(i, float(c.P[i]), float(c.h[i]), float(dh[k]),
                 float(score) if math.isfinite(score) else math.inf)


@dataclass(frozen=True)
class LoadDrop:
    """A load drop on loading under displacement control: the pop-in of an MD indentation."""

    index: int        #: curve index of the load peak before the drop
    P: float          #: load at the peak, N
    h: float          #: depth at the peak, m
    drop: float       #: load lost before the load rises again, N
    significance: float  #: drop over the load noise

    def to_dict(self) -> dict:
        return asdict(self)


def detect_load_drop(curve: LoadDisplacementCurve, *, threshold=6.0,
                     min_drop=0.0) -> LoadDrop | None:
    """The first significant load drop on loading, or None.

    Under displacement control a pop-in (dislocation nucleation) shows as a fall of the load
    below its running maximum. From first contact (P > 0) on, the first point whose drawdown
    from the running maximum exceeds ``threshold`` noise standard deviations (and 1 % of the
    peak, so that a noiseless curve is not split by round-off, and ``min_drop``, N) marks the
    event; the peak is the running maximum's point, the drop runs until the load regains the
    peak.
    """
    threshold = check_positive("threshold", threshold)
    min_drop = check_real("min_drop", min_drop, low=0.0, unit="N")
    c = curve.finite()
    idx = np.flatnonzero(c.segment == LOAD)
    idx = idx[np.argmax(c.P[idx] > 0):] if np.any(c.P[idx] > 0) else idx[:0]
    if idx.size < 8:
        return None
    P = c.P[idx]
    sigma = noise_sigma(P)
    running = np.maximum.accumulate(P)
    drawdown = running - P
    hits = np.flatnonzero(drawdown > np.maximum(np.maximum(threshold * sigma, 0.01 * running),
                                                min_drop))
    if hits.size == 0:
        return None
    first = int(hits[0])
    peak = int(np.argmax(P[:first + 1]))
    regained = np.flatnonzero(P[first:] >= P[peak])
    end = first + int(regained[0]) if regained.size else P.size
    drop = float(P[peak] - P[peak:end].min())
    i = int(idx[peak])
    return LoadDrop(i, float(c.P[i]), float(c.h[i]), drop,
                    drop / sigma if sigma > 0 else math.inf)


def elastic_limit(curve: LoadDisplacementCurve, *, min_fraction=0.02) -> int | None:
    """Curve index of the last point before the first pop-in, or None without one.

    A pop-in is a displacement burst under load control (`detect_pop_in`) or a load drop
    under displacement control (`detect_load_drop`, as in MD); the earlier one counts. Only
    events of at least ``min_fraction`` of the largest loading depth (bursts) or load (drops)
    count: the contact oscillations of a particle model (0.4 % of P_max on the TLSPH ci
    curve) are not pop-ins; an MD pop-in drops 20-25 % of its load.
    """
    min_fraction = check_real("min_fraction", min_fraction, low=0.0, high=1.0)
    c = curve.finite()
    load = c.segment == LOAD
    if not np.any(load):
        return None
    burst = detect_pop_in(c)
    if burst is not None and burst.jump < min_fraction * float(np.max(c.h[load])):
        burst = None
    drop = detect_load_drop(c, min_drop=min_fraction * float(np.max(c.P[load])))
    ends = [e.index for e in (burst, drop) if e is not None]
    return min(ends) if ends else None


def pop_in_shear_stress(P, E_r, R) -> float:
    """Largest shear stress under a sphere at load P: 0.31 p_0 (Johnson 1985, nu = 0.3).

    p_0 = (6 P E_r^2 / (pi^3 R^2))^(1/3) is the Hertz peak pressure; P in N, E_r in Pa, R in
    m; returns Pa. At a pop-in this estimates the theoretical shear strength.
    """
    P, E_r, R = check_positive("P", P, "N"), check_positive("E_r", E_r, "Pa"), \
        check_positive("R", R, "m")
    return 0.31 * (6.0 * P * E_r**2 / (math.pi**3 * R**2))**(1.0 / 3.0)


def loading_points(curve: LoadDisplacementCurve, with_pop_in=False):
    """Loading points with h > 0 and P > 0; with ``with_pop_in`` also the index (among
    them) of the last point before the first pop-in, or None."""
    c = curve.finite()
    part = c.loading()
    h, P, seg = c.h[part], c.P[part], c.segment[part]
    keep = (seg == LOAD) & (h > 0) & (P > 0)
    if keep.sum() < 3:
        raise InputError(f"curve {c.meta.get('source', '')!r} has {int(keep.sum())} loading "
                         "points with h > 0 and P > 0; a calibration needs at least 3")
    if not with_pop_in:
        return h[keep], P[keep]
    end = elastic_limit(c)
    pop = None if end is None else int(np.count_nonzero(keep[:end + 1])) - 1
    return h[keep], P[keep], (pop if pop is not None and pop >= 0 else None)


#: loading exponents m of P ~ h^m that each tip shape can give: a sphere 1.5 (Hertz, Johnson
#: 1985) falling towards 1 when fully plastic (p_m constant, A ~ 2 pi R h), a little above
#: 1.5 on a stiffer substrate; a sharp tip 2 at every depth (Kick's law, P = C h^2, Dao et al.
#: 2001), elastic or plastic. Measured on the package's curves: spheres 1.25-1.51 (the MD
#: demo curve 1.51, layered-law curves 1.36-1.47), Dao's Berkovich curves 2.00
EXPONENT_RANGES = {"sphere": (0.8, 1.8), "sharp": (1.7, 2.4)}


def loading_exponent(curve: LoadDisplacementCurve, h0: float = 0.0) -> float:
    """The exponent m of P = k (h - h0)^m over the loading, by least squares in ln P against
    ln(h - h0) over the points above 10 % of the largest load before the first pop-in (a
    pop-in's excursion is not the tip's shape); ``h0`` (m, at most 0) the contact zero."""
    h, P, pop = loading_points(curve, with_pop_in=True)
    if pop is not None and pop >= 3:
        h, P = h[:pop + 1], P[:pop + 1]
    keep = P >= 0.1 * P.max()
    if keep.sum() < 3:
        raise InputError(f"curve {curve.meta.get('source', '')!r}: fewer than 3 loading "
                         "points above 10 % of its load; no loading exponent")
    return float(np.polyfit(np.log(h[keep] - min(h0, 0.0)), np.log(P[keep]), 1)[0])


def first_contact_depth(curve: LoadDisplacementCurve) -> float:
    """The depth (m) of the last loading point at zero load before the load stays positive,
    or 0 when the loading has none at or below 0: where a rigid (MD) tip met its first atom,
    whose load is exactly zero until then."""
    c = curve.finite()
    part = c.loading()
    h, P = c.h[part][c.segment[part] == LOAD], c.P[part][c.segment[part] == LOAD]
    positive = np.nonzero(P > 0)[0]
    zero = np.nonzero(P <= 0)[0]
    zero = zero[zero < positive[-1]] if positive.size else zero[:0]
    return float(min(h[zero.max()], 0.0)) if zero.size else 0.0


def check_tip_shape(curve: LoadDisplacementCurve, shape: str, fit_zero: bool = False) -> float:
    """The curve's loading exponent, or InputError when it contradicts a ``shape`` of
    "sphere" or "sharp" tip (`EXPONENT_RANGES`): a Berkovich curve declared as a sphere
    loads as h^2, not h^1.5. With ``fit_zero`` (a calibration that fits the contact zero: a
    rigid tip on a surface without a sharp zero) the exponent is judged at both ends of the
    zero's range, the nominal surface and the first contact (`first_contact_depth`), and
    refused only when both fall outside: on an a-C film a zero 0.02 nm above the nominal
    surface moved the exponent of its first 0.13 nm from 0.74 to 1.43."""
    m = loading_exponent(curve)
    lo, hi = EXPONENT_RANGES[shape]
    ends = (m, loading_exponent(curve, first_contact_depth(curve))) if fit_zero else (m,)
    if not any(lo <= x <= hi for x in ends) and not (min(ends) < lo and max(ends) > hi):
        other = (shape == "sphere" and min(ends) > hi) or (shape == "sharp" and max(ends) < lo)
        look = ("it looks " + ("sharp" if shape == "sphere" else "spherical") if other else
                f"it does not load like a {shape} tip")
        span = f"h^{m:.2f}" if len(ends) == 1 else \
            f"h^{ends[0]:.2f} (h^{ends[1]:.2f} from its first contact)"
        raise InputError(
            f"curve {curve.meta.get('source', '')!r} loads as P ~ {span}, outside the "
            f"{lo:g}-{hi:g} of a {shape} tip ({curve.indenter or 'no tip named'}): {look}; "
            "check the tip the curve was measured with")
    return m
