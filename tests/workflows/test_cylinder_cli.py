"""Scene `shape = "cylinder"` and `filmscale impact` on it: keys checked at load, the maxima
of the line-contact model, and a one-line refusal where only spheres are modelled."""

import json

import pytest

from filmscale.continuum.contact.cylinder import CylinderImpactModel
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.workflows.cli import main
from filmscale.workflows.scene import parse_scene

SCENE = """
[impactor]
shape = "cylinder"
radius = 1e-3
length = 5e-3
mass = 1e-3
velocity = 5.0

[target.substrate]
name = "steel"
E = 200e9
nu = 0.3
sigma_y = 1e9
"""
STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9, name="steel")


def _impact(tmp_path, capsys, text, *args):
    scene = tmp_path / "cylinder.toml"
    scene.write_text(text)
    code = main(["impact", str(scene), *args])
    return code, capsys.readouterr()


def test_cylinder_scene_builds_the_line_contact_model():
    scene = parse_scene(SCENE)
    model = scene.cylinder_model()
    assert isinstance(model, CylinderImpactModel)
    assert model.length == 5e-3 and model.datum_depth == 5e-3      # default d = L
    with pytest.raises(InputError, match="sphere impactors only"):
        scene.model()
    datum = parse_scene(SCENE.replace("length = 5e-3", "length = 5e-3\ndatum_depth = 0.02"))
    assert datum.cylinder_model().datum_depth == 0.02


@pytest.mark.parametrize("old, new, match", [
    ("length = 5e-3\n", "", r"impactor.length is missing"),
    ("length = 5e-3", "length = -1", r"impactor.length = -1 m is outside"),
    ("length = 5e-3", "length = 5e-3\ndatum_depth = 0", r"impactor.datum_depth = 0 m"),
    ("mass = 1e-3", "mass = 1e-12", r"impactor.mass = 1e-12 kg is lighter than a cylinder"),
    ("shape = \"cylinder\"", "shape = \"sphere\"", r"impactor.length applies to shape"),
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


def test_sphere_only_options_are_refused(tmp_path, capsys):
    code, out = _impact(tmp_path, capsys, SCENE, "--history", str(tmp_path / "h.csv"))
    assert code == 2 and "--history applies to sphere impactors" in out.err
    scene = tmp_path / "cylinder.toml"
    code = main(["impact-map", str(scene), "--velocity", "1:2:2", "--radius", "1e-3:2e-3:2",
                 "--out", str(tmp_path / "map.h5")])
    out = capsys.readouterr()
    assert code == 2 and "sphere impactors only" in out.err
