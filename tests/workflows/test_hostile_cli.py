"""Hostile input on every command: an output that is an input (by name, relative path,
symbolic or hard link), an existing file of another kind, negative numbers as option values,
`report` on files that are no scene result, damaged store files, `plan` against `run`, usage
errors, and writes killed mid-way. Each case asserts the exit status, one line on stderr, no
traceback, and that no file changed but the stated output (hashes of the whole work folder
before and after). Most cases call `main` in-process; a subset runs the real entry point."""

import hashlib
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.tips import berkovich
from filmscale.core.files import TEMP_MARK, _host
from filmscale.workflows.cli import main
from filmscale.workflows.impact_cli import HISTORY_HEADER
from filmscale.workflows.result import RESULT_FORMAT
from tests.helpers.cli import run_main
from tests.helpers.curves import sphere_curve_file
from tests.helpers.scenes import BASE, SCENE

PROFILE_SCENE = SCENE + '\n[target.profile]\nfile = "profile.csv"\n'
FILM = '[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"'
ORACLE = "--C 43.840e9 --dPdh 4.3354e5 --WpWt 0.8242 --hm 1e-6"


def _pipeline(want: str) -> str:
    return BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="", film=FILM,
                       want=want)


def _h5(path: Path, fmt: str | None) -> None:
    with h5py.File(path, "w") as f:
        if fmt:
            f.attrs["format"] = fmt
        f.create_dataset("x", data=[1.0])


@pytest.fixture(scope="module")
def map_bytes(tmp_path_factory) -> bytes:
    """An impact map written by impact-map (once for the module)."""
    d = tmp_path_factory.mktemp("map")
    (d / "scene.toml").write_text(SCENE)
    assert main(["impact-map", str(d / "scene.toml"), "--out", str(d / "map.h5")]) == 0
    return (d / "map.h5").read_bytes()


@pytest.fixture
def work(tmp_path, monkeypatch, map_bytes, capsys) -> Path:
    """A work folder of inputs and earlier outputs of every kind, the current directory."""
    d = tmp_path
    (d / "scene.toml").write_text(SCENE)
    (d / "other.toml").write_text(SCENE)
    (d / "profile_scene.toml").write_text(PROFILE_SCENE)
    (d / "profile.csv").write_text("h_c [nm], E_r [GPa], H [GPa]\n20, 150, 12\n80, 120, 9\n")
    (d / "link.toml").symlink_to("scene.toml")
    os.link(d / "scene.toml", d / "hard.toml")
    sphere_curve_file(d)                                   # film.csv
    (d / "pipe.toml").write_text(_pipeline('["maxima"]'))
    (d / "pipe_tangential.toml").write_text(_pipeline('["maxima", "tangential"]'))
    (d / "pipe_map.toml").write_text(_pipeline('["maxima", "map"]'))
    (d / "sweep.toml").write_text('base = "scene.toml"\n[axes]\n"impactor.velocity" = '
                                  "[0.05, 0.1]\n")
    (d / "sweep.json").write_text((d / "sweep.toml").read_text())     # TOML, named .json
    (d / "sweep_tangential.toml").write_text('base = "pipe_tangential.toml"\n')
    (d / "curves").mkdir()
    curve = synthetic_curve(140e9, 12e9, berkovich(), h_c=40e-9, m=1.4, noise=0.001, seed=1)
    np.savetxt(d / "curves" / "i.csv", np.column_stack([curve.h * 1e9, curve.P * 1e6]),
               delimiter=", ", header="h [nm], P [uN]", comments="")
    (d / "area.toml").write_text('length_unit = "nm"\nC = [24.494, 1000.0]\n')
    (d / "map.h5").write_bytes(map_bytes)
    (d / "trunc.h5").write_bytes(map_bytes[:1000])
    _h5(d / "md.h5", "filmscale.md_indent/1")
    _h5(d / "particles.h5", "filmscale.md_particles/1")
    _h5(d / "result.h5", RESULT_FORMAT)                     # the format, not the content
    _h5(d / "plain.h5", None)
    (d / "notes.txt").write_text("my notes\n")
    (d / "fake.png").write_text("not an image\n")
    (d / "image.png").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(64))
    (d / "empty.dat").write_bytes(b"")
    (d / "binary.bin").write_bytes(bytes(range(256)) * 4)
    (d / "hist.csv").write_text(HISTORY_HEADER + "\n0,0,0,0,0,0,1,0\n")
    (d / "result.html").write_text("<html>someone's page</html>\n")
    (d / "runs").mkdir()
    (d / "runs" / "notes.txt").write_text("not a run\n")
    (d / "results" / "sweep").mkdir(parents=True)
    (d / "results" / "sweep" / "sweep-000.h5").write_text("not a result\n")
    for name, text in (("bad_json", "{"), ("list_json", "[]"), ("ids_json", '{"units": 5}')):
        (d / name).mkdir()
        (d / name / "jobs.json").write_text(text)
    (d / "odd_store" / "calibration-0123456789abcdef" / "done.json").mkdir(parents=True)
    for run in ("md_run", "particle_run"):
        (d / run).mkdir()
        (d / run / "state.json").write_text('{"spec": ')          # a run cut off mid-write
    monkeypatch.chdir(d)
    capsys.readouterr()
    return d


