"""Is the particle scratch's early groove onset numerical? (issue 35's cross-scale check;
docs/particles.md, "Groove onset against the sliding model's first yield").

The slow check (`tests/md/test_scratch_onset.py`: TLSPH, E 70 GPa, nu 0.3, sigma_y 1.53 GPa,
R = 8 um, 0.1 um lattice, 1.2 um block, 0.8 um stroke at 250 m/s, 20 m/s down and up) finds
the onset at 0.773 of the sliding model's first-yield load. An elastic run tells the same
thing for less: the largest von Mises stress of the particles over Hertz's at the same load
(the sliding model's 0.620 p0, frictionless), ``peak``; a particle first yields at
P_model / peak^3 (the stresses scale with p0 ~ P^(1/3)).

Each case is the elastic target at ``--fraction`` of delta_y (default 0.6; delta_y = 20 nm,
the Hertz first-yield depth; 0.765, the measured onset's depth, samples the peak where the
yield happens) with one change from the check's scratch:

* ``speed100``, ``speed50``: the stroke at 100 or 50 m/s (250 m/s is 4.2 % of the P-wave
  speed: a dynamic overshoot would fall as the speed does);
* ``hg1``: TLSPH's hourglass coefficient 1 instead of the MACHDYN examples' 10
  (`particle_inputs.TLSPH_HOURGLASS`); ``q0``: no artificial viscosity (Q1 0 instead of 0.06);
* ``rollers``: zero normal velocity on the block's x ends and far y side (the ULSPH scratch's
  roller sides) instead of free faces;
* ``dx0.08``: the 0.08 um lattice (a_y = 5 spacings) on the same 1.2 um block (rounded to
  the lattice: 15 spacings);
* ``block1.8``: a 1.8 um block (sides, ahead, behind and down to the rigid base) instead of
  1.2 um; ``deep1.8``: the rigid base 1.8 um down, the sides and ends 1.2 um;
* ``ulsph``: MACHDYN's updated-Lagrangian SPH (``method = "ulsph"``, roller sides).

The input is `scratch_input(spec)`'s text with a probe added (``compute reduce max`` of the
von Mises stress, with the position of the particle that carries it, printed with the record:
``probe.dat``) and the case's change made to the text; a case that changes the spec only
(speed, lattice, block, method) runs that spec. Per case: the mean normal force of the steady
stroke over the model's first-yield load, ``peak`` at the end of the descent (the static
indent) and over the steady stroke (its first and last tenth and its largest value), the
depth of the particle that carries the largest, and the onset it predicts,
1 / peak_max^3 of the model's load.

``--onset CASE[,CASE]`` also runs the plastic depth ladder (``--ladder``, fractions of
delta_y; default the slow check's 0.6, 0.7, 0.73, 0.765, 0.8, 0.9) with `groove_onset`'s
criterion and the case's change, and prints its onset over the model's load. Measured
(docs/particles.md, "Groove onset"; 2 cores shared with other jobs): 1-8 min a case, 12 min for
the 1.8 um block's ladder, 35 min for the whole study:

    .venv/bin/python benchmarks/particle_onset_gap.py [--out DIR] [--cases base,speed100,...]
        [--fraction 0.765] [--onset block1.8 --ladder 0.6,0.7,0.73,0.765,0.8,0.85,0.9]
        [--jobs 2]

Runs are kept under DIR if given (a finished run is read back), else in a temporary folder
removed at exit.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np

from filmscale.core.jsonable import to_jsonable
from filmscale.md.engine import EngineOptions, parse_table
from filmscale.md.lammps_units import lammps_to_si, si_to_lammps
from filmscale.md.particle_inputs import lammps_number
from filmscale.md.particle_run import run_particle_input
from filmscale.md.particle_scratch import (FINAL_DUMP, RECORD, ParticleScratchSpec,
                                           _roller_lines, estimated_steps, scratch_input,
                                           spec_from_mapping)
from filmscale.md.particle_scratch_run import analyze_scratch, read_scratch
from filmscale.md.scratch_run import STEADY
from filmscale.md.scratch_onset import (ONSET_THRESHOLD, at_depth, hertz_first_yield,
                                        model_first_yield_load)

R, E, NU, DENSITY = 8e-6, 70e9, 0.3, 2700.0
E_STAR = E / (1 - NU**2)
SPACING = 1e-7
SIGMA_Y = 2 * E_STAR * 4 * SPACING / (math.pi * R) / 1.6     # a_y = 4 spacings (the check)
WIDTH, LENGTH = 12 * SPACING, 8 * SPACING
SPEED, LOAD_SPEED, RELAX = 250.0, 20.0, 0.5e-9
ELASTIC_FRACTION = 0.6                    #: the elastic cases' depth, of delta_y
LADDER = (0.6, 0.7, 0.73, 0.765, 0.8, 0.9)  #: the slow check's depths, of delta_y
PROBE = "probe.dat"
PROBE_COLUMNS = ("time", "x_tip", "fz", "vm", "vm_x", "vm_z")


def onset_spec(*, spacing: float = SPACING, width: float = WIDTH, base: float | None = None,
               speed: float = SPEED,
               method: str = "tlsph", elastic: bool = False, depth: float = 2e-8,
               relax: float = RELAX) -> ParticleScratchSpec:
    """The slow check's scratch (`tests/md/test_scratch_onset.py`'s ``onset_spec``), with the
    changes of a case."""
    sub = {"E": E, "nu": NU, "density": DENSITY, **({} if elastic else {"sigma_y": SIGMA_Y})}
    return spec_from_mapping({
        "name": "onset-gap", "tip": f"sphere:{R * 1e6:g}um", "method": method,
        "target": {"substrate": sub},
        "grid": {"spacing": spacing, "width": width, "depth": width if base is None else base},
        "scratch": {"depth": depth, "length": LENGTH, "speed": speed,
                    "load_speed": LOAD_SPEED, "relax_time": relax, "frames": 0}})


# ---- changes to the input text ----------------------------------------------------------------

def common_field(index: int, value: float, text: str, spec: ParticleScratchSpec) -> str:
    """Set field ``index`` after ``*COMMON`` of the TLSPH pair_coeff (rho E nu Q1 Q2 hg Cp)."""
    def sub(m: re.Match) -> str:
        words = m.group(1).split()
        words[index] = lammps_number(value)
        return "*COMMON " + " ".join(words)
    new, n = re.subn(r"\*COMMON ((?:\S+ ){6}\S+)", sub, text)
    assert n == 1, "one *COMMON expected"
    return new


def rollers(text: str, spec: ParticleScratchSpec) -> str:
    """The ULSPH scratch's roller sides (`particle_scratch._roller_lines`) on a TLSPH block."""
    dx = si_to_lammps(spec.grid.spacing, "length", "particle")
    anchor = "fix sym_y sym_y smd/setvel NULL 0 NULL\n"
    assert anchor in text
    return text.replace(anchor, anchor + "\n".join(_roller_lines(spec.grid, dx)) + "\n")


