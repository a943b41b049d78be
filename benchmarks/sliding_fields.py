"""Cost and accuracy of the sliding-contact stress fields of `continuum.contact.sliding`.

Run:  .venv/bin/python benchmarks/sliding_fields.py

Prints one row a field: points, method, time, and the largest error (in units of p0) against
the second method of tests/continuum/test_sliding_homogeneous.py, evaluated on a 200-point
subset (the check is the slow part and is not timed):
- cylinder, McEwen closed forms (mu = 0.3) against quadrature of the Flamant kernels;
- sphere, Hamilton's normal-load equations (mu = 0) against Gauss quadrature of the
  Boussinesq point-load stresses over the Hertz pressure (subset at z >= 0.3 a);
- sphere with friction (mu = 0.3), tangential part by quadrature of Cerruti's point-force
  stresses (64 x 48 nodes a point) against a second quadrature centred on the disc (Gauss in
  beta, r = sin beta; subset at z >= 0.2 a); the time is for the full field (normal + tangential).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy import integrate

from filmscale.continuum.contact import sliding as sl

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))    # the tests' disc quadrature
from tests.helpers.hertz_disc import hertz_disc_nodes  # noqa: E402

NU, MU = 0.3, 0.3


def flamant(x, z, mu):
    def p(s):
        return math.sqrt(max(1 - s * s, 0.0))

    def d(s):
        return ((x - s) ** 2 + z * z) ** 2

    kern = {
        "sxx": lambda s: -2 / math.pi * p(s) * ((x - s) ** 2 * z + mu * (x - s) ** 3) / d(s),
        "szz": lambda s: -2 / math.pi * p(s) * (z ** 3 + mu * (x - s) * z * z) / d(s),
        "txz": lambda s: -2 / math.pi * p(s) * ((x - s) * z * z + mu * (x - s) ** 2 * z) / d(s),
    }
    pts = [min(max(x, -1.0), 1.0)]
    return {k: integrate.quad(f, -1, 1, points=pts, limit=500, epsabs=1e-12, epsrel=1e-12)[0]
            for k, f in kern.items()}


def boussinesq(x, y, z, nu, nb=160, nphi=320):
    xs, ys, dP = hertz_disc_nodes(nb, nphi)
    dx, dy = x - xs, y - ys
    R2 = dx * dx + dy * dy
    rho = np.sqrt(R2 + z * z)
    sr = ((1 - 2 * nu) / R2 * (1 - z / rho) - 3 * z * R2 / rho ** 5) / (2 * math.pi)
    st = -(1 - 2 * nu) * (1 / R2 * (1 - z / rho) - z / rho ** 3) / (2 * math.pi)
    trz = -3 * np.sqrt(R2) * z * z / (2 * math.pi * rho ** 5)
    c, s = dx / np.sqrt(R2), dy / np.sqrt(R2)
    out = {"sxx": sr * c * c + st * s * s, "syy": sr * s * s + st * c * c,
           "szz": -3 * z ** 3 / (2 * math.pi * rho ** 5), "sxy": (sr - st) * s * c,
           "txz": trz * c, "syz": trz * s}
    return {k: float(np.sum(v * dP)) for k, v in out.items()}


def main():
    rng = np.random.default_rng(1)
    print(f"{'points':>9} | {'method':<34} | {'time (s)':>9} | {'max error / p0':>14}")
    print("-" * 76)
    for n in (10**2, 10**4, 10**6):
        x, z = rng.uniform(-2.5, 2.5, n), rng.uniform(0.05, 2.0, n)
        t = time.perf_counter()
        s = sl.cylinder_stresses(x, z, 1.0, 1.0, MU, NU)
        dt = time.perf_counter() - t
        k = min(n, 200)
        err = max(abs(float(s[c][i]) - v) for i in range(k)
                  for c, v in flamant(x[i], z[i], MU).items())
        print(f"{n:>9} | {'cylinder McEwen closed form':<34} | {dt:>9.4f} | {err:>14.2e}")
    for n in (10**2, 10**4, 10**6):
        x, y = rng.uniform(-2, 2, n), rng.uniform(-2, 2, n)
        z = rng.uniform(0.3, 2.0, n)
        t = time.perf_counter()
        s = sl.sphere_normal_stresses(x, y, z, 1.0, 1.0, NU)
        dt = time.perf_counter() - t
        k = min(n, 200)
        err = max(abs(float(s[c][i]) - v) for i in range(k)
                  for c, v in boussinesq(x[i], y[i], z[i], NU).items())
        print(f"{n:>9} | {'sphere Hamilton normal (mu = 0)':<34} | {dt:>9.4f} | {err:>14.2e}")
    friction_rows(rng)


def cerruti(x, y, z, nu, nb=160, nphi=320):
    xs, ys, dQ = hertz_disc_nodes(nb, nphi)
    X, Y = x - xs, y - ys
    R = np.sqrt(X * X + Y * Y + z * z)
    b, f = (1 - 2 * nu) / (R + z) ** 2, 1 / (2 * math.pi)
    out = {"sxx": f * X / R ** 3 * (-3 * X * X / R ** 2 + b * (R * R - Y * Y - 2 * R * Y * Y / (R + z))),
           "syy": f * X / R ** 3 * (-3 * Y * Y / R ** 2 + b * (3 * R * R - X * X - 2 * R * X * X / (R + z))),
           "szz": -3 * f * X * z * z / R ** 5,
           "sxy": f * Y / R ** 3 * (-3 * X * X / R ** 2 + b * (-R * R + X * X + 2 * R * X * X / (R + z))),
           "syz": -3 * f * X * Y * z / R ** 5, "txz": -3 * f * X * X * z / R ** 5}
    return {k: float(np.sum(v * dQ)) for k, v in out.items()}


def friction_rows(rng):
    for n in (10**2, 10**4, 10**5):
        x, y = rng.uniform(-2, 2, n), rng.uniform(-2, 2, n)
        z = rng.uniform(0.2, 2.0, n)
        t = time.perf_counter()
        s = sl.sphere_stresses(x, y, z, 1.0, 1.0, MU, NU)
        dt = time.perf_counter() - t
        k = min(n, 200)
        err = max(abs(float(s[c][i]) - (MU * v + b[c])) for i in range(k)
                  for b in (boussinesq(x[i], y[i], z[i], NU),)
                  for c, v in cerruti(x[i], y[i], z[i], NU).items())
        print(f"{n:>9} | {'sphere with friction (mu = 0.3)':<34} | {dt:>9.4f} | {err:>14.2e}")


if __name__ == "__main__":
    main()
