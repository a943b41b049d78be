"""The bias of E from a sphere law's own elastic branch on deep curves, removed by Sneddon's
exact rigid sphere (`filmscale.continuum.contact.sneddon`).

Run:  .venv/bin/python benchmarks/sneddon_bias.py [--noise 0.005] [--seed 1]

Each curve is calibrated by `calibrate_sphere` twice, with elastic="law" (the law's own
elastic branch: Hertz's paraboloid, Komvopoulos-Ye's truncated sphere) and elastic="sneddon";
the table gives E from each and (E_law - E_sneddon) / E_sneddon. Rows:

- the recorded MD run of the ci preset (tests/md/recorded/ci: Cu, Mishin potential, rigid
  sphere R = 0.8 nm pushed 0.4 nm; no pop-in is detected, so E comes from the law's elastic
  branch), with the contact zero held at h = 0 and fitted (as `calibrate` does for rigid
  tips); nu = 0.3 assumed (it scales both E alike);
- preset-like curves: the exact sphere (E = 130 GPa, nu = 0.3, 200 points) at the R and
  depth of the ci, quick and research presets (`filmscale.md.spec.PRESETS`);
- exact-sphere curves to delta/R = 0.05 ... 0.5 (R = 4 nm), without noise and with
  ``--noise`` x P_max Gaussian load noise.

For the synthetic rows the truth is E = 130 GPa: the "sneddon" column must return it.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from filmscale.continuum.calibration.sphere import calibrate_sphere  # noqa: E402
from filmscale.continuum.contact.sneddon import sneddon_force  # noqa: E402
from filmscale.continuum.indentation.curves import LoadDisplacementCurve  # noqa: E402
from filmscale.continuum.indentation.tips import Sphere  # noqa: E402

E, NU = 130e9, 0.3
RATIOS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5)
LAWS = ("komvopoulos-ye-continuous", "hertz")


def recorded_ci_curve() -> LoadDisplacementCurve:
    """The recorded ci run's curve in SI, as `filmscale.md.run.read_run` builds it."""
    from filmscale.md.engine import parse_table
    from filmscale.md.spec import preset
    from filmscale.md.lammps_units import lammps_to_si
    spec = preset("ci")
    columns, data = parse_table((ROOT / "tests/md/recorded/ci/indent.dat").read_text())
    data = data[np.unique(data[:, 0], return_index=True)[1]]
    col = {name: data[:, i] for i, name in enumerate(columns)}
    return LoadDisplacementCurve(
        h=lammps_to_si(col["depth"], "length"), P=lammps_to_si(col["load"], "force"),
        t=lammps_to_si(col["time"], "time"), segment=spec.protocol.schedule().segment(
            data[:, 0].astype(int)), indenter=spec.indenter.tip,
        meta={"source": "tests/md/recorded/ci"})


def exact_curve(R, depth, noise=0.0, rng=None, points=200) -> LoadDisplacementCurve:
    h = np.linspace(depth / points, depth, points)
    P = sneddon_force(h, R, E / (1 - NU**2))
    if noise:
        P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(points, int), indenter=Sphere(R))


def row(label, curve, law, truth=None, **options):
    R = curve.indenter.R
    depth = float(np.max(curve.h[curve.segment == 0]))
    E_law = calibrate_sphere(curve, nu=NU, law=law, elastic="law", **options).E.value
    E_exact = calibrate_sphere(curve, nu=NU, law=law, elastic="sneddon", **options).E.value
    bias = E_law / E_exact - 1
    err = "" if truth is None else f"{E_exact / truth - 1:+.1e}"
    print(f"| {label} | {law} | {depth / R:.3f} | {E_law / 1e9:.2f} | {E_exact / 1e9:.2f} | "
          f"{bias:+.2%} | {err} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--noise", type=float, default=0.005)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    from filmscale.md.spec import PRESETS

    print("| curve | law | deepest delta/R | E, law's branch (GPa) | E, Sneddon (GPa) | "
          "law vs Sneddon | Sneddon vs truth |")
    print("|---|---|---|---|---|---|---|")
    md = recorded_ci_curve()
    for law in LAWS:
        row("MD ci (recorded), zero at h = 0", md, law)
        row("MD ci (recorded), zero fitted", md, law, fit_zero=True)
    for name, p in PRESETS.items():
        R, depth = p["indenter"]["radius"], p["protocol"]["depth"]
        for law in LAWS:
            row(f"exact sphere, {name} preset (R {R * 1e9:g} nm, {depth * 1e9:g} nm)",
                exact_curve(R, depth), law, E)
    rng = np.random.default_rng(args.seed)
    for ratio in RATIOS:
        for law in LAWS:
            row(f"exact sphere to {ratio:g} R", exact_curve(4e-9, ratio * 4e-9), law, E)
            row(f"exact sphere to {ratio:g} R, {args.noise:.1%} noise",
                exact_curve(4e-9, ratio * 4e-9, args.noise, rng), law, E)


if __name__ == "__main__":
    main()
