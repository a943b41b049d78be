"""ULSPH (smd/ulsph) particle model: the generated input, and LAMMPS runs of a bonded film
against the layered-elasticity solution (`continuum.contact.coated`) and an elastic-plastic
film that yields."""

import math

import numpy as np
import pytest

from filmscale.continuum.contact.coated import coated_sphere_load
from filmscale.continuum.contact.hertz import hertz_force
from filmscale.continuum.indentation.curves import LOAD
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.md.lammps_input import check_input
from filmscale.md.particle_inputs import input_text
from filmscale.md.particle_run import read_snapshot, run_particles
from filmscale.md.particles import (Grid, IndentLoading, ParticleImpactSpec, ParticleIndentSpec,
                                    ParticleMaterial, ParticleTarget)
from filmscale.md.ulsph_inputs import UlsphSettings, ulsph_material

R = 1e-6
NU = 0.3
SUB = ParticleMaterial(ElasticPlastic(70e9, NU, name="sub"), 2700.0)
FILM = ParticleMaterial(ElasticPlastic(200e9, NU, name="film"), 2700.0)
#: the small block of the LAMMPS tests: R/8, 1.5 R wide and deep, quarter model (2 197
#: particles); the film is 3 lattice planes
GRID = Grid(R / 8, 1.5 * R, 1.5 * R)
T_FILM = 0.375e-6


def spec(films=(), depth=0.1 * R, frames=0, name="ulsph-test", grid=GRID):
    return ParticleIndentSpec(name, "ulsph", ParticleTarget(SUB, films), "sphere:1um",
                              IndentLoading(depth, 50.0, frames=frames), grid)


def test_material_line_converts_to_um_gpa_ns():
    line = ulsph_material(SUB)
    # by hand: K = 70/(3*0.4) = 58.333 GPa, G = 70/2.6 = 26.923 GPa, rho = 2.7 pg/um^3,
    # c0 = sqrt(K/rho) = sqrt(58.333/2.7) = 4.6481 um/ns
    words = line.split()
    assert words[:6] == ["*COMMON", "2.7", words[2], "0.06", "1.0", "1.0"]
    assert float(words[2]) == pytest.approx(math.sqrt(58.333333 / 2.7), rel=1e-6)
    assert words[6:] == ["*EOS_LINEAR", "*STRENGTH_LINEAR", words[8], "*END"]
    assert float(words[8]) == pytest.approx(26.923077, rel=1e-6)
    plastic = ParticleMaterial(ElasticPlastic(200e9, 0.25, 5e9, name="f"), 3500.0)
    words = ulsph_material(plastic, UlsphSettings(q1=0.1, hourglass=False)).split()
    # G = 200/2.5 = 80 GPa, sigma_y 5 GPa, no hardening; hourglass amplitude 0 turns it off
    assert words[3:6] == ["0.1", "1.0", "0.0"]
    assert words[6:] == ["*EOS_LINEAR", "*STRENGTH_LINEAR_PLASTIC", "80", "5", "0", "*END"]


def test_layered_input_bonds_the_film_by_a_cross_interaction():
    text = input_text(spec(((T_FILM, FILM),)))
    check_input(text)            # every command and fix style is in the allow-list
    lines = text.splitlines()
    assert "pair_style smd/ulsph *DENSITY_CONTINUITY *VELOCITY_GRADIENT *GRADIENT_CORRECTION" \
        in lines
    coeffs = [ln for ln in lines if ln.startswith("pair_coeff")]
    assert [c.split()[1:3] for c in coeffs] == [["1", "1"], ["2", "2"], ["1", "2"]]
    assert coeffs[2] == "pair_coeff 1 2 *CROSS"       # after both materials, as ULSPH needs
    # the film: the 3 lattice planes z = 0, -0.125, -0.25 um
    assert "region layer1 block INF INF INF INF -0.3125 0.0625 units box" in lines
    assert "fix integration target smd/integrate_ulsph" in lines
    assert "boundary s s s" in lines
    # the penalty stiffness follows the stiffest layer: 100 E*_film = 100 * 200/0.91 GPa
    k = [ln for ln in lines if ln.startswith("fix ind_interior")][0].split()[4]
    assert float(k) == pytest.approx(100 * 200 / (1 - NU**2), rel=1e-9)


def test_ulsph_specs_refused_where_the_model_does_not_apply():
    hardening = ParticleMaterial(ElasticPlastic(70e9, NU, 300e6, 0.1, name="al"), 2700.0)
    with pytest.raises(InputError, match=r"al\.n = 0\.1.*valid: n = 0"):
        spec(((T_FILM, hardening),))
    with pytest.raises(InputError, match="indentation only"):
        ParticleImpactSpec("imp", "ulsph", ParticleTarget(SUB), "sphere:1um", 1e-14, 50.0, GRID)
    with pytest.raises(InputError, match="ulsph.density"):
        UlsphSettings(density="exact")


def loading(run):
    c = run.curve()
    m = c.segment == LOAD
    return c.h[m], c.P[m]


def smoothed(h, P, at, half_width=0.01 * R):
    """P at depths ``at`` from least squares of P against h^1.5 over +-half_width: the
    ripple of rings of particles entering the contact averages out."""
    out = []
    for x in at:
        m = np.abs(h - x) <= half_width
        basis = h[m] ** 1.5
        out.append(float(basis @ P[m] / (basis @ basis)) * x**1.5)
    return np.array(out)


@pytest.mark.slow     # two runs, 22 s of LAMMPS alone; over a minute on a shared machine
def test_bonded_film_follows_the_layered_elastic_solution(tmp_path):
    """Film 0.375 um, E = 200 GPa on 70 GPa: the layered load over the same model's
    homogeneous load against the coated half-space's load over Hertz's on the substrate."""
    runs = {name: run_particles(spec(films, name=f"ulsph-{name}"), tmp_path / name)
            for name, films in (("homogeneous", ()), ("layered", ((T_FILM, FILM),)))}
    depths = np.array([0.05, 0.07, 0.09]) * R      # contact 2-3 spacings wide and more
    P = {k: smoothed(*loading(r), depths) for k, r in runs.items()}
    ratio = P["layered"] / P["homogeneous"]
    exact = coated_sphere_load(depths, R, T_FILM, FILM.material, SUB.material) \
        / hertz_force(depths, R, SUB.material.plane_strain_modulus)
    # measured here: -0.8, +2.1, +0.3 %; at R/10 and R/12.5 on larger blocks within 1.3 %
    # (docs/particles.md); 10 % is the bound and 5x the measured spread
    np.testing.assert_allclose(ratio, exact, rtol=0.10)
    assert np.all(ratio > 1.4)     # the stiff film shows: the substrate alone gives 1


@pytest.mark.slow
def test_elastic_plastic_film_yields_and_finishes(tmp_path):
    plastic = ParticleMaterial(ElasticPlastic(200e9, NU, 5e9, name="film"), 2700.0)
    s = spec(((T_FILM, plastic),), frames=4, name="ulsph-plastic")
    run = run_particles(s, tmp_path / "plastic")
    assert np.all(np.isfinite(run.load)) and run.load.max() > 0
    snaps = [read_snapshot(p) for p in run.snapshots]
    for snap in snaps:
        assert snap.positions.shape == (s.grid.n_particles, 3)   # no particle lost
        assert np.all(np.isfinite(snap.positions))
    # the film yields under the tip (plastic strain only grows) and leaves an impression
    assert snaps[-1].plastic_strain.max() > 0.01
    h, P = loading(run)
    assert run.depth[-1] > 0.1 * h.max()
