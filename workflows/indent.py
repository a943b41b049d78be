"""Batch indentation analysis: many curve files through Oliver-Pharr on a process pool.

A folder of thousands of curves is the normal case: files are analysed in chunks on worker
processes, each file's problems become flags or an "unreadable" record rather than stopping
the batch, and the progress counts curves on stderr (`progress.progress_bar`: a bar on a
terminal, plain lines in a log).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation import nix_gao_fit, oliver_pharr
from filmscale.continuum.indentation.curves import CurveFlag, drift_rate
from filmscale.continuum.indentation.cycles import cycle_curves
from filmscale.continuum.indentation.io import (CURVE_SUFFIXES, HDF5_SUFFIXES, read_area_function,
                                                read_curves)
from filmscale.continuum.indentation.oliver_pharr import elastic_indent, shallow_depth_hardness
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.indentation.tips import PolynomialArea, parse_tip
from filmscale.core.checks import check_path
from filmscale.core.cores import usable_cores
from filmscale.core.errors import InputError
from filmscale.core.files import check_regular_file

UNREADABLE = "unreadable"
FAILED = 1
#: ``--area-file`` values that take the area function the curve file states
AREA_FROM_FILE = ("file", "vendor")
#: beta of the instruments' own methods, for ``--area-file file`` (NanoSuite's G-Series CSM
#: method: Beta 1.000; TriboScan's Oliver-Pharr analysis: 1)
METHOD_BETA = {"g200-workbook": 1.0, "hysitron-hld": 1.0}


@dataclass(frozen=True)
class AnalysisOptions:
    """What `analyze_file` does to each curve (picklable: it travels to worker processes)."""

    tip: str | None = None          #: tip spec; None: each curve's own indenter
    area_file: str | None = None    #: TOML polynomial area function
    window: tuple = (0.2, 0.98)
    epsilon: str | float = "tip"
    beta: str | float = "tip"
    nu: float | None = None
    frame_compliance: float = 0.0   #: m/N, removed before the analysis
    drift: bool = True              #: remove drift measured on a low-load hold, when present
    plot_dir: str | None = None
    read_format: str = "auto"       #: instrument format (`vendors.FORMATS`)
    columns: str | None = None      #: column mapping, h=NAME[:UNIT],P=...,t=...
    read_options: str | None = None  #: TOML file of reader options (`vendors.read_options_file`)
    cycles: bool = False            #: every unloading cycle, not only the one from the peak
    surface: str = "auto"           #: contact-point criterion (`surface.parse_surface`)
    csm: bool = False               #: CSM analysis of every loading point
    depth_range: tuple | None = None  #: depths (m) of the CSM averages; None: the file's


@lru_cache(maxsize=4)
def reader_options(read_format: str, columns: str | None, read_options: str | None):
    """The `ReadOptions` of the text the command line gives: the TOML file's, then the format
    and the column mapping over it."""
    from filmscale.continuum.indentation.vendors import (ReadOptions, parse_columns,
                                                         read_options_file)
    base = read_options_file(read_options) if read_options else ReadOptions()
    fmt = read_format if read_format != "auto" else base.format
    mapped = parse_columns(columns) if columns else base.columns
    return ReadOptions(fmt, mapped, base.encoding, base.separator, base.decimal,
                       base.header_rows, base.skip_rows)


@lru_cache(maxsize=16)
def _tip(spec: str, area_file: str | None, _modified: int):
    tip = parse_tip(spec)
    return read_area_function(area_file, tip) if area_file else tip


def area_from_file(options: AnalysisOptions) -> bool:
    return options.area_file in AREA_FROM_FILE


def resolve_tip(options: AnalysisOptions, curve_indenter=None, meta=None):
    """The tip for a curve: the option's (text), else the curve's own (a `Tip`); with
    ``--area-file file`` the area function the curve's file states (``meta``). InputError
    when there is none."""
    if area_from_file(options):
        vendor = (meta or {}).get("vendor") or meta or {}
        coefficients = vendor.get("area_coefficients") or (meta or {}).get("area_coefficients")
        if not coefficients:
            raise InputError("--area-file file: the curve's file states no area function "
                             "(area coefficients)")
        return PolynomialArea(tuple(coefficients), parse_tip(options.tip or "berkovich"))
    spec = options.tip or curve_indenter
    if not spec:
        raise InputError("the curve does not name its indenter: give --tip")
    modified = 0       # the cache key includes the area file's time stamp: edits are seen
    if options.area_file:
        try:
            modified = os.stat(options.area_file).st_mtime_ns
        except OSError as err:
            raise InputError(f"cannot read area file {options.area_file}: {err.strerror}") \
                from None
    return _tip(spec, options.area_file, modified)


def expand_inputs(paths) -> list[Path]:
    """Files to analyse: the files given, and the curve files inside the folders given
    (recursively, sorted). InputError for a path that does not exist or an empty folder."""
    out = []
    suffixes = CURVE_SUFFIXES + HDF5_SUFFIXES
    for p in map(Path, paths):
        if p.is_dir():
            found = sorted(f for f in p.rglob("*") if f.is_file()
                           and f.suffix.lower() in suffixes and not f.name.startswith("."))
            if not found:
                raise InputError(f"folder {p} holds no curve files "
                                 f"({', '.join(suffixes)})")
            out += found
        elif p.is_file():
            out.append(p)
        elif p.exists():        # a named pipe, a device, a socket
            check_regular_file(p, "curve file")    # raises: not a regular file
        else:
            raise InputError(f"curve file {p} does not exist")
    return out


def _safe_name(name: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in name)


def analyze_file(path, options: AnalysisOptions, progress=None, plot_file=None) -> list[dict]:
    """Records (plain dicts, SI) of every curve in one file: Oliver-Pharr, or CSM with
    ``options.csm``. ``progress`` (`CurveProgress`) hears how many curves the file holds and
    each one analysed; ``plot_file`` also draws each curve's analysis there (for a file of one
    curve: a run's record)."""
    path = Path(path)
    try:
        curves = read_curves(path, reader_options(options.read_format, options.columns,
                                                  options.read_options))
    except InputError as err:
        curves = None
        message = str(err)
    if progress is not None:
        progress.read(1 if curves is None else len(curves))
    if curves is None:
        if progress is not None:
            progress.done()
        return [{"name": path.stem, "file": str(path), "status": UNREADABLE,
                 "message": message, "flags": [UNREADABLE]}]
    records = []
    for name, curve in curves.items():
        label = f"{path.stem}:{name}" if path.suffix.lower() in HDF5_SUFFIXES \
            or name != path.stem else name
        records += analyze_curve(curve, {"name": label, "file": str(path)}, options,
                                 plot_file=plot_file)
        if progress is not None:
            progress.done()
    return records


