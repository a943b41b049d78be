"""The unit store as many jobs share it: one process per unit (the others wait and reuse), a
corrupted unit found by its checksums and computed again (never reused, never a traceback),
and unit hashes that cover the physics and the package's code, not the rank count or where
the store or the package lie. Oracles: a lone run of the same scene (bit-identical results),
and the first run's own values."""

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from filmscale.workflows import pipeline as pl
from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.store import code_version
from tests.helpers.curves import sphere_curve_file
from tests.helpers.results import scene_results
from tests.helpers.scenes import BASE, CURVES_FILM


def _curves_scene(tmp_path):
    sphere_curve_file(tmp_path)
    text = BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="", film=CURVES_FILM,
                       want='["maxima"]')
    return parse_pipeline(text, "s.toml", tmp_path)


@pytest.mark.parametrize("damage", ["flip a byte of fit.npz", "change E in done.json",
                                    "truncate done.json", "flip a byte of impact.npz"])
def test_a_corrupted_unit_is_set_aside_and_computed_again(tmp_path, capsys, damage):
    scene, store = _curves_scene(tmp_path), tmp_path / "store"
    first = pl.run_scene(scene, store, tmp_path / "a.h5")
    unit = next(p for p in store.glob("impact-*" if "impact" in damage else "calibration-*")
                if p.is_dir())
    if damage.startswith("flip"):
        target = unit / damage.split(" of ")[1]
        data = bytearray(target.read_bytes())
        data[len(data) // 2] ^= 0xFF
        target.write_bytes(bytes(data))
    elif damage == "change E in done.json":
        record = json.loads((unit / "done.json").read_text())
        record["E"]["value"] *= 1.01
        (unit / "done.json").write_text(json.dumps(record))
    else:
        text = (unit / "done.json").read_text()
        (unit / "done.json").write_text(text[:len(text) // 2])
    capsys.readouterr()
    second = pl.run_scene(scene, store, tmp_path / "b.h5")
    err = capsys.readouterr().err
    assert second.units[unit.name] == "ran"
    assert f"unit {unit.name} is corrupted" in err
    assert len(list(store.glob(f"{unit.name}.corrupt-*"))) == 1     # nothing deleted
    assert scene_results(second.path) == scene_results(first.path)
    # the recomputed unit is sound again: a third run reuses everything
    assert set(pl.run_scene(scene, store, tmp_path / "c.h5").units.values()) == {"reused"}


def test_the_code_version_is_the_packages_own_files():
    """Files beside the package (tests, docs, scenes) do not enter the hash; a file inside a
    subpackage does. Oracle: the digest recomputed (uncached) with a probe file placed in
    each, and removed after."""
    import filmscale
    version = code_version()
    assert version.startswith(filmscale.__version__ + "+") and version == code_version()
    root = Path(filmscale.__file__).resolve().parent
    for folder, counts in (("tests", False), ("workflows", True)):
        probe = root / folder / "_code_version_probe.txt"
        try:
            probe.write_text("probe")
            assert (code_version.__wrapped__() != version) == counts, folder
        finally:
            probe.unlink()
    assert code_version.__wrapped__() == version


MD_FILM = '[target.layers.calibrate]\nmd = "ci"\nnp = {np}'


def _md_scene_file(tmp_path, np_):
    path = tmp_path / f"scene{np_}.toml"
    path.write_text(BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
                                film=MD_FILM.format(np=np_), want='["maxima"]'))
    return path


def _run(scene, store, out):
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    return subprocess.Popen([sys.executable, "-m", "filmscale", "run", str(scene), "--store",
                             str(store), "--out", str(out)], stderr=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True, env=env)


def test_two_runs_at_once_compute_each_unit_once_and_the_store_moves(tmp_path):
    """Two `filmscale run` of one scene on one store, started together (an MD ci unit of a
    few seconds, its calibration, the impact): one computes each unit, the other waits and
    reuses it, and both results equal a lone run in another store bit for bit. The store
    then copied elsewhere and run with --np 2 instead of 1 reuses every unit."""
    scene, store = _md_scene_file(tmp_path, 1), tmp_path / "store"
    runs = [_run(scene, store, tmp_path / f"r{i}.h5") for i in range(2)]
    outputs = [p.communicate(timeout=600) for p in runs]
    assert [p.returncode for p in runs] == [0, 0], outputs
    errors = "".join(err for _, err in outputs)
    assert errors.count("filmscale: md-indent ci-cu001") == 1          # LAMMPS ran once
    assert "waiting for another process computing md-indent-" in errors
    assert len([p for p in store.glob("md-indent-*") if p.is_dir()]) == 1
    lone = _run(scene, tmp_path / "lone", tmp_path / "lone.h5")
    assert lone.communicate(timeout=600) and lone.returncode == 0
    want = scene_results(tmp_path / "lone.h5")
    for i in range(2):
        assert scene_results(tmp_path / f"r{i}.h5") == want
    moved = tmp_path / "elsewhere" / "store"
    shutil.copytree(store, moved)
    again = pl.run_scene(parse_pipeline(_md_scene_file(tmp_path, 2).read_text(), "s.toml",
                                        tmp_path), moved, tmp_path / "moved.h5")
    assert set(again.units.values()) == {"reused"}
    np.testing.assert_array_equal(scene_results(again.path), want)


def test_two_runs_of_an_ensemble_share_out_its_seeds(tmp_path):
    """seeds = 2 on the ci preset, a second `filmscale run` started once the first is inside
    its first seed: the second takes the other seed instead of waiting (each process runs
    LAMMPS once), and both results equal (each then reuses the other's unit)."""
    scene = tmp_path / "ensemble.toml"
    scene.write_text(BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
                                 film=MD_FILM.format(np=1) + "\nseeds = 2", want='["maxima"]'))
    store = tmp_path / "store"
    first = _run(scene, store, tmp_path / "a.h5")
    deadline = time.time() + 120
    while not any((p / "in.indent").exists() for p in store.glob("md-indent-*")):
        assert first.poll() is None and time.time() < deadline, "the first run ended early"
        time.sleep(0.05)
    second = _run(scene, store, tmp_path / "b.h5")
    outputs = [p.communicate(timeout=600) for p in (first, second)]
    assert [p.returncode for p in (first, second)] == [0, 0], outputs
    assert [err.count("filmscale: md-indent ci-cu001") for _, err in outputs] == [1, 1]
    assert len([p for p in store.glob("md-indent-*") if p.is_dir()]) == 2
    assert scene_results(tmp_path / "a.h5") == scene_results(tmp_path / "b.h5")


def test_a_run_unit_stored_with_its_curve_as_arrays_still_reads(tmp_path):
    """Before MD units kept indent.h5 they held curve.npz (particle units still do): such a
    unit, finished with its checksums, gives back the curve it stored."""
    from filmscale.workflows.store import finish_unit
    from filmscale.workflows.units import unit_curve
    h = np.linspace(0.0, 2e-9, 7)
    P = 1e-6 * (h / 2e-9) ** 1.5
    segment = np.array([0, 0, 0, 0, 1, 2, 2])
    np.savez(tmp_path / "curve.npz", h=h, P=P, segment=segment)
    finish_unit(tmp_path, {"indenter": "sphere:2nm"}, ("curve.npz",))
    curve = unit_curve(tmp_path)
    np.testing.assert_array_equal(curve.h, h)
    np.testing.assert_array_equal(curve.P, P)
    np.testing.assert_array_equal(curve.segment, segment)
    assert curve.indenter.R == 2e-9 and curve.meta["source"] == str(tmp_path)
