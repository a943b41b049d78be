"""Hostile input to the readers and the Python API: files that are no regular file
(/dev/zero, a pipe whose writer never stops: refused before they are opened), files over the
size limit, binary files, deeply nested TOML and JSON,
folders, missing files and odd names go through every reader of scenes, sweeps, specs, the
site file, curve tables, area files and JSON; the array API gets negative, NaN and infinite
values and shapes that do not match. Each case asserts the error class (InputError, exit 2),
the parameter or file it names, and a single line; a few run the real command line and
assert no traceback. A legitimate input beside each proves the readers still read."""

import math
import os
import subprocess
import sys
import threading
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.continuum import ElasticPlastic, ImpactModel, Layer, LayerStack, solve_impact
from filmscale.continuum.contact import hertz
from filmscale.continuum.contact.impact_map import impact_map
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.contact.restitution import johnson_restitution, thornton_restitution
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_area_function, read_curves, read_table
from filmscale.continuum.indentation.oliver_pharr import (calibrate_frame_compliance,
                                                          elastic_indent, oliver_pharr,
                                                          shallow_depth_hardness)
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.indentation.tips import berkovich
from filmscale.core.checks import check_real, check_real_array
from filmscale.core.errors import InputError
from filmscale.core.files import (MAX_INPUT_BYTES, MAX_INPUT_BYTES_ENV, MAX_NESTING, read_json,
                                  read_text)
from filmscale.md import particle_spec, spec
from filmscale.md.site import load_site
from filmscale.workflows.scene import load_scene
from filmscale.workflows.pipeline_scene import load_pipeline
from filmscale.workflows.sweep import load_sweep
from tests.helpers.scenes import MINIMAL

SCENE = MINIMAL
TABLE = "h [nm], P [uN]\n1, 2\n2, 5\n3, 9\n"
GLASS = ElasticPlastic(E=90e9, nu=0.25, sigma_y=2.4e9, name="glass")
LIMIT = 4096        # bytes: the size limit the hostile cases run under


def one_line(excinfo) -> str:
    """The message of an InputError that is one line (what the command line prints)."""
    message = str(excinfo.value)
    assert excinfo.type is InputError and "\n" not in message and "\r" not in message
    return message


def _site(path):
    os.environ["FILMSCALE_SITE"] = str(path)
    try:
        return load_site()
    finally:
        del os.environ["FILMSCALE_SITE"]


#: every reader of a user's text input: (suffix, how it is called, a valid content or None
#: when a valid one needs more files, whether it is TOML)
READERS = {
    "scene": (".toml", load_scene, SCENE, True),
    "pipeline scene": (".toml", load_pipeline, SCENE, True),
    "sweep": (".toml", load_sweep, None, True),
    "md spec": (".toml", spec.load_spec, None, True),
    "particle spec": (".toml", lambda p: particle_spec.load_spec(p, "indent"), None, True),
    "site file": (".toml", _site, "", True),
    "area file": (".toml", read_area_function, "C = [24.5]\n", True),
    "table": (".csv", read_table, TABLE, False),
    "curve file": (".csv", read_curves, TABLE, False),
    "json": (".json", read_json, '{"a": [1, 2]}', False),
}


@pytest.fixture
def small_limit(monkeypatch):
    monkeypatch.setenv(MAX_INPUT_BYTES_ENV, str(LIMIT))


def _read(reader: str, path: Path):
    return READERS[reader][1](path)


def _input(tmp_path: Path, reader: str) -> Path:
    return tmp_path / f"input{READERS[reader][0]}"


# --- the reader's own limits: size, text, file kinds -------------------------------------

HOSTILE_FILES = {
    "over the size limit": (lambda p: p.write_text("# " + "x" * LIMIT + "\n"),
                            f"is larger than {LIMIT} bytes"),
    "NUL bytes": (lambda p: p.write_bytes(b"title = 1\n\0\0\0"),
                  "is not a text file (binary?): it holds NUL bytes"),
    "not UTF-8": (lambda p: p.write_bytes(b'title = "caf\xe9"\n'),
                  "is not a text file (binary?): it is not UTF-8 text"),
    "random bytes": (lambda p: p.write_bytes(bytes(range(256)) * 4),
                     "is not a text file (binary?)"),
    "/dev/zero": (lambda p: p.symlink_to("/dev/zero"), "a character device, not a regular file"),
    "a named pipe": (lambda p: os.mkfifo(p), "a named pipe (FIFO), not a regular file"),
    "a folder": (lambda p: p.mkdir(), "cannot read"),
    "missing": (lambda p: None, "does not exist"),
}


