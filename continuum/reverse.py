"""Sharp-indentation forward and reverse analysis (Dao et al. 2001; Chollacoop, Dao & Suresh 2003).

A sharp tip loads a power-law hardening solid, sigma = E eps for sigma <= sigma_Y and
sigma = sigma_Y (1 + E eps_p / sigma_Y)^n, along Kick's law P = C h^2. Dao et al. (2001, Acta
Mater. 49, 3899) fitted dimensionless functions Pi1-Pi5 to finite-element (FE) cases so that the
loading curvature C, the initial unloading slope dP/dh and the plastic work ratio W_p/W_t give
the reduced modulus E*, the representative stress sigma_0.033 at eps_r = 0.033, the hardening
exponent n and the yield strength sigma_Y. Chollacoop, Dao & Suresh (2003, Acta Mater. 51,
3713) extended Pi1 to cones of half-angle 50-80 deg and paired two tips ("dual indenter") to
pin down n. Equations and coefficients: physics.md section 10 [C2].

Beyond the closed form, a surrogate is fitted to the FE cases packaged in ``data/dao2001``
(Lu et al. 2020, PNAS 117, 7052; Apache-2.0): a ridge-regularised polynomial maps the
dimensionless observables (ln(c* C h_m / (dP/dh)), W_p/W_t) to ln(c* E* h_m / (dP/dh)),
replacing the Pi4/Pi5 area route where most of the closed form's E* error arises; sigma_0.033
then follows from Dao's Pi1 as in the closed form. `cross_validate` measures both methods on
held-out FE cases.

Public API in SI: Pa, N/m, m. E* follows 1/E* = (1 - nu^2)/E + (1 - nu_i^2)/E_i (E_i = inf:
rigid indenter, the FE convention). Uncertainties are propagated by Monte Carlo with an explicit
seed. Results are frozen dataclasses with ``summary()`` and ``to_dict()``.
"""

from __future__ import annotations

import csv
import functools
import math
import re
from dataclasses import dataclass, fields, is_dataclass, replace
from importlib import resources

import numpy as np
from scipy.optimize import elementwise
from scipy.spatial import Delaunay

from .errors import (MODULUS_MAX, InputError, ModelRangeError, check_choice, check_positive,
                     check_real)
from .materials import modulus_from_reduced

# --- constants of physics.md section 10 -----------------------------------------------------

#: Pi1 (Dao 2001): C / sigma_0.033 = A x^3 + B x^2 + C x + D with x = ln(E*/sigma_0.033)
PI1_DAO = (-1.131, 13.635, -30.594, 29.267)
#: E*/sigma_0.033 interval where Pi1 is monotone (its two stationary points); outside: reject
DAO_RATIO_RANGE = (3.85, 804.0)
#: Pi2: (dP/dh)/(E* h_m) = sum_k p_k(n) x^(3-k); row k holds p_k's cubic in n, highest first
PI2 = np.array([[-1.40557, 0.77526, 0.15830, -0.06831],
                [17.93006, -9.22091, -2.37733, 0.86295],
                [-79.99715, 40.55620, 9.00157, -2.54543],
                [122.65069, -63.88418, -9.58936, 6.20045]])
#: Pi4: p_ave/E* = A (R0 - h_r/h_m)^P
PI4_A, PI4_R0, PI4_P = 0.268536, 0.9952495, 1.1142735
#: h_r/h_m interval where Pi4 was verified against FE
HR_HM_VERIFIED = (0.5, 0.98)
#: Pi5: W_p/W_t = a (b - c^(-d r^e) - f r^g), r = h_r/h_m
PI5 = (1.61217, 1.13111, 1.74756, 1.49291, 2.535334, 0.075187, 1.135826)
#: representative strain of the 70.3 deg (Berkovich-equivalent) cone
EPS_R_DAO = 0.033
#: dP/dh = c* E* sqrt(A_m) (large-deformation FE)
C_STAR_BERKOVICH = 1.2370
C_STAR_CONE = 1.1957
#: Pi1_theta (Chollacoop 2003): (A, B, C, D) with x = ln(E*/sigma_r), sigma_r at eps_r(theta)
PI1_THETA = {50.0: (0.0394, -1.098, 9.862, -11.837),
             60.0: (-0.154, 0.932, 7.657, -11.773),
             80.0: (-2.913, 44.023, -122.771, 119.991)}
#: half-angles (deg) where a Pi1 is calibrated
ANGLE_RANGE = (50.0, 80.0)
BERKOVICH_ANGLE = 70.3
CUBE_CORNER_ANGLE = 42.28
#: hardening exponents of the FE calibration; n is searched here
N_RANGE = (0.0, 0.5)
#: indenter of Dao's experiments (diamond); physics.md section 9 quotes 1141 GPa too
E_I_DAO, NU_I_DAO = 1100e9, 0.07
#: maximum depth and Poisson ratio of the packaged FE cases (rigid indenter): h_m = 0.2 um
#: reproduces Pi2 on the 70-deg file to 0.4 % (median) with E* = E / (1 - 0.3^2)
FE_DEPTH, FE_NU = 0.2e-6, 0.3
#: a 1 % change in dP/dh moving n by more than this is flagged as ill-conditioned
N_SENSITIVITY_LIMIT = 0.1
#: n standard deviation above which n is flagged as poorly determined
N_STD_LIMIT = 0.1
#: surrogate hyper-parameter grid: polynomial total degree and ridge strength
SURROGATE_DEGREES = (1, 2, 3, 4)
SURROGATE_RIDGES = (1e-3, 1e-1, 1.0)
#: grouped CV that picks the surrogate's hyper-parameters: folds, repeated splits, seed
SURROGATE_SELECTION_FOLDS, SURROGATE_SELECTION_REPEATS, SURROGATE_SELECTION_SEED = 5, 3, 0
#: (degree, ridge) of the fallback regression of ln(sigma_0.033/C), fixed: it is used only
#: where C/E* has no Pi1 root, so a low degree extrapolates gently
SURROGATE_FALLBACK = (1, 0.1)

METHODS = ("closed-form", "surrogate")
SELECTIONS = ("nested", "fixed")
_N_GRID = np.linspace(N_RANGE[0], N_RANGE[1], 51)


# --- the dimensionless functions ------------------------------------------------------------

def representative_strain(theta):
    """eps_r(theta) = 2.397e-5 theta^2 - 5.311e-3 theta + 0.2884 (Chollacoop et al. 2003).

    theta: cone half-angle, deg (calibrated 50-80); 0.0335 at 70.3 deg, where Dao's 0.033 is used.
    """
    theta = np.asarray(theta, dtype=float)
    return 2.397e-5 * theta**2 - 5.311e-3 * theta + 0.2884


def representative_stress(E, sigma_y, n, eps_r):
    """sigma_r = sigma_Y (1 + E eps_r / sigma_Y)^n, Pa (Dao et al. 2001; E, sigma_Y in Pa)."""
    return sigma_y * np.power(1.0 + E * eps_r / sigma_y, n)


def dao_pi1(x, coeffs=PI1_DAO):
    """Pi1 = C / sigma_r as a cubic in x = ln(E*/sigma_r) (Dao 2001; Chollacoop 2003)."""
    return np.polyval(coeffs, x)


def dao_pi2(x, n):
    """Pi2 = (dP/dh) / (E* h_m) at x = ln(E*/sigma_0.033) and hardening exponent n (Dao 2001)."""
    x = np.asarray(x, dtype=float)
    n = np.asarray(n, dtype=float)
    return sum(np.polyval(row, n) * x ** (3 - k) for k, row in enumerate(PI2))


def dao_pi4(hr_hm):
    """Pi4 = p_ave / E* = 0.268536 (0.9952495 - h_r/h_m)^1.1142735 (Dao 2001)."""
    with np.errstate(invalid="ignore"):
        return PI4_A * np.power(PI4_R0 - np.asarray(hr_hm, dtype=float), PI4_P)


def dao_pi5(hr_hm):
    """Pi5 = W_p / W_t as a function of h_r/h_m (Dao 2001)."""
    a, b, c, d, e, f, g = PI5
    r = np.asarray(hr_hm, dtype=float)
    return a * (b - c ** (-d * r**e) - f * r**g)


#: W_p/W_t reachable by Pi5 on 0 <= h_r/h_m < 0.9952495 (where Pi4 > 0)
WPWT_RANGE = (float(dao_pi5(0.0)), float(dao_pi5(PI4_R0)))


def _pi4_inverse(p_over_E):
    """h_r/h_m from p_ave/E* (Pi4 inverted in closed form)."""
    return PI4_R0 - np.power(p_over_E / PI4_A, 1.0 / PI4_P)


def _pi5_inverse(WpWt):
    """h_r/h_m from W_p/W_t (Pi5 is increasing on [0, R0]); NaN outside WPWT_RANGE."""
    WpWt = np.asarray(WpWt, dtype=float)
    ok = (WpWt > WPWT_RANGE[0]) & (WpWt < WPWT_RANGE[1])
    out = np.full(WpWt.shape, np.nan)
    if ok.any():
        res = elementwise.find_root(lambda r, w: dao_pi5(r) - w, (0.0, PI4_R0),
                                    args=(WpWt[ok],))
        out[ok] = res.x
    return out


def _pi1_range(coeffs) -> tuple[float, float]:
    """Widest x interval where Pi1 > 0, Pi1 rises and Pi1(x) e^(-x) = C/E* falls (one root)."""
    x = np.linspace(0.0, 10.0, 10001)
    v = np.polyval(coeffs, x)
    dv = np.polyval(np.polyder(coeffs), x)
    ok = (v > 0) & (dv > 0) & (dv < v)
    if not ok.any():
        raise ModelRangeError(f"Pi1 coefficients {tuple(coeffs)} are nowhere monotone on "
                              "0 <= ln(E*/sigma_r) <= 10")
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
    runs = edges.reshape(-1, 2)
    lo, hi = runs[np.argmax(runs[:, 1] - runs[:, 0])]
    return float(x[lo]), float(x[hi - 1])