class CurveProgress:
    """Progress per curve of a batch whose curves are known only file by file: the total is
    the curves of the files read plus, for each file not read yet, their mean per file."""

    def __init__(self, bar, n_files: int):
        self.bar, self.n_files, self.files_read, self.curves = bar, n_files, 0, 0

    def read(self, curves: int, files: int = 1) -> None:
        """``files`` more files read, holding ``curves`` curves."""
        from filmscale.workflows.progress import set_total
        self.files_read += files
        self.curves += curves
        per_file = self.curves / self.files_read if self.curves else 1.0
        set_total(self.bar, self.curves + math.ceil(per_file * (self.n_files
                                                                 - self.files_read)))

    def done(self, curves: int = 1) -> None:
        self.bar.update(curves)


class _Tally:
    """The curves a worker process read (its `CurveProgress` is the parent's)."""

    def __init__(self):
        self.curves = 0

    def read(self, curves: int, files: int = 1) -> None:
        self.curves += curves

    def done(self, curves: int = 1) -> None:
        pass


def _method_constants(options: AnalysisOptions, meta) -> tuple:
    """(beta, nu, where nu came from) for a curve: the options', else, with ``--area-file
    file``, the instrument method's beta, and the file's Poisson ratio when --nu is not
    given."""
    beta = options.beta
    if beta == "tip" and area_from_file(options) and meta.get("format") in METHOD_BETA:
        beta = METHOD_BETA[meta["format"]]
    nu = options.nu
    file_nu = (meta.get("vendor") or {}).get("nu")
    if nu is None and isinstance(file_nu, (int, float)) and -1.0 < file_nu < 0.5:
        return beta, float(file_nu), "file"
    return beta, nu, "option" if nu is not None else None


