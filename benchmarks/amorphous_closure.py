"""The closure of issue 36 on finished a-C film indentations: the film's E, calibrated
substrate-aware, against its own block's E, beside what the slab's rigid base does to it.

For each record (the indent.h5 of `filmscale md indent` on a spec whose top film is amorphous):

- **block E**: the block's own isotropic E (its record, named by the spec's film);
- **film E, base in the model**: `filmscale calibrate RECORD` (the film on its diamond
  substrate, the film's own Hill nu from the record): the exact elastic branch holds the
  slab's substrate on its rigid base, the fixed atoms H under the surface
  (docs/pipeline.md, "A rigid base under a simulated sample"); and its ratio to the block's;
- **film E, half-space substrate**: the same calibration with the base left out of the
  curve's meta (the film on a diamond half-space), as calibrations read before the base was
  modelled;
- **sigma_y seen**: whether the calibration found the curve yielding (an F test: the
  elastic-plastic law beats the elastic one by more than noise), which moves E with it.

    .venv/bin/python benchmarks/amorphous_closure.py RUN/indent.h5 [...]

The records are made with `filmscale md indent examples/md/aC_on_diamond_quick.toml --np 2
--out RUN` (one per quench seed: `seed = N` in its `[[slab.films]]`; docs/amorphous.md,
"Closure"). Reads only: no LAMMPS.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys

import h5py
import numpy as np

from filmscale.continuum.calibration.route import calibrate
from filmscale.continuum.indentation.io import read_curves
from filmscale.md.amorphous_run import read_amorphous_summary
from filmscale.workflows.calibrate_cli import record_film


def slab_facts(path: str) -> tuple[float, float]:
    """The record's rigid base depth (m: the surface less the fixed atoms) and its film's
    block E (Pa), from one read of the record."""
    with h5py.File(path, "r") as f:
        spec = json.loads(f["inputs/spec.json"][()])
        H = float(f.attrs["z_surface"]) - spec["slab"]["fixed_thickness"]
    return H, read_amorphous_summary(spec["slab"]["films"][0]["block"]["source"])["E"]


def row(path: str) -> dict:
    film = record_film(path)
    substrate = film.substrate()
    curve = next(iter(read_curves(path).values()))
    H, block_E = slab_facts(path)
    options = dict(nu=film.nu, tip_material="rigid", thickness=film.thickness,
                   substrate=substrate)
    cal = calibrate(dataclasses.replace(curve, meta={**curve.meta, "base_depth": H}), **options)
    free = calibrate(dataclasses.replace(
        curve, meta={k: v for k, v in curve.meta.items() if k != "base_depth"}), **options)
    return {"record": path, "block_E": block_E, "E": cal.E.value, "E_std": cal.E.std,
            "base_in_model": any("exact layered solution" in w and "rigid base" in w
                                 for w in cal.warnings),
            "E_half_space": free.E.value, "E_half_space_std": free.E.std,
            "nu": film.nu, "base_depth": H, "yield": cal.sigma_y.identified,
            "yield_half_space": free.sigma_y.identified}


def main(paths: list[str]) -> None:
    rows = [row(p) for p in paths]
    print("| record | base depth (nm) | block E (GPa) | film E, base in the model (GPa) | "
          "/ block | sigma_y seen | film E, half-space substrate (GPa) | / block | "
          "sigma_y seen |")
    print("|---|---|---|---|---|---|---|---|---|")
    seen = {True: "yes", False: "no"}
    for r in rows:
        modelled = "" if r["base_in_model"] else " (base not modelled)"
        print(f"| {r['record']} | {r['base_depth'] * 1e9:.2f} | {r['block_E'] / 1e9:.0f} | "
              f"{r['E'] / 1e9:.0f} +- {r['E_std'] / 1e9:.0f}{modelled} | "
              f"{r['E'] / r['block_E']:.3f} | {seen[r['yield']]} | "
              f"{r['E_half_space'] / 1e9:.0f} +- {r['E_half_space_std'] / 1e9:.0f} | "
              f"{r['E_half_space'] / r['block_E']:.3f} | {seen[r['yield_half_space']]} |")
    if len(rows) > 1:
        for key, name in (("E", "base in the model"), ("E_half_space", "half-space substrate")):
            ratio = np.array([r[key] / r["block_E"] for r in rows])
            print(f"film E / block E, {name}, over {len(rows)} records: {ratio.mean():.3f} +- "
                  f"{ratio.std(ddof=1):.3f} (sample std), standard error "
                  f"{ratio.std(ddof=1) / math.sqrt(len(rows)):.3f}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: amorphous_closure.py RUN/indent.h5 [...]")
    main(sys.argv[1:])
