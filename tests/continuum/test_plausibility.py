"""Physical plausibility: unit slips (moduli in GPa written as Pa, radii in um written as m,
profile depths in nm written as m, curve columns in the wrong unit) are refused with the
parameter, the value the check computed and the slip that explains it, in the Python API and
the command line alike; real values pass. Oracles are computed here, independently of the
package: the density m / (4/3 pi R^3), the power of 1000 that makes a modulus plausible, the
E_r of a synthetic curve with its columns rescaled."""

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum import DIAMOND, ElasticPlastic, ImpactModel, Layer, LayerStack
from filmscale.continuum.calibration import calibrate
from filmscale.continuum.contact.impact_map import impact_map
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_curves
from filmscale.continuum.indentation.oliver_pharr import check_curve_modulus, oliver_pharr
from filmscale.continuum.indentation.tips import parse_tip
from filmscale.core.checks import check_density, check_modulus, check_yield_strength
from filmscale.core.errors import InputError
from filmscale.workflows.scene import parse_scene
from filmscale.workflows.pipeline_scene import load_pipeline

GLASS = ElasticPlastic(E=90e9, nu=0.25, sigma_y=2.4e9, name="glass")
LAW = contact_law("hertz")
ROOT = Path(__file__).resolve().parents[2]

SCENE = """
[impactor]
radius = {R}
mass = {m}
velocity = 0.2

[target.substrate]
name = "glass"
E = {E}
nu = 0.25
sigma_y = {sy}
{extra}"""


def scene_text(R=10e-6, m=1.6e-6, E=90e9, sy=2.4e9, extra=""):
    return SCENE.format(R=R, m=m, E=E, sy=sy, extra=extra)


def one_line_input_error(excinfo) -> str:
    message = str(excinfo.value)
    assert excinfo.type is InputError and "\n" not in message
    return message


def density(R, m):
    return m / (4.0 / 3.0 * math.pi * R**3)


def meant_modulus(E):
    """The oracle of the slip: the power of 1000 that takes E into 0.1 GPa - 2 TPa, nearest
    100 GPa."""
    factors = [10.0**k for k in range(-12, 13, 3) if 1e8 <= E * 10.0**k <= 2e12]
    return min(factors, key=lambda f: abs(math.log10(E * f / 1e11))) if factors else None


# --- moduli ----------------------------------------------------------------------------------

@pytest.mark.parametrize("E, meant", [(90, "90e9 (GPa written as Pa)"),
                                      (200, "200e9 (GPa written as Pa)"),
                                      (5000, "5000e6 (MPa written as Pa)"),
                                      (70e3, "70000e6 (MPa written as Pa)"),
                                      (5e7, "5e+10 (kPa written as Pa)"),
                                      (9e12, "9e+09"), (3e12, "3e+09"), (1.2e18, "1.2e+12")])
def test_implausible_modulus_names_the_value_and_the_slip(E, meant):
    with pytest.raises(InputError) as err:
        check_modulus("target.substrate.E", E)
    message = one_line_input_error(err)
    assert message.startswith(f"target.substrate.E = {E:.6g} Pa is not a plausible modulus")
    assert message.endswith(f"did you mean target.substrate.E = {meant}?")
    assert float(meant.split()[0]) == pytest.approx(E * meant_modulus(E), rel=1e-12)


def test_a_modulus_no_slip_explains_gets_no_suggestion():
    with pytest.raises(InputError) as err:
        check_modulus("E", 1e-30)
    assert "did you mean" not in one_line_input_error(err) and meant_modulus(1e-30) is None


@pytest.mark.parametrize("E", [0.1e9, 0.3e9, 3e9, 70e9, 1141e9, 2e12])
def test_moduli_of_real_solids_pass(E):
    # LDPE-like polymers (0.1-0.3 GPa) to diamond (1141 GPa) and the 2 TPa bound itself
    assert check_modulus("E", E) == E


@pytest.mark.parametrize("sigma_y, E", [(90e9, 90e9), (2.4e12, 90e9), (1e13, 200e9)])
def test_yield_strength_at_or_above_e_is_refused(sigma_y, E):
    with pytest.raises(InputError) as err:
        check_yield_strength("film.sigma_y", sigma_y, E, "film.E")
    message = one_line_input_error(err)
    assert f"film.sigma_y = {sigma_y:.6g} Pa is not below film.E = {E:.6g} Pa" in message
    assert f"sigma_y/E of {sigma_y / E:.3g}" in message


