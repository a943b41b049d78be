"""The oblique model against finite elements: test 5 of Chung & Ooi (2011, Granular Matter 13,
643), an elastic sphere hitting a rigid plane at mu = 0.3 and constant normal speed. The FEM
points are as digitised from the paper's figure by the Kratos DEM application's benchmark data
(x = V_t / (mu V_n) before impact, y = the contact point's tangential speed over mu times the
normal speed after it, positive along the incident direction). nu is not stated with the
digitised data: 0.3 is taken; 0.23 to 0.33 moves the model's y by at most 0.05 where it is
compared below.

Where the contact slips throughout or nearly (x >= 4.7, past the curve's minimum), the model
and the FEM agree within 0.1 in y: the digitising error (about 0.03) plus the nu uncertainty.
At small angles they do not: the FEM contact point reverses its tangential speed (y < 0, as
Maw, Barber & Fawcett's Mindlin-Deresiewicz solution says), the capped Mindlin spring of
`solve_oblique` does not (y > 0). That known defect is the strict xfail below: it passes the
day the model is fixed.
"""

import math

import pytest

from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import solve_oblique
from filmscale.continuum.materials import ElasticPlastic

FEM = [(0.876, -0.080), (1.190, -0.213), (1.553, -0.373), (1.915, -0.627), (2.314, -0.947),
       (2.785, -1.253), (3.317, -1.520), (3.970, -1.720), (4.755, -1.707), (5.758, -1.200),
       (7.124, 0.133), (9.118, 2.147), (12.356, 5.427)]
MU = 0.3
GLASSY = ElasticPlastic(E=200e9, nu=0.3, sigma_y=60e9, name="elastic")   # never yields here
MODEL = ImpactModel(GLASSY, contact_law("hertz"), GLASSY)
R, M = 1e-3, 7800.0 * 4.0 / 3.0 * math.pi * 1e-9


def _y(x: float) -> float:
    res = solve_oblique(MODEL, 1.0, R, M, math.degrees(math.atan(x * MU)), MU)
    return res.restitution_contact_point * x / res.restitution


@pytest.mark.parametrize("x, y", [p for p in FEM if p[0] >= 4.7])
def test_near_and_in_gross_slip_the_model_follows_the_fem(x, y):
    assert _y(x) == pytest.approx(y, abs=0.1)


@pytest.mark.xfail(strict=True, reason="known defect: the capped Mindlin spring keeps the "
                   "contact point's direction at small angles where FEM and Maw-Barber-Fawcett "
                   "reverse it (docs/physics.md section 5)")
@pytest.mark.parametrize("x, y", [p for p in FEM if p[0] <= 1.6])
def test_at_small_angles_the_contact_point_reverses_as_in_the_fem(x, y):
    assert _y(x) < 0.0