def prepare_curve(curve, options: AnalysisOptions) -> tuple:
    """The curve with frame compliance, drift and the surface dealt with, and what was done:
    (curve, record fields, flags)."""
    from filmscale.continuum.indentation.surface import FLAG_FRACTION, find_surface

    fields, flags = {}, []
    if options.frame_compliance:
        curve = curve.frame_corrected(options.frame_compliance)
    vendor = curve.meta.get("vendor") or {}
    rate = None
    if vendor.get("drift_correction") and "drift_rate" in vendor:
        rate, fields["drift_source"] = vendor["drift_rate"], "file (removed by the instrument)"
    elif options.drift and curve.t is not None:
        try:
            rate = drift_rate(curve)
            curve = curve.drift_corrected(rate)
            fields["drift_source"] = "measured on the low-load hold"
        except InputError:       # no low-load hold: nothing to correct
            rate = None
    fields["drift_rate"] = rate
    found = find_surface(curve, options.surface)
    if found.shift:
        curve = curve.shifted(found.shift)
    fields.update(found.to_dict())
    h_max = float(np.nanmax(np.abs(curve.h))) if curve.h.size else 0.0
    if abs(found.shift) > FLAG_FRACTION * h_max:
        flags.append(CurveFlag("surface_shift", f"the depth zero moved by "
                               f"{found.shift * 1e9:.3g} nm ({found.method}): the file's "
                               f"contact point was {abs(found.shift) / h_max:.1%} of h_max off"))
    return curve, fields, flags


def _extrapolated(tip, h_c) -> CurveFlag | None:
    """The flag of contact depths outside the range the area function was calibrated on."""
    lo, hi = getattr(tip, "h_range", None) or (None, None)
    if lo is None:
        return None
    h_c = np.atleast_1d(np.asarray(h_c, dtype=float))
    out = np.count_nonzero((h_c < lo) | (h_c > hi))
    if not out:
        return None
    return CurveFlag("area_extrapolated", f"{out} of {h_c.size} contact depths lie outside the "
                     f"area function's calibrated range {lo * 1e9:.4g}-{hi * 1e9:.4g} nm")


def _with_flags(record: dict, flags) -> dict:
    codes = list(record.get("flags", [])) + [f.code for f in flags]
    messages = list(record.get("flag_messages", [])) + [f.message for f in flags]
    return {**record, "flags": codes, "flag_messages": messages}