@pytest.mark.parametrize("sigma_y", [1e6, 2.4e9, 8.9e9, 50e9, math.inf])
def test_yield_strength_below_e_passes(sigma_y):
    assert check_yield_strength("sigma_y", sigma_y, 90e9) == sigma_y


def test_yield_strains_above_a_tenth_are_a_warning_of_the_model():
    strong = ElasticPlastic(90e9, 0.25, 20e9, name="strong")
    assert any("strong sigma_y/E=0.22" in w for w in ImpactModel(strong, LAW).warnings())
    assert not any("sigma_y/E" in w for w in ImpactModel(GLASS, LAW).warnings())


@pytest.mark.parametrize("E, sigma_y, key", [(90, 1.0, "E"), (9e12, 2e9, "E"),
                                             (90e9, 90e9, "sigma_y"), (90e9, 1e13, "sigma_y")])
def test_api_and_scene_give_the_same_message(E, sigma_y, key):
    """ElasticPlastic refuses an implausible material when it is made, with the scene's
    words, its key named either way."""
    with pytest.raises(InputError) as api:
        ElasticPlastic(E, 0.25, sigma_y, name="target.substrate")
    with pytest.raises(InputError) as scene:
        parse_scene(scene_text(E=E, sy=sigma_y))
    assert one_line_input_error(api) == one_line_input_error(scene)
    assert str(api.value).startswith(f"target.substrate.{key} = ")


def test_implausible_layer_and_impactor_are_refused_by_the_model():
    """Refused when made; a fit's unchecked trial material (`ElasticPlastic._trial`) that
    reached a model would be refused at its entry with the same words."""
    with pytest.raises(InputError, match=r"^film\.E = 90 Pa .*did you mean film\.E = 90e9"):
        ElasticPlastic(90, 0.3, 1.0, name="film")
    soft = ElasticPlastic._trial(90, 0.3, 1.0, name="film")
    with pytest.raises(InputError, match=r"^film\.E = 90 Pa .*did you mean film\.E = 90e9"):
        ImpactModel(LayerStack((Layer(5e-9, soft),), GLASS), LAW)
    with pytest.raises(InputError, match=r"^slider\.E = 4e\+13 Pa .*stiffer than diamond"):
        ElasticPlastic(4e13, 0.2, name="slider")
    with pytest.raises(InputError, match=r"^slider\.E = 4e\+13 Pa .*stiffer than diamond"):
        ImpactModel(GLASS, LAW, impactor=ElasticPlastic._trial(4e13, 0.2, name="slider"))


# --- impactor density --------------------------------------------------------------------------

@pytest.mark.parametrize("R, m, meant", [
    (10.0, 1.6e-6, "10e-6 (um written as m)"),       # the slider corner
    (5.0, 1e-12, "5e-6 (um written as m)"),
    (0.05, 1e-12, "0.05e-3 (mm written as m)"),       # 1.9 kg/m^3 at 50 um: the nearest
    (1.0, 7.8e-6, "1e-3 (mm written as m)"),          # a 1 mm steel ball in mm
    (1e3, 1e-20, None),                               # no slip of the radius explains it
])
def test_a_density_lighter_than_air_is_refused_with_its_value(R, m, meant):
    with pytest.raises(InputError) as err:
        check_density(R, m, "impactor.radius", "impactor.mass")
    message = one_line_input_error(err)
    assert f"mean density m/(4/3 pi R^3) of {density(R, m):.3g} kg/m^3" in message
    assert message.startswith(f"impactor.radius = {R:.6g} m with impactor.mass = {m:.6g} kg")
    if meant:
        assert message.endswith(f"did you mean impactor.radius = {meant}?")
    else:
        assert "did you mean" not in message


@pytest.mark.parametrize("R, m", [
    (10e-6, 1.6e-6),     # slider corner (effective mass of the slider, 3.8e8 kg/m^3)
    (1e-6, 1e-12),       # the demo scene's corner
    (0.5e-3, 4.1e-6),    # a 1 mm steel ball, 7800 kg/m^3
    (20e-3, 2.7e-3),     # a ping-pong ball, 80 kg/m^3
    (1e-3, 1e-8),        # a foam bead, 2.4 kg/m^3
])
def test_real_impactors_pass(R, m):
    assert check_density(R, m) == pytest.approx(density(R, m), rel=1e-12)


