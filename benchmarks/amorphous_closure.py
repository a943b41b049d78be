"""The closure of issue 36 on finished a-C film indentations: the film's E, calibrated
substrate-aware, against its own block's E, beside what the slab's rigid base does to it.

For each record (the indent.h5 of `filmscale md indent` on a spec whose top film is amorphous):

- **block E**: the block's own isotropic E (its record, named by the spec's film);
- **film E**: `filmscale calibrate RECORD` (the film on its diamond substrate, the film's own
  Hill nu from the record), and its ratio to the block's;
- **base**: the excess the calibration states for the slab's fixed atoms (first order,
  Boussinesq; docs/pipeline.md, "A rigid base under a simulated sample");
- **sigma_y seen**: whether the calibration found the curve yielding (an F test: the
  elastic-plastic law beats the elastic one by more than noise), which moves E with it;
- **base-corrected E**: the same calibration of the curve with each approach h moved to
  h + c P, c = (1 + nu)(3 - 2 nu) / (2 pi E H) with the substrate's E and nu and H the base's
  depth: what the film reads once the base's first-order stiffening is taken out.

    .venv/bin/python benchmarks/amorphous_closure.py RUN/indent.h5 [...]

The records are made with `filmscale md indent examples/md/aC_on_diamond_quick.toml --np 2
--out RUN` (one per quench seed: `seed = N` in its `[[slab.films]]`; docs/amorphous.md,
"Closure"). Reads only: no LAMMPS.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import sys

import h5py
import numpy as np

from filmscale.continuum.calibration.route import calibrate
from filmscale.continuum.indentation.io import read_curves
from filmscale.md.amorphous_run import read_amorphous_summary
from filmscale.workflows.calibrate_cli import record_film


def base_depth(path: str) -> float:
    with h5py.File(path, "r") as f:
        spec = json.loads(f["inputs/spec.json"][()])
        return float(f.attrs["z_surface"]) - spec["slab"]["fixed_thickness"]


def block_E(path: str) -> float:
    with h5py.File(path, "r") as f:
        spec = json.loads(f["inputs/spec.json"][()])
    return read_amorphous_summary(spec["slab"]["films"][0]["block"]["source"])["E"]


def row(path: str) -> dict:
    film = record_film(path)
    substrate = film.substrate()
    curve = next(iter(read_curves(path).values()))
    H = base_depth(path)
    curve = dataclasses.replace(curve, meta={**curve.meta, "base_depth": H})
    options = dict(nu=film.nu, tip_material="rigid", thickness=film.thickness,
                   substrate=substrate)
    cal = calibrate(curve, **options)
    c = ((1 + substrate.nu) * (3 - 2 * substrate.nu)
         / (2 * math.pi * substrate.E * H))
    moved = dataclasses.replace(curve, h=curve.h + c * np.clip(curve.P, 0.0, None),
                                meta={k: v for k, v in curve.meta.items() if k != "base_depth"})
    corrected = calibrate(moved, **options)
    note = next((w for w in cal.warnings if "rigid base" in w), "")
    stated = re.search(r"E reads at least about ([\d.]+)% high", note)
    return {"record": path, "block_E": block_E(path), "E": cal.E.value, "E_std": cal.E.std,
            "base_excess": float(stated.group(1)) / 100 if stated else math.nan,
            "E_base_corrected": corrected.E.value, "nu": film.nu, "base_depth": H,
            "yield": cal.sigma_y.identified, "yield_base_corrected": corrected.sigma_y.identified}


def main(paths: list[str]) -> None:
    rows = [row(p) for p in paths]
    print("| record | block E (GPa) | film E (GPa) | / block | sigma_y seen | base: E high by | "
          "base-corrected E (GPa) | / block | sigma_y seen |")
    print("|---|---|---|---|---|---|---|---|---|")
    seen = {True: "yes", False: "no"}
    for r in rows:
        print(f"| {r['record']} | {r['block_E'] / 1e9:.0f} | {r['E'] / 1e9:.0f} +- "
              f"{r['E_std'] / 1e9:.0f} | {r['E'] / r['block_E']:.3f} | {seen[r['yield']]} | "
              f"{r['base_excess']:.1%} | {r['E_base_corrected'] / 1e9:.0f} | "
              f"{r['E_base_corrected'] / r['block_E']:.3f} | "
              f"{seen[r['yield_base_corrected']]} |")
    if len(rows) > 1:
        for key, name in (("E", "film"), ("E_base_corrected", "base-corrected")):
            ratio = np.array([r[key] / r["block_E"] for r in rows])
            print(f"{name} E / block E over {len(rows)} records: {ratio.mean():.3f} +- "
                  f"{ratio.std(ddof=1):.3f} (sample std), standard error "
                  f"{ratio.std(ddof=1) / math.sqrt(len(rows)):.3f}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: amorphous_closure.py RUN/indent.h5 [...]")
    main(sys.argv[1:])
