"""MD ensembles: members of one protocol with pop-ins at different depths. Oracles: the
generating E and sigma_y, Hertz's own pop-in stresses from the depths the members were made
with (0.31 p0 with p0 = (2 E*/pi) sqrt(h/R), a formula of depth where the package uses one
of load), and the scatter put into the members."""

import math

import numpy as np
import pytest

from filmscale.continuum.calibration.ensemble import calibrate_ensemble, ensemble_mean
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.core.errors import InputError
from tests.helpers import curves as tc

DEPTHS = (5.0, 5.5, 6.0, 6.5, 7.0)      # pop-in depths of the members, first-yield approaches


def member(rng, at, noise=0.005, points=200):
    """Hertz (E) up to a pop-in at ``at`` first-yield approaches, then the law (E, SY)."""
    dy = float(tc.LAW.first_yield(tc.R, tc.E_STAR, tc.SY, tc.NU).approach)
    h = np.linspace(15 * dy / points, 15 * dy, points)
    hertz = 4 / 3 * tc.E_STAR * np.sqrt(tc.R) * h**1.5
    P = np.where(h <= at * dy, hertz, tc.LAW.contact(h, tc.R, tc.E_STAR, tc.SY, tc.NU).force)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                 indenter=f"sphere:{tc.R * 1e6:g}um"), dy


def test_an_ensemble_gives_the_parameters_its_scatter_and_its_pop_in_statistics():
    rng = np.random.default_rng(21)
    members = [member(rng, at) for at in DEPTHS]
    curves = [c for c, _ in members]
    dy = members[0][1]
    cal = calibrate_ensemble(curves, nu=tc.NU, tip_material="rigid")
    assert abs(cal.E.value - tc.E) < 3 * cal.E.std
    assert abs(cal.sigma_y.value - tc.SY) < 3 * cal.sigma_y.std
    assert "one fit of 5 members" in cal.uncertainty and len(cal.fitted_curves) == 5
    # the pop-in: each member's peak is its last Hertz point, or the one before where the
    # load noise makes that one higher (grid step 0.075 dy); Hertz's shear stress from the
    # depth alone, with the calibrated E*
    h = curves[0].h
    step = h[1] - h[0]
    peaks = [h[h <= at * dy].max() for at in DEPTHS]
    pop = cal.pop_in
    assert pop["members"] == 5
    assert abs(pop["depth"] - np.mean(peaks)) <= step
    assert pop["depth_std"] == pytest.approx(np.std(peaks, ddof=1), abs=step)
    E_star = cal.E.value / (1 - tc.NU**2)
    tau = [0.31 * 2 * E_star / math.pi * math.sqrt(d / tc.R) for d in peaks]
    # the package takes p0 from the load, which carries the 0.5 % load noise: 1/3 of it
    assert pop["shear_stress"] == pytest.approx(np.mean(tau), rel=0.01)
    # the seed-to-seed scatter (the pop-ins at different depths dominate it) is the noise
    # model: at least the members' white noise, and the check's tolerance is twice it
    assert cal.curve_noise > 0.005
    check = cal.cross_check()
    assert check.tolerance == pytest.approx(2 * cal.curve_noise) and \
        "seed-to-seed scatter" in check.text()


def test_members_must_share_one_protocol():
    rng = np.random.default_rng(1)
    a, _ = member(rng, 6.0)
    b, _ = member(rng, 6.0, points=150)
    with pytest.raises(InputError, match="not sampled alike"):
        ensemble_mean([a, b])
    with pytest.raises(InputError, match="at least 2 curves"):
        ensemble_mean([a])
