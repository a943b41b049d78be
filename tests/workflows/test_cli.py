"""The command line: JSON keys, exit status, HDF5 content, plots, atomic writes."""

import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.continuum import ElasticPlastic, elastic_impact
from filmscale.core.files import atomic_h5
from filmscale.workflows.cli import main
from filmscale.workflows.result import read_impact_maps
from tests.helpers.scenes import HERTZ_SCENE

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "slider_corner_disk.toml"
FILMSCALE = Path(sys.executable).with_name("filmscale")

KEYS = ("delta_max", "force_max", "mean_pressure_max", "contact_radius_max", "contact_time",
        "residual_depth", "restitution", "yielded", "regime")


def test_impact_json_has_the_promised_keys_and_meets_hertz(tmp_path, capsys):
    scene = tmp_path / "hertz.toml"
    scene.write_text(HERTZ_SCENE)
    assert main(["impact", str(scene), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(KEYS) <= set(out)
    e_star = ElasticPlastic(E=90e9, nu=0.25).reduced_modulus(ElasticPlastic(E=400e9, nu=0.23))
    ref = elastic_impact(1.6e-6, 10e-6, 0.05, e_star)
    assert out["delta_max"] == pytest.approx(float(ref.delta_max), rel=1e-9)
    assert out["contact_time"] == pytest.approx(float(ref.contact_time), rel=1e-9)
    # 0.05 m/s is above the first-yield velocity (0.0125 m/s): Hertz stays elastic but says so
    assert out["restitution"] == 1.0 and out["yielded"] is True
    assert out["regime"] == "elastic (first yield exceeded)"


def test_overrides_and_history_output(tmp_path, capsys):
    csv = tmp_path / "hist.csv"
    png = tmp_path / "hist.png"
    assert main(["impact", str(EXAMPLE), "--velocity", "0.05", "--radius", "5e-6", "--json",
                 "--history", str(csv), "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["velocity"] == 0.05 and out["radius"] == 5e-6
    assert out["path"] == "time-integration"
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data[:, 3].max() == pytest.approx(out["force_max"], rel=1e-6)
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("args, message", [
    (["--velocity", "-1"], "--velocity = -1 m/s is outside the valid range"),
    (["--velocity", "0"], "--velocity = 0 m/s is outside the valid range"),
    (["--radius", "nan"], "--radius = nan m is outside the valid range"),
])
def test_bad_command_line_values_exit_2_with_one_line(args, message, capsys):
    assert main(["impact", str(EXAMPLE), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_real_entry_point_bad_scene_exits_2_without_traceback(tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text(HERTZ_SCENE.replace('"hertz"', '"hertzian"'))
    done = subprocess.run([str(FILMSCALE), "impact", str(scene)], capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)
    assert done.returncode == 2
    assert done.stderr.startswith("filmscale: error: model.contact_law = 'hertzian'")
    assert "Traceback" not in done.stderr and done.stdout == ""


def test_approach_beyond_radius_exits_1_naming_the_point(capsys):
    assert main(["impact", str(EXAMPLE), "--velocity", "50", "--radius", "1e-8"]) == 1
    err = capsys.readouterr().err
    assert "V = 50 m/s, R = 1e-08 m" in err and "Traceback" not in err


def test_impact_map_writes_si_hdf5_with_provenance_and_a_plot(tmp_path, capsys):
    out, png = tmp_path / "map.h5", tmp_path / "map.png"
    assert main(["impact-map", str(EXAMPLE), "--velocity", "0.001:1:12", "--radius",
                 "1e-7:1e-4:10", "--out", str(out), "--plot", str(png), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["points"] == 120 and summary["layered"]["out_of_range"] > 0
    fields, attrs = read_impact_maps(out)
    assert set(fields) == {"layered", "homogeneous"}
    assert attrs["filmscale_version"] and "slider_corner_disk" in attrs["scene_source"]
    head = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                          cwd=Path(__file__).parent).stdout.strip()
    assert attrs["source_revision"].startswith(head)
    assert "[target.substrate]" in attrs["scene"]
    with h5py.File(out) as f:
        assert f["layered/delta_max"].attrs["units"] == "m"
        assert f["layered/mean_pressure_max"].attrs["units"] == "Pa"
        assert f["layered/velocity"].attrs["units"] == "m/s"
        assert f["layered/velocity"].shape == (12,)
        assert f["layered/delta_max"].shape == (10, 12)
        status = f["layered/status"][()]
        delta = f["layered/delta_max"][()]
    assert np.all(np.isnan(delta[status == 1])) and np.all(np.isfinite(delta[status != 1]))
    # the file holds exactly what the library computes (store round trip, no oracle needed)
    from filmscale.workflows.scene import load_scene
    scene = load_scene(EXAMPLE)
    ref = scene.substrate_model().maxima(fields["homogeneous"]["velocity"][None, :],
                                         fields["homogeneous"]["radius"][:, None],
                                         scene.impactor.mass)
    np.testing.assert_array_equal(fields["homogeneous"]["delta_max"], ref.delta_max)
    assert png.stat().st_size > 50_000


def test_impact_map_bad_range_exits_2(tmp_path, capsys):
    assert main(["impact-map", str(EXAMPLE), "--velocity", "1:0.1:10", "--radius",
                 "1e-6:1e-5:5", "--out", str(tmp_path / "m.h5")]) == 2
    assert "velocity maximum 0.1 is below its minimum 1" in capsys.readouterr().err
    assert not (tmp_path / "m.h5").exists()


def test_interrupted_write_leaves_nothing_and_keeps_the_old_file(tmp_path):
    target = tmp_path / "result.h5"
    with atomic_h5(target) as f:
        f.create_dataset("x", data=[1.0])
    with pytest.raises(KeyboardInterrupt):
        with atomic_h5(target) as f:
            f.create_dataset("x", data=[2.0])
            raise KeyboardInterrupt
    with h5py.File(target) as f:
        assert f["x"][0] == 1.0
    assert [p.name for p in tmp_path.iterdir()] == ["result.h5"]
    mask = os.umask(0)
    os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~mask     # not mkstemp's private 0600


def _scene_with(tmp_path, extra: str) -> str:
    path = tmp_path / "scene.toml"
    path.write_text(HERTZ_SCENE + extra)
    return str(path)


@pytest.mark.parametrize("argv, message", [
    (["impact-map", "{scene}", "--velocity", "1e-3:1e300:5", "--radius", "1e-6:1e-5:5",
      "--out", "{tmp}/m.h5"], "--velocity maximum = 1e+300 m/s is outside the valid range"),
    (["impact-map", "{scene}", "--velocity", "1:1:1", "--radius", "1e-6:1e-5:3",
      "--out", "{tmp}/m.h5", "--plot", "{tmp}/m.png"], "at least 2 velocities and 2 radii"),
    (["impact-map", "{scene}", "--velocity", "0.1:1:3", "--radius", "1e-6:1e-5:3",
      "--out", "{tmp}"], "is a folder"),
    (["impact-map", "{scene}", "--velocity", "0.1:1:3", "--radius", "1e-6:1e-5:3",
      "--out", "{scene}/x.h5"], "is a file, not a folder"),
    (["impact", "{scene}", "--plot", "{tmp}/h.txt"], "the file name must end in one of"),
    (["impact", "{scene}", "--mass", "1e9"], "--mass = 1e+09 kg is outside the valid range"),
])
def test_bad_paths_and_ranges_exit_2_before_any_work(tmp_path, capsys, argv, message):
    scene = _scene_with(tmp_path, "")
    argv = [a.format(scene=scene, tmp=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not list(tmp_path.glob("*.h5")) and not list(tmp_path.glob("*.png"))


@pytest.mark.parametrize("extra, message", [
    ('\n[map]\nvelocity = [0.001, "a", 60]\n', "map.velocity maximum must be a number, got 'a'"),
    ("\n[map]\nvelocity = [0.001, 2.0, [60]]\nradius = [1e-6, 1e-5, 4]\n",
     "map.velocity count = [60] must be an integer"),
    ('\n[target.profile]\nh_c = [1e-9, "a"]\nE_r = [1e11, 1e11]\nH = [1e10, 1e10]\n',
     "target.profile.h_c[1] must be a number, got 'a'"),
    ('\n[target.profile]\nh_c = "abc"\nE_r = [1e11]\nH = [1e10]\n',
     "target.profile.h_c must be a list of numbers"),
])
def test_bad_scene_arrays_exit_2(tmp_path, capsys, extra, message):
    assert main(["impact-map", _scene_with(tmp_path, extra), "--out", str(tmp_path / "m.h5")]) == 2
    assert message in capsys.readouterr().err


def test_string_numbers_and_non_utf8_scenes_are_refused(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(HERTZ_SCENE.replace("E = 90e9", 'E = "90e9"'))
    assert main(["impact", str(scene)]) == 2
    assert "target.substrate.E must be a number, got '90e9'" in capsys.readouterr().err
    scene.write_bytes(b"\xff\xfe not text")
    assert main(["impact", str(scene)]) == 2
    assert "is not UTF-8 text" in capsys.readouterr().err


def test_json_output_is_strict_json_with_null_for_missing_values(tmp_path, capsys):
    # every point beyond the model's range: the maxima are null, not NaN
    assert main(["impact-map", str(EXAMPLE), "--velocity", "100:200:3", "--radius",
                 "1e-8:2e-8:3", "--out", str(tmp_path / "m.h5"), "--json"]) == 0
    text = capsys.readouterr().out
    summary = json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    assert summary["layered"]["delta_max"] is None
    assert summary["layered"]["out_of_range"] == 9


def test_version_option_prints_the_package_version(capsys):
    from filmscale import __version__
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.strip() == f"filmscale {__version__}"
    done = subprocess.run([sys.executable, "-m", "filmscale", "--version"], capture_output=True,
                          text=True)
    assert done.returncode == 0 and done.stdout.strip() == f"filmscale {__version__}"


def test_each_error_kind_exits_with_its_code_in_one_line(monkeypatch, capsys, tmp_path):
    """InputError 2, ModelRangeError and EngineError 1, an unexpected defect 1 with one line
    and no traceback (FILMSCALE_DEBUG=1 shows it)."""
    from filmscale.core.errors import EngineError, InputError, ModelRangeError
    from filmscale.workflows import cli, impact_cli

    scene = tmp_path / "s.toml"
    scene.write_text(HERTZ_SCENE)
    for error, code in ((InputError("radius = 10 m"), 2), (ModelRangeError("delta > R"), 1),
                        (EngineError("LAMMPS: lost atoms"), 1), (ZeroDivisionError("x"), 1)):
        def fail(args, error=error):
            raise error
        monkeypatch.setattr(impact_cli, "cmd_impact", fail)
        assert cli.main(["impact", str(scene)]) == code
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err and str(error) in err
    monkeypatch.setenv("FILMSCALE_DEBUG", "1")
    with pytest.raises(ZeroDivisionError):
        cli.main(["impact", str(scene)])
