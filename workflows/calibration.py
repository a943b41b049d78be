"""Constitutive parameters of one layer (E, sigma_y, n) from load-displacement curves.

Three routes, each with an uncertainty and a verdict on what the data can identify:

- `calibrate_sphere`: spherical indentation (MD, particle model or measured). The loading
  curves of all given tips are fitted together by weighted least squares to the sphere
  contact law of the continuum package (Hertz below first yield, the elastic-plastic law
  beyond), unknowns ln E* and ln sigma_y. Uncertainty: the least-squares covariance
  s^2 (J^T J)^-1 with s^2 the residual variance. sigma_y counts as identified only when the
  elastic-plastic fit beats Hertz alone by more than the noise (F test at 95 %); otherwise
  the data give a lower bound (first yield at the deepest point). The contact
  laws are elastic-perfectly plastic, so n is never identifiable from a sphere.
- `calibrate_sharp`: Berkovich or 70.3 degree cone curves through the reverse analysis of
  Dao et al. (2001) (`filmscale.continuum.reverse`): E*, sigma_y and n. One curve:
  Monte Carlo over the input uncertainties (C from its own least-squares fit, dP/dh and
  W_p/W_t from the stated relative errors); several curves: the indent-to-indent scatter.
- `size_effect`: Nix-Gao H(h) = H0 sqrt(1 + h*/h) (Nix & Gao 1998) over curves at several
  depths or tips, so that nanometre (MD) and micrometre properties are one depth profile.

Units: SI throughout (m, N, Pa).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np
from scipy.optimize import brentq, least_squares
from scipy.stats import f as f_dist

from filmscale.continuum.contact_laws import ContactLaw, contact_law
from filmscale.continuum.curves import LOAD, LoadDisplacementCurve
from filmscale.continuum.errors import InputError, check_real
from filmscale.continuum.indentation import (NixGaoFit, elastic_limit, hertz_fit, nix_gao_fit,
                                             oliver_pharr)
from filmscale.continuum.materials import ElasticPlastic, modulus_from_reduced
from filmscale.continuum.reverse import (E_I_DAO, NU_I_DAO, dao_forward, dao_reverse,
                                        dao_reverse_repeated)
from filmscale.continuum.tips import Sphere, parse_tip

#: relative standard deviation above which a fitted parameter is reported as not identified
IDENTIFIABLE_RSD = 0.3


@dataclass(frozen=True)
class Parameter:
    """A calibrated value with one standard deviation (NaN when the data do not bound it)."""

    value: float
    std: float
    unit: str
    identified: bool
    reason: str = ""      #: why not identified, or how the value was fixed

    def text(self) -> str:
        std = "" if math.isnan(self.std) else f" +- {self.std:.3g}"
        tag = "" if self.identified else f"  [not identified: {self.reason}]"
        return f"{self.value:.4g}{std} {self.unit}".rstrip() + tag


@dataclass(frozen=True)
class Calibration:
    """E, sigma_y and n of one layer, the fit's quality and where they came from."""

    layer: str
    route: str                      #: "sphere", "sharp" or "joint" (several sources)
    E: Parameter
    sigma_y: Parameter
    n: Parameter
    nu: float                       #: Poisson ratio assumed (not fitted)
    uncertainty: str                #: how the standard deviations were obtained
    rms: float                      #: rms misfit / largest load (sphere) or NaN (sharp)
    points: int                     #: load points (sphere) or curves (sharp) used
    sources: tuple[str, ...]
    model: str                      #: contact law or reverse-analysis method
    warnings: tuple[str, ...] = ()
    #: Nix-Gao length of sigma_y (m) when curves at several depths give one; sigma_y is
    #: then the macroscopic (deep) value
    h_star: Parameter | None = None
    #: the source of each fitted curve (joint calibrations; empty: one source)
    curve_sources: tuple[str, ...] = ()
    #: each source's own calibration, as dicts with its ``source`` (joint calibrations)
    components: tuple = ()
    fitted_curves: tuple = field(default=(), repr=False, compare=False)

    def material(self) -> ElasticPlastic:
        """The calibrated layer as the continuum package's material. A sigma_y that the
        data only bound from below enters as that bound: the layer yields no later than
        the data allow (the conservative side for damage)."""
        return ElasticPlastic(self.E.value, self.nu, self.sigma_y.value, self.n.value,
                              self.layer)

    def to_dict(self) -> dict:
        d = asdict(self)
        d.pop("fitted_curves")
        return d

    def cross_check(self, tolerance: float, source: str = "") -> CrossCheck:
        """The calibrated forward model (the contact law, or Dao's forward C for sharp tips)
        against every loading point of the curves it was calibrated on (with ``source``:
        that source's curves of a joint calibration): rms misfit over the largest load of
        each curve, passed when at most ``tolerance``."""
        tolerance = check_real("tolerance", tolerance, low=0.0, low_open=True, high=1.0)
        curves = [c for i, c in enumerate(self.fitted_curves)
                  if not source or not self.curve_sources or self.curve_sources[i] == source]
        if not curves:
            raise InputError(f"calibration of {self.layer} holds no fitted curves"
                             + (f" of {source}" if source else ""))
        resid = np.concatenate([(F - P) / P.max() for h, P, F in curves])
        rms = float(np.sqrt(np.mean(resid**2)))
        return CrossCheck(self.model, rms, float(np.max(np.abs(resid))), tolerance,
                          rms <= tolerance, int(resid.size), source)

    def summary(self) -> str:
        lines = [f"Calibration of {self.layer} ({self.route}: {self.model}; "
                 f"uncertainty: {self.uncertainty})",
                 f"  E       = {self.E.text()}",
                 f"  sigma_y = {self.sigma_y.text()}",
                 f"  n       = {self.n.text()}",
                 f"  nu      = {self.nu:g} (assumed)"]
        if not math.isnan(self.rms):
            lines.append(f"  fit: rms misfit {self.rms:.2%} of the largest load over "
                         f"{self.points} points")
        if self.h_star is not None:
            lines.append(f"  h*      = {self.h_star.text()} (Nix-Gao: sigma_y sqrt(1 + h*/h))")
        for c in self.components:
            lines.append(f"  from {c['source']} ({c['route']}): E {c['E']['value']:.4g} Pa "
                         f"alone, {c['E_joint']['value']:.4g} Pa in the joint fit; sigma_y "
                         f"{c['sigma_y']['value']:.4g} Pa alone")
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class CrossCheck:
    """A calibrated parameter set run forward against the curves it came from."""

    model: str
    rms: float            #: rms misfit / largest load
    worst: float          #: largest |misfit| / largest load
    tolerance: float
    passed: bool
    points: int
    source: str = ""      #: the source whose curves were checked ("": all)

    def to_dict(self) -> dict:
        return asdict(self)

    def text(self) -> str:
        verdict = "passed" if self.passed else "FAILED"
        of = f" of {self.source}" if self.source else ""
        return (f"cross-scale check{of} {verdict}: {self.model} with the calibrated parameters "
                f"reproduces the curves to {self.rms:.1%} rms (worst point {self.worst:.1%}) "
                f"of the largest load; tolerance {self.tolerance:.0%}")


