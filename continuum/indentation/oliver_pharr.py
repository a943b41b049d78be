"""Indentation analysis: Oliver-Pharr and its corrections, spherical tips, size effect.

Equations from docs/physics.md section 9:

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

from filmscale.continuum.materials import DIAMOND, ElasticPlastic, modulus_from_reduced
from filmscale.core.checks import (check_broadcast, check_choice, check_float_array,
                                   check_positive, check_positive_array, check_real)
from filmscale.core.errors import InputError
from filmscale.core.jsonable import to_jsonable

from .curves import CurveFlag, LoadDisplacementCurve, check_curve, implausible_modulus
from .spherical import loading_points
from .tips import Sphere, Tip, beta_hay, beta_no_slip, epsilon_from_exponent, parse_tip

OK, FAILED = 0, 1
EPSILON_CHOICES = ("tip", "exponent")
BETA_CHOICES = ("tip", "hay", "no-slip")
POOR_FIT_RMS = 0.02           #: unloading fit rms above 2 % of P_max is flagged
EXPONENT_RANGE = (1.0, 2.5)   #: m outside this is not a tip-on-half-space unloading


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
            else:
                out[key] = to_jsonable(value)
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
    from scipy.optimize import leastsq
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
    points) gives status FAILED with the reason, not an exception, so batches keep going. An
    E_r outside the range of real solids (a unit slip in the curve's columns) is flagged
    ``implausible_modulus``, with the slip that explains it.
    """
    from scipy.integrate import trapezoid
    if not isinstance(curve, LoadDisplacementCurve):
        raise InputError(f"curve must be a LoadDisplacementCurve, got {type(curve).__name__}")
    tip = parse_tip(tip)
    if np.ndim(window) != 1 or len(window) != 2:
        raise InputError(f"window = {window!r} must be (start, end) fractions of P_max")
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
    if not (math.isfinite(A_c) and A_c > 0):
        return _failed(tip, (lo, hi), flags, f"the area function gives A = {A_c:.3g} m^2 at "
                       f"h_c = {h_c:.4g} m: not a contact area", P_max, h_max)
    E_r = math.sqrt(math.pi) * S / (2.0 * beta_value * math.sqrt(A_c))

    def rescaled(f_h, f_P):
        """E_r with depths x f_h and loads x f_P: S x f_P/f_h, h_c x f_h."""
        area = float(tip.area(f_h * h_c))
        return E_r * f_P / f_h * math.sqrt(A_c / area) if area > 0 else math.inf

    implausible = implausible_modulus(E_r, "Oliver-Pharr", rescaled)
    if implausible:
        flags.append(implausible)
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


# ---- physical plausibility ------------------------------------------------------------------

def apparent_hertz_modulus(curve: LoadDisplacementCurve, R: float) -> float:
    """E* = 3 P / (4 R^(1/2) h^(3/2)) (Hertz, Johnson 1985), Pa: the median over the loading
    points above 10 % of the largest load before the first pop-in, for a sphere of radius R
    (m). Past first yield it falls (to about 5 H at h = R): a lower estimate of E*."""
    h, P, pop = loading_points(curve, with_pop_in=True)
    if pop is not None and pop >= 3:
        h, P = h[:pop + 1], P[:pop + 1]
    keep = P >= 0.1 * P.max()
    return float(np.median(3.0 * P[keep] / (4.0 * math.sqrt(R) * h[keep]**1.5)))


def refuse_implausible(curve: LoadDisplacementCurve, flags) -> None:
    """InputError naming the curve when ``flags`` hold ``implausible_modulus``: a calibration
    takes curves of real solids only."""
    for flag in flags:
        if flag and flag.code == "implausible_modulus":
            raise InputError(f"curve {curve.meta.get('source', '')!r} refused: "
                             f"{flag.message}")


def check_curve_modulus(curve: LoadDisplacementCurve, tip: Tip | str | None = None,
                        R: float | None = None) -> LoadDisplacementCurve:
    """``curve`` when the modulus it implies is that of a real solid; else InputError naming
    the curve and the unit slip that explains it (`implausible_modulus`). A sphere (``tip``,
    else the curve's indenter, or a radius ``R`` in m) gives E* from its loading
    (`apparent_hertz_modulus`), a sharp tip E_r from its unloading (`oliver_pharr`); a curve
    without a tip or an analysable unloading passes (a calibration refuses it otherwise)."""
    tip = parse_tip(tip) if tip else curve.indenter
    if R is None and isinstance(tip, Sphere):
        R = tip.R
    if R is not None:
        E = apparent_hertz_modulus(curve, R)
        refuse_implausible(curve, [implausible_modulus(E, "Hertz fit of its loading",
                                                       lambda f_h, f_P: E * f_P / f_h**1.5)])
    elif tip is not None:
        refuse_implausible(curve, oliver_pharr(curve, tip, check=False).flags)
    return curve


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
    P_max, S = check_float_array("P_max", P_max), check_float_array("S", S)
    if P_max.shape != S.shape or P_max.ndim != 1:
        raise InputError(f"P_max and S must be 1-D arrays of one length, got shapes "
                         f"{P_max.shape} and {S.shape}")
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
    P_max, W_p, W_t = check_broadcast(**{name: check_float_array(name, v) for name, v in
                                         (("P_max", P_max), ("W_p", W_p), ("W_t", W_t))})
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
    P_max, h_c = check_broadcast(P_max=check_positive_array("P_max", P_max, "N"),
                                 h_c=check_positive_array("h_c", h_c, "m"))
    h_e = h_me - 0.75 * P_e / S_e
    h_r = h_c - h_e
    if np.any(h_r <= 0):
        raise InputError(f"contact depth h_c = {float(np.min(h_c)):.4g} m is not beyond the "
                         f"elastic depth h_e = {h_e:.4g} m: the indent is elastic")
    D_c = tip.area(h_c) / (math.pi * h_c)
    return P_max / (math.pi * D_c * h_r)
