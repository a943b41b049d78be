"""Sharp-indentation forward and reverse analysis (Dao et al. 2001; Chollacoop, Dao & Suresh 2003).

A sharp tip loads a power-law hardening solid, sigma = E eps for sigma <= sigma_Y and
sigma = sigma_Y (1 + E eps_p / sigma_Y)^n, along Kick's law P = C h^2. Dao et al. (2001, Acta
Mater. 49, 3899) fitted dimensionless functions Pi1-Pi5 to finite-element (FE) cases so that the
loading curvature C, the initial unloading slope dP/dh and the plastic work ratio W_p/W_t give
the reduced modulus E*, the representative stress sigma_0.033 at eps_r = 0.033, the hardening
exponent n and the yield strength sigma_Y. Chollacoop, Dao & Suresh (2003, Acta Mater. 51,
3713) extended Pi1 to cones of half-angle 50-80 deg and paired two tips ("dual indenter") to
pin down n. Equations and coefficients: docs/physics.md section 10 [C2].

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

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.indentation.reverse.functions import (DAO_RATIO_RANGE, E_I_DAO,
                                                               HR_HM_VERIFIED, METHODS, N_RANGE,
                                                               N_SEARCH_GRID, N_SENSITIVITY_LIMIT,
                                                               N_STD_LIMIT, NU_I_DAO, WPWT_RANGE,
                                                               SharpCalibration, dao_pi1, dao_pi2,
                                                               dao_pi4, dao_pi4_inverse, dao_pi5,
                                                               dao_pi5_inverse,
                                                               interpolation_warnings,
                                                               loading_curvature,
                                                               representative_stress,
                                                               sharp_calibration)
from filmscale.continuum.indentation.reverse.surrogate import deployed_surrogate, surrogate_features
from filmscale.continuum.indentation.reverse.uncertainty import monte_carlo_draws, sample_std
from filmscale.continuum.materials import modulus_from_reduced
from filmscale.core.checks import MODULUS_MAX, check_choice, check_int, check_positive, check_real
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.jsonable import to_jsonable
from filmscale.core.quantities import eng

# --- validation helpers ---------------------------------------------------------------------

def _check_indenter(nu, E_i, nu_i):
    nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    E_i = check_real("E_i", E_i, low=0.0, high=math.inf, low_open=True, unit="Pa")
    nu_i = check_real("nu_i", nu_i, low=-1.0, high=0.5, low_open=True, high_open=True)
    return nu, E_i, nu_i


def check_work_ratio(name, value):
    """W_p/W_t (or another work ratio) checked to lie in (0, 1)."""
    return check_real(name, value, low=0.0, high=1.0, low_open=True, high_open=True)


def check_std(name, value, unit=""):
    """An input's standard deviation checked finite and >= 0."""
    return check_real(name, value, low=0.0, high=math.inf, high_open=True, unit=unit)


def indenter_compliance(E_i, nu_i):
    """(1 - nu_i^2) / E_i, 1/Pa: the indenter's share of 1/E* (0 for E_i = inf)."""
    return (1.0 - nu_i**2) / E_i


def yield_strength(sigma_r, E, n, eps_r):
    """sigma_Y solving sigma_r = sigma_Y (1 + E eps_r / sigma_Y)^n, Pa (arrays broadcast).

    The right side rises with sigma_Y for n < 1, so the root is unique; it lies in
    [sigma_r (sigma_r / (sigma_r + E eps_r))^(n/(1-n)), sigma_r].
    """
    from scipy.optimize import elementwise
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


