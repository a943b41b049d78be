"""``filmscale indent``: its commands ``analyze`` (Oliver-Pharr or CSM analysis of curve files
and folders, with the contact point re-found, the file's own area function where asked, and a
table that names every curve whole), ``calibrate`` (`indent_calibrate`) and ``reverse`` (Dao's
reverse analysis of a sharp-tip curve)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation.film_substrate import FILM_MODELS
from filmscale.core.checks import check_real
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_path
from filmscale.core.jsonable import dumps

from . import indent_calibrate
from .calibrate_cli import substrate_arg
from .outputs import add_force_argument, check_outputs, hdf5_kind, output_path, text_kind
from .quantity_args import add_quantity_argument

#: the film's Poisson ratio when --nu is not given
FILM_NU = 0.3

#: header of the per-indent table ``--profile`` writes (a [target.profile] file of scenes)
PROFILE_HEADER = "h_c [nm], E_r [GPa], H [GPa]"


# ---- the parsers ---------------------------------------------------------------------------

def add_arguments(sub) -> None:
    """``indent`` and its commands, in the order its help lists them: analyze, calibrate
    (`indent_calibrate`), reverse."""
    indent = sub.add_parser("indent", help="indentation analysis: Oliver-Pharr, reverse analysis",
                            description="Analyse indentation load-displacement curves.")
    isub = indent.add_subparsers(dest="indent_command", required=True)
    for add in (_add_analyze_arguments, indent_calibrate.add_arguments,
                _add_reverse_arguments):
        add(isub)


def _add_analyze_arguments(isub) -> None:
    """``indent analyze``."""
    p = isub.add_parser("analyze", help="Oliver-Pharr or CSM analysis of one or many curves",
                        description="Oliver-Pharr (or, with --csm, continuous-stiffness) "
                                    "analysis of curve files (text with units in the header, "
                                    "e.g. 'h [nm], P [uN], t [s]', filmscale HDF5, or "
                                    "instrument exports: G200/iMicro .xls and .xlsx, Hysitron "
                                    ".hld and TriboScan .txt, Anton Paar and other delimited "
                                    "text) and of every curve file inside the folders given.")
    p.add_argument("files", nargs="+", metavar="FILES", help="curve files or folders")
    p.add_argument("--tip", help="berkovich, cube-corner, cone:THETA, sphere:R, "
                                 "sphero-conical:R[:THETA], flat:RADIUS (lengths in m or "
                                 "with nm/um); default: the indenter each curve names")
    p.add_argument("--area-file", metavar="F.toml|file",
                   help="polynomial area function: a TOML file (C = [C0, C1, ...], "
                        "length_unit = 'nm'), or 'file' (also 'vendor'): the one each curve's "
                        "file states, with its method's beta and Poisson ratio")
    p.add_argument("--window", type=_window_arg, default=(0.2, 0.98), metavar="LOW:HIGH",
                   help="unloading fit window, fractions of P_max (default 0.2:0.98)")
    p.add_argument("--surface", default="auto",
                   metavar="auto|file|fit|load:P|stiffness:S|slope:K",
                   help="contact point: auto (default: the file's zero, unless where the load "
                        "leaves its noise and the loading power law's zero both lie beyond 2 %% "
                        "of h_max from it), the file's zero, the loading power law's zero, or "
                        "where the load, the CSM stiffness or dP/dh first exceeds a threshold "
                        "(SI or with units: load:2uN)")
    p.add_argument("--csm", action="store_true",
                   help="continuous stiffness: E_r, E and H at every loading point from the "
                        "harmonic contact stiffness, and their averages over --depth-range")
    p.add_argument("--depth-range", type=_depth_range_arg, metavar="LOW:HIGH",
                   help="with --csm: depths of the averages (100nm:200nm; default the file's "
                        "own, else every point)")
    p.add_argument("--epsilon", type=_constant_arg(("tip", "exponent")), default="tip",
                   help="geometry constant: tip (default), exponent, or a number")
    p.add_argument("--beta", type=_constant_arg(("tip", "hay", "no-slip")), default="tip",
                   help="beta: tip (default), hay, no-slip, or a number")
    p.add_argument("--nu", type=float, help="sample Poisson ratio: adds E to the results")
    add_quantity_argument(p, "--frame-compliance", "m/N", metavar="C_F",
                          help="frame compliance to remove: m/N, or with units (0.2 nm/mN)")
    p.add_argument("--no-drift", action="store_true",
                   help="keep thermal drift (default: remove the drift of a low-load hold)")
    indent_calibrate.add_reader_arguments(p)
    p.add_argument("--cycles", action="store_true",
                   help="analyse every unloading of multi-cycle tests: one record per cycle "
                        "(NAME#1, NAME#2, ...), a depth profile from one indent")
    p.add_argument("--shallow-correction", action="store_true",
                   help="add the Yeo-Polycarpou hardness H_shallow when an elastic indent "
                        "is among the curves")
    p.add_argument("--layers", type=_lengths_arg, metavar="Z1,Z2,...",
                   help="layer interface depths for the profile (m, or with nm/um)")
    p.add_argument("--layer-names", metavar="A,B,...,SUBSTRATE",
                   help="one name per layer and one for the substrate")
    p.add_argument("--json", action="store_true", help="print one JSON object per curve (SI)")
    p.add_argument("--out", metavar="RESULTS.h5", help="HDF5 file of all results")
    p.add_argument("--profile", metavar="PROFILE.csv",
                   help="write h_c, E_r, H per indent: a [target.profile] file for scenes")
    p.add_argument("--plot", metavar="DIR", help="one plot per curve and the depth profile")
    p.add_argument("--film-model", choices=FILM_MODELS,
                   help="the film's Young's modulus from the profile's indents with h_c >= t/10 "
                        "by a film/substrate model (needs --film-thickness and --substrate; "
                        "the film's Poisson ratio is --nu, default 0.3)")
    add_quantity_argument(p, "--film-thickness", "m", metavar="T",
                          help="with --film-model: the film's thickness, m or with units (500nm)")
    p.add_argument("--substrate", type=substrate_arg, metavar="E,nu",
                   help="with --film-model: the substrate under the film, Pa or with units "
                        "(70GPa,0.22)")
    p.add_argument("--workers", type=int, help="worker processes (default: all CPUs, max 8)")
    add_force_argument(p)
    p.set_defaults(func=cmd_indent_analyze)


def _add_reverse_arguments(isub) -> None:
    """``indent reverse``."""
    p = isub.add_parser("reverse", help="E*, sigma_r, n, sigma_y from a sharp-tip curve (Dao)",
                        description="Reverse analysis of sharp indentation (Dao et al. 2001): "
                                    "from the loading curvature C, the unloading slope dP/dh, "
                                    "W_p/W_t and the maximum depth h_m to E*, the 3.3 % "
                                    "representative stress sigma_r, n and sigma_y, each with "
                                    "its standard deviation (Monte Carlo over the inputs' "
                                    "standard deviations). With --C2/--tip2: dual indenter "
                                    "(Chollacoop, Dao & Suresh 2003). SI units.")
    add_quantity_argument(p, "--C", "Pa", required=True,
                          help="loading curvature P/h^2: Pa, or with units (30 GPa)")
    add_quantity_argument(p, "--dPdh", "N/m", required=True,
                          help="initial unloading slope: N/m, or with units (2e5 N/m)")
    p.add_argument("--WpWt", type=float, required=True, help="plastic over total work")
    add_quantity_argument(p, "--hm", "m", required=True,
                          help="maximum depth h_m: m, or with units (500 nm)")
    p.add_argument("--tip", default="berkovich", help="berkovich (default) or cone:70.3")
    p.add_argument("--WpWt-std", type=float, default=0.0, dest="WpWt_std",
                   help="standard deviation of --WpWt (default 0)")
    for name, unit in (("C", "Pa"), ("dPdh", "N/m"), ("hm", "m")):
        add_quantity_argument(p, f"--{name}-std", unit, default=0.0, dest=f"{name}_std",
                              help=f"standard deviation of --{name}, {unit} (default 0)")
    add_quantity_argument(p, "--C2", "Pa",
                          help="second tip's loading curvature, Pa (dual indenter)")
    add_quantity_argument(p, "--C2-std", "Pa", default=0.0, dest="C2_std",
                          help="standard deviation of --C2, Pa")
    p.add_argument("--tip2", help="second tip, cone:THETA with THETA in 50-80 deg")
    p.add_argument("--nu", type=float, default=0.3, help="sample Poisson ratio (default 0.3)")
    add_quantity_argument(p, "--E-i", "Pa", default=1100e9, dest="E_i",
                          help="indenter modulus, Pa (default 1100e9, as Dao et al.)")
    p.add_argument("--nu-i", type=float, default=0.07, dest="nu_i",
                   help="indenter Poisson ratio (default 0.07)")
    p.add_argument("--method", choices=("closed-form", "surrogate"), default="closed-form",
                   help="Dao's closed form (default) or the surrogate trained on the FE cases")
    p.add_argument("--samples", type=int, default=2000, help="Monte Carlo draws (default 2000)")
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.set_defaults(func=cmd_indent_reverse)


# ---- indent analyze: its option types ------------------------------------------------------

def _window_arg(text: str) -> tuple[float, float]:
    parts = text.split(":")
    try:
        low, high = (float(v) for v in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected LOW:HIGH fractions of P_max, got {text!r}") \
            from None
    return low, high


def _constant_arg(choices):
    def parse(text: str):
        if text in choices:
            return text
        try:
            return float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected one of {', '.join(choices)} or a "
                                             f"number, got {text!r}") from None
    return parse


def _lengths_arg(text: str) -> tuple[float, ...]:
    from filmscale.continuum.indentation.tips import parse_length
    try:
        return tuple(check_real("--layers depth", parse_length(v, "--layers depth"), low=0.0,
                                low_open=True, unit="m")
                     for v in text.split(",") if v.strip())
    except InputError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def _profile_table(profile, path: Path) -> None:
    """Per-indent (h_c, E_r, H) in the units scenes read ([target.profile] file)."""
    data = np.column_stack([profile.h_c * 1e9, profile.E_r / 1e9, profile.H / 1e9])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=", ", header=PROFILE_HEADER,
                   comments="", fmt="%.10g")


def _depth_range_arg(text: str) -> tuple[float, float]:
    """LOW:HIGH depths, each in m or with a unit (100nm:200nm)."""
    from filmscale.continuum.indentation.tips import parse_length
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise InputError(f"--depth-range {text!r} must be LOW:HIGH, e.g. 100nm:200nm")
        lo, hi = (parse_length(v.strip(), "--depth-range depth") for v in parts)
        lo = check_real("--depth-range start", lo, low=0.0, high=1e-3, unit="m")
        return lo, check_real("--depth-range end", hi, low=lo, high=1e-3, low_open=True,
                              unit="m")
    except InputError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


# ---- indent analyze: its options, checked before any work ----------------------------------

def _analysis_options(args):
    """The `AnalysisOptions` of ``indent analyze``, every option checked before any work."""
    from filmscale.continuum.indentation.surface import parse_surface

    from .indent import AREA_FROM_FILE, AnalysisOptions

    from_file = args.area_file in AREA_FROM_FILE
    frame = _frame_compliance(args, from_file)
    parse_surface(args.surface)
    options = AnalysisOptions(tip=args.tip, area_file=args.area_file, window=args.window,
                              epsilon=args.epsilon, beta=args.beta, nu=args.nu,
                              frame_compliance=frame or 0.0,
                              drift=not args.no_drift, plot_dir=args.plot,
                              read_format=args.format, columns=args.columns,
                              read_options=args.reader, cycles=args.cycles,
                              surface=args.surface, csm=args.csm,
                              depth_range=args.depth_range)
    _check_tip_area_reader(args, options, from_file)
    _check_ranges(args)
    _check_method_options(args)
    _check_film_options(args)
    if args.shallow_correction and from_file:
        raise InputError("--shallow-correction needs one area function for every curve: give "
                         "an area file, not --area-file file")
    return options


def _frame_compliance(args, from_file: bool) -> float | None:
    """--frame-compliance, else the one an area file written by `indent calibrate` states
    (None: neither gives one)."""
    if args.frame_compliance is None and args.area_file and not from_file:
        from filmscale.continuum.indentation.io import read_frame_compliance
        return read_frame_compliance(args.area_file)   # what `indent calibrate` wrote with it
    return args.frame_compliance


def _check_tip_area_reader(args, options, from_file: bool) -> None:
    """A bad --tip, --area-file or reader option (--format, --columns, --reader) stops here,
    before any work."""
    from .indent import reader_options, resolve_tip
    if args.tip and not from_file:
        resolve_tip(options)
    elif args.tip:
        from filmscale.continuum.indentation.tips import parse_tip
        parse_tip(args.tip)
    elif args.area_file and not from_file:
        raise InputError("--area-file needs --tip (the nominal tip it refines)")
    reader_options(args.format, args.columns, args.reader)


def _check_ranges(args) -> None:
    """The ranges the analysis checks for each curve, refused here once before any curve."""
    check_real("--window start", args.window[0], low=0.0, high=1.0, high_open=True)
    check_real("--window end", args.window[1], low=args.window[0], high=1.0, low_open=True)
    if args.nu is not None:
        check_real("--nu", args.nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    if args.frame_compliance is not None:
        check_real("--frame-compliance", args.frame_compliance, low=0.0, high=1.0, unit="m/N")
    if not isinstance(args.epsilon, str):
        check_real("--epsilon", args.epsilon, low=0.5, high=1.0)
    if not isinstance(args.beta, str):
        check_real("--beta", args.beta, low=0.5, high=2.0)
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers = {args.workers} must be at least 1")


def _check_method_options(args) -> None:
    """The options that go together: a derived --beta with --nu; --csm with a numeric or the
    tip's --beta and --epsilon, and with neither --cycles nor --shallow-correction;
    --depth-range with --csm."""
    if args.beta in ("hay", "no-slip") and args.nu is None:
        raise InputError(f"--beta {args.beta} needs the sample Poisson ratio --nu")
    if args.csm and (args.cycles or args.shallow_correction):
        raise InputError("--csm analyses every loading point of a test: it does not combine "
                         "with --cycles or --shallow-correction")
    if args.csm and args.beta in ("hay", "no-slip"):
        raise InputError(f"--csm takes a numeric --beta, not {args.beta}")
    if args.csm and args.epsilon == "exponent":
        raise InputError("--csm takes the tip's or a numeric --epsilon: a CSM point has no "
                         "unloading exponent to derive it from")
    if args.depth_range and not args.csm:
        raise InputError("--depth-range is the depth range of the CSM averages: give --csm")


def _check_film_options(args) -> None:
    """--film-model goes with --film-thickness and --substrate, and they with it."""
    if args.film_model is None:
        given = [flag for flag, value in (("--film-thickness", args.film_thickness),
                                          ("--substrate", args.substrate)) if value is not None]
        if given:
            raise InputError(f"{' and '.join(given)} apply to a film model: give --film-model "
                             f"({', '.join(FILM_MODELS)})")
        return
    for flag, value, what in (("--film-thickness", args.film_thickness, "the film's thickness"),
                              ("--substrate", args.substrate, "the substrate's E,nu")):
        if value is None:
            raise InputError(f"--film-model {args.film_model} needs {flag} ({what})")
    check_real("--film-thickness", args.film_thickness, low=0.0, high=1e-3, low_open=True,
               unit="m")


def _film_points(records) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(h_c, E_r, a) of the profile's points, a = sqrt(A_c/pi): an indent's own contact area;
    a CSM test's binned points (`indent.csm_profile_points`) with the area of its own
    loading points interpolated at each bin's h_c."""
    from .indent import csm_profile_points
    rows = []
    for r in records:
        if r.get("status") != 0:
            continue
        if r.get("csm"):
            h, area = (np.asarray(r["csm"][k], dtype=float) for k in ("h_c", "A"))
            keep = np.isfinite(h) & np.isfinite(area) & (area > 0)
            order = np.argsort(h[keep])
            for h_c, E_r, _ in csm_profile_points(r):
                A = np.interp(h_c, h[keep][order], area[keep][order])
                rows.append((h_c, E_r, np.sqrt(A / np.pi)))
        elif r.get("A_c") is not None and r["A_c"] > 0:
            rows.append((r["h_c"], r["E_r"], np.sqrt(r["A_c"] / np.pi)))
    if not rows:
        return np.empty(0), np.empty(0), np.empty(0)
    return tuple(np.array(c, dtype=float) for c in zip(*rows))


