"""Oblique impact against experiment and finite elements: tables of residuals and a figure.

Run:  .venv/bin/python benchmarks/oblique_validation.py [--plot FILE.png]

References (`filmscale.continuum.contact.reference_data`): Kharaz, Gorham & Salman (2001),
alumina spheres on glass at 3.9 m/s (tangential restitution e_x, rebound angle, spin against
the incidence angle), and Chung & Ooi (2011) test 5, finite elements (the contact point's
normalised recoil y against x = V_t / (mu V_n)). Beside the model: the rigid-body theory
(gross slip, else rolling: e_x = max(1 - mu (1 + e_n) / tan(theta), 1 - 1/(1 + I/(m R^2)))),
which is what a model without tangential compliance gives. Time per impact is the median over
the points of one call each, from the same run.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

from filmscale.continuum import ElasticPlastic, ImpactModel
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import SOLID_SPHERE, solve_oblique
from filmscale.continuum.contact.reference_data import CHUNG_OOI_2011_TEST5, KHARAZ_2001

K = KHARAZ_2001
SPHERE = ElasticPlastic(E=K["sphere"]["E"], nu=K["sphere"]["nu"], sigma_y=100e9, name="alumina")
ANVIL = ElasticPlastic(E=K["anvil"]["E"], nu=K["anvil"]["nu"], sigma_y=30e9, name="glass")
R = K["sphere"]["radius"]
MASS = K["sphere"]["density"] * 4.0 / 3.0 * math.pi * R**3


def kharaz_model(theta: float):
    model = ImpactModel(ANVIL, contact_law("hertz"), SPHERE)
    start = time.perf_counter()
    res = solve_oblique(model, K["speed"] * math.cos(math.radians(theta)), R, MASS, theta,
                        K["friction"])
    return res, time.perf_counter() - start


def rigid_body(theta: float, mu: float, e_n: float = 1.0, j: float = SOLID_SPHERE) -> float:
    tan = math.tan(math.radians(theta))
    return max(1.0 - mu * (1.0 + e_n) / tan, 1.0 - 1.0 / (1.0 + 1.0 / j)) if tan > 0 else 1.0


def fem_model(x: float, nu: float) -> float:
    solid = ElasticPlastic(E=200e9, nu=nu, sigma_y=60e9, name="elastic")
    mu = CHUNG_OOI_2011_TEST5["friction"]
    res = solve_oblique(ImpactModel(solid, contact_law("hertz"), solid), 1.0, 1e-3,
                        7800.0 * 4.0 / 3.0 * math.pi * 1e-9, math.degrees(math.atan(x * mu)), mu)
    return res.restitution_contact_point * x / res.restitution


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the comparison figure (PNG)")
    args = parser.parse_args(argv)
    mu = K["friction"]
    times = []

    print("Kharaz et al. 2001: tangential restitution e_x")
    print("\n| angle (deg) | measured | model | model - measured | rigid body - measured |")
    print("|---|---|---|---|---|")
    for theta, measured in K["restitution_tangential"]:
        res, dt = kharaz_model(theta)
        times.append(dt)
        print(f"| {theta:.1f} | {measured:.3f} | {res.restitution_tangential:.3f} | "
              f"{res.restitution_tangential - measured:+.3f} | "
              f"{rigid_body(theta, mu) - measured:+.3f} |")
    for key, label, unit in (("rebound_angle", "rebound angle", "deg"), ("spin", "spin", "rad/s")):
        print(f"\nKharaz et al. 2001: {label}")
        print(f"\n| angle (deg) | measured ({unit}) | model | model - measured |")
        print("|---|---|---|---|")
        for theta, measured in K[key]:
            res, dt = kharaz_model(theta)
            times.append(dt)
            value = getattr(res, key)
            print(f"| {theta:.1f} | {measured:.2f} | {value:.2f} | {value - measured:+.2f} |")

    print("\nChung & Ooi 2011 test 5 (FEM): normalised recoil y of the contact point")
    nus = CHUNG_OOI_2011_TEST5["poisson_ratios"]
    print(f"\n| x | FEM | model, nu = {nus[0]} | model, nu = {nus[1]} | "
          "distance outside the band |")
    print("|---|---|---|---|---|")
    for x, y in CHUNG_OOI_2011_TEST5["recoil"]:
        ends = [fem_model(x, nu) for nu in nus]
        outside = max(min(ends) - y, y - max(ends), 0.0)
        print(f"| {x:.2f} | {y:+.3f} | {ends[0]:+.3f} | {ends[1]:+.3f} | {outside:.3f} |")
    print(f"\nmedian time per Kharaz impact: {statistics.median(times) * 1e3:.0f} ms")

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
        grid = np.linspace(0.5, 65.0, 60)
        curves = [kharaz_model(t)[0] for t in grid]
        ax = axes[0]
        ax.plot(*zip(*K["restitution_tangential"]), "ko", label="Kharaz et al. 2001")
        ax.plot(grid, [c.restitution_tangential for c in curves], "C0-", label="model")
        ax.plot(grid, [rigid_body(t, mu) for t in grid], "C3--", label="rigid body")
        ax.set_xlabel("incidence angle from the normal (deg)")
        ax.set_ylabel("tangential restitution $e_x$")
        ax.legend()
        ax = axes[1]
        ax.plot(*zip(*K["spin"]), "ko", label="Kharaz et al. 2001")
        ax.plot(grid, [c.spin for c in curves], "C0-", label="model")
        ax.set_xlabel("incidence angle from the normal (deg)")
        ax.set_ylabel("spin after impact (rad/s)")
        ax.legend()
        ax = axes[2]
        xs = np.linspace(0.2, 13.0, 50)
        for nu, style in zip(nus, ("C0-", "C2-")):
            ax.plot(xs, [fem_model(x, nu) for x in xs], style, label=f"model, nu = {nu}")
        ax.plot(*zip(*CHUNG_OOI_2011_TEST5["recoil"]), "ks", label="FEM, Chung & Ooi 2011")
        ax.axhline(0.0, color="0.7", lw=0.8)
        ax.set_xlabel(r"$V_t / (\mu V_n)$")
        ax.set_ylabel(r"$v_c' / (\mu v_n')$")
        ax.legend()
        fig.savefig(args.plot, dpi=110)
        print(f"wrote {args.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