@pytest.mark.parametrize("kind", list(HOSTILE_FILES))
@pytest.mark.parametrize("reader", list(READERS))
def test_every_reader_refuses_hostile_files_in_one_line(tmp_path, small_limit, reader, kind):
    path = _input(tmp_path, reader)
    make, expect = HOSTILE_FILES[kind]
    make(path)
    with pytest.raises(InputError) as err:
        _read(reader, path)
    message = one_line(err)
    assert expect in message and str(path) in message


@pytest.mark.parametrize("reader", [r for r, v in READERS.items() if v[2] is not None])
def test_every_reader_still_reads_a_valid_file(tmp_path, small_limit, reader):
    path = _input(tmp_path, reader)
    path.write_text(READERS[reader][2])
    assert _read(reader, path) is not None


@pytest.mark.parametrize("reader", ["scene", "table", "md spec"])
def test_an_endless_pipe_is_refused_unopened(tmp_path, small_limit, reader):
    """A FIFO whose writer never stops: the reader refuses it before opening it (the writer
    stays blocked in its open until the test releases it)."""
    path = _input(tmp_path, reader)
    os.mkfifo(path)

    def endless():
        try:
            with open(path, "wb") as f:
                while True:
                    f.write(b"# endless\n" * 1000)
        except (BrokenPipeError, OSError):
            pass

    writer = threading.Thread(target=endless, daemon=True)
    writer.start()
    try:
        with pytest.raises(InputError) as err:
            _read(reader, path)
        assert "not a regular file" in one_line(err)
    finally:
        # the reader never opened it: release the writer from its open (again, should the
        # writer not have reached its open yet), and it stops at its first write
        for _ in range(100):
            if not writer.is_alive():
                break
            os.close(os.open(path, os.O_RDONLY | os.O_NONBLOCK))
            writer.join(timeout=0.1)
    assert not writer.is_alive()


def test_dev_zero_is_refused_and_the_limit_is_configurable(monkeypatch, tmp_path):
    monkeypatch.delenv(MAX_INPUT_BYTES_ENV, raising=False)
    with pytest.raises(InputError, match="a character device, not a regular file"):
        read_text("/dev/zero", "scene")
    big = tmp_path / "big.toml"
    with big.open("wb") as f:           # sparse: refused from its size, unread
        f.truncate(MAX_INPUT_BYTES + 1)
    with pytest.raises(InputError, match=f"larger than {MAX_INPUT_BYTES} bytes"):
        read_text(big, "scene")
    monkeypatch.setenv(MAX_INPUT_BYTES_ENV, "10")
    (tmp_path / "s.toml").write_text("title = 'eleven'\n")
    with pytest.raises(InputError, match="larger than 10 bytes"):
        read_text(tmp_path / "s.toml", "scene")


@pytest.mark.parametrize("value", ["abc", "0", "-5", "1.5", ""])
def test_a_bad_size_limit_names_its_variable(monkeypatch, tmp_path, value):
    (tmp_path / "s.toml").write_text(SCENE)
    monkeypatch.setenv(MAX_INPUT_BYTES_ENV, value)
    with pytest.raises(InputError) as err:
        load_scene(tmp_path / "s.toml")
    assert one_line(err).startswith(f"{MAX_INPUT_BYTES_ENV} = {value!r} must be a positive")


@pytest.mark.parametrize("name", ["line\nbreak.toml", "carriage\rreturn.toml", "tab\tname.toml",
                                  "nul\0name.toml"])
def test_odd_file_names_stay_on_one_line(tmp_path, name):
    with pytest.raises(InputError) as err:
        load_scene(tmp_path / name)
    assert "cannot read scene" in one_line(err)


def test_line_ends_are_made_newlines(tmp_path):
    path = tmp_path / "crlf.toml"
    path.write_bytes(SCENE.replace("\n", "\r\n").encode())
    assert load_scene(path).impactor.radius == 10e-6
    assert read_text(path, "scene") == SCENE


# --- TOML and JSON: nesting, syntax, numbers --------------------------------------------------

def _nested(depth: int) -> str:
    return "x = " + "[" * depth + "1" + "]" * depth + "\n"


