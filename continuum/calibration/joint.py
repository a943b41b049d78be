"""One layer calibrated from several sources at once: an MD or particle-model run at
nanometres and curves measured at micrometres, say.

Each source is first calibrated on its own (`workflows.calibration`). `combine` then gives
the layer one parameter set:

- sigma_y: one Nix-Gao law sigma_y(d) = sigma_y0 sqrt(1 + h*/d) (Nix & Gao 1998, written for
  sigma_y, as `continuum.profiles.StackProfile` scales it) fitted to all sources together,
  so that the nanometre and micrometre strengths both reach the impact model's depth
  profile. Sphere sources enter with their loading points: the contact law evaluated with
  sigma_y(delta) at each approach (how the impact model evaluates the profile), a film
  source with the Gao-weighted properties of the film on its own substrate, their E*
  free unless a pop-in fixed it (a constant-sigma_y fit of a curve whose strength falls with
  depth trades E* against that fall). Sharp sources enter with each curve's sigma_y at its
  maximum depth (Dao reverse analysis). Weighted least squares, each source's residuals
  divided by its own noise (a sphere: the rms misfit of its own fit; a sharp curve: the
  Monte Carlo std of its sigma_y); covariance s^2 (J^T J)^-1 scaled by the residuals.
  h* >= 0; at h* = 0 the layer has no size effect and sigma_y is the joint constant.
- E: the inverse-variance mean of the sources that identify it (a sphere's E from the joint
  fit where it was free there). Where they disagree beyond their standard deviations
  (chi^2 test at 95 %) the mean's std is scaled by the Birge ratio sqrt(chi^2 / (k - 1))
  and a warning lists each source's E: an MD potential's crystal and a measured polycrystal
  need not agree.
- n: the inverse-variance mean of the sources that identify it (sharp tips).

The cross-scale check runs the joint set forward (the contact law with sigma_y(delta); Dao's
forward C with sigma_y(h_m)) over every source's curves.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Callable

import numpy as np

from filmscale.continuum.contact.laws import ContactLaw, contact_law
from filmscale.continuum.indentation.reverse.dao import dao_forward
from filmscale.continuum.indentation.reverse.functions import E_I_DAO, NU_I_DAO
from filmscale.continuum.indentation.size_effect import depth_trend
from filmscale.continuum.indentation.spherical import loading_points
from filmscale.continuum.materials import ElasticPlastic, reduced_modulus
from filmscale.core.errors import InputError

from .result import IDENTIFIABLE_RSD, Calibration, Parameter, modulus_parameter
from .sharp import (MIN_REL_STD, StrengthPoint, h_star_parameter, nix_gao_strengths,
                    sharp_strength_points)
from .sphere import sphere_radius
from .target import SphereTarget

#: floor of a sphere source's noise in the joint weights (as a fraction of its largest load)
MIN_NOISE = 1e-4


@dataclass(frozen=True)
class CalibrationPart:
    """One source's calibration of a layer, as the joint fit uses it."""

    label: str
    calibration: Calibration
    #: where the source puts sigma_y on its own: the start of the joint fit
    strengths: tuple[StrengthPoint, ...]
    #: (sigma_y(depth), own parameters) -> residuals in units of the source's noise
    residuals: Callable
    #: start values of the source's own parameters in the joint fit (a free ln E*)
    own: tuple[float, ...]
    #: own parameters -> the source's E as a Parameter given their std (None: its own E)
    modulus: Callable | None
    #: (E, n, sigma_y(depth)) -> ((h, P, P_model), ...) over the source's loading curves
    forward: Callable


