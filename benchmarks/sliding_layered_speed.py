"""Cost and accuracy of the layered sliding-cylinder field (`continuum.contact.sliding_layered`).

Run:  .venv/bin/python benchmarks/sliding_layered_speed.py

A 256 x 128 grid (x in [-3b, 3b], z in [0, 3b], so interfaces and the surface are included) for
1, 3 and 10 layers of 0.1 b each (alternately TiN and Cr) on steel, mu = 0.3. Columns:
- t_layered: wall time of `layered_cylinder_stresses` on the grid, real materials;
- t_ident / err_ident: time and largest error (p0) with every layer made of steel (the
  homogeneous closed form is then the exact answer);
- err_spectral: largest error (p0) of the spectral integral alone (no closed-form part, z >= 0.05 b)
  for the identical layers: this checks the per-k solve and the k-quadrature independently;
- n_k: the number of wavenumber nodes for l_min = h_1 (the interface rows of the grid).
"""

from __future__ import annotations

import time

import numpy as np

from filmscale.continuum.contact import sliding_layered as sl
from filmscale.continuum.contact.sliding import cylinder_stresses
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack

B, P0, MU = 1e-4, 1e9, 0.3
STEEL = ElasticPlastic(E=210e9, nu=0.3, name="steel")
TIN = ElasticPlastic(E=400e9, nu=0.22, name="TiN")
CR = ElasticPlastic(E=280e9, nu=0.21, name="Cr")
KEYS = ("sxx", "syy", "szz", "txz")


def main():
    x = np.linspace(-3, 3, 256)
    z = np.linspace(0, 3, 128)
    X, Z = np.meshgrid(x, z, indexing="ij")
    ref = cylinder_stresses(X, Z, 1.0, 1.0, MU, STEEL.nu)
    Zs = np.maximum(Z, 0.05)
    ref_s = cylinder_stresses(X, Zs, 1.0, 1.0, MU, STEEL.nu)
    print(f"{'layers':>6} {'points':>7} {'n_k':>6} {'t_layered s':>11} {'t_ident s':>9} "
          f"{'err_ident':>9} {'err_spectral':>12}")
    for n in (1, 3, 10):
        real = LayerStack(tuple(Layer(0.1 * B, TIN if i % 2 == 0 else CR) for i in range(n)),
                          STEEL)
        same = LayerStack(tuple(Layer(0.1 * B, STEEL) for _ in range(n)), STEEL)
        t = time.perf_counter()
        out = sl.layered_cylinder_stresses(X * B, Z * B, real, B, P0, MU)
        t_real = time.perf_counter() - t
        assert np.all(np.isfinite(out["sxx"]))
        t = time.perf_counter()
        same_out = sl.layered_cylinder_stresses(X * B, Z * B, same, B, P0, MU)
        t_same = time.perf_counter() - t
        err = max(float(np.max(np.abs(same_out[k] / P0 - ref[k]))) for k in KEYS)
        spec = sl._field(X.ravel(), Zs.ravel(), same, MU, subtract=False, b=B)
        err_s = max(float(np.max(np.abs(spec[k] - ref_s[k].ravel()))) for k in KEYS)
        s, _ = sl.wavenumber_panels(3.0, 0.1, 3.0 + 2 * 0.1 * n)
        print(f"{n:>6} {X.size:>7} {s.size:>6} {t_real:>11.2f} {t_same:>9.2f} "
              f"{err:>9.1e} {err_s:>12.1e}")


if __name__ == "__main__":
    main()
