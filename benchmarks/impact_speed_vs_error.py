"""Speed against error of the two impact solution paths, and of a 100 x 100 (V, R) map.

Run:  .venv/bin/python benchmarks/impact_speed_vs_error.py [--quick] [--plot FILE.png]

Error is the largest relative error over the maxima (delta_max, force_max, mean_pressure_max,
contact_radius_max, contact_time, restitution) of a set of impacts from elastic to deeply
plastic (V from 0.3 to 150 V_Y), homogeneous and layered, against a tightly converged
reference: the Hertz closed form for the elastic law, else time integration at rtol = 1e-13.
The oblique path in gross slip (mu = 0.1 at 80 degrees) is measured against the rigid-body
closed form e_x = 1 - mu (1 + e_n) / tan(theta), with e_n of the same impact; where the
contact sticks part of the time, against the same path converged (32 000 steps, 3200 springs). The cylinder
(line-contact) paths are measured against their own time integration at rtol 1e-13.
Times are wall-clock medians on this machine; speed and error come from the same run.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from filmscale.continuum import ElasticPlastic, ImpactModel, Layer, LayerStack, elastic_impact
from filmscale.continuum.contact.cylinder import CylinderImpactModel
from filmscale.continuum.contact.hertz import yield_velocity
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import solve_oblique

FIELDS = ("delta_max", "force_max", "mean_pressure_max", "contact_radius_max", "contact_time",
          "restitution")
GLASS = ElasticPlastic(E=90e9, nu=0.25, sigma_y=2.4e9, name="glass")
SLIDER = ElasticPlastic(E=400e9, nu=0.23, name="AlTiC")
MASS = 1.6e-6


def disk():
    mat = lambda n, e, s: ElasticPlastic(E=e, nu=0.3, sigma_y=s, name=n)  # noqa: E731
    return LayerStack([Layer(4e-9, mat("DLC", 200e9, 8e9)), Layer(16e-9, mat("mag", 180e9, 5e9)),
                       Layer(8e-9, mat("IL", 150e9, 3.5e9)), Layer(64e-9, mat("SUL", 130e9, 3e9))],
                      GLASS)


def cases(quick: bool):
    R = 10e-6
    vy = float(yield_velocity(MASS, R, GLASS.reduced_modulus(SLIDER), GLASS.sigma_y, GLASS.nu))
    speeds = vy * np.geomspace(0.3, 150.0, 4 if quick else 8)
    out = [("hertz", "homogeneous", GLASS, v, R) for v in speeds[:2]]
    for law in ("komvopoulos-ye", "komvopoulos-ye-continuous", "jackson-green"):
        for label, target in (("homogeneous", GLASS), ("layered", disk())):
            out += [(law, label, target, v, R) for v in speeds]
    return out


def reference(law, target, V, R):
    if law == "hertz":
        ref = elastic_impact(MASS, R, V, GLASS.reduced_modulus(SLIDER))
        return {k: float(getattr(ref, k)) for k in FIELDS[:-1]} | {"restitution": 1.0}
    res = ImpactModel(target, contact_law(law), SLIDER).history(V, R, MASS, rtol=1e-13).result
    return {k: getattr(res, k) for k in FIELDS}


def rel_error(result, ref) -> float:
    return max(abs(getattr(result, k) / ref[k] - 1.0) for k in FIELDS)


def timed(fn, repeat: int):
    """(median, minimum) wall time of ``repeat`` calls, and the last value. On a shared
    machine the minimum is the stable figure; the median shows the noise."""
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return (statistics.median(times), min(times)), value


def oblique_table(todo, repeat: int) -> None:
    """Oblique impacts in gross slip: time per impact and the largest |e_x - closed form|."""
    mu, theta = 0.1, 80.0
    print("\n| oblique path (gross slip) | setting | ms per impact, homogeneous | "
          "ms per impact, layered | max abs error of e_x |")
    print("|---|---|---|---|---|")
    settings = [("fast", "closed form (Hertz) or time integration", {})]
    settings += [("time", f"{steps} steps, {springs} springs",
                  {"steps": steps, "springs": springs})
                 for steps, springs in ((500, 100), (2000, 400))]
    for path, setting, options in settings:
        errs, times = [], {"homogeneous": [], "layered": []}
        for law, label, target, V, R in todo:
            model = ImpactModel(target, contact_law(law), SLIDER)
            (_, t_min), res = timed(lambda: solve_oblique(model, V, R, MASS, theta, mu,
                                                          path=path, **options), repeat)
            closed = 1 - mu * (1 + res.restitution) / np.tan(np.radians(theta))
            errs.append(abs(res.restitution_tangential - closed))
            times[label].append(t_min)
        print(f"| {path} | {setting} | {statistics.median(times['homogeneous']) * 1e3:.1f} | "
              f"{statistics.median(times['layered']) * 1e3:.1f} | {max(errs):.1e} |",
              flush=True)


def oblique_stick_table(todo, repeat: int) -> None:
    """Oblique impacts that stick part of the time (mu = 0.3, tan(theta) = 0.3 mu and 2.3 mu:
    near full stick and past the reversal of the contact point): time per impact and the
    largest |e_x - reference| against the same path at 32 000 steps and 3200 springs."""
    mu = 0.3
    angles = [float(np.degrees(np.arctan(x * mu))) for x in (0.3, 2.3)]
    picked = [case for case in todo if case[0] in ("hertz", "komvopoulos-ye")][::2]
    refs = {}
    for law, label, target, V, R in picked:
        model = ImpactModel(target, contact_law(law), SLIDER)
        for theta in angles:
            refs[law, label, V, theta] = solve_oblique(
                model, V, R, MASS, theta, mu, path="time", steps=32_000, springs=3200)
    print(f"\n| oblique time path (stick and slip; {len(refs)} impacts) | steps | springs | "
          "ms per impact, homogeneous | ms per impact, layered | max abs error of e_x |")
    print("|---|---|---|---|---|---|")
    for steps, springs in ((250, 50), (500, 100), (1000, 200), (2000, 400), (4000, 800)):
        errs, times = [], {"homogeneous": [], "layered": []}
        for law, label, target, V, R in picked:
            model = ImpactModel(target, contact_law(law), SLIDER)
            for theta in angles:
                (_, t_min), res = timed(lambda: solve_oblique(
                    model, V, R, MASS, theta, mu, path="time", steps=steps, springs=springs),
                    repeat)
                ref = refs[law, label, V, theta]
                errs.append(abs(res.restitution_tangential - ref.restitution_tangential))
                times[label].append(t_min)
        print(f"| MDR spring line | {steps} | {springs} | "
              f"{statistics.median(times['homogeneous']) * 1e3:.1f} | "
              f"{statistics.median(times['layered']) * 1e3:.1f} | {max(errs):.1e} |", flush=True)


def cylinder_table(quick: bool, repeat: int) -> None:
    """Cylinder (line contact, R = 1 mm, L = 5 mm, m = 1 g) on steel and on a 30 um film over
    steel, from elastic to past the fully plastic cap: time per impact and the largest
    relative error against time integration at rtol 1e-13."""
    steel = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9, name="steel")
    film = LayerStack([Layer(30e-6, ElasticPlastic(E=120e9, nu=0.25, sigma_y=0.8e9))], steel)
    fields = ("delta_max", "force_max", "contact_half_width", "contact_time", "restitution")
    speeds = (0.1, 3.0, 10.0) if quick else (0.1, 0.5, 1.0, 3.0, 10.0, 20.0)
    models = {label: CylinderImpactModel(target, 5e-3)
              for label, target in (("homogeneous", steel), ("layered", film))}
    refs = {(label, V): model.history(V, 1e-3, 1e-3, rtol=1e-13).result
            for label, model in models.items() for V in speeds}
    print("\n| cylinder path | setting | ms per impact, homogeneous | ms per impact, layered | "
          "max relative error |")
    print("|---|---|---|---|---|")
    settings = [("energy quadrature", "adaptive, epsrel 1e-12",
                 lambda m, V: m.maxima_adaptive(V, 1e-3, 1e-3)),
                ("energy quadrature", "vectorised fast path, 12 nodes, one point",
                 lambda m, V: m.maxima(V, 1e-3, 1e-3))]
    settings += [("time integration", f"rtol {rtol:.0e}",
                  lambda m, V, rtol=rtol: m.history(V, 1e-3, 1e-3, rtol=rtol).result)
                 for rtol in (1e-6, 1e-8, 1e-10)]
    for path, setting, solve in settings:
        errs, times = [], {"homogeneous": [], "layered": []}
        for label, model in models.items():
            for V in speeds:
                (_, t_min), res = timed(lambda: solve(model, V), repeat)
                ref = refs[label, V]
                errs += [abs(getattr(res, k) / getattr(ref, k) - 1.0) for k in fields]
                times[label].append(t_min)
        print(f"| {path} | {setting} | {statistics.median(times['homogeneous']) * 1e3:.1f} | "
              f"{statistics.median(times['layered']) * 1e3:.1f} | {max(errs):.1e} |",
              flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer impacts and repeats")
    parser.add_argument("--plot", help="write a speed-against-error plot (PNG)")
    args = parser.parse_args(argv)
    repeat = 2 if args.quick else 5
    todo = cases(args.quick)
    print(f"# {len(todo)} impacts; reference: Hertz closed form or time integration at "
          f"rtol 1e-13", flush=True)
    refs = []
    for law, label, target, V, R in todo:
        refs.append(reference(law, target, V, R))
    print(f"# {len(refs)} references computed", file=sys.stderr, flush=True)

    def sweep(path, setting, solve):
        errs, times = [], {"homogeneous": [], "layered": []}
        for (law, label, target, V, R), ref in zip(todo, refs):
            (_, t_min), res = timed(lambda: solve(law, target, V, R), repeat)
            errs.append(rel_error(res, ref))
            times[label].append(t_min)
        print(f"# {path}, {setting}: done", file=sys.stderr, flush=True)
        return (path, setting, statistics.median(times["homogeneous"]),
                statistics.median(times["layered"]), max(errs))

    rows = [sweep("energy quadrature", f"{nodes} nodes",
                  lambda law, target, V, R, nodes=nodes: ImpactModel(
                      target, contact_law(law), SLIDER, quadrature_nodes=nodes)
                  .maxima(V, R, MASS).result())
            for nodes in (6, 8, 12, 16)]
    rows += [sweep("time integration", f"rtol {rtol:.0e}",
                   lambda law, target, V, R, rtol=rtol: ImpactModel(
                       target, contact_law(law), SLIDER).history(V, R, MASS, rtol=rtol).result)
             for rtol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)]

    print("\n(time per impact: median over the impacts of the fastest of the repeats)")
    print("\n| path | setting | ms per impact, homogeneous | ms per impact, layered | "
          "max relative error |")
    print("|---|---|---|---|---|")
    for path, setting, t_h, t_l, err in rows:
        print(f"| {path} | {setting} | {t_h * 1e3:.2f} | {t_l * 1e3:.2f} | {err:.1e} |")

    oblique_table(todo, repeat)
    oblique_stick_table(todo, repeat)
    cylinder_table(args.quick, repeat)

    V = np.geomspace(1e-3, 2.0, 100)
    R = np.geomspace(1e-6, 50e-6, 100)
    rng = np.random.default_rng(20261121)
    print("\n| 100 x 100 (V, R) map of maxima | time (s), fastest | time (s), median | "
          "points computed | max relative error (40 sampled points) |")
    print("|---|---|---|---|---|")
    for law, label, target in (("komvopoulos-ye", "homogeneous", GLASS),
                               ("komvopoulos-ye", "layered", disk()),
                               ("komvopoulos-ye-continuous", "layered", disk()),
                               ("jackson-green", "homogeneous", GLASS)):
        model = ImpactModel(target, contact_law(law), SLIDER)
        model.maxima(V[:3], R[:3], MASS)          # warm-up: first-call imports
        (t_med, t_min), res = timed(lambda: model.maxima(V[None, :], R[:, None], MASS),
                                    3 if args.quick else 7)
        ok = np.argwhere(res.status != 1)
        pick = ok[rng.choice(len(ok), size=min(40, len(ok)), replace=False)]
        err = 0.0
        for i, j in pick:
            ref = model.history(V[j], R[i], MASS, rtol=1e-13).result
            ref = {k: getattr(ref, k) for k in FIELDS}
            err = max(err, rel_error(res.result((i, j)), ref))
        print(f"| {law}, {label} | {t_min:.2f} | {t_med:.2f} | {len(ok)} | {err:.1e} |",
              flush=True)

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
        for path, marker in (("energy quadrature", "o"), ("time integration", "s")):
            sel = [r for r in rows if r[0] == path]
            ax.loglog([r[2] * 1e3 for r in sel], [max(r[4], 1e-16) for r in sel], marker=marker,
                      label=path)
            for r in sel:
                ax.annotate(r[1], (r[2] * 1e3, max(r[4], 1e-16)), fontsize=7)
        ax.set_xlabel("time per impact, homogeneous target (ms)")
        ax.set_ylabel("max relative error")
        ax.legend()
        fig.savefig(Path(args.plot), dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
