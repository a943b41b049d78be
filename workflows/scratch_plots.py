"""The figure of a scratch (`filmscale md scratch --plot`, docs/md-indentation.md; `filmscale
particles scratch --plot`, docs/particles.md): what a reader of the seed dissertation's
chapter 7 looks for. Pyplot-free, as `plots`.

Four panels: the normal and lateral force on the indenter against its sliding distance, the
steady part of the first pass (20-80 % of the stroke, where the friction is averaged) shaded
(under constant load, the target load and the indenter's depth on a right-hand axis);
the friction coefficient F_lat / F_n against the same distance, its steady mean +- std drawn;
the residual groove profile across the groove at mid-stroke, with the undeformed surface (0),
the groove depth, width and pile-up marked; and the cross-section of the plastic zone: the
atoms of the groove's cross-section (the damage analysis's selection: within
`scratch_run.WINDOW` of mid-stroke x, as built) at their final y and height, coloured by their
atomic von Mises strain on a scale clipped at `ETA_MAX`, the damage threshold marked on the
colour bar, the layer interfaces dashed and each layer's damaged region (its width and depth,
measured on the as-built positions as `md.damage` measures them) boxed.

`scratch_figure_data` gathers what the figure draws from a run and its analysis
(`md.scratch_run.read_scratch`, `analyze_scratch`) into a `ScratchFigureData` of plain arrays
(SI), which `plot_scratch` draws; a test or a notebook can build the data directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from .plots import new_figure, save_figure

#: the top of the eta_Mises colour scale (higher strains take its top colour), and its ticks
ETA_MAX = 0.3
ETA_TICKS = (0.0, 0.1, 0.2, 0.3)
#: the units a figure may be drawn in, per SI unit
SCALES = {"nm": 1e9, "um": 1e6, "nN": 1e9, "mN": 1e3}
#: the colours of the layers' damaged-region boxes, top layer first
BOX_COLOURS = ("tab:red", "tab:orange", "tab:pink", "tab:brown")


@dataclass(frozen=True)
class DamageBox:
    """The damaged region of one layer in the cross-section (SI, as built): y from the groove
    axis of its outermost damaged atoms, the depth below the undeformed surface of its
    deepest one, and that of the layer's top (0 for the top layer), where its box starts."""

    layer: str
    y_min: float
    y_max: float
    depth: float
    atoms: int
    top: float = 0.0

    @property
    def width(self) -> float:
        return self.y_max - self.y_min


@dataclass(frozen=True)
class ScratchFigureData:
    """What `plot_scratch` draws, SI (m, N)."""

    name: str
    distance: np.ndarray          #: sliding distance of the indenter along its path, m
    normal_force: np.ndarray      #: N, at each distance
    lateral_force: np.ndarray     #: N, positive against the motion
    stroke_length: float          #: of one pass, m
    steady: tuple[float, float]   #: distances of the steady part of the first pass, m
    friction_mean: float
    friction_std: float
    profile_y: np.ndarray         #: bin centres, m from the groove axis
    profile_h: np.ndarray         #: surface height above the undeformed surface, m
    groove_depth: float
    groove_width: float
    groove_edges: tuple[float, float]   #: y of the profile's zero crossings, m (NaN: none)
    pileup_height: float
    section_y: np.ndarray         #: final y of the cross-section's atoms, m from the axis
    section_h: np.ndarray         #: their final height above the undeformed surface, m
    section_eta: np.ndarray       #: their eta_Mises (NaN: not defined)
    interfaces: tuple[float, ...] = ()     #: depths of the layer interfaces, m (positive)
    damage: tuple[DamageBox, ...] = ()     #: per layer, top layer first
    threshold: float = 0.1
    #: the drawing's units and the strain that marks the plastic zone: an atomistic scratch's
    #: by default; a particle scratch draws um, mN and the equivalent plastic strain
    length_unit: str = "nm"
    force_unit: str = "nN"
    strain_name: str = "atomic von Mises strain η_Mises"
    strain_symbol: str = "eta_Mises"
    strain_max: float = ETA_MAX
    strain_ticks: tuple[float, ...] = ETA_TICKS
    #: a constant-load stroke: its target (N) and the indenter's depth at each distance (m)
    normal_load: float = math.nan
    depth: np.ndarray | None = None
    item: str = "atom"           #: what a dot of the cross-section is
    slice_thickness: float = 1e-9    #: of the cross-section along x, m

    @property
    def length_scale(self) -> float:
        return SCALES[self.length_unit]

    @property
    def force_scale(self) -> float:
        return SCALES[self.force_unit]