def analyze_curve(curve, record: dict, options: AnalysisOptions, plot_file=None) -> list[dict]:
    """The records of one curve (one per cycle with ``options.cycles``); a curve that cannot be
    analysed gives one record with status FAILED and the reason, and the batch goes on.
    ``plot_file``: draw the (last) unloading's analysis there too."""
    try:
        tip = resolve_tip(options, curve.indenter, curve.meta)
        beta, nu, nu_source = _method_constants(options, curve.meta)
        curve, fields, flags = prepare_curve(curve, options)
    except InputError as err:
        return [{**record, "status": FAILED, "message": str(err), "flags": ["failed"]}]
    record = {**record, **fields, "nu_source": nu_source}
    vendor = curve.meta.get("vendor") or {}
    if vendor.get("E") is not None or vendor.get("H") is not None:
        record["vendor"] = {k: vendor.get(k) for k in ("E", "H")}
    if options.csm:
        return [_csm_record(curve, tip, record, flags, options, beta, nu)]
    parts = cycle_curves(curve) if options.cycles else [curve]
    if not parts:
        return [_with_flags({**record, "status": FAILED, "message": "no unloading that sheds "
                             "10 % of its load: no cycle to analyse"}, flags)]
    records = []
    for k, part in enumerate(parts):
        result = oliver_pharr(part, tip, window=options.window, epsilon=options.epsilon,
                              beta=beta, nu=nu)
        named = {**record, "name": f"{record['name']}#{k + 1}"} if options.cycles \
            else dict(record)
        named.update(result.to_dict())
        extra = list(flags)
        if result.ok and (flag := _extrapolated(tip, result.h_c)):
            extra.append(flag)
        named = _with_flags(named, extra)
        if options.cycles:
            named["cycle"] = k + 1
            cycles = vendor.get("cycles") or []
            if k < len(cycles):
                named["vendor"] = {key: cycles[k].get(key) for key in ("E", "H", "S")}
        records.append(named)
        for plot in ([Path(options.plot_dir) / f"{_safe_name(named['name'])}.png"]
                     if options.plot_dir else []) + ([plot_file] if plot_file else []):
            from .plots import plot_curve_analysis
            plot_curve_analysis(part, result, plot, title=named["name"])
    return records


def _csm_record(curve, tip, record, flags, options: AnalysisOptions, beta, nu) -> dict:
    from filmscale.continuum.indentation.csm import csm_analysis

    result = csm_analysis(curve, tip, depth_range=options.depth_range,
                          epsilon=None if options.epsilon == "tip" else options.epsilon,
                          beta=None if beta == "tip" else beta, nu=nu)
    if options.plot_dir:
        from .plots import plot_csm
        plot_csm(curve, result, Path(options.plot_dir) / f"{_safe_name(record['name'])}.png",
                 title=record["name"])
    out = {**record, **result.to_dict(), "status": result.status,
           "message": result.message, "E_r": result.E_r_mean, "E": result.E_mean,
           "H": result.H_mean, "h_c": result.h_c_mean, "tip": result.tip}
    extra = list(flags)
    lo, hi = result.depth_range
    averaged = result.h_c[(result.h >= lo) & (result.h <= hi)]
    if result.ok and (flag := _extrapolated(tip, averaged)):
        extra.append(flag)
    if result.ok and result.n_range == 0:
        extra.append(CurveFlag("depth_range_empty", f"no analysed point between "
                               f"{lo * 1e9:.4g} and {hi * 1e9:.4g} nm"))
    return _with_flags(out, extra)


def _analyze_chunk(args) -> tuple[list[dict], int]:
    """The records of a chunk of files and the number of curves they held."""
    paths, options = args
    tally, out = _Tally(), []
    for p in paths:
        out.extend(analyze_file(p, options, tally))
    return out, tally.curves


def analyze_files(paths, options: AnalysisOptions, *, workers: int | None = None,
                  progress: bool = True) -> list[dict]:
    """Records of every curve in ``paths``, in input order.

    ``workers`` processes (default: the CPUs this process may use, at most 8); one process
    for fewer than 64 files, where starting a pool costs more than it saves. ``paths`` is a
    sequence of str or os.PathLike (one such path alone stands for itself). ``progress``:
    the curves analysed on stderr (`CurveProgress`), after each curve in one process, after
    each chunk of files on a pool.
    """
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(paths, (bytes, dict)) or not isinstance(paths, Iterable):
        raise InputError(f"paths must be a sequence of file paths (str or os.PathLike), got "
                         f"{type(paths).__name__}")
    paths = [check_path(f"paths[{k}]", p) for k, p in enumerate(paths)]
    if workers is None:
        workers = min(usable_cores(), 8)
    workers = max(1, min(int(workers), len(paths)))
    size = max(1, min(256, math.ceil(len(paths) / (workers * 8))))
    chunks = [(paths[i:i + size], options) for i in range(0, len(paths), size)]
    from filmscale.workflows.progress import progress_bar
    bar = progress_bar(len(paths), "curve", "analysing", enabled=progress)
    counter = CurveProgress(bar, len(paths))
    records = []
    try:
        if workers == 1 or len(paths) < 64:
            for p in paths:
                records += analyze_file(p, options, counter)
        else:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                for chunk, (out, curves) in zip(chunks, pool.map(_analyze_chunk, chunks)):
                    records += out
                    counter.read(curves, len(chunk[0]))
                    counter.done(curves)
    finally:
        bar.close()
    return records


