"""Every kind of figure filmscale draws is readable, checked on its Artist tree after a draw:
the sphere map (two targets and their ratio), the oblique maps over (V, angle) and (V, R), the
cylinder (edge) map, an elastic map whose residual depth is blank, the impact histories of a
sphere and a cylinder, the indentation curve analysis, the scene figure of a pipeline
result, a sliding contact's x-z field and first-yield map, and an MD nanoscratch's forces,
groove and plastic zone. In each: (a) no two visible tick labels of one axis overlap, and no axis writes an
offset or multiplier ("1e6") beside them; (b) every axes with
data has an x and a y label (its own or the figure's shared one), and a dimensional
quantity's label carries its unit in parentheses; (c) colour-bar tick labels and labels lie
inside the figure and no two colour-bar labels overlap; (d) no axes is empty: each holds data
or a text note; (e) no legend covers a data point of its axes or another axes; and a map
figure keys its dashed first-yield line, its hatching and its dotted below-validity area in a
legend when it draws them."""

import functools
import re

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.lines import Line2D

from filmscale.continuum.contact.cylinder import CylinderImpactModel
from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.impact_map import cylinder_map, impact_map
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import oblique_map
from filmscale.continuum.indentation.oliver_pharr import oliver_pharr
from filmscale.continuum.materials import ElasticPlastic
from filmscale.workflows import pipeline as pl
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.plots import (plot_curve_analysis, plot_history, plot_impact_maps)
from filmscale.workflows.report import scene_figure
from tests.helpers.curves import synthetic_sharp_curve
from tests.helpers.scenes import BASE, CURVES_FILM

STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e9, name="steel")
#: hard enough that first yield crosses the sphere map, which also has points out of range
#: and approaches below 2 nm: every key a map can have
HARD, HARDER = (ElasticPlastic(E=200e9, nu=0.3, sigma_y=s) for s in (4e9, 6e9))
LAW = contact_law("komvopoulos-ye-continuous")
#: the span of the issue: 0.1-5 m/s, where the default log axis labelled its minor ticks
VELOCITY = np.geomspace(0.1, 5.0, 6)
#: label words of dimensionless quantities, which need no unit
DIMENSIONLESS = ("restitution", "ratio", "e_y", "e_x", "e_c", "friction coefficient")


@functools.cache
def _sphere_maps():
    R = np.geomspace(1e-7, 1e-5, 4)
    return {label: impact_map(ImpactModel(material, LAW), VELOCITY, R, 1e-11)
            for label, material in (("harder", HARDER), ("hard", HARD))}


def _elastic_map():
    hard = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e10)
    return {"elastic": impact_map(ImpactModel(hard, contact_law("hertz")), VELOCITY,
                                  np.geomspace(1e-6, 1e-5, 3), 1e-9)}


def _oblique_angle_map():
    model = ImpactModel(STEEL, contact_law("hertz"))
    return {"steel": oblique_map(model, VELOCITY[::2], 1e-5, 1e-9,
                                 np.array([0.0, 20.0, 40.0, 60.0]), 0.1)}


#: the oblique (V, R) map's normal and tangential fields drawn (all eleven take long)
OBLIQUE_FIELDS = ("delta_max", "residual_depth", "restitution", "restitution_tangential",
                  "restitution_contact_point", "spin")


def _oblique_radius_map():
    model = ImpactModel(STEEL, contact_law("hertz"))
    return {"steel": oblique_map(model, VELOCITY[::2], np.geomspace(1e-6, 1e-5, 3), 1e-9,
                                 30.0, 0.1)}


def _cylinder_map():
    model = CylinderImpactModel(STEEL, 5e-3)
    return {"steel": cylinder_map(model, np.geomspace(0.5, 20.0, 5),
                                  np.geomspace(5e-4, 2e-3, 3), 1e-3)}


def _scene_result(tmp_path):
    """A film calibrated from a curve file on glass, hit by a 1 um corner, with a map from
    20 nm to 10 um (approaches below 2 nm at its small radii) and its +- 2 std bands."""
    from tests.helpers.curves import sphere_curve_file
    sphere_curve_file(tmp_path)
    text = BASE.format(R=1e-6, m=1e-12, V=0.5, t=50e-9, impactor_extra="", film=CURVES_FILM,
                       want='["maxima", "map"]') + \
        "[map]\nvelocity = [0.01, 5.0, 5]\nradius = [2e-8, 1e-5, 4]\n"
    result = pl.run_scene(parse_pipeline(text, "s.toml", tmp_path), tmp_path / "store",
                          tmp_path / "r.h5")
    return scene_figure(result.path)