def _sphere_radius(curve: LoadDisplacementCurve, R) -> float:
    if R is not None:
        return check_real("R", R, low=0.0, low_open=True, high=1.0, unit="m")
    tip = parse_tip(curve.indenter) if curve.indenter else None
    if not isinstance(tip, Sphere):
        raise InputError(f"curve {curve.meta.get('source', '')!r} has indenter "
                         f"{curve.indenter!r}: give R (m) for a spherical calibration")
    return tip.R


def _loading_points(curve: LoadDisplacementCurve, with_pop_in=False):
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


def calibrate_sphere(curves, *, nu: float, R=None, layer: str = "layer",
                     law: str | ContactLaw = "komvopoulos-ye-continuous",
                     indenter: ElasticPlastic | None = None, n: float = 0.0) -> Calibration:
    """E and sigma_y of a homogeneous layer from spherical loading curves.

    Parameters
    ----------
    curves : LoadDisplacementCurve or sequence of them
        Loading (and optionally unloading) of spherical tips, h = approach (m), P (N).
    nu : float
        The layer's Poisson ratio (assumed: a sphere's loading does not separate E and nu).
    R : float or sequence, optional
        Tip radius of each curve, m; default from each curve's ``indenter`` (``sphere:...``).
    law : str or ContactLaw
        Sphere contact law used as the forward model beyond first yield.
    indenter : ElasticPlastic, optional
        An elastic indenter (None: rigid, as the MD and particle tips are).
    n : float
        The hardening exponent reported (not identifiable from an elastic-perfectly plastic
        sphere law); default 0.
    """
    curves = [curves] if isinstance(curves, LoadDisplacementCurve) else list(curves)
    if not curves:
        raise InputError("calibrate_sphere needs at least one curve")
    nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    radii = R if isinstance(R, (list, tuple, np.ndarray)) else [R] * len(curves)
    if len(radii) != len(curves):
        raise InputError(f"R has {len(radii)} values for {len(curves)} curves")
    law = contact_law(law) if isinstance(law, str) else law
    data = []
    for c, r in zip(curves, radii):
        h, P, pop = _loading_points(c, with_pop_in=True)
        data.append((h, P, _sphere_radius(c, r), float(P.max()), pop))
    compliance = 0.0 if indenter is None else indenter.compliance
    sources = tuple(str(c.meta.get("source", f"curve {i}")) for i, c in enumerate(curves))
    common = dict(layer=layer, nu=nu, n=Parameter(
        float(n), math.nan, "", False,
        f"the sphere law ({law.name}) is elastic-perfectly plastic; n fixed"), sources=sources,
        model=law.name)
    if any(pop is not None for *_, pop in data):
        return _sphere_past_pop_in(data, law, nu, compliance, common)
    return _sphere_joint(data, law, nu, compliance, common)


