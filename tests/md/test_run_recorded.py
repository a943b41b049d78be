"""The run logic with a recorded-output fake of the engine (no LAMMPS): the curve in SI from
the recorded ci run, the analysis against the potential's published elastic constants, the
HDF5 record, and an interrupted run resumed from its last restart file."""

import json

import h5py
import numpy as np
import pytest

from filmscale.continuum.elasticity import cubic_stiffness, voigt_reuss_hill
from filmscale.continuum.indentation.curves import HOLD, LOAD, UNLOAD
from filmscale.continuum.indentation.io import read_curves
from filmscale.md import run as md_run
from filmscale.md.analysis import HERTZ_TOLERANCE, analyze_indentation
from filmscale.md.engine import parse_table
from filmscale.md.spec import preset
from tests.helpers.engines import RECORDED, RecordedEngine

EV_PER_A = 1.602176634e-9     # N


def _recorded_table():
    columns, data = parse_table((RECORDED / "indent.dat").read_text())
    data = data[np.unique(data[:, 0], return_index=True)[1]]
    return {c: data[:, i] for i, c in enumerate(columns)}


def test_curve_in_si_with_segments(tmp_path, monkeypatch):
    engine = RecordedEngine()
    monkeypatch.setattr(md_run, "run_input", engine)
    spec = preset("ci")
    run = md_run.run_indentation(spec, tmp_path / "run")
    table = _recorded_table()
    np.testing.assert_allclose(run.curve.h, table["depth"] * 1e-10, rtol=1e-15)
    np.testing.assert_allclose(run.curve.P, table["load"] * EV_PER_A, rtol=1e-15)
    s = spec.protocol.schedule()
    step = table["step"]
    assert np.all(run.curve.segment[step < s.s_hold] == LOAD)
    assert np.all(run.curve.segment[(step >= s.s_hold) & (step < s.s_unload)] == HOLD)
    assert np.all(run.curve.segment[step >= s.s_unload] == UNLOAD)
    assert run.curve.h.max() == pytest.approx(spec.protocol.depth, rel=1e-9)
    # a finished directory is read back without the engine
    md_run.run_indentation(spec, tmp_path / "run")
    assert len(engine.calls) == 1


def test_analysis_of_recorded_run_against_published_constants(tmp_path, monkeypatch):
    monkeypatch.setattr(md_run, "run_input", RecordedEngine())
    run = md_run.run_indentation(preset("ci"), tmp_path / "run")

    class Published:       # Mishin et al., PRB 63, 224106 (2001), EAM Cu1: C11, C12, C44
        C = cubic_stiffness(169.9e9, 122.6e9, 76.2e9)
        E_star = voigt_reuss_hill(C).plane_strain_modulus()

    a = analyze_indentation(run, Published)
    assert abs(a.hertz_ratio - 1.0) < HERTZ_TOLERANCE
    assert a.P_max == pytest.approx(_recorded_table()["load"].max() * EV_PER_A)
    # a plastic indent leaves a residual depth between zero and the maximum depth
    assert 0.0 < a.residual_depth < a.h_max
    # the atoms in contact at full depth: radius near the sphere's footprint sqrt(2Rh - h^2)
    # = 0.69 nm. The hull of discrete atoms lies inside the true edge by up to half a
    # nearest-neighbour spacing (0.13 nm, 19 %), and sink-in moves it further in: 25 %.
    R, h = 8e-10, 4e-10
    assert a.contact_radius_md == pytest.approx(np.sqrt(2 * R * h - h * h), rel=0.25)


def test_interrupted_run_resumes_from_last_restart(tmp_path, monkeypatch):
    spec = preset("ci")
    monkeypatch.setattr(md_run, "run_input", RecordedEngine(stop_after_step=700))
    with pytest.raises(KeyboardInterrupt):
        md_run.run_indentation(spec, tmp_path / "run")
    engine = RecordedEngine()
    monkeypatch.setattr(md_run, "run_input", engine)
    run = md_run.run_indentation(spec, tmp_path / "run")
    name, text = engine.calls[0]
    assert name == "in.resume.1" and "read_restart restart.600.bin" in text
    table = _recorded_table()
    expected = table["load"] + np.where(table["step"] > 600, 1.0, 0.0)
    np.testing.assert_allclose(run.curve.P, expected * EV_PER_A, rtol=1e-12)
    state = json.loads((tmp_path / "run" / "state.json").read_text())
    assert [p["start"] for p in state["parts"]] == [0, 600]
    assert (tmp_path / "run" / "indent.dat").exists()         # the first part is kept
    assert not list((tmp_path / "run").glob("restart.*.bin"))  # finished: no checkpoints


def test_record_holds_curve_inputs_and_provenance(tmp_path, monkeypatch):
    from filmscale.md.record import write_record
    monkeypatch.setattr(md_run, "run_input", RecordedEngine())
    run = md_run.run_indentation(preset("ci"), tmp_path / "run")
    analysis = analyze_indentation(run)
    path = write_record(run, analysis, None)
    curves = read_curves(path)
    np.testing.assert_array_equal(curves["curve"].P, run.curve.P)
    with h5py.File(path, "r") as f:
        assert f.attrs["potential_sha256"] == run.spec.potential.sha256
        assert "lammps_version" in f.attrs
        assert json.loads(f.attrs["derived_seeds"])[0]["velocity"] >= 1
        assert "fix indenter" in f["inputs/in.indent"][()].decode()
        assert f["analysis"].attrs["P_max"] == pytest.approx(analysis.P_max)