@pytest.mark.parametrize("call", ["maxima", "history", "first_yield"])
def test_impact_api_refuses_the_density_at_every_entry(call):
    model = ImpactModel(GLASS, LAW)
    args = (10.0, 1.6e-6) if call == "first_yield" else (0.2, 10.0, 1.6e-6)
    with pytest.raises(InputError) as err:
        getattr(model, call)(*args)
    assert f"of {density(10.0, 1.6e-6):.3g} kg/m^3" in one_line_input_error(err)


def test_impact_arrays_name_the_first_implausible_point():
    R = np.array([1e-6, 2e-6, 30.0, 40.0])
    with pytest.raises(InputError) as err:
        ImpactModel(GLASS, LAW).maxima(0.2, R, 1.6e-6)
    message = one_line_input_error(err)
    assert message.startswith("radius = 30 m") and f"{density(30.0, 1.6e-6):.3g}" in message


def test_impact_map_over_metre_radii_is_refused():
    with pytest.raises(InputError) as err:
        impact_map(ImpactModel(GLASS, LAW), [0.1, 1.0], np.geomspace(1.0, 50.0, 3), 1.6e-6)
    # 1.6 mg on R = 1 mm is 382 kg/m^3, a plausible body: the nearest fix of the first point
    assert "did you mean radius = 1e-3 (mm written as m)?" in one_line_input_error(err)


def test_scene_refuses_impactor_and_map_densities_by_key():
    with pytest.raises(InputError) as err:
        parse_scene(scene_text(R=10))
    assert one_line_input_error(err).startswith("impactor.radius = 10 m with impactor.mass")
    with pytest.raises(InputError) as err:
        parse_scene(scene_text(extra="[map]\nvelocity = [0.01, 1.0, 3]\nradius = [1, 50, 3]\n"))
    message = one_line_input_error(err)
    assert message.startswith("map.radius maximum = 50 m with impactor.mass = 1.6e-06 kg")
    assert f"{density(50.0, 1.6e-6):.3g} kg/m^3" in message


def test_the_examples_are_plausible():
    for name in ("slider_corner_disk.toml", "demo_scene.toml"):
        text = (ROOT / "examples" / name).read_text()
        if "calibrate" in text:
            load_pipeline(ROOT / "examples" / name)
        else:
            parse_scene(text)


# --- profiles ----------------------------------------------------------------------------------

H_C = np.array([10e-9, 20e-9, 50e-9, 100e-9, 200e-9])
E_R = np.full(5, 120e9)
HARD = np.full(5, 8e9)


@pytest.mark.parametrize("scale, unit", [(1e9, "nm"), (1e6, "um")])
def test_profile_depths_in_the_wrong_unit_are_refused(scale, unit):
    with pytest.raises(InputError) as err:
        TableProfile.from_measurements(H_C * scale, E_R, HARD)
    message = one_line_input_error(err)
    deepest = H_C[-1] * scale
    assert message.startswith(f"profile table h_c reaches {deepest:.6g} m, deeper than 1 mm")
    assert f"({unit} written as m)?" in message


@pytest.mark.parametrize("E_r, H, expect", [
    (np.full(5, 120.0), HARD, "profile table E_r[0] = 120 Pa is not a plausible reduced modulus"),
    (np.full(5, 120e15), HARD, "profile table E_r[0] = 1.2e+17 Pa"),
    (E_R, np.array([8e9, 8e9, 130e9, 8e9, 8e9]), "profile table H = 1.3e+11 Pa at row 2 is "
     "not below E_r = 1.2e+11 Pa"),
    (E_R, np.full(5, 8e18), "profile table H = 8e+18 Pa at row 0"),
])
def test_profile_moduli_and_hardness_must_be_a_solids(E_r, H, expect):
    with pytest.raises(InputError) as err:
        TableProfile.from_measurements(H_C, E_r, H)
    assert one_line_input_error(err).startswith(expect)


def test_a_real_profile_passes():
    profile = TableProfile.from_measurements(H_C, E_R, HARD, breakpoints=[50e-9])
    assert profile.depths[0] == pytest.approx(10e-9)