def _modulus(E_star, std_lnE, nu, compliance) -> Parameter:
    E = float(modulus_from_reduced(E_star, nu, compliance))
    dE = E**2 / ((1 - nu**2) * E_star) * std_lnE      # dE/dE* times the std of E*
    return Parameter(E, float(dE), "Pa", bool(std_lnE < IDENTIFIABLE_RSD))


def _residuals(data, law, nu, E_star, sigma_y):
    return np.concatenate([(law.contact(h, r, E_star, sigma_y, nu).force - P) / Pm
                           for h, P, r, Pm, *_ in data])


def _fitted(data, law, nu, E_star, sigma_y):
    return tuple((h, P, law.contact(h, r, E_star, sigma_y, nu).force)
                 for h, P, r, Pm, *_ in data)


def _sphere_joint(data, law, nu, compliance, common) -> Calibration:
    """Smooth curves: ln E* and ln sigma_y together, or Hertz alone when that suffices."""
    # starting point: Hertz on the first third of each curve's load, then yield at the
    # largest mean pressure divided by the law's hardness factor
    E0 = np.median([hertz_fit(LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int)),
                              R=r, P_limit=0.3 * Pm).E_r for h, P, r, Pm, _ in data])
    pm = max(Pm / (math.pi * r * h.max()) for h, P, r, Pm, _ in data)
    sy0 = pm / law.hardness_factor

    def residuals(theta):
        return _residuals(data, law, nu, *np.exp(theta))

    N = sum(h.size for h, *_ in data)
    elastic_sy = 1e3 * E0            # so high that nothing yields: the Hertz branch

    def elastic_residuals(lnE):
        return residuals(np.array([lnE[0], math.log(elastic_sy)]))

    efit = least_squares(elastic_residuals, [math.log(E0)], diff_step=1e-6, xtol=1e-12,
                         ftol=1e-12)
    fit = least_squares(residuals, [efit.x[0], math.log(sy0)], diff_step=1e-6, xtol=1e-12,
                        ftol=1e-12)
    ssr_el, ssr = float(efit.fun @ efit.fun), float(fit.fun @ fit.fun)
    E_star, sigma_y = np.exp(fit.x)
    reaches_yield = any(h.max() > _yield_approach(law, r, E_star, sigma_y, nu)
                        for h, _, r, *_ in data)
    # sigma_y counts as seen when the elastic-plastic fit beats Hertz alone by more than
    # noise: F test of the extra parameter at 95 % (F(1, N - 2) above its 0.95 quantile)
    F = (ssr_el - ssr) / max(ssr / max(N - 2, 1), 1e-300)
    yielded = reaches_yield and F > f_dist.ppf(0.95, 1, max(N - 2, 1))
    warnings = []
    if yielded:
        cov = ssr / max(N - 2, 1) * np.linalg.pinv(fit.jac.T @ fit.jac)
        std_lnE, std_lnS = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        delta_y = max(_yield_approach(law, r, E_star, sigma_y, nu) for _, _, r, *_ in data)
        if max(h.max() for h, *_ in data) < 3 * delta_y:
            warnings.append(f"the deepest point is under 3 x the first-yield approach "
                            f"({delta_y:.3g} m): sigma_y rests on the early elastic-plastic "
                            "range")
        sigma_param = _yield_parameter(sigma_y, std_lnS)
    else:
        # Hertz alone explains the data: E* from the elastic fit; sigma_y only bounded below
        # (first yield exactly at the deepest point)
        ssr = ssr_el
        E_star = float(np.exp(efit.x[0]))
        std_lnE = math.sqrt(ssr / max(N - 1, 1) / float((efit.jac.T @ efit.jac)[0, 0]))
        sigma_param = _lower_bound(data, law, E_star, nu)
        warnings.append(f"sigma_y not identified: {sigma_param.reason}")
    return Calibration(
        route="sphere", E=_modulus(E_star, std_lnE, nu, compliance), sigma_y=sigma_param,
        uncertainty="least-squares covariance s^2 (J^T J)^-1",
        rms=math.sqrt(ssr / N), points=N, warnings=tuple(warnings),
        fitted_curves=_fitted(data, law, nu, E_star,
                              sigma_y if yielded else elastic_sy), **common)


