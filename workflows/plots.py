"""Plots for people: impact-map contours and impact histories, indentation curves and
property profiles. Every function returns a matplotlib `Figure` (shown by Jupyter as it is,
saved with `save_figure` or the ``path`` argument); figures are made without pyplot, so a
script or a notebook keeps its own backend and no figure stays open in pyplot's registry.

Maps put targets side by side (layered and bare substrate, like the seed dissertation's
Figs. 3.2-3.5) with one colour scale per quantity. Every map figure keys, in a legend, what
it draws over the colours: the first-yield boundary (black, dashed), points whose approach
would exceed R (hatched, not computed), points where the approach is below a continuum's
validity (dotted, `CONTINUUM_MIN_APPROACH`) and blank points. Log axes carry 1-2-5 or decade
ticks written as plain numbers (0.1, 2, 50), without labelled minor ticks.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib as mpl
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LogNorm, Normalize, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.patheffects import Normal, Stroke
from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

from filmscale.continuum.contact.kinds import kind_named
from filmscale.core.files import atomic_path
from filmscale.core.quantities import eng

if TYPE_CHECKING:
    from filmscale.continuum.contact.impact_map import GridMap, ImpactMap
    ContactMap = ImpactMap | GridMap

#: file formats the plots can be written in
PLOT_FORMATS = tuple(sorted(FigureCanvasAgg.get_supported_filetypes()))

#: label, display unit and factor from SI for each map field
DISPLAY = {
    "delta_max": ("maximum approach", "nm", 1e9),
    "mean_pressure_max": ("maximum mean pressure", "GPa", 1e-9),
    "force_max": ("maximum force", "mN", 1e3),
    "contact_radius_max": ("maximum contact radius", "µm", 1e6),
    "contact_half_width": ("maximum contact half-width", "µm", 1e6),
    "contact_time": ("contact time", "µs", 1e6),
    "residual_depth": ("residual depth", "nm", 1e9),
    "restitution": ("restitution coefficient e_y", "-", 1.0),
    "restitution_tangential": ("tangential restitution e_x", "-", 1.0),
    "restitution_contact_point": ("contact-point restitution e_c", "-", 1.0),
    "impulse_ratio": ("impulse ratio J_t/J_n", "-", 1.0),
    "rebound_angle": ("rebound angle", "deg", 1.0),
    "spin": ("spin after impact", "rad/s", 1.0),
}
#: fields on a linear colour scale (signed or of order one); the others are logarithmic
LINEAR = {"restitution_tangential", "restitution_contact_point", "impulse_ratio",
          "rebound_angle", "spin"}
#: the smallest approach a continuum contact model is drawn as valid for (m): below a few
#: nanometres the contact is a few atoms wide and the maps mark the points (dotted)
CONTINUUM_MIN_APPROACH = 2e-9
#: the shallowest crater a residual-depth map draws as valid (m): one below an atom's size
#: (picometres) is a continuum's number, not a dent; dotted as well
CONTINUUM_MIN_RESIDUAL = 1e-10
#: the text of the key of those points
BELOW_VALIDITY = f"approach < {CONTINUUM_MIN_APPROACH * 1e9:g} nm: below a continuum's validity"
#: how the first-yield line is drawn: black, dashed, edged in white to show on dark colours
YIELD_STYLE = {"colors": "k", "linestyles": "--", "linewidths": 1.2,
               "path_effects": [Stroke(linewidth=2.8, foreground="w"), Normal()]}


def tick_text(x: float, digits: int = 4, plain: bool | None = None) -> str:
    """A tick value for people: plain from 1e-3 to 1e5 (0.1, 2, 5000), else m x 10^n
    (``plain`` True or False: that style whatever the value)."""
    if x == 0 or not np.isfinite(x):
        return "0" if x == 0 else ""
    if plain or (plain is None and 1e-3 <= abs(x) < 1e5):
        return np.format_float_positional(x, precision=digits, fractional=False, trim="-")
    exponent = int(np.floor(np.log10(abs(x))))
    mantissa = f"{x / 10.0**exponent:.{digits}g}"
    return (f"$10^{{{exponent}}}$" if mantissa == "1"
            else f"${mantissa}\\times10^{{{exponent}}}$")


def readable_log_axis(axis) -> None:
    """Major ticks a person reads on a log ``axis`` (an `Axis`): every 1-9 over less than a
    decade, 1-2-5 over up to about two decades, decades beyond; plain labels (`tick_text`);
    minor ticks unlabelled. Call it after the axis is logarithmic and its limits are set."""
    lo, hi = sorted(axis.get_view_interval())
    decades = np.log10(hi / lo) if lo > 0 else 10.0
    subs = (np.arange(1.0, 10.0) if decades <= 0.8 else
            (1.0, 2.0, 5.0) if decades <= 2.2 else (1.0,))
    axis.set_major_locator(LogLocator(subs=subs))
    axis.set_major_formatter(FuncFormatter(lambda x, _: tick_text(x, 3)))
    axis.set_minor_locator(LogLocator(subs=np.arange(2.0, 10.0)))
    axis.set_minor_formatter(NullFormatter())


def _levels(values: list[np.ndarray], field: str):
    """(contour levels, norm, the value when the field is constant else None) of a field
    over all maps; (None, None, None) when nothing is drawable. A constant field (to six
    digits: a closed form's rounding is no variation) is drawn in one colour with one tick,
    its value, instead of a colour bar over a made-up span."""
    finite = np.concatenate([v[np.isfinite(v)].ravel() for v in values])
    if field not in LINEAR and field != "restitution":
        finite = finite[finite > 0]
    if finite.size == 0:
        return None, None, None
    lo, hi = float(finite.min()), float(finite.max())
    if hi - lo <= 1e-6 * max(abs(lo), abs(hi), 1e-300):      # constant to six digits
        pad = 0.01 * (abs(lo) or 1.0)
        return np.array([lo - pad, lo + pad]), Normalize(lo - pad, lo + pad), lo
    if field == "restitution":
        lo = min(lo, 0.999)
        return np.linspace(lo, 1.0, 21), Normalize(lo, 1.0), None
    if field in LINEAR:
        return np.linspace(lo, hi, 21), Normalize(lo, hi), None
    return np.geomspace(lo, hi, 21), LogNorm(lo, hi), None


def _nice_ticks(lo: float, hi: float, log: bool) -> np.ndarray:
    """1-2-5 ticks within [lo, hi] (log scale), or about six round ticks (linear)."""
    if not log:
        ticks = MaxNLocator(6).tick_values(lo, hi)
        return ticks[(ticks >= lo - 1e-12 * abs(hi)) & (ticks <= hi + 1e-12 * abs(hi))]
    decades = np.arange(np.floor(np.log10(lo)), np.ceil(np.log10(hi)) + 1)
    ticks = np.array([m * 10.0**d for d in decades for m in (1, 2, 5)])
    ticks = ticks[(ticks >= lo) & (ticks <= hi)]
    if ticks.size > 9:
        ticks = ticks[np.isin(np.round(ticks / 10.0 ** np.floor(np.log10(ticks))), (1,))]
    return ticks if ticks.size >= 2 else np.array([lo, hi])


def _wrap(label: str, inches: float) -> str:
    """``label`` in lines that fit along ``inches`` of a colour bar (10 pt text)."""
    return "\n".join(textwrap.wrap(label, max(14, int(inches * 72 / 5.6))))


def _colorbar(fig, mappable, axes, label, norm, constant=None, inches: float = 2.6):
    """A colour bar with readable ticks: one, its value, for a constant field; 1-2-5 or
    round ticks otherwise, with enough digits that neighbours differ (a ratio of 0.999-1.001
    needs four); its label wrapped to the bar's length (``inches``)."""
    cb = fig.colorbar(mappable, ax=axes, shrink=0.95)
    ticks = ([constant] if constant is not None else
             _nice_ticks(norm.vmin, norm.vmax, isinstance(norm, LogNorm)))
    # one style for all ticks: plain where every one is, else all m x 10^n
    plain = all(t == 0 or 1e-3 <= abs(t) < 1e5 for t in ticks)
    digits = next((d for d in range(3, 9) if len({tick_text(t, d, plain) for t in ticks}) ==
                   len(ticks)), 9)
    cb.set_ticks(ticks, labels=[tick_text(t, digits, plain) for t in ticks])
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    cb.set_label(_wrap(label if constant is None else f"{label}: constant", inches))


def _angle_rows(m: ContactMap) -> bool:
    """True for an oblique map over (V, angle); other maps have no angle."""
    angle = getattr(m, "angle", None)
    return angle is not None and np.ptp(angle) > 0


def _rows(m: ContactMap) -> tuple[np.ndarray, str, bool]:
    """The map's row axis for plotting: values, label and whether it is logarithmic. An
    oblique map over (V, angle) has the incidence angle as rows, any other map the radius."""
    if _angle_rows(m):
        return m.angle, "incidence angle (deg)", False
    return m.radius * 1e6, "radius R (µm)", m.radius[-1] / m.radius[0] > 20


#: the x label of every map
VELOCITY_LABEL = "impact velocity V (m/s)"


def _style_axes(ax, m: ContactMap, title: str = "", labels: bool = True):
    """Log scales where the map's axes span more than a factor 20, with readable ticks; the
    title, and the axis labels unless the figure carries them (``labels`` False)."""
    _, label, log = _rows(m)
    if m.velocity[-1] / m.velocity[0] > 20:
        ax.set_xscale("log")
        readable_log_axis(ax.xaxis)
    if log:
        ax.set_yscale("log")
        readable_log_axis(ax.yaxis)
    if title:
        ax.set_title(title)
    if labels:
        ax.set_xlabel(VELOCITY_LABEL)
        ax.set_ylabel(label)


def save_figure(fig: Figure, path) -> Path:
    """Write ``fig`` to ``path`` atomically, in the format of its suffix (PNG when none)."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".") or "png")
    return Path(path)


def _done(fig: Figure, path) -> Figure:
    if path is not None:
        save_figure(fig, path)
    return fig


def new_figure(rows: int = 1, cols: int = 1, **kwargs):
    """A pyplot-free figure and its axes (an array when ``squeeze`` is False)."""
    layout = kwargs.pop("layout", "constrained")
    fig = Figure(figsize=kwargs.pop("figsize"), layout=layout)
    return fig, fig.subplots(rows, cols, **kwargs)


def display(m: ContactMap, field: str, values=None) -> tuple[str, str, float]:
    """(name, unit, factor to that unit) of a map field; a field of a model kind that
    `DISPLAY` does not name is shown by its name in its SI unit. With its ``values`` (SI), a
    force, length, time or pressure is shown in the unit that writes the largest below 1000
    (a slider edge's force in kN, a sphere's in mN)."""
    name, unit, factor = DISPLAY.get(field, (field.replace("_", " "),
                                             m.units.get(field, "-"), 1.0))
    scaled = SCALED_UNITS.get(m.units.get(field, ""))
    finite = None if values is None else np.asarray(values, float)[np.isfinite(values)]
    if scaled and finite is not None and finite.size:
        unit, factor = display_unit(finite, scaled)
    return name, unit, factor


def below_validity(m: ContactMap, field: str = "") -> np.ndarray | None:
    """Where a map's computed approach is below `CONTINUUM_MIN_APPROACH`, and for the
    ``field`` residual_depth also where the crater is shallower than
    `CONTINUUM_MIN_RESIDUAL` (None when the map has no approach)."""
    if "delta_max" not in m.units:
        return None
    delta = m.field("delta_max")
    with np.errstate(invalid="ignore"):
        below = np.isfinite(delta) & (delta < CONTINUUM_MIN_APPROACH)
        if field == "residual_depth" and field in m.units:
            depth = m.field(field)
            below |= (depth > 0) & (depth < CONTINUUM_MIN_RESIDUAL)
    return below & ~m.out_of_range


def yield_boundary(m: ContactMap) -> bool:
    """Whether first yield divides the computed points of a map (a line to draw)."""
    computed = m.yielded[~m.out_of_range]
    return bool(0 < computed.mean() < 1) if computed.size else False


def _blank(m: ContactMap, field: str) -> bool:
    """Whether some computed points of ``field`` are drawn blank (NaN, or <= 0 on a log
    scale: no crater, no tangential speed)."""
    z = m.field(field)[~m.out_of_range]
    linear = field == "restitution" or field in LINEAR
    with np.errstate(invalid="ignore"):
        return bool(np.any(~np.isfinite(z) if linear else ~(z > 0)))


def validity_key(residual: bool = False) -> Patch:
    """The legend handle of the dotted points below a continuum's validity (``residual``:
    shallow craters among them)."""
    label = BELOW_VALIDITY if not residual else BELOW_VALIDITY.replace(
        ":", f" or residual depth < {CONTINUUM_MIN_RESIDUAL * 1e9:g} nm:")
    return Patch(facecolor="0.45", edgecolor="w", hatch="...", lw=0, label=label)


def mark_below_validity(ax, V, below) -> None:
    """Dots over the velocities ``V`` of a line plot where ``below`` (a continuum's
    validity), the whole height of ``ax``, as the maps dot those points."""
    with mpl.rc_context({"hatch.color": "w", "hatch.linewidth": 1.5}):
        ax.fill_between(V, 0, 1, where=below, transform=ax.get_xaxis_transform(),
                        facecolor="0.8", hatch="...", lw=0, step="mid",
                        gid="below validity")


def map_keys(maps, fields) -> list:
    """Legend handles for what a map figure draws over the colours of ``fields`` of
    ``maps`` (a list): the first-yield line, the hatched points out of range, the dotted
    points below a continuum's validity and the blank points, each only where drawn."""
    maps = list(maps)
    keys = []
    if any(yield_boundary(m) for m in maps):
        keys.append(Line2D([], [], color="k", ls="--", lw=1.2, label="first yield",
                           path_effects=YIELD_STYLE["path_effects"]))
    if any(m.out_of_range.any() for m in maps):
        keys.append(Patch(facecolor="0.85", edgecolor="0.3", hatch="///", lw=0,
                          label=f"not computed: {maps[0].range_limit}"))
    dotted = [below_validity(m, f) for m in maps for f in ("", *fields)]
    if any(b is not None and b.any() for b in dotted):
        shallow = "residual_depth" in fields and any(
            np.any(below_validity(m, "residual_depth") & ~below_validity(m)) for m in maps
            if "delta_max" in m.units)
        keys.append(validity_key(shallow))
    blank = [f for f in fields if any(f in m.units and _blank(m, f) for m in maps)]
    tangential = [display(maps[0], f)[0].split()[-1] for f in blank if f in LINEAR]
    if tangential:
        keys.append(Patch(facecolor="w", edgecolor="0.5", lw=0.8, label="blank "
                          f"{', '.join(tangential)}: no tangential speed (normal incidence)"))
    if "residual_depth" in blank:
        keys.append(Patch(facecolor="w", edgecolor="0.5", lw=0.8,
                          label="blank residual depth: no crater"))
    return keys


