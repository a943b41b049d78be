"""Indentation analysis: Oliver-Pharr and its corrections, spherical tips, size effect.

Equations from physics.md section 9:

- Oliver & Pharr, J. Mater. Res. 7 (1992) 1564 and 19 (2004) 3: unloading fit
  P = B (h - h_f)^m over 20-98 % of P_max (ISO 14577-1), S = m B (h_max - h_f)^(m-1),
  h_c = h_max - eps P_max / S, E_r = sqrt(pi) S / (2 beta sqrt(A_c)), H = P_max / A_c.
- Frame compliance (Fischer-Cripps 2011, sec. 3.4): 1/S = C_f + sqrt(pi) sqrt(H) /
  (2 beta E_r sqrt(P_max)) at constant H and E_r.
- Shallow-depth hardness (Yeo & Polycarpou 2007).
- Hertz fit of a spherical tip's elastic loading and the shear stress at pop-in (Johnson 1985).
- Nix & Gao, J. Mech. Phys. Solids 46 (1998) 411: H = H_0 sqrt(1 + h*/h).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.integrate import trapezoid
from scipy.optimize import least_squares, leastsq

from .curves import LOAD, CurveFlag, LoadDisplacementCurve, check_curve
from .errors import InputError, check_choice, check_positive, check_real
from .materials import DIAMOND, ElasticPlastic, modulus_from_reduced
from .tips import Tip, beta_hay, beta_no_slip, epsilon_from_exponent, parse_tip

OK, FAILED = 0, 1
EPSILON_CHOICES = ("tip", "exponent")
BETA_CHOICES = ("tip", "hay", "no-slip")
POOR_FIT_RMS = 0.02           #: unloading fit rms above 2 % of P_max is flagged
EXPONENT_RANGE = (1.0, 2.5)   #: m outside this is not a tip-on-half-space unloading


def _json_float(x):
    return None if x is None or not math.isfinite(x) else float(x)


@dataclass(frozen=True)
class OliverPharrResult:
    """Oliver-Pharr properties of one curve. NaN fields and status FAILED when not analysable."""

    E_r: float           #: reduced modulus, Pa
    H: float             #: hardness P_max / A_c, Pa
    h_c: float           #: contact depth, m
    S: float             #: unloading stiffness dP/dh at h_max, N/m
    A_c: float           #: projected contact area, m^2
    P_max: float         #: peak load, N
    h_max: float         #: depth at the start of unloading, m
    h_f: float           #: final depth of the fitted power law, m
    m: float             #: unloading exponent
    B: float             #: power-law prefactor, N/m^m
    epsilon: float       #: geometry constant used
    beta: float          #: correction factor used
    E: float             #: sample Young's modulus from E_r (NaN when nu not given), Pa
    W_t: float           #: total work, J
    W_e: float           #: elastic (recovered) work, J
    W_p: float           #: plastic work W_t - W_e, J
    We_Wt: float         #: W_e / W_t
    fit_rms: float       #: rms residual of the unloading fit / P_max
    n_fit: int           #: points in the fit window
    window: tuple        #: fit window as fractions of P_max
    tip: str             #: tip used
    flags: tuple = ()    #: CurveFlag tuple
    status: int = OK
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.status == OK

    @property
    def flag_codes(self) -> tuple[str, ...]:
        return tuple(f.code for f in self.flags)

    def to_dict(self) -> dict:
        out = {}
        for key in self.__dataclass_fields__:
            value = getattr(self, key)
            if key == "flags":
                out[key] = [f.code for f in self.flags]
                out["flag_messages"] = [f.message for f in self.flags]
            elif isinstance(value, float):
                out[key] = _json_float(value)
            elif isinstance(value, tuple):
                out[key] = list(value)
            else:
                out[key] = value
        return out

    def summary(self) -> str:
        if not self.ok:
            return f"not analysed: {self.message}"
        lines = [f"E_r = {self.E_r / 1e9:.4g} GPa, H = {self.H / 1e9:.4g} GPa "
                 f"(h_c = {self.h_c * 1e9:.4g} nm, A_c = {self.A_c * 1e18:.4g} nm^2)",
                 f"S = {self.S:.4g} N/m, P_max = {self.P_max * 1e6:.4g} uN, h_max = "
                 f"{self.h_max * 1e9:.4g} nm, m = {self.m:.3f}, W_e/W_t = {self.We_Wt:.3f}"]
        if math.isfinite(self.E):
            lines.append(f"E = {self.E / 1e9:.4g} GPa")
        lines += [f"flag {f}" for f in self.flags]
        return "\n".join(lines)


def sample_modulus(E_r, nu, indenter: ElasticPlastic = DIAMOND) -> float:
    """E = (1 - nu^2) / (1/E_r - (1 - nu_i^2)/E_i), Pa; NaN when E_r is not below the indenter's
    (Oliver & Pharr 1992 eq. 2)."""
    return float(modulus_from_reduced(E_r, nu, indenter.compliance))


def _power_law_fit(h, P, h_max, P_max):
    """Least-squares P = B (h - h_f)^m in scaled units; returns (B, h_f, m, rms / P_max).

    h_f = h_lo - exp(u) keeps every point above h_f, so the model stays real; the start comes
    from the straight line through P^(2/3) (m = 1.5).
    """
    hn, Pn = h / h_max, P / P_max
    lo = float(hn.min())
    y = np.cbrt(np.clip(Pn, 0.0, None))**2          # P^(2/3): a line in h when m = 1.5
    dx = hn - hn.mean()
    slope = float(dx @ (y - y.mean()) / (dx @ dx)) if np.ptp(hn) > 0 else 0.0
    f0 = hn.mean() - y.mean() / slope if slope > 0 else lo - 0.1
    gap0 = max(lo - f0, 1e-3 * max(1.0 - lo, 1e-3))
    x0 = np.array([max(slope, 1e-6)**1.5, math.log(gap0), 1.5])

    def resid(p):
        x = hn - (lo - np.exp(p[1]))
        return p[0] * x**p[2] - Pn

    def jac(p):
        x = hn - (lo - np.exp(p[1]))
        xm = x**p[2]
        return np.stack([xm, p[0] * p[2] * x**(p[2] - 1.0) * np.exp(p[1]),
                         p[0] * xm * np.log(x)], axis=1)

    # MINPACK's lmder through leastsq: half the call overhead of least_squares, which
    # matters for batches of 10^4 curves. Wild trial steps may overflow: MINPACK then
    # shortens the step, and a failed fit is caught by the caller.
    with np.errstate(all="ignore"):
        (b, u, m), _, _, _, ier = leastsq(resid, x0, Dfun=jac, xtol=1e-12, ftol=1e-12,
                                         full_output=True)
        rms = float(np.sqrt(np.mean(resid((b, u, m))**2)))
    if ier not in (1, 2, 3, 4):     # MINPACK gave up
        return math.nan, math.nan, math.nan, math.nan
    f = lo - float(np.exp(min(u, 700.0)))
    return b * P_max / h_max**m, f * h_max, float(m), rms


def _failed(tip, window, flags, message, P_max=math.nan, h_max=math.nan):
    nan = math.nan
    return OliverPharrResult(nan, nan, nan, nan, nan, P_max, h_max, nan, nan, nan, nan, nan,
                             nan, nan, nan, nan, nan, nan, 0, tuple(window), tip.spec,
                             tuple(flags), FAILED, message)


def oliver_pharr(curve: LoadDisplacementCurve, tip: Tip | str, *, window=(0.2, 0.98),
                 epsilon="tip", beta="tip", nu=None, indenter: ElasticPlastic = DIAMOND,
                 check: bool = True) -> OliverPharrResult:
    """Oliver-Pharr analysis of one curve.

    Parameters
    ----------
    curve : LoadDisplacementCurve
        Frame compliance and drift already removed (see `LoadDisplacementCurve`).
    tip : Tip or str
        Area function (``berkovich``, ``cone:70.3``, a `PolynomialArea`, ...).
    window : (float, float)
        Unloading fit range as fractions of P_max (ISO 14577: 0.2-0.98).
    epsilon : 'tip', 'exponent' or float
        Geometry constant: the tip's (0.75 pyramids and spheres, 0.727 cones, 1 flat), from
        the fitted exponent (Pharr-Bolshakov), or a given value.
    beta : 'tip', 'hay', 'no-slip' or float
        The tip's (1.034 three-sided pyramids, 1 axisymmetric), Hay-Bolshakov-Pharr at the
        tip's equivalent cone angle, Borodich-Keer no-slip, or a given value. 'hay' and
        'no-slip' need the sample's nu.
    nu : float or None
        Sample Poisson ratio: gives E from E_r.
    indenter : ElasticPlastic
        Indenter elasticity for E (diamond, 1141 GPa, 0.07 by default).
    check : bool
        Run `check_curve` and attach its flags.

    Returns an `OliverPharrResult`; a curve that cannot be analysed (no unloading, too few
    points) gives status FAILED with the reason, not an exception, so batches keep going.
    """
    tip = parse_tip(tip)
    lo = check_real("window start", window[0], low=0.0, high=1.0, high_open=True)
    hi = check_real("window end", window[1], low=lo, high=1.0, low_open=True)
    if nu is not None:
        nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    if isinstance(epsilon, str):
        check_choice("epsilon", epsilon, EPSILON_CHOICES)
    else:
        epsilon = check_real("epsilon", epsilon, low=0.5, high=1.0)
    if isinstance(beta, str):
        check_choice("beta", beta, BETA_CHOICES)
        if beta != "tip" and nu is None:
            raise InputError(f"beta = {beta!r} needs the sample Poisson ratio nu")
        if beta == "hay" and tip.half_angle is None:
            raise InputError(f"beta = 'hay' needs a conical or pyramidal tip, got {tip.spec}")
        beta_value = {"tip": lambda: tip.beta, "hay": lambda: beta_hay(tip.half_angle, nu),
                      "no-slip": lambda: beta_no_slip(nu)}[beta]()
    else:
        beta_value = check_real("beta", beta, low=0.5, high=2.0)

    flags = list(check_curve(curve, (lo, hi))) if check else []
    c = curve.finite()
    unl = c.unloading()
    if unl.stop - unl.start < 2:
        return _failed(tip, (lo, hi), flags, "no unloading segment after the peak load")
    h_unl, P_unl = c.h[unl], c.P[unl]
    P_max, h_max = float(P_unl[0]), float(h_unl[0])
    if P_max <= 0:
        return _failed(tip, (lo, hi), flags, "the peak load is not positive", P_max, h_max)
    sel = (P_unl >= lo * P_max) & (P_unl <= hi * P_max)
    if sel.sum() < 4:
        return _failed(tip, (lo, hi), flags, f"only {int(sel.sum())} unloading points in the "
                       f"fit window (4 needed)", P_max, h_max)
    B, h_f, m, rms = _power_law_fit(h_unl[sel], P_unl[sel], h_max, P_max)
    if not (h_f < h_max and math.isfinite(m) and m > 0):
        return _failed(tip, (lo, hi), flags, "the unloading power-law fit did not converge",
                       P_max, h_max)
    S = m * B * (h_max - h_f)**(m - 1.0)
    if epsilon == "tip":
        eps = tip.epsilon
    elif epsilon == "exponent":
        eps = epsilon_from_exponent(min(max(m, 1.0 + 1e-6), 10.0))
    else:
        eps = epsilon
    h_c = h_max - eps * P_max / S
    if rms > POOR_FIT_RMS:
        flags.append(CurveFlag("unloading_fit_poor", f"rms residual of the unloading fit is "
                               f"{rms:.2%} of P_max"))
    if not EXPONENT_RANGE[0] <= m <= EXPONENT_RANGE[1]:
        flags.append(CurveFlag("exponent_out_of_range", f"unloading exponent m = {m:.3g} is "
                               f"outside {EXPONENT_RANGE}"))
    if h_c <= 0:
        return _failed(tip, (lo, hi), flags, f"contact depth h_c = {h_c:.3g} m is not positive",
                       P_max, h_max)
    A_c = float(tip.area(h_c))
    E_r = math.sqrt(math.pi) * S / (2.0 * beta_value * math.sqrt(A_c))
    load = c.loading()
    W_t = float(trapezoid(c.P[load], c.h[load]))
    h_end = float(h_unl[-1])
    tail = B * max(h_end - h_f, 0.0)**(m + 1.0) / (m + 1.0) if P_unl[-1] > 0 else 0.0
    W_e = float(-trapezoid(P_unl, h_unl)) + tail
    E = sample_modulus(E_r, nu, indenter) if nu is not None else math.nan
    return OliverPharrResult(
        E_r=E_r, H=P_max / A_c, h_c=h_c, S=S, A_c=A_c, P_max=P_max, h_max=h_max, h_f=h_f, m=m,
        B=B, epsilon=eps, beta=beta_value, E=E, W_t=W_t, W_e=W_e, W_p=W_t - W_e,
        We_Wt=W_e / W_t if W_t > 0 else math.nan, fit_rms=rms, n_fit=int(sel.sum()),
        window=(lo, hi), tip=tip.spec, flags=tuple(flags))


# ---- frame compliance -----------------------------------------------------------------------

@dataclass(frozen=True)
class FrameCompliance:
    """1/S = C_f + k / sqrt(P_max) fitted on indents of one homogeneous reference."""

    C_f: float        #: frame compliance, m/N
    C_f_std: float    #: its standard error, m/N
    slope: float      #: k = sqrt(pi H) / (2 beta E_r), m N^-1/2
    n: int            #: indents used

    def to_dict(self) -> dict:
        return asdict(self)


def calibrate_frame_compliance(P_max, S) -> FrameCompliance:
    """Frame compliance from the intercept of 1/S against 1/sqrt(P_max).

    At constant H and E_r (a homogeneous reference such as fused silica), the measured
    compliance is 1/S = C_f + sqrt(pi) sqrt(H) / (2 beta E_r sqrt(P_max)); the intercept is
    the compliance of the frame (Fischer-Cripps 2011, sec. 3.4). Use the result with
    `LoadDisplacementCurve.frame_corrected` and analyse again.
    """
    P_max, S = np.asarray(P_max, dtype=float), np.asarray(S, dtype=float)
    if P_max.shape != S.shape or P_max.ndim != 1:
        raise InputError("P_max and S must be 1-D arrays of one length")
    if P_max.size < 3:
        raise InputError(f"frame compliance needs at least 3 indents at different loads, "
                         f"got {P_max.size}")
    if not np.all(np.isfinite(P_max) & (P_max > 0) & np.isfinite(S) & (S > 0)):
        raise InputError("frame compliance: every P_max and S must be finite and > 0")
    x = 1.0 / np.sqrt(P_max)
    if np.ptp(x) <= 1e-6 * x.mean():
        raise InputError("frame compliance needs indents at different peak loads")
    (slope, C_f), cov = np.polyfit(x, 1.0 / S, 1, cov="unscaled")
    resid = 1.0 / S - (C_f + slope * x)
    dof = max(P_max.size - 2, 1)
    std = math.sqrt(cov[1, 1] * float(resid @ resid) / dof)
    return FrameCompliance(float(C_f), std, float(slope), int(P_max.size))


# ---- shallow-depth hardness (Yeo & Polycarpou 2007) ---------------------------------------

def elastic_indent(P_max, W_p, W_t, max_plastic_fraction=0.05):
    """Index of the largest-load indent whose unloading retraces loading (|W_p/W_t| below the
    given fraction), or None: P_e, h_m,e and S_e of the Yeo-Polycarpou correction.

    P_max (N), W_p and W_t (J) are arrays over the indents; NaN entries (failed analyses)
    never qualify.
    """
    P_max, W_p, W_t = (np.asarray(v, dtype=float) for v in (P_max, W_p, W_t))
    with np.errstate(divide="ignore", invalid="ignore"):
        elastic = (W_t > 0) & (np.abs(W_p / W_t) < max_plastic_fraction) & np.isfinite(P_max)
    if not elastic.any():
        return None
    return int(np.flatnonzero(elastic)[np.argmax(P_max[elastic])])


def shallow_depth_hardness(P_max, h_c, tip: Tip | str, *, P_e, h_me, S_e):
    """Hardness corrected for the elastic part of a shallow contact (Yeo & Polycarpou 2007).

    h_e = h_m,e - 0.75 P_e / S_e is the elastic contact depth of the largest purely elastic
    indent (load P_e, depth h_m,e, stiffness S_e); h_r = h_c - h_e; D_c = A_c(h_c)/(pi h_c);
    H = P_max / (pi D_c h_r). As h_e/h_c -> 0 this returns Oliver-Pharr's P_max / A_c.

    Parameters
    ----------
    P_max, h_c : float or array_like
        Peak load (N) and contact depth (m) of the indents to correct.
    tip : Tip or str
        Area function.
    P_e, h_me, S_e : float
        Load (N), maximum depth (m) and stiffness (N/m) of the elastic indent.
    """
    tip = parse_tip(tip)
    P_e, h_me, S_e = (check_positive(n, v, u) for n, v, u in
                      (("P_e", P_e, "N"), ("h_me", h_me, "m"), ("S_e", S_e, "N/m")))
    P_max, h_c = np.asarray(P_max, dtype=float), np.asarray(h_c, dtype=float)
    h_e = h_me - 0.75 * P_e / S_e
    h_r = h_c - h_e
    if np.any(h_r <= 0):
        raise InputError(f"contact depth h_c = {float(np.min(h_c)):.4g} m is not beyond the "
                         f"elastic depth h_e = {h_e:.4g} m: the indent is elastic")
    D_c = tip.area(h_c) / (math.pi * h_c)
    return P_max / (math.pi * D_c * h_r)


# ---- spherical tips ---------------------------------------------------------------------------

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
        span = float(h.max())      # unknowns scaled to order one for the solver's tolerances

        def misfit(v):
            K, x = amplitude(v[0] * span)
            return (K * x - P) / P.max()
        fit = least_squares(misfit, [0.0], bounds=([-1.0], [float(h.min()) * 0.999 / span]),
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


def load_noise_sigma(P) -> float:
    """Robust standard deviation of white noise on a smooth signal, from second differences:
    var(P[i+1] - 2 P[i] + P[i-1]) = 6 sigma^2, with sigma from 1.4826 MAD."""
    d2 = np.diff(np.asarray(P, float), 2)
    if d2.size == 0:
        return 0.0
    return 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / math.sqrt(6.0)


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
    sigma = load_noise_sigma(P)
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


# ---- indentation size effect -----------------------------------------------------------------

@dataclass(frozen=True)
class NixGaoFit:
    """H = H_0 sqrt(1 + h*/h) fitted as the straight line H^2 = H_0^2 + H_0^2 h* / h."""

    H0: float          #: macroscopic hardness, Pa
    h_star: float      #: characteristic depth, m
    H0_std: float      #: standard error of H0, Pa
    h_star_std: float  #: standard error of h*, m
    r2: float          #: coefficient of determination of the line
    n: int

    def hardness(self, h):
        """H(h), Pa, at depth h (m)."""
        return self.H0 * np.sqrt(1.0 + self.h_star / np.asarray(h, dtype=float))

    def to_dict(self) -> dict:
        return asdict(self)


def nix_gao_fit(h, H) -> NixGaoFit:
    """Nix-Gao fit of hardness H (Pa) against depth h (m), with standard errors.

    Ordinary least squares of H^2 on 1/h; the errors of H_0 = sqrt(a) and h* = b/a follow
    from the covariance of (a, b) to first order.
    """
    h, H = np.asarray(h, dtype=float), np.asarray(H, dtype=float)
    if h.shape != H.shape or h.ndim != 1 or h.size < 3:
        raise InputError("Nix-Gao needs 1-D arrays h and H of one length, at least 3 indents")
    if not np.all(np.isfinite(h) & (h > 0) & np.isfinite(H) & (H > 0)):
        raise InputError("Nix-Gao: every h and H must be finite and > 0")
    x, y = 1.0 / h, H**2
    if np.ptp(x) <= 1e-9 * x.mean():
        raise InputError("Nix-Gao needs indents at different depths")
    (b, a), cov = np.polyfit(x, y, 1, cov="unscaled")
    resid = y - (a + b * x)
    s2 = float(resid @ resid) / max(h.size - 2, 1)
    cov = cov * s2
    if a <= 0:
        raise InputError("Nix-Gao: H^2 against 1/h extrapolates to a negative H_0^2: the "
                         "hardness does not follow the Nix-Gao form")
    H0, h_star = math.sqrt(a), b / a
    var_a, var_b, cov_ab = cov[1, 1], cov[0, 0], cov[0, 1]
    H0_std = math.sqrt(var_a) / (2.0 * H0)
    h_star_std = math.sqrt(max(var_b / a**2 - 2.0 * b * cov_ab / a**3 + b * b * var_a / a**4,
                               0.0))
    total = float(np.sum((y - y.mean())**2))
    r2 = 1.0 - float(resid @ resid) / total if total > 0 else 1.0
    return NixGaoFit(H0, float(h_star), H0_std, h_star_std, r2, int(h.size))


__all__ = [
    "OliverPharrResult", "oliver_pharr", "sample_modulus", "FrameCompliance",
    "calibrate_frame_compliance", "elastic_indent", "shallow_depth_hardness", "HertzFit",
    "hertz_fit", "PopIn", "detect_pop_in", "elastic_limit", "pop_in_shear_stress", "NixGaoFit",
    "nix_gao_fit",
]
