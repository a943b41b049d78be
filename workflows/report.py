"""`filmscale report RESULT.h5`: one self-contained HTML file (figures embedded as PNG) of a
scene result: the plan and its reasons, each calibrated layer's curve and fit with the
parameters and their uncertainty, the depth profile, and the impact results or map."""

from __future__ import annotations

import base64
import html
import io
import json
import math
from contextlib import contextmanager
from pathlib import Path

import h5py
import numpy as np
from matplotlib.ticker import NullLocator

from filmscale.continuum.calibration.result import (FITS_E, FITS_SIGMA_Y, CrossCheck,
                                                    pop_in_range)
from filmscale.continuum.contact.results import ImpactMaxima
from filmscale.core.errors import InputError
from filmscale.core.files import atomic_path, check_regular_file
from filmscale.continuum.contact.kinds import kind_named
from filmscale.core.quantities import eng
from filmscale.workflows.result import RESULT_FORMAT, RESULT_FORMATS, read_map_group

from .plots import (CONTINUUM_MIN_APPROACH, draw_map_field, key_legend, map_keys,
                    mark_below_validity, new_figure, readable_log_axis, save_figure,
                    validity_key)


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return f'<img src="data:image/png;base64,{base64.b64encode(buf.getvalue()).decode()}">'


def check_result(result) -> Path:
    """``result`` if it is a scene result; InputError naming what it is otherwise."""
    from .outputs import describe, hdf5_format
    result = Path(result)
    if not result.is_file():
        if result.exists() and not result.is_dir():     # a named pipe, a device
            check_regular_file(result, "result")        # raises: not a regular file
        raise InputError(f"result {result} does not exist" if not result.exists() else
                         f"result {result} is a folder, not a file")
    if hdf5_format(result) not in RESULT_FORMATS:
        raise InputError(f"{result} is {describe(result)}; report expects a scene result "
                         f"(format {RESULT_FORMAT}, the RESULT.h5 of filmscale run)")
    return result


@contextmanager
def _result_file(result: Path):
    """The open scene result; a dataset or attribute missing from it, or one that cannot be
    read, is an InputError naming the file (a damaged or truncated result)."""
    with h5py.File(check_result(result), "r") as f:
        try:
            yield f
        except (KeyError, OSError, json.JSONDecodeError) as err:
            detail = err.args[0] if isinstance(err, KeyError) and err.args else err
            raise InputError(f"scene result {result} is damaged or incomplete: {detail}") \
                from None


def _checks(group) -> list[CrossCheck]:
    return [CrossCheck(**c) for c in json.loads(group.attrs["cross_check"])]


def _curve_keys(group) -> list[str]:
    return sorted((k for k in group if k.startswith("curve_")), key=lambda k: int(k[6:]))


#: how the points a parameter was fitted on are marked (`Calibration.fit_roles`)
ROLE_MARKERS = ((FITS_E, "^", "points that set E"),
                (FITS_SIGMA_Y, "s", "points that set sigma_y"),
                (FITS_E | FITS_SIGMA_Y, "D", "points that set E and sigma_y"))


def _load_unit(group) -> tuple[str, float]:
    """The load unit that keeps the axis at 1-1000 (MD curves nN, instruments uN to mN)."""
    keys = _curve_keys(group)
    largest = max(float(np.nanmax(group[k]["P"][()])) for k in keys) if keys else 1.0
    return next(((u, f) for u, f in (("nN", 1e9), ("µN", 1e6), ("mN", 1e3))
                 if largest * f < 1e3), ("N", 1.0))


def _left_out(h, P, excluded: str) -> tuple[int, int] | None:
    """(first, last) index of the range a cross-scale check left out of a curve: the whole
    pop-in range ("pop-in": the loading up to the bottom of the drop) or its burst ("burst":
    after the peak); None when nothing was left out or the curve has no pop-in."""
    span = pop_in_range(h, P) if excluded else None
    if span is None:
        return None
    return (0 if excluded == "pop-in" else span[0] + 1), span[1]