def groove_edges(y: np.ndarray, h: np.ndarray, contact_radius: float) -> tuple[float, float]:
    """The y either side of the groove's lowest point (within ``contact_radius`` of the axis)
    where the profile first rises through zero, as `scratch_run` measures the groove width;
    NaN where there is none."""
    from filmscale.md.scratch_run import groove_bottom
    from filmscale.md.scratch_run import groove_edges as edges_from
    i0 = groove_bottom(y, h, contact_radius)
    if i0 is None or h[i0] >= 0:
        return math.nan, math.nan
    return edges_from(y, h, i0)


def _minimum_image(d: np.ndarray, period: float) -> np.ndarray:
    return d - period * np.round(d / period)


def scratch_figure_data(run, analysis) -> ScratchFigureData:
    """The figure's data of a `ScratchRun` and its `ScratchAnalysis`: the forces over the
    stroke (every pass, against the distance slid), the analysis's profile and figures, and
    the atoms of the damage analysis's cross-section with their damaged regions per layer."""
    from filmscale.md.damage import layer_index
    from filmscale.md.scratch_run import STEADY, WINDOW, damage_reference, stroke_mask

    spec = run.spec
    s = spec.schedule()
    slab = spec.indent.slab_built
    on = stroke_mask(run)
    L = spec.stroke.length
    a = run.final_atoms
    x0 = damage_reference(run)
    Lx, Ly = slab.box[:2]
    x_mid = spec.x_start + 0.5 * L
    section = np.abs(_minimum_image(x0[:, 0] - x_mid, Lx)) <= WINDOW
    eta = (analysis.eta_mises if analysis.eta_mises is not None
           else np.full(len(a["id"]), np.nan))
    y0 = _minimum_image(x0[:, 1] - spec.y_center, Ly)
    layer = layer_index(x0[:, 2], slab.layer_tops)
    hit = section & (np.nan_to_num(eta, nan=0.0) > analysis.damage_threshold)
    boxes = []
    for k, d in enumerate(analysis.damage):
        m = hit & (layer == k)
        if np.any(m):
            top = 0.0 if k == 0 else slab.z_surface - slab.layer_tops[k]
            boxes.append(DamageBox(d.layer, float(y0[m].min()), float(y0[m].max()), d.depth,
                                   d.atoms, top))
    load = spec.stroke.normal_load
    return ScratchFigureData(
        name=spec.name, distance=s.dx * (run.data["step"][on] - s.s_stroke),
        normal_force=run.normal_force[on], lateral_force=run.lateral_force[on],
        normal_load=math.nan if load is None else load,
        depth=None if load is None else run.data["depth"][on],
        stroke_length=L, steady=(STEADY[0] * L, STEADY[1] * L),
        friction_mean=analysis.friction_mean, friction_std=analysis.friction_std,
        profile_y=analysis.profile_y, profile_h=analysis.profile_h,
        groove_depth=analysis.groove_depth, groove_width=analysis.groove_width,
        groove_edges=groove_edges(analysis.profile_y, analysis.profile_h,
                                  spec.contact_radius),
        pileup_height=analysis.pileup_height,
        section_y=_minimum_image(a["y"][section] - spec.y_center, Ly),
        section_h=a["z"][section] - run.z_surface, section_eta=eta[section],
        interfaces=tuple(slab.z_surface - t for t in slab.layer_tops[1:]),
        damage=tuple(boxes), threshold=analysis.damage_threshold)


#: the top of the particles' equivalent plastic strain colour scale, and its ticks
EP_MAX = 0.2
EP_TICKS = (0.0, 0.05, 0.1, 0.15, 0.2)