def probe(text: str, spec: ParticleScratchSpec) -> str:
    """Print the largest von Mises stress and where it is, with the record."""
    m = re.search(r"fix record all print (\d+) ", text)
    every = m.group(1)
    row = " ".join(f"$({v}:%.10g)" for v in ("v_t", "v_x_tip", "v_fz", "c_vmmax[1]",
                                             "c_vmmax[2]", "c_vmmax[3]"))
    lines = ["compute vmmax all reduce max c_stress[7] x z replace 2 1 replace 3 1",
             f'fix probe all print {every} "{row}" file {PROBE} screen no '
             f'title "# {" ".join(PROBE_COLUMNS)}"']
    return text[:m.start()] + "\n".join(lines) + "\n" + text[m.start():]


@dataclass(frozen=True)
class Case:
    name: str
    change: str
    spec_args: dict = field(default_factory=dict)
    text: tuple = ()            #: functions (text, spec) -> text


CASES = {c.name: c for c in (
    Case("base", "the check's scratch (250 m/s, 0.1 um, 1.2 um block, free sides)"),
    Case("speed100", "stroke 100 m/s", {"speed": 100.0}),
    Case("speed50", "stroke 50 m/s", {"speed": 50.0}),
    Case("hg1", "hourglass 1 (not 10)", text=(partial(common_field, 5, 1.0),)),
    Case("q0", "artificial viscosity Q1 0 (not 0.06)", text=(partial(common_field, 3, 0.0),)),
    Case("rollers", "roller x ends and far y side", text=(rollers,)),
    Case("dx0.08", "lattice 0.08 um", {"spacing": 0.08e-6}),
    Case("block1.8", "block 1.8 um", {"width": 1.8e-6}),
    Case("deep1.8", "rigid base 1.8 um down (sides 1.2 um)", {"base": 1.8e-6}),
    Case("ulsph", "ULSPH (roller sides)", {"method": "ulsph"}),
)}