def _film_fit(args, records):
    """The `FilmModulus` of --film-model over the analysed records (InputError when too few
    indents lie in its range)."""
    from filmscale.continuum.indentation.film_substrate import film_modulus
    from filmscale.continuum.materials import DIAMOND
    h_c, E_r, a = _film_points(records)
    return film_modulus(h_c, E_r, a, thickness=args.film_thickness, substrate=args.substrate,
                        model=args.film_model,
                        nu=args.nu if args.nu is not None else FILM_NU, indenter=DIAMOND)


def _nix_gao_line(nix_gao) -> str:
    if not nix_gao.identified:
        return (f"Nix-Gao: h* not identified: {nix_gao.reason}; H = H0 (depth-independent) "
                f"= {nix_gao.H0 / 1e9:.4g} +- {nix_gao.H0_std / 1e9:.2g} GPa")
    return (f"Nix-Gao: H0 = {nix_gao.H0 / 1e9:.4g} +- {nix_gao.H0_std / 1e9:.2g} GPa, "
            f"h* = {nix_gao.h_star * 1e9:.4g} +- {nix_gao.h_star_std * 1e9:.2g} nm")


def _num(value, scale: float, fmt: str) -> str:
    return "-" if value is None or not np.isfinite(value) else format(value / scale, fmt)