def particle_scratch_figure_data(run, analysis) -> ScratchFigureData:
    """The figure's data of a particle scratch (`md.particle_scratch_run`): the forces of
    the stroke against the distance slid, the groove profile, and the particles of the
    mid-stroke lattice column (mirrored in a half model) coloured by their equivalent plastic
    strain, each layer's plastic zone boxed (as `plastic_zones` measures it)."""
    from filmscale.md.particle_scratch_run import mid_section
    from filmscale.md.scratch_run import STEADY

    spec = run.spec
    t1, _, tu, _ = spec.stroke.times
    on = (run.time > t1) & (run.time < tu)
    distance = spec.stroke.speed * (run.time[on] - t1)
    sel = mid_section(run)
    y, h = run.final.positions[sel, 1], run.final.positions[sel, 2]
    ep = run.final.plastic_strain[sel] if run.final.plastic_strain is not None else \
        np.full(int(sel.sum()), np.nan)
    if spec.grid.half:
        off = y > 0.25 * spec.grid.spacing
        y, h, ep = (np.concatenate([-y[off], y]), np.concatenate([h[off], h]),
                    np.concatenate([ep[off], ep]))
    tops = np.cumsum([0.0, *(t for t, _ in spec.target.films)])
    boxes = tuple(DamageBox(z.layer, -z.width / 2, z.width / 2, z.depth, z.particles,
                            float(tops[k]))
                  for k, z in enumerate(analysis.damage) if z.particles)
    L = spec.stroke.length
    return ScratchFigureData(
        name=spec.name, distance=distance, normal_force=run.fz[on],
        lateral_force=run.lateral_force[on], stroke_length=L,
        steady=(STEADY[0] * L, STEADY[1] * L), friction_mean=analysis.friction_mean,
        friction_std=analysis.friction_std, profile_y=analysis.profile_y,
        profile_h=analysis.profile_h, groove_depth=analysis.groove_depth,
        groove_width=analysis.groove_width,
        groove_edges=groove_edges(analysis.profile_y, analysis.profile_h, spec.contact_radius),
        pileup_height=analysis.pileup_height, section_y=y, section_h=h, section_eta=ep,
        interfaces=tuple(float(t) for t in tops[1:]), damage=boxes,
        threshold=analysis.plastic_threshold, length_unit="um", force_unit="mN",
        strain_name="equivalent plastic strain ε_p", strain_symbol="eps_p", strain_max=EP_MAX,
        strain_ticks=EP_TICKS, item="particle", slice_thickness=spec.grid.spacing)


def _steady_span(ax, d: ScratchFigureData, label: bool) -> None:
    lo, hi = d.steady
    ax.axvspan(lo * d.length_scale, hi * d.length_scale, color="0.9", lw=0,
               label="steady part (20-80 % of the first pass)" if label else None)
    passes = int(round(float(np.max(d.distance, initial=0.0)) / d.stroke_length))
    for k in range(1, passes):
        ax.axvline(k * d.stroke_length * d.length_scale, color="0.5", lw=0.8, ls=":",
                   label="end of a pass" if label and k == 1 else None)


def _legend_below(ax, ncol: int = 2) -> None:
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=ncol,
              frameon=False)


def _draw_forces(ax, d: ScratchFigureData) -> None:
    _steady_span(ax, d, True)
    x = d.distance * d.length_scale
    ax.plot(x, d.normal_force * d.force_scale, "-", lw=1.0, color="tab:blue",
            label="normal force F_n")
    ax.plot(x, d.lateral_force * d.force_scale, "-", lw=1.0, color="tab:red",
            label="lateral force F_lat (against the motion)")
    if math.isfinite(d.normal_load):
        ax.axhline(d.normal_load * d.force_scale, color="tab:blue", lw=1.0, ls="--",
                   label=f"target load {d.normal_load * d.force_scale:.3g} {d.force_unit}")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(f"sliding distance ({d.length_unit})")
    ax.set_ylabel(f"force ({d.force_unit})")
    ax.set_title("forces on the indenter", fontsize=9)
    if d.depth is None:
        _legend_below(ax)
        return
    # under load the depth is the output: on its own axis, in the legend with the forces
    right = ax.twinx()
    right.plot(x, d.depth * d.length_scale, "-", lw=1.0, color="0.35",
               label="indenter depth (right axis)")
    right.set_ylabel(f"indenter depth ({d.length_unit})")
    handles = [h for a in (ax, right) for h in a.get_legend_handles_labels()[0]]
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2),
              ncol=2, frameon=False)


