"""Published restitution closed forms (continuum/contact/restitution_fits.py)."""

import numpy as np
import pytest

from filmscale.continuum import ElasticPlastic, ImpactModel
from filmscale.continuum.contact.hertz import yield_velocity
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.restitution_fits import (THORNTON_HIGH_SPEED_FACTOR,
                                                          thornton_1997, thornton_high_speed,
                                                          thornton_yield_ratio)
from filmscale.core.errors import InputError

STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=0.7e9, name="steel")


def test_thornton_printed_values():
    # docs/physics.md section 4, from Thornton (1997)
    e = thornton_1997([2.0, 5.0, 10.0, 100.0])
    np.testing.assert_allclose(e, [0.930626, 0.773337, 0.658558, 0.374299], atol=1e-6)


def test_thornton_is_one_up_to_yield_and_falls_after():
    assert np.all(thornton_1997([0.2, 1.0]) == 1.0)
    e = thornton_1997(np.geomspace(1.0, 1e3, 50))
    assert np.all(np.diff(e) < 0)


def test_high_speed_limit():
    assert THORNTON_HIGH_SPEED_FACTOR == pytest.approx(1.185, abs=5e-4)   # physics.md
    assert thornton_1997(1e8) / thornton_high_speed(1e8) == pytest.approx(1.0, abs=1e-6)
    assert 0.0 < 1.0 - thornton_1997(12.0) / thornton_high_speed(12.0) < 0.01


def test_yield_ratio_matches_the_thornton_law():
    # independent route: the law's own first-yield speed over section 2's V_Y
    R, m = 1e-3, 3.3e-5
    E_star = STEEL.E / (1.0 - STEEL.nu**2)
    V_Y = yield_velocity(m, R, E_star, STEEL.sigma_y, STEEL.nu)
    for f in (2.0, 2.8):
        law = contact_law("thornton", limiting_pressure_factor=f)
        V_y = law.first_yield(R, E_star, STEEL.sigma_y, STEEL.nu, mass=m).velocity
        assert V_y / V_Y == pytest.approx(thornton_yield_ratio(f, STEEL.nu), rel=1e-10)
    assert thornton_yield_ratio(1.295 * np.exp(0.736 * 0.3), 0.3) == pytest.approx(1.0)


def test_thornton_law_with_crater_reproduces_the_closed_form_in_V_Y_units():
    R, m = 1e-3, 7850.0 * 4.0 / 3.0 * np.pi * 1e-9
    V_Y = yield_velocity(m, R, STEEL.E / (1.0 - STEEL.nu**2), STEEL.sigma_y, STEEL.nu)
    ratio = np.array([2.0, 10.0, 100.0, 1000.0])
    e = ImpactModel(STEEL, contact_law("thornton"), None, "crater").maxima(
        ratio * V_Y, R, m).restitution
    np.testing.assert_allclose(e, thornton_1997(ratio / thornton_yield_ratio(2.8, 0.3)),
                               rtol=1e-8)


def test_inputs_are_checked():
    with pytest.raises(InputError):
        thornton_high_speed(0.0)
    with pytest.raises(InputError):
        thornton_yield_ratio(-1.0, 0.3)