def _pm(r: dict, key: str) -> str:
    """``mean +- std`` in GPa of a CSM average."""
    return f"{_num(r.get(key + '_mean'), 1e9, '.4g')} +- {_num(r.get(key + '_std'), 1e9, '.2g')}"


# ---- indent analyze: what it prints ---------------------------------------------------------

def _analysed(r: dict) -> bool:
    return r.get("status") == 0


def _vendor_difference(r: dict, key: str) -> str:
    """The relative difference of E or H from the instrument's own value, or "-"."""
    difference = r.get("vendor_difference") or {}
    return format(difference[key], "+.2%") if key in difference else "-"


def _csm_columns(records, with_E: bool) -> list:
    """(header, width, cell) of a CSM table: each average +- its scatter, the points and
    depths averaged, and against the instrument's own values where a file had them."""
    columns = [("E_r [GPa]", 15, lambda r: _pm(r, "E_r"))]
    columns += [("E [GPa]", 15, lambda r: _pm(r, "E"))] if with_E else []
    columns += [("H [GPa]", 15, lambda r: _pm(r, "H")),
                ("points", 6, lambda r: str(r["n_range"])),
                ("depths [nm]", 11, lambda r: "{:.0f}-{:.0f}".format(
                    *(d * 1e9 for d in r["depth_range"])))]
    if any(r.get("vendor_difference") for r in records):
        columns += [(f"{k} vs file", 9, lambda r, k=k: _vendor_difference(r, k))
                    for k in ("E", "H")]
    return columns


