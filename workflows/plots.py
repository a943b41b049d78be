"""Plots for people: impact-map contours and impact histories, indentation curves and
property profiles. Every function returns a matplotlib `Figure` (shown by Jupyter as it is,
saved with `save_figure` or the ``path`` argument); figures are made without pyplot, so a
script or a notebook keeps its own backend and no figure stays open in pyplot's registry.

Maps put targets side by side (layered and bare substrate, like the seed dissertation's
Figs. 3.2-3.5) with one colour scale per quantity, the first-yield boundary dashed, and
points whose approach would exceed R hatched (in every map filmscale draws).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LogNorm, Normalize, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.ticker import FormatStrFormatter, MaxNLocator, NullFormatter

from filmscale.continuum.contact.kinds import kind_named
from filmscale.core.files import atomic_path

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


def _levels(values: list[np.ndarray], field: str):
    """(contour levels, norm, the value when the field is constant else None) of a field
    over all maps; (None, None, None) when nothing is drawable. A constant field is drawn
    in one colour with one tick, its value, instead of a colour bar over a made-up span."""
    finite = np.concatenate([v[np.isfinite(v)].ravel() for v in values])
    if field not in LINEAR and field != "restitution":
        finite = finite[finite > 0]
    if finite.size == 0:
        return None, None, None
    lo, hi = float(finite.min()), float(finite.max())
    if hi - lo <= 1e-9 * max(abs(lo), abs(hi), 1e-300):
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


def _colorbar(fig, mappable, axes, label, norm, constant=None):
    cb = fig.colorbar(mappable, ax=axes, shrink=0.95)
    if constant is not None:
        cb.set_ticks([constant])
        cb.ax.yaxis.set_major_formatter(FormatStrFormatter("%.4g"))
        cb.ax.yaxis.set_minor_formatter(NullFormatter())
        cb.set_label(f"{label}: constant")
        return
    ticks = _nice_ticks(norm.vmin, norm.vmax, isinstance(norm, LogNorm))
    cb.set_ticks(ticks)
    # enough digits that neighbouring ticks differ (a ratio of 0.999-1.001 needs four)
    digits = next((d for d in range(3, 9) if len({f"{t:.{d}g}" for t in ticks}) == len(ticks)),
                  9)
    cb.ax.yaxis.set_major_formatter(FormatStrFormatter(f"%.{digits}g"))
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    cb.set_label(label)


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


def _style_axes(ax, m: ContactMap, first_row: bool, last_row: bool,
                first_col: bool, title):
    _, label, log = _rows(m)
    if m.velocity[-1] / m.velocity[0] > 20:
        ax.set_xscale("log")
    if log:
        ax.set_yscale("log")
    if first_row:
        ax.set_title(title)
    if last_row:
        ax.set_xlabel("impact velocity V (m/s)")
    if first_col:
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


def display(m: ContactMap, field: str) -> tuple[str, str, float]:
    """(name, unit, factor to that unit) of a map field; a field of a model kind that
    `DISPLAY` does not name is shown by its name in its SI unit."""
    return DISPLAY.get(field, (field.replace("_", " "), m.units.get(field, "-"), 1.0))


def draw_map_field(fig: Figure, ax, m: ContactMap, field: str,
                   label: str | None = None):
    """One field of one map on ``ax`` with its own colour bar, as `plot_impact_maps` draws
    it: hatched out of range, dashed first yield, a constant field in one colour."""
    name, unit, factor = display(m, field)
    z = m.field(field) * factor
    levels, norm, constant = _levels([z], field)
    filled = _fill(ax, m, z, field, levels, norm)
    if filled is not None:
        _colorbar(fig, filled, ax, label or f"{name} ({unit})", norm, constant)
    _style_axes(ax, m, True, True, True, "")


def _fill(ax, m, z, field, levels, norm):
    """Filled contours of ``z`` (display units) on a map's grid, the first-yield line and
    the out-of-range hatching; the contour set, or None when nothing was drawable."""
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
    yielded = m.yielded.astype(float)
    if 0 < yielded.mean() < 1:
        ax.contour(V, Y, yielded, levels=[0.5], colors="w", linestyles="--", linewidths=1.0)
    _hatch_out_of_range(ax, V, Y, m.out_of_range)
    return filled


def plot_impact_maps(maps: dict[str, ContactMap], path=None, fields=None,
                     title: str = "") -> Figure:
    """Contour plots of ``fields`` (rows) for each labelled map (columns); the Figure, also
    saved to ``path`` when given.

    ``fields`` None: those its model kind shows (`kinds.ModelKind.fields`: an oblique map's
    include its tangential results); a map over (V, angle) shows e_y and the tangential
    results only (the normal maxima do not depend on the angle). With two maps a third column compares them:
    their ratio (first / second), or their difference for the signed, linear fields.
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
        name, unit, scale = display(first, field)
        data = [maps[lab].field(field) * scale for lab in labels]
        levels, norm, constant = _levels(data, field)
        filled = None
        for c, lab in enumerate(labels):
            ax = axes[r][c]
            filled = _fill(ax, maps[lab], data[c], field, levels, norm) or filled
            _style_axes(ax, maps[lab], r == 0, r == rows - 1, c == 0, lab)
        if filled is not None:
            _colorbar(fig, filled, list(axes[r][:len(labels)]), f"{name} ({unit})", norm,
                      constant)
        if ratio:
            ax = axes[r][-1]
            V, Y = np.meshgrid(first.velocity, _rows(first)[0])
            difference = field in LINEAR
            with np.errstate(divide="ignore", invalid="ignore"):
                q = (data[0] - data[1] if difference
                     else np.where(data[1] > 0, data[0] / data[1], np.nan))
            centre = 0.0 if difference else 1.0
            finite = q[np.isfinite(q)]
            if finite.size:
                span = max(abs(finite.max() - centre), abs(centre - finite.min()), 1e-3)
                rnorm = TwoSlopeNorm(centre, centre - span, centre + span)
                filled_q = ax.contourf(V, Y, q, levels=np.linspace(centre - span,
                                                                   centre + span, 21),
                                       norm=rnorm, cmap="RdBu_r")
                _colorbar(fig, filled_q, ax, f"{'difference' if difference else 'ratio'} of "
                          f"{name}" + (f" ({unit})" if difference else ""), rnorm)
            # the comparison holds where both maps do: hatched where either is out of range
            _hatch_out_of_range(ax, V, Y, np.logical_or.reduce(
                [maps[lab].out_of_range for lab in labels]))
            _style_axes(ax, first, r == 0, r == rows - 1, False,
                        f"{labels[0]} {'-' if difference else '/'} {labels[1]}")
    if title:
        fig.suptitle(f"{title}\n{_key_note(first, fields, cols)}")
    return _done(fig, path)


