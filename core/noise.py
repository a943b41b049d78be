"""The one noise estimator of the package: white noise on a smooth signal."""

from __future__ import annotations

import math

import numpy as np


def _median(x: np.ndarray) -> float:
    """np.median by selection (np.partition): a batch of curves calls this tens of thousands
    of times, and numpy's median costs several times more on short arrays."""
    n = x.size
    k = n // 2
    if n % 2:
        return float(np.partition(x, k)[k])
    part = np.partition(x, (k - 1, k))
    return 0.5 * float(part[k - 1] + part[k])


def noise_sigma(values) -> float:
    """Robust standard deviation of white noise on a smooth signal (same unit as ``values``).

    Second differences remove a smooth trend (loading, holds, unloading contribute almost
    nothing) and keep the noise: var(x[i+1] - 2 x[i] + x[i-1]) = 6 sigma^2, with the scatter
    of the second differences taken robustly as 1.4826 times their median absolute deviation.
    0 for fewer than three values.
    """
    d2 = np.diff(np.asarray(values, dtype=float), 2)
    if d2.size == 0:
        return 0.0
    return 1.4826 * _median(np.abs(d2 - _median(d2))) / math.sqrt(6.0)
