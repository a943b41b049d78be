"""Scene files: the example parses; bad input names the key, its value and the valid range."""

from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum import StackProfile
from filmscale.continuum.contact.profiles import TableProfile, UniformProfile
from filmscale.core.errors import InputError
from filmscale.workflows.scene import load_scene, parse_scene
from tests.helpers.scenes import MINIMAL

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "slider_corner_disk.toml"


def test_example_scene_builds_a_layered_model():
    scene = load_scene(EXAMPLE)
    assert scene.layered and len(scene.stack.layers) == 4
    assert scene.stack.interface_depths[-1] == pytest.approx(92e-9)
    assert isinstance(scene.model().target, StackProfile)
    assert isinstance(scene.substrate_model().target, UniformProfile)
    assert scene.impactor.material.E == 400e9
    v, r = scene.map.axes()
    assert v.size == 60 and r[0] == pytest.approx(1e-6)


def test_minimal_scene_defaults():
    scene = parse_scene(MINIMAL)
    assert not scene.layered and scene.impactor.material is None   # rigid
    assert scene.law.name == "komvopoulos-ye" and scene.unloading == "auto"


@pytest.mark.parametrize("extra, match", [
    ("\n[model]\ncontact_law = \"hertzian\"\n", r"model.contact_law = 'hertzian' is not one of"),
    ("\n[model]\nlaw = \"hertz\"\n", r"unknown key model.law \(valid keys"),
    ("\n[[target.layers]]\nname = \"DLC\"\nthickness = 0.0\nE = 2e11\nnu = 0.25\nsigma_y = 8e9\n",
     r"target.layers\[0\].thickness = 0 m is outside the valid range \(0, 1\] m"),
    ("\n[[target.layers]]\nname = \"DLC\"\nthickness = -4e-9\nE = 2e11\nnu = 0.25\nsigma_y = 8e9\n",
     r"target.layers\[0\].thickness = -4e-09 m is outside"),
    ("\n[[target.layers]]\nname = \"DLC\"\nthickness = 4e-9\nE = nan\nnu = 0.25\nsigma_y = 8e9\n",
     r"target.layers\[0\].E = nan Pa is outside"),
    ("\n[[target.layers]]\nname = \"DLC\"\nthickness = 4e-9\nnu = 0.25\nsigma_y = 8e9\n",
     r"target.layers\[0\].E is missing"),
    ("\n[[target.layers]]\nthickness = 4e-9\nE = 2e11\nnu = 0.7\nsigma_y = 8e9\n",
     r"target.layers\[0\].nu = 0.7 is outside the valid range \(-1, 0.5\)"),
    ("\n[map]\nvelocity = [0.1, 1.0]\n", r"map.velocity must be \[min, max, count\]"),
])
def test_bad_values_name_the_field(extra, match):
    with pytest.raises(InputError, match=match):
        parse_scene(MINIMAL + extra)


@pytest.mark.parametrize("old, new, match", [
    ("velocity = 0.2", "velocity = -0.2", r"impactor.velocity = -0.2 m/s is outside"),
    ("velocity = 0.2", "", r"impactor.velocity is missing"),
    ("mass = 1.6e-6", "mass = 0", r"impactor.mass = 0 kg is outside"),
    ("shape = \"sphere\"", "shape = \"cube\"", r"impactor.shape = 'cube' is not one of"),
    ("velocity = 0.2", "velocity = 0.2\nE = 4e11", r"impactor.E and impactor.nu go together"),
    ("sigma_y = 2.4e9", "sigma_y = \"hard\"", r"target.substrate.sigma_y must be a number"),
    ("radius = 10e-6", "radius = 10e-6\ncolour = \"red\"", r"unknown key impactor.colour"),
])
def test_bad_impactor_and_substrate(old, new, match):
    with pytest.raises(InputError, match=match):
        parse_scene(MINIMAL.replace(old, new))


def test_not_toml_is_an_input_error():
    with pytest.raises(InputError, match="not valid TOML"):
        parse_scene("[impactor\nradius = 1")
    with pytest.raises(InputError, match="cannot read scene"):
        load_scene("/nonexistent/scene.toml")


def test_measured_profile_inline_and_from_file(tmp_path):
    rows = np.array([[2, 180, 20], [10, 170, 16], [30, 150, 10], [60, 130, 8], [120, 100, 6]])
    inline = MINIMAL + f"""
[target.profile]
h_c = {(rows[:, 0] * 1e-9).tolist()}
E_r = {(rows[:, 1] * 1e9).tolist()}
H = {(rows[:, 2] * 1e9).tolist()}
breakpoints = [20e-9]
"""
    table = tmp_path / "profile.csv"
    table.write_text("h_c [nm], E_r [GPa], H [GPa]\n"
                     + "\n".join(", ".join(map(str, r)) for r in rows))
    from_file = MINIMAL + '\n[target.profile]\nfile = "profile.csv"\nbreakpoints = [20e-9]\n'
    a = parse_scene(inline)
    b = parse_scene(from_file, base=tmp_path)
    for scene in (a, b):
        assert isinstance(scene.profile, TableProfile) and scene.layered
        assert scene.profile.hardness_factor == scene.law.hardness_factor
        assert isinstance(scene.model().target, TableProfile)
    np.testing.assert_allclose(a.profile.hardness, b.profile.hardness, rtol=1e-12)


def test_h_star_gives_the_impact_model_a_size_effect():
    """Limit case: a substrate with a huge Nix-Gao length (1 mm: sigma_y above 400 GPa at
    every approach reached) hits like the same substrate that does not yield at this speed
    (sigma_y = 50 GPa, below E as scenes require; the impact yields below about 7 GPa), at a
    speed that yields it without h*; a bad h_star names its key."""
    sized = parse_scene(MINIMAL.replace('sigma_y = 2.4e9', 'sigma_y = 2.4e9\nh_star = 1e-3'))
    plain = parse_scene(MINIMAL)
    hard = parse_scene(MINIMAL.replace('sigma_y = 2.4e9', 'sigma_y = 50e9'))
    assert not bool(hard.substrate_model().maxima(5.0, 1e-6, 1e-12).yielded)
    V, R, m = 5.0, 1e-6, 1e-12
    assert bool(plain.substrate_model().maxima(V, R, m).yielded)
    got = sized.substrate_model().maxima(V, R, m)
    assert not bool(got.yielded)
    assert float(got.delta_max) == pytest.approx(
        float(hard.substrate_model().maxima(V, R, m).delta_max), rel=1e-9)
    with pytest.raises(InputError, match=r"target.substrate.h_star = -1"):
        parse_scene(MINIMAL.replace('sigma_y = 2.4e9', 'sigma_y = 2.4e9\nh_star = -1e-9'))