def _curve_figure():
    _, curve = synthetic_sharp_curve(70.1e9, 0.33, 0.5e9, 0.122, 1e-6)
    return plot_curve_analysis(curve, oliver_pharr(curve, "berkovich"), title="Al 7075")


def _slide_figures():
    """The x-z field of a sliding edge on two films, and its first-yield map over (load,
    friction) crossing first yield and changing the layer that governs."""
    from filmscale.continuum.contact.slide_map import slide_map
    from filmscale.continuum.contact.slider import Slider, slide
    from filmscale.continuum.materials import Layer, LayerStack
    from filmscale.workflows.slide_plots import plot_slide, plot_slide_map
    film = ElasticPlastic(E=200e9, nu=0.25, sigma_y=8e9, name="DLC")
    ru = ElasticPlastic(E=300e9, nu=0.3, sigma_y=3.5e9, name="Ru")
    stack = LayerStack((Layer(20e-9, film), Layer(30e-9, ru)), STEEL)
    edge = Slider("cylinder", 10e-6, length=10e-6)
    field = plot_slide(slide(stack, edge, 2e-2, 0.4, refine=False))
    mp = slide_map(stack, edge, np.geomspace(1e-3, 0.3, 6), np.linspace(0.0, 1.0, 5))
    return field, plot_slide_map(mp, title="an edge on two films")


def _scratch_figure():
    """A synthetic two-layer scratch: forces over a 3 nm stroke, a groove 0.4 nm deep with
    pile-up either side, and a cross-section of atoms whose strain falls off from the groove,
    damaged in both layers."""
    from filmscale.workflows.scratch_plots import (DamageBox, ScratchFigureData, groove_edges,
                                                   plot_scratch)
    rng = np.random.default_rng(7)
    s = np.linspace(0.0, 3e-9, 300)
    Fn = 60e-9 + 3e-9 * rng.standard_normal(s.size)
    Fl = 15e-9 * (1 - np.exp(-s / 0.3e-9)) + 1.5e-9 * rng.standard_normal(s.size)
    y = np.linspace(-2.9e-9, 2.9e-9, 30)
    h = -0.4e-9 * np.exp(-(y / 0.9e-9) ** 2) + 0.15e-9 * np.exp(-((np.abs(y) - 1.8e-9)
                                                               / 0.5e-9) ** 2)
    ys, zs = np.meshgrid(np.arange(-2.9e-9, 2.95e-9, 0.18e-9), np.arange(-3e-9, 0.0, 0.18e-9))
    ys, zs = ys.ravel(), zs.ravel()
    eta = 0.5 * np.exp(-(ys**2 + zs**2) / (1.1e-9) ** 2)
    mu = Fl[100:250] / Fn[100:250]
    return plot_scratch(ScratchFigureData(
        name="Cu on Ni", distance=s, normal_force=Fn, lateral_force=Fl, stroke_length=3e-9,
        steady=(0.6e-9, 2.4e-9), friction_mean=float(mu.mean()),
        friction_std=float(mu.std(ddof=1)), profile_y=y, profile_h=h,
        groove_depth=float(-h.min()), groove_width=1.6e-9,
        groove_edges=groove_edges(y, h, 1.5e-9), pileup_height=float(h.max()),
        section_y=ys, section_h=zs, section_eta=eta, interfaces=(1.0e-9,),
        damage=(DamageBox("Cu", -1.3e-9, 1.3e-9, 0.98e-9, 120),
                DamageBox("Ni", -0.9e-9, 0.9e-9, 1.4e-9, 40, top=1.0e-9))))


FIGURES = {
    "sphere map": lambda tmp: plot_impact_maps(_sphere_maps(), title="a steel sphere"),
    "elastic map": lambda tmp: plot_impact_maps(_elastic_map(),
                                                fields=("delta_max", "residual_depth")),
    "oblique map over angle": lambda tmp: plot_impact_maps(_oblique_angle_map()),
    "oblique map over radius": lambda tmp: plot_impact_maps(_oblique_radius_map(),
                                                            fields=OBLIQUE_FIELDS),
    "cylinder map": lambda tmp: plot_impact_maps(_cylinder_map(), title="edge"),
    "sphere history": lambda tmp: plot_history(
        ImpactModel(STEEL, LAW).history(1.0, 1e-5, 1e-9), kind="sphere"),
    "cylinder history": lambda tmp: plot_history(
        CylinderImpactModel(STEEL, 5e-3).history(5.0, 1e-3, 1e-3), kind="cylinder"),
    "curve analysis": lambda tmp: _curve_figure(),
    "scene figure": _scene_result,
    "slide field": lambda tmp: _slide_figures()[0],
    "slide map": lambda tmp: _slide_figures()[1],
    "scratch": lambda tmp: _scratch_figure(),
}


