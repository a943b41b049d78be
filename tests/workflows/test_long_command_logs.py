"""Long commands in a batch job's log (docs/hpc.md: "logs show progress"): each of
`impact-map` (a cylinder's point-wise map and an oblique map), `indent analyze`, `md indent`,
`particles` and `run`, run through `main` with stderr a file (not a terminal), writes no
carriage return and plain progress lines from the one helper (`workflows.progress`): a first
one before the end and a last one at 100 %, each with its count, percentage and time left.
Oracle: the counts the commands are given (points of the map, curves in the files, steps of
the schedule). Also `impact-map --mass`, whose map points all take the mass given: the oracle
is the scene's model evaluated directly at that mass."""

import json
import re
import sys

import h5py
import numpy as np
import pytest

from filmscale.workflows.cli import main
from tests.helpers.engines import RecordedEngine
from tests.helpers.scenes import BASE, CYLINDER_FILM_ON_STEEL, SCENE
from tests.helpers.scenes import OBLIQUE as OBLIQUE_TEMPLATE

#: a plain progress line: ``filmscale: LABEL: N/TOTAL UNITs, P% (RATE UNITs/s, T s left)``
PROGRESS = re.compile(r"^filmscale: (?P<label>.+): (?P<n>\d+)/(?P<total>\d+) (?P<unit>\w+)s, "
                      r"(?P<percent>\d+)% \((?P<rate>\S+) (?P=unit)s/s, "
                      r"(?P<left>[\d.]+ (s|min|h)) left\)$")

CYLINDER = CYLINDER_FILM_ON_STEEL

OBLIQUE = OBLIQUE_TEMPLATE.format(mu=0.1) + """
[map]
velocity = [0.05, 0.2, 3]
"""


def _logged(monkeypatch, tmp_path, argv) -> tuple[int, str]:
    """(exit status, the stderr log) of ``main(argv)`` with stderr a file."""
    log = tmp_path / "stderr.log"
    with open(log, "w", encoding="utf-8") as stream, monkeypatch.context() as patch:
        assert not stream.isatty()
        patch.setattr(sys, "stderr", stream)
        code = main([str(a) for a in argv])
    return code, log.read_text(encoding="utf-8")


def _progress(log: str, label: str) -> list[re.Match]:
    """The progress lines of ``label`` in a log that holds no carriage return; at least a
    first one before the end and a last one at 100 %, counts and percentages rising."""
    assert "\r" not in log
    lines = [m for m in map(PROGRESS.match, log.splitlines()) if m and m["label"] == label]
    assert len(lines) >= 2, log
    first, last = lines[0], lines[-1]
    assert 0 < int(first["n"]) < int(first["total"]) and int(first["percent"]) < 100
    assert last["n"] == last["total"] and last["percent"] == "100"
    assert [int(m["n"]) for m in lines] == sorted(int(m["n"]) for m in lines)
    return lines


def test_a_cylinder_map_logs_each_target(monkeypatch, tmp_path, capsys):
    """2 radii x 3 velocities, progress after each radius (the line model's point-wise
    map): 3/6, then 6/6 impacts, for the layered target and for the bare substrate."""
    scene = tmp_path / "cylinder.toml"
    scene.write_text(CYLINDER)
    code, log = _logged(monkeypatch, tmp_path, [
        "impact-map", scene, "--velocity", "0.5:8:3", "--radius", "5e-4:1e-3:2",
        "--out", tmp_path / "map.h5"])
    assert code == 0, log
    for label in ("layered target", "steel only"):
        lines = _progress(log, label)
        assert [(m["n"], m["total"], m["unit"]) for m in lines] == [("3", "6", "impact"),
                                                                  ("6", "6", "impact")]
        assert f"{label}: 3 x 2 impacts" in log


def test_an_oblique_map_logs_its_rows(monkeypatch, tmp_path):
    """3 velocities x 3 angles, progress after each angle: 3, 6, 9 of 9 impacts with a line
    at every report (the 30 s between lines set to 0), else the first and the last."""
    from filmscale.workflows import progress
    monkeypatch.setattr(progress, "PLAIN_EVERY_S", 0.0)
    scene = tmp_path / "oblique.toml"
    scene.write_text(OBLIQUE)
    code, log = _logged(monkeypatch, tmp_path, ["impact-map", scene, "--angle", "20:80:3",
                                                   "--out", tmp_path / "m.h5"])
    assert code == 0, log
    lines = _progress(log, "steel only")
    assert [m["n"] for m in lines] == ["3", "6", "9"] and lines[0]["total"] == "9"


