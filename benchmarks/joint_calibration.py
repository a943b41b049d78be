"""Speed against error of the joint (nanometre + micrometre) calibration of one layer.

Run:  .venv/bin/python benchmarks/joint_calibration.py [--seeds N] [--md-unit DIR]

Synthetic rows: the curves of tests/workflows/test_joint.py, an MD-like 5 nm sphere pushed
2 nm (0.5 % noise, one seed per row) and Berkovich curves at 1, 2 and 5 um, all from
sigma_y = 0.3 GPa sqrt(1 + 2 um / d), E = 130 GPa. Errors against those generating values;
time is the wall clock of the two part calibrations plus `combine`, from the same run.

``--md-unit DIR`` (a finished md-indent unit, e.g. under demo_output/runs after `make demo`)
adds a row for a real MD curve with synthetic Cu Berkovich curves (sigma_y 0.2 GPa,
h* 1.6 um, E 120 GPa, n 0.3 at 0.5-5 um): there is no truth for the joint law, so the row
shows what it gives and whether it calls h* identified.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))    # the tests' curve builders

from tests.workflows import test_joint as tj  # noqa: E402
from tests.workflows.test_calibration import synthetic_sharp_curve  # noqa: E402
from filmscale.continuum.calibration.joint import combine, sharp_part, sphere_part
from filmscale.continuum.calibration.sharp import calibrate_sharp
from filmscale.continuum.calibration.sphere import calibrate_sphere


def joint(md, sharp, nu, md_tip_law=tj.LAW):
    start = time.perf_counter()
    parts = [sphere_part("md", calibrate_sphere(md, nu=nu, law=md_tip_law), [md], md_tip_law),
             sharp_part("um", calibrate_sharp(sharp, nu=nu), sharp, "berkovich")]
    cal = combine(parts, "film")
    return cal, time.perf_counter() - start


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--md-unit", type=Path)
    args = ap.parse_args(argv)
    sharp = tj.sharp_curves()
    print("| curves | sigma_y0 error | h* error | E error | h* identified | md / um rms | "
          "time (s) |")
    print("|---|---|---|---|---|---|---|")
    for seed in range(1, args.seeds + 1):
        cal, wall = joint(tj.md_curve(np.random.default_rng(seed)), sharp, tj.NU)
        rms = [cal.cross_check(1.0, s).rms for s in ("md", "um")]
        print(f"| synthetic, seed {seed} | {cal.sigma_y.value / tj.SY0 - 1:+.2%} | "
              f"{cal.h_star.value / tj.H_STAR - 1:+.2%} | {cal.E.value / tj.E - 1:+.2%} | "
              f"{cal.h_star.identified} | {rms[0]:.2%} / {rms[1]:.2%} | {wall:.3f} |")
    if args.md_unit:
        from filmscale.workflows.units import unit_curve
        md = unit_curve(args.md_unit)
        cu = [synthetic_sharp_curve(120e9, 0.34, 0.2e9 * np.sqrt(1 + 1.6e-6 / d), 0.3, d)[1]
              for d in (0.5e-6, 1e-6, 2e-6, 5e-6)]
        cal, wall = joint(md, cu, 0.34)
        rms = [cal.cross_check(1.0, s).rms for s in ("md", "um")]
        h = cal.h_star
        print(f"| MD {args.md_unit.name} + Cu Berkovich | sigma_y0 "
              f"{cal.sigma_y.value / 1e9:.3g} +- {cal.sigma_y.std / 1e9:.2g} GPa | h* "
              f"{h.value * 1e6:.3g} +- {h.std * 1e6:.2g} um | E {cal.E.value / 1e9:.4g} GPa | "
              f"{h.identified} | {rms[0]:.2%} / {rms[1]:.2%} | {wall:.3f} |" if h else
              f"| MD {args.md_unit.name} + Cu Berkovich | no size effect | | | | | {wall:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