# ---- running ----------------------------------------------------------------------------------

def run_text(spec: ParticleScratchSpec, case: Case, run_dir: Path, with_probe: bool):
    text = scratch_input(spec)
    for change in case.text:
        text = change(text, spec)
    if with_probe:
        text = probe(text, spec)
    spec_dict = to_jsonable({**spec.to_dict(), "case": case.name})
    stale = [*run_dir.glob("fields.*.dump"), run_dir / RECORD, run_dir / FINAL_DUMP,
             run_dir / PROBE]
    run_particle_input(run_dir, f"in.{spec.method}", text, spec_dict, stale,
                       estimated_steps(spec), EngineOptions())
    return read_scratch(spec, run_dir)


def vm_per_load() -> float:
    """The model's largest von Mises stress over Hertz's p0 (frictionless: 0.620)."""
    from filmscale.continuum.contact.slider import Slider, slide

    spec = onset_spec()
    P = hertz_first_yield(spec)[0]
    ratio = slide(spec.target.stack, Slider("sphere", R), P, 0.0).first_yield["yield_ratio"]
    return ratio * SIGMA_Y / hertz_p0(P)


def hertz_p0(P):
    return (6 * np.asarray(P) * E_STAR**2 / (math.pi**3 * R**2)) ** (1 / 3)


