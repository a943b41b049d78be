"""Monte Carlo propagation of input uncertainties through the reverse analysis, with an
explicit seed."""

from __future__ import annotations

import math

import numpy as np

# --- uncertainty ------------------------------------------------------------------------------

def monte_carlo_draws(evaluate, means, stds, samples, seed):
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


def sample_std(values):
    """Sample standard deviation (ddof = 1) of ``values``; NaN for fewer than two."""
    return float(np.std(values, ddof=1)) if values.size > 1 else math.nan
