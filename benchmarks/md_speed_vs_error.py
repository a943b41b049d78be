"""What sets an MD indentation's cost, and what each setting does to the answer.

    .venv/bin/python benchmarks/md_speed_vs_error.py [--store DIR] [--np 2]

Starting from the quick preset (2.2 nm of Cu on Ni(001), CuNi potential, rigid sphere
R = 1.5 nm, 0.8 nm deep at 100 m/s, 4 fs, 10 K, 5.5 nm box), one setting at a time is
changed: the loading speed, the timestep, the temperature, the box's lateral size, and the
seed (the noise floor every other difference is read against). Each run is an MD unit (reused
from the store when finished). For each: the film's E as the pipeline calibrates it
(substrate-aware, rigid tip, fitted zero), the pop-in load, the mean contact pressure at the
largest load (P_max / pi (2 R h - h^2), a hardness at this depth), the atom-steps and the
wall time, and each figure's difference from the preset: a setting that changes a figure by
more than a scene's tolerance has to be paid for; one that does not can be saved. The table
is the one `filmscale.workflows.md_costs` holds and the planner reads.
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
from filmscale.workflows.pipeline_scene import CalibrationSource
from filmscale.workflows.store import done_record
from filmscale.workflows.units import run_unit, unit_curve

#: (label, protocol/slab change) of each run; the first is the quick preset itself
VARIANTS = (
    ("quick preset (100 m/s, 4 fs, 10 K, 5.5 nm)", {}),
    ("seed 2027", {"protocol.seed": 2027}),
    ("speed 200 m/s", {"protocol.speed": 200.0}),
    ("speed 50 m/s", {"protocol.speed": 50.0}),
    ("timestep 2 fs", {"protocol.timestep": 2e-15}),
    ("temperature 100 K", {"protocol.temperature": 100.0}),
    ("box 4.4 nm", {"slab.lateral_size": 4.4e-9}),
)


def _spec(changes: dict):
    data = copy.deepcopy(PRESETS["quick"])
    for key, value in changes.items():
        table, name = key.split(".")
        data[table][name] = value
    return spec_from_mapping(data)


def _figures(curve, R: float, src: CalibrationSource, base: Path, record: dict) -> dict:
    thickness, substrate = src.film(base, record)
    cal = calibrate(curve, nu=record["potential_elastic"]["top"]["nu"], tip_material="rigid",
                    thickness=thickness, substrate=substrate)
    peak = elastic_limit(curve)
    k = int(np.argmax(curve.P))
    h = float(curve.h[k])
    return {"E": cal.E.value, "E_std": cal.E.std,
            "pop_in": float(curve.P[peak]) if peak is not None else math.nan,
            "p_m": float(curve.P[k]) / (math.pi * (2 * R * h - h * h))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--store", default="benchmark_runs/md_speed")
    parser.add_argument("--np", type=int, default=2)
    args = parser.parse_args(argv)
    store = Path(args.store)
    src = CalibrationSource(0, "Cu", "md", ("quick",), args.np, tip_material="rigid")
    rows = []
    for label, changes in VARIANTS:
        spec = _spec(changes)
        start = time.perf_counter()
        path, reused = run_unit(src, spec, store)
        record = done_record(path)
        wall = record["wall_time"] if reused else time.perf_counter() - start
        figures = _figures(unit_curve(path), spec.indenter.tip.R, src, store, record)
        atom_steps = spec.slab_built.n_atoms * spec.protocol.schedule().s_end
        rows.append((label, figures, atom_steps, wall))
    ref = rows[0][1]
    print("MD indentation, quick preset and one change at a time (E: the film's calibrated E; "
          "p_m: mean pressure at the largest load); differences from the preset")
    print(f"{'run':<44}{'E GPa':>14}{'dE':>8}{'pop-in nN':>11}{'d':>8}{'p_m GPa':>9}"
          f"{'d':>8}{'atom-steps':>12}{'wall s':>8}")
    for label, f, atom_steps, wall in rows:
        def rel(key):
            ratio = f[key] / ref[key]
            return f"{ratio - 1:+.1%}" if math.isfinite(ratio) else "-"
        pop = f"{f['pop_in'] * 1e9:.1f}" if math.isfinite(f["pop_in"]) else "none"
        print(f"{label:<44}{f['E'] / 1e9:>7.1f} +- {f['E_std'] / 1e9:<3.1f}{rel('E'):>8}"
              f"{pop:>11}{rel('pop_in'):>8}{f['p_m'] / 1e9:>9.1f}"
              f"{rel('p_m'):>8}{atom_steps:>12.3g}{wall:>8.0f}")


if __name__ == "__main__":
    main()
