"""``filmscale calibrate``: a layer's E, sigma_y (and n) from curve files, through the same
function the scene pipeline calls (`filmscale.continuum.calibration.route.calibrate`)."""

from __future__ import annotations

import argparse
import sys

from filmscale.core.errors import InputError
from filmscale.core.jsonable import dumps

from .quantity_args import add_quantity_argument


def _substrate_arg(text: str):
    """E,nu[,sigma_y] in Pa or with units ("90 GPa,0.25,2 GPa"): the substrate under a film."""
    from filmscale.continuum.materials import ElasticPlastic
    from filmscale.core.quantities import to_si
    parts = text.split(",")
    try:
        values = [float(to_si(f"--substrate {name}", v, unit))
                  for v, name, unit in zip(parts, ("E", "nu", "sigma_y"), ("Pa", "", "Pa"))]
    except (InputError, ValueError) as err:
        raise argparse.ArgumentTypeError(f"expected E,nu[,sigma_y] (Pa or with units), got "
                                         f"{text!r}: {err}") from None
    if len(parts) not in (2, 3):
        raise argparse.ArgumentTypeError(f"expected E,nu[,sigma_y] (Pa), got {text!r}")
    try:
        return ElasticPlastic(*values, name="substrate")
    except InputError as err:
        raise argparse.ArgumentTypeError(f"--substrate: {err}") from None


def cmd_calibrate(args) -> int:
    from filmscale.continuum.calibration.route import calibrate
    from filmscale.continuum.indentation.io import read_curves
    if (args.film_thickness is None) != (args.substrate is None):
        raise InputError("--film-thickness and --substrate go together (a film on a "
                         "substrate), or leave both out (a half-space)")
    curves = [c for path in args.curves for c in read_curves(path).values()]
    cal = calibrate(curves, nu=args.nu, tip=args.tip, tip_material=args.tip_material,
                    thickness=args.film_thickness, substrate=args.substrate, law=args.law,
                    layer=args.layer, contact_zero=args.contact_zero)
    check = cal.cross_check(args.tolerance, exclude=args.exclude)
    if args.json:
        print(dumps({
            "E": cal.E.value, "E_std": cal.E.std, "E_identified": cal.E.identified,
            "sigma_y": cal.sigma_y.value, "sigma_y_std": cal.sigma_y.std,
            "sigma_y_identified": cal.sigma_y.identified,
            "n": cal.n.value if cal.n.identified else None,
            "n_std": cal.n.std if cal.n.identified else None,
            "h_star": None if cal.h_star is None else cal.h_star.value,
            "nu": cal.nu, "route": cal.route, "model": cal.model,
            "cross_check_rms": check.rms, "cross_check_tolerance": check.tolerance,
            "passed": check.passed, "cross_check_noise": check.noise,
            "cross_check_excluded": check.excluded, "cross_check_lacks": check.lacks,
            "points": cal.points, "warnings": list(cal.warnings)}))
    else:
        print(cal.summary())
        print(f"  {check.text()}")
    for warning in cal.warnings:
        print(f"filmscale: warning: {warning}", file=sys.stderr)
    return 0


def add_commands(sub) -> None:
    from filmscale.continuum.calibration.result import EXCLUDES, NOISE_FACTOR
    from filmscale.continuum.calibration.target import CONTACT_ZEROS, TIP_MATERIALS
    from filmscale.continuum.contact.laws import LAW_NAMES
    p = sub.add_parser(
        "calibrate", help="E, sigma_y (and n) of a layer from curve files",
        description="Calibrate a layer from load-displacement curves: spherical tips through "
                    "the contact law (on a half-space, or as a film on a stated substrate), a "
                    "sharp tip through Dao's reverse analysis. Prints E, sigma_y and n with "
                    "their standard deviations and the cross-scale check of the calibrated "
                    "forward model against the curves.")
    p.add_argument("curves", nargs="+", help="curve files (text tables or HDF5)")
    p.add_argument("--tip", help="the tip of every curve, e.g. sphere:5um or berkovich "
                                 "(default: each curve's own)")
    p.add_argument("--tip-material", choices=TIP_MATERIALS, default="diamond",
                   help="rigid (MD and particle runs) or diamond (default, measured curves)")
    add_quantity_argument(p, "--film-thickness", "m", metavar="T",
                          help="the layer is a film of thickness T (m, or with units: 1 um) "
                               "on --substrate")
    p.add_argument("--substrate", type=_substrate_arg, metavar="E,nu[,sigma_y]",
                   help="the substrate under the film, Pa or with units: 90GPa,0.25,2GPa "
                        "(without sigma_y it takes the film's)")
    p.add_argument("--law", choices=LAW_NAMES, default="komvopoulos-ye-continuous",
                   help="sphere contact law (default komvopoulos-ye-continuous)")
    p.add_argument("--contact-zero", choices=CONTACT_ZEROS,
                   help="sphere tips: fit the depth zero with E, or hold it fixed at the "
                        "curves' h = 0 (default: fit for a rigid tip, fixed for diamond)")
    p.add_argument("--nu", type=float, default=0.3,
                   help="the layer's Poisson ratio, assumed (default 0.3)")
    p.add_argument("--layer", default="layer", help="the layer's name in the output")
    p.add_argument("--tolerance", type=float,
                   help="cross-scale check: largest rms misfit over the largest load "
                        f"(default {NOISE_FACTOR:g} x the curves' own load noise)")
    p.add_argument("--exclude", choices=[e for e in EXCLUDES if e], default="",
                   help="leave the loading up to the bottom of the first pop-in out of the "
                        "check")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.set_defaults(func=cmd_calibrate)

