"""The options of `filmscale sweep submit` without SLURM: ``--dry-run`` prints what would be
submitted (sbatch is not even on PATH) and writes nothing; every option reaches both array
jobs' sbatch command lines; what is refused is refused in one line naming the option; each
array job's time limit is its largest task's from the planner's cost model; and paths of
this node only are refused unless ``--allow-local-paths``. Oracles: the command lines
printed, SLURM's own formats (sbatch's --mem, --array=...%N), the files under the test's
folder before and after, and stand-in planner costs."""

import json
import math
import os
import shlex
import subprocess
import sys

import pytest

from filmscale.core.errors import InputError
from filmscale.workflows import slurm
from filmscale.workflows.plan import Plan, Step
from filmscale.workflows.slurm import (SubmitOptions, array_jobs, array_limit,
                                       check_shared_paths, sbatch_options, scene_estimate_s,
                                       submission_paths)
from filmscale.workflows.sweep import load_sweep
from tests.helpers.scenes import BASE

MD_FILM = '[target.layers.calibrate]\nmd = "ci"\nnp = 2'
KNOWN_FILM = "E = 200e9\nsigma_y = 8e9"


def _sweep(tmp_path, film=MD_FILM, velocities=(0.5, 2.0)):
    (tmp_path / "base.toml").write_text(BASE.format(
        R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="", film=film, want='["maxima"]'))
    path = tmp_path / "sweep.toml"
    path.write_text(f'base = "base.toml"\n[axes]\n"impactor.velocity" = {list(velocities)}\n')
    return path


def _submit(tmp_path, *args, env=None):
    return subprocess.run([sys.executable, "-m", "filmscale", "sweep", "submit",
                           str(tmp_path / "sweep.toml"), "--store", str(tmp_path / "store"),
                           "--out-dir", str(tmp_path / "out"), *args],
                          capture_output=True, text=True, cwd=tmp_path, env=env)


def _files(folder):
    return sorted((str(p.relative_to(folder)), p.stat().st_mtime_ns)
                  for p in folder.rglob("*"))


ALL_OPTIONS = ["--account", "A", "--qos", "Q", "--mem", "4G", "--constraint", "C",
               "--gres", "gpu:1", "--array-limit", "2",
               "--sbatch=--exclusive --mail-type=END", "--sbatch=--comment='two words'"]


def test_a_dry_run_prints_both_jobs_with_every_option_and_writes_nothing(tmp_path):
    _sweep(tmp_path)
    before = _files(tmp_path)
    no_slurm = tmp_path.parent / f"{tmp_path.name}-empty-path"   # outside: not in the snapshot
    no_slurm.mkdir()
    done = _submit(tmp_path, "--dry-run", "--allow-local-paths", *ALL_OPTIONS,
                   env={**os.environ, "PATH": str(no_slurm)})
    assert done.returncode == 0, done.stderr
    assert _files(tmp_path) == before           # no store, no out-dir, no jobs.json, no log
    assert not (tmp_path / "store").exists() and not (tmp_path / "out").exists()
    lines = done.stdout.splitlines()
    commands = [shlex.split(line) for line in lines if line.startswith("sbatch ")]
    assert len(commands) == 2
    given = ["--account=A", "--qos=Q", "--mem=4G", "--constraint=C", "--gres=gpu:1",
             "--exclusive", "--mail-type=END", "--comment=two words"]
    for argv in commands:
        assert argv[:3] == ["sbatch", "--parsable", "--requeue"]
        assert argv[-len(given):] == given      # both jobs, the extra options last
    units, scenes = commands
    assert "--array=0%2" in units and "--array=0-1%2" in scenes
    assert "--dependency=afterok:<job 1>" in scenes and "--cpus-per-task=2" in units
    assert lines.count("#!/bin/bash") == 1 and lines.count("#!/bin/sh") == 1
    assert any("'run-unit'" in line for line in lines)
    assert any(line.startswith("exec ") and "'--only'" in line for line in lines)
    assert sum(line.startswith("# time limit: the largest task's") for line in lines) == 2
    assert lines[-1] == "# dry run: nothing submitted, nothing written"


