"""`filmscale plan` and `run` on a sliding scene whose film is calibrated from curve files
(issue 34): the calibration, the slide unit, the result file, the reuse of every unit, the
refusals, sweeps of sliding scenes. The oracle is the same question asked directly:
`slide()` on the stack built by hand with the calibrated materials, and the linearised std
recomputed from two direct slides."""

import json
import math

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.laws import DEFAULT_LAW, contact_law
from filmscale.continuum.contact.slider import FIELD_NX, FIELD_NZ, Slider, slide
from filmscale.continuum.materials import DIAMOND, ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError
from filmscale.core.jsonable import dumps
from filmscale.workflows.pipeline import SceneResult, run_scene
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.result import SLIDE_RESULT_FORMAT
from tests.helpers.cli import run_main

#: the film the curves are made of (E, sigma_y; nu 0.3) and the scene's numbers
E_FILM, SY_FILM = 120e9, 3e9
NIP = ElasticPlastic(160e9, 0.3, 2.5e9, name="NiP")
THICKNESS, RADIUS, LENGTH, LOAD, MU = 200e-9, 10e-6, 10e-6, 10e-3, 0.2

EDGE = """
title = "an edge on a calibrated film"
[slider]
shape = "cylinder"
radius = "10 um"
length = "10 um"
normal_load = "{load}"
[contact]
friction = 0.2
[target.substrate]
name = "NiP"
E = "160 GPa"
nu = 0.3
sigma_y = "2.5 GPa"
[[target.layers]]
name = "film"
thickness = "200 nm"
nu = 0.3
[target.layers.calibrate]
curves = ["film.csv"]
tip = "sphere:5um"
{outputs}"""


def scene_text(load="10 mN", outputs=""):
    return EDGE.format(load=load, outputs=outputs)


@pytest.fixture
def folder(tmp_path):
    """tmp_path with film.csv: the loading of (E_FILM, SY_FILM) under a 5 um diamond sphere
    by the package's default contact law (what a sliding scene's calibration fits) to 20
    first-yield approaches, 1 % load noise; and edge.toml."""
    law = contact_law(DEFAULT_LAW)
    E_r = ElasticPlastic(E_FILM, 0.3, SY_FILM).reduced_modulus(DIAMOND)
    dy = float(law.first_yield(5e-6, E_r, SY_FILM, 0.3).approach)
    h = np.linspace(0.2 * dy, 20 * dy, 120)
    P = law.contact(h, 5e-6, E_r, SY_FILM, 0.3).force
    P = P + np.random.default_rng(2).normal(0.0, 0.01 * P.max(), h.size)
    (tmp_path / "film.csv").write_text("h [nm], P [uN]\n" + "".join(
        f"{a * 1e9:.6f}, {b * 1e6:.8f}\n" for a, b in zip(h, P)))
    (tmp_path / "edge.toml").write_text(scene_text())
    return tmp_path


def by_hand(E, sigma_y, load=LOAD):
    """`slide()` on the stack built by hand: the film of (E, sigma_y) on NiP."""
    film = ElasticPlastic(E, 0.3, sigma_y, name="film")
    stack = LayerStack((Layer(THICKNESS, film),), NIP)
    return slide(stack, Slider("cylinder", RADIUS, LENGTH), load, MU)


