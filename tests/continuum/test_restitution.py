"""Unloading models and closed-form restitution (docs/physics.md section 4)."""

import numpy as np
import pytest

from filmscale.continuum.contact.hertz import hertz_force
from filmscale.continuum.contact.restitution import (UNLOADING_MODELS, johnson_restitution,
                                                     thornton_restitution, unload)

R, E = 10e-6, 100e9


@pytest.mark.parametrize("model", UNLOADING_MODELS)
def test_every_model_leaves_no_crater_after_a_hertz_loading(model):
    d = 50e-9
    res = unload(model, delta_max=d, force_max=hertz_force(d, R, E), area_max=np.pi * R * d,
                 E_star=E, R=R, yield_approach=d)
    assert res.residual_depth == pytest.approx(0.0, abs=1e-12 * d)
    assert res.radius == pytest.approx(R, rel=1e-12)
    assert res.work == pytest.approx(0.4 * hertz_force(d, R, E) * d, rel=1e-12)


@pytest.mark.parametrize("model", UNLOADING_MODELS)
def test_unloading_law_passes_through_the_maximum(model):
    d, p, area = 200e-9, 0.02, np.pi * 1.2e-6**2     # a plastic state: flatter, wider than Hertz
    res = unload(model, delta_max=d, force_max=p, area_max=area, E_star=E, R=R,
                 yield_approach=10e-9)
    assert 0 < res.residual_depth < d
    assert res.force(d, E) == pytest.approx(p, rel=1e-12)
    assert res.force(res.residual_depth, E) == 0.0


def test_jackson_chusoipin_green_grows_from_zero_at_yield():
    d_y = 10e-9
    ratios = np.array([1.0, 2.0, 10.0, 100.0, 1000.0])
    res = unload("jackson-chusoipin-green", delta_max=ratios * d_y, force_max=1.0,
                 area_max=1e-12, E_star=E, R=R, yield_approach=d_y)
    frac = res.residual_depth / (ratios * d_y)
    assert frac[0] == 0.0
    assert np.all(np.diff(frac) > 0) and frac[-1] < 1


def test_johnson_fully_plastic_rebound_equals_crater_unloading():
    # constant pressure p_d on a^2 = 2 R delta, then a Hertz rebound from the crater
    m, V, p_d = 1e-6, 3.0, 5e9
    a = (2 * m * V**2 * R / (np.pi * p_d)) ** 0.25
    delta = a**2 / (2 * R)
    crater = unload("crater", delta_max=delta, force_max=p_d * np.pi * a**2,
                    area_max=np.pi * a**2, E_star=E, R=R, yield_approach=0.0)
    assert johnson_restitution(m, R, V, E, p_d) == pytest.approx(
        np.sqrt(crater.work / (0.5 * m * V**2)), rel=1e-12)
    # and e ~ V^(-1/4)
    e1, e2 = johnson_restitution(m, R, np.array([3.0, 48.0]), E, p_d)
    assert e2 / e1 == pytest.approx(16 ** -0.25, rel=1e-12)


def test_thornton_closed_form_limits():
    v_y = 1.0
    assert thornton_restitution(0.5, v_y) == 1.0
    assert thornton_restitution(1.0 + 1e-12, v_y) == pytest.approx(1.0, abs=1e-6)
    big = 1e8
    # docs/physics.md: large-V limit 1.185 (V_y/V)^(1/4); the exact prefactor is
    # sqrt(6 sqrt(3)/5) (1/(2 sqrt(6/5)))^(1/4) = 1.1852
    assert thornton_restitution(big, v_y) == pytest.approx(1.185 * big**-0.25, rel=1e-3)