def sphere_part(label: str, cal: Calibration, curves, law: str | ContactLaw,
                indenter: ElasticPlastic | None = None, thickness: float | None = None,
                substrate: ElasticPlastic | None = None) -> CalibrationPart:
    """A sphere source: its loading points after a pop-in with E* fixed by the Hertz fit
    before it, else all its loading points with E* free; approaches from the source's own
    contact zero. With ``thickness`` and ``substrate`` the layer is a film on that substrate,
    as the source's own calibration took it: the law sees the Gao-weighted E_p, sigma_y and
    nu at each approach (`SphereTarget`'s weights), the film's sigma_y being the joint
    sigma_y(delta); a substrate without sigma_y takes the film's."""
    law = contact_law(law) if isinstance(law, str) else law
    nu = cal.nu
    compliance = 0.0 if indenter is None else indenter.compliance
    target = SphereTarget(nu, indenter, thickness, substrate)
    loading, fitted, free = [], [], True
    for c in curves:
        recorded, P, pop = loading_points(c, with_pop_in=True)
        h = np.clip(recorded - cal.contact_zero, 0.0, None)
        r = sphere_radius(c, None)
        w = target.film_weights(h, r)
        loading.append((recorded, h, P, r, w))
        keep = slice(None) if pop is None else slice(pop + 1, None)
        fitted.append((h[keep], P[keep], r, float(P.max()),
                       None if w is None else tuple(x[keep] for x in w)))
        free = free and pop is None
    fitted = [d for d in fitted if d[0].size]
    if not fitted:      # a pop-in at the last point: the source gives E alone
        raise InputError(f"{label}: no loading points after the pop-in; a joint "
                         "calibration needs the source's plastic loading")

    def e_star(E):
        return reduced_modulus(E / (1.0 - nu**2), indenter)

    def force(h, r, E_star, sigma, w):
        """The law's force with the layer's reduced modulus E_star and strength sigma (arrays
        over h), or what a film of them on the substrate presents there."""
        if w is None:
            return law.unchecked_contact(h, r, E_star, sigma, nu).force
        return law.unchecked_contact(h, r, *target.felt(E_star, sigma, w)).force

    E_own, s_own = e_star(cal.E.value), cal.sigma_y.value

    def misfit(E_star, sigma_at):
        return np.concatenate([(force(h, r, E_star, sigma_at(h), w) - P) / Pm
                               for h, P, r, Pm, w in fitted])
    noise = max(float(np.sqrt(np.mean(misfit(E_own, lambda h: s_own)**2))), MIN_NOISE)

    def residuals(sigma_at, own):
        return misfit(math.exp(own[0]) if free else E_own, sigma_at) / noise

    def modulus(own, std_ln):
        return modulus_parameter(math.exp(own[0]), std_ln, nu, compliance)

    # where its own fit puts sigma_y: the depth weighted by (dF/dsigma_y)^2, the points
    # that decide a constant sigma_y
    depth = np.concatenate([h for h, *_ in fitted])
    dF = misfit(E_own, lambda h: 1.01 * s_own) - misfit(E_own, lambda h: s_own)
    strengths = ((StrengthPoint(label, s_own, cal.sigma_y.std / s_own,
                                float(dF**2 @ depth / (dF @ dF))),)
                 if cal.sigma_y.identified and dF @ dF > 0 else ())

    def forward(E, n, sigma_at):
        return tuple((recorded, P, force(h, r, e_star(E), sigma_at(h), w))
                     for recorded, h, P, r, w in loading)
    return CalibrationPart(label, cal, strengths, residuals,
                           (math.log(E_own),) if free else (), modulus if free else None,
                           forward)


def sharp_part(label: str, cal: Calibration, curves, tip: str, E_i: float = E_I_DAO,
               nu_i: float = NU_I_DAO) -> CalibrationPart:
    """A sharp source: each curve's sigma_y at its maximum depth (Dao reverse analysis)."""
    points = tuple(sharp_strength_points(curves, tip, nu=cal.nu, E_i=E_i, nu_i=nu_i,
                                         source=label))
    d = np.array([p.depth for p in points])
    s = np.array([p.sigma_y for p in points])
    w = 1.0 / np.maximum([p.rel_std for p in points], MIN_REL_STD)
    loads = [(*loading_points(c), p.depth) for c, p in zip(curves, points)]

    def residuals(sigma_at, own):
        return w * np.log(sigma_at(d) / s)

    def forward(E, n, sigma_at):
        return tuple((h, P, dao_forward(E, cal.nu, float(sigma_at(np.array([h_m]))[0]), n,
                                        h_m, tip=tip, E_i=E_i, nu_i=nu_i).C * h**2)
                     for h, P, h_m in loads)
    return CalibrationPart(label, cal, points, residuals, (), None, forward)


