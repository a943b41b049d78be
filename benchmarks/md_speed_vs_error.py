"""What sets an MD indentation's cost, and what each setting does to the answer.

    .venv/bin/python benchmarks/md_speed_vs_error.py [--store DIR] [--np 2]

Starting from the ci preset (2.2 nm of Cu(001), Mishin potential, rigid sphere R = 0.8 nm,
0.4 nm deep), one setting at a time is changed: the loading speed, the timestep, the
temperature and the box's lateral size. Each run is an MD unit (reused from the store when
finished). For each: the reduced modulus E_r (Hertz before the pop-in, `calibrate` with a rigid
tip), the pop-in load (first load drop), the mean contact pressure at the largest load
(P_max / pi (2 R h - h^2), a hardness at this depth), the atom-steps and the wall time, and
each figure's difference from the ci preset: a setting that changes a figure by more than a
scene's tolerance has to be paid for; one that does not can be saved.
"""

from __future__ import annotations

import argparse
import copy
import math
import time
from pathlib import Path

import numpy as np

from filmscale.continuum.calibration import calibrate
from filmscale.continuum.indentation.spherical import elastic_limit
from filmscale.md.spec import PRESETS, spec_from_mapping
from filmscale.workflows.scene import CalibrationSource
from filmscale.workflows.units import done_record, run_unit, unit_curve

#: (label, protocol/slab change) of each run; the first is the ci preset itself
VARIANTS = (
    ("ci preset (200 m/s, 4 fs, 10 K, 3.7 nm)", {}),
    ("speed 100 m/s", {"protocol.speed": 100.0}),
    ("speed 50 m/s", {"protocol.speed": 50.0}),
    ("timestep 2 fs", {"protocol.timestep": 2e-15}),
    ("temperature 100 K", {"protocol.temperature": 100.0}),
    ("box 5.5 nm", {"slab.lateral_size": 5.5e-9}),
)


def _spec(changes: dict):
    data = copy.deepcopy(PRESETS["ci"])
    for key, value in changes.items():
        table, name = key.split(".")
        data[table][name] = value
    return spec_from_mapping(data)


def _figures(curve, R: float) -> dict:
    cal = calibrate(curve, nu=0.3, tip_material="rigid", law="komvopoulos-ye-continuous")
    peak = elastic_limit(curve)
    k = int(np.argmax(curve.P))
    h = float(curve.h[k])
    return {"E_r": cal.E.value / (1 - 0.3**2),
            "pop_in": float(curve.P[peak]) if peak is not None else math.nan,
            "p_m": float(curve.P[k]) / (math.pi * (2 * R * h - h * h))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--store", default="benchmark_runs/md_speed")
    parser.add_argument("--np", type=int, default=2)
    args = parser.parse_args(argv)
    store = Path(args.store)
    src = CalibrationSource(0, "Cu", "md", ("ci",), args.np, tip_material="rigid")
    rows = []
    for label, changes in VARIANTS:
        spec = _spec(changes)
        start = time.perf_counter()
        path, reused = run_unit(src, spec, store)
        wall = done_record(path)["wall_time"] if reused else time.perf_counter() - start
        figures = _figures(unit_curve(path), spec.indenter.tip.R)
        atom_steps = spec.slab_built.n_atoms * spec.protocol.schedule().s_end
        rows.append((label, figures, atom_steps, wall))
    ref = rows[0][1]
    print("MD indentation, ci preset and one change at a time (E_r: Hertz before the pop-in; "
          "p_m: mean pressure at the largest load); differences from the ci preset")
    print(f"{'run':<40}{'E_r GPa':>9}{'dE_r':>8}{'pop-in nN':>11}{'d':>8}{'p_m GPa':>9}"
          f"{'d':>8}{'atom-steps':>12}{'wall s':>8}")
    for label, f, atom_steps, wall in rows:
        def rel(key):
            ratio = f[key] / ref[key]
            return f"{ratio - 1:+.1%}" if math.isfinite(ratio) else "-"
        pop = f"{f['pop_in'] * 1e9:.1f}" if math.isfinite(f["pop_in"]) else "none"
        print(f"{label:<40}{f['E_r'] / 1e9:>9.1f}{rel('E_r'):>8}"
              f"{pop:>11}{rel('pop_in'):>8}{f['p_m'] / 1e9:>9.1f}"
              f"{rel('p_m'):>8}{atom_steps:>12.3g}{wall:>8.0f}")


if __name__ == "__main__":
    main()