def _with_std(r: dict, key: str) -> str:
    """A value in GPa, ``+- std`` after it where the record has its standard deviation."""
    value = _num(r.get(key), 1e9, ".4g")
    std = r.get(key + "_std")
    return value if std is None or not np.isfinite(std) else f"{value} +- {std / 1e9:.2g}"


def _unloading_columns(with_E: bool) -> list:
    """(header, width, cell) of an Oliver-Pharr table: one unloading per row."""
    columns = [("E_r [GPa]", 10, lambda r: _with_std(r, "E_r"))]
    columns += [("E [GPa]", 9, lambda r: _with_std(r, "E"))] if with_E else []
    return columns + [("H [GPa]", 9, lambda r: _with_std(r, "H")),
                      ("h_c [nm]", 9, lambda r: _num(r["h_c"], 1e-9, ".4g")),
                      ("S [N/m]", 10, lambda r: _num(r["S"], 1.0, ".4g"))]


#: the curve column widens to the longest name up to this; a longer name has a line of its
#: own, its figures on the next line under an empty name cell
NAME_WIDTH_MAX = 40


def _table_row(r: dict, cells: list[str], widths: list[int], width: int) -> str:
    """One curve: its cells ("-" where not analysed), its flags and why it failed; a name
    longer than the name column on a line of its own above them."""
    name = r["name"] if len(r["name"]) <= width else ""
    row = " ".join([f"{name:<{width}}"] + [f"{c:>{w}}" for c, w in zip(cells, widths)])
    why = "" if _analysed(r) else f" ({r.get('message', '')})"
    row = f"{row}  {','.join(r.get('flags', []))}{why}"
    return row if name or not r["name"] else f"{r['name']}\n{row}"