def key_legend(fig, keys, ax=None, title: str = ""):
    """The keys under ``ax`` (one map panel), else at the head of the figure under its
    ``title`` (the legend's own title: a suptitle would overlap it; its foot holds the
    velocity label). A figure without keys gets its title as a suptitle."""
    options = {"handles": keys, "fontsize": 8, "frameon": False, "handlelength": 2.4}
    if ax is not None and keys:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1, **options)
    elif keys:
        fig.legend(loc="outside upper center", ncol=min(len(keys), 3), title=title or None,
                   title_fontsize="large", **options)
    elif title:
        fig.suptitle(title)


def draw_map_field(fig: Figure, ax, m: ContactMap, field: str,
                   label: str | None = None, keys: bool = True):
    """One field of one map on ``ax`` with its own colour bar, as `plot_impact_maps` draws
    it: hatched out of range, dashed first yield, dotted below a continuum's validity, a
    constant field in one colour; the keys of those under the panel (``keys``), else left
    to the caller (`map_keys`)."""
    name, unit, factor = display(m, field, m.field(field))
    z = m.field(field) * factor
    levels, norm, constant = _levels([z], field)
    filled = _fill(ax, m, z, field, levels, norm)
    _style_axes(ax, m)
    if filled is not None:
        inches = 0.95 * ax.get_position().height * fig.get_size_inches()[1]
        _colorbar(fig, filled, ax, label or f"{name} ({unit})", norm, constant, inches)
    if keys:
        key_legend(fig, map_keys([m], (field,)), ax)


