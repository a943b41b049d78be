"""`filmscale calibrate` on run records takes what they hold: a simulation's rigid tip, and
the film on a substrate of the run (thickness from the record's spec; an MD substrate's E
and nu from the potential's elastic constants, a particle model's substrate as stated); the
options override each; measured curves keep diamond and no film.

The MD records are written by `md.record.write_record` from the recorded ci run (no LAMMPS
run: tests/md/test_run_recorded.py's engine stand-in), once as run (a Cu half-space) and
once under the spec of the quick preset (2.2 nm Cu on Ni). The oracles are the specs'
stated values and, for the Ni substrate, the Voigt-Reuss-Hill E and nu of nickel's measured
elastic constants, which the CuNi potential was fitted to."""

import json
from dataclasses import replace

import numpy as np
import pytest

from filmscale.continuum.elasticity import cubic_stiffness, voigt_reuss_hill
from filmscale.md import engine as md_engine
from filmscale.md import record as md_record
from filmscale.md import run as md_run
from filmscale.md.analysis import analyze_indentation
from filmscale.md.spec import PRESETS, preset
from filmscale.workflows.cli import main
from tests.helpers.engines import RecordedEngine

TIP_NOTE = "filmscale: tip material: rigid (from the record)"


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """(half-space record, film record) of the recorded ci run."""
    out = tmp_path_factory.mktemp("records")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(md_run, "run_input", RecordedEngine())
        mp.setattr(md_record, "lammps_info", dict)      # provenance without loading LAMMPS
        run = md_run.run_indentation(preset("ci"), out / "run")
        analysis = analyze_indentation(run)
        half = md_record.write_record(run, analysis, None, out / "ci.h5")
        film = md_record.write_record(replace(run, spec=preset("quick")), analysis, None,
                                      out / "film.h5")
    return str(half), str(film)


def _calibrate(capsys, *args):
    status = main(["calibrate", *args, "--nu", "0.34", "--json"])
    out, err = capsys.readouterr()
    return status, (json.loads(out) if status == 0 else None), err


def test_a_half_space_record_gives_a_rigid_tip_and_no_film(records, capsys):
    status, d, err = _calibrate(capsys, records[0])
    assert status == 0
    assert d["inputs"]["tip_material"] == "rigid"
    assert d["inputs"]["tip_material_from"] == "record"
    assert d["inputs"]["film_thickness"] is None and d["inputs"]["substrate"] is None
    assert d["inputs"]["from"] == "record"
    assert err.count(TIP_NOTE) == 1
    # a rigid tip's depth zero is fitted (`calibrate`'s default for rigid tips)
    assert any(w.startswith("contact zero fitted") for w in d["warnings"])
    # the text output says what came from the record
    assert main(["calibrate", records[0], "--nu", "0.34"]) == 0
    out = capsys.readouterr().out
    assert "tip material: rigid (from the record)" in out
    assert "target: a half-space (from the record)" in out


def test_tip_material_option_overrides_the_record(records, capsys):
    status, d, err = _calibrate(capsys, records[0], "--tip-material", "diamond")
    assert status == 0 and TIP_NOTE not in err
    assert d["inputs"]["tip_material"] == "diamond"
    assert d["inputs"]["tip_material_from"] == "option"
    assert not any(w.startswith("contact zero fitted") for w in d["warnings"])


def test_film_thickness_and_substrate_options_override_the_record(records, capsys):
    status, d, _ = _calibrate(capsys, records[1], "--substrate", "200GPa,0.3")
    assert status == 0
    inputs = d["inputs"]
    assert inputs["film_thickness"] == pytest.approx(2.2e-9, rel=1e-12)   # the quick film
    assert inputs["film_thickness_from"] == "record" and inputs["substrate_from"] == "option"
    assert inputs["substrate"]["E"] == 200e9 and inputs["substrate"]["nu"] == 0.3
    assert inputs["from"] == "record and option"
    assert "on a film of 2.2 nm" in d["model"]
    status, d, _ = _calibrate(capsys, records[1], "--film-thickness", "3 nm",
                              "--substrate", "200GPa,0.3")
    assert status == 0 and d["inputs"]["from"] == "option"
    assert d["inputs"]["film_thickness"] == pytest.approx(3e-9)
    assert "on a film of 3 nm" in d["model"]