# --- tips -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class SharpTip:
    """A sharp tip and its Pi1 calibration; build with `sharp_tip` or directly for user data.

    Parameters
    ----------
    name : str
        Label, e.g. "berkovich", "cone:60".
    theta : float
        Half-angle of the (equivalent) cone, deg.
    eps_r : float or None
        Representative plastic strain of the tip; None: uncalibrated.
    pi1 : tuple of 4 floats or None
        (A, B, C, D) of Pi1_theta = C / sigma_r = A x^3 + B x^2 + C x + D with
        x = ln(E*/sigma_r). None with theta in [50, 80] deg: interpolated between the tabulated
        angles (see `loading_curvature`); None otherwise: uncalibrated.
    c_star : float or None
        c* in dP/dh = c* E* sqrt(A_m).
    x_range : tuple of 2 floats or None
        Interval of x where Pi1 may be inverted; computed from `pi1` when None.
    dao_functions : bool
        True where Pi2, Pi4 and Pi5 (calibrated for 70.3 deg) apply: Berkovich and the 70.3 deg
        cone. Only such tips support `dao_reverse`; the others give C alone.

    A cube corner (42.28 deg) lies outside the calibrated 50-80 deg: ``sharp_tip("cube-corner")``
    is uncalibrated, and using it raises `ModelRangeError` until the user supplies a
    calibration, e.g. ``dataclasses.replace(sharp_tip("cube-corner"), eps_r=..., pi1=(...))``.
    """

    name: str
    theta: float
    eps_r: float | None = None
    pi1: tuple[float, float, float, float] | None = None
    c_star: float | None = None
    x_range: tuple[float, float] | None = None
    dao_functions: bool = False

    def __post_init__(self):
        object.__setattr__(self, "theta", check_real("tip half-angle theta", self.theta, low=0.0,
                                                     high=90.0, low_open=True, high_open=True,
                                                     unit="deg"))
        if self.eps_r is not None:
            object.__setattr__(self, "eps_r", check_real("tip eps_r", self.eps_r, low=0.0,
                                                         high=1.0, low_open=True))
        if self.c_star is not None:
            object.__setattr__(self, "c_star", check_positive("tip c_star", self.c_star))
        if self.pi1 is not None:
            coeffs = tuple(self.pi1) if isinstance(self.pi1, (tuple, list)) else ()
            if len(coeffs) != 4:
                raise InputError(f"tip pi1 must be 4 numbers (A, B, C, D), got {self.pi1!r}")
            coeffs = tuple(check_real(f"tip pi1[{i}]", c) for i, c in enumerate(coeffs))
            object.__setattr__(self, "pi1", coeffs)
            if self.x_range is None:
                object.__setattr__(self, "x_range", _pi1_range(coeffs))
        if self.x_range is not None:
            lo, hi = (check_real("tip x_range", v) for v in self.x_range)
            if not lo < hi:
                raise InputError(f"tip x_range = {self.x_range!r} must be increasing")
            object.__setattr__(self, "x_range", (lo, hi))

    @property
    def interpolated(self) -> bool:
        """Pi1 interpolated between tabulated angles (no coefficients of its own)."""
        return self.pi1 is None and ANGLE_RANGE[0] <= self.theta <= ANGLE_RANGE[1]

    def _require_calibration(self):
        if self.eps_r is None or (self.pi1 is None and not self.interpolated):
            raise ModelRangeError(
                f"tip {self.name} ({self.theta:g} deg) has no Pi1 calibration: the Chollacoop "
                f"functions hold for {ANGLE_RANGE[0]:g}-{ANGLE_RANGE[1]:g} deg; supply eps_r and "
                "pi1 (dataclasses.replace(tip, eps_r=..., pi1=(A, B, C, D)))")


def _tabulated_tips() -> dict[float, SharpTip]:
    tips = {BERKOVICH_ANGLE: SharpTip(f"cone:{BERKOVICH_ANGLE:g}", BERKOVICH_ANGLE, EPS_R_DAO,
                                      PI1_DAO, C_STAR_CONE,
                                      tuple(math.log(r) for r in DAO_RATIO_RANGE), True)}
    for theta, coeffs in PI1_THETA.items():
        tips[theta] = SharpTip(f"cone:{theta:g}", theta, float(representative_strain(theta)),
                               coeffs, C_STAR_CONE)
    return dict(sorted(tips.items()))


_TABULATED = _tabulated_tips()


def sharp_tip(spec) -> SharpTip:
    """The `SharpTip` for ``spec``: "berkovich", "cone:THETA" (deg, 50-80) or "cube-corner".

    "berkovich": c* = 1.2370, eps_r = 0.033, Dao's Pi1 (equivalent cone 70.3 deg).
    "cone:THETA": c* = 1.1957; 70.3 uses Dao's Pi1 and eps_r = 0.033; 50, 60 and 80 the
    Chollacoop Pi1_theta with eps_r(theta); other angles interpolate (`loading_curvature`).
    "cube-corner" (42.28 deg): uncalibrated (see `SharpTip`). A `SharpTip` passes through.
    """
    if isinstance(spec, SharpTip):
        return spec
    valid = "berkovich, cone:THETA (THETA in [50, 80] deg), cube-corner"
    if not isinstance(spec, str):
        raise InputError(f"tip = {spec!r} is not one of: {valid}")
    s = spec.strip().lower()
    if s == "berkovich":
        return replace(_TABULATED[BERKOVICH_ANGLE], name="berkovich", c_star=C_STAR_BERKOVICH)
    if s in ("cube-corner", "cube_corner", "cubecorner"):
        return SharpTip("cube-corner", CUBE_CORNER_ANGLE)
    m = re.fullmatch(r"cone:\s*(\S+)", s)
    if m is None:
        raise InputError(f"tip = {spec!r} is not one of: {valid}")
    try:
        theta = float(m.group(1))
    except ValueError:
        raise InputError(f"tip = {spec!r}: the cone half-angle must be a number of degrees, "
                         f"as in cone:60") from None
    theta = check_real(f"tip cone half-angle (tip = {spec!r})", theta, low=ANGLE_RANGE[0],
                       high=ANGLE_RANGE[1], unit="deg")
    if theta in _TABULATED:
        return _TABULATED[theta]
    return SharpTip(f"cone:{theta:g}", theta, float(representative_strain(theta)), None,
                    C_STAR_CONE)


def _direct_curvature(tip: SharpTip, E, E_star, sigma_y, n):
    s = representative_stress(E, sigma_y, n, tip.eps_r)
    x = np.log(E_star / s)
    ok = (x >= tip.x_range[0]) & (x <= tip.x_range[1])
    return s * dao_pi1(x, tip.pi1), ok


