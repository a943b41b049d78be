"""`filmscale impact --angle`: the oblique keys, the scene's friction, bad values exit 2."""

import json
import math

import numpy as np
import pytest

from filmscale.core.errors import InputError
from filmscale.workflows.cli import main
from filmscale.workflows.scene import parse_scene
from tests.helpers.scenes import OBLIQUE

SCENE = OBLIQUE

OBLIQUE_KEYS = ("restitution_tangential", "restitution_contact_point", "impulse_ratio",
                "rebound_angle", "spin", "regime_tangential")


def _run(tmp_path, capsys, mu, *args):
    scene = tmp_path / "oblique.toml"
    scene.write_text(SCENE.format(mu=mu))
    code = main(["impact", str(scene), *args])
    out = capsys.readouterr()
    return code, out


def test_angle_adds_the_tangential_keys_and_meets_gross_slip(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, 0.1, "--angle", "80", "--json")
    assert code == 0
    data = json.loads(out.out)
    assert all(k in data for k in OBLIQUE_KEYS)
    e_n = data["restitution"]
    # gross slip (rigid-body closed form, docs/physics.md section 5)
    assert data["restitution_tangential"] == pytest.approx(
        1 - 0.1 * (1 + e_n) / math.tan(math.radians(80)), abs=1e-6)
    assert data["regime_tangential"] == "slip"


def test_no_angle_keeps_the_normal_output(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, 0.3, "--json")
    assert code == 0
    assert not any(k in json.loads(out.out) for k in OBLIQUE_KEYS)


def test_scene_angle_and_text_summary(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.format(mu=0.3).replace("velocity = 0.1", "velocity = 0.1\nangle = 30"))
    assert main(["impact", str(scene)]) == 0
    assert "tangential regime" in capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["--angle", "90"], "--angle = 90 degrees is outside the valid range"),
    (["--angle", "-5"], "--angle = -5 degrees is outside the valid range"),
])
def test_bad_angle_exits_2_with_one_line(tmp_path, capsys, args, message):
    code, out = _run(tmp_path, capsys, 0.3, *args)
    assert code == 2
    assert message in out.err and out.err.count("\n") == 1


@pytest.mark.parametrize("change, key", [("friction = 0.3", "contact.friction"),
                                         ("velocity = 0.1", "impactor.angle")])
def test_bad_scene_keys_name_the_key(change, key):
    text = SCENE.format(mu=0.3)
    bad = {"friction = 0.3": "friction = -0.3",
           "velocity = 0.1": "velocity = 0.1\nangle = 95"}[change]
    with pytest.raises(InputError, match=key):
        parse_scene(text.replace(change, bad))


def test_pipeline_plans_and_stores_the_oblique_point(tmp_path):
    from filmscale.continuum.contact.oblique import REGIMES
    from filmscale.workflows.plan import plan_scene
    from filmscale.workflows.pipeline_scene import parse_pipeline
    from filmscale.workflows.units import impact_evaluation
    text = SCENE.format(mu=0.1).replace("velocity = 0.1", "velocity = 0.1\nangle = 80")
    pipeline = parse_pipeline(text + '[outputs]\nwant = ["maxima", "tangential"]\n')
    plan = plan_scene(pipeline)
    assert plan.decisions["direction"] == "oblique" and plan.decisions["angle"] == 80
    impact_evaluation(pipeline.completed({}), plan, tmp_path)
    with np.load(tmp_path / "impact.npz") as f:
        e_n, e_x = float(f["point__restitution"]), float(f["point__restitution_tangential"])
        assert REGIMES[int(f["point__regime_tangential"])] == "slip"
    assert e_x == pytest.approx(1 - 0.1 * (1 + e_n) / math.tan(math.radians(80)), abs=1e-6)


MAP = """
[map]
velocity = [0.05, 0.2, 3]
radius = [0.5e-3, 1e-3, 2]
"""