def test_a_film_record_gives_its_thickness_and_the_substrate_from_the_potential(records,
                                                                                 capsys):
    try:
        md_engine.load_library()
    except Exception as exc:         # the substrate's constants take a LAMMPS run
        pytest.skip(f"LAMMPS unavailable: {exc}")
    status, d, err = _calibrate(capsys, records[1])
    assert status == 0 and err.count(TIP_NOTE) == 1
    inputs = d["inputs"]
    film = PRESETS["quick"]["slab"]["films"][0]
    assert inputs["film_thickness"] == pytest.approx(film["thickness"], rel=1e-12)
    assert inputs["from"] == "record" and inputs["tip_material"] == "rigid"
    # nickel, Simmons & Wang (1971): C11 246.5, C12 147.3, C44 124.7 GPa
    nickel = voigt_reuss_hill(cubic_stiffness(246.5e9, 147.3e9, 124.7e9))
    assert inputs["substrate"]["E"] == pytest.approx(nickel.E, rel=0.01)
    assert inputs["substrate"]["nu"] == pytest.approx(nickel.nu, rel=0.01)
    assert inputs["substrate"]["name"] == "Ni"
    assert "CuNi" in inputs["substrate_how"]
    assert "on a film of 2.2 nm on Ni" in d["model"]


def _particle_record(tmp_path, monkeypatch):
    """A particle-model indentation record of an elastic 0.5 um film (120 GPa) on a 200 GPa
    substrate: Hertz's loading of the film under the 1 um rigid sphere."""
    from filmscale.md.particle_run import ParticleRun, write_particle_record
    from filmscale.md.particle_spec import preset as particle_preset
    from filmscale.md.particle_spec import spec_from_mapping
    data = particle_preset("ci", "indent", "peri").to_dict()
    data.pop("kind")
    data["target"]["films"] = [{"thickness": 5e-7, "E": 120e9, "nu": 0.25, "name": "film",
                                "density": 8900.0}]
    data["target"]["substrate"].update(E=200e9, nu=0.25, name="steel", density=7800.0)
    spec = spec_from_mapping(data, "indent")
    t1 = spec.loading.times[0]
    t = np.linspace(t1 / 60, t1, 60)
    h = spec.loading.depth * t / t1
    P = 4 / 3 * 120e9 / (1 - 0.25**2) * np.sqrt(1e-6) * h**1.5
    run_dir = tmp_path / "particles"
    run_dir.mkdir()
    (run_dir / "state.json").write_text(json.dumps({"input": "in.particles", "engine": {}}))
    (run_dir / "in.particles").write_text("# stand-in\n")
    run = ParticleRun(spec, run_dir, t, h, P, np.zeros_like(t), (), 60, 0.0)

    class Result:
        def to_dict(self):
            return {"P_max": float(P.max())}
    monkeypatch.setattr(md_engine, "lammps_info", dict)
    return str(write_particle_record(run, Result(), path=tmp_path / "particles.h5"))


def test_a_particle_record_gives_its_film_substrate_and_fixed_zero(tmp_path, monkeypatch,
                                                                   capsys):
    path = _particle_record(tmp_path, monkeypatch)
    status, d, err = _calibrate(capsys, path)
    assert status == 0 and err.count(TIP_NOTE) == 1
    inputs = d["inputs"]
    assert inputs["tip_material"] == "rigid" and inputs["from"] == "record"
    assert inputs["film_thickness"] == pytest.approx(5e-7)
    assert inputs["substrate"] == {"E": 200e9, "nu": 0.25, "sigma_y": None, "name": "steel"}
    # a particle model's surface is where its contact law puts it: the zero stays fixed
    assert inputs["contact_zero"] == "fixed" and inputs["contact_zero_from"] == "record"
    assert not any(w.startswith("contact zero fitted") for w in d["warnings"])
    status, d, _ = _calibrate(capsys, path, "--contact-zero", "fit")
    assert status == 0 and d["inputs"]["contact_zero_from"] == "option"


