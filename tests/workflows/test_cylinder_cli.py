"""Scene `shape = "cylinder"` and `filmscale impact` on it: keys checked at load, the maxima
of the line-contact model, and a one-line refusal where only spheres are modelled."""

import json

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.cylinder import CylinderImpactModel
from filmscale.continuum.contact.impact_map import CYLINDER_UNITS
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.workflows.cli import main

HISTORY_HEADER = ("time [s], delta [m], velocity [m/s], force [N], contact_radius [m], "
                  "mean_pressure [Pa], phase, branch")
#: a line contact has a half-width, not a radius
CYLINDER_HISTORY_HEADER = HISTORY_HEADER.replace("contact_radius", "contact_half_width")
from filmscale.workflows.result import read_impact_maps
from filmscale.workflows.scene import parse_scene
from tests.helpers.scenes import CYLINDER_ON_STEEL

SCENE = CYLINDER_ON_STEEL
STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9, name="steel")


def _impact(tmp_path, capsys, text, *args):
    scene = tmp_path / "cylinder.toml"
    scene.write_text(text)
    code = main(["impact", str(scene), *args])
    return code, capsys.readouterr()


def test_cylinder_scene_builds_the_line_contact_model():
    scene = parse_scene(SCENE)
    model = scene.model()
    assert scene.kind.name == "cylinder" and isinstance(model, CylinderImpactModel)
    assert model.length == 5e-3 and model.datum_depth == 5e-3      # default d = L
    datum = parse_scene(SCENE.replace("length = 5e-3", "length = 5e-3\ndatum_depth = 0.02"))
    assert datum.model().datum_depth == 0.02


@pytest.mark.parametrize("old, new, match", [
    ("length = 5e-3\n", "", r"impactor.length is missing"),
    ("length = 5e-3", "length = -1", r"impactor.length = -1 m is outside"),
    ("length = 5e-3", "length = 5e-3\ndatum_depth = 0", r"impactor.datum_depth = 0 m"),
    ("mass = 1e-3", "mass = 1e-12", r"impactor.mass = 1e-12 kg is lighter than a cylinder"),
    ("shape = \"cylinder\"", "shape = \"sphere\"", r"impactor.length applies to cylinder impactors only"),
    ("velocity = 5.0", "velocity = 5.0\nangle = 30", r"impactor.angle applies to sphere"),
    ("sigma_y = 1e9", "sigma_y = 1e9\n[model]\ncontact_law = \"hertz\"",
     r"model.contact_law applies to sphere impactors"),
])
def test_cylinder_keys_are_checked_at_load(old, new, match):
    with pytest.raises(InputError, match=match):
        parse_scene(SCENE.replace(old, new))


def test_impact_json_gives_the_cylinder_maxima(tmp_path, capsys):
    code, out = _impact(tmp_path, capsys, SCENE, "--json")
    assert code == 0
    data = json.loads(out.out)
    ref = CylinderImpactModel(STEEL, 5e-3).maxima(5.0, 1e-3, 1e-3)
    assert data["shape"] == "cylinder"
    for key in ("delta_max", "force_max", "restitution", "residual_depth", "contact_time",
                "contact_half_width"):
        assert data[key] == pytest.approx(getattr(ref, key), rel=1e-12), key
    assert 0 < data["restitution"] < 1 and data["residual_depth"] > 0


def test_impact_text_and_time_path(tmp_path, capsys):
    code, out = _impact(tmp_path, capsys, SCENE, "--velocity", "0.5")
    assert code == 0 and "Impact of a cylinder" in out.out and "end effects" in out.out
    text = SCENE + "\n[model]\npath = \"time\"\nrtol = 1e-10\n"
    code, out = _impact(tmp_path, capsys, text, "--json")
    data = json.loads(out.out)
    assert data["path"] == "time-integration"
    ref = CylinderImpactModel(STEEL, 5e-3).maxima(5.0, 1e-3, 1e-3)
    assert data["delta_max"] == pytest.approx(ref.delta_max, rel=1e-7)


