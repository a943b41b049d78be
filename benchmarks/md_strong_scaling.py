"""Strong-scaling estimate (on paper) for an MD preset on a cluster: the wall time of the
research preset against the rank count, from the planner's measured single-node cost and a
one-parameter parallel-efficiency model.

    .venv/bin/python benchmarks/md_strong_scaling.py [--preset research]

The model: each rank owns a column of the slab (the input splits laterally only, `processors
* * 1`, because a split along z would give ranks the vacuum) and also computes and exchanges
the ghost atoms within the pair cutoff plus the neighbour skin of its column. Its efficiency
is taken as 1 / (1 + a g), g the ghost-to-owned ratio, with a fixed by LAMMPS's published rule
for its benchmarks (a 3-D decomposition): parallel efficiency about 50 % at a few hundred
atoms per core and close to 100 % for many (LAMMPS manual, "Benchmarks"; Thompson et al.,
Comput. Phys. Commun. 271, 108171, 2022). Here: 50 % at 300 atoms per core in a cube of the
preset's density. Nothing here is measured on more than one node; the 2-rank time is the
planner's estimate from the quick preset's measured throughput.
"""

from __future__ import annotations

import argparse
import math

from filmscale.md.spec import preset
from filmscale.workflows.plan import md_cost_s

SKIN_M = 2.0e-10                   # `neighbor 2.0 bin` in the generated input (metal units)
ATOMS_PER_CORE_AT_HALF = 300       # LAMMPS: ~50 % efficiency at "a few 100" atoms per core


def grid(ranks: int) -> tuple[int, int]:
    """The most nearly square px x py = ranks (what LAMMPS picks for a square box)."""
    px = max(d for d in range(1, int(math.isqrt(ranks)) + 1) if ranks % d == 0)
    return px, ranks // px


def column_ghost_ratio(lx: float, ly: float, ranks: int, shell: float) -> float:
    px, py = grid(ranks)
    wx, wy = lx / px, ly / py
    return ((wx + 2 * shell) * (wy + 2 * shell) - wx * wy) / (wx * wy)


def cube_ghost_ratio(atoms: float, density: float, shell: float) -> float:
    side = (atoms / density) ** (1 / 3)
    return ((side + 2 * shell) ** 3 - side ** 3) / side ** 3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--preset", default="research", choices=("quick", "research"))
    args = parser.parse_args()
    spec = preset(args.preset)
    slab = spec.slab_built
    lx, ly, _ = slab.box
    n = slab.n_atoms
    density = n / (lx * ly * (slab.z_surface))      # atoms per m^3 of material
    shell = spec.potential.cutoff + SKIN_M
    a = 1.0 / cube_ghost_ratio(ATOMS_PER_CORE_AT_HALF, density, shell)
    efficiency = {r: 1.0 / (1.0 + a * column_ghost_ratio(lx, ly, r, shell))
                  for r in (2, 8, 16, 32, 64, 128, 256, 512, 1024)}
    t2 = md_cost_s(spec, 2)
    steps = spec.protocol.schedule().s_end
    print(f"{args.preset} preset: {n} atoms, {steps} steps, box {lx * 1e9:.1f} x "
          f"{ly * 1e9:.1f} nm, ghost shell {shell * 1e10:.1f} A (cutoff + skin); "
          f"2 ranks: {t2 / 3600:.1f} h (planner); efficiency model a = {a:.3f}")
    print(f"{'ranks':>6} {'grid':>7} {'atoms/rank':>10} {'column nm':>10} {'ghost/own':>9} "
          f"{'eff':>5} {'ideal h':>8} {'est. h':>7} {'core-h':>7}")
    for r, eff in efficiency.items():
        px, py = grid(r)
        ideal = t2 * 2 / r
        est = ideal * efficiency[2] / eff
        print(f"{r:6d} {px:3d} x{py:3d} {n / r:10.0f} {lx / px * 1e9:5.2f}x{ly / py * 1e9:4.2f}"
              f" {column_ghost_ratio(lx, ly, r, shell):9.2f} {eff:5.2f} {ideal / 3600:8.2f}"
              f" {est / 3600:7.2f} {est * r / 3600:7.0f}")


if __name__ == "__main__":
    main()