HOSTILE_TOML = {
    "arrays nested 33 deep": (_nested(MAX_NESTING), f"more than {MAX_NESTING} deep"),
    "arrays nested 100000 deep": (_nested(100_000), f"more than {MAX_NESTING} deep"),
    "inline tables nested 2000 deep": ("x = " + "{a = " * 2000 + "1" + "}" * 2000 + "\n",
                                       f"more than {MAX_NESTING} deep"),
    "dotted keys 5000 deep": ("a" + ".a" * 5000 + " = 1\n", f"more than {MAX_NESTING} deep"),
    "an integer of 5000 digits": ("x = " + "1" * 5000 + "\n", "is not valid TOML"),
    "an unclosed table": ("[impactor\nradius = 1\n", "is not valid TOML"),
    "a duplicate key": ("a = 1\na = 2\n", "is not valid TOML"),
}


@pytest.mark.parametrize("kind", list(HOSTILE_TOML))
@pytest.mark.parametrize("reader", [r for r, v in READERS.items() if v[3]])
def test_every_toml_reader_refuses_hostile_toml_in_one_line(tmp_path, reader, kind):
    path = _input(tmp_path, reader)
    text, expect = HOSTILE_TOML[kind]
    path.write_text(text)
    with pytest.raises(InputError) as err:
        _read(reader, path)
    assert expect in one_line(err)


def test_nesting_at_the_limit_is_read(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text(_nested(MAX_NESTING - 1))      # the top table is the first level
    with pytest.raises(InputError, match="C must be a list"):
        read_area_function(path)                  # parsed: its keys are checked next


@pytest.mark.parametrize("text, expect", [
    ("[" * 100_000, f"more than {MAX_NESTING} deep"),
    ("[" * (MAX_NESTING + 1) + "]" * (MAX_NESTING + 1), f"more than {MAX_NESTING} deep"),
    ('{"a": ' * 40 + "1" + "}" * 40, f"more than {MAX_NESTING} deep"),
    ("1" * 5000, "is not valid JSON"),
    ("{'a': 1}", "is not valid JSON"),
    ("", "is not valid JSON"),
])
def test_json_reader_refuses_hostile_json(tmp_path, text, expect):
    path = tmp_path / "x.json"
    path.write_text(text)
    with pytest.raises(InputError) as err:
        read_json(path, "run record")
    assert expect in one_line(err)


SCENE_VALUES = {
    "E beyond the float range": ("E = 90e9", "E = 1" + "0" * 400,
                                 "target.substrate.E is beyond the range of a float"),
    "E infinite": ("E = 90e9", "E = inf", "target.substrate.E = inf Pa is outside"),
    "radius NaN": ("radius = 10e-6", "radius = nan", "impactor.radius = nan m is outside"),
    "mass negative": ("mass = 1.6e-6", "mass = -1.6e-6",
                      "impactor.mass = -1.6e-06 kg is outside"),
    "nu a string": ("nu = 0.25", 'nu = "0.25"', "target.substrate.nu must be a number"),
    "sigma_y a table": ("sigma_y = 2.4e9", "sigma_y = {a = 1}",
                        "target.substrate.sigma_y must be a number"),
    "velocity a date": ("velocity = 0.2", "velocity = 1979-05-27",
                        "impactor.velocity must be a number, got datetime.date(1979, 5, 27)"),
    "layers a string": ("[target.substrate]", '[target]\nlayers = "x"\n[target.substrate]',
                        "target.layers must be an array of tables"),
}


@pytest.mark.parametrize("case", list(SCENE_VALUES))
def test_hostile_scene_values_name_their_key(tmp_path, case):
    old, new, expect = SCENE_VALUES[case]
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.replace(old, new, 1))
    with pytest.raises(InputError) as err:
        load_scene(path)
    assert expect in one_line(err)


@pytest.mark.parametrize("text, value", [("5", 5), ('"text"', "text"), ("null", None)])
def test_json_scalars_are_read(tmp_path, text, value):
    (tmp_path / "x.json").write_text(text)
    assert read_json(tmp_path / "x.json") == value


# --- HDF5 curve files ------------------------------------------------------------------------

def _h5_curve(path: Path, **datasets):
    with h5py.File(path, "w") as f:
        g = f.create_group("c")
        g.attrs["format"] = "filmscale.curve/1"
        for name, value in datasets.items():
            if name == "meta":
                g.attrs["meta"] = value
            else:
                g.create_dataset(name, data=value)