def _fill(ax, m, z, field, levels, norm):
    """Filled contours of ``z`` (display units) on a map's grid, the first-yield line, the
    points below a continuum's validity and the out-of-range hatching; the contour set, or
    None when nothing was drawable (the panel then says why)."""
    V, Y = np.meshgrid(m.velocity, _rows(m)[0])
    linear = field == "restitution" or field in LINEAR
    z = z if linear else np.where(z > 0, z, np.nan)
    filled = None
    ax.set_xlim(V.min(), V.max())
    ax.set_ylim(Y.min(), Y.max())
    if levels is not None and np.isfinite(z).any():
        filled = ax.contourf(V, Y, z, levels=levels, norm=norm, cmap="viridis",
                             extend="neither" if len(levels) == 2 else "both")
    else:           # say why the panel is blank rather than leave an empty frame
        computed = z[~m.out_of_range]
        why = ("0 everywhere" if computed.size and np.all(np.nan_to_num(computed) == 0)
               else "nothing computed")
        ax.text(0.5, 0.5, f"{display(m, field)[0]}:\n{why}", transform=ax.transAxes,
                ha="center", va="center", color="0.3")
    if yield_boundary(m):           # among the computed points only
        ax.contour(V, Y, np.where(m.out_of_range, np.nan, m.yielded.astype(float)),
                   levels=[0.5], **YIELD_STYLE).set_gid("first yield")
    _mark_below_validity(ax, V, Y, below_validity(m, field))
    _hatch_out_of_range(ax, V, Y, m.out_of_range)
    return filled


