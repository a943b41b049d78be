"""Restitution validation: e_y of every contact law and unloading model against Thornton's
closed form and the particle model, with the speed and error of each path from the same run.

Run:  .venv/bin/python benchmarks/restitution_validation.py [--plot FILE.png]

Scene: a rigid sphere, R = 1 mm, of solid-steel mass (7850 kg/m^3, m = 32.9 mg) on a
steel-like half-space (E = 200 GPa, nu = 0.3, sigma_Y = 0.7 GPa); V / V_Y from 1 to 1000 on 25
log-spaced points plus the table's, with V_Y = 15.7 mm/s from `hertz.yield_velocity`
(p0 = C(nu) sigma_Y, docs/physics.md section 2). While delta << R, e depends on V / V_Y alone
except for Jackson-Green, whose area exponent and hardness depend on sigma_Y / E* and a / R.

References (continuum/contact/restitution_fits.py): Thornton's closed form with
p_y = C(nu) sigma_Y (V_y = V_Y) and with p_y = 2.8 sigma_Y (V_y = 3.958 V_Y, the package's
Thornton law). The rms log-difference sqrt(mean(ln(e / e_ref)^2)) runs over the 25 points,
leaving out those whose status is not OK (their count is printed).

Particle model: TLSPH, elastic-perfectly plastic Al (E = 70 GPa, nu = 0.3, sigma_Y = 0.3 GPa),
rigid R = 1 um sphere at 50 m/s of the mass that reaches 0.1 R elastically
(`benchmarks/particles_convergence.py --sweep plastic-impact`): e = 0.211 at R/5 (10 s) and
0.204 at R/7.5 (64 s). The continuum models are evaluated on that scene.

Speed and error: time per e is the fastest of 3 repeats of one vectorised `maxima` call over
the grid, over the number of points (the same for the closed form). Error is the largest
|e_fast - e_time| at V / V_Y = 3, 30 and 300 against `history` at rtol = 1e-10, whose median
time per impact is printed too.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np

from filmscale.continuum import ElasticPlastic, ImpactModel
from filmscale.continuum.contact.hertz import yield_velocity
from filmscale.continuum.contact.laws import LAW_NAMES, contact_law
from filmscale.continuum.contact.restitution import UNLOADING_MODELS
from filmscale.continuum.contact.restitution_fits import thornton_1997, thornton_yield_ratio
from filmscale.continuum.contact.results import OK

STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=0.7e9, name="steel-like")
R = 1e-3
MASS = 7850.0 * 4.0 / 3.0 * np.pi * R**3
TABLE_RATIOS = np.array([1.0, 2.0, 5.0, 10.0, 30.0, 100.0, 300.0, 1000.0])
GRID = np.geomspace(1.0, 1000.0, 25)
CHECK_RATIOS = np.array([3.0, 30.0, 300.0])

AL = ElasticPlastic(E=70e9, nu=0.3, sigma_y=0.3e9, name="Al-pp")
R_PARTICLE, V_PARTICLE = 1e-6, 50.0
#: TLSPH restitution by spacing (docs/impact-model.md, "Restitution validation")
PARTICLE = {"R/5": 0.211, "R/7.5": 0.204}
#: Hertz never yields: it has no unloading model to compare
LAWS = tuple(law for law in LAW_NAMES if law != "hertz")


def e_star(material):
    return material.E / (1.0 - material.nu**2)


def particle_mass():
    """Mass whose elastic Hertz impact at 50 m/s reaches 0.1 R on Al (as the particle run)."""
    return (0.1 * R_PARTICLE)**2.5 * 16 * e_star(AL) * np.sqrt(R_PARTICLE) / (15 * V_PARTICLE**2)


def references(ratio):
    """Thornton's closed form at V / V_Y = ratio for p_y = C sigma_Y and p_y = 2.8 sigma_Y."""
    return {"Thornton, p_y = C sigma_Y": thornton_1997(ratio),
            "Thornton, p_y = 2.8 sigma_Y":
                thornton_1997(ratio / thornton_yield_ratio(2.8, STEEL.nu))}


def best_time(fn, repeats=3):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def run():
    """Every (law, unloading) pair on the grid, the table, the particle scene and the checks."""
    V_Y = float(yield_velocity(MASS, R, e_star(STEEL), STEEL.sigma_y, STEEL.nu))
    ratios = np.union1d(GRID, TABLE_RATIOS)
    on_grid = np.isin(ratios, GRID)
    refs = references(ratios)
    m_p = particle_mass()
    V_Y_p = float(yield_velocity(m_p, R_PARTICLE, e_star(AL), AL.sigma_y, AL.nu))
    rows = []
    for law in LAWS:
        for unloading in UNLOADING_MODELS:
            model = ImpactModel(STEEL, contact_law(law), None, unloading)
            maxima = model.maxima(ratios * V_Y, R, MASS)
            seconds = best_time(lambda: model.maxima(ratios * V_Y, R, MASS)) / ratios.size
            e = np.asarray(maxima.restitution)
            ok = on_grid & (np.asarray(maxima.status) == OK)
            rms = {name: float(np.sqrt(np.mean(np.log(e[ok] / ref[ok])**2)))
                   for name, ref in refs.items()}
            fast = model.maxima(CHECK_RATIOS * V_Y, R, MASS).restitution
            slow, t_slow = [], []
            for V in CHECK_RATIOS * V_Y:
                start = time.perf_counter()
                slow.append(model.history(V, R, MASS, rtol=1e-10).result.restitution)
                t_slow.append(time.perf_counter() - start)
            particle = ImpactModel(AL, contact_law(law), None, unloading).maxima(
                V_PARTICLE, R_PARTICLE, m_p).result().restitution
            rows.append({"law": law, "unloading": unloading,
                         "default": model.law.default_unloading == unloading,
                         "e": e, "status": np.asarray(maxima.status), "rms": rms,
                         "left_out": int(on_grid.sum() - ok.sum()), "seconds": seconds,
                         "error": float(np.max(np.abs(np.asarray(fast) - slow))),
                         "time_seconds": statistics.median(t_slow), "particle": particle})
    fit_seconds = best_time(lambda: thornton_1997(ratios)) / ratios.size
    return {"V_Y": V_Y, "ratios": ratios, "refs": refs, "rows": rows, "fit_seconds": fit_seconds,
            "particle_ratio": V_PARTICLE / V_Y_p}