# --- indentation curves ------------------------------------------------------------------------

BERKOVICH = parse_tip("berkovich")
SPHERE = parse_tip("sphere:5um")


def _curve(tip, E_r=100e9, H=5e9, h_c=100e-9):
    return synthetic_curve(E_r, H, tip, h_c=h_c)


def _sphere_loading():
    """The contact law's loading of E = 120 GPa, sigma_y = 3 GPa under a 5 um diamond sphere
    to 20 first-yield approaches (as the pipeline's curve file)."""
    law = contact_law("komvopoulos-ye-continuous")
    E_r = ElasticPlastic(120e9, 0.3, 3e9).reduced_modulus(DIAMOND)
    dy = float(law.first_yield(SPHERE.R, E_r, 3e9, 0.3).approach)
    h = np.linspace(0.2 * dy, 20 * dy, 120)
    return LoadDisplacementCurve(h, law.contact(h, SPHERE.R, E_r, 3e9, 0.3).force,
                                 indenter=SPHERE)


def _scaled(curve, f_h=1.0, f_P=1.0):
    return replace(curve, h=curve.h * f_h, P=curve.P * f_P, segment=None,
                   meta={"source": "slip.csv"})


@pytest.mark.parametrize("f_h, f_P, slip", [
    (1e9, 1.0, "depths in nm read as m (depths x 1e-09)"),
    (1e6, 1.0, "depths in um read as m (depths x 1e-06)"),
    (1e-9, 1.0, "depths in m read as nm (depths x 1e+09)"),
    (1.0, 1e-6, "loads in N read as uN (loads x 1e+06)"),
    (1.0, 1e9, "loads in nN read as N (loads x 1e-09)"),
])
def test_oliver_pharr_flags_a_curve_in_the_wrong_units(f_h, f_P, slip):
    """The flag states the E_r it found (the oracle: E_r scales as P/h^2 for a Berkovich
    tip, h_c with h) and the slip; the analysis still returns its numbers."""
    good = oliver_pharr(_curve(BERKOVICH), BERKOVICH)
    assert good.ok and not good.flags
    result = oliver_pharr(_scaled(_curve(BERKOVICH), f_h, f_P), BERKOVICH)
    assert result.ok and "implausible_modulus" in result.flag_codes
    assert result.E_r == pytest.approx(good.E_r * f_P / f_h**2, rel=1e-6)
    message = next(f.message for f in result.flags if f.code == "implausible_modulus")
    assert message.startswith(f"the curve implies E_r = {result.E_r:.3g} Pa (Oliver-Pharr)")
    assert slip in message and f"E_r = {good.E_r:.3g} Pa" in message


@pytest.mark.parametrize("E_r, H", [(0.3e9, 0.01e9), (3e9, 0.2e9), (100e9, 5e9),
                                    (900e9, 40e9)])
def test_curves_of_real_solids_are_not_flagged(E_r, H):
    for tip in (BERKOVICH, SPHERE):
        curve = _curve(tip, E_r, H)
        assert "implausible_modulus" not in oliver_pharr(curve, tip).flag_codes
        assert check_curve_modulus(curve, tip) is curve


@pytest.mark.parametrize("tip, f_h, f_P, slip", [
    (SPHERE, 1e9, 1.0, "depths in nm read as m"), (SPHERE, 1e-3, 1.0, "depths in m read as mm"),
    (SPHERE, 1.0, 1e-6, "loads in N read as uN"),
    (BERKOVICH, 1e9, 1.0, "depths in nm read as m"), (BERKOVICH, 1e-6, 1.0, "depths in m "
                                                      "read as um")])
def test_calibration_refuses_a_curve_in_the_wrong_units(tip, f_h, f_P, slip):
    curve = _sphere_loading() if tip is SPHERE else _curve(tip)
    calibrate(curve, nu=0.3)          # the real curve calibrates
    with pytest.raises(InputError) as err:
        calibrate(replace(_scaled(curve, f_h, f_P), indenter=tip), nu=0.3)
    message = one_line_input_error(err)
    assert message.startswith("curve 'slip.csv' refused: the curve implies E_r = ")
    assert slip in message