def _table(records, csm: bool, nu=None) -> list[str]:
    """The results table: whole curve names (`NAME_WIDTH_MAX`); E where a Poisson ratio was
    given or known; each value's +- where the record has its standard deviation; the surface
    shift where one was applied; against the instrument's own values where the file had
    them. Each column as wide as its widest cell."""
    with_E = nu is not None or any(_analysed(r) and r.get("E") is not None
                                   and np.isfinite(r["E"]) for r in records)
    columns = _csm_columns(records, with_E) if csm else _unloading_columns(with_E)
    if any(r.get("surface_shift") for r in records):
        columns += [("surface [nm]", 12, lambda r: _num(r.get("surface_shift") or 0.0, 1e-9,
                                                         ".3g"))]
    cells = [[cell(r) if _analysed(r) else "-" for _, _, cell in columns] for r in records]
    widths = [max([w, len(h)] + [len(row[k]) for row in cells])
              for k, (h, w, _) in enumerate(columns)]
    width = max([5] + [len(r["name"]) for r in records if len(r["name"]) <= NAME_WIDTH_MAX])
    header = " ".join([f"{'curve':<{width}}"] + [f"{h:>{w}}" for (h, _, _), w in
                                                 zip(columns, widths)])
    return [header + "  flags"] + [_table_row(r, row, widths, width)
                                   for r, row in zip(records, cells)]