def print_tables(res):
    ratios, refs, rows = res["ratios"], res["refs"], res["rows"]
    pick = np.isin(ratios, TABLE_RATIOS)
    names = list(refs)
    print(f"V_Y = {res['V_Y'] * 1e3:.2f} mm/s (steel-like, R = 1 mm); particle scene at "
          f"V/V_Y = {res['particle_ratio']:.1f}\n")
    head = ["model", *(f"{r:g}" for r in TABLE_RATIOS), "rms vs T(C)", "rms vs T(2.8)",
            "Al 50 m/s", "us per e", "max err"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name in names:
        e = refs[name][pick]
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in e)
              + f" | - | - | - | {res['fit_seconds'] * 1e6:.2f} | exact |")
    for row in rows:
        label = f"{row['law']} + {row['unloading']}" + (" (default)" if row["default"] else "")
        cells = [f"{v:.3f}" + ("*" if s != OK else "")
                 for v, s in zip(row["e"][pick], row["status"][pick])]
        left = f" ({row['left_out']} left out)" if row["left_out"] else ""
        print(f"| {label} | " + " | ".join(cells)
              + f" | {row['rms'][names[0]]:.3f}{left} | {row['rms'][names[1]]:.3f} | "
              f"{row['particle']:.3f} | {row['seconds'] * 1e6:.0f} | {row['error']:.1e} |")
    print("| particle model (TLSPH) | " + " | ".join("-" for _ in TABLE_RATIOS) + " | - | - | "
          + ", ".join(f"{v:.3f} ({k})" for k, v in PARTICLE.items()) + " | - | - |")
    print("\n* status not OK (2: returns more energy than it took, Kogut-Etsion's jump)\n")
    print("closest unloading model per law (smallest rms log-difference):")
    for name in names:
        for law in LAWS:
            mine = [r for r in rows if r["law"] == law]
            best = min(mine, key=lambda r: r["rms"][name])
            print(f"  vs {name}: {law}: {best['unloading']} ({best['rms'][name]:.3f})")
    print("closest to the particle model (e at the Al scene against "
          f"{PARTICLE['R/7.5']:.3f}):")
    for law in LAWS:
        best = min((r for r in rows if r["law"] == law),
                   key=lambda r: abs(r["particle"] - PARTICLE["R/7.5"]))
        print(f"  {law}: {best['unloading']} ({best['particle']:.3f})")
    print("\ntime integration (rtol 1e-10), median ms per impact: "
          + ", ".join(f"{r['law']}+{r['unloading']} {r['time_seconds'] * 1e3:.0f}"
                      for r in rows))


def plot(res, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratios, grid = res["ratios"], np.isin(res["ratios"], GRID)
    fig, axes = plt.subplots(1, len(UNLOADING_MODELS), figsize=(15, 4.8), sharey=True)
    colours = dict(zip(LAWS, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    for ax, unloading in zip(axes, UNLOADING_MODELS):
        for (name, e), style in zip(res["refs"].items(), ("k-", "k--")):
            ax.plot(ratios, e, style, lw=2.2, label=name.replace("sigma_Y", "σ_Y"))
        for row in (r for r in res["rows"] if r["unloading"] == unloading):
            ok = grid & (row["status"] == OK)
            colour = colours[row["law"]]
            ax.plot(ratios[ok], row["e"][ok], "o-", ms=3, lw=2.8 if row["default"] else 1.2,
                    color=colour, label=row["law"])
            ax.plot(res["particle_ratio"], row["particle"], "x", color=colour, ms=7, mew=2)
        for (spacing, e), marker in zip(PARTICLE.items(), ("s", "D")):
            ax.plot(res["particle_ratio"], e, marker, color="crimson", ms=9, mfc="none",
                    mew=2, label=f"TLSPH {spacing} (Al, 50 m/s)")
        ax.set_xscale("log")
        ax.set_xlabel("V / V_Y")
        ax.set_title(f"unloading: {unloading}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("normal restitution e_y")
    axes[0].set_ylim(0.0, 1.05)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=5, fontsize=9)
    fig.suptitle("Rigid sphere on an elastic-perfectly plastic half-space: lines steel-like "
                 "(σ_Y/E* = 3.2e-3), thick where the unloading is the law's default; "
                 "x: each law on the particle scene")
    fig.tight_layout(rect=(0, 0.13, 1, 1))
    fig.savefig(path, dpi=110)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plot", metavar="FILE.png", help="write the e(V/V_Y) figure")
    args = parser.parse_args(argv)
    res = run()
    print_tables(res)
    if args.plot:
        plot(res, args.plot)
        print(f"\nfigure: {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
