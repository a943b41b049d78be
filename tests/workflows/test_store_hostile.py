"""The store stays inside itself (docs/security.md): a store whose folders or files are
links, whose ``done.json`` names files outside its unit, huge files or a hostile nesting, a
read-only store and names with escape sequences. Nothing is read or written through a link,
a damaged unit is set aside and computed again (the results equal the first run's), and
`status` reads a read-only store without creating a file and prints every name escaped.
Oracles: the first run's own results, the files outside the store byte for byte, the
store's listing before and after."""

import contextlib
import hashlib
import json
import os
import resource
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from filmscale.core.files import shown
from filmscale.workflows.cli import main
from tests.helpers.curves import sphere_curve_file
from tests.helpers.results import scene_results
from tests.helpers.scenes import BASE, CURVES_FILM


@pytest.fixture(autouse=True)
def _no_slurm(monkeypatch):
    """No SLURM queue: `status` and `cancel` would ask ``squeue``, which waits seconds for a
    controller where one is installed but not running; these tests are about the store."""
    from filmscale.workflows import slurm
    monkeypatch.setattr(slurm, "queue_states", lambda job_ids: {})


def _scene_file(tmp_path) -> Path:
    sphere_curve_file(tmp_path)
    path = tmp_path / "s.toml"
    path.write_text(BASE.format(R=1e-6, m=1e-12, V=1.0, t=2e-6, impactor_extra="",
                                film=CURVES_FILM, want='["maxima"]'))
    return path


def _first_run(tmp_path, capsys):
    """A curves scene run once: (scene file, store, its calibration unit)."""
    scene, store = _scene_file(tmp_path), tmp_path / "store"
    assert main(["run", str(scene), "--store", str(store), "--out", str(tmp_path / "a.h5")]) == 0
    capsys.readouterr()
    unit = next(p for p in store.glob("calibration-*") if p.is_dir())
    return scene, store, unit


def _rerun(tmp_path, scene, store, capsys) -> str:
    """Run the scene again (into b.h5): its stderr; the results equal the first run's."""
    code = main(["run", str(scene), "--store", str(store), "--out", str(tmp_path / "b.h5")])
    err = capsys.readouterr().err
    assert code == 0, err
    assert scene_results(tmp_path / "b.h5") == scene_results(tmp_path / "a.h5")
    return err


def _status(store, capsys, *extra) -> str:
    code = main(["status", str(store), *extra])
    out = capsys.readouterr()
    assert code == 0, out.err
    return out.out


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _rewrite_checksums(unit: Path, files: dict[str, str]) -> None:
    record = json.loads((unit / "done.json").read_text())
    record["checksums"]["files"] = files
    (unit / "done.json").write_text(json.dumps(record))


def _sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def test_a_unit_folder_that_is_a_link_is_set_aside_and_nothing_is_written_outside(
        tmp_path, capsys):
    """The calibration unit replaced by a link to a folder outside the store that holds a
    fit.npz of its own (and no done.json): the run sets the link aside (the link, not what it
    points to) and computes the unit again in a real folder."""
    scene, store, unit = _first_run(tmp_path, capsys)
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "fit.npz").write_bytes(b"the user's own fit.npz")
    (outside / "notes.txt").write_text("not the store's")
    before = _files(outside)
    shutil.rmtree(unit)
    unit.symlink_to(outside, target_is_directory=True)
    err = _rerun(tmp_path, scene, store, capsys)
    assert _files(outside) == before
    assert f"unit {unit.name} is corrupted ({unit} is a symbolic link" in err
    assert unit.is_dir() and not unit.is_symlink() and (unit / "done.json").is_file()
    aside = list(store.glob(f"{unit.name}.corrupt-*"))
    assert len(aside) == 1 and aside[0].is_symlink() and aside[0].resolve() == outside


@pytest.mark.parametrize("name", ["fit.npz", "done.json"])
def test_a_file_of_a_unit_that_is_a_link_is_not_read_through(tmp_path, capsys, name):
    """A file of a finished unit replaced by a link to an identical copy outside the store
    (its checksum still matches): the unit is not reused through the link but set aside."""
    scene, store, unit = _first_run(tmp_path, capsys)
    outside = tmp_path / f"outside-{name}"
    shutil.copyfile(unit / name, outside)
    before = outside.read_bytes()
    (unit / name).unlink()
    (unit / name).symlink_to(outside)
    out = _status(store, capsys)
    assert f"{unit / name} is a symbolic link" in out and "corrupted" in out
    err = _rerun(tmp_path, scene, store, capsys)
    assert f"unit {unit.name} is corrupted ({unit / name} is a symbolic link" in err
    assert outside.read_bytes() == before
    assert not (unit / name).is_symlink()