def test_records_and_measured_curves_do_not_mix_without_a_tip_material(records, tmp_path,
                                                                       capsys):
    h = np.linspace(1e-10, 4e-10, 40)
    (tmp_path / "m.csv").write_text(
        "h [nm], P [uN]\n" + "".join(f"{a * 1e9:.6f}, {2e-8 * (a / 4e-10)**1.5 * 1e6:.8f}\n"
                                     for a in h))
    status = main(["calibrate", records[0], str(tmp_path / "m.csv"), "--tip", "sphere:0.8nm"])
    assert status == 2
    assert "give --tip-material" in capsys.readouterr().err


def test_an_md_record_gives_its_films_own_poisson_ratio(records, tmp_path, capsys):
    """A record with its film's elastic constants: `calibrate` assumes their Hill nu, not
    0.3 (an a-C block's 0.135 moved its E by 10 %); --nu overrides it; a record without them
    keeps 0.3. Oracle: an isotropic C built here from Lame's constants of E = 655 GPa and
    nu = 0.135, whose every average is that nu."""
    from filmscale.continuum.elasticity import voigt_reuss_hill
    from filmscale.md.elastic import ElasticConstants
    E, nu = 655e9, 0.135
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] = lam + 2 * mu
    C[np.arange(3, 6), np.arange(3, 6)] = mu
    elastic = ElasticConstants("SiC_tersoff", "C", "amorphous", C, (3e-9,) * 3, 1e-3, 0.0,
                               voigt_reuss_hill(C))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(md_run, "run_input", RecordedEngine())
        mp.setattr(md_record, "lammps_info", dict)
        run = md_run.run_indentation(preset("ci"), tmp_path / "run")
        path = str(md_record.write_record(run, analyze_indentation(run), elastic,
                                          tmp_path / "with_elastic.h5"))
    assert main(["calibrate", path, "--json"]) == 0
    out, err = capsys.readouterr()
    d = json.loads(out)
    assert d["nu_from"] == "record" and d["nu"] == pytest.approx(nu, rel=1e-9)
    assert "filmscale: nu 0.135 (from the record" in err
    assert main(["calibrate", path, "--nu", "0.2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["nu_from"] == "option" and d["nu"] == 0.2
    assert main(["calibrate", records[0], "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["nu_from"] == "default" and d["nu"] == 0.3


def test_several_runs_of_one_protocol_are_an_ensemble(tmp_path, capsys):
    """Three records of one protocol (the recorded ci run, its load scaled by 0.9 and 1.1:
    seeds that differ) give E's std as the members' standard error, computed here from
    each record calibrated alone, where one joint fit's covariance would say far less."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(md_run, "run_input", RecordedEngine())
        mp.setattr(md_record, "lammps_info", dict)
        run = md_run.run_indentation(preset("ci"), tmp_path / "run")
        analysis = analyze_indentation(run)
        paths = [str(md_record.write_record(
            replace(run, curve=replace(run.curve, P=run.curve.P * k)), analysis, None,
            tmp_path / f"seed{i}.h5")) for i, k in enumerate((1.0, 0.9, 1.1))]
    alone = [_calibrate(capsys, p)[1]["E"] for p in paths]
    status, d, err = _calibrate(capsys, *paths)
    assert status == 0
    assert "an ensemble of 3 runs of one protocol" in err
    sem = np.std(alone, ddof=1) / np.sqrt(3)
    assert d["E_std"] == pytest.approx(sem, rel=1e-9)
    assert min(alone) < d["E"] < max(alone)


def test_an_md_curve_carries_its_rigid_base_and_the_calibration_names_it(tmp_path, capsys):
    """The base lies at the fixed atoms' top: the run's surface less the spec's
    fixed_thickness. A record's calibration states what it does to E."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(md_run, "run_input", RecordedEngine())
        mp.setattr(md_record, "lammps_info", dict)
        run = md_run.run_indentation(preset("ci"), tmp_path / "run")
        path = md_record.write_record(run, analyze_indentation(run), None, tmp_path / "ci.h5")
    H = run.z_surface - preset("ci").slab.fixed_thickness
    assert run.curve.meta["base_depth"] == pytest.approx(H, rel=1e-12)
    status, d, _ = _calibrate(capsys, str(path))
    assert status == 0
    assert any(w.startswith(f"a rigid base {H:.3g} m under the surface") for w in d["warnings"])
