"""Plots for people: impact-map contours and impact histories (matplotlib, no display needed).

Maps put targets side by side (layered and bare substrate, like the seed dissertation's
Figs. 3.2-3.5) with one colour scale per quantity, the first-yield boundary dashed, and
points whose approach would exceed R hatched.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.colors import LogNorm, Normalize, TwoSlopeNorm  # noqa: E402
from matplotlib.ticker import (FormatStrFormatter, MaxNLocator,  # noqa: E402
                               NullFormatter)

from filmscale.continuum import MAP_FIELDS, ImpactHistory, ImpactMap  # noqa: E402

from .store import atomic_path  # noqa: E402

#: file formats the plots can be written in
PLOT_FORMATS = tuple(sorted(FigureCanvasAgg.get_supported_filetypes()))

#: label, display unit and factor from SI for each map field
DISPLAY = {
    "delta_max": ("maximum approach", "nm", 1e9),
    "mean_pressure_max": ("maximum mean pressure", "GPa", 1e-9),
    "force_max": ("maximum force", "mN", 1e3),
    "contact_radius_max": ("maximum contact radius", "µm", 1e6),
    "contact_time": ("contact time", "µs", 1e6),
    "residual_depth": ("residual depth", "nm", 1e9),
    "restitution": ("restitution coefficient e_y", "-", 1.0),
}


def _levels(values: list[np.ndarray], field: str):
    finite = np.concatenate([v[np.isfinite(v)].ravel() for v in values])
    if field == "restitution":
        lo = float(np.min(finite)) if finite.size else 0.0
        lo = min(lo, 0.999)
        return np.linspace(lo, 1.0, 21), Normalize(lo, 1.0)
    positive = finite[finite > 0]
    if positive.size == 0:
        return None, None
    lo, hi = float(positive.min()), float(positive.max())
    if hi <= lo * 1.0001:
        hi = lo * 1.01
    return np.geomspace(lo, hi, 21), LogNorm(lo, hi)


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


def _colorbar(fig, mappable, axes, label, norm):
    cb = fig.colorbar(mappable, ax=axes, shrink=0.95)
    cb.set_ticks(_nice_ticks(norm.vmin, norm.vmax, isinstance(norm, LogNorm)))
    cb.ax.yaxis.set_major_formatter(FormatStrFormatter("%.3g"))
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    cb.set_label(label)


def _style_axes(ax, m: ImpactMap, first_row: bool, last_row: bool, first_col: bool, title):
    if m.velocity[-1] / m.velocity[0] > 20:
        ax.set_xscale("log")
    if m.radius[-1] / m.radius[0] > 20:
        ax.set_yscale("log")
    if first_row:
        ax.set_title(title)
    if last_row:
        ax.set_xlabel("impact velocity V (m/s)")
    if first_col:
        ax.set_ylabel("radius R (µm)")


def _save(fig, path) -> Path:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)
    return Path(path)


def plot_impact_maps(maps: dict[str, ImpactMap], path, fields=tuple(MAP_FIELDS),
                     title: str = "") -> Path:
    """Contour plots of ``fields`` (rows) for each labelled map (columns), saved to ``path``.

    With two maps a third column shows their ratio (first / second): where the film matters.
    """
    labels = list(maps)
    ratio = len(labels) == 2
    rows, cols = len(fields), len(labels) + ratio
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols + 1.2, 2.9 * rows),
                             squeeze=False, constrained_layout=True)
    for r, field in enumerate(fields):
        name, unit, scale = DISPLAY[field]
        data = [maps[lab].field(field) * scale for lab in labels]
        levels, norm = _levels(data, field)
        filled = None
        for c, lab in enumerate(labels):
            ax = axes[r][c]
            m = maps[lab]
            V, R = np.meshgrid(m.velocity, m.radius * 1e6)
            z = data[c] if field == "restitution" else np.where(data[c] > 0, data[c], np.nan)
            if levels is not None and np.isfinite(z).any():
                filled = ax.contourf(V, R, z, levels=levels, norm=norm, cmap="viridis",
                                     extend="both")
            yielded = m.maxima.yielded.astype(float)
            if 0 < yielded.mean() < 1:
                ax.contour(V, R, yielded, levels=[0.5], colors="w", linestyles="--",
                           linewidths=1.0)
            _hatch_out_of_range(ax, V, R, m)
            _style_axes(ax, m, r == 0, r == rows - 1, c == 0, lab)
        if filled is not None:
            _colorbar(fig, filled, list(axes[r][:len(labels)]), f"{name} ({unit})", norm)
        if ratio:
            ax = axes[r][-1]
            m = maps[labels[0]]
            V, R = np.meshgrid(m.velocity, m.radius * 1e6)
            with np.errstate(divide="ignore", invalid="ignore"):
                q = np.where(data[1] > 0, data[0] / data[1], np.nan)
            finite = q[np.isfinite(q)]
            if finite.size:
                span = max(abs(finite.max() - 1), abs(1 - finite.min()), 1e-3)
                rnorm = TwoSlopeNorm(1.0, 1 - span, 1 + span)
                filled_q = ax.contourf(V, R, q, levels=np.linspace(1 - span, 1 + span, 21),
                                       norm=rnorm, cmap="RdBu_r")
                _colorbar(fig, filled_q, ax, f"ratio of {name}", rnorm)
            _hatch_out_of_range(ax, V, R, m)
            _style_axes(ax, m, r == 0, r == rows - 1, False, f"{labels[0]} / {labels[1]}")
    if title:
        fig.suptitle(f"{title}\ndashed: first yield; hatched: approach would exceed R "
                     f"(not computed); blank residual depth: no crater")
    return _save(fig, path)


def _hatch_out_of_range(ax, V, R, m: ImpactMap):
    out = m.out_of_range.astype(float)
    if out.any():
        ax.contourf(V, R, out, levels=[0.5, 1.5], colors=["0.85"], hatches=["///"])


def plot_history(history: ImpactHistory, path, title: str = "") -> Path:
    """Force against approach, and approach and force against time, of one impact."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    contact = history.phase > 0
    t_us = history.time[contact] * 1e6
    d_nm = history.delta[contact] * 1e9
    f_mn = history.force[contact] * 1e3
    load = history.phase[contact] == 1
    ax1.plot(d_nm[load], f_mn[load], label="loading")
    ax1.plot(d_nm[~load], f_mn[~load], label="unloading")
    ax1.set_xlabel("approach δ (nm)")
    ax1.set_ylabel("force P (mN)")
    ax1.legend()
    ax2.plot(t_us, d_nm, color="C0")
    ax2.set_xlabel("time (µs)")
    ax2.set_ylabel("approach δ (nm)", color="C0")
    ax3 = ax2.twinx()
    ax3.plot(t_us, f_mn, color="C3")
    ax3.set_ylabel("force P (mN)", color="C3")
    res = history.result
    fig.suptitle(title or f"{res.contact_law}: V = {res.velocity:.3g} m/s, "
                 f"R = {res.radius * 1e6:.3g} µm, e_y = {res.restitution:.4f}")
    return _save(fig, path)