@pytest.mark.parametrize("mem", ["4G", "4g", "4000M", "500K", "2T", "0", "4000", "4GB"])
def test_slurm_memory_sizes_are_taken(mem):
    assert SubmitOptions(mem=mem).sbatch_args() == [f"--mem={mem}"]


@pytest.mark.parametrize("mem", ["4.5G", "4Gi", "G", "-4G", "4B", "4P", "four", "4 G", ""])
def test_garbage_memory_sizes_are_refused(mem):
    with pytest.raises(InputError, match="not SLURM's memory format|one word"):
        SubmitOptions(mem=mem)


@pytest.mark.parametrize("option", ["--array", "--dependency", "--output", "--open-mode",
                                    "--signal", "--requeue", "--parsable", "--job-name",
                                    "--time", "--error", "--no-requeue", "--cpus-per-task"])
def test_an_option_filmscale_sets_itself_is_refused_naming_it(option):
    with pytest.raises(InputError, match=f"'{option}=x' is {option}, which filmscale sweep "
                                         "submit sets itself"):
        sbatch_options([f"--exclusive {option}=x"])


@pytest.mark.parametrize("text, message", [
    ("--dep=afterok:1", "'--dep=afterok:1' abbreviates --dependency"),
    ("--out=x.log", "abbreviates --output"),
    ("-A acct", "'-A' is not a long option"),
    ("--mail-type END", "'END' is not a long option"),
    ("--account=acct", "give filmscale sweep submit's own --account"),
    ("--mem=4G", "own --mem"),
    ("--comment='open", "No closing quotation"),
])
def test_other_sbatch_texts_are_refused(text, message):
    with pytest.raises(InputError, match=message):
        sbatch_options([text])


def test_a_refused_option_exits_2_in_one_line_before_anything_is_written(tmp_path):
    _sweep(tmp_path)
    before = _files(tmp_path)
    done = _submit(tmp_path, "--allow-local-paths", "--sbatch=--array=0-3")
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.splitlines() == [
        "filmscale: error: --sbatch: '--array=0-3' is --array, which filmscale sweep submit "
        "sets itself for its array jobs: it cannot be passed through"]
    assert _files(tmp_path) == before


@pytest.mark.parametrize("args, message", [
    (["--array-limit", "0"], "--array-limit = 0 must be at least 1"),
    (["--account", "a b"], "--account = 'a b' must be one word"),
    (["--scene-time", "0"], "--scene-time = 0 min must be at least 1"),
])
def test_wrong_values_are_refused(tmp_path, args, message):
    _sweep(tmp_path)
    done = _submit(tmp_path, "--dry-run", "--allow-local-paths", *args)
    assert done.returncode == 2 and message in done.stderr, done.stderr
    assert len(done.stderr.splitlines()) == 1


# ---- paths the compute nodes must see ------------------------------------------------------

def test_a_sweep_under_tmp_is_refused_in_one_line_without_the_flag(tmp_path):
    _sweep(tmp_path)
    before = _files(tmp_path)
    done = _submit(tmp_path, "--dry-run")
    assert done.returncode == 2 and done.stdout == ""
    (line,) = done.stderr.splitlines()
    # the first path under /tmp: the sweep file here (the venv is not under /tmp)
    assert "is under /tmp, a folder of this node only" in line and "--allow-local-paths" in line
    assert str(tmp_path / "sweep.toml") in line or str(sys.prefix) in line
    assert _files(tmp_path) == before


@pytest.mark.parametrize("path", ["/tmp", "/tmp/s", "/var/tmp/s", "/dev/shm/a/b",
                                  "/scratch/job/s"])
def test_node_local_folders_and_tmpdir_are_refused(monkeypatch, path):
    monkeypatch.setenv("TMPDIR", "/scratch/job")
    with pytest.raises(InputError, match=f"--store {path} is under "):
        check_shared_paths({"--store": path})


