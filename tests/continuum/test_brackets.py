"""The impact fast path's bracketed solvers against closed forms and scipy.optimize.elementwise
(the library they stand in for, to keep scipy.optimize out of the map command's start-up)."""

import numpy as np
import pytest
from scipy.optimize import elementwise

from filmscale.continuum.contact.brackets import find_maximum, find_root

EPS = np.finfo(float).eps


def test_root_of_cubics_to_four_ulps_of_the_closed_form():
    # x^3 = p over twelve decades: the root is p^(1/3); both solvers end within 4 eps |x|
    p = np.geomspace(1e-30, 1e6, 200)
    x = find_root(lambda x, p: x**3 - p, 0.0, 2.0 * np.cbrt(p) + 1e-12, args=(p,))
    exact = np.cbrt(p)
    assert np.all(np.abs(x - exact) <= 8 * EPS * exact)
    ref = elementwise.find_root(lambda x, p: x**3 - p, (0.0, 2.0 * np.cbrt(p) + 1e-12),
                                args=(p,)).x
    assert np.all(np.abs(x - ref) <= 8 * EPS * exact)


def test_root_keeps_the_shape_and_handles_zero_ends_and_a_jump():
    lo, hi = np.zeros((2, 3)), np.ones((2, 3))
    shift = np.array([[0.0, 0.25, 0.5], [0.75, 1.0, 0.3]])
    x = find_root(lambda x, s: x - s, lo, hi, args=(shift,))
    assert x.shape == (2, 3)
    np.testing.assert_allclose(x, shift, rtol=0, atol=4 * EPS)
    # a step has no zero: the bracket shrinks onto the jump (bisection fallback)
    step = find_root(lambda x, s: np.where(x < s, -1.0, 1.0), 0.0, 1.0, args=(np.array([0.3]),))
    assert abs(step[0] - 0.3) <= 4 * EPS


def test_root_refuses_a_bracket_without_a_sign_change():
    with pytest.raises(ValueError, match="opposite signs"):
        find_root(lambda x: x - 2.0, np.zeros(3), np.ones(3))


def test_maximum_of_x_exp_minus_x_over_p_is_p_over_e():
    # f = x exp(-x/p) peaks at x = p with f = p/e; the bracket puts the peak off-centre
    p = np.geomspace(1e-9, 1e3, 50)
    x, fx = find_maximum(lambda x, p: x * np.exp(-x / p), 0.3 * p, 0.8 * p, 4.0 * p, args=(p,))
    np.testing.assert_allclose(x, p, rtol=2e-7)          # the bracket width asked for
    np.testing.assert_allclose(fx, p / np.e, rtol=1e-14)  # quadratic peak: xrtol^2 in value
    ref = elementwise.find_minimum(lambda x, p: -x * np.exp(-x / p), (0.3 * p, 0.8 * p, 4.0 * p),
                                   args=(p,))
    np.testing.assert_allclose(fx, -ref.f_x, rtol=1e-14)


def test_maximum_never_returns_less_than_the_middle_value():
    # a kinked peak (|x - c|) is found to the bracket width, the value to the same
    c = np.array([0.2, 0.5, 0.9])
    x, fx = find_maximum(lambda x, c: -np.abs(x - c), 0.0, c + 0.05, 1.0, args=(c,))
    assert np.all(fx >= -0.05)
    np.testing.assert_allclose(x, c, rtol=0, atol=2e-7)
