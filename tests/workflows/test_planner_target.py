"""The planner's target (rule 3) under `model.target` and a zero tolerance, the standard
deviation where the calibrated layer is left out, `SceneResult.open`, and the sweeps' warning
about swept keys that change nothing the plans keep. Oracles: the substrate-alone and layered
models evaluated directly (the change the plan states), the plan rule 3 makes without the key,
and results of scenes that differ only in the swept key."""

import json
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.continuum import ImpactModel
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.workflows.cli import main
from filmscale.workflows.pipeline import SceneResult, run_scene
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.plan import Plan, chosen_model, plan_scene
from filmscale.workflows.sweep import load_sweep, run_sweep, unused_keys
from tests.helpers.curves import sphere_curve_file
from tests.helpers.scenes import BASE, CURVES_FILM, MINIMAL, scene

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "sweep_corner.toml"
#: a thin film under a large sphere: rule 3 models the substrate alone at a 5 % tolerance
THIN = dict(t=4e-9, R=10e-6)
#: a thick stiff film under a small sphere: rule 3 models the films
THICK = dict(t=200e-9, R=1e-6, m=1e-12, V=1.0)


def _with(text_scene, model="", tolerance=None):
    """The pipeline scene ``text_scene`` (BASE text) with a [model] table and tolerance."""
    text = text_scene + (f"[model]\n{model}\n" if model else "")
    if tolerance is not None:
        text = text.replace("tolerance = 0.05", f"tolerance = {tolerance}")
    return parse_pipeline(text)


def _text(t, R, m=1.6e-6, V=0.2, film='E = 200e9\nsigma_y = 8e9', want='["maxima"]'):
    return BASE.format(R=R, m=m, V=V, t=t, film=film, want=want, impactor_extra="")


def _target(plan):
    return next(s for s in plan.steps if s.name == "target")


def _change(sc):
    """The films' change of the maxima at the scene's point, from the models directly."""
    full = sc.model().maxima(sc.impactor.velocity, sc.impactor.radius, sc.impactor.mass)
    bare = ImpactModel(sc.stack.substrate, sc.law).maxima(
        sc.impactor.velocity, sc.impactor.radius, sc.impactor.mass)
    return max(abs(float(bare.delta_max / full.delta_max) - 1),
               abs(float(bare.force_max / full.force_max) - 1))


def test_model_target_is_a_checked_key_read_by_the_scene():
    assert scene().completed({}).model_target == "auto"
    assert _with(_text(**THIN), 'target = "layered"').completed({}).model_target == "layered"
    with pytest.raises(InputError, match=r"model.target = 'films' is not one of: auto, "
                                         r"layered, substrate"):
        _with(_text(**THIN), 'target = "films"')


def test_forced_layered_keeps_films_that_rule_3_leaves_out_and_states_their_change():
    auto = plan_scene(scene(**THIN))
    assert auto.decisions["target"] == "substrate" and auto.decisions["model_target"] == "auto"
    pipe = _with(_text(**THIN), 'target = "layered"')
    plan = plan_scene(pipe)
    step = _target(plan)
    assert plan.decisions["target"] == "layered" and plan.decisions["model_target"] == "layered"
    assert step.model.startswith("layered profile")
    assert step.reason.startswith('forced by model.target = "layered"')
    assert "rule 3 would leave them out" in step.reason
    change = _change(pipe.completed({}))
    assert f"{change:.2%} at most" in step.reason
    assert plan.decisions["films_change"] == pytest.approx(change, rel=1e-9)
    assert step.error.startswith("the weighting's own")     # the Gao weighting's error


def test_forced_substrate_leaves_out_films_that_rule_3_keeps_with_their_change_as_error():
    assert plan_scene(scene(**THICK)).decisions["target"] == "layered"
    pipe = _with(_text(**THICK), 'target = "substrate"')
    plan = plan_scene(pipe)
    step = _target(plan)
    assert plan.decisions["target"] == "substrate"
    assert step.reason.startswith('forced by model.target = "substrate"')
    assert "rule 3 would keep them" in step.reason
    change = _change(pipe.completed({}))
    assert change > 0.05
    assert step.error == f"{change:.2%} from the films left out"


def test_a_zero_tolerance_keeps_the_films_whenever_they_change_anything():
    zero = _with(_text(**THIN), tolerance=0)
    assert zero.tolerance == 0.0
    plan = plan_scene(zero)
    assert plan.decisions["target"] == "layered" and plan.decisions["films_change"] > 0
    assert "above the tolerance 0%" in _target(plan).reason
    with pytest.raises(InputError, match="outputs.tolerance"):
        _with(_text(**THIN), tolerance=-0.01)