def _mean(items, name: str, unit: str) -> tuple[Parameter, list[str]]:
    """Inverse-variance mean of the identified (label, Parameter) items; the first item's
    parameter when none is identified."""
    from scipy.stats import chi2
    use = [(label, p) for label, p in items
           if p.identified and math.isfinite(p.std) and p.std > 0]
    if not use:
        return items[0][1], []
    x = np.array([p.value for _, p in use])
    w = 1.0 / np.array([p.std for _, p in use])**2
    mean, std = float(w @ x / w.sum()), float(1.0 / math.sqrt(w.sum()))
    warnings = []
    if len(use) > 1:
        stat, dof = float(w @ (x - mean)**2), len(use) - 1
        if chi2.sf(stat, dof) < 0.05:
            birge = math.sqrt(stat / dof)
            std *= birge
            each = ", ".join(f"{label} {p.value:.4g} +- {p.std:.3g}" for label, p in use)
            warnings.append(f"the sources disagree on {name} beyond their uncertainties "
                            f"(chi^2 {stat:.3g} over {dof} degrees of freedom): {each} "
                            f"{unit}; the mean's std is scaled by the Birge ratio {birge:.3g}")
    return Parameter(mean, std, unit, True,
                     f"inverse-variance mean of {len(use)} sources"), warnings


def _start(points) -> tuple[float, float]:
    """(sigma_y0, h*) to start from: the Nix-Gao fit of the sources' own strengths, or a
    constant where it has none."""
    try:
        fit = nix_gao_strengths(points)
        return fit.H0, fit.h_star if fit.identified else 0.0
    except InputError:
        return float(np.median([p.sigma_y for p in points])), 0.0


def _joint_fit(parts, d_ref, sized: bool):
    """Least squares over [ln sigma_y0, h*/d_ref (``sized`` only, else h* = 0), each part's
    own parameters]. Returns the parameters (h*/d_ref included), their standard errors, the
    index of each part's own parameters, the sum of squares and its degrees of freedom."""
    from scipy.optimize import least_squares
    first = 2 if sized else 1
    own_at = np.cumsum([first] + [len(p.own) for p in parts])
    sy0, h_star = _start([pt for p in parts for pt in p.strengths])

    def residuals(theta):
        scale = theta[1] * d_ref if sized else 0.0

        def sigma_at(d):
            return math.exp(theta[0]) * np.sqrt(1.0 + scale / np.asarray(d))
        return np.concatenate([p.residuals(sigma_at, theta[a:a + len(p.own)])
                               for p, a in zip(parts, own_at)])
    x0 = [math.log(sy0)] + ([h_star / d_ref] if sized else []) + \
        [v for p in parts for v in p.own]
    low = [-np.inf] + ([0.0] if sized else []) + [-np.inf] * (len(x0) - first)
    fit = least_squares(residuals, x0, bounds=(low, np.inf), x_scale="jac",
                        xtol=1e-12, ftol=1e-12, gtol=1e-12)
    ssr, dof = float(fit.fun @ fit.fun), fit.fun.size - len(x0)
    if dof < 1:
        raise InputError(f"a joint calibration needs more data than its {len(x0)} "
                         f"parameters; it has {fit.fun.size} residuals")
    std = np.sqrt(np.clip(np.diag(ssr / dof * np.linalg.pinv(fit.jac.T @ fit.jac)), 0, None))
    x = fit.x if sized else np.insert(fit.x, 1, 0.0)
    std = std if sized else np.insert(std, 1, 0.0)
    return x, std, own_at + (0 if sized else 1), ssr, dof