def _write_curves(folder) -> list:
    """Two text curves and an HDF5 file of three curves: 5 curves in 3 files."""
    from filmscale.continuum.indentation.io import write_curve_group
    from filmscale.continuum.indentation.synthetic import synthetic_curve
    from filmscale.continuum.indentation.tips import berkovich
    curves = [synthetic_curve(150e9, 15e9, berkovich(), h_c=h_c, m=1.4, noise=0.001, seed=k)
              for k, h_c in enumerate((20e-9, 30e-9, 40e-9, 50e-9, 60e-9))]
    paths = []
    for k, c in enumerate(curves[:2]):
        paths.append(folder / f"indent_{k}.csv")
        np.savetxt(paths[-1], np.column_stack([c.h * 1e9, c.P * 1e6, c.t]), delimiter=", ",
                   header="h [nm], P [uN], t [s]", comments="")
    paths.append(folder / "three.h5")
    with h5py.File(paths[-1], "w") as f:
        for k, c in enumerate(curves[2:]):
            write_curve_group(f.create_group(f"c{k}"), c)
    return paths


def test_indent_analyze_counts_curves_not_files(monkeypatch, tmp_path, capsys):
    """5 curves in 3 files: the lines count curves (the last 5/5, not 3/3), each one as it
    is analysed; the closing line counts both."""
    paths = _write_curves(tmp_path)
    code, log = _logged(monkeypatch, tmp_path, ["indent", "analyze", *paths, "--tip",
                                                   "berkovich", "--json"])
    assert code == 0, log
    lines = _progress(log, "analysing")
    assert {m["unit"] for m in lines} == {"curve"}
    assert (lines[0]["n"], lines[-1]["n"], lines[-1]["total"]) == ("1", "5", "5")
    assert "analysed 5 of 5 curves from 3 files" in log
    assert len(capsys.readouterr().out.splitlines()) == 5


def test_indent_analyze_on_a_pool_counts_each_chunks_curves(monkeypatch, tmp_path):
    """64 files start the process pool (2 workers, chunks of 4 files): a line after each
    chunk (the 30 s between lines set to 0), in steps of 4 curves up to 64/64."""
    from filmscale.workflows import progress
    monkeypatch.setattr(progress, "PLAIN_EVERY_S", 0.0)
    (first, *_) = _write_curves(tmp_path)
    folder = tmp_path / "many"
    folder.mkdir()
    for k in range(64):
        (folder / f"c{k:02d}.csv").write_bytes(first.read_bytes())
    code, log = _logged(monkeypatch, tmp_path, ["indent", "analyze", folder, "--tip",
                                                "berkovich", "--workers", "2", "--json"])
    assert code == 0, log
    lines = _progress(log, "analysing")
    assert [int(m["n"]) for m in lines] == list(range(4, 65, 4))
    assert {m["total"] for m in lines} == {"64"}


class ReportingEngine(RecordedEngine):
    """The recorded ci run, reporting its steps as LAMMPS's thermo output does."""

    def __call__(self, input_file, run_dir, options, *, log_name, progress=None):
        out = super().__call__(input_file, run_dir, options, log_name=log_name,
                               progress=progress)
        for step in (100, 800, 10**6):          # past the end: the schedule's last step
            if progress is not None:
                progress(step)
        return out


@pytest.fixture
def recorded_md(monkeypatch):
    """`md indent` and `run` without LAMMPS for the indentation (the potential's elastic
    constants still run, a second)."""
    from filmscale.md import record as md_record
    from filmscale.md import run as md_run
    monkeypatch.setattr(md_run, "run_input", ReportingEngine())
    monkeypatch.setattr(md_record, "lammps_info", dict)


def test_md_indent_logs_its_steps(monkeypatch, tmp_path, recorded_md):
    from filmscale.md.spec import preset
    steps = preset("ci").protocol.schedule().s_end
    code, log = _logged(monkeypatch, tmp_path, ["md", "indent", "--preset", "ci", "--out",
                                                   tmp_path / "run"])
    assert code == 0, log
    lines = _progress(log, "ci-cu001")
    assert lines[0]["n"] == "100" and lines[-1]["total"] == str(steps)
    assert len(lines) == 2                  # no repeat of the 100 % line


def test_run_logs_its_md_unit(monkeypatch, tmp_path, recorded_md):
    scene = tmp_path / "scene.toml"
    scene.write_text(BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-9, impactor_extra="",
                                 film='[target.layers.calibrate]\nmd = "ci"',
                                 want='["maxima"]'))
    code, log = _logged(monkeypatch, tmp_path, ["run", scene, "--store", tmp_path / "store",
                                                   "--out", tmp_path / "r.h5"])
    assert code == 0, log
    (label,) = {m["label"] for m in map(PROGRESS.match, log.splitlines()) if m}
    assert label.startswith("md-indent-") and label.endswith(" (MD)")
    _progress(log, label)