def loading_curvature(tip, E, E_star, sigma_y, n):
    """Kick's-law curvature C = P/h^2 of a material under ``tip``, Pa, and a validity mask.

    C = sigma_r Pi1_theta(ln(E*/sigma_r)), sigma_r at the tip's eps_r (Chollacoop et al. 2003).
    Between tabulated angles theta_a < theta < theta_b (50, 60, 70.3, 80 deg), ln C is
    interpolated linearly in ln tan(theta) at fixed material [D]: predicting the 60 deg FE
    cases from 50 and 70.3 deg this way errs by 1.7 % (median), the 70.3 deg cases from 60 and
    80 deg by 4 %, against 34 % and 69 % for interpolating Pi1 at fixed x. ``ok`` is False
    where x leaves the Pi1 range of a tip used.

    Parameters
    ----------
    tip : str or SharpTip
    E : array_like
        Young's modulus of the sample, Pa.
    E_star : array_like
        Reduced modulus, Pa.
    sigma_y : array_like
        Yield strength, Pa.
    n : array_like
        Hardening exponent.
    """
    tip = sharp_tip(tip)
    tip._require_calibration()
    if not tip.interpolated:
        return _direct_curvature(tip, E, E_star, sigma_y, n)
    ta, tb = _neighbours(tip.theta)
    Ca, oka = _direct_curvature(_TABULATED[ta], E, E_star, sigma_y, n)
    Cb, okb = _direct_curvature(_TABULATED[tb], E, E_star, sigma_y, n)
    lt = np.log(np.tan(np.radians([ta, tip.theta, tb])))
    w = (lt[2] - lt[1]) / (lt[2] - lt[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        C = np.exp(w * np.log(Ca) + (1.0 - w) * np.log(Cb))
    return C, oka & okb


def _neighbours(theta) -> tuple[float, float]:
    """The tabulated angles bracketing theta (50 <= theta <= 80 deg)."""
    angles = list(_TABULATED)
    hi = min(max(int(np.searchsorted(angles, theta)), 1), len(angles) - 1)
    return angles[hi - 1], angles[hi]


def _interpolation_note(tip: SharpTip) -> tuple[str, ...]:
    if not tip.interpolated:
        return ()
    ta, tb = _neighbours(tip.theta)
    return (f"Pi1 for {tip.theta:g} deg is interpolated (ln C linear in ln tan theta) between "
            f"{ta:g} and {tb:g} deg: expect a few % in C",)


# --- validation helpers ---------------------------------------------------------------------

def _check_indenter(nu, E_i, nu_i):
    nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    E_i = check_real("E_i", E_i, low=0.0, high=math.inf, low_open=True, unit="Pa")
    nu_i = check_real("nu_i", nu_i, low=-1.0, high=0.5, low_open=True, high_open=True)
    return nu, E_i, nu_i


def _check_WpWt(name, value):
    return check_real(name, value, low=0.0, high=1.0, low_open=True, high_open=True)


def _check_std(name, value, unit=""):
    return check_real(name, value, low=0.0, high=math.inf, high_open=True, unit=unit)


def _check_int(name, value, low, high):
    x = check_real(name, value, low=low, high=high)
    if x != int(x):
        raise InputError(f"{name} = {value!r} must be an integer in [{low}, {high}]")
    return int(x)


def _indenter_compliance(E_i, nu_i):
    return (1.0 - nu_i**2) / E_i


def yield_strength(sigma_r, E, n, eps_r):
    """sigma_Y solving sigma_r = sigma_Y (1 + E eps_r / sigma_Y)^n, Pa (arrays broadcast).

    The right side rises with sigma_Y for n < 1, so the root is unique; it lies in
    [sigma_r (sigma_r / (sigma_r + E eps_r))^(n/(1-n)), sigma_r].
    """
    sigma_r, E, n, eps_r = np.broadcast_arrays(*(np.asarray(a, dtype=float)
                                                 for a in (sigma_r, E, n, eps_r)))
    out = sigma_r.copy()
    hard = n > 0
    if hard.any():
        s, e, k, er = sigma_r[hard], E[hard], n[hard], eps_r[hard]
        lo = np.log(s) + k / (1.0 - k) * np.log(s / (s + e * er))
        res = elementwise.find_root(
            lambda u, s_, e_, k_, er_: np.log(representative_stress(e_, np.exp(u), k_, er_))
            - np.log(s_), (lo, np.log(s)), args=(s, e, k, er))
        out[hard] = np.exp(res.x)
    return out


# --- forward ------------------------------------------------------------------------------

def _fmt_value(v, fmt=".6g"):
    return "nan" if v is None or not np.isfinite(v) else format(v, fmt)


def _summary_row(label, value, std, unit):
    return f"  {label:<12} {_fmt_value(value)} +- {_fmt_value(std, '.3g')} {unit}".rstrip()


def _plain(value):
    """JSON-able copy: floats (None for NaN), lists for arrays and tuples, dicts for results."""
    if is_dataclass(value):
        return {f.name: _plain(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if np.isfinite(value) else None
    return value


@dataclass(frozen=True)
class ForwardResult:
    """Indentation response predicted by the Dao functions; SI units."""

    tip: str                    #: tip name
    h_m: float                  #: maximum depth, m
    E_star: float               #: reduced modulus E*, Pa
    eps_r: float                #: representative plastic strain of the tip
    sigma_r: float              #: representative stress at eps_r, Pa
    C: float                    #: loading curvature P/h^2, Pa
    P_m: float                  #: maximum load C h_m^2, N
    dPdh: float                 #: initial unloading slope, N/m (NaN: tip without Pi2)
    A_m: float                  #: true projected contact area at h_m, m^2 (NaN: no Pi2)
    p_ave: float                #: mean pressure P_m/A_m, Pa (NaN: no Pi2)
    hr_hm: float                #: residual to maximum depth h_r/h_m (NaN: no Pi2)
    WpWt: float                 #: plastic to total work W_p/W_t (NaN: no Pi2)
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        return _plain(self)

    def summary(self) -> str:
        lines = [f"Sharp indentation, forward (Dao et al. 2001), tip {self.tip}, "
                 f"h_m = {self.h_m:.4g} m",
                 f"  E*              {_fmt_value(self.E_star)} Pa",
                 f"  sigma_r         {_fmt_value(self.sigma_r)} Pa (eps_r = {self.eps_r:.4g})",
                 f"  C = P/h^2       {_fmt_value(self.C)} Pa",
                 f"  P_m             {_fmt_value(self.P_m)} N",
                 f"  dP/dh           {_fmt_value(self.dPdh)} N/m",
                 f"  A_m             {_fmt_value(self.A_m)} m^2",
                 f"  p_ave           {_fmt_value(self.p_ave)} Pa",
                 f"  h_r/h_m         {_fmt_value(self.hr_hm, '.4f')}",
                 f"  W_p/W_t         {_fmt_value(self.WpWt, '.4f')}"]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def dao_forward(E, nu, sigma_y, n, h_m, *, tip="berkovich", E_i=E_I_DAO, nu_i=NU_I_DAO,
                c_star=None) -> ForwardResult:
    """Predict C, dP/dh, W_p/W_t and h_r/h_m of a power-law solid (Dao et al. 2001).

    Steps (physics.md section 10): E* from E, nu, E_i, nu_i; sigma_r at the tip's eps_r;
    C = sigma_r Pi1(x), x = ln(E*/sigma_r); dP/dh = E* h_m Pi2(x, n); A_m = (dP/dh / (c* E*))^2;
    p_ave = C h_m^2 / A_m; h_r/h_m = Pi4^-1(p_ave/E*); W_p/W_t = Pi5(h_r/h_m). Pi2, Pi4 and
    Pi5 hold for the 70.3 deg geometry only: other cones give C (and sigma_r) alone.

    Parameters
    ----------
    E : float
        Young's modulus of the sample, Pa.
    nu : float
        Poisson ratio of the sample.
    sigma_y : float
        Yield strength sigma_Y, Pa.
    n : float
        Hardening exponent, calibrated on [0, 0.5].
    h_m : float
        Maximum depth, m.
    tip : str or SharpTip
        See `sharp_tip`.
    E_i, nu_i : float
        Indenter modulus (Pa; ``math.inf`` for a rigid one) and Poisson ratio.
    c_star : float, optional
        Overrides the tip's c*.

    Raises
    ------
    InputError
        A parameter outside its valid range.
    ModelRangeError
        n > 0.5, E*/sigma_r outside the tip's Pi1 range, or p_ave/E* beyond Pi4.
    """
    E = check_real("E", E, low=0.0, high=MODULUS_MAX, low_open=True, unit="Pa")
    nu, E_i, nu_i = _check_indenter(nu, E_i, nu_i)
    sigma_y = check_real("sigma_y", sigma_y, low=0.0, high=E, low_open=True, unit="Pa")
    n = check_real("n", n, low=0.0, high=1.0, high_open=True)
    h_m = check_positive("h_m", h_m, "m")
    tip = sharp_tip(tip)
    if c_star is not None:
        c_star = check_positive("c_star", c_star)
    if n > N_RANGE[1]:
        raise ModelRangeError(f"n = {n:g} exceeds {N_RANGE[1]:g}, the largest hardening "
                              "exponent of the Dao/Chollacoop FE calibration")
    tip._require_calibration()
    E_star = 1.0 / ((1.0 - nu**2) / E + _indenter_compliance(E_i, nu_i))
    sigma_r = float(representative_stress(E, sigma_y, n, tip.eps_r))
    C, ok = loading_curvature(tip, E, E_star, sigma_y, n)
    if not ok:
        raise ModelRangeError(f"E*/sigma_r = {E_star / sigma_r:.4g} is outside the range where "
                              f"the Pi1 of tip {tip.name} holds")
    C = float(C)
    warnings = list(_interpolation_note(tip))
    nan = math.nan
    dPdh = A_m = p_ave = hr_hm = WpWt = nan
    if tip.dao_functions:
        cs = c_star if c_star is not None else tip.c_star
        x = math.log(E_star / sigma_r)
        dPdh = float(E_star * h_m * dao_pi2(x, n))
        A_m = (dPdh / (cs * E_star)) ** 2
        p_ave = C * h_m**2 / A_m
        if not 0.0 < p_ave / E_star < float(dao_pi4(0.0)):
            raise ModelRangeError(f"p_ave/E* = {p_ave / E_star:.4g} is outside (0, "
                                  f"{float(dao_pi4(0.0)):.4g}), the range of Pi4")
        hr_hm = float(_pi4_inverse(p_ave / E_star))
        WpWt = float(dao_pi5(hr_hm))
        warnings += _hr_warning(hr_hm)
    else:
        warnings.append(f"Pi2, Pi4 and Pi5 are calibrated for the 70.3 deg geometry only: "
                        f"dP/dh, A_m, p_ave, h_r/h_m and W_p/W_t are not given for {tip.name}")
    return ForwardResult(tip=tip.name, h_m=h_m, E_star=E_star, eps_r=tip.eps_r, sigma_r=sigma_r,
                         C=C, P_m=C * h_m**2, dPdh=dPdh, A_m=A_m, p_ave=p_ave, hr_hm=hr_hm,
                         WpWt=WpWt, warnings=tuple(warnings))


def _hr_warning(hr_hm) -> list[str]:
    lo, hi = HR_HM_VERIFIED
    if np.isfinite(hr_hm) and not lo <= hr_hm <= hi:
        return [f"h_r/h_m = {hr_hm:.4f} is outside {lo:g}-{hi:g}, where Pi4 was verified"]
    return []


# --- reverse: vectorised cores ---------------------------------------------------------------

#: reasons a reverse evaluation fails, by code (0: fine)
_REASONS = {
    1: "W_p/W_t = {W:.4g} is outside ({lo:.4f}, {hi:.4f}), the range of Pi5",
    2: ("C/E* = {CE:.4g} is outside ({celo:.4g}, {cehi:.4g}): Pi1 has no root with "
        "{rlo:.4g} < E*/sigma_r < {rhi:.4g}, the range where the tip's Pi1 is monotone"),
    3: ("E* = {Es:.4g} Pa is at or above the indenter's plane-strain modulus: no sample "
        "modulus E exists for E_i, nu_i"),
    4: "a non-positive input or a W_p/W_t outside (0, 1)",
    6: ("the surrogate's prediction is not finite or has sigma_r >= E*: the inputs lie far "
        "outside its FE cases"),
}


def _solve_n(x, target):
    """n on [0, 0.5] with Pi2(x, n) = target; flag 0 root, 1 at 0, 2 at 0.5 (no root)."""
    g = dao_pi2(x[:, None], _N_GRID[None, :]) - target[:, None]
    cross = g[:, :-1] * g[:, 1:] <= 0
    has = cross.any(axis=1)
    multi = (g[:, :-1] * g[:, 1:] < 0).sum(axis=1) > 1
    n = np.where(np.abs(g[:, 0]) <= np.abs(g[:, -1]), N_RANGE[0], N_RANGE[1])
    flag = np.where(n == N_RANGE[0], 1, 2)
    if has.any():
        i = np.argmax(cross[has], axis=1)
        res = elementwise.find_root(lambda k, xx, t: dao_pi2(xx, k) - t,
                                    (_N_GRID[i], _N_GRID[i + 1]), args=(x[has], target[has]))
        n[has] = res.x
        flag[has] = 0
    return n, flag, multi


def _n_sensitivity(x, n):
    """Change of n for a 1 % change of dP/dh: the larger of the local 0.01 Pi2 / |dPi2/dn| and
    the mean 0.01 Pi2 * 0.5 / (span of Pi2 over n in [0, 0.5]) (Pi2 can be nearly flat in n
    overall yet locally steep where it is not monotone, E*/sigma < 25)."""
    h = 1e-4
    p = dao_pi2(x, n)
    slope = np.abs(dao_pi2(x, n + h) - dao_pi2(x, n - h)) / (2 * h)
    grid = dao_pi2(np.asarray(x)[..., None], _N_GRID)
    span = grid.max(axis=-1) - grid.min(axis=-1)
    with np.errstate(divide="ignore"):
        return 0.01 * np.abs(p) * np.maximum(1.0 / slope, (N_RANGE[1] - N_RANGE[0]) / span)


def _pi1_x(CE, tip: SharpTip):
    """x = ln(E*/sigma_r) solving Pi1(x) e^(-x) = C/E* in the tip's range; NaN where none."""
    lo, hi = tip.x_range
    f_lo = dao_pi1(lo, tip.pi1) * math.exp(-lo)
    f_hi = dao_pi1(hi, tip.pi1) * math.exp(-hi)
    ok = (CE < f_lo) & (CE > f_hi)
    x = np.full(CE.shape, np.nan)
    if ok.any():
        res = elementwise.find_root(lambda u, ce: dao_pi1(u, tip.pi1) * np.exp(-u) - ce,
                                    (lo, hi), args=(CE[ok],))
        x[ok] = res.x
    return x


def _closed_form_core(C, S, W, hm, c_star, tip: SharpTip, model=None):
    """Dao's reverse steps on arrays: E*, x, h_r/h_m, failure code, fallback mask."""
    reason = np.zeros(C.shape, dtype=int)
    hr = _pi5_inverse(W)
    reason[~np.isfinite(hr)] = 1
    with np.errstate(invalid="ignore", divide="ignore"):
        sqrt_A = c_star * C * hm**2 / (dao_pi4(hr) * S)
        E_star = S / (c_star * sqrt_A)
        x = _pi1_x(C / E_star, tip)
    reason[(reason == 0) & ~np.isfinite(x)] = 2
    return E_star, x, hr, reason, np.zeros(C.shape, dtype=bool)


def _surrogate_core(C, S, W, hm, c_star, tip: SharpTip, model=None):
    """The surrogate's E*; x from Dao's Pi1, or from the fallback regression of ln(sigma/C)
    where C/E* has no Pi1 root (flagged); h_r/h_m from Pi5 where it reaches."""
    model = _surrogate() if model is None else model
    pred = model.predict(_features(C, S, W, hm, c_star))
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        E_star = np.exp(pred[:, 0]) * S / (hm * c_star)
        x = _pi1_x(C / E_star, tip)
        fallback = ~np.isfinite(x)
        x[fallback] = np.log(E_star[fallback] / (C[fallback] * np.exp(pred[fallback, 1])))
    # sigma_r at or above E* is no material: refuse rather than extrapolate that far
    reason = np.where(np.isfinite(E_star) & (E_star > 0) & np.isfinite(x) & (x > 0), 0, 6)
    return E_star, x, _pi5_inverse(W), reason, fallback


def _reverse_arrays(C, S, W, hm, *, tip, c_star, nu, E_i, nu_i, method, model=None):
    """Full single-tip reverse on 1-D arrays; NaN and a code where a case fails.

    ``model``: a trained surrogate other than the deployed one (cross-validation).
    """
    C, S, W, hm = (np.atleast_1d(np.asarray(a, dtype=float)) for a in (C, S, W, hm))
    C, S, W, hm = np.broadcast_arrays(C, S, W, hm)
    bad = (C <= 0) | (S <= 0) | (hm <= 0) | (W <= 0) | (W >= 1)
    safe = [np.where(bad, 1.0, a) for a in (C, S, hm)]
    Ws = np.where(bad, 0.5, W)
    core = _closed_form_core if method == "closed-form" else _surrogate_core
    E_star, x, hr, reason, fallback = core(safe[0], safe[1], Ws, safe[2], c_star, tip, model)
    with np.errstate(invalid="ignore", over="ignore"):
        sigma_r = E_star * np.exp(-x)
    reason[bad] = 4
    E = modulus_from_reduced(E_star, nu, _indenter_compliance(E_i, nu_i))
    reason[(reason == 0) & ~np.isfinite(E)] = 3
    good = reason == 0
    n = np.full(C.shape, np.nan)
    flag = np.zeros(C.shape, dtype=int)
    multi = np.zeros(C.shape, dtype=bool)
    sigma_y = np.full(C.shape, np.nan)
    if good.any():
        n[good], flag[good], multi[good] = _solve_n(x[good], S[good] / (E_star[good] * hm[good]))
        sigma_y[good] = yield_strength(sigma_r[good], E[good], n[good], tip.eps_r)
    raw = {"E_star_raw": E_star.copy()}     # unmasked, for the error messages
    with np.errstate(invalid="ignore", divide="ignore"):
        raw["CE"] = C / E_star
    out = {"E_star": E_star, "sigma_r": sigma_r, "n": n, "sigma_y": sigma_y, "E": E,
           "hr_hm": hr, "x": x}
    for v in out.values():
        v[~good] = np.nan
    out.update(raw, reason=reason, flag=flag, multi=multi, fallback=fallback)
    return out


def _raise_reason(out, i, *, W, tip):
    """ModelRangeError for the failure code of case i of a `_reverse_arrays` output."""
    code = int(out["reason"][i])
    lo, hi = WPWT_RANGE
    xlo, xhi = tip.x_range
    msg = _REASONS[code].format(W=W, lo=lo, hi=hi, CE=out["CE"][i], rlo=math.exp(xlo),
                                rhi=math.exp(xhi), celo=dao_pi1(xhi, tip.pi1) * math.exp(-xhi),
                                cehi=dao_pi1(xlo, tip.pi1) * math.exp(-xlo),
                                Es=out["E_star_raw"][i])
    if code == 2:
        msg += "; method='surrogate' extrapolates with a warning instead"
    raise ModelRangeError(f"reverse analysis ({tip.name}): {msg}")


# --- uncertainty ------------------------------------------------------------------------------

def _monte_carlo(evaluate, means, stds, samples, seed):
    """Evaluate on Gaussian draws of the inputs; returns (outputs of valid draws, dropped share).

    Common random numbers: one standard-normal matrix from ``seed`` scaled by each std, so the
    spread is exactly zero at zero std and linear in the std while the model is near linear.
    """
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((len(means), samples))
    draws = [m + s * zi for m, s, zi in zip(means, stds, z)]
    out = evaluate(*draws)
    good = out["reason"] == 0
    return {k: v[good] for k, v in out.items()}, 1.0 - good.mean()


def _spread(values):
    return float(np.std(values, ddof=1)) if values.size > 1 else math.nan


# --- reverse: public --------------------------------------------------------------------------

@dataclass(frozen=True)
class ReverseResult:
    """Properties recovered from one sharp indentation; SI units, ``*_std`` = 1 standard deviation.

    The point values come from the mean inputs; the standard deviations from Monte Carlo over
    the input standard deviations (``samples`` draws) or, for `dao_reverse_repeated`, from the
    scatter of the per-indent results (``samples`` = number of indents).
    """

    E_star: float               #: reduced modulus E*, Pa
    E_star_std: float           #: Pa
    sigma_r: float              #: representative stress at eps_r, Pa
    sigma_r_std: float          #: Pa
    eps_r: float                #: representative plastic strain of the tip
    n: float                    #: strain-hardening exponent, in [0, 0.5]
    n_std: float
    sigma_y: float              #: yield strength sigma_Y, Pa
    sigma_y_std: float          #: Pa
    E: float                    #: Young's modulus of the sample from E*, nu, E_i, nu_i, Pa
    E_std: float                #: Pa
    hr_hm: float                #: h_r/h_m from Pi5^-1 (NaN where W_p/W_t is beyond Pi5)
    tip: str
    method: str                 #: "closed-form" or "surrogate"
    samples: int                #: Monte Carlo draws, indents, or 0 (no uncertainty given)
    seed: int | None            #: Monte Carlo seed (None when not sampled)
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        return _plain(self)

    def summary(self) -> str:
        lines = [f"Sharp-indentation reverse analysis ({self.method}), tip {self.tip}"
                 + (f", {self.samples} samples" if self.samples else ""),
                 _summary_row("E*", self.E_star, self.E_star_std, "Pa"),
                 _summary_row("E", self.E, self.E_std, "Pa"),
                 _summary_row(f"sigma_{self.eps_r:g}", self.sigma_r, self.sigma_r_std, "Pa"),
                 _summary_row("n", self.n, self.n_std, ""),
                 _summary_row("sigma_y", self.sigma_y, self.sigma_y_std, "Pa"),
                 f"  h_r/h_m      {_fmt_value(self.hr_hm, '.4f')}"]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def _check_method(method):
    return check_choice("method", method, METHODS)


def _reverse_setup(tip, c_star, nu, E_i, nu_i, method):
    nu, E_i, nu_i = _check_indenter(nu, E_i, nu_i)
    method = _check_method(method)
    tip = sharp_tip(tip)
    if c_star is not None:
        c_star = check_positive("c_star", c_star)
    if not tip.dao_functions:
        raise ModelRangeError(f"reverse analysis needs Pi2, Pi4 and Pi5, calibrated only for "
                              f"berkovich and cone:70.3; tip {tip.name} can serve as the second "
                              "tip of dual_reverse")
    cs = c_star if c_star is not None else tip.c_star
    return tip, cs, nu, E_i, nu_i, method


def _point_warnings(out, i, tip, method, *, C, S, W, hm, c_star, about_n=True) -> list[str]:
    """Identifiability warnings of case i of a `_reverse_arrays` output (``about_n``: include
    those on the single-tip n)."""
    w = []
    x = out["x"][i]
    ratio = math.exp(x)
    if method == "closed-form":
        w += _hr_warning(out["hr_hm"][i])
    else:
        if out["fallback"][i]:
            rlo, rhi = DAO_RATIO_RANGE
            w.append(f"C/E* has no root of Pi1 with {rlo:g} < E*/sigma_r < {rhi:g}: sigma_r "
                     f"comes from the surrogate's direct regression (E*/sigma_r = {ratio:.4g}), "
                     "an extrapolation")
        if not _surrogate().inside(_features(C, S, W, hm, c_star)[None, :]):
            w.append("the inputs lie outside the FE training cases of the surrogate "
                     "(ln(c* C h_m/(dP/dh)), W_p/W_t hull): it extrapolates")
    if not about_n:
        return w
    if out["flag"][i]:
        bound = N_RANGE[out["flag"][i] - 1]
        w.append(f"no root of Pi2 for n in [{N_RANGE[0]:g}, {N_RANGE[1]:g}]: n is set to the "
                 f"bound {bound:g}" + (" (no hardening resolved)" if bound == 0 else ""))
    if out["multi"][i]:
        w.append("Pi2 has several roots in n on [0, 0.5]: the smallest is reported")
    dn = float(_n_sensitivity(x, out["n"][i]))
    if dn > N_SENSITIVITY_LIMIT:
        w.append(f"n is ill-conditioned at E*/sigma_r = {ratio:.3g} (Dao et al. flag the region "
                 f"near E*/sigma = 20): a 1 % change in dP/dh moves n by {dn:.2g}")
    return w


def dao_reverse(C, dPdh, WpWt, h_m, *, tip="berkovich", nu=0.3, E_i=E_I_DAO, nu_i=NU_I_DAO,
                c_star=None, C_std=0.0, dPdh_std=0.0, WpWt_std=0.0, h_m_std=0.0,
                method="closed-form", samples=2000, seed=0) -> ReverseResult:
    """E*, sigma_r, n and sigma_Y from one sharp indentation (Dao et al. 2001).

    Closed form (physics.md section 10): h_r/h_m = Pi5^-1(W_p/W_t);
    A_m = (c* P_m / (Pi4 dP/dh))^2 with P_m = C h_m^2; E* = dP/dh / (c* sqrt(A_m));
    sigma_0.033 from C/sigma = Pi1(ln(E*/sigma)); n from Pi2(x, n) = dP/dh / (E* h_m) on
    [0, 0.5] (no root: the nearer bound, n = 0 wherever the data ask for less than no
    hardening); sigma_Y from sigma_0.033 = sigma_Y (1 + E 0.033/sigma_Y)^n.
    Surrogate: E* from the polynomial fitted to the packaged FE cases (`cross_validate`), then
    sigma_0.033, n and sigma_Y as above (sigma_0.033 from a direct regression, with a warning,
    where C/E* has no Pi1 root).

    Parameters
    ----------
    C : float
        Loading curvature P/h^2, Pa.
    dPdh : float
        Initial unloading slope dP/dh, N/m.
    WpWt : float
        Plastic to total work W_p/W_t, in (0, 1).
    h_m : float
        Maximum depth, m.
    tip : str or SharpTip
        "berkovich" or "cone:70.3" (the geometries of Pi2, Pi4, Pi5).
    nu : float
        Poisson ratio of the sample (only for E from E*).
    E_i, nu_i : float
        Indenter modulus (Pa; ``math.inf``: rigid) and Poisson ratio.
    c_star : float, optional
        Overrides the tip's c*.
    C_std, dPdh_std, WpWt_std, h_m_std : float
        Standard deviations of the inputs (Pa, N/m, -, m), taken as independent Gaussians.
    method : {"closed-form", "surrogate"}
    samples : int
        Monte Carlo draws when any std is non-zero.
    seed : int
        Seed of the draws (fixed default: reproducible results).

    Raises
    ------
    InputError
        A parameter outside its valid range.
    ModelRangeError
        Closed form: W_p/W_t beyond Pi5, or E*/sigma_0.033 outside (3.85, 804); either
        method: a tip other than berkovich and cone:70.3, or E* above the indenter's share.
    """
    C = check_positive("C", C, "Pa")
    S = check_positive("dPdh", dPdh, "N/m")
    W = _check_WpWt("WpWt", WpWt)
    hm = check_positive("h_m", h_m, "m")
    stds = (_check_std("C_std", C_std, "Pa"), _check_std("dPdh_std", dPdh_std, "N/m"),
            _check_std("WpWt_std", WpWt_std), _check_std("h_m_std", h_m_std, "m"))
    samples = _check_int("samples", samples, 2, 10**7)
    seed = _check_int("seed", seed, 0, 2**63 - 1)
    tip, cs, nu, E_i, nu_i, method = _reverse_setup(tip, c_star, nu, E_i, nu_i, method)

    def evaluate(c, s, w, h):
        return _reverse_arrays(c, s, w, h, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                               method=method)

    point = evaluate(C, S, W, hm)
    if point["reason"][0]:
        _raise_reason(point, 0, W=W, tip=tip)
    warnings = _point_warnings(point, 0, tip, method, C=C, S=S, W=W, hm=hm, c_star=cs)
    keys = ("E_star", "sigma_r", "n", "sigma_y", "E")
    std = dict.fromkeys(keys, 0.0)
    used, used_seed = 0, None
    if any(stds):
        draws, dropped = _monte_carlo(evaluate, (C, S, W, hm), stds, samples, seed)
        std = {k: _spread(draws[k]) for k in keys}
        used, used_seed = int(draws["E_star"].size), seed
        if dropped > 0:
            warnings.append(f"{dropped:.1%} of the Monte Carlo draws fell outside the model "
                            "range and were dropped: the standard deviations understate it")
        if std["n"] > N_STD_LIMIT:
            warnings.append(f"n is poorly determined: its standard deviation is {std['n']:.2g}")
    return ReverseResult(
        E_star=float(point["E_star"][0]), E_star_std=std["E_star"],
        sigma_r=float(point["sigma_r"][0]), sigma_r_std=std["sigma_r"], eps_r=tip.eps_r,
        n=float(point["n"][0]), n_std=std["n"], sigma_y=float(point["sigma_y"][0]),
        sigma_y_std=std["sigma_y"], E=float(point["E"][0]), E_std=std["E"],
        hr_hm=float(point["hr_hm"][0]), tip=tip.name, method=method, samples=used,
        seed=used_seed, warnings=tuple(warnings))


def _check_repeats(name, values, *, low=0.0, high=math.inf, high_open=False):
    if isinstance(values, (str, bool)):
        raise InputError(f"{name} must be numbers, got {values!r}")
    try:
        arr = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError):
        raise InputError(f"{name} must be numbers, got {values!r}") from None
    if arr.ndim != 1:
        raise InputError(f"{name} must be a 1-D array of repeats, got shape {arr.shape}")
    bad = ~np.isfinite(arr) | (arr <= low) | ((arr >= high) if high_open else (arr > high))
    if bad.any():
        rb = ")" if high_open else "]"
        raise InputError(f"{name} contains {arr[bad][0]:.6g}: every value must be finite and "
                         f"in ({low:g}, {high:g}{rb}")
    return arr


def dao_reverse_repeated(C, dPdh, WpWt, h_m, *, tip="berkovich", nu=0.3, E_i=E_I_DAO,
                         nu_i=NU_I_DAO, c_star=None, method="closed-form") -> ReverseResult:
    """Reverse analysis of repeated indents: each indent reversed, then mean and scatter.

    Reversing each indent keeps the correlation of C, dP/dh and W_p/W_t within an indent (a
    stiffer spot raises several of them at once), which independent input scatter would lose,
    and follows the model's non-linearity. The values are the means over indents; ``*_std``
    the sample standard deviation (ddof = 1) across indents, i.e. the indent-to-indent scatter
    (divide by sqrt(samples) for the standard error of the mean).

    Parameters
    ----------
    C, dPdh, WpWt : array_like
        One value per indent: Pa, N/m, and a ratio in (0, 1).
    h_m : float or array_like
        Maximum depth of each indent (or one for all), m.
    tip, nu, E_i, nu_i, c_star, method
        As in `dao_reverse`.

    Raises
    ------
    InputError
        Fewer than two indents, mismatched lengths or a value out of range.
    ModelRangeError
        An indent outside the model's range (the message gives its index).
    """
    C = _check_repeats("C", C)
    S = _check_repeats("dPdh", dPdh)
    W = _check_repeats("WpWt", WpWt, high=1.0, high_open=True)
    hm = _check_repeats("h_m", h_m)
    if hm.size == 1:
        hm = np.full(C.shape, hm[0])
    if not C.size == S.size == W.size == hm.size:
        raise InputError(f"C, dPdh, WpWt and h_m must have one value per indent, got lengths "
                         f"{C.size}, {S.size}, {W.size}, {hm.size}")
    if C.size < 2:
        raise InputError(f"repeated indents need at least 2 indents, got {C.size}")
    tip, cs, nu, E_i, nu_i, method = _reverse_setup(tip, c_star, nu, E_i, nu_i, method)
    out = _reverse_arrays(C, S, W, hm, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                          method=method)
    warnings = []
    for i in range(C.size):
        if out["reason"][i]:
            try:
                _raise_reason(out, i, W=W[i], tip=tip)
            except ModelRangeError as err:
                raise ModelRangeError(f"indent {i}: {err}") from None
        warnings += [f"indent {i}: {w}" for w in _point_warnings(out, i, tip, method, C=C[i],
                                                                  S=S[i], W=W[i], hm=hm[i],
                                                                  c_star=cs)]
    mean = {k: float(np.mean(out[k])) for k in ("E_star", "sigma_r", "n", "sigma_y", "E",
                                                  "hr_hm")}
    std = {k: _spread(out[k]) for k in ("E_star", "sigma_r", "n", "sigma_y", "E")}
    if std["n"] > N_STD_LIMIT:
        warnings.append(f"n is poorly determined: its scatter across indents is {std['n']:.2g}")
    return ReverseResult(
        E_star=mean["E_star"], E_star_std=std["E_star"], sigma_r=mean["sigma_r"],
        sigma_r_std=std["sigma_r"], eps_r=tip.eps_r, n=mean["n"], n_std=std["n"],
        sigma_y=mean["sigma_y"], sigma_y_std=std["sigma_y"], E=mean["E"], E_std=std["E"],
        hr_hm=mean["hr_hm"], tip=tip.name, method=method, samples=int(C.size), seed=None,
        warnings=tuple(warnings))


# --- dual indenter --------------------------------------------------------------------------

@dataclass(frozen=True)
class DualResult:
    """Properties from two sharp tips (Chollacoop, Dao & Suresh 2003); SI, ``*_std`` = 1 s.d."""

    E_star: float               #: reduced modulus from the first tip, Pa
    E_star_std: float           #: Pa
    sigma_r: float              #: representative stress at the first tip's eps_r, Pa
    sigma_r_std: float          #: Pa
    eps_r: float                #: first tip's representative strain
    sigma_r2: float             #: stress of the fitted law at the second tip's eps_r, Pa
    sigma_r2_std: float         #: Pa
    eps_r2: float               #: second tip's representative strain
    n: float                    #: strain-hardening exponent, in [0, 0.5]
    n_std: float
    sigma_y: float              #: yield strength, Pa
    sigma_y_std: float          #: Pa
    E: float                    #: Young's modulus of the sample, Pa
    E_std: float                #: Pa
    tip: str
    tip2: str
    method: str                 #: method of the first tip's reverse analysis
    samples: int                #: Monte Carlo draws used (0: no uncertainty given)
    seed: int | None
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        return _plain(self)

    def summary(self) -> str:
        lines = [f"Dual-indenter reverse analysis ({self.method}), tips {self.tip} + {self.tip2}"
                 + (f", {self.samples} samples" if self.samples else ""),
                 _summary_row("E*", self.E_star, self.E_star_std, "Pa"),
                 _summary_row("E", self.E, self.E_std, "Pa"),
                 _summary_row(f"sigma_{self.eps_r:.3g}", self.sigma_r, self.sigma_r_std, "Pa"),
                 _summary_row(f"sigma_{self.eps_r2:.3g}", self.sigma_r2, self.sigma_r2_std, "Pa"),
                 _summary_row("n", self.n, self.n_std, ""),
                 _summary_row("sigma_y", self.sigma_y, self.sigma_y_std, "Pa")]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def _dual_arrays(single, C2, tip, tip2):
    """n and sigma_Y matching the second tip's C2, given the first tip's results (arrays).

    n is searched on [0, 0.5]: for each n, sigma_Y follows from sigma_r of the first tip, and
    C2 predicted by the second tip's Pi1 must equal the measured one. This is the Chollacoop
    ratio equation solved in n instead of sigma_Y (same root for tabulated tips); it also
    serves interpolated angles. No root: the nearer bound; n = 0 when the stress at the larger
    strain is not larger (no hardening).
    """
    good = single["reason"] == 0
    E, Es, s1 = single["E"], single["E_star"], single["sigma_r"]
    N = C2.size
    n = np.full(N, np.nan)
    flag = np.zeros(N, dtype=int)
    reason = single["reason"].copy()

    def g_of(k, e, es, s, c2):
        sy = yield_strength(s, e, k, tip.eps_r)
        c, ok = loading_curvature(tip2, e, es, sy, k)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(ok, np.log(c / c2), np.nan)

    if good.any():
        idx = np.flatnonzero(good)
        args = (E[idx, None], Es[idx, None], s1[idx, None], C2[idx, None])
        kg = np.broadcast_to(_N_GRID, (idx.size, _N_GRID.size))
        g = g_of(kg, *(np.broadcast_to(a, kg.shape) for a in args))
        finite = np.isfinite(g)
        none = ~finite.any(axis=1)
        reason[idx[none]] = 5
        cross = g[:, :-1] * g[:, 1:] <= 0
        has = cross.any(axis=1) & ~none
        ends = np.where(np.isfinite(g[:, [0, -1]]), np.abs(g[:, [0, -1]]), np.inf)
        at_low = ends[:, 0] <= ends[:, 1]
        n[idx] = np.where(at_low, N_RANGE[0], N_RANGE[1])
        flag[idx] = np.where(at_low, 1, 2)
        if has.any():
            j = np.argmax(cross[has], axis=1)
            h = idx[has]
            res = elementwise.find_root(g_of, (_N_GRID[j], _N_GRID[j + 1]),
                                        args=(E[h], Es[h], s1[h], C2[h]))
            n[h] = res.x
            flag[h] = 0
    ok = reason == 0
    n[~ok] = np.nan
    sigma_y = np.full(N, np.nan)
    sigma_y[ok] = yield_strength(s1[ok], E[ok], n[ok], tip.eps_r)
    with np.errstate(invalid="ignore"):
        sigma_r2 = representative_stress(E, sigma_y, n, tip2.eps_r)
    out = {k: np.where(ok, v, np.nan) for k, v in single.items()
           if k in ("E_star", "sigma_r", "E")}
    out.update(n=n, sigma_y=sigma_y, sigma_r2=sigma_r2, flag=flag, reason=reason)
    return out


def dual_reverse(C, dPdh, WpWt, h_m, C2, *, tip2, tip="berkovich", nu=0.3, E_i=E_I_DAO,
                 nu_i=NU_I_DAO, c_star=None, C_std=0.0, dPdh_std=0.0, WpWt_std=0.0,
                 h_m_std=0.0, C2_std=0.0, method="closed-form", samples=2000,
                 seed=0) -> DualResult:
    """E*, sigma_Y and n from a Berkovich (or 70.3 deg cone) curve plus a second tip's C2.

    Chollacoop, Dao & Suresh (2003): E* and sigma_0.033 from the first tip (`dao_reverse`),
    sigma_r at the second tip's eps_r from its Pi1_theta, then sigma_Y and n from
    ln(sigma_0.033/sigma_Y) / ln(sigma_r/sigma_Y) = ln(1 + 0.033 E/sigma_Y) /
    ln(1 + eps_r E/sigma_Y) and n = ln(sigma_0.033/sigma_Y) / ln(1 + 0.033 E/sigma_Y)
    (solved in n, see `_dual_arrays`). The tips' strains must differ: 50 or 60 deg
    (eps_r = 0.083, 0.056) pair best with the Berkovich.

    Parameters
    ----------
    C, dPdh, WpWt, h_m
        First tip's curve, as in `dao_reverse` (Pa, N/m, -, m).
    C2 : float
        Loading curvature P/h^2 of the second tip, Pa.
    tip2 : str or SharpTip
        Second tip: "cone:THETA" with THETA in [50, 80] deg, or a user-calibrated `SharpTip`.
    tip, nu, E_i, nu_i, c_star, method, samples, seed
        As in `dao_reverse`.
    C_std, dPdh_std, WpWt_std, h_m_std, C2_std : float
        Standard deviations of the inputs (independent Gaussians), Pa, N/m, -, m, Pa.

    Raises
    ------
    InputError
        A parameter outside its valid range.
    ModelRangeError
        As `dao_reverse`; an uncalibrated second tip; a second tip with the first tip's eps_r;
        or C2 outside the second tip's Pi1 range for every n in [0, 0.5].
    """
    C = check_positive("C", C, "Pa")
    S = check_positive("dPdh", dPdh, "N/m")
    W = _check_WpWt("WpWt", WpWt)
    hm = check_positive("h_m", h_m, "m")
    C2 = check_positive("C2", C2, "Pa")
    stds = (_check_std("C_std", C_std, "Pa"), _check_std("dPdh_std", dPdh_std, "N/m"),
            _check_std("WpWt_std", WpWt_std), _check_std("h_m_std", h_m_std, "m"),
            _check_std("C2_std", C2_std, "Pa"))
    samples = _check_int("samples", samples, 2, 10**7)
    seed = _check_int("seed", seed, 0, 2**63 - 1)
    tip, cs, nu, E_i, nu_i, method = _reverse_setup(tip, c_star, nu, E_i, nu_i, method)
    tip2 = sharp_tip(tip2)
    tip2._require_calibration()
    if abs(tip2.eps_r - tip.eps_r) < 1e-3:
        raise ModelRangeError(f"tips {tip.name} and {tip2.name} share eps_r = {tip.eps_r:.3g}: "
                              "the dual method needs different representative strains")

    def evaluate(c, s, w, h, c2):
        single = _reverse_arrays(c, s, w, h, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                                 method=method)
        c2 = np.broadcast_to(np.atleast_1d(np.asarray(c2, dtype=float)), single["n"].shape)
        single["reason"] = np.where(c2 <= 0, 4, single["reason"])
        out = _dual_arrays({k: single[k] for k in ("E_star", "sigma_r", "E", "reason")},
                           np.where(c2 <= 0, 1.0, c2), tip, tip2)
        out["single"] = single
        return out

    point = evaluate(C, S, W, hm, C2)
    single = point.pop("single")
    code = int(point["reason"][0])
    if code == 5:
        raise ModelRangeError(f"dual reverse: C2 = {C2:.6g} Pa is outside the Pi1 range of tip "
                              f"{tip2.name} for every n in [0, 0.5]")
    if code:
        _raise_reason(single, 0, W=W, tip=tip)
    # the single-tip n is superseded by the dual one: only E* and sigma_r warnings apply
    warnings = _point_warnings(single, 0, tip, method, C=C, S=S, W=W, hm=hm, c_star=cs,
                               about_n=False)
    warnings += list(_interpolation_note(tip2))
    if point["flag"][0]:
        bound = N_RANGE[point["flag"][0] - 1]
        warnings.append(f"no n in [{N_RANGE[0]:g}, {N_RANGE[1]:g}] matches C2: n is set to "
                        f"{bound:g}" + (" (the stress at the larger strain is not larger: no "
                                        "hardening)" if bound == 0 else ""))
    keys = ("E_star", "sigma_r", "sigma_r2", "n", "sigma_y", "E")
    std = dict.fromkeys(keys, 0.0)
    used, used_seed = 0, None
    if any(stds):
        def evaluate_mc(*a):
            out = evaluate(*a)
            out.pop("single")
            return out
        draws, dropped = _monte_carlo(evaluate_mc, (C, S, W, hm, C2), stds, samples, seed)
        std = {k: _spread(draws[k]) for k in keys}
        used, used_seed = int(draws["n"].size), seed
        if dropped > 0:
            warnings.append(f"{dropped:.1%} of the Monte Carlo draws fell outside the model "
                            "range and were dropped: the standard deviations understate it")
        if std["n"] > N_STD_LIMIT:
            warnings.append(f"n is poorly determined: its standard deviation is {std['n']:.2g}")
    return DualResult(
        E_star=float(point["E_star"][0]), E_star_std=std["E_star"],
        sigma_r=float(point["sigma_r"][0]), sigma_r_std=std["sigma_r"], eps_r=tip.eps_r,
        sigma_r2=float(point["sigma_r2"][0]), sigma_r2_std=std["sigma_r2"], eps_r2=tip2.eps_r,
        n=float(point["n"][0]), n_std=std["n"], sigma_y=float(point["sigma_y"][0]),
        sigma_y_std=std["sigma_y"], E=float(point["E"][0]), E_std=std["E"], tip=tip.name,
        tip2=tip2.name, method=method, samples=used, seed=used_seed, warnings=tuple(warnings))


# --- packaged data ----------------------------------------------------------------------------

#: column names of the packaged CSVs -> (key, factor to SI)
_COLUMNS = {"Case": ("case", 1.0), "n": ("n", 1.0), "E (GPa)": ("E", 1e9),
            "sy (GPa)": ("sigma_y", 1e9), "C (GPa)": ("C", 1e9), "dP/dh (N/m)": ("dPdh", 1.0),
            "Wp/Wt": ("WpWt", 1.0), "E* (GPa)": ("E_star", 1e9), "hm (um)": ("h_m", 1e-6),
            "s0.033 (GPa)": ("sigma_0.033", 1e9), "s0.066 (GPa)": ("sigma_0.066", 1e9),
            "s0.1 (GPa)": ("sigma_0.1", 1e9)}
DATA_FILES = ("Berkovich.csv", "FEM_50deg.csv", "FEM_60deg.csv", "FEM_70deg.csv",
              "FEM_80deg.csv", "Al6061.csv")


@functools.cache
def _read_table(name: str) -> dict:
    path = resources.files("filmscale.continuum") / "data" / "dao2001" / name
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], [r for r in rows[1:] if r]
    cols = {}
    for j, title in enumerate(header):
        key, factor = _COLUMNS[title]
        cols[key] = np.array([float(r[j]) if r[j].strip() else np.nan for r in body]) * factor
        cols[key].flags.writeable = False
    return cols


def dao2001_table(name: str) -> dict[str, np.ndarray]:
    """Columns of a packaged ``data/dao2001`` file in SI (Pa, N/m, m); NaN for blanks.

    Keys: case, n, E, sigma_y, C, dPdh, WpWt (FE files); C, dPdh, WpWt, E_star, sigma_y, h_m,
    sigma_0.033, sigma_0.066, sigma_0.1, n (Al6061.csv). Data: Lu et al. (2020), Apache-2.0.
    """
    check_choice("data file", name, DATA_FILES)
    return {k: v.copy() for k, v in _read_table(name).items()}


#: FE files with C, dP/dh and W_p/W_t, their tip and c*
_FE_REVERSE_FILES = (("Berkovich.csv", "berkovich"), ("FEM_70deg.csv", "cone:70.3"))


@functools.cache
def _fe_cases() -> dict:
    """Pooled FE cases usable for the reverse analysis, with true E* and sigma_0.033."""
    parts = {k: [] for k in ("file", "case", "tip", "c_star", "n", "E", "sigma_y", "C", "dPdh",
                             "WpWt")}
    for name, tip in _FE_REVERSE_FILES:
        t = _read_table(name)
        m = t["C"].size
        parts["file"] += [name] * m
        parts["tip"] += [tip] * m
        parts["c_star"].append(np.full(m, sharp_tip(tip).c_star))
        for k in ("case", "n", "E", "sigma_y", "C", "dPdh", "WpWt"):
            parts[k].append(t[k])
    d = {k: (np.array(v) if k in ("file", "tip") else np.concatenate(v))
         for k, v in parts.items()}
    d["E_star"] = d["E"] / (1.0 - FE_NU**2)
    d["sigma_r"] = representative_stress(d["E"], d["sigma_y"], d["n"], EPS_R_DAO)
    d["h_m"] = np.full(d["C"].size, FE_DEPTH)
    # one group per material: the Berkovich cases repeat 70-deg materials and must be held out
    # together, or a fold would test on a material it trained on
    key = np.round(np.c_[d["n"], d["E"] / 1e9, d["sigma_y"] / 1e9], 4)
    _, d["group"] = np.unique(key, axis=0, return_inverse=True)
    d["group"] = d["group"].ravel()
    return d


# --- surrogate --------------------------------------------------------------------------------

def _features(C, S, W, hm, c_star):
    """Surrogate inputs: ln(c* C h_m / (dP/dh)) and W_p/W_t (c* takes out the tip's shape)."""
    C, S, W, hm = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (C, S, W, hm)))
    return np.stack([np.log(c_star * C * hm / S), W], axis=-1)