def combine(parts, layer: str) -> Calibration:
    """One calibration of ``layer`` from the calibrations of two or more sources (module
    docstring)."""
    parts = list(parts)
    if len(parts) < 2:
        raise InputError(f"a joint calibration of {layer} needs 2 or more sources, got "
                         f"{len(parts)}")
    cals = [p.calibration for p in parts]
    nu = cals[0].nu
    if any(c.nu != nu for c in cals):
        raise InputError(f"the sources of {layer} assume different nu: "
                         f"{sorted({c.nu for c in cals})}")
    depths = [pt.depth for p in parts for pt in p.strengths] or [1e-6]
    d_ref = float(np.exp(np.mean(np.log(depths))))
    x, std, own_at, ssr, dof = _joint_fit(parts, d_ref, sized=True)
    # a size effect counts as seen by the rule of `depth_trend`: the sources' depths span
    # MIN_DEPTH_RATIO and Nix-Gao beats one constant sigma_y by the F test
    flat = _joint_fit(parts, d_ref, sized=False)
    trend = depth_trend([pt.depth for p in parts for pt in p.strengths] or [d_ref],
                        flat[3], ssr, dof)
    sized = trend.identified
    if not sized:
        x, std, own_at, ssr, dof = flat
    moduli = [(p.label, p.modulus(x[a:a + 1], std[a]) if p.modulus else p.calibration.E)
              for p, a in zip(parts, own_at)]
    E, warnings = _mean(moduli, "E", "Pa")
    n, n_warnings = _mean([(p.label, c.n) for p, c in zip(parts, cals)], "n", "")
    warnings += n_warnings
    sy0, h_star = math.exp(x[0]), float(x[1] * d_ref)
    sy_std, h_std = sy0 * std[0], d_ref * std[1]
    sigma_y = Parameter(sy0, sy_std, "Pa", bool(std[0] < IDENTIFIABLE_RSD),
                        "" if std[0] < IDENTIFIABLE_RSD
                        else f"relative uncertainty above {IDENTIFIABLE_RSD:.0%}")
    if sized:
        h_param = h_star_parameter(h_star, h_std)
        warnings.append(f"sigma_y is the macroscopic sigma_y0 of one Nix-Gao law over "
                        f"{len(parts)} sources")
    else:
        h_param = Parameter(math.nan, math.nan, "m", False, trend.reason)
        warnings.append(f"no size effect: {trend.reason}; sigma_y is one constant over the "
                        "sources")

    def sigma_at(d):
        return sy0 * np.sqrt(1.0 + h_star / np.asarray(d, dtype=float))
    fitted, labels = [], []
    for p in parts:
        curves = p.forward(E.value, n.value, sigma_at)
        fitted += curves
        labels += [p.label] * len(curves)
    resid = np.concatenate([(F - P) / P.max() for h, P, F in fitted])
    return Calibration(
        layer=layer, route="joint", E=E, sigma_y=sigma_y, n=n, nu=nu,
        uncertainty=("sigma_y0, h* (and free sphere E*): weighted least squares over all "
                     "sources, covariance s^2 (J^T J)^-1; E, n: inverse-variance means "
                     "(Birge-scaled where the sources disagree)"),
        rms=float(np.sqrt(np.mean(resid**2))), points=int(resid.size),
        sources=tuple(s for c in cals for s in c.sources),
        model="joint (" + "; ".join(f"{p.label}: {c.model}" for p, c in zip(parts, cals))
              + ")",
        warnings=tuple(warnings), h_star=h_param, curve_sources=tuple(labels),
        components=tuple({"source": p.label, "E_joint": asdict(E_k), **c.to_dict()}
                         for p, c, (_, E_k) in zip(parts, cals, moduli)),
        fitted_curves=tuple(fitted))
