"""Plots of sliding contacts: the x-z stress field of `filmscale slide --plot` and the
first-yield map of `filmscale slide-map --plot` (docs/sliding.md). Pyplot-free, as `plots`.

The field is drawn as each layer's von Mises stress over its own yield strength, the measure
that says which layer yields first; a nanometre film under a micrometre contact is invisible
on the whole depth, so a second panel shows the films alone."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap, Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from filmscale.continuum.contact.sliding import von_mises
from filmscale.core.quantities import eng

from .plots import (FORCE_UNITS, LENGTH_UNITS, YIELD_STYLE, display_unit, new_figure,
                    readable_log_axis, save_figure)

#: colour map of the yield ratio: light below first yield, dark towards it
RATIO_CMAP = "magma_r"
#: the layers' colours on the map of which layer yields first
LAYER_COLOURS = ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02",
                 "#a6761d", "#666666")


def _ratio_fields(result):
    """Per layer: depths (m), yield ratio (or von Mises in Pa where sigma_y is infinite)."""
    f = result.field
    out = []
    for z, s, m in zip(f["depths"], f["stresses"], result.stack.materials()):
        vm = von_mises(s)
        out.append((z, vm / m.sigma_y if np.isfinite(m.sigma_y) else np.full(vm.shape, np.nan)))
    return out


def _done(fig: Figure, path) -> Figure:
    if path is not None:
        save_figure(fig, path)
    return fig


def plot_slide(result, path=None, title: str = "") -> Figure:
    """The x-z plane through a sliding contact: von Mises / sigma_y of each layer over the
    whole depth (left) and over the films (right; only with films), the interfaces dashed,
    the contact (|x| <= a) as a bar on the surface, the first yield starred, the sliding
    direction and the trailing edge marked. Returns the Figure (saved to ``path``)."""
    stack = result.stack
    films = sum(layer.thickness for layer in stack.layers)
    x = result.field["x"]
    size = result.contact.size
    parts = _ratio_fields(result)
    finite = [r[np.isfinite(r)] for _, r in parts]
    top = max([float(v.max()) for v in finite if v.size] + [1.0])
    norm = Normalize(0.0, top)
    lu, lf = display_unit([x.max(), films or size], LENGTH_UNITS)
    panels = 2 if films > 0 else 1
    fig, axes = new_figure(1, panels, figsize=(5.2 * panels + 1.2, 4.4), squeeze=False)
    depth_limits = [(0.0, float(parts[-1][0][-1]))]
    if films > 0:
        depth_limits.append((0.0, 1.6 * films))
    first = result.first_yield
    for ax, (z_lo, z_hi) in zip(axes[0], depth_limits):
        for z, ratio in parts:
            if z[0] > z_hi:
                continue
            mesh = ax.pcolormesh(x * lf, z * lf, np.ma.masked_invalid(ratio), cmap=RATIO_CMAP,
                                 norm=norm, shading="gouraud")
        for depth in stack.interface_depths:
            if depth <= z_hi:
                ax.axhline(depth * lf, color="w", lw=1.0, ls="--")
        ax.plot([-size * lf, size * lf], [z_lo, z_lo], color="tab:blue", lw=5,
                solid_capstyle="butt", clip_on=False)
        if first is not None and first["z"] <= z_hi:
            ax.plot(first["x"] * lf, first["z"] * lf, marker="*", ms=14, color="tab:cyan",
                    mec="k", ls="none")
        ax.set_ylim(z_hi * lf, z_lo)
        ax.set_xlim(x[0] * lf, x[-1] * lf)
        ax.set_xlabel(f"x, sliding direction ({lu})")
        ax.set_ylabel(f"depth z ({lu})")
    if films > 0:
        axes[0][1].set_title("the films", fontsize=10)
        for name, (z0, z1) in zip([layer.material.name for layer in stack.layers],
                                  zip((0.0, *stack.interface_depths), stack.interface_depths)):
            axes[0][1].text(x[-1] * lf * 0.97, 0.5 * (z0 + z1) * lf, name or "film",
                            ha="right", va="center", fontsize=8, color="k",
                            bbox={"fc": "w", "ec": "none", "alpha": 0.7, "pad": 1})
    axes[0][0].set_title("whole depth", fontsize=10)
    fig.colorbar(mesh, ax=axes[0], label="yield ratio: von Mises / σ_y of the layer",
                 shrink=0.9)
    letter = "a" if result.slider.shape == "sphere" else "b"
    keys = [Line2D([], [], color="tab:blue", lw=5,
                   label=f"contact, {letter} = {eng(size, 'm')}"),
            Line2D([], [], color="0.4", ls="--", label="interface")]
    if first is not None:
        keys.append(Line2D([], [], marker="*", ms=12, color="tab:cyan", mec="k", ls="none",
                           label=f"largest ratio: {first['layer']} "
                                 f"({first['yield_ratio']:.2f})"))
    fig.legend(handles=keys, loc="outside lower center", ncols=3, fontsize=8, frameon=False)
    c = result.contact
    fig.suptitle(title or f"{result.slider.shape} R = {eng(result.slider.radius, 'm')}, "
                 f"P = {eng(c.load, 'N')}, μ = {result.friction:g}: p0 = {eng(c.p0, 'Pa')}; "
                 f"sliding in +x, trailing edge at x = -{letter}", fontsize=10)
    return _done(fig, path)


def plot_slide_map(mp, path=None, title: str = "") -> Figure:
    """A first-yield map over (normal load, friction): the largest yield ratio of any layer
    with its contour at 1 (first yield) and, where modelled, the shakedown load (left); the
    layer whose ratio is largest (right). Returns the Figure (saved to ``path``)."""
    loads, mus = mp.normal_load, mp.friction
    fu, ff = display_unit(loads, FORCE_UNITS)
    ratio = mp["yield_ratio_max"]
    fig, axes = new_figure(1, 2, figsize=(11.5, 5.2), squeeze=False)
    ax = axes[0][0]
    X, Y = np.meshgrid(loads * ff, mus)
    finite = ratio[np.isfinite(ratio)]
    hi = float(finite.max()) if finite.size else 1.0
    mesh = ax.pcolormesh(X, Y, ratio, cmap=RATIO_CMAP, norm=Normalize(0.0, max(hi, 1.0)),
                         shading="nearest")
    fig.colorbar(mesh, ax=ax, label="largest yield ratio (von Mises / σ_y) of any layer")
    keys = []
    if finite.size and finite.min() < 1.0 < finite.max() and loads.size > 1 and mus.size > 1:
        ax.contour(X, Y, ratio, levels=[1.0], **YIELD_STYLE)
        keys.append(Line2D([], [], color="k", ls="--", label="first yield (ratio 1)"))
    if "shakedown_load" in mp.values:
        ax.plot(mp["shakedown_load"] * ff, mus, color="tab:cyan", lw=2)
        keys.append(Line2D([], [], color="tab:cyan", lw=2, label="elastic shakedown limit"))
    layer = mp["first_yield_layer"]
    names = mp.layer_names
    colours = ListedColormap([LAYER_COLOURS[i % len(LAYER_COLOURS)]
                              for i in range(len(names))])
    bx = axes[0][1]
    bx.pcolormesh(X, Y, np.ma.masked_less(layer, 0), cmap=colours,
                  norm=BoundaryNorm(np.arange(len(names) + 1) - 0.5, colours.N),
                  shading="nearest")
    shown = sorted(set(int(v) for v in np.unique(layer) if v >= 0))
    layer_keys = [Patch(color=colours(i), label=names[i]) for i in shown]
    load_at = mp["first_yield_load"]
    if np.isfinite(load_at).any():
        bx.plot(load_at * ff, mus, color="k", lw=1.5)
        layer_keys.append(Line2D([], [], color="k", lw=1.5, label="first-yield load"))
    # below the axes: the map fills its axes, a legend inside would hide data
    bx.legend(handles=layer_keys, title="largest ratio in", fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.16), ncols=min(len(layer_keys), 4), frameon=False)
    for a in (ax, bx):
        if loads.size > 1 and loads[-1] / loads[0] > 3:
            a.set_xscale("log")
            a.set_xlim(loads[0] * ff, loads[-1] * ff)
            readable_log_axis(a.xaxis)
        a.set_xlabel(f"normal load P ({fu})")
        a.set_ylabel("friction coefficient μ")
    if keys:
        ax.legend(handles=keys, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16),
                  ncols=len(keys), frameon=False)
    fig.suptitle(title or f"first yield of a sliding {mp.kind.split('-')[-1]}", fontsize=10)
    return _done(fig, path)