def _print_records(args, records) -> None:
    """One JSON object per curve, or the table."""
    if args.json:
        for r in records:
            print(dumps(r))
    else:
        print("\n".join(_table(records, args.csm, args.nu)))


def _print_counts(records, analysed, n_files: int, elapsed: float, elastic) -> None:
    """What was analysed, on stderr, and the elastic reference of --shallow-correction."""
    flagged = sum(1 for r in analysed if r["flags"])
    print(f"analysed {len(analysed)} of {len(records)} curves from {n_files} files in "
          f"{elapsed:.2f} s; {flagged} with flags, {len(records) - len(analysed)} not analysed",
          file=sys.stderr)
    if elastic is not None:
        print(f"shallow-depth correction: elastic reference {records[elastic]['name']} "
              f"(H_shallow)", file=sys.stderr)


def _print_profile(profile, nix_gao, film) -> None:
    """The text summaries of the depth profile, its Nix-Gao fit and the film fit."""
    if profile is not None:
        print(profile.summary())
        if nix_gao is not None:
            print(_nix_gao_line(nix_gao))
    if film is not None:
        print(film.summary())


# ---- indent analyze: its files --------------------------------------------------------------

def _analyze_inputs(args) -> list[Path]:
    """The curve files of ``indent analyze``, its outputs checked against them (and the --plot
    folder made) before any curve is read."""
    from .indent import AREA_FROM_FILE, expand_inputs
    from .result import INDENT_RESULTS_FORMAT
    output_path("--out", args.out, ("h5", "hdf5"))
    output_path("--profile", args.profile)
    if args.plot and Path(args.plot).exists() and not Path(args.plot).is_dir():
        raise InputError(f"--plot {args.plot} is a file: give a folder for the plots")
    files = expand_inputs(args.files)
    area_file = ([("the --area-file", args.area_file)]
                 if args.area_file and args.area_file not in AREA_FROM_FILE else [])
    check_outputs([("an input curve file", f) for f in files] + area_file,
                  [("--out", args.out, hdf5_kind(INDENT_RESULTS_FORMAT, "indentation results")),
                   ("--profile", args.profile, text_kind(PROFILE_HEADER, "a profile table"))],
                  args.force)
    if args.plot:
        Path(args.plot).mkdir(parents=True, exist_ok=True)
    return files


def _profile(args, records):
    """(profile, Nix-Gao fit) of the analysed records over --layers and --layer-names
    (`indent.profile_of`: None where there are too few indents)."""
    from .indent import profile_of
    names = tuple(args.layer_names.split(",")) if args.layer_names else ()
    return profile_of(records, args.layers or (), names)