def test_history_csv_round_trips_and_plots(tmp_path, capsys):
    csv, png = tmp_path / "h.csv", tmp_path / "h.png"
    code, out = _impact(tmp_path, capsys, SCENE, "--json", "--history", str(csv), "--plot",
                        str(png))
    assert code == 0, out.err
    assert csv.read_text().splitlines()[0] == CYLINDER_HISTORY_HEADER
    assert "contact_half_width [m]" in CYLINDER_HISTORY_HEADER
    assert png.read_bytes().startswith(b"\x89PNG")
    hist = CylinderImpactModel(STEEL, 5e-3).history(5.0, 1e-3, 1e-3, rtol=1e-8)
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    columns = (hist.time, hist.delta, hist.velocity, hist.force, hist.contact_half_width,
               hist.mean_pressure, hist.phase, hist.branch)
    assert table.shape == (hist.time.size, 8)
    for k, column in enumerate(columns):      # %.17g: exact round trip
        assert np.array_equal(table[:, k], column), k
    assert json.loads(out.out)["path"] == "time-integration"
    # a sphere's history and a cylinder's replace each other without --force
    csv.write_text(HISTORY_HEADER + "\n0,0,0,0,0,0,1,0\n")
    code, out = _impact(tmp_path, capsys, SCENE, "--history", str(csv))
    assert code == 0 and csv.read_text().startswith(CYLINDER_HISTORY_HEADER)
    csv.write_text("something else\n")
    code, out = _impact(tmp_path, capsys, SCENE, "--history", str(csv))
    assert code == 2 and "--force" in out.err


def test_sphere_only_options_are_refused(tmp_path, capsys):
    code, out = _impact(tmp_path, capsys, SCENE, "--angle", "30")
    assert code == 2 and "--angle applies to sphere impactors" in out.err
    assert len(out.err.strip().splitlines()) == 1


def test_impact_map_of_a_cylinder_scene(tmp_path, capsys):
    scene = tmp_path / "cylinder.toml"
    scene.write_text(SCENE.replace("[target.substrate]", "[[target.layers]]\nname = \"film\"\n"
                                   "thickness = 30e-6\nE = 120e9\nnu = 0.25\nsigma_y = 0.8e9\n\n"
                                   "[target.substrate]"))
    out_h5, png = tmp_path / "map.h5", tmp_path / "map.png"
    code = main(["impact-map", str(scene), "--velocity", "0.5:8:3", "--radius", "5e-4:1e-3:2",
                 "--out", str(out_h5), "--plot", str(png), "--json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    summary = json.loads(out.out)
    assert summary["points"] == 6 and "contact_half_width" in summary["homogeneous"]
    assert "steel only: 3/6 impacts" in out.err    # progress after each radius
    assert png.read_bytes().startswith(b"\x89PNG")
    fields, attrs = read_impact_maps(out_h5)
    assert attrs["shape"] == "cylinder" and attrs["length"] == 5e-3
    assert attrs["length_units"] == "m" and attrs["mass"] == 1e-3
    assert set(fields) == {"layered", "homogeneous"}
    with h5py.File(out_h5) as f:
        assert f["layered/velocity"].shape == (3,) and f["layered/radius"].shape == (2,)
        for name, unit in {**CYLINDER_UNITS, "status": "1", "regime": "1"}.items():
            assert f["layered"][name].shape == (2, 3), name
            assert f["layered"][name].attrs["units"] == unit, name
        assert "contact_radius_max" not in f["layered"]
    layered = parse_scene(scene.read_text(), base=tmp_path).model()
    for label, model in (("layered", layered), ("homogeneous", CylinderImpactModel(STEEL, 5e-3))):
        assert fields[label]["regime_names"] == ["elastic", "contained plastic", "fully plastic"]
        assert fields[label]["model"]["shape"] == "cylinder"
        ref = model.maxima(fields[label]["velocity"][2], fields[label]["radius"][1], 1e-3)
        assert fields[label]["delta_max"][1, 2] == ref.delta_max
        assert fields[label]["contact_half_width"][1, 2] == ref.contact_half_width


def test_impact_map_refuses_angle_for_cylinders(tmp_path, capsys):
    scene = tmp_path / "cylinder.toml"
    scene.write_text(SCENE)
    code = main(["impact-map", str(scene), "--velocity", "1:2:2", "--angle", "0:30:2",
                 "--out", str(tmp_path / "map.h5")])
    err = capsys.readouterr().err
    assert code == 2 and "--angle applies to sphere impactors" in err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "map.h5").exists()
