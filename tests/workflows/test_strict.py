"""`--strict` of `filmscale calibrate` and `filmscale run`: exit status 1 when the cross-scale
check fails or a requested parameter is not identified, 0 otherwise; without it, 0 either way.
The curves are made by the contact law (or Dao's forward functions) with known parameters, so
whether the check can pass and whether the data bound sigma_y are known beforehand; and the
JSON of `filmscale calibrate --json` with its keys and types."""

import json

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.workflows.cli import main
from tests.helpers import curves as tc
from tests.helpers.curves import write_curves
from tests.helpers.scenes import BASE

E, NU, SY, R = 120e9, 0.3, 3e9, 5e-6
LAW = contact_law("komvopoulos-ye-continuous")
E_R = ElasticPlastic(E, NU, SY).reduced_modulus(DIAMOND)
DY = float(LAW.first_yield(R, E_R, SY, NU).approach)     # first-yield approach


def _sphere_file(path, depth, noise=0.01, seed=2):
    """The law's loading of E = 120 GPa, sigma_y = 3 GPa under a 5 um diamond sphere to
    ``depth`` with ``noise`` (of the largest load) Gaussian load noise, as a text table."""
    h = np.linspace(depth / 120, depth, 120)
    P = LAW.contact(h, R, E_R, SY, NU).force
    P = P + np.random.default_rng(seed).normal(0.0, noise * P.max(), h.size)
    path.write_text("h [nm], P [uN]\n"
                    + "".join(f"{a * 1e9:.6f}, {b * 1e6:.8f}\n" for a, b in zip(h, P)))
    return str(path)