def _write_outputs(args, records, options, profile, nix_gao, film, n_analysed: int) -> None:
    """--out (every record, the profile and its fits), --profile and the --plot of the
    profile."""
    if args.out:
        _write_results(args.out, records, options, profile, nix_gao, film)
        print(f"wrote {args.out}", file=sys.stderr)
    if args.profile:
        if profile is None:
            raise InputError("--profile needs at least 2 analysed curves")
        _profile_table(profile, Path(args.profile))
        print(f"wrote {args.profile}", file=sys.stderr)
    if args.plot and profile is not None:
        _plot_profile(profile, nix_gao, film, Path(args.plot) / "profile.png", n_analysed)


def _write_results(path, records, options, profile, nix_gao, film) -> None:
    """The HDF5 results of --out."""
    from filmscale.core.provenance import provenance

    from .indent import options_dict
    from .result import write_indentation_results
    profile_data = None
    if profile is not None:
        profile_data = profile.to_dict()
        profile_data["nix_gao"] = nix_gao.to_dict() if nix_gao is not None else None
        profile_data["film"] = film.to_dict() if film is not None else None
    write_indentation_results(path, records, provenance(command=" ".join(sys.argv)),
                              options_dict(options), profile_data)


def _plot_profile(profile, nix_gao, film, path: Path, n_analysed: int) -> None:
    from filmscale.continuum.materials import DIAMOND

    from .plots import plot_property_profile
    try:
        fit = profile.to_depth_profile()
    except InputError:          # too few indents between interfaces for the lines
        fit = None
    plot_property_profile(profile, path, nix_gao, fit, DIAMOND.compliance,
                          title=f"{n_analysed} indents", film=film)


# ---- the commands ---------------------------------------------------------------------------

def cmd_indent_analyze(args) -> int:
    from .indent import UNREADABLE, analyze_files, shallow_depth_correction

    options = _analysis_options(args)
    files = _analyze_inputs(args)
    start = time.perf_counter()
    records = analyze_files(files, options, workers=args.workers)
    elapsed = time.perf_counter() - start
    unreadable = [r for r in records if r.get("status") == UNREADABLE]
    analysed = [r for r in records if _analysed(r)]
    for r in unreadable:
        print(f"filmscale: error: {r['name']}: {r['message']}", file=sys.stderr)
    elastic = shallow_depth_correction(records, options) if args.shallow_correction else None
    profile, nix_gao = _profile(args, records)

    _print_records(args, records)
    film = _film_fit(args, records) if args.film_model else None
    if args.json and film is not None:    # one more line: the profile's film fit and Nix-Gao
        print(dumps({"film": film.to_dict(),
                     "nix_gao": nix_gao.to_dict() if nix_gao is not None else None}))
    _print_counts(records, analysed, len(files), elapsed, elastic)
    if not args.json:
        _print_profile(profile, nix_gao, film)
    _write_outputs(args, records, options, profile, nix_gao, film, len(analysed))
    if unreadable:
        return 2
    return 0 if analysed else 1


def cmd_indent_reverse(args) -> int:
    from filmscale.continuum.indentation.reverse.dao import dao_reverse
    from filmscale.continuum.indentation.reverse.dual import dual_reverse

    common = dict(tip=args.tip, nu=args.nu, E_i=args.E_i, nu_i=args.nu_i, C_std=args.C_std,
                  dPdh_std=args.dPdh_std, WpWt_std=args.WpWt_std, h_m_std=args.hm_std,
                  method=args.method, samples=args.samples, seed=args.seed)
    if (args.C2 is None) != (args.tip2 is None):
        raise InputError("the dual-indenter analysis needs both --C2 and --tip2")
    if args.C2 is not None:
        result = dual_reverse(args.C, args.dPdh, args.WpWt, args.hm, args.C2, tip2=args.tip2,
                              C2_std=args.C2_std, **common)
    else:
        result = dao_reverse(args.C, args.dPdh, args.WpWt, args.hm, **common)
    if args.json:
        print(dumps(result.to_dict()))
    else:
        print(result.summary())
    for warning in result.warnings:
        print(f"filmscale: warning: {warning}", file=sys.stderr)
    return 0
