"""The scene pipeline: the planner's rules on scenes built to trigger each, and a scene run
end to end on the MD ci preset (interrupted, resumed, then reused without LAMMPS)."""

import h5py
import numpy as np
import pytest

from filmscale.continuum import ImpactModel, contact_law
from filmscale.continuum.errors import InputError
from filmscale.workflows import pipeline as pl
from filmscale.workflows.report import write_report

BASE = """
[impactor]
radius = {R}
mass = {m}
velocity = {V}
{impactor_extra}
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
[[target.layers]]
name = "film"
thickness = {t}
nu = 0.3
{film}
[outputs]
want = {want}
tolerance = 0.05
"""


def scene(R=10e-6, m=1.6e-6, V=0.2, t=4e-9, film='E = 200e9\nsigma_y = 8e9',
          want='["maxima"]', impactor_extra=""):
    return pl.parse_pipeline(BASE.format(R=R, m=m, V=V, t=t, film=film, want=want,
                                         impactor_extra=impactor_extra))


def names(plan):
    return [(s.name, s.model) for s in plan.steps]


def test_thin_film_under_a_large_sphere_is_left_out_with_its_error():
    plan = pl.plan_scene(scene(t=4e-9, R=10e-6))
    target = [s for s in plan.steps if s.name == "target"][0]
    assert target.model.startswith("substrate alone")
    change = float(target.error.split("%")[0]) / 100
    # the reported error is the real change: recompute it with the continuum model
    sc = scene(t=4e-9, R=10e-6).completed({})
    law = sc.law
    full = sc.model().maxima(0.2, 10e-6, 1.6e-6)
    bare = ImpactModel(sc.stack.substrate, law).maxima(0.2, 10e-6, 1.6e-6)
    assert change == pytest.approx(max(abs(float(bare.delta_max / full.delta_max) - 1),
                                       abs(float(bare.force_max / full.force_max) - 1)),
                                   abs=1e-4)
    assert change < 0.05


def test_thick_stiff_film_under_a_small_sphere_is_modelled():
    plan = pl.plan_scene(scene(t=200e-9, R=1e-6, m=1e-12, V=1.0))
    assert ("target", "layered profile (Gao weighting, physics.md s. 7)") in names(plan)
    assert plan.decisions["target"] == "layered"


def test_hertz_where_nothing_yields_and_the_law_where_it_does():
    slow = pl.plan_scene(scene(V=1e-3))
    assert slow.decisions["law"] == "hertz"
    fast = pl.plan_scene(scene(V=1.0))
    assert fast.decisions["law"] == "komvopoulos-ye"
    # independent check of the rule: the law itself says whether the point yields
    sc = scene().completed({})
    for V, plan in ((1e-3, slow), (1.0, fast)):
        yielded = bool(ImpactModel(sc.stack.substrate, sc.law).maxima(V, 10e-6,
                                                                      1.6e-6).yielded)
        assert yielded == (plan.decisions["law"] != "hertz")


def test_histories_take_the_time_path_and_maps_the_fast_path():
    plan = pl.plan_scene(scene(want='["maxima", "history"]'))
    assert plan.decisions["path"] == "time"
    assert any(s.model == "time integration (histories)" for s in plan.steps)
    assert pl.plan_scene(scene()).decisions["path"] == "fast"


@pytest.mark.parametrize("extra, want", [("friction = 0.5", '["maxima"]'),
                                         ("angle = 30.0", '["maxima"]'),
                                         ("", '["maxima", "tangential"]')])
def test_oblique_or_frictional_questions_are_refused(extra, want):
    with pytest.raises(InputError, match="normal impact only"):
        pl.plan_scene(scene(impactor_extra=extra, want=want))


def test_md_only_for_layers_whose_parameters_are_missing():
    given = scene(film='E = 200e9\nsigma_y = 8e9\n[target.layers.calibrate]\nmd = "ci"')
    assert given.calibrations == ()
    missing = scene(film='[target.layers.calibrate]\nmd = "ci"')
    plan = pl.plan_scene(missing)
    assert plan.steps[0].name == "calibrate film" and "MD indentation (ci" in \
        plan.steps[0].model
    assert plan.steps[-1].model == "chosen after calibration"
    with pytest.raises(InputError, match="outputs.want"):
        scene(want='["everything"]')
    with pytest.raises(InputError, match="nonexistent"):
        scene(film='[target.layers.calibrate]\nmd = "nonexistent"')


def test_scene_runs_resumes_after_an_interruption_and_reuses_every_unit(tmp_path,
                                                                         monkeypatch):
    """MD ci preset -> calibration -> impact map. The first run is interrupted before the
    impact unit; the second resumes (MD and calibration reused); the third launches no
    LAMMPS and gives the same file contents. The impact point is checked against the
    continuum model evaluated directly with the calibrated material."""
    text = BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-9, impactor_extra="",
                       film='[target.layers.calibrate]\nmd = "ci"',
                       want='["maxima", "map"]') + \
        "[map]\nvelocity = [0.1, 10.0, 4]\nradius = [1e-7, 1e-5, 4]\n"
    sc = pl.parse_pipeline(text, "test.toml", tmp_path)
    store, out = tmp_path / "store", tmp_path / "result.h5"
    real = pl._impact_evaluation

    def interrupted(*args):
        raise KeyboardInterrupt
    monkeypatch.setattr(pl, "_impact_evaluation", interrupted)
    with pytest.raises(KeyboardInterrupt):
        pl.run_scene(sc, store, out)
    assert not out.exists()
    monkeypatch.setattr(pl, "_impact_evaluation", real)
    second = pl.run_scene(sc, store, out)
    assert sorted(second.units.values()) == ["ran", "reused", "reused"]

    def no_lammps(*args, **kwargs):
        raise AssertionError("LAMMPS launched on a rerun")
    import filmscale.md.run as md_run
    monkeypatch.setattr(md_run, "run_input", no_lammps)
    out3 = tmp_path / "again.h5"
    third = pl.run_scene(sc, store, out3)
    assert set(third.units.values()) == {"reused"}
    with h5py.File(out, "r") as a, h5py.File(out3, "r") as b:
        for key in ("impact/point/delta_max", "impact/map/restitution", "calibration/0/P"):
            np.testing.assert_array_equal(a[key][()], b[key][()])
        E = a["calibration/0"].attrs["E"]
        assert 50e9 < E < 300e9                        # Cu: E about 110-150 GPa
        assert a.attrs["format"] == pl.RESULT_FORMAT
        assert "lammps_version" in a.attrs["md_0"] and "potential_sha256" in a.attrs["md_0"]
        cal = pl.parse_pipeline(text, "test.toml", tmp_path)
        mat = {0: pl.ElasticPlastic(E, 0.3, a["calibration/0"].attrs["sigma_y"])}
        scene_done = cal.completed(mat)
        model = (ImpactModel(scene_done.stack.substrate, contact_law(second.plan.decisions[
            "law"])) if second.plan.decisions["target"] == "substrate" else
            ImpactModel(scene_done.model().target, contact_law(second.plan.decisions["law"])))
        direct = model.maxima(1.0, 1e-6, 1e-12)
        assert a["impact/point/delta_max"][()] == pytest.approx(float(direct.delta_max),
                                                               rel=1e-9)
    report = write_report(out)
    assert "<h2>Plan</h2>" in report.read_text() and "data:image/png" in report.read_text()