def _draw_calibration(ax, group, title: str):
    """Each calibration curve (small dots), the points each parameter was fitted on (marked
    by role), the calibrated forward model on the fit's own contact zero (line), and the
    range a cross-scale check left out (shaded); log axes where the curves span more than a
    decade of depth (nanometre and micrometre sources)."""
    curves = _curve_keys(group)
    depths = [float(group[k]["h"][()].max()) for k in curves]
    excluded = next((c.excluded for c in _checks(group) if c.excluded), "")
    unit, factor = _load_unit(group)
    labelled = set()

    def label(text):
        if text in labelled:
            return None
        labelled.add(text)
        return text
    for i, key in enumerate(curves):
        h, P, F = (group[key][k][()] for k in ("h", "P", "P_model"))
        roles = group[key]["fitted_for"][()] if "fitted_for" in group[key] else None
        x, P, F = h * 1e9, P * factor, F * factor
        color = f"C{i % 10}"
        span = _left_out(h, P, excluded)
        if span is not None:
            ax.axvspan(x[span[0]], x[span[1]], color=color, alpha=0.12, lw=0,
                       label=label(f"left out of the check: the {excluded}"))
        ax.plot(x, P, ".", ms=2, color=color, alpha=0.6, label=label("calibration curve"))
        if roles is not None:
            for role, marker, text in ROLE_MARKERS:
                sel = roles == role
                if sel.any():
                    ax.plot(x[sel], P[sel], marker, ms=3.5, mfc="none", mew=0.7,
                            color=color, label=label(text))
        ax.plot(x, F, "-", color="k" if len(curves) == 1 else color, lw=1.2,
                label=label("calibrated forward model"))
    if depths and max(depths) > 10 * min(depths):
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel("depth h (nm)")
    ax.set_ylabel(f"load P ({unit})")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="best", framealpha=0.8)       # where it covers no point


def _draw_residuals(ax, group):
    """(P_model - P) / P_max of each calibration curve against depth, with the first
    cross-scale check's tolerance and its verdict written in the panel."""
    check = _checks(group)[0]
    for i, key in enumerate(_curve_keys(group)):
        h, P, F = (group[key][k][()] for k in ("h", "P", "P_model"))
        span = _left_out(h, P, check.excluded)
        if span is not None:
            ax.axvspan(h[span[0]] * 1e9, h[span[1]] * 1e9, color=f"C{i % 10}", alpha=0.12,
                       lw=0)
        ax.plot(h * 1e9, 100 * (F - P) / P.max(), ".", ms=3, color=f"C{i % 10}")
    for sign in (-1, 1):
        ax.axhline(100 * sign * check.tolerance, color="0.4", ls="--", lw=1,
                   label="tolerance" if sign > 0 else None)
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.set_xlabel("depth h (nm)")
    ax.set_ylabel("(model - curve) / P_max (%)")
    ax.set_title(check_verdict(check), fontsize=7.5)
    ax.legend(fontsize=7, loc="best")


def check_verdict(check: CrossCheck) -> str:
    """The cross-scale check in three short lines for a figure panel: the verdict with the
    rms against the tolerance, what was left out and the misfit of each part of a pop-in
    curve, and the parts that fail."""
    sign = "<=" if check.passed else ">"
    lines = [f"cross-scale check {'passed' if check.passed else 'FAILED'}: {check.rms:.1%} rms "
             f"{sign} tolerance {check.tolerance:.1%}"
             + (f" (2 x noise {check.noise:.2%})" if check.basis.startswith("2 x") else "")]
    detail = [f"{check.excluded} left out ({check.excluded_points} points)"] \
        if check.excluded else []
    if check.parts:
        detail.append("by part: " + ", ".join(f"{name} {rms:.1%}"
                                              for name, rms in check.parts.items()))
    if detail:
        lines.append("; ".join(detail))
    left_out = {"pop-in": ("elastic", "burst"), "burst": ("burst",)}.get(check.excluded, ())
    failing = [name for name, rms in check.parts.items()
               if name not in left_out and rms > check.tolerance]
    if failing and not check.passed:
        lines.append("the model cannot follow: " + ", ".join(
            {"elastic": "the elastic loading before the pop-in", "flow": "the flow after the "
             "pop-in"}.get(name, name) for name in failing))
    return "\n".join(lines)


