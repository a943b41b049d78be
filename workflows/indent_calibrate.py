"""``filmscale indent calibrate``: frame compliance and tip area function from indents on a
reference sample, written as the area file ``indent analyze --area-file`` reads.

Also the reader options that ``indent analyze`` and ``indent calibrate`` share (instrument
format, column mapping, a TOML of reader options).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from filmscale.core.checks import check_real
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.files import atomic_path
from filmscale.core.jsonable import dumps

from .outputs import check_outputs, output_path, text_kind
from .quantity_args import add_quantity_argument

FORMAT_CHOICES = ("auto", "filmscale", "g200", "hysitron", "anton-paar", "delimited")


def add_reader_arguments(p) -> None:
    """--format, --columns and --reader of the commands that read curve files."""
    p.add_argument("--format", choices=FORMAT_CHOICES, default="auto",
                   help="file format (default auto: the filmscale table, else an instrument "
                        "export found from the file: workbook sheets, encoding, separator, "
                        "decimal comma, header rows)")
    p.add_argument("--columns", metavar="h=NAME[:UNIT],P=...,t=...",
                   help="column mapping: header name or 1-based number of each column, and "
                        "its unit where the header gives none, e.g. "
                        "'h=Depth:nm,P=Load:uN,t=Time:s'")
    p.add_argument("--reader", metavar="READER.toml",
                   help="reader options: format, encoding, separator, decimal, header_rows, "
                        "skip_rows, [columns] and [units] tables")


def add_arguments(isub) -> None:
    """``indent calibrate``, on the sub-parsers of ``indent``."""
    p = isub.add_parser(
        "calibrate", help="frame compliance and tip area function from reference indents",
        description="Fit the frame compliance and the area function A(h_c) = C0 h_c^2 + C1 h_c "
                    "+ C2 h_c^(1/2) + ... (Oliver & Pharr 1992, 2004) to indents on a reference "
                    "of known modulus, and write them as the area file that 'indent analyze "
                    "--area-file' reads. Every unloading of a multi-cycle test is one indent.")
    p.add_argument("files", nargs="+", metavar="FILES", help="curve files or folders")
    p.add_argument("--reference", required=True, metavar="fused-silica|tungsten|E=...,nu=...",
                   help="reference material: fused-silica (E 72.0 GPa, nu 0.17), tungsten "
                        "(409.8 GPa, 0.28), or E=72GPa,nu=0.17")
    p.add_argument("--fit", choices=("frame", "area", "both"), default="both",
                   help="fit the frame compliance, the area function or both (default)")
    p.add_argument("--tip", default="berkovich",
                   help="nominal tip: berkovich (default), cube-corner, cone:THETA")
    p.add_argument("--terms", type=int, default=4,
                   help="area coefficients C0..C(N-1), 2 to 9 (default 4; C0 stays the "
                        "nominal tip's unless --fit-c0)")
    p.add_argument("--fit-c0", action="store_true",
                   help="fit C0 as well (a real tip's differs from the ideal 24.5)")
    p.add_argument("--method", choices=("auto", "unloading", "csm"), default="auto",
                   help="indents from unloadings, or from every loading point of CSM tests "
                        "(default auto: csm when every curve has the harmonic stiffness)")
    p.add_argument("--surface", default="auto",
                   metavar="auto|file|fit|load:P|stiffness:S|slope:K",
                   help="contact point, as in indent analyze (default auto)")
    p.add_argument("--no-drift", action="store_true",
                   help="keep thermal drift (default: remove it as indent analyze does)")
    p.add_argument("--area-file", metavar="F.toml",
                   help="with --fit frame: the area function to keep (default: the nominal tip)")
    add_quantity_argument(p, "--frame-compliance", "m/N", metavar="C_F",
                          help="with --fit area: the frame compliance to remove, m/N or with "
                               "units (0.2 nm/mN; default 0)")
    p.add_argument("--window", default="0.2:0.98", metavar="LOW:HIGH",
                   help="unloading fit window, fractions of P_max (default 0.2:0.98)")
    add_reader_arguments(p)
    p.add_argument("--json", action="store_true", help="print the calibration as JSON (SI)")
    p.add_argument("--out", required=True, metavar="TIP.toml", help="the area file to write")
    p.add_argument("--force", action="store_true",
                   help="write the area file even when the quality gate refuses the fit, and "
                        "replace an existing file that is not an earlier output of this "
                        "command (an input is never replaced)")
    p.set_defaults(func=cmd_indent_calibrate)


def _window(text: str) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in text.split(":"))
    except ValueError:
        raise InputError(f"--window {text!r} must be LOW:HIGH, e.g. 0.2:0.98") from None
    lo = check_real("--window start", lo, low=0.0, high=1.0, high_open=True)
    return lo, check_real("--window end", hi, low=lo, high=1.0, low_open=True)


def _calibration_inputs(args):
    """The reference, tip, window, frame compliance, kept area function and reader options
    of ``indent calibrate``, each checked before any work (bad options stop here)."""
    from filmscale.continuum.indentation.io import read_area_function
    from filmscale.continuum.indentation.surface import parse_surface
    from filmscale.continuum.indentation.tip_calibration import parse_reference
    from filmscale.continuum.indentation.tips import parse_tip

    from .indent import reader_options

    reference = parse_reference(args.reference)
    parse_surface(args.surface)
    tip = parse_tip(args.tip)
    window = _window(args.window)
    if args.area_file and args.fit != "frame":
        raise InputError("--area-file is the area function kept by --fit frame; with --fit "
                         f"{args.fit} the area function is fitted")
    if args.frame_compliance is not None and args.fit != "area":
        raise InputError("--frame-compliance is the compliance kept by --fit area; with --fit "
                         f"{args.fit} it is fitted")
    C_f = 0.0 if args.frame_compliance is None else check_real(
        "--frame-compliance", args.frame_compliance, low=0.0, high=1.0, unit="m/N")
    check_real("--terms", args.terms, low=2, high=9)
    area = read_area_function(args.area_file, tip) if args.area_file else None
    read = reader_options(args.format, args.columns, args.reader)
    return reference, tip, window, C_f, area, read


def _calibration_files(args) -> list[Path]:
    """The curve files, --out checked against them and the --area-file."""
    from filmscale.continuum.indentation.tip_calibration import AREA_FILE_HEADER

    from .indent import expand_inputs

    output_path("--out", args.out, ("toml",))
    files = expand_inputs(args.files)
    check_outputs([("an input curve file", f) for f in files]
                  + ([("the --area-file", args.area_file)] if args.area_file else []),
                  [("--out", args.out, text_kind(AREA_FILE_HEADER, "a tip area file"))],
                  args.force)
    return files


def _read_indents(files, read, args) -> tuple[list, list[str], list[float]]:
    """(curves, names, surface shifts) of every curve of the files, prepared as ``indent
    analyze`` prepares them (drift, contact point); an unreadable file stops: exit 2."""
    from filmscale.continuum.indentation.io import read_curves

    from .indent import AnalysisOptions, prepare_curve

    prepare = AnalysisOptions(drift=not args.no_drift, surface=args.surface)
    curves, names, shifts = [], [], []
    for f in files:
        for name, curve in read_curves(f, read).items():
            curve, fields, _ = prepare_curve(curve, prepare)
            curves.append(curve)
            names.append(f"{f.stem}:{name}" if name != f.stem else name)
            shifts.append(fields["surface_shift"])
    return curves, names, shifts


def _print_calibration(args, cal, names, shifts) -> None:
    """The calibration (JSON or its summary) and, on stderr, how many surfaces were
    re-found."""
    if args.json:
        print(dumps({**cal.to_dict(), "surface_shift": dict(zip(names, shifts))}))
    else:
        print(cal.summary())
    moved = sum(1 for s in shifts if s)
    if moved:
        print(f"surface re-found on {moved} of {len(shifts)} curves (--surface {args.surface})",
              file=sys.stderr)


def _write_area_file(args, cal, problem: str | None) -> None:
    """The area file of --out, unless the quality gate refuses the fit (``problem``,
    `TipCalibration.problem`) and --force is not given (exit 1)."""
    if problem and not args.force:
        raise ModelRangeError(f"calibration refused, {args.out} not written: {problem} "
                              "(--force writes it anyway)")
    with atomic_path(Path(args.out)) as tmp:
        Path(tmp).write_text(cal.area_file_text("nm"), encoding="utf-8")
    if problem:
        print(f"filmscale: warning: written although refused (--force): {problem}",
              file=sys.stderr)


def cmd_indent_calibrate(args) -> int:
    from filmscale.continuum.indentation.tip_calibration import calibrate_tip

    reference, tip, window, C_f, area, read = _calibration_inputs(args)
    files = _calibration_files(args)
    start = time.perf_counter()
    curves, names, shifts = _read_indents(files, read, args)
    cal = calibrate_tip(curves, reference, tip=tip, fit=args.fit, terms=args.terms,
                        frame_compliance=C_f, area=area, window=window, fit_c0=args.fit_c0,
                        method=args.method, names=names)
    elapsed = time.perf_counter() - start
    problem = cal.problem()
    _print_calibration(args, cal, names, shifts)
    _write_area_file(args, cal, problem)
    what = "CSM points" if cal.method == "csm" else "indents"
    print(f"calibrated on {len(cal.h_c)} {what} from {len(files)} files in {elapsed:.2f} s; "
          f"wrote {args.out}", file=sys.stderr)
    return 0