def elastic_case(args) -> dict:
    case, root, fraction = args
    spec = onset_spec(elastic=True, relax=0.0, **case.spec_args)
    spec = at_depth(spec, fraction * hertz_first_yield(onset_spec())[2])
    tag = "" if fraction == ELASTIC_FRACTION else f"_{fraction:g}"
    run = run_text(spec, case, root / f"elastic_{case.name}{tag}", True)
    a = analyze_scratch(run)
    pr = read_probe(run, spec)
    with np.errstate(divide="ignore", invalid="ignore"):
        peak = pr["vm"] / (vm_per_load() * hertz_p0(np.maximum(pr["fz"], 1e-30)))
    idx = np.flatnonzero(pr["steady"])
    tenth = max(1, idx.size // 10)
    i_max = idx[np.argmax(peak[idx])]
    return {"case": case.name, "change": case.change, "particles": spec.grid.n_particles,
            "wall": run.wall_time, "Fn": a.normal_force_mean,
            "peak_descent": float(peak[pr["descent_end"]]),
            "peak_first": float(np.mean(peak[idx[:tenth]])),
            "peak_last": float(np.mean(peak[idx[-tenth:]])),
            "peak_max": float(peak[i_max]), "z_max": float(-pr["vm_z"][i_max]),
            "x_max": float(pr["x_tip"][i_max]), "a": math.sqrt(R * spec.stroke.depth)}


def read_probe(run, spec: ParticleScratchSpec) -> dict:
    """The probe's columns over the steady stroke, SI (time, tip x, normal force, largest von
    Mises stress and its particle's x and z)."""
    cols, data = parse_table((run.run_dir / PROBE).read_text())
    data = data[np.unique(data[:, 0], return_index=True)[1]]
    units = {"time": "time", "x_tip": "length", "fz": "force", "vm": "pressure",
             "vm_x": "length", "vm_z": "length"}
    col = {c: lammps_to_si(v, units[c], "particle") for c, v in zip(cols, data.T)}
    t1, T, _, _ = spec.stroke.times
    t, x = col["time"], col["x_tip"]
    col["steady"] = (t > t1) & (t <= t1 + T) & (x >= STEADY[0] * LENGTH) & \
        (x <= STEADY[1] * LENGTH)
    col["descent_end"] = int(np.flatnonzero(t <= t1)[-1])
    return col


def onset_point(args) -> dict:
    case, spec, run_dir = args
    run = run_text(spec, case, run_dir, True)
    a = analyze_scratch(run)
    ep = run.final.plastic_strain
    x = run.initial.positions[:, 0]
    sel = (x >= STEADY[0] * LENGTH) & (x <= STEADY[1] * LENGTH)
    under = ep[sel]
    hot = under > ONSET_THRESHOLD
    where = run.initial.positions[sel][hot]
    pr = read_probe(run, spec)
    return {"depth": spec.stroke.depth, "Fn": a.normal_force_mean, "hot": int(hot.sum()),
            "ep": float(np.max(under)), "wall": run.wall_time,
            "hot_z": sorted({round(-z / spec.grid.spacing) for z in where[:, 2]}),
            "hot_x": sorted({round(x / spec.grid.spacing) for x in where[:, 0]}),
            "vm_max": float(np.max(pr["vm"][pr["steady"]])) / SIGMA_Y}


def onset_ladder(case: Case, root: Path, pool, ladder=LADDER) -> dict:
    base = onset_spec(**case.spec_args)
    dy = hertz_first_yield(base)[2]
    tasks = [(case, at_depth(base, f * dy), root / f"onset_{case.name}" / f"depth_{f:g}")
             for f in ladder]
    points = list(pool.map(onset_point, tasks))
    first = next((k for k, p in enumerate(points) if p["hot"]), None)
    P_model = model_first_yield_load(base)
    out = {"case": case.name, "points": points, "P_model": P_model}
    if first:
        lo, hi = points[first - 1]["Fn"], points[first]["Fn"]
        out["onset"], out["error"] = 0.5 * (lo + hi), 0.5 * (hi - lo)
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", type=Path, default=None)
    p.add_argument("--cases", default=",".join(CASES))
    p.add_argument("--onset", default="")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--ladder", default=",".join(f"{f:g}" for f in LADDER),
                   help="the ladder's depths, of delta_y (default: the slow check's)")
    p.add_argument("--fraction", type=float, default=ELASTIC_FRACTION,
                   help="the elastic cases' depth, of delta_y")
    args = p.parse_args(argv)
    names = [c for c in args.cases.split(",") if c]
    ladder = [float(f) for f in args.ladder.split(",")]
    ladders = [c for c in args.onset.split(",") if c]
    for name in (*names, *ladders):
        if name not in CASES:
            p.error(f"unknown case {name!r}; cases: {', '.join(CASES)}")
    tmp = None
    if args.out is None:
        tmp = tempfile.TemporaryDirectory(prefix="onset_gap_")
        root = Path(tmp.name)
    else:
        root = args.out.resolve()
        root.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    P_model = model_first_yield_load(onset_spec())
    print(f"model first-yield load {P_model * 1e3:.4f} mN; its von Mises stress "
          f"{vm_per_load():.4f} p0; elastic cases at {args.fraction:g} delta_y")
    try:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(elastic_case, [(CASES[n], root, args.fraction) for n in names]))
            if rows:
                print("\n| case | change | particles | wall s | F_n / P_model | peak, descent "
                      "end | steady, first tenth | last tenth | largest | its depth / a | "
                      "at tip x / L | onset predicted / P_model |")
                print("|---|---|---|---|---|---|---|---|---|---|---|---|")
            for r in rows:
                print(f"| {r['case']} | {r['change']} | {r['particles']} | {r['wall']:.0f} | "
                      f"{r['Fn'] / P_model:.3f} | {r['peak_descent']:.3f} | "
                      f"{r['peak_first']:.3f} | {r['peak_last']:.3f} | {r['peak_max']:.3f} | "
                      f"{r['z_max'] / r['a']:.2f} | {r['x_max'] / LENGTH:.2f} | "
                      f"{1 / r['peak_max']**3:.3f} |", flush=True)
            for name in ladders:
                o = onset_ladder(CASES[name], root, pool, ladder)
                print(f"\nonset ladder, {name} ({CASES[name].change}): depths / delta_y "
                      f"{', '.join(f'{f:g}' for f in ladder)}")
                for f, pt in zip(ladder, o["points"]):
                    print(f"  {f:5.3f}: F_n / P_model {pt['Fn'] / o['P_model']:.3f}, "
                          f"{pt['hot']} particles above {ONSET_THRESHOLD:g}, largest "
                          f"{pt['ep']:.2g} (at lattice x {pt['hot_x']}, planes below the "
                          f"surface {pt['hot_z']}), largest von Mises over the steady stroke "
                          f"{pt['vm_max']:.3f} sigma_y, {pt['wall']:.0f} s")
                if "onset" in o:
                    print(f"  onset {o['onset'] * 1e3:.4f} +- {o['error'] * 1e3:.4f} mN = "
                          f"{o['onset'] / o['P_model']:.3f} +- {o['error'] / o['P_model']:.3f} "
                          "of the model's load", flush=True)
                else:
                    print("  the ladder does not bracket the onset", flush=True)
    finally:
        if tmp is not None:
            tmp.cleanup()
    print(f"\ntotal wall {time.perf_counter() - started:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
