"""Sharp-tip calibration of a layer (Dao et al. 2001 reverse analysis) and the Nix-Gao size
effect of its yield strength over curves at several depths (Nix & Gao 1998)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.oliver_pharr import oliver_pharr, refuse_implausible
from filmscale.continuum.indentation.reverse import dao_reverse_repeated
from filmscale.continuum.indentation.reverse.dao import dao_forward, dao_reverse
from filmscale.continuum.indentation.reverse.functions import E_I_DAO, NU_I_DAO
from filmscale.continuum.indentation.size_effect import (NixGaoFit, admissible_h_star,
                                                         depth_trend, nix_gao_fit)
from filmscale.continuum.indentation.spherical import check_tip_shape, loading_points
from filmscale.core.errors import InputError

from .result import FITS_E, FITS_SIGMA_Y, IDENTIFIABLE_RSD, Calibration, Parameter


#: n is identified when its std is below N_STD_MAX and it lies strictly inside the range
#: Dao's functions were calibrated on (a value at a bound is where the root search stopped)
N_STD_MAX, N_RANGE = 0.1, (0.0, 0.5)


def sharp_inputs(curve: LoadDisplacementCurve, tip="berkovich"):
    """(C, C_std, dP/dh, W_p/W_t, h_m) of one sharp-tip curve: C by least squares of
    P = C h^2 over the loading with h >= h_m/2 (C_std its standard error), the rest from
    the Oliver-Pharr analysis of the unloading."""
    op = oliver_pharr(curve, tip)
    if not op.ok:
        raise InputError(f"curve {curve.meta.get('source', '')!r}: {op.message}")
    refuse_implausible(curve, op.flags)     # a unit slip, before the reverse analysis
    h, P = loading_points(curve)
    m = h >= 0.5 * op.h_max
    x = h[m]**2
    C = float(P[m] @ x / (x @ x))
    r = P[m] - C * x
    C_std = math.sqrt(float(r @ r) / max(m.sum() - 1, 1) / float(x @ x))
    return C, C_std, op.S, op.W_p / op.W_t, op.h_max


def calibrate_sharp(curves, *, nu: float, tip="berkovich", layer: str = "layer",
                    E_i: float = E_I_DAO, nu_i: float = NU_I_DAO, dPdh_rsd: float = 0.05,
                    WpWt_std: float = 0.01, samples: int = 2000, seed: int = 0) -> Calibration:
    """E, sigma_y and n from Berkovich (or 70.3 degree cone) curves by Dao's reverse
    analysis. One curve: Monte Carlo with C's own standard error, a relative error
    ``dPdh_rsd`` of the unloading slope and an absolute error ``WpWt_std`` of W_p/W_t
    (typical of Oliver-Pharr fits; state yours). Several curves: their scatter.
    ``E_i = math.inf`` for the rigid tips of MD and particle runs."""
    curves = [curves] if isinstance(curves, LoadDisplacementCurve) else list(curves)
    if not curves:
        raise InputError("calibrate_sharp needs at least one curve")
    for c in curves:
        check_tip_shape(c, "sharp")
    inputs = np.array([sharp_inputs(c, tip) for c in curves])
    C, C_std, S, W, hm = inputs.T
    if len(curves) == 1:
        r = dao_reverse(C[0], S[0], W[0], hm[0], tip=tip, nu=nu, E_i=E_i, nu_i=nu_i,
                        C_std=C_std[0], dPdh_std=dPdh_rsd * S[0], WpWt_std=WpWt_std,
                        samples=samples, seed=seed)
        how = (f"Monte Carlo ({samples} draws): C standard error, dP/dh +-{dPdh_rsd:.0%}, "
               f"W_p/W_t +-{WpWt_std:g}")
    else:
        r = dao_reverse_repeated(C, S, W, hm, tip=tip, nu=nu, E_i=E_i, nu_i=nu_i)
        how = f"scatter of {len(curves)} curves (1 standard deviation)"

    def param(value, std, unit):
        ok = math.isfinite(std) and std < IDENTIFIABLE_RSD * max(abs(value), 1e-300)
        return Parameter(float(value), float(std), unit, ok,
                         "" if ok else f"relative uncertainty above {IDENTIFIABLE_RSD:.0%}")

    n_ok, n_reason = True, ""
    if not (math.isfinite(r.n_std) and r.n_std < N_STD_MAX):
        n_ok, n_reason = False, f"standard deviation above {N_STD_MAX:g}"
    elif not N_RANGE[0] < r.n < N_RANGE[1]:
        n_ok, n_reason = False, (f"n = {r.n:.3g} at or beyond the bounds {N_RANGE} of Dao's "
                                 "functions")
    fitted, roles = [], []
    for c, h_m in zip(curves, hm):
        h, P = loading_points(c)
        C_model = dao_forward(r.E, nu, r.sigma_y, r.n, h_m, tip=tip, E_i=E_i, nu_i=nu_i).C
        fitted.append((h, P, float(C_model) * h**2))
        # C comes from the loading beyond h_m / 2 (`sharp_inputs`); with the unloading's
        # slope and work it sets E, sigma_y and n together
        roles.append(np.where(h >= 0.5 * h_m, FITS_E | FITS_SIGMA_Y, 0).astype(np.int8))
    return Calibration(
        layer=layer, route="sharp", E=param(r.E, r.E_std, "Pa"),
        sigma_y=param(r.sigma_y, r.sigma_y_std, "Pa"),
        n=Parameter(float(r.n), float(r.n_std), "", n_ok, n_reason),
        nu=nu, uncertainty=how, rms=math.nan, points=len(curves),
        sources=tuple(str(c.meta.get("source", f"curve {i}")) for i, c in enumerate(curves)),
        model=f"Dao et al. 2001 reverse analysis ({r.method}, {tip})", warnings=r.warnings,
        fitted_curves=tuple(fitted), fit_roles=tuple(roles))


@dataclass(frozen=True)
class StrengthPoint:
    """sigma_y from one sharp indent and the depth it belongs to (its maximum depth)."""

    source: str
    sigma_y: float         #: Pa
    rel_std: float         #: relative standard deviation of sigma_y
    depth: float           #: m


def sharp_strength_points(curves, tip="berkovich", *, nu: float, E_i: float = E_I_DAO,
                          nu_i: float = NU_I_DAO, source: str = "", dPdh_rsd: float = 0.05,
                          WpWt_std: float = 0.01, samples: int = 400) -> list[StrengthPoint]:
    """sigma_y of each sharp curve at its maximum depth (Dao reverse analysis), with the
    Monte Carlo standard deviation of `calibrate_sharp`'s one-curve route."""
    points = []
    for i, c in enumerate(curves):
        C, C_std, S, W, h_m = sharp_inputs(c, tip)
        r = dao_reverse(C, S, W, h_m, tip=tip, nu=nu, E_i=E_i, nu_i=nu_i, C_std=C_std,
                        dPdh_std=dPdh_rsd * S, WpWt_std=WpWt_std, samples=samples)
        points.append(StrengthPoint(source or str(c.meta.get("source", f"curve {i}")),
                                    float(r.sigma_y), float(r.sigma_y_std / r.sigma_y),
                                    float(h_m)))
    return points


