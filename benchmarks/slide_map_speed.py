"""Cost and accuracy of first-yield maps over (normal load, friction) (`continuum.contact.slide_map`)
and of one refined sliding contact (`slider.slide`).

Run:  .venv/bin/python benchmarks/slide_map_speed.py [--quick]

Cases: a slider edge (cylinder, R = L = 10 um, rigid) and a bump (sphere, R = 10 um) on a
homogeneous NiP target and on DLC / CoCrPt / Ru films (4 / 16 / 10 nm) on NiP, the disk of
examples/slider_bump_disk.toml; one case with 10x thicker films (the contact 3-30 times the
top film instead of 30-300 times). Columns:
- t_map: wall time of the map (loads x frictions);
- t_slide: one `slide` at the map's middle point (grid, then the zoomed local search);
- err_grid: the largest relative shortfall of the map's per-layer von Mises maxima against
  `slide` at the map's four corners (the map searches its grid only; `slide` refines);
- first_yield: the load of first yield at friction 0 and at the largest friction (N).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from filmscale.continuum.contact.slide_map import slide_map
from filmscale.continuum.contact.slider import Slider, slide
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack

NIP = ElasticPlastic(E=160e9, nu=0.3, sigma_y=2.5e9, name="NiP")
DLC = ElasticPlastic(E=200e9, nu=0.25, sigma_y=8e9, name="DLC")
COCRPT = ElasticPlastic(E=180e9, nu=0.3, sigma_y=5e9, name="CoCrPt")
RU = ElasticPlastic(E=300e9, nu=0.3, sigma_y=3.5e9, name="Ru")


def disk(scale=1.0):
    return LayerStack((Layer(4e-9 * scale, DLC), Layer(16e-9 * scale, COCRPT),
                       Layer(10e-9 * scale, RU)), NIP)


def case(name, stack, slider, loads, mus):
    start = time.perf_counter()
    mp = slide_map(stack, slider, loads, mus)
    t_map = time.perf_counter() - start
    start = time.perf_counter()
    slide(stack, slider, float(loads[loads.size // 2]), float(mus[mus.size // 2]))
    t_slide = time.perf_counter() - start
    shortfall = 0.0
    for i in (0, loads.size - 1):
        for f in (0, mus.size - 1):
            r = slide(stack, slider, float(loads[i]), float(mus[f]))
            for j, row in enumerate(r.layers):
                shortfall = max(shortfall, 1.0 - mp["layer_von_mises_max"][j, f, i]
                                / row.von_mises_max)
    fy = mp["first_yield_load"]
    print(f"{name:<34} {mus.size:>3} x {loads.size:<3} {t_map:>8.2f} {t_slide:>8.2f} "
          f"{shortfall:>9.1e} {fy[0]:>11.3g} {fy[-1]:>11.3g}")


def main():
    quick = "--quick" in sys.argv
    n = 10 if quick else 50
    edge = Slider("cylinder", 10e-6, length=10e-6)
    bump = Slider("sphere", 10e-6)
    mus = np.linspace(0.0, 1.0, n)
    print(f"{'case':<34} {'map':>9} {'t_map s':>8} {'t_slide':>8} {'err_grid':>9} "
          f"{'P_y(mu=0)':>11} {'P_y(mu=max)':>11}")
    case("edge, homogeneous NiP", LayerStack((), NIP), edge, np.geomspace(1e-3, 1.0, n), mus)
    case("edge, disk films (contact/h1 30-300)", disk(), edge,
         np.geomspace(1e-3, 0.1, n), mus)
    case("edge, 10x films (contact/h1 3-30)", disk(10.0), edge,
         np.geomspace(1e-3, 0.1, n), mus)
    case("bump, homogeneous NiP", LayerStack((), NIP), bump, np.geomspace(1e-4, 1e-2, n), mus)
    m = 6 if quick else 12
    case("bump, disk films", disk(), bump, np.geomspace(1e-4, 1e-2, m), np.linspace(0, 1, m))


if __name__ == "__main__":
    main()