@pytest.fixture(params=list(FIGURES))
def drawn(request, tmp_path):
    """(name, figure, renderer) of each figure kind, drawn."""
    fig = FIGURES[request.param](tmp_path)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return request.param, fig, canvas.get_renderer()


def _is_colorbar(ax) -> bool:
    return ax.get_label() == "<colorbar>"


def _has_data(ax) -> bool:
    lines = any(len(line.get_xdata()) for line in ax.lines if line.get_visible())
    return bool(lines or ax.collections or ax.images or ax.patches)


def _shown_tick_labels(axis):
    """The tick labels of ``axis`` drawn: visible, with text, at a tick inside the view."""
    lo, hi = sorted(axis.get_view_interval())
    slack = 1e-9 * (abs(lo) + abs(hi))
    ticks = axis.get_major_ticks() + axis.get_minor_ticks()
    return [label for tick in ticks if lo - slack <= tick.get_loc() <= hi + slack
            for label in (tick.label1, tick.label2)
            if label.get_visible() and label.get_text().strip()]


def _overlap(a, b, slack=1.0) -> bool:
    return (a.x0 < b.x1 - slack and b.x0 < a.x1 - slack and a.y0 < b.y1 - slack
            and b.y0 < a.y1 - slack)


def _axes(fig):
    return [ax for ax in fig.axes if ax.get_visible()]


def check_tick_labels_do_not_overlap(fig, renderer):
    """... and are plain: no axis writes an offset or a multiplier ("1e6") beside them."""
    for ax in _axes(fig):
        for axis in (ax.xaxis, ax.yaxis):
            offset = axis.get_offset_text()
            assert not (offset.get_visible() and offset.get_text()), \
                f"{ax.get_title()!r} writes {offset.get_text()!r} beside its ticks"
            boxes = [(t.get_text(), t.get_window_extent(renderer))
                     for t in _shown_tick_labels(axis)]
            clashes = [(a, b) for i, (a, box_a) in enumerate(boxes)
                       for b, box_b in boxes[i + 1:] if _overlap(box_a, box_b)]
            assert not clashes, f"overlapping tick labels on {ax.get_title()!r}: {clashes}"


def _has_unit(label: str) -> bool:
    return bool(re.search(r"\([^()]*\w[^()]*\)", label)) or \
        any(word in label for word in DIMENSIONLESS)


def check_labels_and_units(fig):
    """Labels of each axes: its own, its twin's (an axes in the same place) or the
    figure's shared ones."""
    shared_x, shared_y = fig.get_supxlabel(), fig.get_supylabel()
    for ax in _axes(fig):
        if not _has_data(ax) or not ax.axison:
            continue
        if _is_colorbar(ax):
            label = ax.get_ylabel() or ax.get_xlabel()
            assert label and _has_unit(label), f"colour bar label {label!r} has no unit"
            continue
        twins = [a for a in _axes(fig) if a.get_position().bounds == ax.get_position().bounds]
        x = next((a.get_xlabel() for a in twins if a.get_xlabel()), shared_x)
        y = next((a.get_ylabel() for a in twins if a.get_ylabel()), shared_y)
        assert x and y, f"axes {ax.get_title()!r} lacks a label: x {x!r}, y {y!r}"
        for label in (x, y):
            assert _has_unit(label), f"label {label!r} has no unit in parentheses"


def check_colorbars_inside(fig, renderer):
    box = fig.bbox
    labels = []
    for ax in filter(_is_colorbar, _axes(fig)):
        texts = _shown_tick_labels(ax.yaxis) + _shown_tick_labels(ax.xaxis)
        texts += [t for t in (ax.yaxis.label, ax.xaxis.label) if t.get_text()]
        for text in texts:
            ext = text.get_window_extent(renderer)
            assert (ext.x0 >= box.x0 - 1 and ext.x1 <= box.x1 + 1 and ext.y0 >= box.y0 - 1
                    and ext.y1 <= box.y1 + 1), f"colour bar text {text.get_text()!r} clipped"
        labels += [(t.get_text(), t.get_window_extent(renderer))
                   for t in (ax.yaxis.label, ax.xaxis.label) if t.get_text()]
    clashes = [(a, b) for i, (a, box_a) in enumerate(labels)
               for b, box_b in labels[i + 1:] if _overlap(box_a, box_b)]
    assert not clashes, f"colour bar labels overlap: {clashes}"


