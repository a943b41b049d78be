"""Closure of the scale link on real MD: the film E calibrated from the quick preset (2.2 nm of
Cu on Ni(001), substrate-aware) against the E calibrated from a thick homogeneous Cu(001) run
of the same potential and sphere, and both against the potential's own Voigt-Reuss-Hill E.

    .venv/bin/python benchmarks/md_closure.py [--store DIR] [--np 2]

Runs two MD units (142 s and 122 s on 2 cores, measured; finished units in the store are
reused) and prints a table. Each curve is calibrated through `calibrate` (the function the
pipeline and `filmscale calibrate` call) with a rigid tip and the layer's Poisson ratio from
the potential.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from filmscale.continuum.calibration import calibrate
from filmscale.workflows.scene import CalibrationSource
from filmscale.workflows.units import done_record, run_unit, unit_curve

#: the quick preset's Cu film made a thick homogeneous Cu block: same potential, sphere,
#: protocol and lateral size; 5 nm of Cu under the surface instead of 2.2 nm on Ni
THICK_CU = """
name = "thick-cu001"
[potential]
name = "CuNi"
[slab]
orientation = "001"
lateral_size = 5.5e-9
films = []
substrate = { element = "Cu", thickness = 5e-9 }
[indenter]
shape = "sphere"
radius = 1.5e-9
[protocol]
depth = 8e-10
speed = 100.0
timestep = 4e-15
equilibration_time = 1e-12
hold_time = 1e-12
record_every = 10
restart_every = 1000
seed = 2026
"""


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--store", default="benchmark_runs/md_closure")
    parser.add_argument("--np", type=int, default=2)
    args = parser.parse_args(argv)
    store = Path(args.store)
    base = store / "specs"
    base.mkdir(parents=True, exist_ok=True)
    rows = []
    (base / "thick.toml").write_text(THICK_CU)
    for label, name in (("Cu 2.2 nm on Ni (quick)", "quick"), ("thick Cu", "thick.toml")):
        src = CalibrationSource(0, "Cu", "md", (name,), args.np, tip_material="rigid")
        start = time.perf_counter()
        path, reused = run_unit(src, src.spec(base), store)
        wall = time.perf_counter() - start
        record = done_record(path)
        curve = unit_curve(path)
        vrh = record["potential_elastic"]["top"]
        nu = vrh["nu"]
        film = record.get("film")
        aware = calibrate(curve, nu=nu, tip_material="rigid", layer="Cu",
                          **({"thickness": film["thickness"],
                              "substrate": src.film(base, record)[1]} if film else {}))
        alone = calibrate(curve, nu=nu, tip_material="rigid", layer="Cu")
        rows.append((label, aware, alone, vrh["E"], wall, reused))
    print("Film E from MD curves (rigid sphere R = 1.5 nm, 0.8 nm deep, CuNi potential), "
          "against the potential's Voigt-Reuss-Hill E of Cu")
    print(f"{'run':<26}{'E (substrate-aware)':>22}{'E (half-space fit)':>21}{'VRH E':>10}"
          f"{'aware/VRH':>11}{'run s':>8}")
    for label, aware, alone, vrh, wall, reused in rows:
        print(f"{label:<26}{aware.E.value / 1e9:>13.1f} +- {aware.E.std / 1e9:<4.1f}GPa"
              f"{alone.E.value / 1e9:>14.1f} GPa{vrh / 1e9:>7.1f}{aware.E.value / vrh:>11.3f}"
              f"{'reused' if reused else f'{wall:.0f}':>8}")
    film, thick = rows[0][1].E.value, rows[1][1].E.value
    print(f"film (substrate-aware) / thick Cu: {film / thick:.3f}; film (half-space fit) / "
          f"thick Cu: {rows[0][2].E.value / thick:.3f}")


if __name__ == "__main__":
    main()