def _write_curve(path: Path, curve, h_unit: str, h_factor: float) -> Path:
    rows = "".join(f"{h * h_factor:.9g}, {P * 1e6:.9g}\n" for h, P in zip(curve.h, curve.P))
    path.write_text(f"h [{h_unit}], P [uN]\n" + rows)
    return path


@pytest.mark.parametrize("tip", [BERKOVICH, SPHERE])
def test_a_curve_file_whose_m_column_holds_nm_is_flagged_then_refused(tmp_path, tip):
    """The issue's case: `h [m]` holding nanometres gave E_r = 1e-7 Pa and a passing
    cross-check; now the analysis flags it and the calibration refuses it."""
    curve = _curve(tip)
    ok = read_curves(_write_curve(tmp_path / "ok.csv", curve, "nm", 1e9))["ok"]
    bad = read_curves(_write_curve(tmp_path / "bad.csv", curve, "m", 1e9))["bad"]
    assert "implausible_modulus" not in oliver_pharr(ok, tip).flag_codes
    assert "implausible_modulus" in oliver_pharr(bad, tip).flag_codes
    loading = _sphere_loading() if tip is SPHERE else curve
    _write_curve(tmp_path / "bad.csv", loading, "m", 1e9)
    with pytest.raises(InputError, match=r"bad\.csv' refused: .*depths in nm read as m"):
        calibrate(replace(read_curves(tmp_path / "bad.csv")["bad"], indenter=tip), nu=0.3)


PIPELINE = scene_text(R=1e-6, m=1e-12, extra="""
[[target.layers]]
name = "film"
thickness = 2e-6
nu = 0.3
[target.layers.calibrate]
curves = ["film.csv"]
tip = "sphere:5um"
""")


def test_a_pipeline_refuses_the_curve_before_any_work(tmp_path):
    _write_curve(tmp_path / "film.csv", _sphere_loading(), "nm", 1e9)
    (tmp_path / "scene.toml").write_text(PIPELINE)
    load_pipeline(tmp_path / "scene.toml")           # in nm, read as nm: a real curve
    _write_curve(tmp_path / "film.csv", _sphere_loading(), "m", 1e9)
    (tmp_path / "scene.toml").write_text(PIPELINE)
    with pytest.raises(InputError) as err:
        load_pipeline(tmp_path / "scene.toml")
    assert "film.csv' refused" in one_line_input_error(err)


# --- the command line: exit 2, one line, no traceback -----------------------------------------

def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "filmscale", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          stdin=subprocess.DEVNULL)


@pytest.mark.parametrize("command, text, expect", [
    ("impact", scene_text(E=90), "target.substrate.E = 90 Pa is not a plausible"),
    ("impact", scene_text(R=10), "did you mean impactor.radius = 10e-6 (um written as m)?"),
    ("impact", scene_text(sy=2.4e12), "target.substrate.sigma_y = 2.4e+12 Pa is not below"),
    ("impact-map", scene_text(extra="[map]\nvelocity = [0.01, 1.0, 3]\nradius = [1, 50, 3]\n"),
     "map.radius maximum = 50 m"),
    ("run", PIPELINE, "film.csv' refused: the curve implies E_r = "),
])
def test_cli_refuses_a_unit_slip_in_one_line(tmp_path, command, text, expect):
    _write_curve(tmp_path / "film.csv", _sphere_loading(), "m", 1e9)
    (tmp_path / "scene.toml").write_text(text)
    extra = {"impact-map": ["--out", "map.h5"], "run": ["--store", "store", "--out", "r.h5"]}
    run = _cli(command, "scene.toml", *extra.get(command, []), cwd=tmp_path)
    assert run.returncode == 2, run.stderr
    assert expect in run.stderr and "Traceback" not in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "map.h5").exists() and not (tmp_path / "r.h5").exists()


def test_cli_overrides_meet_the_same_checks(tmp_path, capsys):
    from filmscale.workflows.cli import main
    (tmp_path / "scene.toml").write_text(scene_text())
    assert main(["impact", str(tmp_path / "scene.toml"), "--radius", "10"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did you mean radius = 10e-6 (um written as m)?" in err
    assert main(["impact-map", str(tmp_path / "scene.toml"), "--velocity", "0.1:1:2",
                 "--radius", "1:50:2", "--out", str(tmp_path / "m.h5")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{density(1.0, 1.6e-6):.3g} kg/m^3" in err
    assert not (tmp_path / "m.h5").exists()