@pytest.mark.parametrize("path", ["/work/s", "/home/u/store", "/tmpfs-not/s", "/scratch/s"])
def test_other_folders_pass(monkeypatch, path):
    monkeypatch.setenv("TMPDIR", "/scratch/job")
    check_shared_paths({"--store": path})


def test_a_tmpdir_of_slash_is_no_local_folder(monkeypatch):
    monkeypatch.setenv("TMPDIR", "/")
    check_shared_paths({"--store": "/work/s"})


def test_a_link_into_a_node_local_folder_is_refused(tmp_path, monkeypatch):
    """The link is checked as resolved too: here the node-local folder is $TMPDIR alone."""
    monkeypatch.setattr(slurm, "NODE_LOCAL", ())
    monkeypatch.setenv("TMPDIR", str(tmp_path / "local"))
    (tmp_path / "local").mkdir()
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "store").symlink_to(tmp_path / "local")
    check_shared_paths({"--out-dir": tmp_path / "shared" / "out"})
    with pytest.raises(InputError, match="--store .*shared/store is under .*local"):
        check_shared_paths({"--store": tmp_path / "shared" / "store"})


def test_an_interpreter_under_tmp_is_refused(monkeypatch):
    monkeypatch.setattr(sys, "prefix", "/tmp/venv")
    paths = submission_paths("/work/sweep.toml", "/work/store", "/work/out")
    with pytest.raises(InputError, match=r"the Python environment \(sys.prefix\) /tmp/venv"):
        check_shared_paths(paths)


# ---- time limits ----------------------------------------------------------------------------

def test_an_arrays_limit_is_its_largest_tasks():
    minutes, why = array_limit(None, {"scene 0": 10.0, "scene 1": 1000.0}, "--scene-time")
    assert minutes == math.ceil((3 * 1000.0 + 600) / 60)
    assert "scene 1" in why and "one limit" in why
    assert array_limit(45, {"scene 0": 1e6}, "--scene-time") == (
        45, "45 min, as --scene-time gives")


def _planned(cost, seen):
    def plan_impact(scene, *args):
        seen.append(scene)
        return Plan((Step("impact", "m", "r", "e", cost), Step("x", "m", "r", "e", math.nan)))
    return plan_impact


def test_a_scene_tasks_estimate_is_its_planned_impact_not_its_md(tmp_path, monkeypatch):
    """The planner's impact cost (a stand-in film while the layer awaits its MD), once and
    once for each of E and sigma_y shifted; the MD run is the units job's."""
    seen = []
    monkeypatch.setattr(slurm, "plan_impact", _planned(100.0, seen))
    _, scenes = load_sweep(_sweep(tmp_path))
    assert scene_estimate_s(scenes[0]) == 3 * 100.0
    film = seen[0].stack.layers[0].material
    assert (film.E, film.sigma_y) == (0.5 * 90e9, 0.25 * 2.4e9)   # half E, a quarter sigma_y
    _, known = load_sweep(_sweep(tmp_path, KNOWN_FILM))
    assert scene_estimate_s(known[0]) == 100.0                      # no calibration: once
    jobs = array_jobs(tmp_path / "sweep.toml", "s", scenes, tmp_path / "store",
                      tmp_path / "out", SubmitOptions())
    limits = [next(o for o in job.options if o.startswith("--time=")) for job in jobs]
    md = math.ceil((3 * slurm._estimate_s(scenes[0], 0, 0) + 600) / 60)
    assert limits == [f"--time={md // 60}:{md % 60:02d}:00", "--time=0:25:00"]  # 3x300+600 s


def test_the_scene_limit_does_not_grow_with_the_number_of_scenes(tmp_path):
    """The real planner on a known film: 1 and 12 scenes ask for the same limit (the old rule,
    60 s a scene, gave 12 scenes 46 min)."""
    limits = []
    for n in (1, 12):
        _, scenes = load_sweep(_sweep(tmp_path, KNOWN_FILM, [0.5 + i for i in range(n)]))
        (job,) = array_jobs(tmp_path / "sweep.toml", "s", scenes, tmp_path / "store",
                            tmp_path / "out", SubmitOptions())
        limits.append(next(o for o in job.options if o.startswith("--time=")))
    assert limits[0] == limits[1] == "--time=0:11:00"