def test_impact_map_over_velocity_and_angle(tmp_path, capsys):
    from filmscale.workflows.result import read_impact_maps
    scene = tmp_path / "m.toml"
    scene.write_text(SCENE.format(mu=0.1) + MAP)
    out = tmp_path / "m.h5"
    assert main(["impact-map", str(scene), "--angle", "20:80:3", "--out", str(out),
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["points"] == 9
    fields, _ = read_impact_maps(out)
    f = fields["homogeneous"]
    assert f["angle"].tolist() == [20.0, 50.0, 80.0]
    assert f["restitution_tangential"].shape == (3, 3) == f["delta_max"].shape
    # the 80 degree row slides throughout: the rigid-body closed form
    e_n = f["restitution"][2]
    assert f["restitution_tangential"][2] == pytest.approx(
        1 - 0.1 * (1 + e_n) / math.tan(math.radians(80)), abs=1e-6)


def test_velocity_angle_map_plots_the_tangential_results_against_the_angle(tmp_path, capsys):
    """The (V, angle) map's plot: angle rows, e_y and the four tangential fields, one row each
    (the figure's height says how many rows were drawn), and a PNG that decodes."""
    import matplotlib.image
    scene = tmp_path / "m.toml"
    scene.write_text(SCENE.format(mu=0.1) + MAP)
    plot = tmp_path / "m.png"
    assert main(["impact-map", str(scene), "--angle", "5:80:4", "--out", str(tmp_path / "m.h5"),
                 "--plot", str(plot)]) == 0
    image = matplotlib.image.imread(plot)
    assert image.shape[0] == pytest.approx(5 * 2.9 * 110, abs=2)      # 5 rows at dpi 110
    assert image.std() > 0.05                                        # not blank


def test_velocity_angle_map_axes_and_fields():
    """`plot_impact_maps` picks angle rows, e_y plus the tangential fields, and linear colour
    scales for the signed contact-point restitution."""
    from filmscale.continuum.contact.impact import ImpactModel
    from filmscale.continuum.contact.laws import contact_law
    from filmscale.continuum.contact.oblique import oblique_map
    from filmscale.continuum.materials import ElasticPlastic
    from filmscale.workflows import plots
    steel = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e9)
    mp = oblique_map(ImpactModel(steel, contact_law("hertz")), np.array([0.05, 0.1]), 1e-3,
                     3.27e-5, np.array([2.0, 10.0, 80.0]), 0.1)
    values, label, log = plots._rows(mp)
    assert values.tolist() == [2.0, 10.0, 80.0] and label.startswith("incidence") and not log
    e_c = mp.field("restitution_contact_point")
    assert e_c.min() < 0 < e_c.max()          # reverses at small angles, slides at 80 degrees
    levels, norm, constant = plots._levels([e_c], "restitution_contact_point")
    assert levels[0] == pytest.approx(e_c.min()) and levels[-1] == pytest.approx(e_c.max())
    assert constant is None
    levels, _, constant = plots._levels([np.full((2, 2), 0.7)], "restitution_tangential")
    assert levels[-1] > levels[0] and constant == 0.7     # one colour band, named by its value


def test_impact_map_over_velocity_and_radius_at_the_scene_angle(tmp_path, capsys):
    from filmscale.workflows.result import read_impact_maps
    scene = tmp_path / "m.toml"
    scene.write_text(SCENE.format(mu=0.1).replace("velocity = 0.1", "velocity = 0.1\nangle = 80")
                     + MAP)
    out = tmp_path / "m.h5"
    assert main(["impact-map", str(scene), "--out", str(out)]) == 0
    f = read_impact_maps(out)[0]["homogeneous"]
    assert f["restitution_tangential"].shape == (2, 3) and np.all(f["angle"] == 80)


@pytest.mark.parametrize("args, message", [
    (["--angle", "10:95:3"], "--angle = 95 degrees is outside the valid range"),
    (["--angle", "10:10:1", "--plot", "x.png"], "at least 2 velocities and 2 angles"),
])
def test_bad_map_angles_exit_2(tmp_path, capsys, args, message):
    scene = tmp_path / "m.toml"
    scene.write_text(SCENE.format(mu=0.1) + MAP)
    code = main(["impact-map", str(scene), "--out", str(tmp_path / "m.h5"), *args])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1


def test_map_angle_and_radius_axes_exclude_each_other(tmp_path, capsys):
    with pytest.raises(SystemExit) as done:
        main(["impact-map", "m.toml", "--out", "m.h5", "--angle", "10:80:3", "--radius",
              "1e-3:2e-3:2"])
    assert done.value.code == 2
    assert "not allowed with argument --angle" in capsys.readouterr().err
