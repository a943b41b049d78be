"""Dual-indenter reverse analysis (Chollacoop, Dao & Suresh 2003): a second sharp tip of
another half-angle pins down the hardening exponent n."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from filmscale.continuum.indentation.reverse.dao import (check_std, check_work_ratio,
                                                         identifiability_warnings,
                                                         raise_reverse_failure,
                                                         resolve_reverse_setup, reverse_arrays,
                                                         summary_row, yield_strength)
from filmscale.continuum.indentation.reverse.functions import (E_I_DAO, N_RANGE, N_SEARCH_GRID,
                                                               N_STD_LIMIT, NU_I_DAO,
                                                               interpolation_warnings,
                                                               loading_curvature,
                                                               representative_stress,
                                                               sharp_calibration)
from filmscale.continuum.indentation.reverse.uncertainty import monte_carlo_draws, sample_std
from filmscale.core.checks import check_int, check_positive
from filmscale.core.errors import ModelRangeError
from filmscale.core.jsonable import to_jsonable

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
        return to_jsonable(self)

    def summary(self) -> str:
        lines = [f"Dual-indenter reverse analysis ({self.method}), tips {self.tip} + {self.tip2}"
                 + (f", {self.samples} samples" if self.samples else ""),
                 summary_row("E*", self.E_star, self.E_star_std, "Pa"),
                 summary_row("E", self.E, self.E_std, "Pa"),
                 summary_row(f"sigma_{self.eps_r:.3g}", self.sigma_r, self.sigma_r_std, "Pa"),
                 summary_row(f"sigma_{self.eps_r2:.3g}", self.sigma_r2, self.sigma_r2_std, "Pa"),
                 summary_row("n", self.n, self.n_std, ""),
                 summary_row("sigma_y", self.sigma_y, self.sigma_y_std, "Pa")]
        return "\n".join(lines + [f"  warning: {w}" for w in self.warnings])


def dual_reverse_arrays(single, C2, tip, tip2):
    """n and sigma_Y matching the second tip's C2, given the first tip's results (arrays).

    n is searched on [0, 0.5]: for each n, sigma_Y follows from sigma_r of the first tip, and
    C2 predicted by the second tip's Pi1 must equal the measured one. This is the Chollacoop
    ratio equation solved in n instead of sigma_Y (same root for tabulated tips); it also
    serves interpolated angles. No root: the nearer bound; n = 0 when the stress at the larger
    strain is not larger (no hardening).
    """
    from scipy.optimize import elementwise
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
        kg = np.broadcast_to(N_SEARCH_GRID, (idx.size, N_SEARCH_GRID.size))
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
            res = elementwise.find_root(g_of, (N_SEARCH_GRID[j], N_SEARCH_GRID[j + 1]),
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
    (solved in n, see `dual_reverse_arrays`). The tips' strains must differ: 50 or 60 deg
    (eps_r = 0.083, 0.056) pair best with the Berkovich.

    Parameters
    ----------
    C, dPdh, WpWt, h_m
        First tip's curve, as in `dao_reverse` (Pa, N/m, -, m).
    C2 : float
        Loading curvature P/h^2 of the second tip, Pa.
    tip2 : str or Cone
        Second tip: "cone:THETA" with THETA in [50, 80] deg, or a `Cone` with its own
        calibration (eps_r, pi1).
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
    W = check_work_ratio("WpWt", WpWt)
    hm = check_positive("h_m", h_m, "m")
    C2 = check_positive("C2", C2, "Pa")
    stds = (check_std("C_std", C_std, "Pa"), check_std("dPdh_std", dPdh_std, "N/m"),
            check_std("WpWt_std", WpWt_std), check_std("h_m_std", h_m_std, "m"),
            check_std("C2_std", C2_std, "Pa"))
    samples = check_int("samples", samples, 2, 10**7)
    seed = check_int("seed", seed, 0, 2**63 - 1)
    tip, cs, nu, E_i, nu_i, method = resolve_reverse_setup(tip, c_star, nu, E_i, nu_i, method)
    tip2 = sharp_calibration(tip2)
    tip2.require_calibration()
    if abs(tip2.eps_r - tip.eps_r) < 1e-3:
        raise ModelRangeError(f"tips {tip.name} and {tip2.name} share eps_r = {tip.eps_r:.3g}: "
                              "the dual method needs different representative strains")

    def evaluate(c, s, w, h, c2):
        single = reverse_arrays(c, s, w, h, tip=tip, c_star=cs, nu=nu, E_i=E_i, nu_i=nu_i,
                                method=method)
        c2 = np.broadcast_to(np.atleast_1d(np.asarray(c2, dtype=float)), single["n"].shape)
        single["reason"] = np.where(c2 <= 0, 4, single["reason"])
        out = dual_reverse_arrays({k: single[k] for k in ("E_star", "sigma_r", "E", "reason")},
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
        raise_reverse_failure(single, 0, W=W, tip=tip)
    # the single-tip n is superseded by the dual one: only E* and sigma_r warnings apply
    warnings = identifiability_warnings(single, 0, tip, method, C=C, S=S, W=W, hm=hm,
                                        c_star=cs, about_n=False)
    warnings += list(interpolation_warnings(tip2))
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
        draws, dropped = monte_carlo_draws(evaluate_mc, (C, S, W, hm, C2), stds, samples, seed)
        std = {k: sample_std(draws[k]) for k in keys}
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
