"""Files laid out like instrument exports, written from a curve: for the reader tests.

Each writer takes one or more curves (SI) and writes the same numbers, rounded to 10
significant digits in the instrument's units, as the vendor software lays them out:

- KLA/Agilent G200 and iMicro (NanoSuite "Export to Excel"): a ``Results`` sheet and a
  ``Required Inputs`` sheet, then one sheet per test (``Test 001``, ...) with a header row,
  a row of units under it, a ``Segment`` column holding a marker at the first row of each
  segment, and further channels (harmonic stiffness, hardness, modulus) left blank.
- Hysitron/Bruker TriboScan ``.txt``: Latin-1 text, a preamble, then a tab-separated header
  ``Depth (nm)  Load (µN)  Time (s)  Depth (V)  Load (V)``, CR LF line ends.
- TriboScan ``.hld``-style text: ``Key: value`` preamble lines, a ``Time (s)  Load (µN)  Disp
  (nm)`` header (another column order).
- Anton Paar: ``;``-separated, decimal comma, a two-row header (names, then units in
  brackets), normal force ``Fn`` in mN and penetration depth ``Pd`` in nm.
- the package's own table: ``h [nm], P [uN], t [s]``.
"""

import numpy as np

from filmscale.continuum.indentation.curves import HOLD, LOAD, UNLOAD


def rounded(x) -> list[float]:
    """Values rounded to 10 significant digits, as every writer here writes them (Python
    floats, whose repr is the shortest text that reads back to the same number)."""
    return [float(f"{v:.10g}") for v in np.asarray(x, dtype=float)]


def columns(curve):
    """(h in nm, P in uN, t in s), rounded."""
    return rounded(curve.h * 1e9), rounded(curve.P * 1e6), rounded(curve.t)


def write_native(path, curve):
    h, P, t = columns(curve)
    lines = ["h [nm], P [uN], t [s]"] + [f"{a!r}, {b!r}, {c!r}" for a, b, c in zip(h, P, t)]
    path.write_text("\n".join(lines) + "\n")


def _markers(segment):
    """G200-style segment markers: text at the first row of each segment, blank elsewhere."""
    names = {LOAD: "Loading", HOLD: "Hold", UNLOAD: "Unloading"}
    out, previous, cycle = [], None, 1
    for s in segment:
        if s != previous:
            if s == LOAD and previous is not None:
                cycle += 1
            out.append(f"{'Reloading' if s == LOAD and cycle > 1 else names[s]} {cycle}")
        else:
            out.append(None)
        previous = s
    return out


def write_g200(path, curves):
    """A G200/iMicro workbook with one test sheet per curve (``curves``: a list)."""
    from openpyxl import Workbook

    wb = Workbook()
    results = wb.active
    results.title = "Results"
    results.append(["Test", "Modulus At Max Load", "Hardness At Max Load"])
    results.append(["", "GPa", "GPa"])
    inputs = wb.create_sheet("Required Inputs")
    inputs.append(["Poissons Ratio", 0.17])
    inputs.append(["Surface Approach Velocity", 10, "nm/s"])
    for k, curve in enumerate(curves, start=1):
        results.append([k, None, None])
        ws = wb.create_sheet(f"Test {k:03d}")
        ws.append(["Segment", "Displacement Into Surface", "Load On Sample", "Time On Sample",
                   "Harmonic Contact Stiffness", "Hardness", "Modulus"])
        ws.append([None, "nm", "mN", "s", "N/m", "GPa", "GPa"])
        h, P, t = columns(curve)
        for marker, a, b, c in zip(_markers(curve.segment), h, rounded(np.array(P) * 1e-3), t):
            ws.append([marker, a, b, c, None, None, None])
    wb.save(path)


def write_triboscan(path, curve):
    h, P, t = columns(curve)
    lines = ["Hysitron TriboScan 9.6", "Analysis: Oliver-Pharr", f"Number of Points = {len(h)}",
             "", "Depth (nm)\tLoad (\u00b5N)\tTime (s)\tDepth (V)\tLoad (V)"]
    lines += [f"{a!r}\t{b!r}\t{c!r}\t{a * 1e-3:.5f}\t{b * 1e-4:.5f}" for a, b, c in zip(h, P, t)]
    path.write_bytes("\r\n".join(lines).encode("latin-1"))


def write_hld(path, curve):
    h, P, t = columns(curve)
    lines = ["File Version: Hysitron", "Tip Name: Berkovich", "Number of Points: " + str(len(h)),
             "Time (s)\tLoad (\u00b5N)\tDisp (nm)"]
    lines += [f"{c!r}\t{b!r}\t{a!r}" for a, b, c in zip(h, P, t)]
    path.write_bytes("\n".join(lines).encode("latin-1"))


def write_anton_paar(path, curve):
    h, P, t = columns(curve)
    lines = ["Anton Paar Indentation;Export", "Fn;Pd;Time", "[mN];[nm];[s]"]
    lines += [f"{b!r};{a!r};{c!r}".replace(".", ",")
              for a, b, c in zip(h, rounded(np.array(P) * 1e-3), t)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
