"""The one HDF5 layout of impact maps (`workflows.result.write_map_group`): xarray opens an
impact-map file and a scene result's map with named coordinates and units, without
``phony_dims``; the maps convert to xarray and pandas; the first layout still reads; and the
figures drawn from maps are Figures, with constant fields and out-of-range points drawn the
same way wherever a map is drawn."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.impact_map import ImpactMap, impact_map
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import oblique_map
from filmscale.continuum.materials import ElasticPlastic
from filmscale.workflows.cli import main
from filmscale.workflows.result import (IMPACT_MAP_FORMAT_1, read_impact_maps,
                                        write_impact_maps, write_map_group)

xr = pytest.importorskip("xarray")
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "slider_corner_disk.toml"
STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e9)


def steel_map() -> ImpactMap:
    model = ImpactModel(STEEL, contact_law("komvopoulos-ye-continuous"))
    return impact_map(model, np.geomspace(0.01, 10, 5), np.geomspace(1e-7, 1e-4, 4), 1e-6)


def test_impact_map_file_opens_in_xarray_with_named_coordinates(tmp_path, capsys):
    out = tmp_path / "map.h5"
    assert main(["impact-map", str(EXAMPLE), "--velocity", "0.001:1:6", "--radius",
                 "1e-7:1e-4:4", "--out", str(out)]) == 0
    fields, _ = read_impact_maps(out)
    for label in ("layered", "homogeneous"):
        ds = xr.open_dataset(out, engine="h5netcdf", group=label)     # no phony_dims
        assert ds["delta_max"].dims == ("radius", "velocity")
        assert ds["velocity"].attrs["units"] == "m/s" and ds["radius"].attrs["units"] == "m"
        assert ds["mass"].attrs["units"] == "kg" and ds["delta_max"].attrs["units"] == "m"
        assert ds["yielded"].dtype == bool
        np.testing.assert_array_equal(ds["velocity"], np.geomspace(0.001, 1, 6))
        np.testing.assert_array_equal(ds["delta_max"], fields[label]["delta_max"])
        # a value picked by coordinate is the field at that (R, V)
        V4 = float(np.geomspace(0.001, 1, 6)[4])
        np.testing.assert_equal(float(ds["restitution"].sel(radius=1e-5, velocity=V4,
                                                            method="nearest")),
                                fields[label]["restitution"][2, 4])
        ds.close()


def test_map_converts_to_xarray_and_pandas_point_by_point():
    mp = steel_map()
    ds = mp.to_xarray()
    assert ds["force_max"].dims == ("radius", "velocity") and ds.attrs["shape"] == "sphere"
    np.testing.assert_array_equal(ds["force_max"].values, mp.field("force_max"))
    df = mp.to_dataframe()
    assert len(df) == mp.radius.size * mp.velocity.size and df.attrs["units"]["force_max"] == "N"
    for i, R in enumerate(mp.radius):
        for j, V in enumerate(mp.velocity):
            row = df.loc[(R, V)]
            np.testing.assert_equal(row["delta_max"], mp.maxima.delta_max[i, j])
            assert row["yielded"] == mp.yielded[i, j]


def test_oblique_map_over_angles_has_angle_rows_and_radius_as_a_coordinate(tmp_path):
    model = ImpactModel(STEEL, contact_law("hertz"))
    mp = oblique_map(model, np.array([0.05, 0.1]), 1e-3, 3.27e-5, np.array([2.0, 10.0, 80.0]),
                     0.1)
    path = write_impact_maps(tmp_path / "o.h5", {"steel": mp}, {}, {})
    with xr.open_dataset(path, engine="h5netcdf", group="steel") as ds:
        assert ds["rebound_angle"].dims == ("angle", "velocity")
        assert ds["angle"].attrs["units"] == "degrees" and ds["radius"].dims == ("angle",)
        np.testing.assert_array_equal(ds["angle"], [2.0, 10.0, 80.0])
        np.testing.assert_array_equal(ds["radius"], 1e-3)
        np.testing.assert_array_equal(ds["spin"], mp.field("spin"))
    back = read_impact_maps(path)[0]["steel"]
    np.testing.assert_array_equal(back["angle"], mp.angle)
    np.testing.assert_array_equal(back["yielded"], mp.yielded)


def test_a_file_of_the_first_layout_still_reads(tmp_path):
    """filmscale.impact_map/1: shared /velocity and /radius, mass a root attribute."""
    mp = steel_map()
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"], f.attrs["shape"], f.attrs["mass"] = IMPACT_MAP_FORMAT_1, "sphere", 1e-6
        f["velocity"], f["radius"] = mp.velocity, mp.radius
        g = f.create_group("homogeneous")
        for key, value in mp.to_dict().items():
            if key not in ("velocity", "radius", "mass"):
                g[key] = np.asarray(value)
        g.attrs["regime_names"] = json.dumps(list(mp.regime_names))
        g.attrs["model"] = "{}"
    fields = read_impact_maps(path)[0]["homogeneous"]
    np.testing.assert_array_equal(fields["radius"], mp.radius)
    assert fields["mass"] == 1e-6
    np.testing.assert_array_equal(fields["contact_time"], mp.field("contact_time"))


def test_a_map_read_back_draws_as_the_map_it_was(tmp_path):
    mp = steel_map()
    with h5py.File(tmp_path / "g.h5", "w") as f:
        write_map_group(f.create_group("map"), mp.to_dict())
    from filmscale.workflows.result import read_map_group
    with h5py.File(tmp_path / "g.h5", "r") as f:
        back = ImpactMap.from_arrays(read_map_group(f["map"]), mp.regime_names)
    for name in ("delta_max", "restitution", "residual_depth"):
        np.testing.assert_array_equal(back.field(name), mp.field(name))
    np.testing.assert_array_equal(back.out_of_range, mp.out_of_range)


def _hatched(ax) -> bool:
    """Whether ``ax`` holds the hatched contour set of out-of-range points."""
    return any("///" in (getattr(c, "hatches", None) or ()) for c in ax.collections)


def test_maps_draw_as_figures_hatched_out_of_range_and_constant_fields_in_one_colour():
    from matplotlib.figure import Figure

    from filmscale.workflows.plots import draw_map_field, plot_impact_maps
    mp = steel_map()
    assert mp.out_of_range.any() and (~mp.out_of_range).any()
    fig = plot_impact_maps({"steel": mp}, fields=("delta_max", "residual_depth"))
    assert isinstance(fig, Figure) and _hatched(fig.axes[0])
    # the report's panel (draw_map_field) hatches the same points
    panel = Figure()
    draw_map_field(panel, panel.subplots(), mp, "delta_max")
    assert _hatched(panel.axes[0])
    # an elastic map: restitution 1 everywhere, one colour and one tick, its value
    soft = impact_map(ImpactModel(ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e10),
                                  contact_law("hertz")), [0.01, 0.1], [1e-4, 1e-3], 1e-6)
    assert np.all(soft.field("restitution") == 1.0)
    fig = Figure()
    draw_map_field(fig, fig.subplots(), soft, "restitution")
    bar = fig.axes[-1]
    assert list(bar.get_yticks()) == [1.0] and bar.get_ylabel().endswith(": constant")


def test_a_lower_bound_is_shown_as_one_in_the_report_and_the_figure(tmp_path):
    """A film curve that stays below first yield bounds sigma_y from below only: the scene
    result's report writes ">=" in the parameter table, and the report's and the summary
    figure's maps say they are computed at that bound."""
    from filmscale.continuum.materials import DIAMOND
    from filmscale.workflows import pipeline as pl
    from filmscale.workflows.report import scene_figure, write_report
    from filmscale.workflows.pipeline_scene import parse_pipeline
    from tests.helpers.scenes import BASE
    E, nu, sy, R = 120e9, 0.3, 3e9, 5e-6
    law = contact_law("komvopoulos-ye-continuous")
    E_r = ElasticPlastic(E, nu, sy).reduced_modulus(DIAMOND)
    h = np.linspace(0.05, 0.8, 80) * float(law.first_yield(R, E_r, sy, nu).approach)
    P = law.contact(h, R, E_r, sy, nu).force
    (tmp_path / "film.csv").write_text(
        "h [nm], P [uN]\n" + "".join(f"{a * 1e9:.6f}, {b * 1e6:.8f}\n" for a, b in zip(h, P)))
    film = '[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"'
    text = BASE.format(R=1e-6, m=1e-12, V=1.0, t=200e-9, impactor_extra="", film=film,
                       want='["maxima", "map"]') + \
        "[map]\nvelocity = [0.1, 10.0, 4]\nradius = [1e-7, 1e-5, 3]\n"
    result = pl.run_scene(parse_pipeline(text, "b.toml", tmp_path), tmp_path / "store",
                          tmp_path / "b.h5")
    (cal,) = result.calibrations().values()
    assert cal.sigma_y.lower_bound and cal.sigma_y.value <= sy
    html = write_report(result.path).read_text()
    assert f"<td>&gt;= {cal.sigma_y.value / 1e9:.4g} GPa</td>" in html     # table: eng units
    assert (f"Map computed with film&#x27;s sigma_y at its lower bound (&gt;= "
            f"{cal.sigma_y.value / 1e9:.3g} GPa)") in html
    titles = [ax.get_title() for ax in scene_figure(result.path).axes]
    assert any(f">= {cal.sigma_y.value / 1e9:.3g} GPa" in t for t in titles)
    assert any(f"sigma_y >= {cal.sigma_y.value / 1e9:.4g} GPa" in t for t in titles)