def check_no_empty_axes(fig):
    """Each axes holds data or a note, and the axes fill every cell of their grid (no
    blank panel where a grid has no axes)."""
    cells = {}
    for ax in _axes(fig):
        assert _has_data(ax) or ax.texts, f"empty axes {ax.get_title()!r}"
        spec = ax.get_subplotspec()
        if spec is not None and not _is_colorbar(ax):
            grid = spec.get_gridspec()
            cells.setdefault(grid, set()).update(
                (r, c) for r in spec.rowspan for c in spec.colspan)
    for grid, used in cells.items():
        rows, cols = grid.get_geometry()
        empty = {(r, c) for r in range(rows) for c in range(cols)} - used
        assert not empty, f"empty grid cells {sorted(empty)}"


def _legends(fig):
    return [(legend, None) for legend in fig.legends] + \
        [(ax.get_legend(), ax) for ax in fig.axes if ax.get_legend() is not None]


def check_legends_cover_no_data(fig, renderer):
    for legend, owner in _legends(fig):
        box = legend.get_window_extent(renderer)
        for ax in _axes(fig):
            if ax is owner or (owner is not None and ax.bbox.bounds == owner.bbox.bounds):
                points = [line.get_transform().transform(line.get_xydata())
                          for line in ax.lines if line.get_visible() and line.get_label()
                          and len(line.get_xdata())]
                inside = sum(int(np.sum((p[:, 0] > box.x0) & (p[:, 0] < box.x1)
                                        & (p[:, 1] > box.y0) & (p[:, 1] < box.y1)))
                             for p in points)
                assert inside == 0, f"the legend of {ax.get_title()!r} covers {inside} points"
            else:
                assert not _overlap(box, ax.get_window_extent(renderer)), \
                    f"a legend covers the axes {ax.get_title()!r}"


def check_map_keys(fig):
    keys = " ".join(t.get_text() for legend, _ in _legends(fig) for t in legend.get_texts())
    collections = [c for ax in fig.axes for c in ax.collections]
    if any("///" in (getattr(c, "hatches", None) or ()) for c in collections):
        assert "not computed" in keys, keys
    if any(c.get_gid() == "first yield" for c in collections):
        assert "first yield" in keys, keys
    if any(c.get_gid() == "below validity" for c in collections):
        assert "below" in keys, keys


def test_the_figure_is_readable(drawn):
    name, fig, renderer = drawn
    check_tick_labels_do_not_overlap(fig, renderer)
    check_labels_and_units(fig)
    check_colorbars_inside(fig, renderer)
    check_no_empty_axes(fig)
    check_legends_cover_no_data(fig, renderer)
    check_map_keys(fig)


def test_a_short_log_span_gets_plain_1_2_5_ticks_and_no_minor_labels():
    """0.1-5 m/s: major ticks 0.1, 0.2, 0.5, 1, 2, 5, written as plain numbers."""
    fig = plot_impact_maps(_sphere_maps(), fields=("delta_max",))
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    texts = [t.get_text() for t in _shown_tick_labels(ax.xaxis)]
    assert texts == ["0.1", "0.2", "0.5", "1", "2", "5"]
    assert not any(t.get_text() for t in ax.xaxis.get_minorticklabels())


def test_a_map_keys_first_yield_hatching_and_approaches_below_2_nm_in_a_legend():
    fig = plot_impact_maps(_sphere_maps(), fields=("delta_max", "restitution"),
                           title="a steel sphere")
    collections = [c for ax in fig.axes for c in ax.collections]
    for gid in ("first yield", "below validity"):
        assert any(c.get_gid() == gid for c in collections), gid
    assert any("///" in (getattr(c, "hatches", None) or ()) for c in collections)
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [
        "first yield", "not computed: approach > R",
        "approach < 2 nm: below a continuum's validity"]
    assert legend.get_title().get_text() == "a steel sphere"
    assert isinstance(legend.legend_handles[0], Line2D)
    assert [h.get_hatch() for h in legend.legend_handles[1:]] == ["///", "..."]
