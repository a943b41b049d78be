"""Particle models run by LAMMPS (seconds each): elastic indentation and impact against the
Hertz closed forms, the record, rerun without LAMMPS, and the peridynamic solid."""

import json

import h5py
import numpy as np
import pytest

from filmscale.continuum.contact.hertz import hertz_force
from filmscale.continuum.indentation.curves import LOAD
from filmscale.md.particle_run import (analyze_impact, analyze_indent, block_hertz_force,
                                       read_snapshot, run_particles, write_particle_record)
from filmscale.md.particle_spec import preset
from filmscale.md.particles import Grid

R = 1e-6


def loading_error(run, base_depth):
    """rms relative difference of the loading curve over 0.3-1 h_max from the Hertz load on
    the finite block (`block_hertz_force`)."""
    c = run.curve()
    m = (c.segment == LOAD) & (c.h >= 0.3 * c.h.max())
    mat = run.spec.target.substrate.material
    ref = block_hertz_force(c.h[m], R, mat.E, mat.nu, base_depth)
    return float(np.sqrt(np.mean((c.P[m] / ref - 1) ** 2)))


@pytest.fixture(scope="module")
def ci_indent(tmp_path_factory):
    return run_particles(preset("ci", "indent"), tmp_path_factory.mktemp("ci_indent"))


def test_ci_indentation_follows_hertz_on_the_block(ci_indent):
    res = analyze_indent(ci_indent)
    # ci is R/5: measured P_max 0.94 of the block's Hertz load and 13 % rms over the loading
    # (lattice noise: rings of particles enter the contact one at a time); R/10 reaches 4.6 %
    assert res.block_ratio == pytest.approx(1.0, abs=0.10)
    assert loading_error(ci_indent, 2 * R) < 0.15
    # the curve names the block's rigid base for the calibration's note on it
    assert ci_indent.curve().meta["base_depth"] == ci_indent.spec.grid.depth == 2 * R
    # the block is stiffer than a half-space: P_max / Hertz above 1 by the base's effect
    assert 1.0 < res.hertz_ratio < 1.25
    # elastic: the surface comes back (residual under 10 % of h_max)
    assert res.residual_depth < 0.1 * res.h_max


def test_ci_record_and_rerun_without_lammps(ci_indent, tmp_path):
    res = analyze_indent(ci_indent)
    path = write_particle_record(ci_indent, res, {"command": "test"})
    with h5py.File(path, "r") as f:
        assert f.attrs["format"] == "filmscale.md_particles/1"
        assert "lammps_version" in f.attrs
        assert f["result"].attrs["P_max"] == pytest.approx(res.P_max)
        assert "in.tlsph" in f["inputs"]
        np.testing.assert_allclose(f["curve/P"][()], ci_indent.load)
    again = run_particles(ci_indent.spec, ci_indent.run_dir)     # finished: read back
    np.testing.assert_array_equal(again.load, ci_indent.load)
    snap = read_snapshot(ci_indent.snapshots[-1])
    assert snap.von_mises is not None and np.all(np.isfinite(snap.von_mises))
    assert snap.positions.shape == (ci_indent.spec.grid.n_particles, 3)


def test_ci_elastic_impact_matches_hertz(tmp_path):
    out = analyze_impact(run_particles(preset("ci", "impact"), tmp_path))
    # measured: delta_max 0.985, t_c 0.962 of Hertz, e = 0.996 (energy conserved to 1 %)
    assert out.separated
    assert out.delta_max == pytest.approx(out.hertz_delta_max, rel=0.03)
    assert out.contact_time == pytest.approx(out.hertz_contact_time, rel=0.06)
    assert 0.97 < out.restitution < 1.01
    # the block is stiffer than the half-space, so the force exceeds Hertz (measured 1.10)
    assert 1.0 < out.P_max / out.hertz_force_max < 1.2


def test_peri_ci_indentation_follows_hertz(tmp_path):
    run = run_particles(preset("ci", "indent", "peri"), tmp_path)
    # in a process of its own: after other LAMMPS runs in this process peri/lps was not
    # reproducible (1 of 4 repeats off by 12 %)
    assert json.loads((tmp_path / "state.json").read_text())["engine"]["mode"] == "mpirun"
    res = analyze_indent(run)
    # measured 1.12 at R/8: the horizon softens the free surface, the rigid base stiffens
    assert res.hertz_ratio == pytest.approx(1.0, abs=0.15)
    snap = read_snapshot(run.snapshots[-1])
    assert snap.damage is not None and np.all(snap.damage == 0)   # s00 = 1: no bond breaks