def _sphere_past_pop_in(data, law, nu, compliance, common) -> Calibration:
    """Curves with a pop-in (MD's defect-free crystal): E* by Hertz on the loading before
    the first pop-in, then sigma_y with E* fixed on the loading after it. The contact law
    has no pop-in, so a joint fit would trade E* against the elastic overshoot. The std of
    sigma_y adds the propagated std of E* to its own (conditional) one."""
    # stage 1: P = E* x with x = 4/3 sqrt(R) h^1.5, each curve weighted by 1/P_max
    pre = [(h[:pop + 1], P[:pop + 1], r, Pm) for h, P, r, Pm, pop in data if pop is not None]
    x = np.concatenate([4 / 3 * math.sqrt(r) * h**1.5 / Pm for h, P, r, Pm in pre])
    y = np.concatenate([P / Pm for h, P, r, Pm in pre])
    if x.size < 3:
        raise InputError(f"only {x.size} loading points before the pop-in: a Hertz fit of "
                         "E needs at least 3")
    E_star = float(x @ y / (x @ x))
    r1 = y - E_star * x
    std_lnE = math.sqrt(float(r1 @ r1) / max(x.size - 1, 1) / float(x @ x)) / E_star
    # stage 2: the rest of each curve (all of a curve without a pop-in)
    post = [(h[pop + 1:] if pop is not None else h, P[pop + 1:] if pop is not None else P,
             r, Pm) for h, P, r, Pm, pop in data]
    post = [d for d in post if d[0].size]
    N2 = sum(h.size for h, *_ in post)
    warnings = [f"pop-in at {Pm_pop:.3g} N, {h_pop:.3g} m: E from the {x.size} Hertz points "
                "before it, sigma_y from the loading after it"
                for Pm_pop, h_pop in ((P[pop], h[pop]) for h, P, r, Pm, pop in data
                                      if pop is not None)]
    sigma_param = None
    if N2 >= 2:
        sy0 = max(Pm / (math.pi * r * h.max()) for h, P, r, Pm in post) / law.hardness_factor
        def residuals(ln_sy, ln_E=math.log(E_star)):
            return _residuals(post, law, nu, math.exp(ln_E), math.exp(ln_sy[0]))
        fit = least_squares(residuals, [math.log(sy0)], diff_step=1e-6, xtol=1e-12,
                            ftol=1e-12)
        sigma_y = float(np.exp(fit.x[0]))
        if any(h.max() > _yield_approach(law, r, E_star, sigma_y, nu) for h, _, r, _ in post):
            ssr2 = float(fit.fun @ fit.fun)
            J_S = fit.jac[:, 0]
            eps = 1e-4
            J_E = (residuals(fit.x, math.log(E_star) + eps)
                   - residuals(fit.x, math.log(E_star) - eps)) / (2 * eps)
            var_cond = ssr2 / max(N2 - 1, 1) / float(J_S @ J_S)
            sens = -float(J_S @ J_E) / float(J_S @ J_S)     # d ln sigma_y / d ln E*
            sigma_param = _yield_parameter(sigma_y, math.sqrt(var_cond
                                                              + (sens * std_lnE)**2))
    if sigma_param is None:
        sigma_param = _lower_bound(post or pre, law, E_star, nu)
        warnings.append(f"sigma_y not identified: {sigma_param.reason}")
    fitted = _fitted(data, law, nu, E_star, sigma_param.value)
    resid = np.concatenate([(f - P) / P.max() for h, P, f in fitted])
    return Calibration(
        route="sphere", E=_modulus(E_star, std_lnE, nu, compliance), sigma_y=sigma_param,
        uncertainty="sequential least squares (Hertz before the pop-in, then sigma_y with E* "
                    "fixed); covariances s^2 (J^T J)^-1, E*'s propagated into sigma_y",
        rms=math.sqrt(float(resid @ resid) / resid.size), points=int(resid.size),
        warnings=tuple(warnings), fitted_curves=fitted, **common)


