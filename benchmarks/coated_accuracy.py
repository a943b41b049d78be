"""Accuracy and cost of the layered (film on substrate) sphere contact approximations against
the converged solution `continuum.contact.coated.coated_solution`.

Run:  .venv/bin/python benchmarks/coated_accuracy.py [--quick] [--convergence]

For a rigid sphere (paraboloid, R = 1 mm) on a film of t = 1 um bonded to a substrate
(E_s = 70 GPa; nu = 0.3 for both), at contact radii a/t = 0.1 ... 30 of the exact solution:

- Gao: the weighting the package applies (`StackProfile.properties(delta, R)`: the Gao-weighted
  plane-strain modulus at a = sqrt(R delta)), with Hertz's load at that modulus
  (`hertz.hertz_force_unchecked`). Load error at the exact approach delta; approach error at the
  exact load P (the Gao approach that gives P). And as a stiffness model: Gao's modulus at
  the exact contact radius (delta = a^2/R in `properties`) against the flat punch's S/(2a)
  (`apparent_modulus`).
- two-term: the form `coated.py` used before the converged solution (pressure restricted to
  (1 - r^2/a^2)^(1/2) and ^(3/2) terms fitted by least squares to the sphere's displacement;
  `two_term` below, the former `coated_contact` verbatim), compared the same way (its load
  at the approach delta, its approach at the load P, by root finding in its contact radius).

N is the node count of the converged solution; the times are per call on one thread (OpenBLAS
limited to one thread so that a shared machine gives repeatable numbers): the exact solution
with its Phi table cached (cold: with the table built), the two-term form, the Gao load.
Everything is dimensionless in a/t and the modulus ratio (R and t only set the scale).

--convergence prints the relative change of the exact load and flat-punch stiffness with the
Gauss-Legendre nodes per panel (4, 8, 16 against 32) instead.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import math
import time

import numpy as np
from scipy.optimize import brentq
from scipy.special import gamma, j0, jv

from filmscale.continuum.contact import coated
from filmscale.continuum.contact.hertz import hertz_force_unchecked
from filmscale.continuum.contact.profiles import StackProfile
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack

R, T, E_SUB, NU = 1e-3, 1e-6, 70e9, 0.3
RATIOS = (1 / 40, 1 / 5.7, 5.7, 100.0)
LAMBDAS = (0.1, 0.3, 1.0, 3.0, 10.0, 30.0)


def _transform(k, a, nu):
    """Zeroth-order Hankel transform of (1 - r^2/a^2)^nu on r < a."""
    return a * a * 2**nu * gamma(nu + 1) * jv(nu + 1, k * a) / (k * a)**(nu + 1)


def _homogeneous(r, a, nu, E_p):
    """Surface displacement of a homogeneous half-space under (1 - r^2/a^2)^nu, r <= a."""
    if nu == 0.5:
        return math.pi * (2 * a * a - r * r) / (4 * a * E_p)
    return 3 * math.pi * (8 * a**4 - 8 * a * a * r * r + 3 * r**4) / (64 * a**3 * E_p)


def two_term(a, R, thickness, film, substrate):
    """(delta, P) of the former two-term least-squares form (24 collocation points,
    trapezoidal wavenumber sum of C - 1 up to k t = 60)."""
    E_p = film.plane_strain_modulus
    r = np.linspace(0.0, a, 24)
    dk = 0.05 / max(a, thickness)
    k = np.arange(0.5 * dk, 60.0 / thickness, dk)
    correction = coated._kernel(k * thickness, film, substrate) - 1.0
    bessel = j0(np.outer(r, k))
    nus = (0.5, 1.5)
    cols = [_homogeneous(r, a, nu, E_p)
            + (2 / E_p) * np.trapezoid(bessel * (_transform(k, a, nu) * correction), k, axis=1)
            for nu in nus]
    A = np.column_stack([c * (E_p / a) for c in cols] + [-np.ones_like(r)])
    x, *_ = np.linalg.lstsq(A, -r * r / (2 * R * a), rcond=None)
    load = math.pi * a * a * E_p * sum(c / (nu + 1) for c, nu in zip(x[:-1], nus))
    return float(x[-1] * a), float(load)


def timed(fn, *args, repeat=3):
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args)
        best = min(best, time.perf_counter() - t0)
    return out, best


def root_in_log(fn, target, guess):
    """x > 0 with fn(x) = target for an increasing fn, bracketed from ``guess`` outwards."""
    def gap(s):
        return math.log(fn(math.exp(s)) / target)
    lo = hi = math.log(guess)
    while gap(lo) > 0:
        lo -= 0.5
    while gap(hi) < 0:
        hi += 0.5
    return math.exp(lo if lo == hi else brentq(gap, lo, hi, xtol=1e-12, rtol=1e-13))


def materials(ratio):
    # finite strengths: StackProfile also weights sigma_y (irrelevant here). The ratio 100
    # makes a 7 TPa film, stiffer than any solid: a dimensionless study, so the film is made
    # unchecked for plausibility, as a fit's trial material is
    return (ElasticPlastic._trial(ratio * E_SUB, NU, 1e9, name="film"),
            ElasticPlastic(E_SUB, NU, 1e9, name="substrate"))


def row(ratio, lam):
    film, sub = materials(ratio)
    a = lam * T
    coated._solve_cached.cache_clear()
    coated._phi_table.cache_clear()
    t0 = time.perf_counter()
    coated.coated_solution(a, R, T, film, sub)
    cold = time.perf_counter() - t0

    def exact():
        coated._solve_cached.cache_clear()
        return coated.coated_solution(a, R, T, film, sub)
    sol, t_exact = timed(exact)
    delta, P = sol.delta, sol.load

    profile = StackProfile(LayerStack((Layer(T, film),), sub))

    def gao(d):
        return float(hertz_force_unchecked(d, R, profile.properties(d, R)[0]))
    P_gao, t_gao = timed(gao, delta)
    d_gao = root_in_log(gao, P, delta)
    # as a stiffness model: Gao's modulus at the contact radius a against S/(2a)
    gao_modulus = float(profile.properties(a * a / R, R)[0]) / (0.5 * sol.stiffness / a) - 1

    (d_same, P_same), t_two = timed(two_term, a, R, T, film, sub)
    a_d = root_in_log(lambda r: two_term(r, R, T, film, sub)[0], delta, a)
    P_two = two_term(a_d, R, T, film, sub)[1]
    a_p = root_in_log(lambda r: two_term(r, R, T, film, sub)[1], P, a)
    d_two = two_term(a_p, R, T, film, sub)[0]
    return {"N": sol.nodes, "gao_P": P_gao / P - 1, "gao_d": d_gao / delta - 1,
            "gao_S": gao_modulus, "two_P": P_two / P - 1, "two_d": d_two / delta - 1,
            "two_a": (d_same / delta - 1, P_same / P - 1),
            "t_exact": t_exact, "t_cold": cold, "t_two": t_two, "t_gao": t_gao}


def name_of(ratio):
    return f"1/{1 / ratio:g}" if ratio < 1 else f"{ratio:g}"


def accuracy(lambdas):
    print("| E_f/E_s | a/t | N | Gao P(delta) | Gao delta(P) | Gao E'(a) vs S/2a | "
          "two-term P(delta) | two-term delta(P) | two-term at a: delta, P | exact ms (cold) "
          "| two-term ms | Gao ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for ratio in RATIOS:
        for lam in lambdas:
            r = row(ratio, lam)
            print(f"| {name_of(ratio)} | {lam:g} | {r['N']} | {100 * r['gao_P']:+.1f} % | "
                  f"{100 * r['gao_d']:+.1f} % | {100 * r['gao_S']:+.1f} % | "
                  f"{100 * r['two_P']:+.2f} % | "
                  f"{100 * r['two_d']:+.2f} % | {100 * r['two_a'][0]:+.1f} %, "
                  f"{100 * r['two_a'][1]:+.1f} % | {1e3 * r['t_exact']:.1f} "
                  f"({1e3 * r['t_cold']:.0f}) | {1e3 * r['t_two']:.1f} | "
                  f"{1e3 * r['t_gao']:.2f} |", flush=True)


def convergence(lambdas):
    """|P_n / P_32 - 1| and |S_n / S_32 - 1| with n Gauss-Legendre nodes per panel."""
    per_panel = (4, 8, 16, 32)
    print("| E_f/E_s | a/t | panels | " + " | ".join(f"n = {n}: P, S" for n in per_panel[:-1])
          + " |")
    print("|---|---|---|" + "---|" * (len(per_panel) - 1))
    for ratio in (1 / 100,) + RATIOS:
        film, sub = materials(ratio)
        key = coated._film_key(film, sub)
        for lam in lambdas:
            phi = coated._phi(lam, key)
            m = max(1, math.ceil(lam / coated._PANEL_T))
            out = []
            for n in per_panel:
                J1, J2, e1, e2 = coated._nystrom(lam, phi, m, n)
                out.append((2 * (e2 / e1 * J1 - J2), 2 * J1))
            ref = out[-1]
            cells = " | ".join(f"{abs(p / ref[0] - 1):.0e}, {abs(s / ref[1] - 1):.0e}"
                               for p, s in out[:-1])
            print(f"| {name_of(ratio)} | {lam:g} | {m} | {cells} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a/t = 1 and 10 only")
    parser.add_argument("--convergence", action="store_true",
                        help="node convergence of the exact solution instead")
    args = parser.parse_args()
    lambdas = (1.0, 10.0) if args.quick else LAMBDAS
    if args.convergence:
        convergence(lambdas if args.quick else (0.01,) + lambdas + (100.0,))
    else:
        accuracy(lambdas)


if __name__ == "__main__":
    main()
