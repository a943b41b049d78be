"""`filmscale slide` and `slide-map` as a user runs them: the JSON keys the issue spells, the
per-layer table, the refusals (exit 2, one line naming the key or option), the HDF5 map's
layout (dimension scales read by xarray) and the figures. Oracles: Hertz's closed forms and
the closed-form search of `sliding.cylinder_sliding` for the numbers; the issue's text for the
names."""

import json
import math

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.sliding import cylinder_sliding
from filmscale.workflows.cli import main
from filmscale.workflows.slide_scene import parse_slide_scene
from tests.helpers.scenes import MINIMAL

NIP = """
[target.substrate]
name = "NiP"
E = "160 GPa"
nu = 0.3
sigma_y = "2.5 GPa"
"""
EDGE = """
title = "an edge"
[slider]
shape = "cylinder"
radius = "10 um"
length = "10 um"
normal_load = "10 mN"
[contact]
friction = 0.2
""" + NIP
FILM = """
[[target.layers]]
name = "DLC"
thickness = "20 nm"
E = "200 GPa"
nu = 0.25
sigma_y = "8 GPa"
"""


def _run(tmp_path, capsys, text, *args, command="slide"):
    scene = tmp_path / "slide.toml"
    scene.write_text(text)
    code = main([command, str(scene), *args])
    return code, capsys.readouterr()


def test_slide_json_has_the_issue_keys_and_hertz_numbers(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, EDGE, "--json")
    assert code == 0, out.err
    d = json.loads(out.out)
    P_line, R = 10e-3 / 10e-6, 10e-6
    E_star = 160e9 / (1 - 0.3**2)                             # rigid slider
    b = math.sqrt(4 * P_line * R / (math.pi * E_star))
    assert d["contact_radius"] == pytest.approx(b, rel=1e-12)
    assert d["p0"] == pytest.approx(2 * P_line / (math.pi * b), rel=1e-12)
    (row,) = d["layers"]
    assert set(row) >= {"name", "von_mises_max", "x", "z", "yield_ratio", "tensile_max",
                        "interface_shear_max"}
    ref = cylinder_sliding(10e-3, 10e-6, R, 160e9, 0.3, 0.2, 2.5e9)
    assert row["von_mises_max"] == pytest.approx(ref.vm_max, rel=1e-5)
    assert d["first_yield"]["layer"] == "NiP"
    assert set(d["first_yield"]) >= {"layer", "x", "z"}
    assert d["shakedown"]["modelled"]


def test_load_and_friction_options_override_the_scene(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, EDGE, "--json", "--load", "40 mN", "--friction", "0")
    d = json.loads(out.out)
    assert code == 0 and d["normal_load"] == pytest.approx(0.04) and d["friction"] == 0.0
    assert d["surface_tensile_max"] == pytest.approx(0.0, abs=1e-6 * d["p0"])


def test_slide_table_and_plot(tmp_path, capsys):
    png = tmp_path / "field.png"
    code, out = _run(tmp_path, capsys, EDGE + FILM, "--plot", str(png))
    assert code == 0, out.err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for word in ("DLC", "NiP", "first yield:", "contact half-width b", "shakedown: the "
                 "shakedown of a layered target"):
        assert word in out.out


@pytest.mark.parametrize("old, new, match", [
    ('length = "10 um"\n', "", "slider.length is missing"),
    ('shape = "cylinder"', 'shape = "sphere"', "slider.length applies to other slider shapes"),
    ('shape = "cylinder"', 'shape = "cone"', "slider.shape"),
    ('normal_load = "10 mN"', 'normal_load = "10 um"', "slider.normal_load"),
    ('normal_load = "10 mN"', "normal_load = -1", "slider.normal_load = -1"),
    ("friction = 0.2", "friction = -0.2", "contact.friction"),
    ("friction = 0.2", "friction = 0.2\nangle = 3", "contact.angle"),
    ('radius = "10 um"', 'radius = "10 um"\nE = "400 GPa"', "slider.E and slider.nu"),
    ("[slider]", "[impactor]\nradius = 1e-5\nmass = 1e-6\nvelocity = 0.1\n[slider]",
     "has an \\[impactor\\]"),
    ('sigma_y = "2.5 GPa"', 'sigma_y = "2.5 GPa"\nh_star = 1e-9', "h_star"),
])
def test_bad_scenes_exit_2_with_one_line(tmp_path, capsys, old, new, match):
    code, out = _run(tmp_path, capsys, EDGE.replace(old, new))
    assert code == 2
    assert out.err.count("\n") == 1 and "Traceback" not in out.err
    assert pytest.importorskip("re").search(match, out.err), out.err


@pytest.mark.parametrize("args, match", [
    (["--friction", "-1"], "--friction"),
    (["--load", "5 m"], "--load"),
    (["--load", "0"], "--load"),
])
def test_bad_options_exit_2(tmp_path, capsys, args, match):
    code, out = _run(tmp_path, capsys, EDGE, *args)
    assert code == 2 and match in out.err and out.err.count("\n") == 1


def test_impact_commands_refuse_a_sliding_scene_and_slide_an_impact_scene(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, EDGE, command="impact")
    assert code == 2 and "[slider]" in out.err and "filmscale slide" in out.err
    code, out = _run(tmp_path, capsys, MINIMAL)
    assert code == 2 and "[impactor]" in out.err