def _targets(E_star, sigma_r, C, S, hm, c_star):
    """ln(c* E* h_m / (dP/dh)) (= ln(h_m / sqrt(A_m))) and ln(sigma_0.033 / C)."""
    return np.stack([np.log(c_star * E_star * hm / S), np.log(sigma_r / C)], axis=-1)


def _design(Z, degree):
    return np.stack([Z[:, 0] ** i * Z[:, 1] ** j for i in range(degree + 1)
                     for j in range(degree + 1 - i)], axis=-1)


def _ridge_solve(XtX, Xty, ridge):
    """Ridge coefficients; the constant term (column 0) is not shrunk."""
    A = XtX + ridge * np.eye(XtX.shape[0])
    A[0, 0] -= ridge
    return np.linalg.solve(A, Xty)


@dataclass(frozen=True)
class _PolyRidge:
    """Ridge-regularised polynomial of total degree ``degree`` on standardised inputs."""

    mean: np.ndarray
    scale: np.ndarray
    degree: int
    ridge: float
    coef: np.ndarray

    @classmethod
    def fit(cls, F, y, degree, ridge):
        mean, scale = F.mean(axis=0), F.std(axis=0)
        X = _design((F - mean) / scale, degree)
        return cls(mean, scale, degree, ridge, _ridge_solve(X.T @ X, X.T @ y, ridge))

    def predict(self, F):
        return _design((F - self.mean) / self.scale, self.degree) @ self.coef