def test_a_lock_file_that_is_a_link_is_set_aside(tmp_path, capsys):
    """``<unit>.lock`` replaced by a link to a file outside the store: the lock is never
    opened through it (no truncation of the file it points to)."""
    scene, store, unit = _first_run(tmp_path, capsys)
    lock = Path(f"{unit}.lock")
    outside = tmp_path / "precious.txt"
    outside.write_text("precious")
    lock.unlink()
    lock.symlink_to(outside)
    err = _rerun(tmp_path, scene, store, capsys)
    assert outside.read_text() == "precious"
    assert f"lock file {lock} is a symbolic link" in err
    assert lock.is_file() and not lock.is_symlink()


@pytest.mark.parametrize("named", ["/etc/hostname", "../x", "absolute"])
def test_checksums_naming_a_file_outside_the_unit_are_a_damaged_unit(tmp_path, capsys, named):
    """done.json lists, with its right checksum, a file outside the unit instead of
    fit.npz, and fit.npz is damaged: not reused (formerly BadZipFile), set aside."""
    scene, store, unit = _first_run(tmp_path, capsys)
    if named == "absolute":
        target = tmp_path / "outside.bin"
        target.write_bytes(b"outside the store")
        named = str(target)
    elif named == "../x":
        target = store / "x"
        target.write_bytes(b"beside the unit")
    else:
        target = Path(named)
        if not target.is_file():
            pytest.skip(f"{named} does not exist here")
    _rewrite_checksums(unit, {named: _sha256(target)})
    (unit / "fit.npz").write_bytes(b"damaged")
    out = _status(store, capsys)
    assert f"its checksums name {named}, not a plain file name of the unit" in out
    err = _rerun(tmp_path, scene, store, capsys)
    assert f"unit {unit.name} is corrupted" in err


def test_checksums_leaving_out_the_file_a_reuse_reads_are_a_damaged_unit(tmp_path, capsys):
    """done.json lists no file at all and fit.npz is damaged: the unit is not reused."""
    scene, store, unit = _first_run(tmp_path, capsys)
    _rewrite_checksums(unit, {})
    (unit / "fit.npz").write_bytes(b"damaged")
    assert "its checksums leave out fit.npz" in _status(store, capsys)
    assert f"unit {unit.name} is corrupted" in _rerun(tmp_path, scene, store, capsys)


@contextlib.contextmanager
def _memory_cap(extra: int):
    """The process's address space capped at its present size plus ``extra`` bytes (the soft
    limit, restored after): reading a file of gigabytes whole fails at once."""
    try:
        with open("/proc/self/status") as f:
            size = next(int(line.split()[1]) * 1024 for line in f
                        if line.startswith("VmSize:"))
    except (OSError, StopIteration):
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = size + extra if hard == resource.RLIM_INFINITY else min(hard, size + extra)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def test_checksums_naming_a_huge_file_refuse_it_by_its_size_unread(tmp_path, capsys):
    """A sparse 4 GiB file in the unit, named in done.json: `status` refuses it by its size
    (fstat) with the memory capped at 256 MiB more than in use (formerly read whole:
    MemoryError)."""
    scene, store, unit = _first_run(tmp_path, capsys)
    with open(unit / "big.bin", "wb") as f:
        f.truncate(4 * 2**30)
    _rewrite_checksums(unit, {"fit.npz": _sha256(unit / "fit.npz"), "big.bin": "0" * 64})
    with _memory_cap(256 * 2**20):
        out = _status(store, capsys)
    assert "big.bin is larger than" in out and "corrupted" in out
    assert f"unit {unit.name} is corrupted" in _rerun(tmp_path, scene, store, capsys)


def test_a_deeply_nested_record_is_a_damaged_unit(tmp_path, capsys):
    """done.json nested 10000 deep: read with the bounded reader (formerly RecursionError)."""
    scene, store, unit = _first_run(tmp_path, capsys)
    (unit / "done.json").write_text("[" * 10000 + "]" * 10000)
    out = _status(store, capsys)
    assert "corrupted" in out and "nests tables and arrays more than" in out
    assert f"unit {unit.name} is corrupted" in _rerun(tmp_path, scene, store, capsys)