def _call(capsys, *args):
    status = main(["calibrate", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_a_check_within_the_noise_and_identified_parameters_exit_0(tmp_path, capsys):
    """20 first-yield approaches with 1 % noise: E and sigma_y identified, the misfit is the
    noise (1 %), so a 3 % tolerance passes."""
    path = _sphere_file(tmp_path / "ok.csv", 20 * DY)
    common = [path, "--tip", "sphere:5um", "--tolerance", "0.03"]
    status, out, err = _call(capsys, *common, "--strict")
    assert status == 0 and "strict" not in err
    assert "cross-scale check passed" in out


def test_a_tolerance_below_the_noise_fails_strict_only(tmp_path, capsys):
    """The same curve against 0.2 %: the 1 % noise cannot be fitted away, the check fails;
    --strict exits 1 with the rms and tolerance on one stderr line, without it 0."""
    path = _sphere_file(tmp_path / "noisy.csv", 20 * DY)
    common = [path, "--tip", "sphere:5um", "--tolerance", "0.002"]
    status, out, err = _call(capsys, *common)
    assert status == 0 and "cross-scale check FAILED" in out and "strict" not in err
    status, out, err = _call(capsys, *common, "--strict")
    assert status == 1 and "cross-scale check FAILED" in out      # results still printed
    lines = [line for line in err.splitlines() if line.startswith("filmscale: strict: ")]
    assert lines == ["filmscale: strict: cross-scale check failed (rms 1.0% > tolerance 0.2%)"]


def test_an_elastic_curve_leaves_sigma_y_unidentified(tmp_path, capsys):
    """Loading to half the first-yield approach is Hertzian: the check passes but nothing
    bounds sigma_y from above, so --strict exits 1 naming sigma_y and the reason."""
    path = _sphere_file(tmp_path / "elastic.csv", 0.5 * DY, noise=0.002)
    status, out, err = _call(capsys, path, "--tip", "sphere:5um", "--tolerance", "0.03",
                             "--strict", "--json")
    assert status == 1
    d = json.loads(out)
    assert d["passed"] and d["sigma_y_identified"] is False and d["E_identified"] is True
    lines = [line for line in err.splitlines() if line.startswith("filmscale: strict: ")]
    assert len(lines) == 1 and lines[0].startswith("filmscale: strict: sigma_y not identified: ")
    assert lines[0].endswith(d["sigma_y_reason"]) and d["sigma_y_reason"]


def test_json_keys_and_types(tmp_path, capsys):
    path = _sphere_file(tmp_path / "ok.csv", 20 * DY)
    status, out, _ = _call(capsys, path, "--tip", "sphere:5um", "--tolerance", "0.03",
                           "--json")
    assert status == 0
    d = json.loads(out)
    # the keys of earlier versions stay
    old = {"E", "E_std", "E_identified", "sigma_y", "sigma_y_std", "sigma_y_identified", "n",
           "n_std", "h_star", "nu", "route", "model", "cross_check_rms",
           "cross_check_tolerance", "passed", "cross_check_noise", "cross_check_excluded",
           "cross_check_lacks", "points", "warnings"}
    assert old <= set(d)
    for key in ("E", "E_std", "sigma_y", "sigma_y_std", "nu", "cross_check_rms",
                "cross_check_tolerance"):
        assert isinstance(d[key], float), key
    for key in ("E_identified", "sigma_y_identified", "n_identified", "h_star_identified",
                "passed"):
        assert isinstance(d[key], bool), key
    for key in ("E_reason", "sigma_y_reason", "h_star_reason"):
        assert isinstance(d[key], str), key
    assert d["E_identified"] and d["sigma_y_identified"] and d["E_reason"] == ""
    assert d["n"] is None and d["n_identified"] is False
    # a sphere fits no depth law: h* null, not identified, and why
    assert d["h_star"] is None and d["h_star_std"] is None and not d["h_star_identified"]
    assert "depth law" in d["h_star_reason"]
    check = d["check"]
    assert {"passed", "rms", "worst", "tolerance", "noise", "basis", "excluded",
            "lacks"} <= set(check)
    assert check["passed"] is True and check["rms"] == d["cross_check_rms"]
    assert isinstance(check["worst"], float) and check["worst"] >= check["rms"]
    assert check["tolerance"] == pytest.approx(0.03) and check["basis"] == "stated"
    # measured curves: today's defaults
    inputs = d["inputs"]
    assert inputs["tip_material"] == "diamond" and inputs["tip_material_from"] == "default"
    assert inputs["film_thickness"] is None and inputs["substrate"] is None
    assert inputs["from"] == "default"
    assert abs(d["E"] - E) < 3 * d["E_std"]


def test_sharp_curves_at_one_depth_try_no_depth_law(tmp_path, capsys):
    _, curve = tc.synthetic_sharp_curve(70.1e9, 0.33, 0.5e9, 0.122, 1e-6)
    status, out, _ = _call(capsys, write_curves(tmp_path / "berk.h5", [curve]), "--nu", "0.33",
                           "--json")
    d = json.loads(out)
    assert status == 0 and d["route"] == "sharp"
    assert d["h_star"] is None and not d["h_star_identified"]
    assert "one depth" in d["h_star_reason"]


def test_sharp_curves_of_one_material_at_three_depths_identify_no_h_star(tmp_path, capsys):
    """Dao's forward curves of one depth-independent material at 0.5, 1 and 2 um: the
    size-effect fit is tried and finds no h*, so --strict exits 1 naming h_star."""
    curves = [tc.synthetic_sharp_curve(70.1e9, 0.33, 0.5e9, 0.122, h)[1]
              for h in (0.5e-6, 1e-6, 2e-6)]
    path = write_curves(tmp_path / "depths.h5", curves)
    status, out, err = _call(capsys, path, "--nu", "0.33", "--json", "--strict")
    d = json.loads(out)
    assert d["route"] == "sharp" and not d["h_star_identified"] and d["h_star_reason"]
    assert status == 1
    assert any(line.startswith("filmscale: strict: h_star not identified: ")
               for line in err.splitlines())


def _scene_text(tolerance: float) -> str:
    """The pipeline tests' scene with its film calibrated from film.csv at ``tolerance``."""
    film = (f'[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"\n'
            f"tolerance = {tolerance}")
    return BASE.format(R=1e-6, m=1e-12, V=1.0, t=200e-9, impactor_extra="", film=film,
                       want='["maxima"]') + \
        '[model]\ncontact_law = "komvopoulos-ye-continuous"\n'


@pytest.mark.parametrize("tolerance, status", [(0.03, 0), (0.002, 1)])
def test_run_strict_exits_1_on_a_failed_layer_check_after_writing(tmp_path, capsys,
                                                                  tolerance, status):
    """A scene whose layer is calibrated from the 1 %-noise curve: --strict exits 0 when the
    layer's check tolerates the noise (3 %), 1 when it does not (0.2 %); the result file is
    written either way and holds the failed check."""
    _sphere_file(tmp_path / "film.csv", 20 * DY)
    scene = tmp_path / "scene.toml"
    scene.write_text(_scene_text(tolerance))
    out = tmp_path / "r.h5"
    got = main(["run", str(scene), "--store", str(tmp_path / "store"), "--out", str(out),
                "--strict"])
    err = capsys.readouterr().err
    assert got == status and out.is_file()
    with h5py.File(out, "r") as f:
        (check,) = json.loads(f["calibration/0"].attrs["cross_check"])
    assert check["passed"] == (status == 0)
    strict = [line for line in err.splitlines() if line.startswith("filmscale: strict: ")]
    if status:
        assert strict == ["filmscale: strict: layer film: cross-scale check failed (rms 1.0% "
                          "> tolerance 0.2%)"]
    else:
        assert strict == []
    # without --strict the same run exits 0 (every unit reused)
    assert main(["run", str(scene), "--store", str(tmp_path / "store"), "--out", str(out),
                 "--force"]) == 0