def _group_folds(groups, k, seed):
    """Fold index per case: whole groups shuffled by ``seed`` (int or int sequence), dealt
    round-robin."""
    rng = np.random.default_rng(seed)
    order = rng.permutation(np.unique(groups))
    fold_of = np.empty(order.max() + 1, dtype=int)
    fold_of[order] = np.arange(order.size) % k
    return fold_of[groups]


def _select(F, y, groups, seed):
    """(degree, ridge) minimising the median |relative error| of exp(y) in grouped 5-fold CV,
    averaged over SURROGATE_SELECTION_REPEATS splits (seeds [seed, r]) to steady the choice.

    Same fits as `_PolyRidge.fit`, sharing each fold's standardisation and normal equations
    across the grid.
    """
    grid = [(d, r) for d in SURROGATE_DEGREES for r in SURROGATE_RIDGES]
    score = np.zeros(len(grid))
    for rep in range(SURROGATE_SELECTION_REPEATS):
        folds = _group_folds(groups, SURROGATE_SELECTION_FOLDS, [seed, rep])
        pred = np.empty((len(grid), y.size))
        for f in range(SURROGATE_SELECTION_FOLDS):
            te = folds == f
            mean, scale = F[~te].mean(axis=0), F[~te].std(axis=0)
            Ztr, Zte = (F[~te] - mean) / scale, (F[te] - mean) / scale
            for degree in SURROGATE_DEGREES:
                Xtr, Xte = _design(Ztr, degree), _design(Zte, degree)
                XtX, Xty = Xtr.T @ Xtr, Xtr.T @ y[~te]
                for ridge in SURROGATE_RIDGES:
                    pred[grid.index((degree, ridge)), te] = Xte @ _ridge_solve(XtX, Xty, ridge)
        score += np.median(np.abs(np.expm1(pred - y)), axis=1)
    return grid[int(np.argmin(score))]