def test_time_and_scene_time_replace_the_cost_model(tmp_path):
    _, scenes = load_sweep(_sweep(tmp_path))
    units, scenes_job = array_jobs(tmp_path / "sweep.toml", "s", scenes, tmp_path / "store",
                                   tmp_path / "out",
                                   SubmitOptions(unit_minutes=30, scene_minutes=125))
    assert "--time=0:30:00" in units.options and "--time=2:05:00" in scenes_job.options
    assert units.limit_why == "30 min, as --time gives"


# ---- submission, with a stand-in sbatch ---------------------------------------------------

def _fake_slurm(tmp_path, refuse_second: bool):
    """sbatch and scancel stand-ins on PATH: sbatch records its arguments and script and
    answers job ids 77, 78 (or refuses the second job); scancel records its arguments."""
    bin_ = tmp_path.parent / f"{tmp_path.name}-bin"
    calls = tmp_path.parent / f"{tmp_path.name}-calls"
    bin_.mkdir()
    calls.mkdir()
    refuse = ('[ -e "$d/0" ] && { echo "sbatch: error: Invalid account" >&2; '
              'echo "sbatch: error: Batch job submission failed" >&2; exit 1; }\n'
              if refuse_second else "")
    (bin_ / "sbatch").write_text(
        f'#!/bin/sh\nd={calls}\n{refuse}n=$(ls "$d" | grep -c "^[0-9]$")\n'
        'echo "$@" > "$d/$n"; cat > "$d/$n.sh"; echo "$((77 + n))"\n')
    (bin_ / "scancel").write_text(f'#!/bin/sh\necho "$@" >> {calls}/scancel\n')
    for f in bin_.iterdir():
        f.chmod(0o755)
    return {**os.environ, "PATH": f"{bin_}{os.pathsep}{os.environ['PATH']}"}, calls


def test_a_submission_sends_what_the_dry_run_prints(tmp_path):
    _sweep(tmp_path)
    env, calls = _fake_slurm(tmp_path, refuse_second=False)
    dry = _submit(tmp_path, "--dry-run", "--allow-local-paths", *ALL_OPTIONS).stdout
    done = _submit(tmp_path, "--allow-local-paths", *ALL_OPTIONS, env=env)
    assert done.returncode == 0, done.stderr
    printed = [shlex.split(line)[1:] for line in dry.splitlines() if line.startswith("sbatch ")]
    sent = [(calls / f"{n}").read_text().split() for n in (0, 1)]
    printed[1][printed[1].index("--dependency=afterok:<job 1>")] = "--dependency=afterok:77"
    assert [" ".join(p) for p in printed] == [" ".join(s) for s in sent]
    assert (calls / "0.sh").read_text().startswith("#!/bin/bash\n")
    jobs = json.loads((tmp_path / "store" / "jobs.json").read_text())
    assert list(jobs["units"].values()) == ["77_0"]
    assert jobs["scenes"] == {"sweep-000": "78_0", "sweep-001": "78_1"}


def test_a_refused_scenes_job_cancels_the_units_job(tmp_path):
    _sweep(tmp_path)
    env, calls = _fake_slurm(tmp_path, refuse_second=True)
    done = _submit(tmp_path, "--allow-local-paths", env=env)
    assert done.returncode == 1 and done.stdout == ""
    assert done.stderr.splitlines() == [
        "filmscale: sbatch refused the job: sbatch: error: Invalid account; sbatch: error: "
        "Batch job submission failed; the run units' job 77 was cancelled"]
    assert (calls / "scancel").read_text().split() == ["77"]
    assert not (tmp_path / "store" / "jobs.json").exists()