def scene_stack(f) -> tuple[list[tuple[str, float]], str]:
    """(name, thickness) of each layer of a scene result's scene, top first, and the name
    of its substrate; ([], "") where the scene's text does not say (a profile, not TOML)."""
    import tomllib
    try:
        text = f["scene"][()]
        target = tomllib.loads(text.decode() if isinstance(text, bytes) else str(text))["target"]
        layers = [(str(layer.get("name", f"layer {k + 1}")), float(layer["thickness"]))
                  for k, layer in enumerate(target.get("layers", []))]
        return layers, str(target["substrate"].get("name", "substrate"))
    except (tomllib.TOMLDecodeError, KeyError, TypeError, ValueError, AttributeError):
        return [], ""


def _mark_interfaces(ax, stack) -> None:
    """A dotted line at each interface's depth (nm) of ``stack`` (`scene_stack`), named on
    a top axis by the layers either side ("Cu film | glass")."""
    layers, substrate = stack
    names = [name for name, _ in layers] + [substrate]
    depths = np.cumsum([t for _, t in layers]) * 1e9
    lo, hi = ax.get_xlim()
    inside = [k for k, d in enumerate(depths) if lo < d < hi]
    for k in inside:
        ax.axvline(depths[k], color="0.5", ls=":", lw=0.9)
    if inside:
        top = ax.secondary_xaxis("top")
        # every other name a line higher: two interfaces a decade apart would overlap
        top.set_xticks([depths[k] for k in inside],
                       labels=[f"{names[k]} | {names[k + 1]}" + "\n" * (i % 2)
                               for i, k in enumerate(inside)], fontsize=7)
        top.xaxis.set_minor_locator(NullLocator())


def _draw_profile(ax_E, ax_sy, group, radius, stack=([], "")):
    """The stack's effective plane-strain modulus (on ``ax_E``) and yield strength (on
    ``ax_sy``, its own axis) against the approach under a sphere of ``radius``, Gao-weighted,
    with the interfaces of ``stack`` (`scene_stack`) marked and named."""
    d = group["delta"][()] * 1e9
    layers, substrate = stack
    what = " on ".join([f"{name} ({eng(t, 'm', 3)})" for name, t in layers] +
                       [substrate] if substrate else [])
    panels = ((ax_E, "E_p", "effective E/(1-ν²) (GPa)", "C0"),
              (ax_sy, "sigma_y", "effective yield strength σ_y (GPa)", "C1"))
    for ax, key, label, colour in panels:
        ax.plot(d, group[key][()] * 1e-9, color=colour)
        ax.set_xscale("log")
        readable_log_axis(ax.xaxis)
        ax.set_xlabel("approach δ (nm)")
        ax.set_ylabel(label)
        _mark_interfaces(ax, stack)
    ax_E.set_title(_wrapped(f"{what + ': ' if what else ''}effective properties under a "
                            f"sphere of R = {eng(radius, 'm')} (Gao weighting)", 58),
                   fontsize=9)
    if layers:
        ax_sy.set_title("dotted: approach = depth of an interface", fontsize=8)


MAP_PANELS = (("delta_max", "maximum approach (nm)", 1e9),
              ("restitution", "restitution e_y", 1.0),
              ("residual_depth", "residual depth (nm)", 1e9))


def result_map(group):
    """The impact map of a scene result's impact/map group (either layout: /2 or /3), as
    its model kind reads it (a sphere's where the file names none)."""
    kind = kind_named(str(group.attrs.get("kind", "sphere")))
    return kind.map_from_arrays(read_map_group(group))