@pytest.mark.slow
def test_converged_spacing_within_five_percent_of_hertz_on_the_block(tmp_path):
    spec = preset("ci", "indent")
    spec = type(spec)(**{**spec.__dict__, "grid": Grid(R / 10, 2 * R, 2 * R)})
    run = run_particles(spec, tmp_path)
    # measured 4.6 % rms over 0.3-1 h_max, P_max 0.963 of the block's Hertz load
    assert loading_error(run, 2 * R) < 0.05
    c = run.curve()
    assert np.max(c.P) / block_hertz_force(c.h.max(), R, 70e9, 0.3, 2 * R) == \
        pytest.approx(1.0, abs=0.05)
    assert hertz_force(c.h.max(), R, 70e9 / 0.91) < np.max(c.P)


@pytest.mark.slow
def test_fine_elastic_impact_keeps_its_energy(tmp_path):
    """R/10 (about 2.5 min): an elastic impact must give e = 1. Before the impactor cluster
    was taken out of TLSPH, its particles failed at this spacing and e fell to 0.878."""
    spec = preset("ci", "impact")
    spec = type(spec)(**{**spec.__dict__, "grid": Grid(R / 10, 2 * R, 2 * R)})
    out = analyze_impact(run_particles(spec, tmp_path))
    # measured 0.997; delta_max 0.959 and t_c 0.950 of Hertz (block and penalty compliance)
    assert 0.97 <= out.restitution <= 1.01
    assert out.delta_max / out.hertz_delta_max == pytest.approx(1.0, abs=0.06)


def test_plastic_indentation_stops_at_separation_with_the_crater_residual(tmp_path):
    """Elastic-perfectly plastic Al (sigma_y 0.3 GPa) at R/5: the run halts once the
    unloading tip leaves the surface, well before the scheduled end, and the residual depth
    matches the crater model (Johnson 1985, section 11.5: Hertzian recovery from the run's
    own P_max over the Komvopoulos-Ye contact area at h_max) within 0.1 h_max: the area is
    the continuum law's, not the particles' (measured 93.5 nm against 85.8 nm at h_max
    100 nm, 0.077 h_max apart, at R/5)."""
    from dataclasses import replace

    from filmscale.continuum.contact.laws import contact_law
    from filmscale.continuum.contact.restitution import unload
    from filmscale.continuum.materials import ElasticPlastic
    from filmscale.md.particles import ParticleMaterial, ParticleTarget

    mat = ElasticPlastic(70e9, 0.3, 3e8, name="Al-pp")
    spec = replace(preset("ci", "indent"), target=ParticleTarget(ParticleMaterial(mat, 2700.)))
    run = run_particles(spec, tmp_path)
    res = analyze_indent(run)
    assert run.time[-1] < 0.9 * spec.loading.times[2]
    assert run.load[-1] <= 0.0
    E_star = mat.plane_strain_modulus
    area = contact_law("komvopoulos-ye-continuous").contact(
        res.h_max, R, E_star, mat.sigma_y, mat.nu).area
    crater = unload("crater", delta_max=res.h_max, force_max=res.P_max, area_max=area,
                    E_star=E_star, R=R, yield_approach=0.0)
    assert res.residual_depth == pytest.approx(float(crater.residual_depth),
                                               abs=0.1 * res.h_max)


@pytest.mark.slow
@pytest.mark.parametrize("alloy, measured", [("6061", 27.443e9), ("7075", None)])
def test_dao_example_specs_within_five_percent(tmp_path, alloy, measured):
    """The example specs (about 3 min each on 2 ranks): C within 5 % (issue 20's criterion)
    of Dao's forward function, and for Al 6061 of the mean of the packaged measured
    Berkovich indents (27.44 GPa, Al6061.csv). Measured: 28.4 GPa (+0.4 % and +3.4 %) and
    45.0 GPa (+0.5 %)."""
    from pathlib import Path

    from filmscale.continuum.indentation.reverse.functions import loading_curvature
    from filmscale.md.engine import EngineOptions
    from filmscale.md.particle_spec import load_spec
    spec = load_spec(Path(__file__).resolve().parents[2] / "examples" / "particles"
                     / f"dao_al{alloy}.toml", "indent")
    res = analyze_indent(run_particles(spec, tmp_path, EngineOptions(np=2, omp_threads=1)))
    mat = spec.target.substrate.material
    dao, _ = loading_curvature("berkovich", mat.E, mat.plane_strain_modulus, mat.sigma_y,
                               mat.n)
    assert res.C == pytest.approx(float(dao), rel=0.05)
    if measured is not None:
        assert res.C == pytest.approx(measured, rel=0.05)
