"""Speed of cylinder (line-contact) impact maps: the vectorised fast path against the
point-by-point adaptive path it replaced (issue 33 item 7), and the agreement of both with the
time integration.

Run:  .venv/bin/python benchmarks/cylinder_map_speed.py [--quick] [--full]

Maps over V = 0.01..60 m/s (log) and R = 0.2..3 mm (log) of a steel cylinder, L = 5 mm,
m = 1 g, on steel ("uniform") and on a 30 um film over steel ("layered"): elastic, contained
plastic, fully plastic and out-of-range points. Columns:

- old: `cylinder_map` as it was, one `CylinderImpactModel.maxima_adaptive` (scipy quad and
  brentq) per point. Timed on a strided sub-grid of at most 6 x 6 points and scaled to the
  map's count ("est."), or on the whole map with --full (minutes: 0.03 s a point uniform,
  0.2 s layered);
- new: `cylinder_map` (one vectorised `CylinderImpactModel.maxima` call), fastest of 3;
  "20 blocks": with a progress callback, as `filmscale impact-map` runs it;
- vs old: the largest relative difference of any map field between the new map and the
  adaptive path, over the sub-grid (the whole map with --full);
- vs time: the largest relative difference of any map field to `CylinderImpactModel.history`
  (solve_ivp, rtol 1e-10) at up to two points of each regime (the residual depth relative to
  the approach).

Times are wall-clock seconds on this machine (fastest of the repeats).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from filmscale.continuum.contact.cylinder import CylinderImpactModel
from filmscale.continuum.contact.impact_map import CYLINDER_UNITS, cylinder_map, grid_map
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack

STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9, name="steel")
FILM = ElasticPlastic(E=120e9, nu=0.25, sigma_y=0.8e9, name="film")
LENGTH, MASS = 5e-3, 1e-3
TARGETS = {"uniform": STEEL, "layered": LayerStack([Layer(30e-6, FILM)], STEEL)}


class _Adaptive:
    """The model with its adaptive, point-by-point maxima: the map as it was computed."""

    def __init__(self, model):
        self.maxima = model.maxima_adaptive


def _old_map(model, velocity, radius):
    from filmscale.continuum.contact.cylinder import REGIME_NAMES
    from filmscale.continuum.contact.impact_map import (CYLINDER_MAP_FIELDS,
                                                        CYLINDER_STATUS_MESSAGES)
    return grid_map(_Adaptive(model), velocity, radius, MASS, kind="cylinder",
                    shape="cylinder", fields=CYLINDER_MAP_FIELDS, units=CYLINDER_UNITS,
                    regime_names=REGIME_NAMES, status_messages=CYLINDER_STATUS_MESSAGES,
                    range_limit="half-width > min(R, d/5)")


def _fastest(fn, repeat):
    best, value = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        best = min(best, time.perf_counter() - start)
    return best, value


def _rel(a, b, scale=None):
    """Largest |a/b - 1| over the finite pairs (|a - b|/scale where ``scale`` is given)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    both = np.isfinite(a) & np.isfinite(b)
    if not both.any():
        return 0.0
    a, b = a[both], b[both]
    den = np.abs(b) if scale is None else np.asarray(scale, float)[both]
    diff = np.abs(a - b)
    return float(np.max(np.where(diff == 0, 0.0, diff / np.where(den > 0, den, 1.0))))


def _vs(values, ref_values, rows, cols):
    """Largest relative difference of every map field at the points (rows, cols)."""
    worst = 0.0
    for key in CYLINDER_UNITS:
        new = values[key][rows, cols]
        scale = values["delta_max"][rows, cols] if key == "residual_depth" else None
        worst = max(worst, _rel(new, ref_values[key], scale))
    return worst


def run(n_v, n_r, label, full, repeat):
    model = CylinderImpactModel(TARGETS[label], LENGTH)
    V, R = np.geomspace(0.01, 60.0, n_v), np.geomspace(2e-4, 3e-3, n_r)
    model.maxima(1.0, 1e-3, MASS)          # imports and first-call costs out of the timing
    t_new, mp = _fastest(lambda: cylinder_map(model, V, R, MASS), repeat)
    t_blocks, _ = _fastest(lambda: cylinder_map(model, V, R, MASS,
                                                progress=lambda *a: None), repeat)
    # the old, point-by-point map: on a strided sub-grid unless --full
    step_v, step_r = (1, 1) if full else (max(1, -(-n_v // 6)), max(1, -(-n_r // 6)))
    vi, ri = np.arange(0, n_v, step_v), np.arange(0, n_r, step_r)
    t_old, old = _fastest(lambda: _old_map(model, V[vi], R[ri]), 1)
    t_old *= (n_v * n_r) / (vi.size * ri.size)
    assert np.array_equal(old.status, mp.status[np.ix_(ri, vi)])
    rows, cols = np.meshgrid(ri, vi, indexing="ij")
    vs_old = _vs(mp.values, {k: old.values[k] for k in CYLINDER_UNITS}, rows, cols)
    # the time path at up to two points of each regime
    picks = [p for g in range(3) for p in np.argwhere(mp.regime == g)[
        np.linspace(0, max((mp.regime == g).sum() - 1, 0), 2).astype(int)]
        if (mp.regime == g).any()]
    picks = list({tuple(p) for p in picks})
    hist = {k: [] for k in CYLINDER_UNITS}
    for i, j in picks:
        res = model.history(V[j], R[i], MASS).result
        for k in CYLINDER_UNITS:
            hist[k].append(getattr(res, k))
    pr, pc = (np.array([p[n] for p in picks]) for n in (0, 1))
    vs_time = _vs(mp.values, {k: np.array(v) for k, v in hist.items()}, pr, pc)
    counts = [int((mp.regime == g).sum()) for g in (-1, 0, 1, 2)]
    old_text = f"{t_old:.1f}" + ("" if full else " est.")
    print(f"| {n_v} x {n_r} | {label} | {old_text} | {t_new:.2f} | {t_blocks:.2f} | "
          f"{t_old / t_new:.0f} | {vs_old:.1e} ({vi.size * ri.size} points) | "
          f"{vs_time:.1e} ({len(picks)} points) | {counts} |", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the 20 x 20 maps only")
    parser.add_argument("--full", action="store_true",
                        help="time the old path on the whole map (minutes)")
    args = parser.parse_args(argv)
    sizes = [(20, 20)] if args.quick else [(20, 20), (100, 100)]
    print("| map (V x R) | target | old point by point (s) | new vectorised (s) | "
          "new, 20 progress blocks (s) | speed-up | max rel. diff. to old | "
          "max rel. diff. to time path | points out / elastic / contained / fully plastic |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n_v, n_r in sizes:
        for label in TARGETS:
            run(n_v, n_r, label, args.full, 3)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
