"""Contact laws: Hertz limit, first yield, published breakpoints and jumps, continuity."""

import math

import numpy as np
import pytest

from filmscale.continuum.contact.hertz import first_yield, hertz_force
from filmscale.continuum.contact.laws import KY_CONTINUOUS, KY_LITERAL, LAW_NAMES, contact_law
from filmscale.core.errors import InputError

R, E, SY, NU = 10e-6, 96e9, 2.4e9, 0.25


def jump(law, k):
    """Relative force jump at the k-th threshold, homogeneous target."""
    d = law.approach_at_severity(law.thresholds[k], R, E, SY, NU)
    left = law.force_area(d, R, E, SY, NU, k)[0]
    right = law.force_area(d, R, E, SY, NU, k + 1)[0]
    return right / left - 1.0


@pytest.mark.parametrize("name", LAW_NAMES)
def test_every_law_is_hertz_well_below_yield(name):
    law = contact_law(name)
    d = 1e-3 * law.first_yield(R, E, SY, NU).approach
    state = law.contact(d, R, E, SY, NU)
    # KY's truncated area gives Hertz x sqrt(1 - delta/2R): relative deviation delta/(4R)
    tol = 1e-12 + d / (4 * R)
    assert state.force == pytest.approx(hertz_force(d, R, E), rel=tol)
    assert state.area == pytest.approx(np.pi * R * d, rel=2 * tol)
    assert int(state.branch) == 0


@pytest.mark.parametrize("name, rel", [("hertz", 1e-12), ("jackson-green", 1e-12),
                                       ("kogut-etsion", 0.005), ("komvopoulos-ye", 0.02)])
def test_first_yield_against_section_2(name, rel):
    # section 2 (von Mises, C(nu)) at nu = 0.3; KE's K H = (0.454 + 0.41 nu) 2.8 sigma_Y is
    # within 0.3 % of C(nu) sigma_Y; KY's eps = 1.78 gives 6.34 against 6.43 (1.4 %)
    assert contact_law(name).first_yield(R, E, SY, 0.3).approach == pytest.approx(
        first_yield(R, E, SY, 0.3).approach, rel=rel)


def test_ky_yield_approach_matches_physics_md_coefficient():
    law = contact_law("komvopoulos-ye")
    e_large = 1e4 * SY     # delta_Y = 2R k/(1+k), k = (1.78 sigma/E*)^2: the 6.34 is k -> 0
    d_y = law.first_yield(R, e_large, SY, 0.3).approach
    assert d_y / (R * (SY / e_large) ** 2) == pytest.approx(2 * 1.78**2, rel=1e-6)
    assert 2 * 1.78**2 == pytest.approx(6.34, abs=0.005)
    # and p_m = 1.07 sigma_Y at yield (the dissertation's value)
    state = law.contact(d_y * (1 - 1e-12), R, e_large, SY, 0.3)
    assert state.mean_pressure / SY == pytest.approx(1.07, abs=0.005)


def test_ky_literal_jumps_are_the_ones_physics_md_reports():
    law = contact_law("komvopoulos-ye")
    assert not law.continuous
    assert jump(law, 0) == pytest.approx(-0.046, abs=0.001)
    # eps = 400 lies beyond delta = R unless E*/sigma_Y > 400: use a stiffer material
    d = law.approach_at_severity(400.0, R, 500 * SY, SY, NU)
    left = law.force_area(d, R, 500 * SY, SY, NU, 2)[0]
    right = law.force_area(d, R, 500 * SY, SY, NU, 3)[0]
    assert right / left - 1 == pytest.approx(0.083, abs=0.001)


def test_ky_continuous_constants_round_to_physics_md_values():
    c = KY_CONTINUOUS
    assert c["C1"] == pytest.approx(0.665, abs=5e-4)
    assert c["C2"] == pytest.approx(2.312, abs=5e-4)
    assert c["PLATEAU"] == pytest.approx(2.8, abs=5e-3)
    assert c["TAIL"] == pytest.approx(0.70, abs=0.01)
    assert KY_LITERAL["K_EL"] == pytest.approx(0.600211, abs=1e-6)


@pytest.mark.parametrize("name", ["hertz", "komvopoulos-ye-continuous", "thornton"])
def test_laws_that_claim_continuity_are_continuous(name):
    law = contact_law(name)
    assert law.continuous
    stiff = 500 * SY        # so that every threshold lies below delta = R
    for k, level in enumerate(law.thresholds):
        d = law.approach_at_severity(level, R, stiff, SY, NU)
        left, a_left = law.force_area(d, R, stiff, SY, NU, k)
        right, a_right = law.force_area(d, R, stiff, SY, NU, k + 1)
        assert right == pytest.approx(left, rel=1e-12)
        assert a_right == pytest.approx(a_left, rel=1e-12)


def test_kogut_etsion_jumps_are_the_published_fits():
    law = contact_law("kogut-etsion")
    assert not law.continuous
    assert jump(law, 0) == pytest.approx(0.03, abs=1e-12)     # 1.03 P_c against Hertz P_c
    # at 6: 1.40 x 6^1.263 / (1.03 x 6^1.425)
    assert jump(law, 1) == pytest.approx(1.40 * 6**1.263 / (1.03 * 6**1.425) - 1, rel=1e-9)


@pytest.mark.parametrize("name", LAW_NAMES)
def test_force_and_area_grow_with_approach_within_each_branch(name):
    law = contact_law(name)
    d = np.geomspace(1e-6, 0.99, 4000) * R
    state = law.contact(d, R, E, SY, NU)
    for b in np.unique(state.branch):
        sel = state.branch == b
        assert np.all(np.diff(state.force[sel]) > 0)
        assert np.all(np.diff(state.area[sel]) > 0)


@pytest.mark.parametrize("name, factor", [("komvopoulos-ye", 2.8), ("kogut-etsion", 2.8),
                                          ("thornton", 2.8)])
def test_fully_plastic_mean_pressure_tends_to_the_hardness(name, factor):
    law = contact_law(name)
    stiff = 2000 * SY
    d = 0.5 * R
    state = law.contact(d, R, stiff, SY, NU)
    # KY and KE reach their plateau exactly; Thornton's p_m = p_y (1 - a_y^2/(3 a^2)) -> p_y
    a_y2 = law.approach_at_severity(1.0, R, stiff, SY, NU) * R if name == "thornton" else 0.0
    expected = factor * SY * (1 - a_y2 / (3 * R * d))
    assert state.mean_pressure == pytest.approx(expected, rel=1e-9)
    assert law.hardness_factor == pytest.approx(factor)


def test_unknown_law_is_an_input_error():
    with pytest.raises(InputError, match="contact_law = 'hertzian'"):
        contact_law("hertzian")
    with pytest.raises(InputError, match="limiting_pressure_factor"):
        contact_law("thornton", limiting_pressure_factor=math.nan)