def _draw_friction(ax, d: ScratchFigureData) -> None:
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(d.normal_force > 0, d.lateral_force / d.normal_force, np.nan)
    _steady_span(ax, d, False)
    ax.plot(d.distance * d.length_scale, mu, ".", ms=2.5, color="0.3", label="F_lat / F_n", zorder=3)
    lo, hi = d.steady
    if np.isfinite(d.friction_mean):
        std = d.friction_std if np.isfinite(d.friction_std) else 0.0
        ax.fill_between([lo * d.length_scale, hi * d.length_scale], d.friction_mean - std, d.friction_mean + std,
                        color="tab:orange", alpha=0.3, lw=0)
        ax.plot([lo * d.length_scale, hi * d.length_scale], [d.friction_mean] * 2, "-", color="tab:orange", lw=1.8,
                label=f"steady mean +- std: {d.friction_mean:.3f} +- {std:.3f}")
    ax.set_xlabel(f"sliding distance ({d.length_unit})")
    ax.set_ylabel("friction coefficient μ = F_lat / F_n")
    ax.set_title("friction", fontsize=9)
    _legend_below(ax)


def _draw_profile(ax, d: ScratchFigureData) -> None:
    y, h = d.profile_y * d.length_scale, d.profile_h * d.length_scale
    ax.axhline(0.0, color="0.5", lw=0.9, ls="--", label="undeformed surface (0)")
    ax.plot(y, h, "o-", ms=3, lw=1.2, color="tab:blue", label="surface height at mid-stroke")
    finite = np.isfinite(h)
    if np.isfinite(d.groove_depth) and d.groove_depth > 0 and np.any(finite):
        left, right = d.groove_edges
        within = finite & ~((y < left * d.length_scale) | (y > right * d.length_scale))     # NaN edges: everywhere
        y_low = y[int(np.argmin(np.where(within if within.any() else finite, h, np.inf)))]
        ax.plot([y_low, y_low], [0.0, -d.groove_depth * d.length_scale], "-", color="tab:red", lw=2,
                marker="_", ms=10, label=f"groove depth {d.groove_depth * d.length_scale:.3g} {d.length_unit}")
    left, right = d.groove_edges
    if np.isfinite(left) and np.isfinite(right):
        ax.plot([left * d.length_scale, right * d.length_scale], [0.0, 0.0], "-", color="tab:green", lw=2.5,
                marker="|", ms=12, mew=2,
                label=f"groove width {d.groove_width * d.length_scale:.3g} {d.length_unit}")
    if np.isfinite(d.pileup_height) and np.any(finite):
        top = int(np.argmax(np.where(finite, h, -np.inf)))
        ax.plot([y[top]], [d.pileup_height * d.length_scale], "v", ms=8, color="tab:purple",
                label=f"pile-up {d.pileup_height * d.length_scale:.3g} {d.length_unit}")
    ax.set_xlabel(f"y across the groove ({d.length_unit})")
    ax.set_ylabel(f"surface height ({d.length_unit})")
    ax.set_title("residual groove at mid-stroke", fontsize=9)
    _legend_below(ax)


def _marker_area(d: ScratchFigureData, ax_inches: float) -> float:
    """Marker area (pt^2) of an atom: about half its spacing (the cube root of the volume
    per atom) at the panel's scale, so that the atoms of neighbouring columns of the
    projection stay apart."""
    span_y = float(np.ptp(d.section_y)) if d.section_y.size else d.slice_thickness
    span_h = float(np.ptp(d.section_h)) if d.section_h.size else d.slice_thickness
    per_atom = (span_y * span_h * d.slice_thickness / max(d.section_y.size, 1)) ** (1 / 3)
    diameter = 0.55 * per_atom / max(span_y, 1e-12) * ax_inches * 72
    return float(np.clip(diameter, 1.5, 14.0) ** 2)


