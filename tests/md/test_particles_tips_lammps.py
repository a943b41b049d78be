"""Real LAMMPS runs of the particle models' Berkovich pyramid and sphero-conical tip on an
elastic block, against the elastic closed forms (slow: 5-10 min each on 2 cores)."""

from dataclasses import replace

import pytest

from filmscale.md.engine import EngineOptions
from filmscale.md.particle_run import analyze_indent, run_particles
from filmscale.md.particle_spec import load_spec
from filmscale.md.particles import Grid

pytestmark = pytest.mark.slow
EXAMPLE = "examples/particles/berkovich_elastic.toml"


def test_berkovich_example_within_five_percent_of_sneddon_with_beta(tmp_path):
    # issue 20: the pyramid against Sneddon's 70.3 deg cone times King's beta = 1.034, on the
    # block (rigid base 1.2 um down). Measured 0.992 (docs/particles.md); 5 % is the issue's
    spec = load_spec(EXAMPLE, "indent")
    out = analyze_indent(run_particles(spec, tmp_path, EngineOptions(np=2, omp_threads=1)))
    assert out.block_ratio == pytest.approx(1.0, abs=0.05)


def test_sphero_conical_tip_within_five_percent_of_sneddons_profile_solution(tmp_path):
    # R = 0.5 um rounding of a 70.3 deg cone, 0.12 um deep (past the tangent depth, 17 nm),
    # quarter model; against Sneddon's solution for that profile on the block. Measured 0.976
    spec = load_spec(EXAMPLE, "indent")
    spec = replace(spec, name="sphero-conical", tip="sphero-conical:0.5um:70.3",
                   grid=Grid(5e-8, 1.2e-6, 1.2e-6, quarter=True))
    out = analyze_indent(run_particles(spec, tmp_path, EngineOptions(np=2, omp_threads=1)))
    assert out.block_ratio == pytest.approx(1.0, abs=0.05)