#: floor of a strength point's relative std in the Nix-Gao weights (a noise-free point
#: would otherwise take all the weight)
MIN_REL_STD = 1e-3


def nix_gao_strengths(points) -> NixGaoFit:
    """sigma_y0 and h* of sigma_y(d) = sigma_y0 sqrt(1 + h*/d) (Nix & Gao 1998, written for
    sigma_y) from strength points, when they identify a depth law; else the
    depth-independent strength with h* not identified (`size_effect.depth_trend`).

    Weighted least squares in ln sigma_y with weights 1/rel_std; h* > -0.9 x the smallest
    depth. Standard errors from s^2 (J^T J)^-1 with s^2 the weighted residual variance over
    N - 2 degrees of freedom (the stated stds weight the points; their scatter sets the
    scale, as in `nix_gao_fit`). The depth law is kept only when the strengths span a depth
    ratio of `MIN_DEPTH_RATIO`, it beats the weighted constant by the F test of
    `depth_trend`; h* is identified when also positive by two standard deviations. ``H0`` of the result is
    sigma_y0 (or the constant), ``r2`` is that of ln sigma_y."""
    from scipy.optimize import least_squares
    points = list(points)
    if len(points) < 3:
        raise InputError(f"a Nix-Gao fit needs at least 3 strengths, got {len(points)}")
    d = np.array([p.depth for p in points])
    s = np.array([p.sigma_y for p in points])
    w = 1.0 / np.maximum([p.rel_std for p in points], MIN_REL_STD)
    if not np.all(np.isfinite(s) & (s > 0) & np.isfinite(w) & np.isfinite(d) & (d > 0)):
        raise InputError("Nix-Gao: every strength and depth must be finite and > 0, with a "
                         "finite std")
    ln_s = np.log(s)
    flat_ln = float(np.average(ln_s, weights=w**2))
    flat_ssr = float(np.sum(w**2 * (ln_s - flat_ln)**2))
    dof = len(points) - 2

    def flat(reason: str, p_value: float = math.nan) -> NixGaoFit:
        # the weighted mean of ln sigma_y; its std from the scatter about it
        var = flat_ssr / max(len(points) - 1, 1) / float(np.sum(w**2))
        sy = math.exp(flat_ln)
        return NixGaoFit(sy, math.nan, sy * math.sqrt(var), math.nan, 0.0, len(points),
                         False, reason, p_value)
    span = depth_trend(d)
    if not span.identified:
        return flat(span.reason)
    d_ref = float(np.exp(np.mean(np.log(d))))

    def residuals(x):
        return w * (x[0] + 0.5 * np.log1p(x[1] * d_ref / d) - ln_s)
    low = -0.9 * float(d.min()) / d_ref
    fit = least_squares(residuals, [flat_ln, 0.0], bounds=([-np.inf, low], [np.inf, np.inf]),
                        xtol=1e-14, ftol=1e-14, gtol=1e-14)
    ssr = float(fit.fun @ fit.fun)
    trend = depth_trend(d, flat_ssr, ssr, dof)
    if not trend.identified:
        return flat(trend.reason, trend.p_value)
    cov = ssr / dof * np.linalg.pinv(fit.jac.T @ fit.jac)
    h_star, h_star_std = float(fit.x[1] * d_ref), d_ref * math.sqrt(cov[1, 1])
    sigma_y0 = math.exp(fit.x[0])
    r2 = 1.0 - ssr / flat_ssr if flat_ssr > 0 else 1.0
    return NixGaoFit(sigma_y0, h_star, sigma_y0 * math.sqrt(cov[0, 0]), h_star_std, r2,
                     len(points), *admissible_h_star(h_star, h_star_std), trend.p_value)