def _mark_below_validity(ax, V, Y, below):
    """Dots over the points whose approach is below a continuum's validity."""
    if below is None or not below.any():
        return
    with mpl.rc_context({"hatch.color": "0.9", "hatch.linewidth": 1.5}):
        ax.contourf(V, Y, below.astype(float), levels=[0.5, 1.5], colors="none",
                    hatches=["..."]).set_gid("below validity")


def _hatch_out_of_range(ax, V, Y, out_of_range: np.ndarray):
    """Hatching over the points out of the model's range, out to the computed points (the
    filled contours stop at the last cell of computed corners: no blank strip between)."""
    out = out_of_range.astype(float)
    if out.any():
        ax.contourf(V, Y, out, levels=[1e-3, 1.5], colors=["0.85"], hatches=["///"])


def plot_impact_maps(maps: dict[str, ContactMap], path=None, fields=None,
                     title: str = "") -> Figure:
    """Contour plots of ``fields`` (rows) for each labelled map (columns); the Figure, also
    saved to ``path`` when given. The axes' labels are the figure's (one for the velocity,
    one for the rows), the keys of the lines, hatching and blanks at its foot.

    ``fields`` None: those its model kind shows (`kinds.ModelKind.fields`: an oblique map's
    include its tangential results); a map over (V, angle) shows e_y and the tangential
    results only (the normal maxima do not depend on the angle). With two maps a third
    column compares them: their ratio (first / second), or their difference for the
    signed, linear fields.
    """
    labels = list(maps)
    first = maps[labels[0]]
    if fields is None:
        shown = tuple(kind_named(first.kind).fields)
        fields = (("restitution",) + tuple(f for f in shown if f in first.tangential)
                  if _angle_rows(first) else shown)
    ratio = len(labels) == 2
    rows, cols = len(fields), len(labels) + ratio
    fig, axes = new_figure(rows, cols, figsize=(4.2 * cols + 1.2, 2.9 * rows), squeeze=False)
    for r, field in enumerate(fields):
        name, unit, scale = display(first, field, np.concatenate(
            [maps[lab].field(field).ravel() for lab in labels]))
        data = [maps[lab].field(field) * scale for lab in labels]
        levels, norm, constant = _levels(data, field)
        filled = None
        for c, lab in enumerate(labels):
            ax = axes[r][c]
            filled = _fill(ax, maps[lab], data[c], field, levels, norm) or filled
            _style_axes(ax, maps[lab], lab if r == 0 else "", labels=False)
        if filled is not None:
            _colorbar(fig, filled, list(axes[r][:len(labels)]), f"{name} ({unit})", norm,
                      constant, inches=2.6)
        if ratio:
            _draw_comparison(fig, axes[r][-1], maps, labels, field, data)
            _style_axes(axes[r][-1], first, f"{labels[0]} {'-' if field in LINEAR else '/'} "
                        f"{labels[1]}" if r == 0 else "", labels=False)
    fig.supxlabel(VELOCITY_LABEL)
    fig.supylabel(_rows(first)[1])
    key_legend(fig, map_keys(maps.values(), fields), title=title)
    return _done(fig, path)