def _key_note(first, fields, columns: int) -> str:
    """What the lines, hatching and blanks of the maps mean: only what the fields drawn can
    show, wrapped to the figure's width."""
    import textwrap
    notes = ["dashed: first yield", f"hatched: {first.range_limit} (not computed)"]
    if _angle_rows(first):
        notes.append("blank e_x, e_c: no tangential speed (normal incidence)")
    elif "residual_depth" in fields:
        notes.append("blank residual depth: no crater")
    return "\n".join(textwrap.wrap("; ".join(notes), width=60 * columns))


def _hatch_out_of_range(ax, V, Y, out_of_range: np.ndarray):
    out = out_of_range.astype(float)
    if out.any():
        ax.contourf(V, Y, out, levels=[0.5, 1.5], colors=["0.85"], hatches=["///"])


def plot_history(history, path=None, title: str = "", kind: str = "sphere") -> Figure:
    """Force against approach, and approach and force against time, of one impact of the
    model ``kind`` (its `kinds.ModelKind.history_labels` name the axes); the Figure, also
    saved to ``path`` when given."""
    res = history.result
    labels = kind_named(kind).history_labels
    approach, what = labels(res) if labels else ("approach δ (nm)", kind)
    fig, (ax1, ax2) = new_figure(1, 2, figsize=(10, 4))
    contact = history.phase > 0
    t_us = history.time[contact] * 1e6
    d_nm = history.delta[contact] * 1e9
    f_mn = history.force[contact] * 1e3
    load = history.phase[contact] == 1
    ax1.plot(d_nm[load], f_mn[load], label="loading")
    ax1.plot(d_nm[~load], f_mn[~load], label="unloading")
    ax1.set_xlabel(approach)
    ax1.set_ylabel("force P (mN)")
    ax1.legend()
    ax2.plot(t_us, d_nm, color="C0")
    ax2.set_xlabel("time (µs)")
    ax2.set_ylabel(approach, color="C0")
    ax3 = ax2.twinx()
    ax3.plot(t_us, f_mn, color="C3")
    ax3.set_ylabel("force P (mN)", color="C3")
    fig.suptitle(title or f"{what}: V = {res.velocity:.3g} m/s, "
                 f"R = {res.radius * 1e6:.3g} µm, e_y = {res.restitution:.4f}")
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
    ax.legend(fontsize=7, loc="lower right")
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

