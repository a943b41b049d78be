"""Cost and accuracy of the layered sliding-sphere field (`continuum.contact.sliding_sphere_layered`).

Run:  .venv/bin/python benchmarks/sliding_sphere_layered_speed.py

The y = 0 plane (x in [-3a, 3a], z in [0, 3a], so the surface and the interfaces are grid rows)
on grids of 64 x 32, 128 x 64 and 256 x 128 points, for 1, 3 and 5 layers of 0.1 a each
(alternately TiN and Cr) on steel, mu = 0.3. Columns:
- n_k: wavenumber nodes of the layered correction (l_min = h_1: the rows in the top layer);
- t_hom: the homogeneous part, `sphere_stresses` on the grid (Hamilton's closed form and the
  Cerruti quadrature of the traction, ~0.2 ms a point), the same for every stack with a TiN top;
- t_corr: the layered correction on the grid (distinct |x| times distinct depths, matrix path);
- err_ident: largest deviation (p0) from the homogeneous field with every layer made of steel
  (the correction must vanish; the field is the closed form plus it);
- err_unsub: largest difference (p0) between the full spectral integral (no closed-form part)
  and closed form + correction for the real stack at the grid points with z >= 0.1 a, and
  (err_0.2) with z >= 0.2 a, where the Cerruti quadrature of the closed-form part is itself
  exact to ~1e-14 q0 (it is good to ~1e-9 q0 at 0.1 a; docs/sliding.md).
Last line: a 3-D grid of 32 x 32 x 16 general points (x, y in [-2a, 2a], z in [0, 2a]) on the
3-layer stack through `layered_sphere_stresses` (the per-radius matrix path), split likewise.
"""

from __future__ import annotations

import time

import numpy as np

from filmscale.continuum.contact import sliding_sphere_layered as ssl
from filmscale.continuum.contact.sliding import sphere_stresses
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack

A, P0, MU = 1e-4, 1e9, 0.3
STEEL = ElasticPlastic(E=210e9, nu=0.3, name="steel")
TIN = ElasticPlastic(E=400e9, nu=0.22, name="TiN")
CR = ElasticPlastic(E=280e9, nu=0.21, name="Cr")
KEYS = ("sxx", "syy", "szz", "sxy", "syz", "txz")


def stacks(n):
    real = LayerStack(tuple(Layer(0.1 * A, TIN if i % 2 == 0 else CR) for i in range(n)), STEEL)
    same = LayerStack(tuple(Layer(0.1 * A, STEEL) for _ in range(n)), STEEL)
    return ssl._scaled(real, A), ssl._scaled(same, A)


def timed(f, *args, **kw):
    t = time.perf_counter()
    out = f(*args, **kw)
    return out, time.perf_counter() - t


def main():
    print(f"{'grid':>9} {'layers':>6} {'n_k':>6} {'t_hom s':>8} {'t_corr s':>8} "
          f"{'err_ident':>9} {'err_unsub':>9} {'err_0.2':>8}")
    for nx, nz in ((64, 32), (128, 64), (256, 128)):
        X, Z = (v.ravel() for v in np.meshgrid(np.linspace(-3, 3, nx), np.linspace(0, 3, nz)))
        Y = np.zeros(X.size)
        hom, t_hom = timed(sphere_stresses, X, Y, Z, 1.0, 1.0, MU, TIN.nu)
        deep = Z >= 0.1
        for n in (1, 3, 5):
            real, same = stacks(n)
            lay = ssl._layer_of(Z, real.tops, "below")
            corr, t_corr = timed(ssl._correction, X, Y, Z, lay, real, MU)
            ident = ssl._correction(X, Y, Z, lay, same, MU)
            err_ident = max(float(np.max(np.abs(ident[k]))) for k in KEYS)
            full = ssl._correction(X[deep], Y[deep], Z[deep], lay[deep], real, MU,
                                   subtract=False)
            diff = np.max([np.abs(full[k] - hom[k][deep] - corr[k][deep]) for k in KEYS],
                          axis=0)
            err_unsub = float(np.max(diff))
            err_02 = float(np.max(diff[Z[deep] >= 0.2]))
            n_k = ssl._nodes(0.1, 3.0, 3.0 + 2 * real.tops[-1])[0].size
            print(f"{nx:>4}x{nz:<4} {n:>6} {n_k:>6} {t_hom:>8.2f} {t_corr:>8.2f} "
                  f"{err_ident:>9.1e} {err_unsub:>9.1e} {err_02:>8.1e}")
    # a 3-D grid of general points
    X, Y, Z = (v.ravel() for v in np.meshgrid(np.linspace(-2, 2, 32), np.linspace(-2, 2, 32),
                                               np.linspace(0, 2, 16), indexing="ij"))
    real, same = stacks(3)
    _, t_hom = timed(sphere_stresses, X, Y, Z, 1.0, 1.0, MU, TIN.nu)
    lay = ssl._layer_of(Z, real.tops, "below")
    _, t_corr = timed(ssl._correction, X, Y, Z, lay, real, MU)
    ident = ssl._correction(X, Y, Z, ssl._layer_of(Z, same.tops, "below"), same, MU)
    err_ident = max(float(np.max(np.abs(ident[k]))) for k in KEYS)
    stack = LayerStack(tuple(Layer(0.1 * A, TIN if i % 2 == 0 else CR) for i in range(3)), STEEL)
    out, t_all = timed(ssl.layered_sphere_stresses, X * A, Y * A, Z * A, stack, A, P0, MU)
    assert all(np.all(np.isfinite(v)) for v in out.values())
    n_k = ssl._nodes(0.1, float(np.hypot(2, 2)), 2.0 + 2 * real.tops[-1])[0].size
    print(f"3-D 32x32x16 (3 layers): n_k {n_k}, t_hom {t_hom:.2f} s, t_corr {t_corr:.2f} s, "
          f"layered_sphere_stresses {t_all:.2f} s, err_ident {err_ident:.1e}")


if __name__ == "__main__":
    main()