@dataclass(frozen=True)
class _Surrogate:
    models: tuple[_PolyRidge, _PolyRidge]   #: ln(c* E* h_m/(dP/dh)); fallback ln(sigma/C)
    hull: Delaunay                          #: training inputs, to flag extrapolation

    def predict(self, F):
        F = np.atleast_2d(F)
        return np.stack([m.predict(F) for m in self.models], axis=-1)

    def inside(self, F) -> bool:
        return bool(np.all(self.hull.find_simplex(np.atleast_2d(F)) >= 0))


def _train(F, Y, groups, seed, hyper=None) -> _Surrogate:
    """Fit on (F, Y); ``hyper`` = (degree, ridge) of the E* polynomial, else selected."""
    if hyper is None:
        hyper = _select(F, Y[:, 0], groups, seed)
    return _Surrogate((_PolyRidge.fit(F, Y[:, 0], *hyper),
                       _PolyRidge.fit(F, Y[:, 1], *SURROGATE_FALLBACK)), Delaunay(F))


def _fe_design():
    d = _fe_cases()
    F = _features(d["C"], d["dPdh"], d["WpWt"], d["h_m"], d["c_star"])
    Y = _targets(d["E_star"], d["sigma_r"], d["C"], d["dPdh"], d["h_m"], d["c_star"])
    return d, F, Y


