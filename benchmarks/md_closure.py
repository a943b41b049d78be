"""Closure of the scale link on real MD: the film E calibrated from the quick preset (2.2 nm of
Cu on Ni(001), substrate-aware) against the E calibrated from a thick homogeneous Cu(001) run
of the same potential and sphere, and both against the potential's own Voigt-Reuss-Hill E.

    .venv/bin/python benchmarks/md_closure.py [--store DIR] [--np 2] [--causes]

Runs two MD units (about 2 min each on 2 cores; finished units in the store are reused) and
prints a table. Each curve is calibrated through `calibrate` (the function the pipeline and
`filmscale calibrate` call) with a rigid tip and the layer's Poisson ratio from the potential.

``--causes`` also separates what sets the elastic segment of the thick Cu run: the fix indent
wall constant K (10, 100, 1000 eV/A^3), the surface orientation ((001) against (111), each
against its own indentation modulus) and the Hertz range (to half the pop-in load, as the
calibration takes it, or up to the burst); three more runs, and a figure of the apparent
modulus P / (4/3 sqrt(R) h^1.5) against depth, ``STORE/elastic_segment.png``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from filmscale.continuum.calibration import calibrate
from filmscale.continuum.calibration.sphere import HERTZ_FRACTION, calibrate_sphere
from filmscale.continuum.indentation.spherical import loading_points
from filmscale.md.lammps_units import lammps_to_si
from filmscale.workflows.pipeline_scene import CalibrationSource
from filmscale.workflows.store import done_record
from filmscale.workflows.units import run_unit, unit_curve

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
    parser.add_argument("--causes", action="store_true",
                        help="also vary K and the orientation of the thick Cu run")
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
        rows.append((label, aware, alone, vrh, wall, reused))
    print("Film E from MD curves (rigid sphere R = 1.5 nm, 0.8 nm deep, CuNi potential), "
          "against the potential's Voigt-Reuss-Hill E of Cu and its (001) indentation "
          "modulus M (Vlassak & Nix 1994)")
    print(f"{'run':<26}{'E (substrate-aware)':>22}{'E (half-space fit)':>21}{'VRH E':>8}"
          f"{'E/VRH':>8}{'M(001)':>8}{'E*/M':>7}{'run s':>8}")
    for label, aware, alone, vrh, wall, reused in rows:
        E_star = aware.E.value / (1 - vrh["nu"]**2)
        print(f"{label:<26}{aware.E.value / 1e9:>13.1f} +- {aware.E.std / 1e9:<4.1f}GPa"
              f"{alone.E.value / 1e9:>14.1f} GPa{vrh['E'] / 1e9:>8.1f}"
              f"{aware.E.value / vrh['E']:>8.3f}{vrh['M'] / 1e9:>8.1f}{E_star / vrh['M']:>7.3f}"
              f"{'reused' if reused else f'{wall:.0f}':>8}")
    film, thick = rows[0][1].E.value, rows[1][1].E.value
    print(f"film (substrate-aware) / thick Cu: {film / thick:.3f}; film (half-space fit) / "
          f"thick Cu: {rows[0][2].E.value / thick:.3f}")
    if args.causes:
        causes(store, base, args.np)


#: (label, wall constant in eV/A^3, orientation) of the thick Cu runs that separate causes
VARIANTS = (("K 10 eV/A^3, (001)", 10.0, "001"), ("K 100 eV/A^3, (001)", 100.0, "001"),
            ("K 1000 eV/A^3, (001)", 1000.0, "001"), ("K 100 eV/A^3, (111)", 100.0, "111"))


def causes(store: Path, base: Path, ranks: int) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    fig, ax = plt.subplots(figsize=(7, 4.5))
    print(f"\nThick Cu: what sets the elastic segment. E* = E / (1 - nu^2) over the "
          f"indentation modulus M of the surface, Hertz to {HERTZ_FRACTION:g} of the pop-in "
          "load with the depth zero fixed and fitted (the default for a rigid tip), and with "
          "the zero fitted up to the burst")
    print(f"{'run':<24}{'M GPa':>7}{'fixed zero':>12}{'fitted':>16}{'h0 A':>7}{'to burst':>10}"
          f"{'pop-in nN':>11}{'run s':>8}")
    for label, K, orientation in VARIANTS:
        name = f"thick-K{K:g}-{orientation}.toml"
        text = THICK_CU.replace('orientation = "001"', f'orientation = "{orientation}"')
        text = text.replace("radius = 1.5e-9", f"radius = 1.5e-9\nK = "
                            f"{float(lammps_to_si(K, 'indent_constant'))!r}")
        (base / name).write_text(text)
        src = CalibrationSource(0, "Cu", "md", (name,), ranks, tip_material="rigid")
        start = time.perf_counter()
        path, reused = run_unit(src, src.spec(base), store)
        wall = time.perf_counter() - start
        curve, top = unit_curve(path), done_record(path)["potential_elastic"]["top"]
        fixed, fitted, burst = (calibrate_sphere(curve, nu=top["nu"], hertz_fraction=f,
                                                 fit_zero=z)
                                for f, z in ((HERTZ_FRACTION, False), (HERTZ_FRACTION, True),
                                             (1.0, True)))
        h, P, pop = loading_points(curve, with_pop_in=True)
        ratio = [c.E.value / (1 - top["nu"]**2) / top["M"] for c in (fixed, fitted, burst)]
        std = fitted.E.std / fitted.E.value * ratio[1]
        print(f"{label:<24}{top['M'] / 1e9:>7.1f}{ratio[0]:>12.3f}{ratio[1]:>10.3f} +- "
              f"{std:.3f}{fitted.contact_zero * 1e10:>7.2f}{ratio[2]:>10.3f}"
              f"{(P[pop] * 1e9 if pop is not None else float('nan')):>11.1f}"
              f"{'reused' if reused else f'{wall:.0f}':>8}")
        shown = h > 0.5e-10
        modulus = P[shown] / (4 / 3 * np.sqrt(curve.indenter.R) * h[shown]**1.5) / top["M"]
        ax.plot(h[shown] * 1e10, modulus, lw=1, label=label)
    ax.axhline(1.0, color="k", ls="--", lw=0.8)
    ax.set_xlabel("depth h (angstrom)")
    ax.set_ylabel("P / (4/3 sqrt(R) h^1.5) / M")
    ax.set_title("thick Cu, R = 1.5 nm: apparent modulus over the indentation modulus")
    ax.set_ylim(0.3, 1.6)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(store / "elastic_segment.png", dpi=100)
    print(f"figure: {store / 'elastic_segment.png'}")


if __name__ == "__main__":
    main()
