"""The dimensionless functions of sharp indentation (Dao et al. 2001; Chollacoop, Dao & Suresh
2003) and their constants, docs/physics.md section 10 [C2].

A sharp tip loads a power-law hardening solid, sigma = E eps for sigma <= sigma_Y and
sigma = sigma_Y (1 + E eps_p / sigma_Y)^n, along Kick's law P = C h^2. Pi1 gives C from the
reduced modulus E* and the representative stress sigma_r at the tip's representative strain
eps_r; Pi2 the unloading slope dP/dh; Pi4 and Pi5 the mean pressure and the plastic work
ratio from the residual depth ratio h_r/h_m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from filmscale.continuum.indentation.tips import Cone, parse_tip
from filmscale.core.checks import check_real
from filmscale.core.errors import InputError, ModelRangeError

# --- constants of docs/physics.md section 10 -----------------------------------------------------

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
#: indenter of Dao's experiments (diamond); docs/physics.md section 9 quotes 1141 GPa too
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
#: grid of n on which the reverse analyses bracket their roots in n before refining them
N_SEARCH_GRID = np.linspace(N_RANGE[0], N_RANGE[1], 51)


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


def dao_pi4_inverse(p_over_E):
    """h_r/h_m from p_ave/E* (Pi4 inverted in closed form)."""
    return PI4_R0 - np.power(p_over_E / PI4_A, 1.0 / PI4_P)


def dao_pi5_inverse(WpWt):
    """h_r/h_m from W_p/W_t (Pi5 is increasing on [0, R0]); NaN outside WPWT_RANGE."""
    from scipy.optimize import elementwise
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


# --- tips and their calibration -------------------------------------------------------------

@dataclass(frozen=True)
class SharpCalibration:
    """A sharp tip resolved for the numeric code: its Pi1 calibration, c*, and whether Dao's
    Pi2, Pi4 and Pi5 apply. Built by `sharp_calibration` from a `Cone`.

    name: the tip's spec (``berkovich``, ``cone:60``); theta: half-angle of the (equivalent)
    cone, deg; eps_r, pi1, c_star: as on `Cone` (None: uncalibrated); x_range: interval of
    x = ln(E*/sigma_r) where Pi1 may be inverted (computed from pi1 when None);
    dao_functions: True for Berkovich and the 70.3 deg cone, the geometry of Pi2, Pi4, Pi5.
    """

    name: str
    theta: float
    eps_r: float | None = None
    pi1: tuple[float, float, float, float] | None = None
    c_star: float | None = None
    x_range: tuple[float, float] | None = None
    dao_functions: bool = False

    def __post_init__(self):
        if self.pi1 is not None and self.x_range is None:
            object.__setattr__(self, "x_range", _pi1_range(self.pi1))

    @property
    def interpolated(self) -> bool:
        """Pi1 interpolated between tabulated angles (no coefficients of its own)."""
        return self.pi1 is None and ANGLE_RANGE[0] <= self.theta <= ANGLE_RANGE[1]

    def require_calibration(self):
        """Raise ModelRangeError unless the tip has (or can interpolate) a Pi1 calibration."""
        if self.eps_r is None or (self.pi1 is None and not self.interpolated):
            raise ModelRangeError(
                f"tip {self.name} ({self.theta:g} deg) has no Pi1 calibration: the Chollacoop "
                f"functions hold for {ANGLE_RANGE[0]:g}-{ANGLE_RANGE[1]:g} deg; supply eps_r and "
                "pi1 (dataclasses.replace(tip, eps_r=..., pi1=(A, B, C, D)))")


def _tabulated_tips() -> dict[float, SharpCalibration]:
    tips = {BERKOVICH_ANGLE: SharpCalibration(f"cone:{BERKOVICH_ANGLE:g}", BERKOVICH_ANGLE,
                                              EPS_R_DAO, PI1_DAO, C_STAR_CONE,
                                              tuple(math.log(r) for r in DAO_RATIO_RANGE), True)}
    for theta, coeffs in PI1_THETA.items():
        tips[theta] = SharpCalibration(f"cone:{theta:g}", theta,
                                       float(representative_strain(theta)), coeffs, C_STAR_CONE)
    return dict(sorted(tips.items()))


_TABULATED = _tabulated_tips()
_SHARP_TIPS = "berkovich, cone:THETA (THETA in [50, 80] deg), cube-corner"


def sharp_tip(spec) -> Cone:
    """The `Cone` for ``spec``: "berkovich", "cone:THETA" (deg, 50-80) or "cube-corner".

    The tip of `parse_tip`, its calibration (eps_r, pi1, c_star) left None: the reverse
    analysis then uses the published one (`sharp_calibration`). "berkovich": c* = 1.2370,
    eps_r = 0.033, Dao's Pi1 (equivalent cone 70.3 deg). "cone:THETA": c* = 1.1957; 70.3 uses
    Dao's Pi1 and eps_r = 0.033; 50, 60 and 80 the Chollacoop Pi1_theta with eps_r(theta);
    other angles interpolate (`loading_curvature`). "cube-corner" (42.28 deg): uncalibrated,
    and using it raises `ModelRangeError` until the user supplies a calibration, e.g.
    ``dataclasses.replace(sharp_tip("cube-corner"), eps_r=..., pi1=(...))``. A `Cone` passes
    through.
    """
    if isinstance(spec, Cone):
        return spec
    if not isinstance(spec, str):
        raise InputError(f"tip = {spec!r} is not one of: {_SHARP_TIPS}")
    text = spec.strip().lower()
    text = {"cube_corner": "cube-corner", "cubecorner": "cube-corner"}.get(text, text)
    try:
        tip = parse_tip(text)
    except InputError:
        raise InputError(f"tip = {spec!r} is not one of: {_SHARP_TIPS}") from None
    if not isinstance(tip, Cone):
        raise InputError(f"tip = {spec!r} is not one of: {_SHARP_TIPS}")
    if tip.tip_radius > 0:
        raise InputError(f"tip = {spec!r} is a truncated cone: the reverse analysis takes a "
                         f"sharp tip, one of: {_SHARP_TIPS}")
    if tip.name == "cone":
        check_real(f"tip cone half-angle (tip = {spec!r})", tip.half_angle_deg,
                   low=ANGLE_RANGE[0], high=ANGLE_RANGE[1], unit="deg")
    return tip


def sharp_calibration(tip) -> SharpCalibration:
    """The calibration the reverse analysis uses for ``tip`` (text or `Cone`): the tip's own
    eps_r, pi1 and c_star where given, the published ones for its angle elsewhere.

    Raises
    ------
    InputError
        ``tip`` is not a sharp tip (`sharp_tip`).
    ModelRangeError
        A truncated cone (tip_radius > 0): the Dao functions hold for sharp tips.
    """
    if isinstance(tip, SharpCalibration):
        return tip
    cone = sharp_tip(tip)
    if cone.tip_radius > 0:
        raise ModelRangeError(f"tip {cone.spec} is truncated (tip_radius = {cone.tip_radius:g} "
                              "m): the Dao/Chollacoop functions hold for sharp tips only")
    theta = cone.half_angle_deg
    if cone.name == "berkovich":
        base = replace(_TABULATED[BERKOVICH_ANGLE], c_star=C_STAR_BERKOVICH)
    elif theta in _TABULATED:
        base = _TABULATED[theta]
    elif ANGLE_RANGE[0] <= theta <= ANGLE_RANGE[1]:
        base = SharpCalibration(cone.spec, theta, float(representative_strain(theta)), None,
                                C_STAR_CONE)
    else:
        base = SharpCalibration(cone.spec, theta)
    own = cone.pi1 is not None
    return replace(base, name=cone.spec, theta=theta,
                   eps_r=base.eps_r if cone.eps_r is None else cone.eps_r,
                   pi1=cone.pi1 if own else base.pi1, x_range=None if own else base.x_range,
                   c_star=base.c_star if cone.c_star is None else cone.c_star)


def _direct_curvature(tip: SharpCalibration, E, E_star, sigma_y, n):
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
    tip : str or Cone
        See `sharp_tip`; its calibration as in `sharp_calibration`.
    E : array_like
        Young's modulus of the sample, Pa.
    E_star : array_like
        Reduced modulus, Pa.
    sigma_y : array_like
        Yield strength, Pa.
    n : array_like
        Hardening exponent.
    """
    tip = sharp_calibration(tip)
    tip.require_calibration()
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


def interpolation_warnings(tip: SharpCalibration) -> tuple[str, ...]:
    """The warning that ``tip``'s Pi1 is interpolated between tabulated angles (or none)."""
    if not tip.interpolated:
        return ()
    ta, tb = _neighbours(tip.theta)
    return (f"Pi1 for {tip.theta:g} deg is interpolated (ln C linear in ln tan theta) between "
            f"{ta:g} and {tb:g} deg: expect a few % in C",)
