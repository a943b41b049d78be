"""filmscale against micromechanics (the peer that reads the same instrument exports), side by
side on the real files in tests/data/instruments: E, H and the time to read and analyse each
whole file, in one run.

    python benchmarks/instrument_peer.py [--repeat 3]

micromechanics is not installed at run time: install the ``bench`` extra
(``pip install -e '.[bench]'``); without it the filmscale half of the table is printed.

Both tools get the same inputs: the area function the file states (G200: the Results sheet's
area coefficients; Hysitron: the header's Tip C0..C5; FQ.xls states none, so the ideal
Berkovich), the file's Poisson ratio (0.3 where it states none), and the file's depth zero (filmscale ``--surface
file``; micromechanics finds no surface by default). CSM tests are averaged over the file's
own depth range (100-200 nm); multi-cycle and single unloadings give one value per
unloading. E and H per file are the medians over its tests (or cycles). The instrument's
own Results (where the file has them) are the third column. Times exclude the imports (each
tool is run once on the file before timing; best of --repeat).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import time
import warnings
from pathlib import Path

import numpy as np

from filmscale.workflows.indent import AnalysisOptions, analyze_file

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "instruments"
#: file -> (filmscale options, the file's Poisson ratio)
FILES = {
    "FS_Calibration.xls": (AnalysisOptions(tip="berkovich", area_file="file", csm=True,
                                           surface="file"), 0.18),
    "Example.xls": (AnalysisOptions(tip="berkovich", area_file="file", csm=True,
                                    surface="file"), 0.18),
    "Popin.xls": (AnalysisOptions(csm=True, tip="berkovich", surface="file", beta=1.0), 0.3),
    "FQ.xls": (AnalysisOptions(tip="berkovich", cycles=True, surface="file", beta=1.0), 0.18),
    "Exp-50mN_0000.hld": (AnalysisOptions(tip="berkovich", area_file="file", surface="file",
                                          nu=0.3), 0.3),
}


def best_time(run, repeat: int):
    run()                                   # imports and caches out of the timing
    times, out = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return min(times), out


def filmscale_values(path: Path, options: AnalysisOptions):
    records = [r for r in analyze_file(path, options) if r.get("status") == 0]
    E = [r["E"] for r in records if r.get("E") is not None and math.isfinite(r["E"])]
    H = [r["H"] for r in records if r.get("H") is not None and math.isfinite(r["H"])]
    return len(records), (float(np.median(E)) if E else math.nan,
                          float(np.median(H)) if H else math.nan)


def peer_area(path: Path) -> list[float] | None:
    """The area coefficients (nm) the file states, for micromechanics' "iso" tip."""
    curves = __import__("filmscale.continuum.indentation.io", fromlist=["read_curves"]) \
        .read_curves(path)
    meta = next(iter(curves.values())).meta
    si = (meta.get("vendor") or {}).get("area_coefficients") or meta.get("area_coefficients")
    if not si:
        return None
    return [c / 1e-9**(2.0 - 2.0**(1 - k)) for k, c in enumerate(si)]


def peer_values(path: Path, nu: float, area):
    """micromechanics' medians of E and H over the file's tests (GPa -> Pa)."""
    from micromechanics.indentation import Indentation
    from micromechanics.indentation.tip import Tip
    tip = Tip(shape=list(area)) if area else Tip()
    E, H, n = [], [], 0

    def analyse_one():
        nonlocal n
        try:
            i.analyse()
        except Exception:               # the peer's failures are counted, not raised
            return
        modulus, hardness = np.atleast_1d(i.modulus), np.atleast_1d(i.hardness)
        if modulus.size > 20:           # CSM: the 100-200 nm average, as the instrument
            depth = np.asarray(i.h)[np.asarray(i.valid)]
            sel = (depth >= 0.1) & (depth <= 0.2)
            modulus, hardness = modulus[sel].mean(keepdims=True), \
                hardness[sel].mean(keepdims=True)
        E.extend(modulus * 1e9)
        H.extend(hardness * 1e9)
        n += 1

    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        i = Indentation(str(path), nuMat=nu, tip=tip, output={"verbose": 0})
        tests = 0
        for _ in i:                     # a workbook: every test sheet in turn
            tests += 1
            analyse_one()
        if tests == 0:                  # a single-test file (.hld)
            analyse_one()
    return n, (float(np.nanmedian(E)) if E else math.nan,
               float(np.nanmedian(H)) if H else math.nan)


def instrument_values(path: Path):
    from filmscale.continuum.indentation.io import read_curves
    E, H = [], []
    for curve in read_curves(path).values():
        vendor = curve.meta.get("vendor") or {}
        E += [vendor["E"]] if "E" in vendor else []
        H += [vendor["H"]] if "H" in vendor else []
    return (float(np.median(E)) if E else math.nan, float(np.median(H)) if H else math.nan)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per tool (best)")
    args = parser.parse_args()
    try:
        import micromechanics          # noqa: F401
        have_peer = True
    except ImportError:
        have_peer = False
        print("micromechanics is not installed (pip install -e '.[bench]'): filmscale only")

    def gpa(v):
        return "-" if not math.isfinite(v) else f"{v / 1e9:.4g}"

    print(f"{'file':<20} {'tests':>5} {'filmscale E/H [GPa]':>20} {'peer E/H [GPa]':>16} "
          f"{'instrument E/H':>15} {'filmscale [s]':>13} {'peer [s]':>9} {'speed-up':>8}")
    total_fs = total_peer = 0.0
    for name, (options, nu) in FILES.items():
        path = DATA / name
        t_fs, (n, (E, H)) = best_time(lambda: filmscale_values(path, options), args.repeat)
        total_fs += t_fs
        peer = ("-", "-", "-")
        if have_peer:
            area = peer_area(path)
            t_peer, (n_peer, (E_p, H_p)) = best_time(lambda: peer_values(path, nu, area),
                                                     args.repeat)
            total_peer += t_peer
            peer = (f"{gpa(E_p)}/{gpa(H_p)} ({n_peer})", f"{t_peer:.3f}",
                    f"{t_peer / t_fs:.1f}x")
        E_i, H_i = instrument_values(path)
        print(f"{name:<20} {n:>5} {gpa(E) + '/' + gpa(H):>20} {peer[0]:>16} "
              f"{gpa(E_i) + '/' + gpa(H_i):>15} {t_fs:>13.3f} {peer[1]:>9} {peer[2]:>8}")
    if have_peer:
        print(f"{'all files':<20} {'':>5} {'':>20} {'':>16} {'':>15} {total_fs:>13.3f} "
              f"{total_peer:>9.3f} {total_peer / total_fs:>7.1f}x")


if __name__ == "__main__":
    main()
