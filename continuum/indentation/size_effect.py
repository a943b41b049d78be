"""Indentation size effect: Nix & Gao, J. Mech. Phys. Solids 46 (1998) 411,
H = H_0 sqrt(1 + h*/h) (docs/physics.md section 9), and the rule that decides whether a set
of indents identifies a depth law at all.

A depth law is identified only when both hold (`depth_trend`):

- the indents span depths of at least `MIN_DEPTH_RATIO` (deepest over shallowest): repeats at
  one depth hold scatter, not a trend;
- the law beats one depth-independent value by more than the indents' own scatter: the
  nested-model F test of its extra parameter, F = (SSR_flat - SSR_law) / (SSR_law / dof),
  at the `TREND_LEVEL` significance level.

Otherwise the depth-independent value is the answer and h* is not identified, with the reason.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from filmscale.core.errors import InputError

#: a depth law needs indents whose depths span at least this ratio
MIN_DEPTH_RATIO = 2.0
#: and must beat a depth-independent value by an F test at this significance level
TREND_LEVEL = 0.05


@dataclass(frozen=True)
class DepthTrend:
    """Whether a set of indents identifies a depth law, and why (not)."""

    identified: bool
    reason: str           #: why not identified ("" when identified)
    depth_ratio: float    #: deepest over shallowest depth
    F: float              #: F statistic of the law's extra parameter (NaN: not computed)
    p_value: float        #: its p-value (NaN: not computed)


def depth_trend(depths, ssr_flat: float | None = None, ssr_law: float | None = None,
                dof: int = 0) -> DepthTrend:
    """The verdict of the module docstring's rule on indents at ``depths`` (m), given the
    sums of squared (weighted) residuals of the depth-independent fit and of the depth law
    and the law's residual degrees of freedom. Without sums only the depth span is judged."""
    from scipy.stats import f as f_dist
    d = np.asarray(depths, dtype=float)
    ratio = float(d.max() / d.min()) if d.size and d.min() > 0 else math.nan
    if not ratio >= MIN_DEPTH_RATIO:
        return DepthTrend(False, f"the indents span depths {d.min():.3g}-{d.max():.3g} m, a "
                                 f"ratio of {ratio:.3g} (a depth law needs at least "
                                 f"{MIN_DEPTH_RATIO:g}): their spread is scatter at one depth",
                          ratio, math.nan, math.nan)
    if ssr_flat is None or ssr_law is None:
        return DepthTrend(True, "", ratio, math.nan, math.nan)
    if dof < 1:
        return DepthTrend(False, "too few indents to test a depth trend against their "
                                 "scatter", ratio, math.nan, math.nan)
    F = (ssr_flat - ssr_law) / max(ssr_law / dof, 1e-300)
    p = float(f_dist.sf(F, 1, dof)) if F > 0 else 1.0
    if p > TREND_LEVEL:
        return DepthTrend(False, f"no depth trend beyond the indents' scatter (F test of "
                                 f"the depth law against one constant: F = {F:.3g}, p = "
                                 f"{p:.2g} > {TREND_LEVEL:g})", ratio, float(F), p)
    return DepthTrend(True, "", ratio, float(F), p)


@dataclass(frozen=True)
class NixGaoFit:
    """H = H_0 sqrt(1 + h*/h) fitted as the straight line H^2 = H_0^2 + H_0^2 h* / h.

    When the indents hold no depth trend (`depth_trend`), H0 is the depth-independent value
    (the rms hardness), h* and its std are NaN and ``identified`` is False. A trend whose h*
    is not positive by two standard deviations keeps its values, with ``identified``
    False."""

    H0: float          #: macroscopic hardness, Pa
    h_star: float      #: characteristic depth, m (NaN: not identified)
    H0_std: float      #: standard error of H0, Pa
    h_star_std: float  #: standard error of h*, m
    r2: float          #: coefficient of determination of the line
    n: int
    identified: bool = True
    reason: str = ""   #: why h* is not identified
    p_value: float = math.nan   #: of the F test of the depth law against one constant

    def hardness(self, h):
        """H(h), Pa, at depth h (m): H0 at every depth when there is no depth trend."""
        h = np.asarray(h, dtype=float)
        if math.isnan(self.h_star):
            return np.full(h.shape, self.H0)
        return self.H0 * np.sqrt(1.0 + self.h_star / h)

    def to_dict(self) -> dict:
        return asdict(self)


def nix_gao_fit(h, H) -> NixGaoFit:
    """Nix-Gao fit of hardness H (Pa) against depth h (m), with standard errors.

    Ordinary least squares of H^2 on 1/h; the errors of H_0 = sqrt(a) and h* = b/a follow
    from the covariance of (a, b) to first order. h* is reported only when the indents
    identify it (`depth_trend`: a depth span of at least `MIN_DEPTH_RATIO`, a slope beyond
    the scatter, and h* > 0 by two standard deviations); otherwise H0 is the
    depth-independent fit and ``identified`` is False with the reason.
    """
    h, H = np.asarray(h, dtype=float), np.asarray(H, dtype=float)
    if h.shape != H.shape or h.ndim != 1 or h.size < 3:
        raise InputError("Nix-Gao needs 1-D arrays h and H of one length, at least 3 indents")
    if not np.all(np.isfinite(h) & (h > 0) & np.isfinite(H) & (H > 0)):
        raise InputError("Nix-Gao: every h and H must be finite and > 0")
    x, y = 1.0 / h, H**2
    flat_ssr = float(np.sum((y - y.mean())**2))

    def flat(reason: str, p: float = math.nan) -> NixGaoFit:
        H0 = math.sqrt(float(y.mean()))
        H0_std = float(np.std(y, ddof=1)) / math.sqrt(y.size) / (2.0 * H0)
        return NixGaoFit(H0, math.nan, H0_std, math.nan, 0.0, int(h.size), False, reason, p)
    if np.ptp(x) <= 1e-9 * x.mean():
        return flat(depth_trend(h).reason or "the indents are all at one depth")
    (b, a), cov = np.polyfit(x, y, 1, cov="unscaled")
    resid = y - (a + b * x)
    ssr = float(resid @ resid)
    trend = depth_trend(h, flat_ssr, ssr, h.size - 2)
    if not trend.identified:
        return flat(trend.reason, trend.p_value)
    cov = cov * ssr / (h.size - 2)
    if a <= 0:
        return flat("H^2 against 1/h extrapolates to a negative H_0^2: the hardness does not "
                    "follow the Nix-Gao form", trend.p_value)
    H0, h_star = math.sqrt(a), b / a
    var_a, var_b, cov_ab = cov[1, 1], cov[0, 0], cov[0, 1]
    H0_std = math.sqrt(var_a) / (2.0 * H0)
    h_star_std = math.sqrt(max(var_b / a**2 - 2.0 * b * cov_ab / a**3 + b * b * var_a / a**4,
                               0.0))
    r2 = 1.0 - ssr / flat_ssr if flat_ssr > 0 else 1.0
    return NixGaoFit(H0, float(h_star), H0_std, h_star_std, r2, int(h.size),
                     *admissible_h_star(h_star, h_star_std), trend.p_value)


def admissible_h_star(h_star: float, h_star_std: float) -> tuple[bool, str]:
    """(identified, reason) of a fitted h*: its two-standard-deviation interval must be
    physically admissible (h* > 0)."""
    if h_star - 2.0 * h_star_std > 0:
        return True, ""
    return False, (f"h* = {h_star:.3g} +- {h_star_std:.2g} m is not positive by two standard "
                   "deviations")