def test_scene_reads_quantities_with_units():
    scene = parse_slide_scene(EDGE + FILM)
    assert scene.slider.radius == pytest.approx(1e-5) and scene.normal_load == pytest.approx(1e-2)
    assert scene.stack.layers[0].thickness == pytest.approx(2e-8) and scene.friction == 0.2


# ------------------------------------------------------------------------ slide-map
def test_slide_map_file_has_dimension_scales_and_the_plot(tmp_path, capsys):
    out_h5 = tmp_path / "map.h5"
    code, out = _run(tmp_path, capsys, EDGE + FILM, "--load", "1mN:100mN:4", "--friction",
                     "0:0.6:3", "--out", str(out_h5), "--plot", "--json", command="slide-map")
    assert code == 0, out.err
    summary = json.loads(out.out)
    assert summary["points"] == 12 and len(summary["first_yield"]) == 3
    assert (tmp_path / "map.png").read_bytes()[:4] == b"\x89PNG"
    with h5py.File(out_h5) as f:
        assert f.attrs["format"] == "filmscale.slide_map/1"
        assert json.loads(f.attrs["layer_names"]) == ["DLC", "NiP"]
        assert f["layer_yield_ratio"].shape == (2, 3, 4)
        assert f["yield_ratio_max"].dims[1][0].name == "/normal_load"
        assert f["normal_load"].attrs["units"] == "N"
        np.testing.assert_allclose(f["normal_load"][()], np.geomspace(1e-3, 0.1, 4))
    xr = pytest.importorskip("xarray")
    ds = xr.open_dataset(out_h5, engine="h5netcdf")
    assert ds["layer_yield_ratio"].dims == ("layer", "friction", "normal_load")
    ds.close()


def test_slide_map_refusals(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, EDGE, "--load", "1mN:10mN:3", "--friction", "0:1:2",
                     "--plot", command="slide-map")
    assert code == 2 and "--plot" in out.err and "--out" in out.err
    code, out = _run(tmp_path, capsys, EDGE, "--load", "10mN:1mN:3", "--friction", "0:1:2",
                     "--out", str(tmp_path / "m.h5"), command="slide-map")
    assert code == 2 and "--load maximum" in out.err
    code, out = _run(tmp_path, capsys, EDGE, "--load", "1mN:10mN:3", "--friction", "-1:1:2",
                     "--out", str(tmp_path / "m.h5"), command="slide-map")
    assert code == 2 and "--friction minimum" in out.err
    assert not (tmp_path / "m.h5").exists()


def test_a_film_far_thinner_than_the_contact_exits_2_at_once(tmp_path, capsys):
    code, out = _run(tmp_path, capsys, EDGE + FILM.replace('"20 nm"', '"0.01 nm"'))
    assert code == 2 and "target.layers[0] (DLC)" in out.err and out.err.count("\n") == 1


# ------------------------------------------------------------------ friction from a scratch
def _scratch_record(path, mean=0.24, std=0.04, points=180, fmt="filmscale.md_scratch/1"):
    """A scratch record as `filmscale md scratch` writes its analysis (format, analysis attrs)."""
    with h5py.File(path, "w") as f:
        f.attrs["format"] = fmt
        a = f.create_group("analysis")
        a.attrs["friction_mean"], a.attrs["friction_std"] = mean, std
        a.attrs["steady_points"] = points
    return path


def test_friction_from_a_scratch_record(tmp_path, capsys):
    _scratch_record(tmp_path / "scratch.h5")
    text = EDGE.replace("friction = 0.2", 'friction_from = "scratch.h5"')
    code, out = _run(tmp_path, capsys, text, "--json")
    assert code == 0, out.err
    d = json.loads(out.out)
    assert d["friction"] == 0.24
    assert d["friction_source"]["std"] == 0.04 and d["friction_source"]["points"] == 180
    ref = cylinder_sliding(10e-3, 10e-6, 10e-6, 160e9, 0.3, 0.24, 2.5e9)
    assert d["layers"][0]["von_mises_max"] == pytest.approx(ref.vm_max, rel=1e-5)
    code, out = _run(tmp_path, capsys, text)
    assert "friction from the scratch record" in out.out and "0.240 +- 0.040" in out.out
    # --friction replaces the record's, and says no source
    code, out = _run(tmp_path, capsys, text, "--json", "--friction", "0.1")
    assert json.loads(out.out)["friction"] == 0.1 and "friction_source" not in out.out
    # the record is an input: a plot may not overwrite it, whatever its name
    _scratch_record(tmp_path / "record.png")
    code, out = _run(tmp_path, capsys, text.replace("scratch.h5", "record.png"), "--plot",
                     str(tmp_path / "record.png"))
    assert code == 2 and "scratch record" in out.err, out.err


@pytest.mark.parametrize("setup, match", [
    ("both", "contact.friction and contact.friction_from"),
    ("missing", "contact.friction_from = .* is not a file"),
    ("other", "is not a scratch record"),
])
def test_friction_from_refusals(tmp_path, capsys, setup, match):
    _scratch_record(tmp_path / "other.h5", fmt="filmscale.impact_map/2")
    _scratch_record(tmp_path / "scratch.h5")
    name = {"both": "scratch.h5", "missing": "nope.h5", "other": "other.h5"}[setup]
    new = f'friction_from = "{name}"' + ("\nfriction = 0.2" if setup == "both" else "")
    code, out = _run(tmp_path, capsys, EDGE.replace("friction = 0.2", new))
    assert code == 2 and out.err.count("\n") == 1
    assert pytest.importorskip("re").search(match, out.err), out.err