def _yield_parameter(sigma_y, std_lnS) -> Parameter:
    ok = bool(std_lnS < IDENTIFIABLE_RSD)
    return Parameter(float(sigma_y), float(sigma_y * std_lnS), "Pa", ok,
                     "" if ok else f"relative uncertainty {std_lnS:.0%} above "
                                   f"{IDENTIFIABLE_RSD:.0%}")


def _lower_bound(data, law, E_star, nu) -> Parameter:
    value = min(_yield_lower_bound(law, h.max(), r, E_star, nu) for h, _, r, *_ in data)
    return Parameter(value, math.nan, "Pa", False,
                     "no curve passes first yield beyond noise; the value is a lower bound")


def _yield_approach(law: ContactLaw, R, E_star, sigma_y, nu) -> float:
    """The approach of first yield, m."""
    return float(law.first_yield(R, E_star, sigma_y, nu).approach)


def _yield_lower_bound(law: ContactLaw, delta_max, R, E_star, nu) -> float:
    """The sigma_y at which first yield falls exactly at the deepest point: any larger
    sigma_y leaves the whole curve elastic (root in ln sigma_y, bracketed by 1e-6 E* and E*)."""
    def gap(ln_sy):
        return _yield_approach(law, R, E_star, math.exp(ln_sy), nu) - delta_max
    return math.exp(brentq(gap, math.log(1e-6 * E_star), math.log(E_star), xtol=1e-12))


