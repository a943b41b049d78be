"""Speed against error of the particle scratch (`filmscale.md.particle_scratch`): particle
spacing against groove width (issue 35).

One elastic-perfectly plastic Al-like target (E 70 GPa, nu 0.3, sigma_y 300 MPa, density
2700 kg/m^3), a rigid frictionless sphere R = 1 um scratched 0.15 R deep (contact radius
a = sqrt(2 R d - d^2) = 0.527 um) over 1.2 um at 100 m/s (50 m/s down and up, 1 ns of
relaxation), half model, TLSPH on one rank, at a sequence of lattice spacings. The block is
the same at every spacing: 1.2 um (2.28 a) to the sides, ahead, behind and down to the rigid
base; the default spacings 0.2, 0.15, 0.12, 0.1 um (R/5 ... R/10) all divide it and the
half stroke, so the mid-stroke section is the same lattice column x = 0.6 um.

Per spacing: particles, steps, wall time, CPU time (LAMMPS's loop time times its % CPU use:
the cost on a quiet core), the residual groove's depth, width and pile-up at
mid-stroke, the friction mu = F_lat / F_n (mean +- standard deviation over the steady stroke),
the mean normal force and the plastic zone (eps_p > 1e-3) of the mid-stroke section
(`analyze_scratch`; "block" where it reaches the block's side or the layer above its base:
then it is the block's size, not a figure). Then the error of each figure against the finest spacing and, where the
finest three change monotonically, the Richardson extrapolation to zero spacing with its
observed order p (f(h) = f0 + C h^p, solved for p with unequal spacing ratios).

References beside them: the tip's chord at the scratch depth 2 a = 2 sqrt(2 R d - d^2) (a
geometric reference for the residual width: an elastic-plastic groove springs back, so
w < 2 a), and the particle indentation load at the same depth (`particles indent`, quarter
model on the same material, tip, spacing, width and depth, held 2 ns at the depth: the mean
load over the hold's second half). Williams' fully plastic scratch carries its load on the
front half of the contact (F_n / P_indent = 0.5); TLSPH gives about 1 (docs/particles.md).

Run (5.5 minutes of CPU, 9 minutes wall on 2 cores shared with other jobs; runs kept under
DIR if given, else in a temporary folder removed at exit; a finished run in DIR is read back,
not rerun; ``--block`` changes the block, e.g. ``--block 1.8 --spacings 0.2,0.15``):

    .venv/bin/python benchmarks/particle_scratch_spacing.py [--out DIR] [--spacings 0.2,0.15,...]
        [--block 1.2]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

from filmscale.continuum.materials import ElasticPlastic
from filmscale.md.particle_run import run_particles
from filmscale.md.particle_scratch import ParticleScratchSpec, ParticleStroke, ScratchGrid
from filmscale.md.particle_scratch_run import analyze_scratch, run_scratch
from filmscale.md.particles import (Grid, IndentLoading, ParticleIndentSpec, ParticleMaterial,
                                    ParticleTarget)

R = 1e-6
DEPTH = 0.15 * R
BLOCK = 1.2e-6               #: width (sides, ahead, behind) and depth of the block, m
LENGTH = 1.2e-6              #: stroke, m
SPEED, LOAD_SPEED, RELAX = 100.0, 50.0, 1e-9
HOLD = 2e-9                  #: the reference indentation's hold at the depth, s
AL = ParticleMaterial(ElasticPlastic(70e9, 0.3, 300e6, name="Al-pp"), 2700.0)
DEFAULT_SPACINGS = (0.2, 0.15, 0.12, 0.1)      # um

#: (key, header, unit scale, format) of the figures compared across spacings
FIGURES = (("groove_depth", "groove depth nm", 1e9, ".1f"),
           ("groove_width", "groove width um", 1e6, ".3f"),
           ("pileup_height", "pile-up nm", 1e9, ".1f"),
           ("friction_mean", "mu mean", 1.0, ".3f"),
           ("normal_force_mean", "F_n mN", 1e3, ".3f"),
           ("zone_width", "zone width um", 1e6, ".2f"),
           ("zone_depth", "zone depth um", 1e6, ".2f"))


def chord() -> float:
    """The tip's chord at the scratch depth, 2 sqrt(2 R d - d^2), m."""
    return 2 * math.sqrt(2 * R * DEPTH - DEPTH**2)


def scratch_spec(dx: float, block: float = BLOCK) -> ParticleScratchSpec:
    return ParticleScratchSpec(
        name=f"scratch-{dx * 1e9:g}nm-{block * 1e9:g}nm", target=ParticleTarget(AL),
        tip="sphere:1um", grid=ScratchGrid(dx, block, block, half=True),
        stroke=ParticleStroke(DEPTH, LENGTH, SPEED, LOAD_SPEED, relax_time=RELAX, frames=0))