def _draw_band(ax, impact, key, label, scale) -> bool:
    """The map's ``key`` against V at the map radius nearest the scene's R, with the band
    of +- 2 standard deviations from the calibrations (``map_std``) where it is wider than
    the line (else the title says it is narrower), and the velocities where the approach is
    below a continuum's validity dotted; whether any were."""
    V, R = impact["map/velocity"][()], impact["map/radius"][()]
    i = int(np.argmin(np.abs(np.log(R / float(impact["point/radius"][()])))))
    value = impact[f"map/{key}"][()][i] * scale
    std = impact[f"map_std/{key}"][()][i] * scale
    # a linearised band must not promise a rebound faster than the impact
    high = np.minimum(value + 2 * std, 1.0) if key == "restitution" else value + 2 * std
    # visible: wider than about two line widths (3 % of the axis) somewhere
    span = float(np.nanmax(value) - np.nanmin(value)) or float(np.nanmax(np.abs(value)))
    visible = bool(np.nanmax(high - value + 2 * std) > 0.03 * span)
    if visible:
        ax.fill_between(V, value - 2 * std, high, alpha=0.3, label="+- 2 std (calibration)")
    ax.plot(V, value, color="C0")
    below = (impact["map/delta_max"][()][i] < CONTINUUM_MIN_APPROACH
             if "delta_max" in impact["map"] else np.zeros(V.size, bool))
    if below.any():
        mark_below_validity(ax, V, below)
    ax.set_xscale("log")
    readable_log_axis(ax.xaxis)
    ax.set_xlabel("impact velocity V (m/s)")
    ax.set_ylabel(label)
    with np.errstate(divide="ignore", invalid="ignore"):
        widest = np.nanmax(np.where(value != 0, 2 * std / np.abs(value), np.nan))
    ax.set_title(f"{label.split(' (')[0]} at R = {eng(R[i], 'm')}:\n2 std at most "
                 f"{widest:.2%} of the value" + ("" if visible else
                                                 " (band narrower than the line)"),
                 fontsize=9)
    if visible:
        ax.legend(fontsize=8, loc="best")
    return bool(below.any())


def _profile_figure(f, radius) -> str:
    fig, axes = new_figure(1, 2, figsize=(10, 3.8))
    _draw_profile(*axes, f["profile"], radius, scene_stack(f))
    return _png(fig)


def _panel(draw, *args, size=(5, 3.6)) -> str:
    fig, ax = new_figure(figsize=size)
    draw(ax, *args)
    return _png(fig)


def bound_note(calibration_group) -> str:
    """What the impact results rest on when a calibrated sigma_y is only a lower bound (the
    curves never passed first yield): the maps are computed at the bound, not bounds
    themselves (with some laws, e.g. Jackson-Green, e_y is not monotonic in sigma_y)."""
    bounded = [(c["layer"], c["sigma_y"]["value"]) for c in
               (json.loads(g.attrs["calibration"]) for g in calibration_group.values())
               if c["sigma_y"].get("lower_bound")]
    return "; ".join(f"computed with {layer}'s sigma_y at its lower bound (>= {value / 1e9:.3g} "
                     "GPa)" for layer, value in bounded)


def _map_figure(group, note: str = "") -> str:
    """The report's map panels: those of `MAP_PANELS` the map's model kind has (a flat
    punch has no crater), with the keys of what is drawn over them."""
    m = result_map(group)
    panels = ([panel for panel in MAP_PANELS if panel[0] in m.units]
              or [(key, None, 1.0) for key in list(m.units)[:1]])    # a kind of its own
    fig, axes = new_figure(1, len(panels), figsize=(4.4 * len(panels), 4.0), squeeze=False)
    for ax, (key, label, _) in zip(axes[0], panels):
        draw_map_field(fig, ax, m, key, label=label, keys=False)
    key_legend(fig, map_keys([m], [key for key, _, _ in panels]), title=note)
    return _png(fig)


def _band_figure(impact) -> str:
    fig, axes = new_figure(1, 2, figsize=(10, 3.8))
    below = [_draw_band(ax, impact, *panel) for ax, panel in zip(axes, MAP_PANELS[:2])]
    key_legend(fig, [validity_key()] if any(below) else [])
    return _png(fig)


