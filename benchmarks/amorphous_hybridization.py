"""The ci quench over density against published a-C relations (issue 36): sp3 against density,
the bulk modulus against the mean coordination, and E at the density of measured ta-C.

Each row is `filmscale md amorphous --preset ci --density D` (512 atoms, SiC_tersoff, 1e15 K/s).
Three comparisons, each with its source:

- **K against the mean coordination Z.** Rigidity percolation (He & Thorpe, PRL 54, 2107
  (1985)) puts the onset of a covalent network's rigidity at Z = 2.4, above which the moduli
  grow as (Z - 2.4)^nu; for a-C structures with Brenner's potential the bulk modulus followed
  such a power law of the mean coordination with nu = 1.51 +- 0.17 ("Modeling of amorphous
  carbon structures with arbitrary structural constraints", J. Phys.: Condens. Matter 22,
  395402 (2010)). The fit here: least squares of ln K on ln(Z - 2.4).
- **sp3 against density.** Linear over the range in measurements and simulations (the
  issue's premise); the fit's slope and its rms residual.
- **E at 3.26 g/cm3.** Surface Brillouin scattering of ta-C gave E of about 760 GPa at
  3.26 g/cm3 (Ferrari et al., APL 75, 1893 (1999)).

    .venv/bin/python benchmarks/amorphous_hybridization.py [--out DIR] [--np N]

Runs go to DIR (default: a temporary folder, removed at the end); a finished run there is
read back without LAMMPS.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from filmscale.md.amorphous import amorphous_preset
from filmscale.md.amorphous_run import analyze_amorphous, run_amorphous
from filmscale.md.engine import EngineOptions

DENSITIES = (2.0, 2.4, 2.6, 2.8, 3.0, 3.26)      # g/cm3
#: the rigidity-percolation threshold of the mean coordination (He & Thorpe 1985)
Z_RIGID = 2.4
#: the Brenner-potential exponent of K against Z - 2.4 (JPCM 22, 395402 (2010))
NU_PUBLISHED, NU_PUBLISHED_STD = 1.51, 0.17
#: ta-C by surface Brillouin scattering (Ferrari et al. 1999): density g/cm3, E Pa
FERRARI_DENSITY, FERRARI_E = 3.26, 760e9


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="run folder (default: temporary)")
    parser.add_argument("--np", type=int, default=1, help="MPI ranks per run (default 1)")
    args = parser.parse_args(argv)
    base = amorphous_preset("ci")
    rows = []
    with tempfile.TemporaryDirectory(prefix="aC-hyb-") as tmp:
        root = args.out or Path(tmp)
        for d in DENSITIES:
            print(f"{d:g} g/cm3 ...", file=sys.stderr, flush=True)
            t0 = time.perf_counter()
            run = run_amorphous(dataclasses.replace(base, density=d * 1000.0),
                                root / f"rho_{d:g}", EngineOptions(np=args.np))
            rows.append((d, analyze_amorphous(run), time.perf_counter() - t0))
    report(rows)
    return 0


def report(rows) -> None:
    print("| density (g/cm3) | sp3 | mean Z | K (GPa) | E (GPa) | wall (s) |")
    print("|---|---|---|---|---|---|")
    for d, a, wall in rows:
        print(f"| {d:g} | {a.fractions['sp3']:.3f} | {a.mean_coordination:.3f} | "
              f"{a.elastic.average.K / 1e9:.0f} | {a.elastic.E / 1e9:.0f} | {wall:.0f} |")
    rho = np.array([d for d, _, _ in rows])
    sp3 = np.array([a.fractions["sp3"] for _, a, _ in rows])
    Z = np.array([a.mean_coordination for _, a, _ in rows])
    K = np.array([a.elastic.average.K for _, a, _ in rows])
    slope, icept = np.polyfit(rho, sp3, 1)
    rms = np.sqrt(np.mean((sp3 - (slope * rho + icept)) ** 2))
    print(f"\nsp3 = {slope:.3f} x density (g/cm3) {icept:+.3f}; rms residual {rms:.3f}")
    x, y = np.log(Z - Z_RIGID), np.log(K)
    (nu, lnK0), cov = np.polyfit(x, y, 1, cov=True)
    resid = y - (nu * x + lnK0)
    print(f"K = {np.exp(lnK0) / 1e9:.0f} GPa x (Z - {Z_RIGID})^nu: nu = {nu:.2f} +- "
          f"{np.sqrt(cov[0, 0]):.2f} (published, Brenner: {NU_PUBLISHED} +- "
          f"{NU_PUBLISHED_STD}); rms residual of ln K {np.sqrt(np.mean(resid ** 2)):.3f}")
    E_ta = next((a.elastic.E for d, a, _ in rows if d == FERRARI_DENSITY), None)
    if E_ta is not None:
        print(f"E at {FERRARI_DENSITY} g/cm3: {E_ta / 1e9:.0f} GPa against ta-C's measured "
              f"{FERRARI_E / 1e9:.0f} GPa ({E_ta / FERRARI_E - 1:+.1%})")


if __name__ == "__main__":
    sys.exit(main())