def _draw_comparison(fig, ax, maps, labels, field, data):
    """The ratio (first / second) of a field of two maps, or their difference for the
    signed, linear fields, hatched where either map is out of range; a note instead of a
    colour bar where they are equal everywhere or nothing compares."""
    first = maps[labels[0]]
    name, unit, _ = display(first, field)
    V, Y = np.meshgrid(first.velocity, _rows(first)[0])
    ax.set_xlim(V.min(), V.max())
    ax.set_ylim(Y.min(), Y.max())
    difference = field in LINEAR
    with np.errstate(divide="ignore", invalid="ignore"):
        q = (data[0] - data[1] if difference
             else np.where(data[1] > 0, data[0] / data[1], np.nan))
    centre = 0.0 if difference else 1.0
    finite = q[np.isfinite(q)]
    deviation = float(np.max(np.abs(finite - centre))) if finite.size else 0.0
    if deviation > 1e-6 * max(1.0, float(np.max(np.abs(finite)))):
        span = max(deviation, 1e-3)
        rnorm = TwoSlopeNorm(centre, centre - span, centre + span)
        filled = ax.contourf(V, Y, q, levels=np.linspace(centre - span, centre + span, 21),
                             norm=rnorm, cmap="RdBu_r")
        _colorbar(fig, filled, ax, f"{'difference' if difference else 'ratio'} of "
                  f"{name}" + (f" ({unit})" if difference else ""), rnorm)
    else:
        what = "difference 0" if difference else "ratio 1"
        ax.text(0.5, 0.5, f"{name}:\n{what} where both are computed" if finite.size
                else f"{name}:\nnothing to compare", transform=ax.transAxes, ha="center",
                va="center", color="0.3", wrap=True)
    # the comparison holds where both maps do: hatched where either is out of range
    _hatch_out_of_range(ax, V, Y, np.logical_or.reduce(
        [maps[lab].out_of_range for lab in labels]))