def _snapshot(folder: Path) -> dict[str, str]:
    return {p.relative_to(folder).as_posix():
            hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "folder"
            for p in sorted(folder.rglob("*"))}


def _entry_point(argv: list[str]) -> tuple[int, str, str]:
    done = subprocess.run([sys.executable, "-m", "filmscale", *argv], capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)
    return done.returncode, done.stdout, done.stderr


# (id, command line, exit status, text of the one stderr line (exit != 0), files changed)
CASES = [
    # an output that is an input of the same command
    ("history=scene", "impact scene.toml --history scene.toml", 2,
     "--history scene.toml is the input scene; choose another file", ()),
    ("history=./scene", "impact scene.toml --history ./scene.toml", 2, "is the input scene", ()),
    ("history=symlink", "impact scene.toml --history link.toml", 2, "is the input scene", ()),
    ("history=hardlink", "impact scene.toml --history hard.toml", 2, "is the input scene", ()),
    ("history=profile", "impact profile_scene.toml --history profile.csv", 2,
     "is the scene's target.profile file", ()),
    ("history=plot", "impact scene.toml --history h.png --plot h.png", 2,
     "--plot h.png is also --history", ()),
    ("force keeps inputs", "impact scene.toml --history scene.toml --force", 2,
     "is the input scene", ()),
    ("map out=scene", "impact-map scene.toml --out scene.toml", 2,
     "--out scene.toml is the input scene", ()),
    ("map out=symlink", "impact-map link.toml --out scene.toml", 2, "is the input scene", ()),
    ("map out=hardlink", "impact-map scene.toml --out hard.toml", 2, "is the input scene", ()),
    ("map out=profile", "impact-map profile_scene.toml --out profile.csv", 2,
     "is the scene's target.profile file", ()),
    ("map force keeps inputs", "impact-map scene.toml --out scene.toml --force", 2,
     "is the input scene", ()),
    ("analyze out=curve", "indent analyze plain.h5 --tip berkovich --out plain.h5", 2,
     "--out plain.h5 is an input curve file", ()),
    ("analyze profile=curve", "indent analyze curves/i.csv --profile curves/i.csv", 2,
     "--profile curves/i.csv is an input curve file", ()),
    ("analyze profile=curve in folder", "indent analyze curves --profile curves/i.csv", 2,
     "is an input curve file", ()),
    ("analyze profile=area", "indent analyze curves --tip berkovich --area-file area.toml "
     "--profile area.toml", 2, "--profile area.toml is the --area-file", ()),
    ("analyze out=profile", "indent analyze curves --out r.h5 --profile r.h5", 2,
     "--profile r.h5 is also --out", ()),
    ("report out=result", "report result.h5 --out result.h5", 2,
     "--out result.h5 is the input result", ()),
    ("report figure=out", "report result.h5 --out r.png --figure r.png", 2,
     "--figure r.png is also --out", ()),
    ("run out=scene", "run scene.toml --out scene.toml", 2, "--out scene.toml is the input "
     "scene", ()),
    ("run out=curve source", "run pipe.toml --out film.csv", 2,
     "--out film.csv is a calibration source of the scene (curves:film.csv)", ()),
    ("run out=report", "run scene.toml --out r.html --report", 2,
     "--report r.html is also --out", ()),
    ("run store=scene", "run scene.toml --store scene.toml --out r.h5", 2,
     "--store scene.toml is a file, not a folder", ()),
    ("sweep index=sweep file", "sweep run sweep.json --out-dir . --force", 2,
     "--out-dir sweep.json is the sweep file", ()),
    ("sweep out-dir file", "sweep run sweep.toml --out-dir notes.txt", 2,
     "--out-dir notes.txt is a file, not a folder", ()),
    ("md out=file", "md indent --preset ci --out scene.toml", 2,
     "--out scene.toml is a file, not a folder", ()),
    ("md out=folder of others", "md indent --preset ci --out runs", 2,
     "--out runs is a folder of other files", ()),
    ("particles out=file", "particles indent --preset ci --out notes.txt", 2,
     "is a file, not a folder", ()),
    ("particles out=folder of others", "particles impact --preset ci --out runs", 2,
     "is a folder of other files", ()),
    # an existing file of another kind: refused without --force
    ("map over text", "impact-map scene.toml --out notes.txt", 2,
     "--out notes.txt exists and is a text file, not an impact map; choose another file, "
     "or --force replaces it", ()),
    ("map over other scene", "impact-map scene.toml --out other.toml", 2,
     "exists and is a text file", ()),
    ("map over md record", "impact-map scene.toml --out md.h5", 2,
     "exists and is an MD indentation record (filmscale md indent), not an impact map", ()),
    ("map over damaged h5", "impact-map scene.toml --out trunc.h5", 2,
     "exists and is a damaged HDF5 file", ()),
    ("map over scene result", "impact-map scene.toml --out result.h5", 2,
     "exists and is a scene result (filmscale run)", ()),
    ("map over binary", "impact-map scene.toml --out binary.bin", 2,
     "exists and is a binary file", ()),
    ("map plot over text", "impact-map scene.toml --out m.h5 --plot fake.png", 2,
     "--plot fake.png exists and is a text file, not a PNG image", ()),
    ("history over text", "impact scene.toml --history notes.txt", 2,
     "--history notes.txt exists and is a text file, not an impact history", ()),
    ("history over map", "impact scene.toml --history map.h5", 2,
     "exists and is an impact map (filmscale impact-map), not an impact history", ()),
    ("analyze out over map", "indent analyze curves --out map.h5", 2,
     "--out map.h5 exists and is an impact map", ()),
    ("analyze profile over text", "indent analyze curves --profile notes.txt", 2,
     "--profile notes.txt exists and is a text file, not a profile table", ()),
    ("report over html page", "report result.h5", 2,
     "--out result.html exists and is a text file, not an HTML report", ()),
    ("report figure over text", "report result.h5 --out r.html --figure fake.png", 2,
     "--figure fake.png exists and is a text file", ()),
    ("run over map", "run scene.toml --out map.h5", 2,
     "--out map.h5 exists and is an impact map (filmscale impact-map), not a scene result",
     ()),
    ("run report over html page", "run scene.toml --out result.h5 --report", 2,
     "--report result.html exists and is a text file", ()),
    ("sweep over text", "sweep run sweep.toml", 2,
     "--out-dir results/sweep/sweep-000.h5 exists and is a text file, not a scene result",
     ()),
    # ... replaced with --force, and an earlier output of the same kind without it
    ("map --force over text", "impact-map scene.toml --out notes.txt --force", 0, "",
     ("notes.txt",)),
    ("map over earlier map", "impact-map scene.toml --out map.h5", 0, "", ("map.h5",)),
    ("history --force over text", "impact scene.toml --history notes.txt --force", 0, "",
     ("notes.txt",)),
    ("history over earlier history", "impact scene.toml --history hist.csv", 0, "",
     ("hist.csv",)),
    ("plot over a png", "impact-map scene.toml --out m.h5 --plot image.png", 0, "",
     ("m.h5", "image.png")),
    # negative numbers are values: the range check answers, not argparse
    ("reverse --C", f"indent reverse {ORACLE} --C -1e11", 2,
     "C = -1e+11 Pa is outside the valid range", ()),
    ("reverse --dPdh", f"indent reverse {ORACLE} --dPdh -5e6", 2,
     "dPdh = -5e+06 N/m is outside the valid range", ()),
    ("reverse --WpWt", f"indent reverse {ORACLE} --WpWt -0.5", 2,
     "WpWt = -0.5 is outside the valid range", ()),
    ("reverse --hm", f"indent reverse {ORACLE} --hm -1E-6", 2,
     "h_m = -1e-06 m is outside the valid range", ()),
    ("reverse --C-std", f"indent reverse {ORACLE} --C-std -1e9", 2,
     "C_std = -1e+09 Pa is outside the valid range", ()),
    ("reverse --dPdh-std", f"indent reverse {ORACLE} --dPdh-std -4e3", 2,
     "dPdh_std = -4000 N/m is outside the valid range", ()),
    ("reverse --WpWt-std", f"indent reverse {ORACLE} --WpWt-std -.01", 2,
     "WpWt_std = -0.01 is outside the valid range", ()),
    ("reverse --hm-std", f"indent reverse {ORACLE} --hm-std -1e-9", 2,
     "h_m_std = -1e-09 m is outside the valid range", ()),
    ("reverse --C2", f"indent reverse {ORACLE} --C2 -2e10 --tip2 cone:60", 2,
     "C2 = -2e+10 Pa is outside the valid range", ()),
    ("reverse --E-i", f"indent reverse {ORACLE} --E-i -1e12", 2,
     "E_i = -1e+12 Pa is outside the valid range", ()),
    ("reverse --samples", f"indent reverse {ORACLE} --samples -5", 2,
     "samples = -5 is outside the valid range", ()),
    ("reverse --seed", f"indent reverse {ORACLE} --seed -1", 2,
     "seed = -1 is outside the valid range", ()),
    ("reverse --nu accepted", f"indent reverse {ORACLE} --nu -0.2", 0, "", ()),
    ("reverse --nu-i accepted", f"indent reverse {ORACLE} --nu-i -0.1", 0, "", ()),
    ("impact --velocity", "impact scene.toml --velocity -1e-3", 2,
     "--velocity = -0.001 m/s is outside the valid range", ()),
    ("impact --velocity -inf", "impact scene.toml --velocity -inf", 2,
     "--velocity = -inf m/s is outside the valid range", ()),
    ("impact --radius", "impact scene.toml --radius -1e-6", 2,
     "--radius = -1e-06 m is outside the valid range", ()),
    ("impact --mass", "impact scene.toml --mass -1.6e-6", 2,
     "--mass = -1.6e-06 kg is outside the valid range", ()),
    ("map --velocity", "impact-map scene.toml --velocity -1:1:3 --out m.h5", 2,
     "--velocity minimum = -1 m/s is outside the valid range", ()),
    ("map --radius", "impact-map scene.toml --radius -1e-6:1e-5:3 --out m.h5", 2,
     "--radius minimum = -1e-06 m is outside the valid range", ()),
    ("analyze --frame-compliance", "indent analyze curves --frame-compliance -1e-9", 2,
     "--frame-compliance = -1e-09 m/N is outside the valid range", ()),
    ("analyze --window", "indent analyze curves --window -0.1:0.9", 2,
     "--window start = -0.1 is outside the valid range", ()),
    ("analyze --nu refused", "indent analyze curves --nu -1.5", 2,
     "--nu = -1.5 is outside the valid range", ()),
    ("analyze --epsilon", "indent analyze curves --epsilon -0.7", 2,
     "--epsilon = -0.7 is outside the valid range [0.5, 1]", ()),
    ("analyze --beta", "indent analyze curves --beta -1", 2,
     "--beta = -1 is outside the valid range [0.5, 2]", ()),
    ("analyze --workers", "indent analyze curves --workers -2", 2,
     "--workers = -2 must be at least 1", ()),
    ("analyze --layers", "indent analyze curves --layers -5nm,10nm", 2,
     "--layers depth = -5e-09 m is outside the valid range", ()),
    ("analyze --nu accepted", "indent analyze curves --tip berkovich --nu -0.3 --workers 1",
     0, "", ()),
    ("calibrate --film-thickness", "calibrate film.csv --tip sphere:5um --film-thickness "
     "-1e-9 --substrate 90e9,0.25", 2, "film thickness = -1e-09 m is outside the valid "
     "range", ()),
    ("calibrate --nu", "calibrate film.csv --tip sphere:5um --nu -1.5", 2,
     "nu = -1.5 is outside the valid range", ()),
    ("calibrate --tolerance", "calibrate film.csv --tip sphere:5um --tolerance -0.1", 2,
     "tolerance = -0.1 is outside the valid range", ()),
    ("calibrate --substrate", "calibrate film.csv --tip sphere:5um --film-thickness 1e-6 "
     "--substrate -9e10,0.25", 2, "substrate.E = -9e+10 Pa is outside the valid range", ()),
    ("md --np", "md indent --preset ci --np -2", 2, "np = -2 must be an integer", ()),
    ("md --omp", "md indent --preset ci --omp -1", 2, "omp_threads = -1 must be an integer",
     ()),
    ("particles --np", "particles indent --preset ci --np -1", 2,
     "np = -1 must be an integer", ()),
    ("sweep --jobs", "sweep run sweep.toml --jobs -1", 2, "--jobs = -1 must be at least 1", ()),
    ("sweep --only", "sweep run sweep.toml --only -1", 2,
     "--only = -1 must be a scene index", ()),
    ("sweep --unit", "sweep run-unit sweep.toml --unit -1", 2, "--unit = -1 must be in", ()),
    ("sweep --time", "sweep submit sweep.toml --time -5", 2, "--time = -5 min must exceed", ()),
    # report on files that are no scene result
    ("report map", "report map.h5", 2, "map.h5 is an impact map (filmscale impact-map); "
     "report expects a scene result", ()),
    ("report md record", "report md.h5", 2, "md.h5 is an MD indentation record", ()),
    ("report particle record", "report particles.h5", 2, "is a particle-model record", ()),
    ("report truncated", "report trunc.h5", 2, "trunc.h5 is a damaged HDF5 file", ()),
    ("report other h5", "report plain.h5", 2, "is an HDF5 file without a filmscale format",
     ()),
    ("report text", "report scene.toml", 2, "scene.toml is a text file; report expects", ()),
    ("report binary", "report binary.bin", 2, "binary.bin is a binary file", ()),
    ("report empty", "report empty.dat", 2, "empty.dat is an empty file", ()),
    ("report image", "report image.png", 2, "image.png is a PNG file", ()),
    ("report folder", "report curves", 2, "result curves is a folder, not a file", ()),
    ("report missing", "report absent.h5", 2, "result absent.h5 does not exist", ()),
    ("report incomplete", "report result.h5 --out r.html", 2,
     "scene result result.h5 is damaged or incomplete", ()),
    # damaged store files
    ("status bad jobs.json", "status bad_json", 2, "bad_json/jobs.json is not valid JSON", ()),
    ("status list jobs.json", "status list_json", 2, "list_json/jobs.json is damaged", ()),
    ("cancel odd jobs.json", "cancel ids_json", 2, "ids_json/jobs.json is damaged", ()),
    ("status unreadable record", "status odd_store", 0, "", ()),     # status creates no file
    ("md damaged run state", "md indent --preset ci --out md_run --json", 2,
     "/md_run/state.json is not valid JSON", ("md_run/dumps",)),
    ("particles damaged run state", "particles indent --preset ci --out particle_run --json",
     2, "/particle_run/state.json is not valid JSON", ()),
    ("status store is a file", "status notes.txt", 2, "store notes.txt is not a folder", ()),
    # plan refuses what run refuses, before any work
    ("plan tangential", "plan pipe_tangential.toml", 2,
     "a normal approach has no tangential motion", ()),
    ("run tangential", "run pipe_tangential.toml --store st --out r.h5", 2,
     "a normal approach has no tangential motion", ()),
    ("plan map without axes", "plan pipe_map.toml", 2,
     "an impact map needs velocity and radius ranges", ()),
    ("run map without axes", "run pipe_map.toml --store st --out r.h5", 2,
     "an impact map needs velocity and radius ranges", ()),
    ("sweep plan tangential", "sweep plan sweep_tangential.toml", 2,
     "a normal approach has no tangential motion", ()),
    ("sweep run tangential", "sweep run sweep_tangential.toml --store st", 2,
     "a normal approach has no tangential motion", ()),
    # usage errors: one line
    ("bad float", "impact scene.toml --velocity fast", 2,
     "--velocity must be a number, got 'fast' (or a speed in m/s or with units", ()),
    ("missing value", "indent reverse --C 1e11 --dPdh", 2,
     "argument --dPdh: expected one argument", ()),
    ("unknown option", "impact scene.toml --speed 1", 2, "unrecognized arguments: --speed 1",
     ()),
    ("no command", "", 2, "the following arguments are required: command", ()),
]