def indent_spec(dx: float, block: float = BLOCK) -> ParticleIndentSpec:
    return ParticleIndentSpec(f"indent-{dx * 1e9:g}nm-{block * 1e9:g}nm", "tlsph",
                              ParticleTarget(AL), "sphere:1um",
                              IndentLoading(DEPTH, LOAD_SPEED, HOLD, frames=0, unload=False),
                              Grid(dx, block, block, quarter=True))


def progress_printer(label: str):
    """A `progress(step, total)` callback printing at each quarter of the estimated steps."""
    shown = [0]

    def report(step: int, total: int) -> None:
        quarter = min(4, int(4 * step / max(total, 1)))
        if quarter > shown[0]:
            shown[0] = quarter
            # stderr: while LAMMPS runs in this process, its stdout goes to the run directory
            print(f"    {label}: step {step} (~{25 * quarter} % of ~{total} estimated)",
                  file=sys.stderr, flush=True)
    return report


def lammps_cpu(run_dir: Path) -> float:
    """CPU seconds of a run from its LAMMPS log: each "Loop time" times the "% CPU use" that
    follows it (the cost on a shared machine, where wall time depends on the other jobs)."""
    loop, cpu = 0.0, 0.0
    for line in (run_dir / "log.in.tlsph").read_text(errors="replace").splitlines():
        if line.startswith("Loop time of"):
            loop = float(line.split()[3])
        elif "% CPU use" in line:
            cpu += loop * float(line.split("%")[0]) / 100
    return cpu


def zone_edge(zone, spec: ParticleScratchSpec) -> str:
    """Where the plastic zone of the mid-stroke section reaches the block: its side (the
    outermost lattice column), its base (the layer above the fixed base), both, or no."""
    g = spec.grid
    i_lo, i_hi, j, j_lo, k = g.lattice_bounds()
    side = zone.width / 2 >= (j - 0.5) * g.spacing
    base = zone.depth >= (k - 1.5) * g.spacing
    return {(True, True): "side, base", (True, False): "side", (False, True): "base",
            (False, False): "no"}[(side, base)]


def measure(dx: float, block: float, root: Path) -> dict:
    spec = scratch_spec(dx, block)
    g = spec.grid
    print(f"scratch, spacing {dx * 1e6:g} um (R/{R / dx:.3g}): {g.n_particles} particles, "
          f"block {g.width / spec.contact_radius:.2f} a", flush=True)
    run = run_scratch(spec, root / spec.name, progress=progress_printer("scratch"))
    a = analyze_scratch(run)
    zone = a.damage[0]
    print(f"  done: {a.steps} steps, {a.wall_time:.1f} s; groove {a.groove_depth * 1e9:.1f} nm "
          f"deep, {a.groove_width * 1e6:.3f} um wide", flush=True)
    ind = indent_spec(dx, block)
    print(f"indentation reference, spacing {dx * 1e6:g} um: {ind.grid.n_particles} particles",
          flush=True)
    irun = run_particles(ind, root / ind.name, progress=progress_printer("indent"))
    t1, t2, _ = ind.loading.times
    held = irun.time > 0.5 * (t1 + t2)
    P = float(irun.load[held].mean())
    print(f"  done: {irun.steps} steps, {irun.wall_time:.1f} s; load at depth {P * 1e3:.3f} mN",
          flush=True)
    return {"dx": dx, "particles": a.particles, "steps": a.steps, "wall": a.wall_time,
            "cpu": lammps_cpu(run.run_dir), "indent_cpu": lammps_cpu(irun.run_dir),
            "groove_depth": a.groove_depth, "groove_width": a.groove_width,
            "pileup_height": a.pileup_height, "friction_mean": a.friction_mean,
            "friction_std": a.friction_std, "normal_force_mean": a.normal_force_mean,
            "zone_width": zone.width, "zone_depth": zone.depth, "zone_edge": zone_edge(zone, spec),
            "indent_load": P,
            "indent_wall": irun.wall_time, "indent_particles": ind.grid.n_particles}


def richardson(h: list[float], f: list[float]) -> tuple[float, float] | None:
    """(f0, p) of f = f0 + C h^p through three points of decreasing h, or None when the
    sequence is not monotonic or does not converge (no p > 0). Unequal ratios: p solves
    (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) by bisection."""
    d12, d23 = f[0] - f[1], f[1] - f[2]
    if not (math.isfinite(d12) and math.isfinite(d23)) or d12 * d23 <= 0:
        return None
    ratio = d12 / d23

    def g(p):
        return (h[0]**p - h[1]**p) / (h[1]**p - h[2]**p)

    lo, hi = 1e-3, 20.0
    if not g(lo) < ratio < g(hi):
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < ratio else (lo, mid)
    p = 0.5 * (lo + hi)
    f0 = f[2] - d23 * h[2]**p / (h[1]**p - h[2]**p)
    return f0, p


def row(*cells) -> None:
    print("| " + " | ".join(str(c) for c in cells) + " |", flush=True)