@functools.cache
def _surrogate() -> _Surrogate:
    """The deployed surrogate: all FE cases, hyper-parameters by repeated grouped 5-fold CV."""
    d, F, Y = _fe_design()
    return _train(F, Y, d["group"], SURROGATE_SELECTION_SEED)


def surrogate_hyperparameters() -> dict:
    """Degree and ridge of the deployed surrogate's E* polynomial and of the fallback
    regression of sigma_0.033, and the number of training cases."""
    s = _surrogate()
    return {"E_star": {"degree": s.models[0].degree, "ridge": s.models[0].ridge},
            "sigma_r_fallback": {"degree": s.models[1].degree, "ridge": s.models[1].ridge},
            "cases": int(s.hull.points.shape[0])}


# --- cross-validation -------------------------------------------------------------------------

@dataclass(frozen=True)
class ErrorStats:
    """Median and 90th percentile of |error| over cases: relative for E*, sigma_r, sigma_y
    (fractions), absolute for n."""

    E_star_median: float
    E_star_p90: float
    sigma_r_median: float
    sigma_r_p90: float
    n_median: float
    n_p90: float
    sigma_y_median: float
    sigma_y_p90: float

    @classmethod
    def of(cls, E_star, sigma_r, n, sigma_y):
        def q(a, p):
            a = np.abs(a[np.isfinite(a)])
            return float(np.percentile(a, p)) if a.size else math.nan
        return cls(q(E_star, 50), q(E_star, 90), q(sigma_r, 50), q(sigma_r, 90), q(n, 50),
                   q(n, 90), q(sigma_y, 50), q(sigma_y, 90))


@dataclass(frozen=True)
class CrossValidation:
    """Held-out errors of the surrogate and the closed form on the same grouped folds.

    Per-case arrays hold signed errors: relative (estimate/true - 1) for E*, sigma_0.033 and
    sigma_Y, absolute (estimate - true) for n. The closed form has nothing to train, so its
    per-case errors do not depend on the folds; they are listed for a like-for-like comparison.
    """

    k: int
    seed: int
    selection: str              #: "nested" (honest) or "fixed" (deployed hyper-parameters)
    file: tuple[str, ...]       #: data file of each case
    case: np.ndarray            #: case number in its file
    fold: np.ndarray            #: test fold of each case
    closed_E_star: np.ndarray
    closed_sigma_r: np.ndarray
    closed_n: np.ndarray
    closed_sigma_y: np.ndarray
    surrogate_E_star: np.ndarray
    surrogate_sigma_r: np.ndarray
    surrogate_n: np.ndarray
    surrogate_sigma_y: np.ndarray
    hyperparameters: tuple      #: per fold: (degree, ridge) of the E* polynomial
    closed_form: ErrorStats
    surrogate: ErrorStats

    def to_dict(self) -> dict:
        return _plain(self)

    def summary(self) -> str:
        lines = [f"{self.k}-fold grouped cross-validation on {self.case.size} FE cases "
                 f"(seed {self.seed}, hyper-parameters: {self.selection})",
                 "  method        E* median  E* p90  sigma median  sigma p90  n median  n p90"]
        for label, s in (("closed form", self.closed_form), ("surrogate", self.surrogate)):
            lines.append(f"  {label:<12} {s.E_star_median:9.2%} {s.E_star_p90:7.2%} "
                         f"{s.sigma_r_median:12.2%} {s.sigma_r_p90:10.2%} {s.n_median:9.3f} "
                         f"{s.n_p90:6.3f}")
        return "\n".join(lines)