def test_a_sliding_scene_runs_on_its_calibrated_film_and_reuses_every_unit(folder,
                                                                          monkeypatch):
    import filmscale.md.run as md_run

    def no_lammps(*args, **kwargs):
        raise AssertionError("LAMMPS launched for curve files")
    monkeypatch.setattr(md_run, "run_input", no_lammps)
    pipeline = parse_pipeline(scene_text(), "edge.toml", folder)
    assert pipeline.sliding and pipeline.outputs == {"stresses"}
    first = run_scene(pipeline, folder / "store", folder / "r.h5")
    assert sorted(k.split("-")[0] for k in first.units) == ["calibration", "slide"]
    assert set(first.units.values()) == {"ran"}
    with h5py.File(first.path, "r") as f:
        assert f.attrs["format"] == SLIDE_RESULT_FORMAT and "filmscale_version" in f.attrs
        assert "std_note" not in f.attrs
        assert f["scene"][()].decode() == scene_text()
        plan = json.loads(f.attrs["plan"])
        assert plan["decisions"]["sliding"] and plan["decisions"]["dimension"] == "2-D"
        cal = f["calibration/0"]
        E, E_std = cal.attrs["E"], cal.attrs["E_std"]
        sy, sy_std = cal.attrs["sigma_y"], cal.attrs["sigma_y_std"]
        rho = json.loads(cal.attrs["calibration"])["correlation"]
        assert abs(E - E_FILM) < 3 * E_std and E_std < 0.1 * E        # within its std
        assert abs(sy - SY_FILM) < 3 * sy_std
        assert json.loads(cal.attrs["cross_check"])[0]["passed"]
        g = f["slide"]
        stored = json.loads(g.attrs["result"])
        arrays = {k: g[k][()] for k in g if isinstance(g[k], h5py.Dataset)}
        units = {k: g[k].attrs["units"] for k in arrays}
        field = {k: g["field"][k][()] for k in ("x", "z", "layer", "von_mises")}
    # the oracle: the same slide asked directly of the stack with the calibrated film
    direct = by_hand(E, sy)
    assert stored == json.loads(dumps(direct.to_dict()))           # bit for bit
    for j, row in enumerate(direct.layers):
        for key in ("von_mises_max", "x", "z", "tensile_max"):
            assert arrays[key][j] == pytest.approx(getattr(row, key), rel=1e-12)
    assert arrays["yield_ratio"][0] == pytest.approx(direct.layers[0].yield_ratio, rel=1e-12)
    assert math.isnan(arrays["interface_shear_max"][1])        # the substrate has none
    assert units["von_mises_max"] == "Pa" and units["yield_ratio"] == "1" and \
        units["x"] == "m" and units["p0_std"] == "Pa"
    rows = FIELD_NZ + 3 * FIELD_NZ                      # the film's, then the substrate's
    assert field["von_mises"].shape == (rows, FIELD_NX)
    assert field["x"].shape == (FIELD_NX,) and field["z"].shape == (rows,)
    assert list(np.bincount(field["layer"])) == [FIELD_NZ, 3 * FIELD_NZ]
    # the refined maximum is at least the grid's
    for j in (0, 1):
        assert field["von_mises"][field["layer"] == j].max() <= \
            arrays["von_mises_max"][j] * (1 + 1e-12)
    # the film's yield ratio std, linearised by hand: d_E from a direct slide at E + std,
    # d_sigma from the ratio at sigma_y + std, combined with the calibration's correlation
    ratio = direct.layers[0].yield_ratio
    d_E = by_hand(E + E_std, sy).layers[0].yield_ratio - ratio
    d_s = direct.layers[0].von_mises_max / (sy + sy_std) - ratio
    expected = math.sqrt(d_E**2 + d_s**2 + 2 * rho * d_E * d_s)
    assert arrays["yield_ratio_std"][0] == pytest.approx(expected, rel=1e-9)
    assert 0 < expected < 0.2 * ratio
    # the notebook's view: one row per layer, value and std
    table = SceneResult.open(first.path).to_dataframe()
    assert list(table.index) == ["film", "NiP"]
    assert table.loc["film", "yield_ratio_std"] == pytest.approx(expected, rel=1e-9)
    again = run_scene(parse_pipeline(scene_text(), "edge.toml", folder), folder / "store",
                      folder / "r2.h5")
    assert again.units.keys() == first.units.keys()
    assert set(again.units.values()) == {"reused"}
    with h5py.File(first.path, "r") as a, h5py.File(again.path, "r") as b:
        for key in ("slide/yield_ratio", "slide/yield_ratio_std", "slide/field/von_mises",
                    "calibration/0/curve_0/P"):
            np.testing.assert_array_equal(a[key][()], b[key][()])


def test_plan_prints_the_sliding_model(folder, capsys):
    code, out, err = run_main(["plan", str(folder / "edge.toml")], capsys)
    assert code == 0, err
    assert "calibrate film: curves from film.csv" in out
    assert "2-D plane strain (cylinder), layered target (1 layer(s) on the substrate)" in out
    assert f"{FIELD_NX} x {FIELD_NZ} points (x by depth) per film" in out
    assert "after calibration" in out and "uncertainty" in out
    sphere = (scene_text().replace('shape = "cylinder"', 'shape = "sphere"')
              .replace('length = "10 um"\n', ""))
    sphere = sphere[:sphere.index("[[target.layers]]")]       # bare NiP: nothing to calibrate
    (folder / "bump.toml").write_text(sphere)
    code, out, err = run_main(["plan", str(folder / "bump.toml")], capsys)
    assert code == 0, err
    assert "3-D (sphere), homogeneous target: Hertz" in out
    assert "after calibration" not in out and "uncertainty" not in out      # timed, no std


