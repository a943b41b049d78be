"""The pop-in law (issue 30): Hertz to the pop-in load, the burst, then the elastic-plastic
law. Oracle: synthetic displacement-controlled curves written in the test from Hertz's closed
form (Johnson 1985) and the law, with pop-in loads drawn around a known mean; the largest
shear stress 0.31 p0 computed here from the generating E and load."""

import math

import numpy as np
import pytest

from filmscale.continuum.calibration import calibrate_sphere
from filmscale.continuum.calibration.ensemble import calibrate_ensemble
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve

LAW = contact_law("komvopoulos-ye-continuous")
E, NU, SY, R = 120e9, 0.3, 2e9, 10e-9
E_STAR = E / (1 - NU**2)
P_POP, P_POP_SCATTER = 2e-7, 0.05        # N; relative curve-to-curve scatter


def hertz(h):
    return 4 / 3 * E_STAR * math.sqrt(R) * h**1.5


def burst_curve(rng, P_pop, noise=0.01, points=300):
    """Hertz up to the approach where it carries P_pop, then (a load drop under displacement
    control) the law with (E, SY) to 3 times that approach; noise of 1 % of the largest
    load."""
    h_pop = (P_pop / (4 / 3 * E_STAR * math.sqrt(R)))**(2 / 3)
    h = np.linspace(3 * h_pop / points, 3 * h_pop, points)
    P = np.where(h <= h_pop, hertz(h), LAW.contact(h, R, E_STAR, SY, NU).force)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                 indenter=f"sphere:{R * 1e9:g}nm", meta={"source": "synthetic"})


def curves(n=6, seed=2):
    rng = np.random.default_rng(seed)
    loads = P_POP * (1 + P_POP_SCATTER * rng.standard_normal(n))
    return [burst_curve(rng, p) for p in loads], loads


def test_the_law_between_bursts_is_hertz_then_the_flow_branch():
    cs, loads = curves(n=1)
    cal = calibrate_sphere(cs[0], nu=NU, elastic="law")    # the curve is a paraboloid's
    h, P, F = cal.fitted_curves[0]
    before = h < 0.9 * (loads[0] / (4 / 3 * E_STAR * math.sqrt(R)))**(2 / 3)
    # the forward model is Hertz with the fitted E* before the pop-in
    E_fit = cal.E.value / (1 - NU**2)
    assert F[before] == pytest.approx(4 / 3 * E_fit * math.sqrt(R) * h[before]**1.5,
                                      rel=1e-9)
    assert cal.pop_in["members"] == 1 and math.isnan(cal.pop_in["load_std"])


@pytest.mark.parametrize("seed", [2, 3, 4])
def test_E_pop_in_load_and_sigma_y_within_three_std(seed):
    """Six curves fitted together (one contact zero, each curve's own pop-in). Fitted one by
    one and averaged, the members' E is biased by about -3 % at this noise with the zero
    fitted, within each member's own std (3-4 %) but not within the standard error of their
    mean (seed 2: 116.7 +- 0.95 GPa for 120 GPa): `calibrate_ensemble` takes the joint fit
    (test below)."""
    cs, loads = curves(seed=seed)
    cal = calibrate_sphere(cs, nu=NU)
    assert abs(cal.E.value - E) < 3 * cal.E.std
    assert abs(cal.sigma_y.value - SY) < 3 * cal.sigma_y.std
    pop = cal.pop_in
    sem = pop["load_std"] / math.sqrt(pop["members"])
    assert pop["members"] == len(cs)
    assert abs(pop["load"] - P_POP) < 3 * sem
    # the drawn loads' own scatter, within the sampling error of a std over 6 draws
    assert pop["load_std"] == pytest.approx(np.std(loads, ddof=1), rel=0.35)
    # tau_max = 0.31 p0 with p0 = (6 P E*^2 / (pi^3 R^2))^(1/3) (Johnson 1985)
    tau = 0.31 * (6 * P_POP * E_STAR**2 / (math.pi**3 * R**2))**(1 / 3)
    assert abs(pop["shear_stress"] - tau) < 3 * pop["shear_stress_std"] / math.sqrt(len(cs))
    # the whole curve but the burst passes at the seed-to-seed or curve noise
    check = cal.cross_check(exclude="burst")
    assert check.passed, check.text()


def test_the_pop_in_law_passes_where_the_law_alone_fails():
    cs, _ = curves(n=1, seed=5)
    law_alone = calibrate_sphere(cs[0], nu=NU, split_at_pop_in=False).cross_check()
    pop_in_law = calibrate_sphere(cs[0], nu=NU).cross_check(exclude="burst")
    assert not law_alone.passed and pop_in_law.passed
    assert pop_in_law.rms < 2.6 * 0.01


@pytest.mark.parametrize("seed", [2, 3, 4])
def test_an_ensemble_is_unbiased_and_carries_the_pop_in_statistics(seed):
    cs, _ = curves(seed=seed)
    cal = calibrate_ensemble(cs, nu=NU)
    assert abs(cal.E.value - E) < 3 * cal.E.std
    assert abs(cal.sigma_y.value - SY) < 3 * cal.sigma_y.std
    assert cal.pop_in["members"] == len(cs)
    assert abs(cal.pop_in["load"] - P_POP) < 3 * cal.pop_in["load_std"] / math.sqrt(len(cs))
    assert cal.cross_check(exclude="burst").passed


def test_a_film_s_elastic_loading_is_the_exact_layered_solution():
    """A 2 nm film (130 GPa) on a 220 GPa substrate under a rigid 1.5 nm sphere: the elastic
    loading to a pop-in at 0.4 nm written with the converged layered solution
    (`coated_sphere_load`, its own root search per approach), the law after it, 0.2 % noise.
    The film's E comes back within 1 % (measured -0.13 %; the Gao-weighted Hertz load read
    it 5.7 % low)."""
    from filmscale.continuum.contact.coated import coated_sphere_load
    from filmscale.continuum.materials import ElasticPlastic
    film_E, t, R_md, sub = 130e9, 2e-9, 1.5e-9, ElasticPlastic(220e9, 0.3, name="substrate")
    film = ElasticPlastic(film_E, NU, 1.0)
    h = np.linspace(0.6e-9 / 150, 0.6e-9, 150)
    elastic = coated_sphere_load(h, R_md, t, film, sub)
    after = LAW.contact(h, R_md, film_E / (1 - NU**2), 15e9, NU).force
    P = np.where(h <= 0.4e-9, elastic, np.minimum(after, 0.75 * elastic))
    P = P + np.random.default_rng(1).normal(0, 0.002 * P.max(), P.size)
    curve = LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                  indenter="sphere:1.5nm", meta={"source": "film"})
    cal = calibrate_sphere(curve, nu=NU, thickness=t, substrate=sub, elastic="law")
    assert "exact layered solution" in cal.model
    assert cal.E.value == pytest.approx(film_E, rel=0.01)
