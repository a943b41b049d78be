"""Speed and error of batch Oliver-Pharr analysis, and the reverse analysis's error table.

Run:  .venv/bin/python benchmarks/indentation_speed.py [--n 10000] [--workers 2] [--quick]

1. Batch: N synthetic Berkovich curves with known E_r, H and unloading exponent (random
   E_r 60-300 GPa, E_r/H 8-25, h_c 10 nm-1 um, m 1.2-1.8, load noise 0-0.5 % of P_max,
   segments not labelled) are written as CSV files in a temporary folder; the time is
   `filmscale indent analyze`'s own path (`analyze_files`: read, detect segments, check,
   fit) on the given worker processes. Error: relative error of E_r and H against the truth,
   from the same run.
2. Error against noise: the same analysis at fixed noise levels.
3. Reverse analysis (Dao et al. 2001): closed form and surrogate against the finite-element
   cases, k-fold cross-validated, and the six Al 6061 indents.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from filmscale.workflows.indent import AnalysisOptions, analyze_files
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.tips import berkovich

TIP = berkovich()


def population(n: int, seed: int, noise=None):
    rng = np.random.default_rng(seed)
    E_r = rng.uniform(60e9, 300e9, n)
    H = E_r / rng.uniform(8.0, 25.0, n)
    h_c = np.exp(rng.uniform(np.log(10e-9), np.log(1e-6), n))
    m = rng.uniform(1.2, 1.8, n)
    noise = rng.uniform(0.0, 0.005, n) if noise is None else np.full(n, noise)
    return E_r, H, h_c, m, noise


def write_curves(folder: Path, params, seed: int) -> list[Path]:
    paths = []
    for k, (E_r, H, h_c, m, noise) in enumerate(zip(*params)):
        c = synthetic_curve(E_r, H, TIP, h_c=h_c, m=m, noise=noise, seed=seed + k,
                            n_load=150, n_hold=30, n_unload=150)
        path = folder / f"c{k:06d}.csv"
        np.savetxt(path, np.column_stack([c.h * 1e9, c.P * 1e6, c.t]), delimiter=",",
                   header="h [nm], P [uN], t [s]", comments="", fmt="%.9g")
        paths.append(path)
    return paths


def errors(records, params):
    E_r, H = params[0], params[1]
    got_E = np.array([r.get("E_r") or np.nan for r in records], dtype=float)
    got_H = np.array([r.get("H") or np.nan for r in records], dtype=float)
    return np.abs(got_E / E_r - 1), np.abs(got_H / H - 1), sum(bool(r["flags"]) for r in records)


def fmt_err(e):
    e = e[np.isfinite(e)]
    return f"{np.median(e):9.2e} {np.percentile(e, 95):9.2e} {e.max():9.2e}"


def batch(n: int, workers: int):
    params = population(n, seed=1)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        paths = write_curves(Path(tmp), params, seed=1000)
        written = time.perf_counter() - t0
        t0 = time.perf_counter()
        records = analyze_files(paths, AnalysisOptions(tip="berkovich"), workers=workers,
                                progress=False)
        elapsed = time.perf_counter() - t0
    eE, eH, flagged = errors(records, params)
    print(f"\n1. Batch analysis of {n} curve files on {workers} worker process(es) "
          f"(files written in {written:.1f} s, not counted)")
    print(f"{'curves':>7} {'seconds':>8} {'ms/curve':>9} | {'E_r err median':>14} "
          f"{'p95':>9} {'max':>9} | {'H err median':>12} {'p95':>9} {'max':>9} | flagged")
    print(f"{n:7d} {elapsed:8.2f} {1e3 * elapsed / n:9.3f} | {fmt_err(eE):>34} | "
          f"{fmt_err(eH):>32} | {flagged}")
    return elapsed


def noise_table(n: int):
    print(f"\n2. Error against load noise ({n} curves per level, one process, in memory)")
    print(f"{'noise/P_max':>11} {'ms/curve':>9} | {'E_r err median':>14} {'p95':>9} {'max':>9} "
          f"| {'H err median':>12} {'p95':>9} {'max':>9}")
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    from filmscale.continuum.indentation import oliver_pharr
    for level in (0.0, 0.001, 0.003, 0.01):
        params = population(n, seed=2, noise=level)
        curves = []
        for k, (E_r, H, h_c, m, noise) in enumerate(zip(*params)):
            c = synthetic_curve(E_r, H, TIP, h_c=h_c, m=m, noise=noise, seed=k,
                                n_load=150, n_hold=30, n_unload=150)
            curves.append((c.h, c.P, c.t))
        t0 = time.perf_counter()
        results = [oliver_pharr(LoadDisplacementCurve(h, P, t), TIP) for h, P, t in curves]
        elapsed = time.perf_counter() - t0
        records = [r.to_dict() for r in results]
        eE, eH, _ = errors(records, params)
        print(f"{level:11.3f} {1e3 * elapsed / n:9.3f} | {fmt_err(eE):>34} | {fmt_err(eH):>32}")


def _pct(value, digits=1):
    return "-" if value is None else f"{100 * value:.{digits}f}%"


def reverse_tables():
    from filmscale.continuum.indentation import reverse

    print("\n3. Reverse analysis against the finite-element cases (Dao framework data): median "
          "and p90 of |relative error| (n: absolute)")
    print(f"{'data':<30} {'method':<32} {'cases':>5} {'C fwd':>6} {'E* med':>7} {'p90':>6} "
          f"{'s_r med':>7} {'p90':>6} {'n med':>6} {'s_y med':>7}")
    for row in reverse.fe_error_table():
        n_med = row["n_median"]
        print(f"{row['file']:<30} {row['method']:<32} {row['cases']:>5} "
              f"{_pct(row['C_median']):>6} {_pct(row['E_star_median']):>7} "
              f"{_pct(row['E_star_p90'], 0):>6} {_pct(row['sigma_r_median']):>7} "
              f"{_pct(row['sigma_r_p90'], 0):>6} "
              f"{'-' if n_med is None else f'{n_med:.3f}':>6} {_pct(row['sigma_y_median']):>7}")
    print()
    print(reverse.cross_validate().summary())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=10_000, help="curves in the batch")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="1000 curves, smaller tables")
    args = parser.parse_args(argv)
    n = 1000 if args.quick else args.n
    batch(n, args.workers)
    noise_table(200 if args.quick else 1000)
    reverse_tables()
    return 0


if __name__ == "__main__":
    sys.exit(main())
