"""Indentation size effect: Nix & Gao, J. Mech. Phys. Solids 46 (1998) 411,
H = H_0 sqrt(1 + h*/h) (docs/physics.md section 9)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from filmscale.core.errors import InputError


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