def summary_row(label, value, std, unit):
    """One line of a result's ``summary()``: label, value +- std in engineering units."""
    if value is None or not np.isfinite(value):
        return f"  {label:<12} nan {unit}".rstrip()
    return f"  {label:<12} {eng(value, unit, std=math.nan if std is None else std)}"


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
        return to_jsonable(self)

    def summary(self) -> str:
        lines = [f"Sharp indentation, forward (Dao et al. 2001), tip {self.tip}, "
                 f"h_m = {eng(self.h_m, 'm')}",
                 f"  E*              {eng(self.E_star, 'Pa')}",
                 f"  sigma_r         {eng(self.sigma_r, 'Pa')} (eps_r = {self.eps_r:.4g})",
                 f"  C = P/h^2       {eng(self.C, 'Pa')}",
                 f"  P_m             {eng(self.P_m, 'N')}",
                 f"  dP/dh           {eng(self.dPdh, 'N/m')}",
                 f"  A_m             {self.A_m * 1e12:.4g} µm^2",
                 f"  p_ave           {eng(self.p_ave, 'Pa')}",
                 f"  h_r/h_m         {_fmt_value(self.hr_hm, '.4f')}",
                 f"  W_p/W_t         {_fmt_value(self.WpWt, '.4f')}"]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def dao_forward(E, nu, sigma_y, n, h_m, *, tip="berkovich", E_i=E_I_DAO, nu_i=NU_I_DAO,
                c_star=None) -> ForwardResult:
    """Predict C, dP/dh, W_p/W_t and h_r/h_m of a power-law solid (Dao et al. 2001).

    Steps (docs/physics.md section 10): E* from E, nu, E_i, nu_i; sigma_r at the tip's eps_r;
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
    tip : str or Cone
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
    tip = sharp_calibration(tip)
    if c_star is not None:
        c_star = check_positive("c_star", c_star)
    if n > N_RANGE[1]:
        raise ModelRangeError(f"n = {n:g} exceeds {N_RANGE[1]:g}, the largest hardening "
                              "exponent of the Dao/Chollacoop FE calibration")
    tip.require_calibration()
    E_star = 1.0 / ((1.0 - nu**2) / E + indenter_compliance(E_i, nu_i))
    sigma_r = float(representative_stress(E, sigma_y, n, tip.eps_r))
    C, ok = loading_curvature(tip, E, E_star, sigma_y, n)
    if not ok:
        raise ModelRangeError(f"E*/sigma_r = {E_star / sigma_r:.4g} is outside the range where "
                              f"the Pi1 of tip {tip.name} holds")
    C = float(C)
    warnings = list(interpolation_warnings(tip))
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
        hr_hm = float(dao_pi4_inverse(p_ave / E_star))
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
    from scipy.optimize import elementwise
    g = dao_pi2(x[:, None], N_SEARCH_GRID[None, :]) - target[:, None]
    cross = g[:, :-1] * g[:, 1:] <= 0
    has = cross.any(axis=1)
    multi = (g[:, :-1] * g[:, 1:] < 0).sum(axis=1) > 1
    n = np.where(np.abs(g[:, 0]) <= np.abs(g[:, -1]), N_RANGE[0], N_RANGE[1])
    flag = np.where(n == N_RANGE[0], 1, 2)
    if has.any():
        i = np.argmax(cross[has], axis=1)
        res = elementwise.find_root(lambda k, xx, t: dao_pi2(xx, k) - t,
                                    (N_SEARCH_GRID[i], N_SEARCH_GRID[i + 1]),
                                    args=(x[has], target[has]))
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
    grid = dao_pi2(np.asarray(x)[..., None], N_SEARCH_GRID)
    span = grid.max(axis=-1) - grid.min(axis=-1)
    with np.errstate(divide="ignore"):
        return 0.01 * np.abs(p) * np.maximum(1.0 / slope, (N_RANGE[1] - N_RANGE[0]) / span)


def _pi1_x(CE, tip: SharpCalibration):
    """x = ln(E*/sigma_r) solving Pi1(x) e^(-x) = C/E* in the tip's range; NaN where none."""
    from scipy.optimize import elementwise
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


def _closed_form_core(C, S, W, hm, c_star, tip: SharpCalibration, model=None):
    """Dao's reverse steps on arrays: E*, x, h_r/h_m, failure code, fallback mask."""
    reason = np.zeros(C.shape, dtype=int)
    hr = dao_pi5_inverse(W)
    reason[~np.isfinite(hr)] = 1
    with np.errstate(invalid="ignore", divide="ignore"):
        sqrt_A = c_star * C * hm**2 / (dao_pi4(hr) * S)
        E_star = S / (c_star * sqrt_A)
        x = _pi1_x(C / E_star, tip)
    reason[(reason == 0) & ~np.isfinite(x)] = 2
    return E_star, x, hr, reason, np.zeros(C.shape, dtype=bool)


def _surrogate_core(C, S, W, hm, c_star, tip: SharpCalibration, model=None):
    """The surrogate's E*; x from Dao's Pi1, or from the fallback regression of ln(sigma/C)
    where C/E* has no Pi1 root (flagged); h_r/h_m from Pi5 where it reaches."""
    model = deployed_surrogate() if model is None else model
    pred = model.predict(surrogate_features(C, S, W, hm, c_star))
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        E_star = np.exp(pred[:, 0]) * S / (hm * c_star)
        x = _pi1_x(C / E_star, tip)
        fallback = ~np.isfinite(x)
        x[fallback] = np.log(E_star[fallback] / (C[fallback] * np.exp(pred[fallback, 1])))
    # sigma_r at or above E* is no material: refuse rather than extrapolate that far
    reason = np.where(np.isfinite(E_star) & (E_star > 0) & np.isfinite(x) & (x > 0), 0, 6)
    return E_star, x, dao_pi5_inverse(W), reason, fallback


def reverse_arrays(C, S, W, hm, *, tip, c_star, nu, E_i, nu_i, method, model=None):
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
    E = modulus_from_reduced(E_star, nu, indenter_compliance(E_i, nu_i))
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


