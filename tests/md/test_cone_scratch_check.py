"""Issue 35's cone checks in MD (slow: about 9 min on 2 cores): Cu(001) scratched at 0.8 nm by
a rigid frictionless 45 deg cone (`examples/md/cone_scratch_cu.toml`), and its indentation to
the same depth.

References written here: Goddard & Wilman's ploughing friction (2/pi) cot(theta) of a
rigid-plastic groove (Wear 5, 114 (1962)); Williams' scratch hardness 8 F_n / (pi w^2)
(Tribol. Int. 29, 675 (1996)) against the indentation's load over its nominal section,
pi (r0 + h tan(theta))^2. The ploughing check holds (-15 % and -11 % over two seeds: docs/
md-indentation.md, "Cone scratch against Goddard-Wilman and Williams"); the hardness check
does not, by any width or area measured (1.25-2.2), and stands as a strict xfail.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.indentation.curves import LOAD
from filmscale.md.cone_contact import scratch_contact
from filmscale.md.engine import EngineOptions
from filmscale.md.groove_onset import indentation_twin
from filmscale.md.run import run_indentation
from filmscale.md.scratch import load_scratch_spec
from filmscale.md.scratch_run import analyze_scratch, run_scratch

pytestmark = pytest.mark.slow

SPEC = Path(__file__).resolve().parents[2] / "examples" / "md" / "cone_scratch_cu.toml"


@pytest.fixture(scope="module")
def cone_runs(tmp_path_factory, lammps_module):
    root = tmp_path_factory.mktemp("cone")
    spec = load_scratch_spec(SPEC)
    scratch = run_scratch(spec, root / "scratch", EngineOptions(np=2))
    twin = run_indentation(indentation_twin(spec, spec.stroke.depth), root / "twin",
                           EngineOptions(np=2))
    return spec, scratch, analyze_scratch(scratch), twin


def test_the_ploughing_friction_of_a_frictionless_cone_is_goddard_wilmans(cone_runs):
    spec, _, analysis, _ = cone_runs
    theta = math.radians(spec.indent.indenter.tip.half_angle)
    ploughing = 2.0 / math.pi / math.tan(theta)                  # 0.637 at 45 deg
    assert analysis.friction_mean == pytest.approx(ploughing, rel=0.20)


def test_the_contact_the_atoms_show_carries_the_recorded_load(cone_runs):
    spec, scratch, _, _ = cone_runs
    contact = scratch_contact(scratch)
    k = int(np.argmin(np.abs(scratch.data["step"] - spec.schedule().s_unload)))
    assert contact.normal_force == pytest.approx(scratch.data["fz"][k], rel=1e-3)
    # the cone touched the pile-up: the loaded contact is wider than the residual groove
    assert contact.width > analyze_scratch(scratch).groove_width


@pytest.mark.xfail(strict=True, reason="measured: Williams' scratch hardness is 1.9-2.2 times "
                   "the indentation's load over its nominal section (1.25 with the loaded "
                   "contact's width and radius): docs/md-indentation.md")
def test_williams_scratch_hardness_is_the_indentation_hardness(cone_runs):
    spec, _, analysis, twin = cone_runs
    w = analysis.groove_width
    H_scratch = 8.0 * analysis.normal_force_mean / (math.pi * w * w)
    curve = twin.curve.finite()
    end = int(np.flatnonzero(curve.segment == LOAD)[-1])
    tip = spec.indent.indenter.tip
    r = tip.tip_radius + curve.h[end] * math.tan(math.radians(tip.half_angle))
    H_indent = curve.P[end] / (math.pi * r * r)
    assert H_scratch == pytest.approx(H_indent, rel=0.15)