def test_a_zero_tolerance_makes_rule_6_name_every_measured_md_setting():
    """Rule 6 reads the tolerance on the film's E: 0 asks for an ensemble (one run's E
    carries 2.2 %) and finds no cheaper setting within it."""
    pipe = _with(_text(**THIN, film='[target.layers.calibrate]\nmd = "quick"'), tolerance=0)
    (step,) = [s for s in plan_scene(pipe).steps if s.name.startswith("calibrate")]
    assert any("ask for an ensemble" in a for a in step.advice)
    assert "no cheaper measured setting keeps E within the tolerance 0%" in step.advice


def test_layered_without_films_is_refused_and_a_forced_target_is_known_before_calibration():
    bare = MINIMAL + '[model]\ntarget = "layered"\n'
    with pytest.raises(InputError, match=r'model.target = "layered" keeps the films, but the '
                                         r"target has none"):
        plan_scene(parse_pipeline(bare))
    pending = _with(_text(**THIN, film='[target.layers.calibrate]\nmd = "ci"'),
                    'target = "substrate"')
    plan = plan_scene(pending)
    assert plan.decisions == {"target": "substrate", "model_target": "substrate"}
    assert _target(plan).reason == 'forced by model.target = "substrate"'
    assert plan.steps[-1].model == "chosen after calibration"


def test_a_measured_profile_without_layers_is_modelled_not_dropped():
    """A target.profile alone is the target's depth dependence: rule 3 weighs it against the
    substrate like films (it was modelled as the bare substrate before)."""
    text = MINIMAL.replace("radius = 10e-6", "radius = 1e-6").replace(
        "mass = 1.6e-6", "mass = 1e-12").replace("velocity = 0.2", "velocity = 1.0") + \
        "[target.profile]\nh_c = [1e-9, 5e-9, 20e-9, 100e-9]\n" \
        "E_r = [300e9, 250e9, 120e9, 90e9]\nH = [20e9, 15e9, 8e9, 6e9]\n"
    plan = plan_scene(parse_pipeline(text))
    assert plan.decisions["target"] == "layered"
    assert _target(plan).model.startswith("measured depth profile")


@pytest.fixture
def thin_curves_scene(tmp_path):
    """A film calibrated from film.csv (E 120 GPa), 4 nm thick under a 10 um sphere: rule 3
    leaves it out."""
    sphere_curve_file(tmp_path)
    return lambda model="": _text(**THIN, film=CURVES_FILM) + (f"[model]\n{model}\n"
                                                                if model else "")


def test_the_std_of_a_left_out_calibrated_layer_is_nan_with_its_reason(tmp_path,
                                                                       thin_curves_scene):
    result = run_scene(parse_pipeline(thin_curves_scene(), "s.toml", tmp_path),
                       tmp_path / "store", tmp_path / "r.h5")
    assert result.plan.decisions["target"] == "substrate"
    assert "not computed" in result.plan.decisions["std"]
    step = result.plan.steps[-1]
    assert step.name == "uncertainty" and "film" in step.reason
    with h5py.File(result.path, "r") as f:
        assert "point_std" not in f["impact"]
    table = result.to_dataframe()
    assert np.isnan(table.loc["delta_max", "std"])
    assert table.loc["delta_max", "std_note"].startswith("not computed: the calibrated layer")
    assert table.attrs["std_note"] == result.plan.decisions["std"]
    # the same film kept: its calibration's spread reaches the results
    kept = run_scene(parse_pipeline(thin_curves_scene('target = "layered"'), "k.toml",
                                    tmp_path), tmp_path / "store", tmp_path / "k.h5")
    assert "std" not in kept.plan.decisions
    kept_table = kept.to_dataframe()
    assert kept_table.loc["delta_max", "std"] > 0 and kept_table.loc["delta_max",
                                                                     "std_note"] == ""
    assert kept_table.loc["velocity", "std_note"] != ""
    # the map of a forced substrate: no <field>_std, and the reason in its attributes
    text = thin_curves_scene('target = "substrate"').replace(
        'want = ["maxima"]', 'want = ["maxima", "map"]') + \
        "[map]\nvelocity = [0.1, 1.0, 3]\nradius = [1e-6, 1e-5, 3]\n"
    mapped = run_scene(parse_pipeline(text, "m.toml", tmp_path), tmp_path / "store",
                       tmp_path / "m.h5")
    ds = mapped.to_xarray()
    assert "delta_max_std" not in ds and ds.attrs["std_note"] == mapped.plan.decisions["std"]


def test_a_result_file_opens_as_a_scene_result(tmp_path, thin_curves_scene):
    result = run_scene(parse_pipeline(thin_curves_scene(), "s.toml", tmp_path),
                       tmp_path / "store", tmp_path / "r.h5")
    opened = SceneResult.open(result.path)
    assert opened.path == result.path and opened.units == {}
    assert opened.plan == result.plan
    assert opened.to_dataframe().equals(result.to_dataframe())
    assert Plan.from_dict(result.plan.to_dict()) == result.plan
    (tmp_path / "not.h5").write_bytes(b"nothing")
    with pytest.raises(InputError, match="SceneResult.open expects a scene result"):
        SceneResult.open(tmp_path / "not.h5")