def raise_reverse_failure(out, i, *, W, tip):
    """ModelRangeError for the failure code of case i of a `reverse_arrays` output."""
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
        return to_jsonable(self)

    def summary(self) -> str:
        lines = [f"Sharp-indentation reverse analysis ({self.method}), tip {self.tip}"
                 + (f", {self.samples} samples" if self.samples else ""),
                 summary_row("E*", self.E_star, self.E_star_std, "Pa"),
                 summary_row("E", self.E, self.E_std, "Pa"),
                 summary_row(f"sigma_{self.eps_r:g}", self.sigma_r, self.sigma_r_std, "Pa"),
                 summary_row("n", self.n, self.n_std, ""),
                 summary_row("sigma_y", self.sigma_y, self.sigma_y_std, "Pa"),
                 f"  h_r/h_m      {_fmt_value(self.hr_hm, '.4f')}"]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def resolve_reverse_setup(tip, c_star, nu, E_i, nu_i, method):
    """The checked (tip calibration, c*, nu, E_i, nu_i, method) of a single-tip reverse
    analysis; a tip without Dao's Pi2, Pi4 and Pi5 is refused."""
    nu, E_i, nu_i = _check_indenter(nu, E_i, nu_i)
    method = check_choice("method", method, METHODS)
    tip = sharp_calibration(tip)
    if c_star is not None:
        c_star = check_positive("c_star", c_star)
    if not tip.dao_functions:
        raise ModelRangeError(f"reverse analysis needs Pi2, Pi4 and Pi5, calibrated only for "
                              f"berkovich and cone:70.3; tip {tip.name} can serve as the second "
                              "tip of dual_reverse")
    cs = c_star if c_star is not None else tip.c_star
    return tip, cs, nu, E_i, nu_i, method


def identifiability_warnings(out, i, tip, method, *, C, S, W, hm, c_star,
                             about_n=True) -> list[str]:
    """Identifiability warnings of case i of a `reverse_arrays` output (``about_n``: include
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
        if not deployed_surrogate().inside(surrogate_features(C, S, W, hm, c_star)[None, :]):
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

    Closed form (docs/physics.md section 10): h_r/h_m = Pi5^-1(W_p/W_t);
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
    tip : str or Cone
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
    W = check_work_ratio("WpWt", WpWt)
    hm = check_positive("h_m", h_m, "m")
    stds = (check_std("C_std", C_std, "Pa"), check_std("dPdh_std", dPdh_std, "N/m"),
            check_std("WpWt_std", WpWt_std), check_std("h_m_std", h_m_std, "m"))
    samples = check_int("samples", samples, 2, 10**7)
    seed = check_int("seed", seed, 0, 2**63 - 1)
    tip, cs, nu, E_i, nu_i, method = resolve_reverse_setup(tip, c_star, nu, E_i, nu_i, method)

    def evaluate(c, s, w, h):
        return reverse_arrays(c, s, w, h, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                              method=method)

    point = evaluate(C, S, W, hm)
    if point["reason"][0]:
        raise_reverse_failure(point, 0, W=W, tip=tip)
    warnings = identifiability_warnings(point, 0, tip, method, C=C, S=S, W=W, hm=hm, c_star=cs)
    keys = ("E_star", "sigma_r", "n", "sigma_y", "E")
    std = dict.fromkeys(keys, 0.0)
    used, used_seed = 0, None
    if any(stds):
        draws, dropped = monte_carlo_draws(evaluate, (C, S, W, hm), stds, samples, seed)
        std = {k: sample_std(draws[k]) for k in keys}
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
    tip, cs, nu, E_i, nu_i, method = resolve_reverse_setup(tip, c_star, nu, E_i, nu_i, method)
    out = reverse_arrays(C, S, W, hm, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                         method=method)
    warnings = []
    for i in range(C.size):
        if out["reason"][i]:
            try:
                raise_reverse_failure(out, i, W=W[i], tip=tip)
            except ModelRangeError as err:
                raise ModelRangeError(f"indent {i}: {err}") from None
        warnings += [f"indent {i}: {w}"
                     for w in identifiability_warnings(out, i, tip, method, C=C[i], S=S[i],
                                                       W=W[i], hm=hm[i], c_star=cs)]
    mean = {k: float(np.mean(out[k])) for k in ("E_star", "sigma_r", "n", "sigma_y", "E",
                                                  "hr_hm")}
    std = {k: sample_std(out[k]) for k in ("E_star", "sigma_r", "n", "sigma_y", "E")}
    if std["n"] > N_STD_LIMIT:
        warnings.append(f"n is poorly determined: its scatter across indents is {std['n']:.2g}")
    return ReverseResult(
        E_star=mean["E_star"], E_star_std=std["E_star"], sigma_r=mean["sigma_r"],
        sigma_r_std=std["sigma_r"], eps_r=tip.eps_r, n=mean["n"], n_std=std["n"],
        sigma_y=mean["sigma_y"], sigma_y_std=std["sigma_y"], E=mean["E"], E_std=std["E"],
        hr_hm=mean["hr_hm"], tip=tip.name, method=method, samples=int(C.size), seed=None,
        warnings=tuple(warnings))
