"""Issue 35's cone checks in MD: a Cu(001) half-space scratched by a rigid frictionless cone at
constant depth, against Goddard & Wilman's ploughing friction and against the indentation
hardness of the same crystal and cone.

    .venv/bin/python benchmarks/md_cone_scratch.py --out DIR [--np 2] [--depth 1.2nm]
        [--half-angle 60] [--seed 2027] [--spec OTHER.toml]

Runs two MD runs in DIR (the scratch of `examples/md/cone_scratch_cu.toml`, a 45 deg cone
0.8 nm deep unless told otherwise, and its indentation twin, `md.groove_onset.
indentation_twin`: the same crystal, slab cross-section, cone and protocol, indented to the
scratch depth; finished runs are read back) and prints one table:

- the ploughing friction F_lat / F_n over the steady stroke against (2/pi) cot(theta)
  (Goddard & Wilman, Wear 5, 114 (1962): a rigid-plastic groove, contact on the front half of
  the cone, no friction on its faces; the wall pushes along the flank normal, so the contact
  is frictionless);
- the scratch hardness 8 F_n / (pi w^2) (Williams, Tribol. Int. 29, 675 (1996)) with three
  widths w: the residual groove's at the undeformed surface level, between its pile-up
  crests, and the loaded contact's at the end of the stroke (`md.cone_contact`); against the
  twin's Oliver-Pharr hardness (`continuum.indentation.oliver_pharr`, the cone's area
  function), its load at depth over the nominal section pi (r0 + h tan(theta))^2, and its
  load over pi a^2 of its own loaded contact.

The cone is `fix wall/region` on a moving `region cone` (docs/md-indentation.md, "The cone's
contact"). Cost on 2 cores: 6-7 min for the scratch (24 200 atoms, 26 500 steps; 9 min at
1.2 nm) and 1-2 min for the twin.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation.curves import LOAD
from filmscale.continuum.indentation.oliver_pharr import oliver_pharr
from filmscale.core.quantities import to_si
from filmscale.md.cone_contact import indentation_contact, scratch_contact
from filmscale.md.engine import EngineOptions
from filmscale.md.groove_onset import indentation_twin
from filmscale.md.indentation import RigidIndenter
from filmscale.md.run import run_indentation
from filmscale.md.scratch import load_scratch_spec
from filmscale.md.scratch_run import analyze_scratch, groove_profile, run_scratch

SPEC = Path(__file__).resolve().parents[1] / "examples" / "md" / "cone_scratch_cu.toml"


def _spec(depth: float | None, half_angle: float | None, seed: int | None, path: Path = SPEC):
    spec = load_scratch_spec(path)
    indent = spec.indent
    if half_angle is not None:
        cone = indent.indenter
        indent = dataclasses.replace(indent, indenter=RigidIndenter.cone(
            half_angle, cone.tip.tip_radius, cone.K, cone.height))
    if seed is not None:
        indent = dataclasses.replace(indent, protocol=dataclasses.replace(indent.protocol,
                                                                          seed=seed))
    stroke = spec.stroke if depth is None else dataclasses.replace(spec.stroke, depth=depth)
    return dataclasses.replace(spec, indent=indent, stroke=stroke)


def indentation_hardness(run) -> dict:
    """The twin's hardness, Pa: Oliver-Pharr's; the load at the end of the loading over the
    nominal section there, pi (r0 + h tan(theta))^2; and the load at the end of the hold (its
    dump) over pi a^2, a the farthest atom the cone pushes (`md.cone_contact`), with the
    contact's load against the record's (the geometry's check)."""
    curve = run.curve.finite()
    spec = run.spec
    tip = spec.indenter.tip
    op = oliver_pharr(curve, tip)
    end = int(np.flatnonzero(curve.segment == LOAD)[-1])
    r = tip.tip_radius + curve.h[end] * math.tan(math.radians(tip.half_angle))
    contact = indentation_contact(run)
    step = spec.protocol.schedule().s_unload
    recorded = float(run.curve.P[np.argmin(np.abs(run.steps - step))])   # steps: unfiltered
    return {"H_op": float(op.H), "H_nominal": float(curve.P[end]) / (math.pi * r * r),
            "H_contact": contact.normal_force / (math.pi * contact.radius**2),
            "P_loaded": float(curve.P[end]), "contact_radius": contact.radius,
            "contact_check": contact.normal_force / recorded - 1.0}


def scratch_touch(run) -> dict:
    """The scratch's contact at the end of its stroke (loaded, its dump): width across the
    groove, the share of the load behind the axis, and its load against the record's."""
    contact = scratch_contact(run)
    k = int(np.argmin(np.abs(run.data["step"] - run.spec.schedule().s_unload)))
    return {"width": contact.width, "rear_share": contact.rear_share(),
            "normal_force": float(run.data["fz"][k]),
            "contact_check": contact.normal_force / float(run.data["fz"][k]) - 1.0}


def crest_width(run) -> float:
    """The residual groove's width between its pile-up crests (the highest point of the
    mid-stroke profile either side of the axis, within twice the contact radius), m."""
    y, h, _ = groove_profile(run)
    near = np.isfinite(h) & (np.abs(y) <= 2 * run.spec.contact_radius)
    left, right = near & (y < 0), near & (y > 0)
    return float(y[right][np.argmax(h[right])] - y[left][np.argmax(h[left])])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="run directory root")
    parser.add_argument("--np", type=int, default=2)
    parser.add_argument("--depth", default=None, help="scratch depth, e.g. 0.8nm")
    parser.add_argument("--half-angle", type=float, default=None, help="deg")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--spec", type=Path, default=SPEC, help="another scratch spec")
    args = parser.parse_args(argv)
    depth = None if args.depth is None else to_si("--depth", args.depth, "m")
    spec = _spec(depth, args.half_angle, args.seed, args.spec)
    engine = EngineOptions(np=args.np)
    root = Path(args.out)
    theta = spec.indent.indenter.tip.half_angle
    tag = f"theta{theta:g}_d{spec.stroke.depth * 1e9:g}nm_s{spec.indent.protocol.seed}"
    if args.spec != SPEC:
        tag = f"{spec.indent.name}_{tag}"
    t0 = time.perf_counter()
    scratch_run = run_scratch(spec, root / f"scratch_{tag}", engine)
    scratch = analyze_scratch(scratch_run)
    touch = scratch_touch(scratch_run)
    t1 = time.perf_counter()
    twin_run = run_indentation(indentation_twin(spec, spec.stroke.depth), root / f"twin_{tag}",
                               engine)
    twin = indentation_hardness(twin_run)
    t2 = time.perf_counter()
    ploughing = 2.0 / math.pi / math.tan(math.radians(theta))
    w = scratch.groove_width
    H_s = 8.0 * scratch.normal_force_mean / (math.pi * w * w)
    print(f"cone {theta:g} deg, depth {spec.stroke.depth * 1e9:.3g} nm, "
          f"seed {spec.indent.protocol.seed}; scratch {t1 - t0:.0f} s, twin {t2 - t1:.0f} s "
          f"(wall, {args.np} ranks; a finished run is read back)")
    print("| check | measured | reference | ratio | issue 35 |")
    print("|---|---|---|---|---|")
    mu = scratch.friction_mean
    print(f"| ploughing friction F_lat/F_n | {mu:.3f} +- {scratch.friction_std:.3f} (std) | "
          f"(2/pi) cot(theta) = {ploughing:.3f} | {mu / ploughing:.3f} | within 20 % |")
    for key, name in (("H_op", "Oliver-Pharr"), ("H_nominal", "load / nominal section")):
        H = twin[key]
        print(f"| scratch hardness 8 F_n/(pi w^2), w residual | {H_s / 1e9:.2f} GPa | "
              f"indentation, {name}: {H / 1e9:.2f} GPa | {H_s / H:.3f} | within 15 % |")
    w_crest = crest_width(scratch_run)
    H_crest = 8.0 * scratch.normal_force_mean / (math.pi * w_crest * w_crest)
    print(f"| scratch hardness, w between the residual pile-up crests | {H_crest / 1e9:.2f} GPa "
          f"| indentation, load / nominal section: {twin['H_nominal'] / 1e9:.2f} GPa | "
          f"{H_crest / twin['H_nominal']:.3f} | within 15 % |")
    w_c = touch["width"]          # steady along the stroke; the load is the stroke's mean
    H_c = 8.0 * scratch.normal_force_mean / (math.pi * w_c * w_c)
    print(f"| scratch hardness, w the loaded contact's width | {H_c / 1e9:.2f} GPa | "
          f"indentation, load / pi a^2 of its contact: {twin['H_contact'] / 1e9:.2f} GPa | "
          f"{H_c / twin['H_contact']:.3f} | (like for like) |")
    print(f"scratch: F_n {scratch.normal_force_mean * 1e9:.1f} nN, F_lat "
          f"{scratch.lateral_force_mean * 1e9:.1f} nN, groove {scratch.groove_depth * 1e9:.3f} "
          f"nm deep, {w * 1e9:.3f} nm wide, pile-up {scratch.pileup_height * 1e9:.3f} nm; "
          f"twin: load at depth {twin['P_loaded'] * 1e9:.1f} nN, F_n / P "
          f"{scratch.normal_force_mean / twin['P_loaded']:.3f} (Williams: 0.5)")
    print(f"widths: residual at the surface level {w * 1e9:.3f} nm, between the crests "
          f"{w_crest * 1e9:.3f} nm, the loaded contact {w_c * 1e9:.3f} nm")
    print(f"contact (loaded dumps): scratch {w_c * 1e9:.3f} nm wide, {touch['rear_share']:.3f} "
          f"of its load behind the axis (Williams: 0); twin a = "
          f"{twin['contact_radius'] * 1e9:.3f} nm; the contacts' loads against the records: "
          f"{touch['contact_check']:+.1e}, {twin['contact_check']:+.1e}")


if __name__ == "__main__":
    main()