def h_star_parameter(h_star: float, h_star_std: float) -> Parameter:
    """h* as a calibrated parameter: identified when its relative std is below
    `IDENTIFIABLE_RSD` and it is positive by two standard deviations."""
    ok, reason = admissible_h_star(h_star, h_star_std)
    if ok and not h_star_std < IDENTIFIABLE_RSD * h_star:
        ok, reason = False, f"relative uncertainty above {IDENTIFIABLE_RSD:.0%}"
    return Parameter(h_star, h_star_std, "m", ok, reason)


def apply_size_effect(cal: Calibration, points) -> Calibration:
    """``cal`` with sigma_y0 and h* of `nix_gao_strengths` over ``points`` when they identify
    a depth law; otherwise ``cal``'s depth-independent sigma_y with h* marked not identified
    and the reason (also for fewer than 3 strengths)."""
    points = list(points)
    try:
        fit = nix_gao_strengths(points)
    except InputError as err:
        fit = None
        reason = str(err)
    else:
        reason = fit.reason
    if fit is None or math.isnan(fit.h_star):
        return replace(cal, h_star=Parameter(math.nan, math.nan, "m", False, reason),
                       warnings=cal.warnings + (f"no size effect: {reason}; sigma_y is the "
                                                "depth-independent value",))
    depths = [p.depth for p in points]
    return replace(
        cal, sigma_y=replace(cal.sigma_y, value=fit.H0, std=fit.H0_std),
        h_star=h_star_parameter(fit.h_star, fit.h_star_std),
        warnings=cal.warnings + (
            f"sigma_y is the macroscopic sigma_y0 of a Nix-Gao fit over {fit.n} strengths "
            f"({min(depths):.3g}-{max(depths):.3g} m, R^2 {fit.r2:.3f} in ln sigma_y, "
            f"p = {fit.p_value:.2g} against one constant)",))


def with_size_effect(cal: Calibration, curves, tip="berkovich", *, E_i: float = E_I_DAO,
                     nu_i: float = NU_I_DAO) -> Calibration:
    """``cal`` with the Nix-Gao depth dependence of sigma_y from sharp curves at three or
    more maximum depths: each curve is reversed on its own (Dao) and
    sigma_y(h_m) = sigma_y0 sqrt(1 + h*/h_m) is fitted (`nix_gao_strengths`; the Nix-Gao
    form written for sigma_y rather than hardness, because the depth profile scales sigma_y:
    hardness grows more slowly than sigma_y and would give a smaller h*). sigma_y becomes
    the macroscopic sigma_y0 with the fit's standard error."""
    return apply_size_effect(cal, sharp_strength_points(curves, tip, nu=cal.nu, E_i=E_i,
                                                        nu_i=nu_i))


def size_effect(curves, tip="berkovich") -> NixGaoFit:
    """Nix-Gao fit of the Oliver-Pharr hardness of curves at several maximum depths."""
    results = [oliver_pharr(c, tip) for c in curves]
    ok = [r for r in results if r.ok]
    if len(ok) < 3:
        raise InputError(f"a size-effect fit needs at least 3 analysable curves at different "
                         f"depths, got {len(ok)} of {len(results)}")
    return nix_gao_fit([r.h_c for r in ok], [r.H for r in ok])
