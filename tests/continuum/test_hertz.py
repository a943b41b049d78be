"""Closed forms of docs/physics.md sections 1-2 against independent computations."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from filmscale.continuum.contact.hertz import (HERTZ_DURATION_FACTOR, elastic_impact,
                                               elastic_impact_time, first_yield, hertz_force,
                                               yield_pressure_factor, yield_velocity)


def test_duration_constant_matches_direct_quadrature_and_physics_md():
    # t_c V / delta_max = 2 integral_0^1 dx / sqrt(1 - x^(5/2)) (energy conservation)
    integral, _ = quad(lambda x: 1.0 / np.sqrt(1.0 - x**2.5), 0.0, 1.0, limit=200)
    assert HERTZ_DURATION_FACTOR == pytest.approx(2.0 * integral, rel=1e-9)
    assert HERTZ_DURATION_FACTOR == pytest.approx(2.943275, abs=5e-7)  # docs/physics.md digits


def test_elastic_impact_energy_balance():
    # the Hertz work (8/15) E* R^(1/2) delta_max^(5/2) equals m V^2 / 2 (exact identity)
    m, R, V, E = 1.6e-6, 10e-6, 0.3, 100e9
    res = elastic_impact(m, R, V, E)
    work = 0.4 * res.force_max * res.delta_max
    assert work == pytest.approx(0.5 * m * V**2, rel=1e-13)
    assert res.force_max == pytest.approx(hertz_force(res.delta_max, R, E), rel=1e-14)


def test_time_history_reaches_half_duration_and_obeys_energy():
    m, R, V, E = 1e-6, 5e-6, 0.1, 80e9
    d_max = elastic_impact(m, R, V, E).delta_max
    t_half = elastic_impact(m, R, V, E).contact_time / 2
    assert elastic_impact_time(d_max, d_max, V) == pytest.approx(t_half, rel=1e-12)
    # d(delta)/dt = V sqrt(1 - (delta/delta_max)^(5/2)): finite-difference the inverse t(delta)
    d = 0.6 * d_max
    h = 1e-6 * d_max
    dt_dd = (elastic_impact_time(d + h, d_max, V) - elastic_impact_time(d - h, d_max, V)) / (2 * h)
    assert 1.0 / dt_dd == pytest.approx(V * np.sqrt(1 - 0.6**2.5), rel=1e-8)


def _on_axis_von_mises(z_over_a, nu):
    """|sigma_z - sigma_r| / p0 on the axis under a Hertz pressure (Johnson 1985 eq. 3.45)."""
    z = z_over_a
    sigma_r = -(1 + nu) * (1 - z * np.arctan(1 / z)) + 0.5 / (1 + z**2)
    sigma_z = -1 / (1 + z**2)
    return abs(sigma_z - sigma_r)


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5])
def test_yield_pressure_factor_against_exact_von_mises(nu):
    res = minimize_scalar(lambda z: -_on_axis_von_mises(z, nu), bounds=(0.05, 2.0),
                          method="bounded", options={"xatol": 1e-10})
    exact = 1.0 / -res.fun
    # docs/physics.md: the exponential fit is within 0.35 % of the exact value on [0, 0.5]
    assert yield_pressure_factor(nu) == pytest.approx(exact, rel=0.0035)


def test_first_yield_pressure_is_the_hertz_peak_pressure():
    R, E, sy, nu = 20e-6, 120e9, 3e9, 0.3
    fy = first_yield(R, E, sy, nu)
    p0 = 1.5 * fy.force / (np.pi * fy.contact_radius**2)    # Hertz: p0 = 3P/(2 pi a^2)
    assert p0 == pytest.approx(yield_pressure_factor(nu) * sy, rel=1e-13)
    assert fy.contact_radius**2 == pytest.approx(R * fy.approach, rel=1e-13)
    assert fy.force == pytest.approx(hertz_force(fy.approach, R, E), rel=1e-13)


def test_yield_velocity_reaches_exactly_the_yield_approach():
    m, R, E, sy, nu = 2e-6, 15e-6, 90e9, 2e9, 0.25
    vy = yield_velocity(m, R, E, sy, nu)
    assert elastic_impact(m, R, vy, E).delta_max == pytest.approx(
        first_yield(R, E, sy, nu).approach, rel=1e-12)