def _draw_section(fig, ax, d: ScratchFigureData) -> None:
    order = np.argsort(np.nan_to_num(d.section_eta, nan=-1.0))      # damaged atoms on top
    cmap = colormaps["viridis"].with_extremes(bad="0.75")
    dots = ax.scatter(d.section_y[order] * d.length_scale, d.section_h[order] * d.length_scale,
                      c=d.section_eta[order], cmap=cmap, norm=Normalize(0.0, d.strain_max),
                      s=_marker_area(d, 4.2), lw=0, plotnonfinite=True)
    ax.axhline(0.0, color="0.5", lw=0.9, ls="--", label="undeformed surface (0)")
    for k, depth in enumerate(d.interfaces):
        ax.axhline(-depth * d.length_scale, color="k", lw=1.0, ls="-.",
                   label="layer interface" if k == 0 else None)
    for k, box in enumerate(d.damage):
        ax.add_patch(Rectangle((box.y_min * d.length_scale, -box.depth * d.length_scale), box.width * d.length_scale,
                               (box.depth - box.top) * d.length_scale, fill=False, lw=1.6, ls="--",
                               ec=BOX_COLOURS[k % len(BOX_COLOURS)],
                               label=f"plastic in {box.layer} ({d.strain_symbol} > {d.threshold:g}): "
                                     f"width {box.width * d.length_scale:.3g} {d.length_unit}, depth "
                                     f"{box.depth * d.length_scale:.3g} {d.length_unit}"))
    left, right = d.groove_edges
    if np.isfinite(left) and np.isfinite(right):
        for k, edge in enumerate((left, right)):
            ax.axvline(edge * d.length_scale, color="tab:green", lw=1.0, ls=":",
                       label="groove edges (profile crossing 0)" if k == 0 else None)
    if not d.damage:
        ax.text(0.02, 0.04, f"no {d.item} over {d.strain_symbol} {d.threshold:g}", fontsize=8,
                transform=ax.transAxes)
    cb = fig.colorbar(dots, ax=ax, extend="max", shrink=0.95)
    ticks = sorted([t for t in d.strain_ticks if abs(t - d.threshold) > 0.1 * d.strain_max]
                   + [d.threshold])
    cb.set_ticks(ticks, labels=[f"{t:g} threshold" if math.isclose(t, d.threshold)
                                else f"{t:g}" for t in ticks])
    cb.ax.axhline(d.threshold, color="w", lw=2.5)
    cb.ax.axhline(d.threshold, color="k", lw=1.2)
    cb.set_label(f"{d.strain_name} (dimensionless)")
    ax.set_xlabel(f"y across the groove ({d.length_unit})")
    ax.set_ylabel(f"height above the surface ({d.length_unit})")
    ax.set_title(f"plastic zone: {d.item}s of the mid-stroke cross-section", fontsize=9)
    _legend_below(ax, ncol=1)


def plot_scratch(data: ScratchFigureData, path=None, title: str = "") -> Figure:
    """Forces and friction against the sliding distance, the residual groove profile and the
    cross-section of the plastic zone (the module docstring); the Figure, also saved
    (atomically) to ``path`` when given."""
    fig, axes = new_figure(2, 2, figsize=(12.0, 9.0))
    _draw_forces(axes[0][0], data)
    _draw_friction(axes[1][0], data)
    _draw_profile(axes[0][1], data)
    _draw_section(fig, axes[1][1], data)
    for ax in axes.flat:
        ax.ticklabel_format(useOffset=False)
    if data.profile_y.size and data.section_y.size:
        lo = min(data.profile_y.min(), data.section_y.min()) * data.length_scale
        hi = max(data.profile_y.max(), data.section_y.max()) * data.length_scale
        for ax in axes[:, 1]:
            ax.set_xlim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
    fig.suptitle(title or f"{data.name}: scratch", fontsize=11)
    if path is not None:
        save_figure(fig, path)
    return fig