def _map_columns(fig, grid, col: int, f, bands: bool) -> None:
    """The scene figure's maximum approach and restitution maps from column ``col``, over
    both rows or over their +- 2 std bands (``bands``), and the keys at its head."""
    m = result_map(f["impact/map"])
    note = bound_note(f["calibration"])
    for k, (key, label, scale) in enumerate(MAP_PANELS[:2]):
        ax = fig.add_subplot(grid[0, col + k] if bands else grid[:, col + k])
        draw_map_field(fig, ax, m, key, label=label, keys=False)
        ax.set_title(label.split(" (")[0] + (f"\n{note}".replace(" (>=", "\n(>=")
                                             if note else ""), fontsize=8)
        if bands:
            _draw_band(fig.add_subplot(grid[1, col + k]), f["impact"], key, label, scale)
    key_legend(fig, map_keys([m], [key for key, _, _ in MAP_PANELS[:2]]))


def scene_figure(result):
    """One Figure summing up a scene result, every panel of its grid used: the first
    calibrated layer's curves with the points each parameter was fitted on and the
    calibrated forward model, its residuals beneath with the cross-scale check's verdict;
    the stack's effective modulus and yield strength against the approach (the layers and
    substrate named); and the map's maximum approach and restitution (when there is a map),
    above their +- 2 std bands at the scene's radius (when the calibrations give standard
    deviations). The keys of the maps' lines, hatching and dots at its head."""
    from matplotlib.figure import Figure
    with _result_file(Path(result)) as f:
        has_map = "map" in f["impact"]
        bands = has_map and "map_std" in f["impact"]
        calibration = list(f["calibration"])[:1]
        cols = len(calibration) + 1 + 2 * has_map
        fig = Figure(figsize=(4.6 * cols, 8.6 if bands else 6.8), layout="constrained")
        grid = fig.add_gridspec(2, cols, height_ratios=(1.6, 1.0))
        for key in calibration:
            g = f["calibration"][key]
            cal = json.loads(g.attrs["calibration"])
            law = "pop-in law" if cal["model"].startswith("pop-in law") else cal["route"]
            _draw_calibration(fig.add_subplot(grid[0, 0]), g, f"{g.attrs['layer']} ({law}): "
                              f"E {_quantity(cal['E']['value'], 'Pa', cal['E']['std'])},\n"
                              f"sigma_y {_bounded_quantity(cal['sigma_y'])}")
            _draw_residuals(fig.add_subplot(grid[1, 0]), g)
        col = len(calibration)
        _draw_profile(fig.add_subplot(grid[0, col]), fig.add_subplot(grid[1, col]),
                      f["profile"], float(f["impact/point/radius"][()]), scene_stack(f))
        if has_map:
            _map_columns(fig, grid, col + 1, f, bands)
    return fig


def _wrapped(text: str, width: int) -> str:
    """``text`` in lines of at most ``width`` characters, for a panel title."""
    import textwrap
    return "\n".join(textwrap.wrap(text, width))


def _bounded_quantity(parameter: dict) -> str:
    """A calibrated value with its std for people; ">= value" for a lower bound."""
    if parameter.get("lower_bound"):
        return ">= " + _quantity(parameter["value"], parameter["unit"])
    return _quantity(parameter["value"], parameter["unit"], parameter["std"])


def write_figure(result, out) -> Path:
    """`scene_figure` of a scene result, saved as PNG to ``out``."""
    return save_figure(scene_figure(result), out)


def _number(value, fmt: str, unit: str = "") -> str:
    """A number of a result file's JSON (where null stands for NaN) for a table cell."""
    if value is None or value != value:
        return "-"
    return f"{value:{fmt}}{unit}"


def _quantity(value, unit: str, std=None) -> str:
    """A value of a result file's JSON (null stands for NaN) in engineering units."""
    if value is None or value != value:
        return "-"
    return eng(value, unit, std=None if std is None else _float(std))


def _float(value) -> float:
    return math.nan if value is None else float(value)


def _pop_in_text(p: dict) -> str:
    return (f"<p>Pop-in over {p['members']} seeds: load "
            f"{_quantity(p['load'], 'N', p['load_std'])} at "
            f"{_quantity(p['depth'], 'm', p['depth_std'])}; shear stress (0.31 p0) "
            f"{_quantity(p['shear_stress'], 'Pa', p['shear_stress_std'])}</p>")