def _errors(out, d, sel=slice(None)):
    return {"E_star": out["E_star"] / d["E_star"][sel] - 1.0,
            "sigma_r": out["sigma_r"] / d["sigma_r"][sel] - 1.0,
            "n": out["n"] - d["n"][sel],
            "sigma_y": out["sigma_y"] / d["sigma_y"][sel] - 1.0}


def _fe_reverse(d, method, rows=None, model=None):
    """Reverse FE cases ``rows`` (all: None) with a rigid indenter, nu = 0.3, h_m = 0.2 um."""
    rows = np.arange(d["C"].size) if rows is None else rows
    out = {k: np.full(rows.size, np.nan) for k in ("E_star", "sigma_r", "n", "sigma_y")}
    for tip_name in np.unique(d["tip"][rows]):
        tip = sharp_tip(str(tip_name))
        sel = d["tip"][rows] == tip_name
        r_ = rows[sel]
        r = _reverse_arrays(d["C"][r_], d["dPdh"][r_], d["WpWt"][r_], d["h_m"][r_], tip=tip,
                            c_star=tip.c_star, nu=FE_NU, E_i=math.inf, nu_i=0.0, method=method,
                            model=model)
        for k in out:
            out[k][sel] = r[k]
    return out


def cross_validate(k: int = 5, seed: int = 0, selection: str = "nested") -> CrossValidation:
    """k-fold cross-validation of the surrogate against the closed form on the FE cases.

    The 114 cases of Berkovich.csv and FEM_70deg.csv (h_m = 0.2 um, nu = 0.3, rigid indenter)
    are split by material: the 14 Berkovich materials recur in the 70-deg file, and both cases
    of a material fall in the same fold. ``selection="nested"`` picks each fold's (degree,
    ridge) by an inner grouped 5-fold CV on that fold's training cases only (inner seed
    seeds ``[seed + 1 + fold, r]``): the held-out errors then include the cost of choosing.
    ``"fixed"``
    reuses the deployed surrogate's hyper-parameters, which were chosen on all cases, so it is
    optimistic.

    Parameters
    ----------
    k : int
        Number of folds, 2-50.
    seed : int
        Seed of the fold split.
    selection : {"nested", "fixed"}
    """
    k = _check_int("k", k, 2, 50)
    seed = _check_int("seed", seed, 0, 2**63 - 1)
    selection = check_choice("selection", selection, SELECTIONS)
    return _cross_validate(k, seed, selection)


@functools.cache
def _cross_validate(k, seed, selection) -> CrossValidation:
    d, F, Y = _fe_design()
    folds = _group_folds(d["group"], k, seed)
    closed = _errors(_fe_reverse(d, "closed-form"), d)
    sur = {key: np.full(d["C"].size, np.nan) for key in closed}
    deployed = _surrogate()
    hyper_all = []
    for f in range(k):
        te, tr = folds == f, folds != f
        if selection == "nested":
            hyper = _select(F[tr], Y[tr, 0], d["group"][tr], seed + 1 + f)
        else:
            hyper = (deployed.models[0].degree, deployed.models[0].ridge)
        hyper_all.append(hyper)
        model = _train(F[tr], Y[tr], d["group"][tr], seed, hyper)
        rows = np.flatnonzero(te)
        for key, v in _errors(_fe_reverse(d, "surrogate", rows, model), d, rows).items():
            sur[key][rows] = v
    for v in (*closed.values(), *sur.values()):
        v.flags.writeable = False
    return CrossValidation(
        k=k, seed=seed, selection=selection, file=tuple(d["file"].tolist()),
        case=d["case"].astype(int), fold=folds, closed_E_star=closed["E_star"],
        closed_sigma_r=closed["sigma_r"], closed_n=closed["n"],
        closed_sigma_y=closed["sigma_y"], surrogate_E_star=sur["E_star"],
        surrogate_sigma_r=sur["sigma_r"], surrogate_n=sur["n"], surrogate_sigma_y=sur["sigma_y"],
        hyperparameters=tuple(hyper_all),
        closed_form=ErrorStats.of(closed["E_star"], closed["sigma_r"], closed["n"],
                                  closed["sigma_y"]),
        surrogate=ErrorStats.of(sur["E_star"], sur["sigma_r"], sur["n"], sur["sigma_y"]))


# --- error table ------------------------------------------------------------------------------

def _row(file, tip, method, cases, **errors):
    """One table row: median and p90 of |error| per quantity (None where not measured)."""
    row = {"file": file, "tip": tip, "method": method, "cases": int(cases)}
    for q in ("C", "dPdh", "WpWt", "E_star", "sigma_r", "n", "sigma_y"):
        e = errors.get(q)
        if e is None:
            row[f"{q}_median"] = row[f"{q}_p90"] = None
            continue
        a = np.abs(np.asarray(e, dtype=float))
        a = a[np.isfinite(a)]
        row[f"{q}_median"] = float(np.median(a)) if a.size else None
        row[f"{q}_p90"] = float(np.percentile(a, 90)) if a.size else None
    return row


def _forward_errors(table, tip, h_m, nu, E_i, nu_i):
    """Relative errors of the forward C (and dP/dh, absolute W_p/W_t) against a data file."""
    tip = sharp_tip(tip)
    E, sy, n = table["E"], table["sigma_y"], table["n"]
    E_star = 1.0 / ((1.0 - nu**2) / E + _indenter_compliance(E_i, nu_i))
    C, ok = loading_curvature(tip, E, E_star, sy, n)
    out = {"C": np.where(ok, C / table["C"] - 1.0, np.nan)}
    if tip.dao_functions and "dPdh" in table:
        fwd = [dao_forward(e, nu, s, k, h, tip=tip, E_i=E_i, nu_i=nu_i)
               for e, s, k, h in zip(E, sy, n, np.broadcast_to(h_m, E.shape))]
        out["dPdh"] = np.array([f.dPdh for f in fwd]) / table["dPdh"] - 1.0
        if "WpWt" in table:
            out["WpWt"] = np.array([f.WpWt for f in fwd]) - table["WpWt"]
    return out


@functools.cache
def _fe_error_rows() -> tuple:
    d = _fe_cases()
    cv = _cross_validate(5, 0, "nested")
    rows = []
    for name, tip in _FE_REVERSE_FILES:
        sel = d["file"] == name
        fwd = _forward_errors(_read_table(name), tip, FE_DEPTH, FE_NU, math.inf, 0.0)
        rows.append(_row(name, tip, "closed-form", sel.sum(), **fwd,
                         E_star=cv.closed_E_star[sel], sigma_r=cv.closed_sigma_r[sel],
                         n=cv.closed_n[sel], sigma_y=cv.closed_sigma_y[sel]))
        rows.append(_row(name, tip, "surrogate (5-fold nested CV)", sel.sum(),
                         E_star=cv.surrogate_E_star[sel], sigma_r=cv.surrogate_sigma_r[sel],
                         n=cv.surrogate_n[sel], sigma_y=cv.surrogate_sigma_y[sel]))
    for name, tip in (("FEM_50deg.csv", "cone:50"), ("FEM_60deg.csv", "cone:60"),
                      ("FEM_80deg.csv", "cone:80")):
        t = _read_table(name)
        rows.append(_row(name, tip, "closed-form", t["C"].size,
                         **_forward_errors(t, tip, FE_DEPTH, FE_NU, math.inf, 0.0)))
    # dual indenter: 70.3 deg cone + a second cone on the same FE materials
    t70 = _read_table("FEM_70deg.csv")
    key70 = {tuple(np.round([a, b / 1e9, c / 1e9], 4)): i
             for i, (a, b, c) in enumerate(zip(t70["n"], t70["E"], t70["sigma_y"]))}
    tip1 = sharp_tip("cone:70.3")
    for name, tip2 in (("FEM_50deg.csv", "cone:50"), ("FEM_60deg.csv", "cone:60"),
                       ("FEM_80deg.csv", "cone:80")):
        t2 = _read_table(name)
        i70 = np.array([key70[tuple(np.round([a, b / 1e9, c / 1e9], 4))]
                        for a, b, c in zip(t2["n"], t2["E"], t2["sigma_y"])])
        single = _reverse_arrays(t70["C"][i70], t70["dPdh"][i70], t70["WpWt"][i70], FE_DEPTH,
                                 tip=tip1, c_star=tip1.c_star, nu=FE_NU, E_i=math.inf,
                                 nu_i=0.0, method="closed-form")
        dual = _dual_arrays(single, t2["C"], tip1, sharp_tip(tip2))
        rows.append(_row(f"FEM_70deg.csv + {name}", f"cone:70.3 + {tip2}", "closed-form dual",
                         i70.size, n=dual["n"] - t2["n"],
                         sigma_y=dual["sigma_y"] / t2["sigma_y"] - 1.0))
    al = _read_table("Al6061.csv")
    E_al, nu_al = 66.8e9, 0.33      # Al6061 README: these reproduce E* = 70.2 GPa
    al_fwd = {"C": [dao_forward(E_al, nu_al, s, k, h).C / c - 1.0
                    for s, k, h, c in zip(al["sigma_y"], al["n"], al["h_m"], al["C"])]}
    for method in METHODS:
        r = _reverse_arrays(al["C"], al["dPdh"], al["WpWt"], al["h_m"],
                            tip=sharp_tip("berkovich"), c_star=C_STAR_BERKOVICH, nu=nu_al,
                            E_i=E_I_DAO, nu_i=NU_I_DAO, method=method)
        rows.append(_row("Al6061.csv", "berkovich", method, al["C"].size,
                         **(al_fwd if method == "closed-form" else {}),
                         E_star=r["E_star"] / al["E_star"] - 1.0,
                         sigma_r=r["sigma_r"] / al["sigma_0.033"] - 1.0,
                         n=r["n"] - al["n"], sigma_y=r["sigma_y"] / al["sigma_y"] - 1.0))
    return tuple(rows)


def fe_error_table() -> list[dict]:
    """Accuracy of each route on the packaged data, one row per data file and method.

    Keys: file, tip, method, cases, and ``<q>_median``, ``<q>_p90`` of |error| for q in C,
    dPdh (forward, relative), WpWt (forward, absolute), E_star, sigma_r (sigma_0.033), sigma_y
    (reverse, relative) and n (absolute); None where not measured. FE cases: h_m = 0.2 um,
    nu = 0.3, rigid indenter. Surrogate rows are held-out errors of a 5-fold nested grouped CV
    (seed 0). Dual rows pair the 70.3 deg cone's closed-form E* and sigma_0.033 with the
    second cone's FE C. Al6061 rows: nu = 0.33, E_i = 1100 GPa, nu_i = 0.07.
    """
    return [dict(r) for r in _fe_error_rows()]