#: cases whose stderr has more than the error line: the run's progress bar starts first
STDERR_LINES = {"md damaged run state": 2, "particles damaged run state": 2}

#: the cases also run through the real entry point (a new process each)
ENTRY_POINT = ("history=symlink", "map over md record", "reverse --dPdh", "report map",
               "status bad jobs.json", "bad float", "analyze --frame-compliance")


def _check(case, work, run) -> None:
    name, argv, code, message, changed = case
    before = _snapshot(work)
    status, _, err = run(shlex.split(argv))
    after = _snapshot(work)
    assert status == code, err
    assert "Traceback" not in err
    if code:
        assert len(err.splitlines()) == STDERR_LINES.get(name, 1), err
        assert message in err.splitlines()[-1]
    assert {k: v for k, v in after.items() if k not in changed} == \
        {k: v for k, v in before.items() if k not in changed}
    for name in changed:
        assert after.get(name) not in (None, before.get(name)), name


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_hostile_command_line(case, work, capsys):
    _check(case, work, lambda argv: run_main(argv, capsys))


@pytest.mark.parametrize("case", [c for c in CASES if c[0] in ENTRY_POINT],
                         ids=list(ENTRY_POINT))
def test_hostile_command_line_through_the_entry_point(case, work):
    _check(case, work, _entry_point)


