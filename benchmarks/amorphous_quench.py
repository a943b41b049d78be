"""Speed against error of the amorphous-carbon quench (issue 36): quench rate, block size and
seed against the sp3 fraction and the block's isotropic E.

Every row is `filmscale md amorphous`'s recipe (`md.amorphous`, SiC_tersoff, 3.0 g/cm3, 6000 K
liquid for 2 ps, 1 ps at 300 K, then the 0 K relaxation and the elastic constants) with one
change from the ci recipe (512 atoms, 1e15 K/s, seed 2026). The seed rows give the scatter
that a difference must exceed to mean anything; the other rows are compared with the slowest
quench of the largest block run here (the reference: no converged value is claimed).

    .venv/bin/python benchmarks/amorphous_quench.py [--out DIR] [--np N] [--quick]

Runs go to DIR (default: a temporary folder, removed at the end); a finished run there is
read back without LAMMPS. ``--quick`` leaves out the 1000-atom and 1e14 K/s rows.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from filmscale.md.amorphous import amorphous_preset
from filmscale.md.amorphous_run import analyze_amorphous, run_amorphous
from filmscale.md.engine import EngineOptions


def rows(quick: bool) -> list[tuple[str, dict]]:
    """(label, the change from the ci recipe)."""
    out = [("ci (512 atoms, 1e15 K/s, seed 2026)", {}),
           ("seed 2027", {"seed": 2027}), ("seed 2028", {"seed": 2028}),
           ("216 atoms", {"n_atoms": 216}), ("3e14 K/s", {"quench_rate": 3e14})]
    if not quick:
        out += [("1000 atoms", {"n_atoms": 1000}), ("1e14 K/s", {"quench_rate": 1e14}),
                ("1000 atoms, 1e14 K/s", {"n_atoms": 1000, "quench_rate": 1e14})]
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="run folder (default: temporary)")
    parser.add_argument("--np", type=int, default=1, help="MPI ranks per run (default 1)")
    parser.add_argument("--quick", action="store_true", help="the five fastest rows only")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="aC-bench-") as tmp:
        root = args.out or Path(tmp)
        base = amorphous_preset("ci")
        results = []
        for k, (label, change) in enumerate(rows(args.quick)):
            recipe = dataclasses.replace(base, **change)
            print(f"[{k + 1}] {label}: {recipe.n_atoms} atoms, "
                  f"{recipe.schedule().total} MD steps ...", file=sys.stderr, flush=True)
            t0 = time.perf_counter()
            run = run_amorphous(recipe, root / f"run_{k}", EngineOptions(np=args.np))
            a = analyze_amorphous(run)
            results.append((label, recipe, a, time.perf_counter() - t0))
        report(results)
    return 0


def report(results) -> None:
    seeds = [a for label, _, a, _ in results if label.startswith(("ci", "seed"))]
    sp3_s = np.std([a.fractions["sp3"] for a in seeds], ddof=1)
    E_s = np.std([a.elastic.E for a in seeds], ddof=1)
    ref_label, _, ref, _ = results[-1]
    print(f"\nreference: the last row ({ref_label}); seed scatter (3 seeds, ci): "
          f"sp3 +- {sp3_s:.3f}, E +- {E_s / 1e9:.0f} GPa\n")
    print("| row | atoms | MD steps | wall (s) | sp3 | sp2 | E (GPa) | nu | K (GPa) | "
          "sp3 - ref | E / ref - 1 | C11-C33 spread |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label, recipe, a, wall in results:
        e = a.elastic
        print(f"| {label} | {recipe.n_atoms} | {recipe.schedule().total} | {wall:.0f} | "
              f"{a.fractions['sp3']:.3f} | {a.fractions['sp2']:.3f} | {e.E / 1e9:.0f} | "
              f"{e.nu:.3f} | {e.average.K / 1e9:.0f} | {a.fractions['sp3'] - ref.fractions['sp3']:+.3f} | "
              f"{e.E / ref.elastic.E - 1:+.1%} | {e.axial_spread:.1%} |")
    if math.isfinite(sp3_s):
        print("\nA difference under twice the seed scatter is not resolved by these runs.")


if __name__ == "__main__":
    sys.exit(main())