#: display units of a history's quantities, largest factor first: the first that keeps the
#: largest value under 1000 is used
FORCE_UNITS = (("nN", 1e9), ("µN", 1e6), ("mN", 1e3), ("N", 1.0), ("kN", 1e-3))
LENGTH_UNITS = (("pm", 1e12), ("nm", 1e9), ("µm", 1e6), ("mm", 1e3), ("m", 1.0))
TIME_UNITS = (("ns", 1e9), ("µs", 1e6), ("ms", 1e3), ("s", 1.0))


PRESSURE_UNITS = (("Pa", 1.0), ("kPa", 1e-3), ("MPa", 1e-6), ("GPa", 1e-9))
#: SI unit of a map field -> the display units it may take
SCALED_UNITS = {"N": FORCE_UNITS, "m": LENGTH_UNITS, "s": TIME_UNITS, "Pa": PRESSURE_UNITS}


def display_unit(values, units) -> tuple[str, float]:
    """(unit, factor from SI) of ``units`` that writes the largest of ``values`` below 1000."""
    largest = float(np.nanmax(np.abs(values))) if np.size(values) else 0.0
    return next(((u, f) for u, f in units if largest * f < 1e3), units[-1])


def plot_history(history, path=None, title: str = "", kind: str = "sphere") -> Figure:
    """Force against approach, and approach and force against time, of one impact of the
    model ``kind`` (its `kinds.ModelKind.history_labels` name the axes), each in the unit
    that writes it without an exponent; the Figure, also saved to ``path`` when given."""
    res = history.result
    labels = kind_named(kind).history_labels
    approach, what = labels(res) if labels else ("approach δ (nm)", kind)
    fig, (ax1, ax2) = new_figure(1, 2, figsize=(10, 4))
    contact = history.phase > 0
    (d_unit, d_f), (f_unit, f_f), (t_unit, t_f) = (
        display_unit(getattr(history, k)[contact], units) for k, units in
        (("delta", LENGTH_UNITS), ("force", FORCE_UNITS), ("time", TIME_UNITS)))
    if approach.endswith("(nm)"):       # the kind's label names nm: write it in d_unit
        approach = f"{approach[:-len('(nm)')]}({d_unit})"
    else:
        d_unit, d_f = "nm", 1e9
    t, d = history.time[contact] * t_f, history.delta[contact] * d_f
    force, load = history.force[contact] * f_f, history.phase[contact] == 1
    ax1.plot(d[load], force[load], label="loading")
    ax1.plot(d[~load], force[~load], label="unloading")
    ax1.set_xlabel(approach)
    ax1.set_ylabel(f"force P ({f_unit})")
    ax1.legend(loc="upper left")
    ax2.plot(t, d, color="C0")
    ax2.set_xlabel(f"time ({t_unit})")
    ax2.set_ylabel(approach, color="C0")
    ax3 = ax2.twinx()
    ax3.plot(t, force, color="C3")
    ax3.set_ylabel(f"force P ({f_unit})", color="C3")
    fig.suptitle(title or f"{what}: V = {res.velocity:.3g} m/s, R = {eng(res.radius, 'm')}, "
                 f"e_y = {res.restitution:.4f}")
    return _done(fig, path)


