"""Batch indentation analysis: many curve files through Oliver-Pharr on a process pool.

A folder of thousands of curves is the normal case: files are analysed in chunks on worker
processes, each file's problems become flags or an "unreadable" record rather than stopping
the batch, and a progress bar runs on stderr when it is a terminal.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation import nix_gao_fit, oliver_pharr
from filmscale.continuum.indentation.curves import drift_rate
from filmscale.continuum.indentation.cycles import cycle_curves
from filmscale.continuum.indentation.io import (CURVE_SUFFIXES, HDF5_SUFFIXES, read_area_function,
                                                read_curves)
from filmscale.continuum.indentation.oliver_pharr import elastic_indent, shallow_depth_hardness
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.indentation.tips import parse_tip
from filmscale.core.cores import usable_cores
from filmscale.core.errors import InputError

UNREADABLE = "unreadable"


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


def resolve_tip(options: AnalysisOptions, curve_indenter=None):
    """The tip for a curve: the option's (text), else the curve's own (a `Tip`); InputError
    when neither."""
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
        else:
            raise InputError(f"curve file {p} does not exist")
    return out


def _safe_name(name: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in name)


def analyze_file(path, options: AnalysisOptions) -> list[dict]:
    """Oliver-Pharr records (plain dicts, SI) of every curve in one file."""
    path = Path(path)
    try:
        curves = read_curves(path, reader_options(options.read_format, options.columns,
                                                  options.read_options))
    except InputError as err:
        return [{"name": path.stem, "file": str(path), "status": UNREADABLE,
                 "message": str(err), "flags": [UNREADABLE]}]
    records = []
    for name, curve in curves.items():
        label = f"{path.stem}:{name}" if path.suffix.lower() in HDF5_SUFFIXES \
            or name != path.stem else name
        record = {"name": label, "file": str(path)}
        try:
            tip = resolve_tip(options, curve.indenter)
            if options.frame_compliance:
                curve = curve.frame_corrected(options.frame_compliance)
            rate = None
            if options.drift and curve.t is not None:
                try:
                    rate = drift_rate(curve)
                    curve = curve.drift_corrected(rate)
                except InputError:       # no low-load hold: nothing to correct
                    rate = None
            parts = cycle_curves(curve) if options.cycles else [curve]
            if not parts:
                raise InputError("no unloading that sheds 10 % of its load: no cycle to "
                                 "analyse")
            results = [oliver_pharr(part, tip, window=options.window, epsilon=options.epsilon,
                                    beta=options.beta, nu=options.nu) for part in parts]
        except InputError as err:
            records.append({**record, "status": UNREADABLE, "message": str(err),
                            "flags": [UNREADABLE]})
            continue
        for k, (part, result) in enumerate(zip(parts, results)):
            named = {**record, "name": f"{label}#{k + 1}"} if options.cycles else dict(record)
            named.update(result.to_dict())
            named["drift_rate"] = rate
            if options.cycles:
                named["cycle"] = k + 1
            records.append(named)
            if options.plot_dir:
                from .plots import plot_curve_analysis
                plot_curve_analysis(part, result,
                                    Path(options.plot_dir) / f"{_safe_name(named['name'])}.png",
                                    title=named["name"])
    return records


def _analyze_chunk(args) -> list[dict]:
    paths, options = args
    out = []
    for p in paths:
        out.extend(analyze_file(p, options))
    return out


def analyze_files(paths, options: AnalysisOptions, *, workers: int | None = None,
                  progress: bool = True) -> list[dict]:
    """Records of every curve in ``paths``, in input order.

    ``workers`` processes (default: the CPUs this process may use, at most 8); one process
    for fewer than 64 files, where starting a pool costs more than it saves.
    """
    paths = [Path(p) for p in paths]
    if workers is None:
        workers = min(usable_cores(), 8)
    workers = max(1, min(int(workers), len(paths)))
    size = max(1, min(256, math.ceil(len(paths) / (workers * 8))))
    chunks = [(paths[i:i + size], options) for i in range(0, len(paths), size)]
    from filmscale.workflows.progress import progress_bar
    bar = progress_bar(len(paths), "curve", "analysing", enabled=progress)
    records = []
    try:
        if workers == 1 or len(paths) < 64:
            for chunk in chunks:
                records += _analyze_chunk(chunk)
                bar.update(len(chunk[0]))
        else:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                for chunk, out in zip(chunks, pool.map(_analyze_chunk, chunks)):
                    records += out
                    bar.update(len(chunk[0]))
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


def profile_of(records: list[dict], interfaces=(), layer_names=()):
    """Property-depth profile and Nix-Gao fit of the analysed records (None where there are
    too few indents)."""
    ok = [r for r in records if r.get("status") == 0]
    if len(ok) < 2:
        return None, None
    h_c, E_r, H = (np.array([r[k] for r in ok], dtype=float) for k in ("h_c", "E_r", "H"))
    profile = property_profile(h_c, E_r, H, interfaces=interfaces, layer_names=layer_names)
    try:
        nix_gao = nix_gao_fit(profile.h_c, profile.H) if profile.group_n.size >= 3 else None
    except InputError:
        nix_gao = None
    return profile, nix_gao


def options_dict(options: AnalysisOptions) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(options).items()}