@pytest.mark.parametrize("make, expect", [
    (lambda p: p.symlink_to("/dev/zero"), "not a regular file"),
    (lambda p: os.mkfifo(p), "not a regular file"),
    (lambda p: p.write_text("h, P\n1, 2\n"), "cannot read HDF5 file"),
    (lambda p: _h5_curve(p, h=[0.0, 1e-9, 2e-9]), "has no dataset 'P'"),
    (lambda p: _h5_curve(p, h=np.zeros(LIMIT), P=np.zeros(LIMIT)), "is not a dataset of at "
     f"most {LIMIT} bytes"),
    (lambda p: _h5_curve(p, h=[0, 1e-9], P=[0, 1e-6], meta="[" * 100_000), "more than"),
    (lambda p: _h5_curve(p, h=[0, 1e-9], P=[0, 1e-6], meta="[1, 2]"), "not a JSON object"),
    (lambda p: _h5_curve(p, h=[0, 1e-9], P=[0, 1e-6], meta="{bad"), "is not valid JSON"),
])
def test_hdf5_curve_files_are_checked(tmp_path, small_limit, make, expect):
    path = tmp_path / "curves.h5"
    make(path)
    with pytest.raises(InputError) as err:
        read_curves(path)
    assert expect in one_line(err)


# --- the API: values out of range, NaN, shapes -------------------------------------------------

LAW = contact_law("komvopoulos-ye")
MODEL = ImpactModel(GLASS, LAW)
NAN, INF = math.nan, math.inf