@pytest.mark.parametrize("outputs, message", [
    ('[outputs]\nwant = ["maxima"]\n',
     r"outputs.want\[0\] = 'maxima' is an impact output; a sliding scene \(\[slider\]\) "
     "computes stresses"),
    ('[outputs]\nwant = ["stresses", "map"]\n', r"outputs.want\[1\] = 'map' is an impact"),
    ('[outputs]\nwant = ["everything"]\n', r"outputs.want\[0\].*stresses")])
def test_impact_outputs_are_refused_with_the_choices(folder, outputs, message):
    with pytest.raises(InputError, match=message):
        parse_pipeline(scene_text(outputs=outputs), "edge.toml", folder)


@pytest.mark.parametrize("old, new, message", [
    ("nu = 0.3\n[target.layers.calibrate]", "[target.layers.calibrate]",
     r"target.layers\[0\].nu"),                         # a calibration takes the layer's nu
    ('radius = "10 um"', 'radius = "10 um"\nvelocity = 1.0', "slider.velocity"),
    ("friction = 0.2", "friction = -1", "contact.friction"),
    ('curves = ["film.csv"]', 'curves = ["absent.csv"]', "absent.csv")])
def test_every_key_is_checked_before_any_work(folder, old, new, message):
    with pytest.raises(InputError, match=message):
        parse_pipeline(scene_text().replace(old, new), "edge.toml", folder)


def test_run_prints_the_table_and_report_refuses_a_sliding_result(folder, capsys):
    scene, out = str(folder / "edge.toml"), str(folder / "r.h5")
    code, stdout, err = run_main(["run", scene, "--store", str(folder / "st"), "--out", out,
                                  "--report"], capsys)
    assert code == 2 and err.count("\n") == 1 and "--report" in err
    code, stdout, err = run_main(["run", scene, "--store", str(folder / "st"), "--out", out],
                                 capsys)
    assert code == 0, err
    assert stdout.splitlines()[-1] == out
    film = next(line for line in stdout.splitlines() if line.startswith("film"))
    assert "±" in film and "first yield:" in stdout
    code, stdout, err = run_main(["report", out], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "sliding scene's result" in err and "slide group" in err


def test_a_sweep_of_sliding_scenes_runs_each_load_on_one_calibration(folder, capsys):
    (folder / "sweep.toml").write_text('base = "edge.toml"\nname = "loads"\n[axes]\n'
                                       '"slider.normal_load" = ["5 mN", "20 mN"]\n')
    code, out, err = run_main(["sweep", "run", str(folder / "sweep.toml"), "--store",
                               str(folder / "st"), "--out-dir", str(folder / "o"), "--jobs",
                               "1"], capsys)
    assert code == 0, err
    assert "warning" not in err          # the load counts: it is in every slide unit's hash
    index = json.loads((folder / "o" / "loads.json").read_text())
    assert [s["state"] for s in index["scenes"]] == ["done", "done"]
    calibrations = {k for s in index["scenes"] for k in s["units"] if k.startswith("cal")}
    assert len(calibrations) == 1        # one calibration unit, shared
    for s, load in zip(index["scenes"], (5e-3, 20e-3)):
        with h5py.File(s["result"], "r") as f:
            E, sy = f["calibration/0"].attrs["E"], f["calibration/0"].attrs["sigma_y"]
            stored = json.loads(f["slide"].attrs["result"])
        assert stored["normal_load"] == load
        assert stored["p0"] == pytest.approx(by_hand(E, sy, load).contact.p0, rel=1e-12)


def test_a_pipeline_sliding_scene_takes_its_friction_from_a_scratch_record(tmp_path):
    """[contact] friction_from: the plan's and the run's friction are the record's mean."""
    from filmscale.workflows.pipeline_scene import parse_pipeline
    with h5py.File(tmp_path / "scratch.h5", "w") as f:
        f.attrs["format"] = "filmscale.md_scratch/1"
        a = f.create_group("analysis")
        a.attrs["friction_mean"], a.attrs["friction_std"], a.attrs["steady_points"] = \
            0.31, 0.05, 90
    text = """
[slider]
shape = "cylinder"
radius = 1e-5
length = 1e-5
normal_load = 1e-2
[contact]
friction_from = "scratch.h5"
[target.substrate]
name = "NiP"
E = 160e9
nu = 0.3
sigma_y = 2.5e9
"""
    pipeline = parse_pipeline(text, str(tmp_path / "s.toml"), tmp_path)
    assert pipeline.friction == 0.31
    scene = pipeline.slide_scene({})
    assert scene.friction == 0.31 and scene.friction_source["std"] == 0.05
    with pytest.raises(InputError, match="contact.friction_from"):
        parse_pipeline(text.replace("scratch.h5", "none.h5"), str(tmp_path / "s.toml"),
                       tmp_path)