def plot_curve_analysis(curve, result, path=None, title: str = "") -> Figure:
    """One indentation curve with its Oliver-Pharr fits: the unloading power law over its
    window, the tangent of slope S at h_max, and h_c, h_f marked; the Figure, also saved to
    ``path`` when given."""
    from filmscale.continuum.indentation.curves import SEGMENT_NAMES

    c = curve.finite()
    fig, ax = new_figure(figsize=(5.6, 4.2))
    colours = ("tab:blue", "tab:gray", "tab:green")
    for label, start, stop in c.runs():
        ax.plot(c.h[start:stop] * 1e9, c.P[start:stop] * 1e3, ".", ms=2.5, color=colours[label],
                label=SEGMENT_NAMES[label])
    if result.ok:
        h = np.linspace(result.h_f, result.h_max, 200)
        ax.plot(h * 1e9, result.B * (h - result.h_f)**result.m * 1e3, "-", color="tab:red",
                lw=1.2, label=f"P = B (h - h_f)^m, m = {result.m:.2f}")
        hs = np.array([result.h_max - result.P_max / result.S, result.h_max])
        ax.plot(hs * 1e9, (result.P_max - result.S * (result.h_max - hs)) * 1e3, "--",
                color="k", lw=1, label=f"S = {result.S:.4g} N/m")
        for depth, name in ((result.h_c, "h_c"), (result.h_f, "h_f")):
            ax.axvline(depth * 1e9, color="0.6", lw=0.8, ls=":")
            ax.annotate(name, (depth * 1e9, 0), textcoords="offset points", xytext=(2, 4),
                        fontsize=8, color="0.3")
        text = (f"E_r = {result.E_r / 1e9:.4g} GPa\nH = {result.H / 1e9:.4g} GPa\n"
                f"h_c = {result.h_c * 1e9:.4g} nm")
    else:
        text = f"not analysed:\n{result.message}"
    if result.flags:
        text += "\nflags: " + ", ".join(result.flag_codes)
    ax.text(0.03, 0.97, text, transform=ax.transAxes, va="top", fontsize=8,
            bbox={"facecolor": "white", "alpha": 0.8, "lw": 0})
    ax.set_xlabel("depth h (nm)")
    ax.set_ylabel("load P (mN)")
    ax.set_ylim(bottom=min(0.0, float(np.min(c.P)) * 1e3))
    # below the axes: the unloading and its fits fill the lower right
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2,
              frameon=False)
    ax.set_title(title, fontsize=9)
    return _done(fig, path)


def plot_csm(curve, result, path=None, title: str = "") -> Figure:
    """A CSM test: E (or E_r without a Poisson ratio) and H against depth, beside the
    instrument's own Modulus and Hardness channels where the file has them, with the depth
    range of the averages shaded; the Figure, also saved to ``path`` when given."""
    fig, axes = new_figure(1, 2, figsize=(9.6, 3.9))
    c = curve.finite()
    with_E = result.ok and np.isfinite(result.E).any()
    panels = ((axes[0], result.E if with_E else result.E_r, "E_vendor",
               "modulus E (GPa)" if with_E else "reduced modulus E_r (GPa)"),
              (axes[1], result.H, "H_vendor", "hardness H (GPa)"))
    for ax, ours, channel, label in panels:
        if result.ok:
            lo, hi = result.depth_range
            ax.axvspan(lo * 1e9, hi * 1e9, color="0.92", lw=0,
                       label=f"averaged: {lo * 1e9:.0f}-{hi * 1e9:.0f} nm")
            ax.plot(result.h * 1e9, ours / 1e9, ".", ms=2.5, color="tab:blue", label="filmscale")
            if channel in c.channels and (with_E or channel == "H_vendor"):
                keep = np.isfinite(c.channels[channel]) & (c.h > 0)
                ax.plot(c.h[keep] * 1e9, c.channels[channel][keep] / 1e9, "-", lw=0.9,
                        color="tab:orange", label="the instrument's own channel")
            inside = (result.h >= lo) & (result.h <= hi)
            if inside.any():        # the scatter of the shallowest points would hide the rest
                top = np.nanpercentile(ours[result.h >= lo], 99) / 1e9
                ax.set_ylim(0, 1.3 * top if np.isfinite(top) and top > 0 else None)
            ax.legend(fontsize=7, loc="lower right")
        else:
            ax.text(0.5, 0.5, f"not analysed:\n{result.message}", transform=ax.transAxes,
                    ha="center", va="center", fontsize=8)
        ax.set_xlabel("depth h (nm)")
        ax.set_ylabel(label)
    axes[0].set_title(title, fontsize=9, loc="left")
    return _done(fig, path)