def shallow_depth_correction(records: list[dict], options: AnalysisOptions) -> int | None:
    """Add ``H_shallow`` (Yeo-Polycarpou, Pa) to analysed records when one of them is purely
    elastic; returns the index of that elastic indent, or None."""
    ok = [r for r in records if r.get("status") == 0]
    k = elastic_indent(*([np.nan if r[key] is None else r[key] for r in ok]
                         for key in ("P_max", "W_p", "W_t")))
    if k is None:
        return None
    e = ok[k]
    for r in ok:
        tip = resolve_tip(options, r.get("tip", ""))
        try:
            r["H_shallow"] = float(shallow_depth_hardness(r["P_max"], r["h_c"], tip,
                                                          P_e=e["P_max"], h_me=e["h_max"],
                                                          S_e=e["S"]))
        except InputError:          # the elastic indent itself and shallower ones
            r["H_shallow"] = None
    return records.index(e)


#: a CSM test enters the depth profile as the medians of its points in this many log bins
CSM_PROFILE_BINS = 30


def csm_profile_points(r: dict) -> list[tuple[float, float, float]]:
    """(h_c, E_r, H) of one CSM record: the medians of its points in `CSM_PROFILE_BINS`
    log-spaced bins of contact depth (a test measures the whole profile; its thousand
    points would outweigh every other indent), from the start of its depth range, or 2 % of
    its depth and at least 10 nm (shallower, the stiffness is mostly the oscillation's
    noise and the tip's rounding)."""
    h, h_c, E_r, H = (np.asarray(r["csm"][k], dtype=float) for k in ("h", "h_c", "E_r", "H"))
    if not h.size:
        return []
    start = max(float(r["depth_range"][0]), 0.02 * float(h.max()), 10e-9)
    keep = (h >= start) & np.isfinite(h_c) & (h_c > 0) & np.isfinite(E_r) & np.isfinite(H)
    if keep.sum() < 2:
        return []
    h_c, E_r, H = h_c[keep], E_r[keep], H[keep]
    edges = np.geomspace(h_c.min(), h_c.max() * (1 + 1e-12), CSM_PROFILE_BINS + 1)
    which = np.digitize(h_c, edges) - 1
    return [(float(np.median(h_c[which == k])), float(np.median(E_r[which == k])),
             float(np.median(H[which == k]))) for k in np.unique(which)]


def profile_of(records: list[dict], interfaces=(), layer_names=()):
    """Property-depth profile and Nix-Gao fit of the analysed records (None where there are
    too few indents). A CSM record gives its profile over depth, not one point."""
    ok = [r for r in records if r.get("status") == 0]
    points = []
    for r in ok:
        points += csm_profile_points(r) if r.get("csm") else [(r["h_c"], r["E_r"], r["H"])]
    if len(points) < 2:
        return None, None
    h_c, E_r, H = (np.array(column, dtype=float) for column in zip(*points))
    profile = property_profile(h_c, E_r, H, interfaces=interfaces, layer_names=layer_names)
    try:
        nix_gao = nix_gao_fit(profile.h_c, profile.H) if profile.group_n.size >= 3 else None
    except InputError:
        nix_gao = None
    return profile, nix_gao


def options_dict(options: AnalysisOptions) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(options).items()}
