"""A model kind is one `register` call away from every command: a throw-away flat punch
(tests/helpers/flat_punch.py, oracle: its closed-form linear-spring impact written there)
becomes available to `filmscale impact`, `impact-map`, the scene parser, `run` and the report
without editing any of them. And the cylinder (a slider edge) runs under `filmscale run` and
`sweep run` with a calibrated film, its map equal to `filmscale impact-map` on the same
completed scene."""

import json

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.kinds import register, unregister
from filmscale.workflows.cli import main
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.result import read_impact_maps
from filmscale.workflows.scene import parse_scene
from tests.helpers.curves import sphere_curve_file
from tests.helpers.flat_punch import FLAT_PUNCH, punch_closed_form, punch_map_reference
from tests.helpers.scenes import CYLINDER_CALIBRATED, MINIMAL

#: MINIMAL's glass hit by a flat punch of radius 2 um, 1 ng, at 0.5 m/s, with a map
PUNCH = (MINIMAL.replace('shape = "sphere"', 'shape = "flat-punch"')
         .replace("radius = 10e-6", "radius = 2e-6").replace("mass = 1.6e-6", "mass = 1e-9")
         .replace("velocity = 0.2", "velocity = 0.5")
         + "\n[map]\nvelocity = [0.1, 1.0, 3]\nradius = [1e-6, 4e-6, 2]\n")
E_STAR = 90e9 / (1 - 0.25 ** 2)


@pytest.fixture
def punch():
    register(FLAT_PUNCH)
    yield FLAT_PUNCH
    unregister(FLAT_PUNCH.name)


def test_the_scene_parser_knows_a_registered_shape(punch):
    scene = parse_scene(PUNCH)
    assert scene.kind is punch and scene.model().E_star == pytest.approx(E_STAR)
    with pytest.raises(Exception, match="impactor.length applies to cylinder impactors only"):
        parse_scene(PUNCH.replace("velocity = 0.5", "velocity = 0.5\nlength = 1e-3"))


def test_impact_gives_the_closed_form(punch, tmp_path, capsys):
    path = tmp_path / "punch.toml"
    path.write_text(PUNCH)
    assert main(["impact", str(path), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    for key, value in punch_closed_form(0.5, 2e-6, 1e-9, E_STAR).items():
        assert got[key] == pytest.approx(value, rel=1e-12)
    assert main(["impact", str(path), "--history", str(tmp_path / "h.csv")]) == 2
    assert "flat-punch model has no time history" in capsys.readouterr().err


def test_impact_map_writes_and_plots_the_closed_form(punch, tmp_path, capsys):
    path = tmp_path / "punch.toml"
    path.write_text(PUNCH)
    out, png = tmp_path / "map.h5", tmp_path / "map.png"
    assert main(["impact-map", str(path), "--out", str(out), "--plot", str(png), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    fields, attrs = read_impact_maps(out)
    ref = punch_map_reference(np.geomspace(0.1, 1.0, 3), np.geomspace(1e-6, 4e-6, 2), 1e-9,
                              E_STAR)
    assert attrs["shape"] == "flat-punch" and list(fields) == ["homogeneous"]
    for key, value in ref.items():
        np.testing.assert_allclose(fields["homogeneous"][key], value, rtol=1e-12)
    assert summary["homogeneous"]["force_max"] == pytest.approx(ref["force_max"].max())
    assert png.stat().st_size > 10_000


def test_run_and_report_a_flat_punch_scene(punch, tmp_path, capsys):
    scene = tmp_path / "punch.toml"
    scene.write_text(PUNCH + '\n[outputs]\nwant = ["maxima", "map"]\n')
    result, report = tmp_path / "r.h5", tmp_path / "r.html"
    assert main(["run", str(scene), "--store", str(tmp_path / "store"), "--out",
                 str(result)]) == 0, capsys.readouterr().err
    with h5py.File(result, "r") as f:
        assert f["impact/point/delta_max"][()] == pytest.approx(
            punch_closed_form(0.5, 2e-6, 1e-9, E_STAR)["delta_max"], rel=1e-12)
        assert f["impact/map"].attrs["kind"] == "flat-punch"
        plan = json.loads(f.attrs["plan"])
    assert plan["decisions"]["kind"] == "flat-punch"
    assert main(["report", str(result), "--out", str(report)]) == 0, capsys.readouterr().err
    assert "<img" in report.read_text()


CYLINDER = CYLINDER_CALIBRATED


def _completed_scene_text(result) -> str:
    """The cylinder scene with the film's calibrated E and sigma_y written in."""
    with h5py.File(result, "r") as f:
        g = f["calibration/0"]
        E, sy = float(g.attrs["E"]), float(g.attrs["sigma_y"])
    return (CYLINDER.split("[target.layers.calibrate]")[0]
            + f"E = {E!r}\nsigma_y = {sy!r}\n\n[map]" + CYLINDER.split("[map]")[1]
            ).split("[outputs]")[0]


def test_a_cylinder_scene_runs_calibrates_reports_and_equals_impact_map(tmp_path, capsys):
    E, sy = sphere_curve_file(tmp_path)
    scene = tmp_path / "edge.toml"
    scene.write_text(CYLINDER)
    plan = parse_pipeline(CYLINDER, "edge.toml", tmp_path)
    assert plan.calibrations and plan.map_spec().radius == (5e-4, 1e-3, 2)
    result = tmp_path / "edge.h5"
    assert main(["run", str(scene), "--store", str(tmp_path / "store"), "--out",
                 str(result)]) == 0, capsys.readouterr().err
    with h5py.File(result, "r") as f:
        decisions = json.loads(f.attrs["plan"])["decisions"]
        assert decisions["kind"] == "cylinder" and decisions["target"] == "layered"
        assert float(f["calibration/0"].attrs["E"]) == pytest.approx(E, rel=0.05)
        run_map = {k: f["impact/map"][k][()] for k in ("delta_max", "force_max",
                                                       "contact_half_width", "restitution")}
        point = f["impact/point/contact_half_width"][()]
    assert point > 0
    # the same completed scene through impact-map: the same numbers
    completed = tmp_path / "completed.toml"
    completed.write_text(_completed_scene_text(result))
    assert main(["impact-map", str(completed), "--out", str(tmp_path / "m.h5")]) == 0
    fields, _ = read_impact_maps(tmp_path / "m.h5")
    for key, value in run_map.items():
        np.testing.assert_array_equal(value, fields["layered"][key])
    report = tmp_path / "edge.html"
    assert main(["report", str(result), "--out", str(report)]) == 0
    assert "cylinder" in report.read_text() or "<img" in report.read_text()


def test_a_cylinder_sweep_runs(tmp_path, capsys):
    sphere_curve_file(tmp_path)
    (tmp_path / "base.toml").write_text(CYLINDER.replace('want = ["maxima", "map"]',
                                                         'want = ["maxima"]'))
    sweep = tmp_path / "s.toml"
    sweep.write_text('base = "base.toml"\n[axes]\n"impactor.velocity" = [1.0, 3.0]\n')
    assert main(["sweep", "run", str(sweep), "--store", str(tmp_path / "store"), "--out-dir",
                 str(tmp_path / "out"), "--jobs", "1"]) == 0, capsys.readouterr().err
    results = sorted((tmp_path / "out").rglob("*.h5"))
    assert len(results) == 2
    delta = []
    for path in results:
        with h5py.File(path, "r") as f:
            delta.append(f["impact/point/delta_max"][()])
            assert json.loads(f.attrs["plan"])["decisions"]["kind"] == "cylinder"
    assert delta[1] > delta[0] > 0          # faster: deeper