def plot_property_profile(profile, path=None, nix_gao=None, fit=None,
                          indenter_compliance=0.0, title: str = "", film=None) -> Figure:
    """E_r and H against contact depth: every indent, group means with their standard
    deviation, layer bands, the piecewise fit (a `TableProfile`, E_r recomputed with the
    indenter compliance, 1/Pa), the Nix-Gao curve when given and identified (else a
    horizontal line at the depth-independent H0), and a film/substrate model's fitted E_r(h_c)
    with the indents it was fitted on (``film``, a `FilmModulus`); the Figure, also saved to
    ``path`` when given. Legends sit below the axes, off the data."""
    fig, axes = new_figure(1, 2, figsize=(10.0, 4.8), sharex=True)
    top = float(np.max(profile.h_c)) * 1.05
    edges = [0.0, *profile.interfaces, top]
    for ax, key, name in ((axes[0], "E_r", "reduced modulus E_r (GPa)"),
                          (axes[1], "H", "hardness H (GPa)")):
        for k, (lo, hi) in enumerate(zip(edges[:-1], edges[1:])):
            if hi > lo:
                ax.axvspan(lo * 1e9, hi * 1e9, color=("0.93", "0.85")[k % 2], lw=0)
                ax.text((lo + hi) / 2 * 1e9, 1.0, profile.layer_names[k], ha="center",
                        va="bottom", fontsize=7, transform=ax.get_xaxis_transform())
        ax.plot(profile.h_c * 1e9, getattr(profile, key) / 1e9, ".", ms=3, color="0.45",
                label="indents")
        ax.errorbar(profile.group_h_c * 1e9, getattr(profile, f"group_{key}") / 1e9,
                    yerr=getattr(profile, f"group_{key}_std") / 1e9, fmt="o", ms=4,
                    color="tab:blue", capsize=2, label="mean +- std")
        ax.set_xlabel("contact depth h_c (nm)")
        ax.set_ylabel(name)
        ax.set_xlim(0.0, top * 1e9)
        ax.yaxis.set_major_locator(MaxNLocator(6, steps=[1, 2, 2.5, 5, 10]))
    if fit is not None:
        E_r = 1.0 / (1.0 / fit.plane_strain_modulus + indenter_compliance)
        axes[0].plot(fit.depths * 1e9, E_r / 1e9, "-", color="tab:orange", label="piecewise fit")
        axes[1].plot(fit.depths * 1e9, fit.hardness / 1e9, "-", color="tab:orange",
                     label="piecewise fit")
    if film is not None:
        # the model's E_r(h_c) with a(h_c) from the fitted indents' a/h_c (held at its end
        # values beyond them), their points ringed, t/10 and t marked
        order = np.argsort(film.h_c)
        hs, ratio = film.h_c[order], (film.a / film.h_c)[order]
        h = np.geomspace(max(float(np.min(profile.h_c)), 1e-3 * top), top, 60)
        a = h * np.interp(np.log(h), np.log(hs), ratio)
        axes[0].plot(h * 1e9, film.reduced_modulus(a, h) / 1e9, "-", color="tab:green",
                     label=f"{film.model}: E_f = {film.E / 1e9:.4g} GPa")
        axes[0].plot(film.h_c * 1e9, film.E_r / 1e9, "o", ms=7, mfc="none", mec="tab:green",
                     mew=1.2, label=f"fitted ({film.points} indents, h_c >= t/10)")
        for depth, style in ((film.min_depth, ":"), (film.thickness, "--")):
            if depth <= top:
                axes[0].axvline(depth * 1e9, color="tab:green", ls=style, lw=0.8)
        for depth, label in ((film.min_depth, "t/10"), (film.thickness, "t")):
            if depth <= top:
                axes[0].text(depth * 1e9, 0.98, f" {label}", color="tab:green", fontsize=8,
                             va="top", transform=axes[0].get_xaxis_transform())
    if nix_gao is not None:
        h = np.linspace(profile.h_c.min(), profile.h_c.max(), 200)
        if getattr(nix_gao, "identified", True):
            axes[1].plot(h * 1e9, nix_gao.hardness(h) / 1e9, "-", color="tab:red",
                         label=f"Nix-Gao H0 = {nix_gao.H0 / 1e9:.3g} GPa, "
                               f"h* = {nix_gao.h_star * 1e9:.3g} nm")
        else:
            axes[1].axhline(nix_gao.H0 / 1e9, color="tab:red", ls="--",
                            label=f"depth-independent H = {nix_gao.H0 / 1e9:.3g} GPa "
                                  f"(Nix-Gao h* not identified)")
    for ax in axes:
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2,
                  frameon=False)
    fig.suptitle(title, fontsize=10)
    return _done(fig, path)