def test_particles_log_their_steps(monkeypatch, tmp_path):
    """The ci preset in LAMMPS (about 9 s): its engine reports the steps."""
    code, log = _logged(monkeypatch, tmp_path, ["particles", "indent", "--preset", "ci",
                                                   "--out", tmp_path / "run"])
    assert code == 0, log
    lines = _progress(log, "ci-elastic-sphere")
    assert {m["unit"] for m in lines} == {"step"}


def test_a_terminal_gets_the_bar_with_the_time_left(monkeypatch):
    """On a terminal the same helper draws tqdm's bar, redrawn in place, with the time
    left."""
    import io
    import time

    from filmscale.workflows.progress import count_callback, progress_bar

    class Terminal(io.StringIO):
        def isatty(self):
            return True
    screen = Terminal()
    monkeypatch.setattr(sys, "stderr", screen)
    bar = progress_bar(6, "impact", "steel only")
    report = count_callback(bar)
    time.sleep(0.15)                    # tqdm redraws at most every 0.1 s
    report(3, 6)
    time.sleep(0.15)
    report(6, 6)
    bar.close()
    shown = screen.getvalue()
    assert "\r" in shown and "steel only: 3/6 impacts  50%" in shown
    assert re.search(r"3/6 impacts  50%\|#+ +\| \[00:00 elapsed, 00:00 left, ", shown), shown


# ---- impact-map --mass ----------------------------------------------------------------------

def _map(tmp_path, capsys, text, *args):
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    code = main(["impact-map", str(scene), "--out", str(tmp_path / "m.h5"), "--json",
                 "--force", *map(str, args)])
    out = capsys.readouterr()
    return code, (json.loads(out.out) if code == 0 else None), out.err


def test_map_mass_replaces_the_scenes_mass_at_every_point(tmp_path, capsys):
    """--mass 3.2mg: every point is the scene's model at 3.2e-6 kg (the scene says 1.6 mg),
    the summary and the file say so; the map differs from the scene's own."""
    from filmscale.workflows.result import read_impact_maps
    from filmscale.workflows.scene import parse_scene
    code, summary, err = _map(tmp_path, capsys, SCENE, "--mass", "3.2mg")
    assert code == 0, err
    assert summary["mass"] == pytest.approx(3.2e-6, rel=1e-12)
    fields, _ = read_impact_maps(tmp_path / "m.h5")
    f = fields["homogeneous"]
    assert f["mass"] == pytest.approx(3.2e-6, rel=1e-12)
    model = parse_scene(SCENE).model()
    for i, R in enumerate(f["radius"]):
        for j, V in enumerate(f["velocity"]):
            direct = model.maxima(float(V), float(R), 3.2e-6)
            assert f["delta_max"][i, j] == pytest.approx(float(direct.delta_max), rel=1e-9,
                                                         nan_ok=True)
    heavier = f["delta_max"].copy()
    code, summary, _ = _map(tmp_path, capsys, SCENE)
    assert code == 0 and summary["mass"] == 1.6e-6
    lighter = read_impact_maps(tmp_path / "m.h5")[0]["homogeneous"]["delta_max"]
    both = np.isfinite(heavier) & np.isfinite(lighter)
    assert both.sum() >= 6 and np.all(heavier[both] > lighter[both])


@pytest.mark.parametrize("text, args, words", [
    (SCENE, ("--mass", "0"), ("--mass",)),                         # MASS_RANGE: > 0
    (SCENE, ("--mass", "2e6"), ("--mass", "1e+06")),               # MASS_RANGE: <= 1e6 kg
    # lighter than air at the largest radius of the scene's map (1e-5 m), then of --radius
    (SCENE, ("--mass", "1e-18"), ("map.radius maximum", "--mass", "lighter than air")),
    (SCENE, ("--mass", "1e-12", "--radius", "1e-6:1e-3:3"), ("--radius maximum", "--mass")),
    # a cylinder's own body at its largest radius (L = 5 mm, R = 1 mm: 1.6e-5 kg of steel)
    (CYLINDER, ("--mass", "1e-9", "--velocity", "0.5:8:3", "--radius", "5e-4:1e-3:2"),
     ("--mass", "--radius maximum", "impactor.length")),
    # an angle map's one radius is the impactor's
    (OBLIQUE, ("--mass", "1e-15", "--angle", "20:80:3"), ("impactor.radius", "--mass")),
])
def test_map_mass_is_checked_like_impact_mass(tmp_path, capsys, text, args, words):
    code, _, err = _map(tmp_path, capsys, text, *args)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert all(w in err for w in words), err
    assert not (tmp_path / "m.h5").exists()


def test_map_mass_takes_units_and_an_oblique_map(tmp_path, capsys):
    code, summary, err = _map(tmp_path, capsys, OBLIQUE, "--mass", "65.4 mg", "--angle",
                              "20:80:2", "--velocity", "0.05:0.2:2")
    assert code == 0, err
    assert summary["mass"] == pytest.approx(6.54e-5, rel=1e-12)