def report(results: list[dict], block: float, total: float) -> None:
    results = sorted(results, key=lambda r: -r["dx"])
    print(f"\n## particle spacing against the groove (E 70 GPa, sigma_y 300 MPa, R = 1 um, "
          f"d = {DEPTH / R:g} R, 2 a = {chord() * 1e6:.3f} um, block {block * 1e6:g} um, "
          "half model, one rank)")
    row("spacing um", "R/dx", "particles", "steps", "wall s", "CPU s",
        *(h for _, h, _, _ in FIGURES[:3]), "mu mean +- std", *(h for _, h, _, _ in FIGURES[4:]),
        "zone reaches block")
    row(*["---"] * 14)
    for r in results:
        cells = [f"{r[k] * s:{fmt}}" for k, _, s, fmt in FIGURES]
        row(f"{r['dx'] * 1e6:g}", f"{R / r['dx']:.3g}", r["particles"], r["steps"],
            f"{r['wall']:.1f}", f"{r['cpu']:.1f}", *cells[:3], f"{r['friction_mean']:.3f} +- "
            f"{r['friction_std']:.3f}", *cells[4:], r["zone_edge"])

    print("\n## against the closed-form / indentation references")
    row("spacing um", "w / 2a (chord)", "F_n mN", "P_indent mN", "F_n / P_indent",
        "indent particles", "indent wall s", "indent CPU s")
    row(*["---"] * 8)
    for r in results:
        row(f"{r['dx'] * 1e6:g}", f"{r['groove_width'] / chord():.3f}",
            f"{r['normal_force_mean'] * 1e3:.3f}", f"{r['indent_load'] * 1e3:.3f}",
            f"{r['normal_force_mean'] / r['indent_load']:.3f}", r["indent_particles"],
            f"{r['indent_wall']:.1f}", f"{r['indent_cpu']:.1f}")

    keys = [(k, h, s, fmt) for k, h, s, fmt in FIGURES] + [
        ("indent_load", "P_indent mN", 1e3, ".3f")]
    clipped = {"zone_width": any("side" in r["zone_edge"] for r in results),
               "zone_depth": any("base" in r["zone_edge"] for r in results)}
    finest = results[-1]
    print(f"\n## relative error against the finest spacing ({finest['dx'] * 1e6:g} um)")
    row("spacing um", "wall s", "CPU s", *(h for _, h, _, _ in keys))
    row(*["---"] * (3 + len(keys)))
    for r in results[:-1]:
        row(f"{r['dx'] * 1e6:g}", f"{r['wall']:.1f}", f"{r['cpu']:.1f}",
            *("block" if clipped.get(k) else f"{r[k] / finest[k] - 1:+.1%}" if finest[k]
              else "n/a" for k, *_ in keys))

    if len(results) < 3:
        return
    last = results[-3:]
    h = [r["dx"] for r in last]
    print(f"\n## Richardson extrapolation to zero spacing (the finest three: "
          f"{', '.join(f'{x * 1e6:g}' for x in h)} um)")
    row("figure", "extrapolated", "observed order p", *(f"error at {x * 1e6:g} um" for x in h))
    row(*["---"] * (3 + len(h)))
    for k, head, s, fmt in keys:
        f = [r[k] for r in last]
        if clipped.get(k):
            row(head, "the zone reaches the block", "-", *(f"{v * s:{fmt}}" for v in f))
            continue
        ext = richardson(h, f)
        if ext is None:
            row(head, "not monotonic or not converging", "-",
                *(f"{v * s:{fmt}}" for v in f))
            continue
        f0, p = ext
        row(head, f"{f0 * s:{fmt}}", f"{p:.2f}", *(f"{v / f0 - 1:+.1%}" for v in f))
    print(f"\nwhole benchmark: {total:.0f} s wall (scratch runs "
          f"{sum(r['wall'] for r in results):.0f} s wall, {sum(r['cpu'] for r in results):.0f} s "
          f"CPU; indentation references {sum(r['indent_wall'] for r in results):.0f} s wall, "
          f"{sum(r['indent_cpu'] for r in results):.0f} s CPU)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="keep the runs in this directory (default: a temporary "
                                      "folder removed at exit)")
    parser.add_argument("--spacings", default=",".join(f"{x:g}" for x in DEFAULT_SPACINGS),
                        help="lattice spacings, um, comma-separated (each at most R/5)")
    parser.add_argument("--block", type=float, default=BLOCK * 1e6,
                        help="block width (sides, ahead, behind) and depth, um (default "
                             f"{BLOCK * 1e6:g}: {BLOCK / (chord() / 2):.2f} contact radii)")
    args = parser.parse_args(argv)
    spacings = [float(x) * 1e-6 for x in args.spacings.split(",")]
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="scratch-spacing-") as tmp:
        root = Path(args.out) if args.out else Path(tmp)
        results = [measure(dx, args.block * 1e-6, root) for dx in spacings]
    report(results, args.block * 1e-6, time.perf_counter() - started)
    return 0


if __name__ == "__main__":
    sys.exit(main())