#: (call, the parameter the message must name); values from the issue: negative mass, NaN
#: radius, negative approach, and their kin in every closed form and solver entry
BAD_CALLS = {
    "hertz_force negative approach": (lambda: hertz.hertz_force(-1e-9, 1e-6, 1e11),
                                      "delta contains -1e-09 m"),
    "hertz_force NaN radius": (lambda: hertz.hertz_force(1e-9, NAN, 1e11), "R contains nan m"),
    "hertz_force zero modulus": (lambda: hertz.hertz_force(1e-9, 1e-6, 0.0),
                                 "E_star contains 0 Pa"),
    "hertz_force text": (lambda: hertz.hertz_force("1e-9", 1e-6, 1e11), "delta must be numbers"),
    "contact radius infinite R": (lambda: hertz.hertz_contact_radius(1e-9, INF),
                                  "R contains inf m"),
    "mean pressure negative approach": (lambda: hertz.hertz_mean_pressure([1e-9, -1e-9], 1e-6,
                                                                          1e11),
                                        "delta contains -1e-09 m"),
    "elastic_impact negative mass": (lambda: hertz.elastic_impact(-1.6e-6, 1e-6, 0.2, 1e11),
                                     "m contains -1.6e-06 kg"),
    "elastic_impact NaN radius": (lambda: hertz.elastic_impact(1.6e-6, NAN, 0.2, 1e11),
                                  "R contains nan m"),
    "elastic_impact zero speed": (lambda: hertz.elastic_impact(1.6e-6, 1e-6, 0.0, 1e11),
                                  "V contains 0 m/s"),
    "impact time beyond delta_max": (lambda: hertz.elastic_impact_time(2e-9, 1e-9, 0.2),
                                     "beyond delta_max = 1e-09 m"),
    "impact time zero delta_max": (lambda: hertz.elastic_impact_time(0.0, 0.0, 0.2),
                                   "delta_max contains 0 m"),
    "yield factor nu above 0.5": (lambda: hertz.yield_pressure_factor(0.7), "nu contains 0.7"),
    "first_yield negative sigma_y": (lambda: hertz.first_yield(1e-6, 1e11, -1e9, 0.3),
                                     "sigma_y contains -1e+09 Pa"),
    "yield_velocity NaN mass": (lambda: hertz.yield_velocity(NAN, 1e-6, 1e11, 1e9, 0.3),
                                "m contains nan kg"),
    "law contact negative approach": (lambda: LAW.contact(-1e-9, 1e-6, 1e11, 1e9, 0.3),
                                      "delta contains -1e-09 m"),
    "law contact NaN sigma_y": (lambda: LAW.contact(1e-9, 1e-6, 1e11, NAN, 0.3),
                                "sigma_y contains nan Pa"),
    "law first_yield negative mass": (lambda: LAW.first_yield(1e-6, 1e11, 1e9, 0.3, mass=-1),
                                      "m contains -1 kg"),
    "thornton negative speed": (lambda: thornton_restitution(-1.0, 0.1), "V contains -1 m/s"),
    "johnson zero pressure": (lambda: johnson_restitution(1e-6, 1e-6, 1.0, 1e11, 0.0),
                              "p_d contains 0 Pa"),
    "maxima negative mass": (lambda: MODEL.maxima(0.2, 1e-6, -1.6e-6),
                             "mass contains -1.6e-06 kg"),
    "maxima NaN radius": (lambda: MODEL.maxima(0.2, NAN, 1.6e-6), "radius contains nan m"),
    "maxima infinite speed": (lambda: MODEL.maxima(INF, 1e-6, 1.6e-6),
                              "velocity contains inf m/s"),
    "history negative gap": (lambda: MODEL.history(0.2, 1e-6, 1.6e-6, gap=-1e-9),
                             "gap = -1e-09 m"),
    "history negative mass": (lambda: MODEL.history(0.2, 1e-6, -1.0), "mass contains -1 kg"),
    "first_yield NaN radius": (lambda: MODEL.first_yield(NAN, 1.6e-6), "radius contains nan m"),
    "solve_impact NaN radius": (lambda: solve_impact(GLASS, LAW, 0.2, NAN, 1.6e-6),
                                "radius contains nan m"),
    "impact_map text axis": (lambda: impact_map(MODEL, "fast", [1e-6], 1.6e-6),
                             "velocity must be numbers"),
    "impact_map negative mass": (lambda: impact_map(MODEL, [0.1], [1e-6], -1.0),
                                 "mass = -1 kg"),
    "model of a string": (lambda: ImpactModel("glass", LAW), "target must be a material"),
    "model impactor of a string": (lambda: ImpactModel(GLASS, LAW, impactor="steel"),
                                   "impactor must be an ElasticPlastic"),
    "empty LayerStack": (lambda: LayerStack((), None), "needs a substrate"),
    "LayerStack of None": (lambda: LayerStack(None, GLASS), "layers must be a sequence"),
    "LayerStack of text": (lambda: LayerStack("layers", GLASS), "layers must be a sequence"),
    "LayerStack of numbers": (lambda: LayerStack([1.0], GLASS), "layers must hold Layer"),
    "Layer of text": (lambda: Layer(1e-9, "glass"), "material must be an ElasticPlastic"),
    "Layer negative thickness": (lambda: Layer(-1e-9, GLASS), "glass.thickness = -1e-09 m"),
    "material NaN modulus": (lambda: ElasticPlastic(NAN, 0.3), "E = nan Pa"),
    "material nu 0.5": (lambda: ElasticPlastic(90e9, 0.5), "nu = 0.5"),
    "oliver_pharr of an array": (lambda: oliver_pharr(np.zeros(5), "berkovich"),
                                 "curve must be a LoadDisplacementCurve"),
    "oliver_pharr short window": (lambda: oliver_pharr(_curve(), "berkovich", window=(0.2,)),
                                  "window = (0.2,)"),
    "curve NaN only": (lambda: LoadDisplacementCurve([NAN, NAN], [1.0, 2.0]).finite(),
                       "fewer than 2 finite points"),
    "property_profile lengths": (lambda: property_profile([1e-8, 2e-8], [1e11], [1e10]),
                                 "differ in length: 2, 1, 1"),
    "check_real huge integer": (lambda: check_real("E", 10**400),
                                "E is beyond the range of a float"),
    "check_real_array huge integer": (lambda: check_real_array("E", [1, 10**400]),
                                      "E holds a number beyond the range of a float"),
}


def _curve():
    return synthetic_curve(100e9, 5e9, berkovich(), h_c=100e-9)


@pytest.mark.parametrize("case", list(BAD_CALLS))
def test_api_refuses_bad_values_naming_the_parameter(case):
    call, expect = BAD_CALLS[case]
    with pytest.raises(InputError) as err:
        call()
    assert expect in one_line(err)


