"""Sweeps and the store's status. Oracles: the overrides written by hand (expansion), the same
scene run alone (results), and the store's own files (status)."""

import json

import h5py
import pytest

from filmscale.core.errors import InputError
from filmscale.workflows import pipeline as pl
from filmscale.workflows.cli import main
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.sweep import expand, load_sweep, run_sweep
from tests.helpers.curves import sphere_curve_file
from tests.helpers.scenes import BASE

FILM = '[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"'


def _base(tmp_path, V=1.0):
    sphere_curve_file(tmp_path)
    text = BASE.format(R=1e-6, m=1e-12, V=V, t=2e-6, impactor_extra="", film=FILM,
                       want='["maxima"]')
    (tmp_path / "base.toml").write_text(text)
    return text


def _sweep(tmp_path, body):
    path = tmp_path / "s.toml"
    path.write_text('base = "base.toml"\n' + body)
    return path


def test_axes_make_every_combination_times_each_case():
    sets = expand({"axes": {"a.x": [1, 2], "b.y": [3, 4, 5]},
                   "cases": [{"c.z": 0}, {"c.z": 1, "a.x": 9}]})
    assert len(sets) == 2 * 2 * 3
    assert sets[0] == {"c.z": 0, "a.x": 1, "b.y": 3}
    # an axis wins over a case's value of the same key
    assert sets[6] == {"c.z": 1, "a.x": 1, "b.y": 3}
    assert expand({}) == [{}]


@pytest.mark.parametrize("body, message", [
    ('[axes]\n"impactor.speed_of_light" = [1.0]', "impactor.speed_of_light"),
    ('[axes]\n"target.layers.3.thickness" = [1e-9]', "has 1 entries; '3' is not an index"),
    ('[axes]\n"nowhere.x" = [1]', "the base scene has no nowhere"),
    ('[axes]\n"impactor.velocity" = []', "must be a non-empty list"),
    ('[axes]\n"impactor.velocity" = [-1.0]', "velocity"),
    ('cases = 3', r"cases must be an array of tables"),
    ('[axes]\n"impactor.velocity" = [' + ", ".join(["1.0"] * 101) + ']\n'
     '"impactor.radius" = [' + ", ".join(["1e-6"] * 100) + ']', "more than 10000"),
])
def test_a_bad_sweep_is_refused_before_any_run(tmp_path, body, message):
    _base(tmp_path)
    with pytest.raises(InputError, match=message):
        load_sweep(_sweep(tmp_path, body))


def test_a_sweep_runs_its_scenes_on_one_store_and_each_equals_its_lone_run(tmp_path, capsys):
    """Two velocities, two scenes at once: the calibration (shared) is computed once, and
    each scene's maxima equal those of the same scene run alone in another store."""
    _base(tmp_path)
    name, scenes = load_sweep(_sweep(tmp_path, '[axes]\n"impactor.velocity" = [0.5, 2.0]'))
    assert name == "s" and [s.overrides for s in scenes] == [{"impactor.velocity": 0.5},
                                                               {"impactor.velocity": 2.0}]
    index, entries = run_sweep(name, scenes, tmp_path / "store", tmp_path / "out", jobs=2)
    assert [e["state"] for e in entries] == ["done", "done"]
    written = json.loads(index.read_text())
    assert written["scenes"][1]["overrides"] == {"impactor.velocity": 2.0}
    assert written["warnings"] == []            # the velocity reaches every plan's model
    assert written["scenes"][1]["decisions"]["target"] == "layered"
    calibrations = [u for e in entries for u, how in e["units"].items()
                    if u.startswith("calibration-") and how == "ran"]
    assert len(calibrations) == 1
    for V, entry in zip((0.5, 2.0), entries):
        (tmp_path / f"alone{V}").mkdir()
        alone = pl.run_scene(parse_pipeline(_base(tmp_path / f"alone{V}", V), "a.toml",
                                            tmp_path / f"alone{V}"),
                             tmp_path / f"alone{V}" / "store", tmp_path / f"alone{V}.h5")
        with h5py.File(entry["result"], "r") as f, h5py.File(alone.path, "r") as g:
            assert f["impact/point/delta_max"][()] == g["impact/point/delta_max"][()]
            assert f["impact/point/velocity"][()] == V


def test_sweep_and_status_from_the_command_line(tmp_path, capsys):
    _base(tmp_path)
    sweep = str(_sweep(tmp_path, '[axes]\n"impactor.velocity" = [0.5, 2.0]'))
    assert main(["sweep", "plan", sweep]) == 0
    out = capsys.readouterr().out
    assert "== s-000: impactor.velocity = 0.5" in out and "2 scene(s)" in out
    store = str(tmp_path / "store")
    assert main(["sweep", "run", sweep, "--store", store, "--out-dir",
                 str(tmp_path / "out"), "--jobs", "1"]) == 0
    capsys.readouterr()
    assert main(["status", store, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {r["kind"] for r in rows} == {"calibration", "impact"}
    assert all(r["state"] == "done" for r in rows)
    unit = next(r["unit"] for r in rows if r["kind"] == "calibration")
    (tmp_path / "store" / unit / "fit.npz").write_bytes(b"broken")
    assert main(["status", store]) == 0
    text = capsys.readouterr().out
    assert f"{unit}" in text and "corrupted" in text and "fit.npz is missing or changed" in text
    assert main(["sweep", "run", sweep, "--jobs", "0"]) == 2
    assert "--jobs = 0 must be at least 1" in capsys.readouterr().err
    assert main(["status", str(tmp_path / "nothing")]) == 2


def test_the_commands_a_slurm_task_runs_and_their_refusals(tmp_path, capsys):
    """`sweep run --only K` runs scene K alone with its own index; `sweep run-unit` names its
    range (this sweep has no run unit: curves only); `cancel` of a store nothing was submitted
    to, and `sweep submit` where no sbatch exists, are refused in one line."""
    import shutil
    _base(tmp_path)
    sweep = str(_sweep(tmp_path, '[axes]\n"impactor.velocity" = [0.5, 2.0]'))
    out = tmp_path / "out"
    assert main(["sweep", "run", sweep, "--store", str(tmp_path / "store"), "--out-dir",
                 str(out), "--only", "1"]) == 0
    assert json.loads((out / "s-001.json").read_text())["scenes"][0]["state"] == "done"
    assert not (out / "s-000.h5").exists() and (out / "s-001.h5").exists()
    capsys.readouterr()
    assert main(["sweep", "run", sweep, "--only", "2"]) == 2
    assert "--only = 2 must be a scene index in [0, 1]" in capsys.readouterr().err
    assert main(["sweep", "run-unit", sweep, "--unit", "0"]) == 2
    assert "the sweep has 0 run unit(s)" in capsys.readouterr().err
    assert main(["cancel", str(tmp_path / "store")]) == 2
    assert "nothing was submitted there" in capsys.readouterr().err
    if shutil.which("sbatch") is None:
        assert main(["sweep", "submit", sweep, "--store", str(tmp_path / "s2")]) == 1
        assert "sbatch is not on PATH" in capsys.readouterr().err