def _listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


#: runs status (JSON and text) and cancel in one process, and prints their exit codes and
#: outputs as one JSON line
_READ_ONLY_COMMANDS = """
import contextlib, io, json, sys
from filmscale.workflows import slurm
from filmscale.workflows.cli import main
slurm.queue_states = lambda job_ids: {}     # no SLURM queue (as the _no_slurm fixture)
store, results = sys.argv[1], []
for argv in (["status", store, "--json"], ["status", store], ["cancel", store]):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    results.append([code, out.getvalue(), err.getvalue()])
print(json.dumps(results))
"""


def _read_only_commands(store: Path):
    """status and cancel on ``store`` made read-only for them: as root (where file modes stop
    no write) a read-only bind mount in a private mount namespace (`unshare -m`, gone with
    the process); otherwise the store's modes (chmod a-w). A write probe first proves the
    store read-only. Skips where neither is possible."""
    command = [sys.executable, "-c", _READ_ONLY_COMMANDS, str(store)]
    probe = 'touch "$1/.write-probe" 2>/dev/null && exit 77'
    if os.geteuid() == 0:
        if shutil.which("unshare") is None:
            pytest.skip("root without unshare: no read-only mount for the store")
        script = (f'mount --bind "$1" "$1" && mount -o remount,bind,ro "$1" || exit 78; '
                  f'{probe}; shift; exec "$@"')
        done = subprocess.run(["unshare", "-m", "sh", "-c", script, "sh", str(store),
                               *command], capture_output=True, text=True, timeout=60)
        if done.returncode == 78 or "unshare" in done.stderr and done.returncode != 0:
            pytest.skip(f"no read-only bind mount possible here: {done.stderr.strip()}")
    else:
        modes = {p: p.stat().st_mode for p in [store, *store.rglob("*")]}
        for p, mode in modes.items():
            p.chmod(mode & ~0o222)
        try:
            done = subprocess.run(["sh", "-c", f'{probe}; shift; exec "$@"', "sh", str(store),
                                   *command], capture_output=True, text=True, timeout=60)
        finally:
            for p, mode in modes.items():
                p.chmod(mode)
    if done.returncode == 77:
        pytest.skip("the store could not be made read-only here")
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_status_and_cancel_read_a_read_only_store_and_create_nothing(tmp_path, capsys):
    """A finished store, one unit's lock file removed, its jobs recorded: on the read-only
    store `status` (JSON and text) and `cancel` succeed (formerly refused: status created
    lock files) and the store's listing is unchanged."""
    scene, store, unit = _first_run(tmp_path, capsys)
    Path(f"{unit}.lock").unlink()
    (store / "jobs.json").write_text(json.dumps({"sweep": "s.toml", "units": {},
                                                 "scenes": {"s-000": "4242_0"}}))
    before = _listing(store)
    (as_json, as_text, cancelled) = _read_only_commands(store)
    assert _listing(store) == before
    assert [as_json[0], as_text[0], cancelled[0]] == [0, 0, 0], (as_json, as_text, cancelled)
    rows = json.loads(as_json[1])
    assert {r["unit"]: r["state"] for r in rows} == {
        p.name: "done" for p in store.iterdir() if p.is_dir()}
    assert "2 done" in as_text[1]
    assert "cancelled nothing" in cancelled[2]


def test_status_prints_every_name_escaped(tmp_path, capsys):
    """A unit folder named with an escape sequence, and a finished unit whose checksums name
    one: the text of `status` holds no control character (the names are shown escaped,
    `core.files.shown`); its JSON escapes them as JSON does."""
    store = tmp_path / "store"
    red = "calibration-\x1b[31mred"
    (store / red).mkdir(parents=True)
    named = store / "impact-0123456789abcdef"
    named.mkdir()
    record = {"decisions": {}}
    digest = hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()
    (named / "done.json").write_text(json.dumps(
        {**record, "checksums": {"record": digest, "files": {"\x1b[2J": "0" * 64}}}))
    out = _status(store, capsys)
    assert "\x1b" not in out and "\x07" not in out
    assert shown(red) in out and shown("\x1b[2J") in out
    rows = json.loads(_status(store, capsys, "--json"))
    assert {r["unit"] for r in rows} == {red, named.name}