SHAPE_CALLS = {
    "hertz_force": (lambda: hertz.hertz_force(np.full(3, 1e-9), np.full(2, 1e-6), 1e11),
                    ("delta (3,)", "R (2,)")),
    "elastic_impact": (lambda: hertz.elastic_impact(np.full(4, 1e-6), 1e-6, np.ones(3), 1e11),
                       ("m (4,)", "V (3,)")),
    "law contact": (lambda: LAW.contact(np.full(3, 1e-9), np.full((2, 2), 1e-6), 1e11, 1e9,
                                        0.3), ("delta (3,)", "R (2, 2)")),
    "maxima": (lambda: MODEL.maxima(np.ones(3), np.full(2, 1e-6), 1.6e-6),
               ("velocity (3,)", "radius (2,)")),
    "impact_map 2-D axis": (lambda: impact_map(MODEL, np.ones((2, 2)), [1e-6], 1.6e-6),
                            ("(2, 2)", "(1,)")),
    "frame compliance": (lambda: calibrate_frame_compliance([1e-3, 2e-3, 3e-3], [1e5, 2e5]),
                         ("(3,)", "(2,)")),
    "elastic_indent": (lambda: elastic_indent([1e-3, 2e-3], [1e-9] * 3, [2e-9] * 2),
                       ("P_max (2,)", "W_p (3,)")),
    "shallow depth": (lambda: shallow_depth_hardness([1e-3] * 3, [1e-7] * 2, "berkovich",
                                                     P_e=1e-4, h_me=2e-8, S_e=1e4),
                      ("P_max (3,)", "h_c (2,)")),
    "profile table": (lambda: TableProfile.from_measurements([1e-8, 2e-8, 3e-8], [1e11] * 2,
                                                             [1e10] * 3), ("h_c 3", "E_r 2")),
    "curve": (lambda: LoadDisplacementCurve([0.0, 1e-9, 2e-9], [0.0, 1e-6]), ("3", "2")),
}


@pytest.mark.parametrize("case", list(SHAPE_CALLS))
def test_shape_mismatches_name_both_shapes(case):
    call, shapes = SHAPE_CALLS[case]
    with pytest.raises(InputError) as err:
        call()
    message = one_line(err)
    assert all(shape in message for shape in shapes), message


def test_valid_calls_still_agree_with_their_closed_forms():
    """The checked closed forms return what they did: scalars for scalars, arrays for
    arrays, the energy identity (2/5) P_max delta_max = m V^2 / 2."""
    res = hertz.elastic_impact(1.6e-6, 10e-6, 0.3, 1e11)
    assert np.ndim(res.delta_max) == 0
    assert 0.4 * res.force_max * res.delta_max == pytest.approx(0.5 * 1.6e-6 * 0.09, rel=1e-13)
    assert hertz.hertz_force(np.array([0.0, 1e-9]), 1e-6, 1e11).shape == (2,)
    assert MODEL.maxima(0.2, 10e-6, 1.6e-6).result().delta_max > 0


# --- the command line: exit 2, one line, no traceback -----------------------------------------

def _cli(*args, cwd, env=None):
    return subprocess.run([sys.executable, "-m", "filmscale", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          stdin=subprocess.DEVNULL, env={**os.environ, **(env or {})})


@pytest.mark.parametrize("args, make, env, expect", [
    (["impact", "zero.toml"], lambda d: (d / "zero.toml").symlink_to("/dev/zero"),
     {MAX_INPUT_BYTES_ENV: str(LIMIT)},
     "cannot read scene zero.toml: it is a character device, not a regular file"),
    (["impact", "deep.toml"], lambda d: (d / "deep.toml").write_text(_nested(100_000)), {},
     f"scene deep.toml nests tables and arrays more than {MAX_NESTING} deep"),
    (["impact", "scene.toml"], lambda d: (d / "scene.toml").write_text(SCENE),
     {MAX_INPUT_BYTES_ENV: "lots"}, f"{MAX_INPUT_BYTES_ENV} = 'lots' must be a positive"),
    (["run", "bin.toml"], lambda d: (d / "bin.toml").write_bytes(bytes(range(256))), {},
     "scene bin.toml is not a text file (binary?)"),
    (["indent", "analyze", "bin.csv", "--tip", "berkovich", "--json"],
     lambda d: (d / "bin.csv").write_bytes(bytes(range(256)) * 4), {},
     "table bin.csv is not a text file (binary?)"),
])
def test_cli_reader_errors_exit_2_in_one_line(tmp_path, args, make, env, expect):
    make(tmp_path)
    run = _cli(*args, cwd=tmp_path, env=env)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert len([line for line in run.stderr.splitlines() if expect in line]) == 1