def _table(rows, header) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                   for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def write_report(result, out=None) -> Path:
    """Write the HTML report of a scene result (default: RESULT with suffix .html)."""
    result = Path(result)
    out = Path(out) if out is not None else result.with_suffix(".html")
    with _result_file(result) as f:
        plan = json.loads(f.attrs["plan"])
        parts = [f"<h1>filmscale scene report</h1><p>scene: {html.escape(f.attrs['scene'])}"
                 f"; filmscale {html.escape(f.attrs['filmscale_version'])} "
                 f"({html.escape(f.attrs['source_revision'])}); created "
                 f"{html.escape(f.attrs['created_utc'])}</p>",
                 "<h2>Plan</h2>",
                 _table([(s["name"], s["model"], s["reason"], s["error"],
                          _number(s["cost_s"], ".3g", " s")) for s in plan["steps"]],
                        ("step", "model", "why", "error", "cost"))]
        if len(f["calibration"]):
            parts.append("<h2>Calibrated layers</h2>")
        for key in f["calibration"]:
            g = f["calibration"][key]
            cal = json.loads(g.attrs["calibration"])
            rows = [(name, (">= " if cal[name].get("lower_bound") else "") +
                     _quantity(cal[name]["value"], cal[name]["unit"], cal[name]["std"]),
                     "yes" if cal[name]["identified"] else f"no: {cal[name]['reason']}")
                    for name in ("E", "sigma_y", "n", "h_star") if cal.get(name)]
            parts += [f"<h3>{html.escape(cal['layer'])}</h3>",
                      f"<p>{html.escape(cal['model'])}; uncertainty: "
                      f"{html.escape(cal['uncertainty'])}; rms misfit "
                      f"{_number(cal['rms'], '.2%')} of the largest load over "
                      f"{cal['points']} points</p>",
                      _table(rows, ("parameter", "value +- 1 std", "identified")),
                      *([_pop_in_text(cal["pop_in"])] if cal.get("pop_in") else []),
                      *(f"<p><b>{html.escape(c.text())}</b></p>" for c in _checks(g)),
                      _panel(_draw_calibration, g, _wrapped(f"{cal['layer']}: {cal['model']}",
                                                           62)),
                      _panel(_draw_residuals, g)]
            if cal.get("components"):
                parts.append(_table(
                    [(c["source"], c["route"], _quantity(c["E"]["value"], "Pa"),
                      _quantity(c["E_joint"]["value"], "Pa"),
                      _quantity(c["sigma_y"]["value"], "Pa"))
                     for c in cal["components"]],
                    ("source", "route", "E alone", "E in the joint fit", "sigma_y alone")))
            parts += [f"<p>warning: {html.escape(w)}</p>" for w in cal["warnings"]]
        radius = float(f["impact/point/radius"][()])
        parts += ["<h2>Depth profile</h2>", _profile_figure(f, radius), "<h2>Impact</h2>"]
        point = f["impact/point"]
        units = {k: "" if u == "1" else u for k, u in ImpactMaxima.UNITS.items()}
        parts.append(_table([(k, _quantity(float(point[k][()]), units.get(k, "")))
                             for k in sorted(point)], ("quantity", "value")))
        if "map" in f["impact"]:
            note = bound_note(f["calibration"])
            parts += [f"<p>Map {html.escape(note)}.</p>" if note else "",
                      _map_figure(f["impact/map"], note)]
        if "map_std" in f["impact"]:
            parts += ["<p>Bands: +- 2 standard deviations of the impact results from the "
                      "calibrated parameters' standard deviations (linearised, with the "
                      "parameters' correlation from the fits); <code>map_std</code> in the "
                      "result file holds "
                      "them for every map field.</p>", _band_figure(f["impact"])]
        scene = f["scene"][()]
        scene = scene.decode() if isinstance(scene, bytes) else str(scene)
        parts.append(f"<h2>Scene</h2><pre>{html.escape(scene)}</pre>")
    style = ("<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 6px;"
             "font-size:90%}</style>")
    with atomic_path(out) as tmp:
        Path(tmp).write_text(f"<!doctype html><html><head><meta charset='utf-8'>{style}"
                             f"<title>filmscale report</title></head><body>{''.join(parts)}"
                             "</body></html>")
    return out