def _sweep_files(tmp_path, film, body):
    (tmp_path / "base.toml").write_text(_text(**THIN, film=film) + '[model]\ntarget = "auto"\n'
                                        "[contact]\nfriction = 0.0\n")
    path = tmp_path / "s.toml"
    path.write_text('base = "base.toml"\n' + body)
    return path


THICKNESS = '[axes]\n"target.layers.0.thickness" = [2e-9, 4e-9]\n'


def test_a_sweep_warns_of_a_thickness_the_plans_leave_out_and_keeps_it_when_forced(
        tmp_path, capsys):
    """Two thicknesses of a calibrated film that rule 3 leaves out: identical results, a
    warning in the index and on stderr naming the key, the cases and the way out; the same
    sweep with model.target = "layered": results that differ, no warning."""
    sphere_curve_file(tmp_path)
    sweep = _sweep_files(tmp_path, CURVES_FILM, THICKNESS)
    lines = []
    index, entries = run_sweep(*load_sweep(sweep), tmp_path / "store", tmp_path / "out", 1,
                               say=lines.append)
    (warning,) = json.loads(index.read_text())["warnings"]
    assert warning["key"] == "target.layers.0.thickness"
    assert warning["cases"] == ["s-000", "s-001"]
    assert 'model.target = "layered"' in warning["keep"]
    assert f"warning: {warning['text']}" in lines
    points = [h5py.File(e["result"], "r")["impact/point/delta_max"][()] for e in entries]
    assert points[0] == points[1]
    kept = _sweep_files(tmp_path, CURVES_FILM,
                        THICKNESS + '[[cases]]\n"model.target" = "layered"\n')
    index, entries = run_sweep(*load_sweep(kept), tmp_path / "store", tmp_path / "kept", 1,
                               say=lines.append)
    assert json.loads(index.read_text())["warnings"] == []
    points = [h5py.File(e["result"], "r")["impact/point/delta_max"][()] for e in entries]
    assert points[0] != points[1]


def test_sweep_plan_warns_on_stderr_where_the_plans_are_complete(tmp_path, capsys):
    sweep = _sweep_files(tmp_path, 'E = 200e9\nsigma_y = 8e9',
                         THICKNESS + '"contact.friction" = [0.0, 0.3]\n')
    assert main(["sweep", "plan", str(sweep)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2
    assert err[0].startswith("filmscale: warning: target.layers.0.thickness changes nothing "
                             "the plan keeps in 4 of 4 scene(s) (s-000, s-001, s-002, s-003)")
    assert "contact.friction" in err[1] and "give impactor.angle above 0" in err[1]
    # a key that the plans do keep is not reported
    name, scenes = load_sweep(_sweep_files(tmp_path, 'E = 200e9\nsigma_y = 8e9',
                                           '[axes]\n"impactor.velocity" = [0.1, 0.2]\n'))
    assert unused_keys(scenes, [plan_scene(s.scene).decisions for s in scenes]) == []


def test_the_example_sweep_keeps_the_film_so_its_results_follow_the_thickness(capsys):
    """examples/sweep_corner.toml plans (its MD calibration pending) with the film forced,
    and with the demo's calibrated Cu (E 144 GPa, sigma_y 16 GPa, its result file) each
    scene models the film and the impact point changes with the thickness."""
    name, scenes = load_sweep(EXAMPLE)
    assert len(scenes) == 6
    assert all(s.overrides["model.target"] == "layered" for s in scenes)
    assert main(["sweep", "plan", str(EXAMPLE)]) == 0
    assert "warning" not in capsys.readouterr().err
    cu = {0: ElasticPlastic(144e9, 0.34, 16e9, name="Cu film")}
    delta = {}
    for s in scenes:
        plan = plan_scene(s.scene, cu)
        assert plan.decisions["target"] == "layered" and plan.decisions["films_change"] > 0.05
        sc = s.scene.completed(cu)
        model = chosen_model(sc, plan.decisions["target"], plan.decisions["law"])
        point = model.maxima(sc.impactor.velocity, sc.impactor.radius, sc.impactor.mass)
        delta[tuple(s.overrides.values())] = float(point.delta_max)
    for V in (0.2, 0.5, 2.0):
        assert delta[("layered", V, 2.2e-9)] != delta[("layered", V, 10e-9)]
    # the example's comment: rule 3 without the map would leave the film out of five scenes
    point_only = [replace(s.scene, outputs=frozenset({"maxima"}), data={
        **s.scene.data, "model": {k: v for k, v in s.scene.data["model"].items()
                                  if k != "target"}}) for s in scenes]
    targets = [plan_scene(p, cu).decisions["target"] for p in point_only]
    assert targets == ["substrate"] * 5 + ["layered"]