def test_a_read_error_is_not_called_a_write_error(work, capsys, monkeypatch):
    from filmscale.workflows import impact_cli

    def unreadable(args):
        raise PermissionError(13, "Permission denied", "scene.toml")
    monkeypatch.setattr(impact_cli, "cmd_impact", unreadable)
    code, _, err = run_main(["impact", "scene.toml"], capsys)
    assert code == 2 and err == "filmscale: error: scene.toml: Permission denied\n"


def _temporaries(folder: Path) -> list[Path]:
    return [p for p in folder.iterdir() if TEMP_MARK in p.name]


def test_sigterm_mid_write_leaves_no_temporary_file(work):
    """A real SIGTERM while impact-map writes its HDF5 file (held open by a slowed-down
    attribute write): exit 130, one line, no temporary file, no output."""
    marker = work / "writing"
    script = ("import sys, time\nfrom pathlib import Path\n"
              "import filmscale.workflows.result as result\n"
              "from filmscale.workflows.cli import main\n"
              "original = result.dumps\n"
              "def slow(*args, **kwargs):\n"
              f"    Path({str(marker)!r}).touch()\n"
              "    time.sleep(60)\n"
              "    return original(*args, **kwargs)\n"
              "result.dumps = slow\n"
              "sys.exit(main(sys.argv[1:]))\n")
    proc = subprocess.Popen([sys.executable, "-c", script, "impact-map", "scene.toml", "--out",
                             "killed.h5"], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not marker.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert marker.exists(), proc.stderr.read()
    assert len(_temporaries(work)) == 1           # the write is under way
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert err.splitlines()[-1] == "filmscale: interrupted; nothing half-written was kept"
    assert "Traceback" not in err
    assert _temporaries(work) == [] and not (work / "killed.h5").exists()


def test_sigterm_mid_write_keeps_the_earlier_output(work, capsys, monkeypatch):
    import filmscale.workflows.result as result
    original = result.dumps
    earlier = (work / "map.h5").read_bytes()

    def terminated(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        return original(*args, **kwargs)
    monkeypatch.setattr(result, "dumps", terminated)
    code, _, err = run_main(["impact-map", "scene.toml", "--out", "map.h5"], capsys)
    assert code == 130 and "interrupted" in err and "Traceback" not in err
    assert _temporaries(work) == [] and (work / "map.h5").read_bytes() == earlier


def test_a_killed_process_temporary_is_removed_by_the_next_write(work, capsys):
    """Temporary files of dead processes of this host go; those of a live process or of
    another host (a shared file system) stay."""
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True)
    dead = int(gone.stdout)
    stale = work / f".m.h5{TEMP_MARK}{_host()}.{dead}.abc123.h5"
    live = work / f".m.h5{TEMP_MARK}{_host()}.{os.getpid()}.def456.h5"
    elsewhere = work / f".m.h5{TEMP_MARK}another-node.{dead}.ghi789.h5"
    for p in (stale, live, elsewhere):
        p.write_bytes(b"half")
    code, _, err = run_main(["impact-map", "scene.toml", "--out", "m.h5"], capsys)
    assert code == 0, err
    assert not stale.exists() and live.exists() and elsewhere.exists()
    assert (work / "m.h5").is_file()