def sharp_inputs(curve: LoadDisplacementCurve, tip="berkovich"):
    """(C, C_std, dP/dh, W_p/W_t, h_m) of one sharp-tip curve: C by least squares of
    P = C h^2 over the loading with h >= h_m/2 (C_std its standard error), the rest from
    the Oliver-Pharr analysis of the unloading."""
    op = oliver_pharr(curve, tip)
    if not op.ok:
        raise InputError(f"curve {curve.meta.get('source', '')!r}: {op.message}")
    h, P = _loading_points(curve)
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

    n_std_ok = math.isfinite(r.n_std) and r.n_std < 0.1
    fitted = []
    for c, h_m in zip(curves, hm):
        h, P = _loading_points(c)
        C_model = dao_forward(r.E, nu, r.sigma_y, r.n, h_m, tip=tip, E_i=E_i, nu_i=nu_i).C
        fitted.append((h, P, float(C_model) * h**2))
    return Calibration(
        layer=layer, route="sharp", E=param(r.E, r.E_std, "Pa"),
        sigma_y=param(r.sigma_y, r.sigma_y_std, "Pa"),
        n=Parameter(float(r.n), float(r.n_std), "", n_std_ok,
                    "" if n_std_ok else "standard deviation above 0.1"),
        nu=nu, uncertainty=how, rms=math.nan, points=len(curves),
        sources=tuple(str(c.meta.get("source", f"curve {i}")) for i, c in enumerate(curves)),
        model=f"Dao et al. 2001 reverse analysis ({r.method}, {tip})", warnings=r.warnings,
        fitted_curves=tuple(fitted))


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
    sigma_y) from strength points.

    Weighted least squares in ln sigma_y with weights 1/rel_std; h* > -0.9 x the smallest
    depth. Standard errors from s^2 (J^T J)^-1 with s^2 the weighted residual variance over
    N - 2 degrees of freedom (the stated stds weight the points; their scatter sets the
    scale, as in `nix_gao_fit`). ``H0`` of the result is sigma_y0, ``r2`` is that of
    ln sigma_y."""
    points = list(points)
    if len(points) < 3:
        raise InputError(f"a Nix-Gao fit needs at least 3 strengths, got {len(points)}")
    d = np.array([p.depth for p in points])
    s = np.array([p.sigma_y for p in points])
    w = 1.0 / np.maximum([p.rel_std for p in points], MIN_REL_STD)
    if not np.all(np.isfinite(s) & (s > 0) & np.isfinite(w)):
        raise InputError("Nix-Gao: every strength must be finite and > 0, with a finite std")
    if np.ptp(np.log(d)) < 0.01:
        raise InputError("Nix-Gao needs strengths at different depths")
    d_ref = float(np.exp(np.mean(np.log(d))))
    try:
        start = nix_gao_fit(d, s)
        x0 = [math.log(start.H0), max(start.h_star / d_ref, 0.0)]
    except InputError:
        x0 = [math.log(float(np.median(s))), 0.0]

    def residuals(x):
        return w * np.log(math.exp(x[0]) * np.sqrt(1.0 + x[1] * d_ref / d) / s)
    low = -0.9 * float(d.min()) / d_ref
    x0[1] = max(x0[1], 0.5 * low)
    fit = least_squares(residuals, x0, bounds=([-np.inf, low], [np.inf, np.inf]),
                        xtol=1e-14, ftol=1e-14, gtol=1e-14)
    dof = max(len(points) - 2, 1)
    cov = float(fit.fun @ fit.fun) / dof * np.linalg.pinv(fit.jac.T @ fit.jac)
    sigma_y0 = math.exp(fit.x[0])
    ln_s = np.log(s)
    total = float(np.sum(w**2 * (ln_s - np.average(ln_s, weights=w**2))**2))
    r2 = 1.0 - float(fit.fun @ fit.fun) / total if total > 0 else 1.0
    return NixGaoFit(sigma_y0, float(fit.x[1] * d_ref), sigma_y0 * math.sqrt(cov[0, 0]),
                     d_ref * math.sqrt(cov[1, 1]), r2, len(points))


def apply_size_effect(cal: Calibration, points) -> Calibration:
    """``cal`` with sigma_y0 and h* of `nix_gao_strengths` over ``points``; unchanged (with a
    warning) when they give none: fewer than 3 strengths, one depth, or h* <= 0."""
    try:
        fit = nix_gao_strengths(points)
    except InputError as err:
        return replace(cal, warnings=cal.warnings + (f"no size effect: {err}",))
    if not fit.h_star > 0:
        return replace(cal, warnings=cal.warnings + (
            f"no size effect: the Nix-Gao fit of sigma_y over {fit.n} strengths gives h* = "
            f"{fit.h_star:.3g} m",))
    ok = fit.h_star_std < IDENTIFIABLE_RSD * fit.h_star
    depths = [p.depth for p in points]
    return replace(
        cal, sigma_y=replace(cal.sigma_y, value=fit.H0, std=fit.H0_std),
        h_star=Parameter(fit.h_star, fit.h_star_std, "m", bool(ok),
                         "" if ok else f"relative uncertainty above {IDENTIFIABLE_RSD:.0%}"),
        warnings=cal.warnings + (
            f"sigma_y is the macroscopic sigma_y0 of a Nix-Gao fit over {fit.n} strengths "
            f"({min(depths):.3g}-{max(depths):.3g} m, R^2 {fit.r2:.3f} in ln sigma_y)",))


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
