"""Area functions, geometry constants and beta against closed forms and published values."""

import math

import numpy as np
import pytest

from filmscale.continuum.indentation.tips import (FUSED_SILICA, Cone, FlatPunch, PolynomialArea,
                                                  Sphere, SphericalCone, berkovich, beta_hay,
                                                  beta_no_slip, calibrate_area_function,
                                                  cube_corner, epsilon_from_exponent,
                                                  fit_tip_radius, parse_tip)
from filmscale.continuum.materials import DIAMOND
from filmscale.core.errors import InputError


def test_pyramids_match_their_equivalent_cones():
    # 24.494 and 2.598 are the published ideal areas; pi tan^2 of the equivalent half-angles
    # (70.30, 42.28 deg, quoted to 0.01 deg) reproduce them to the precision of the angles
    for tip, angle in ((berkovich(), 70.30), (cube_corner(), 42.28)):
        cone = Cone(angle)
        assert tip.area(1e-7) == pytest.approx(cone.area(1e-7), rel=1.5e-3)
    assert berkovich().area(2e-7) == pytest.approx(24.494 * 4e-14, rel=1e-12)


def test_sphere_area_is_the_spherical_cap():
    R = 1e-6
    tip = Sphere(R)
    h = 0.3e-6
    a2 = R * R - (R - h)**2       # cap base radius squared, by Pythagoras
    assert tip.area(h) == pytest.approx(math.pi * a2, rel=1e-12)
    assert tip.area(2 * R) == pytest.approx(math.pi * R * R)


def test_spherical_cone_transition_is_smooth():
    tip = SphericalCone(250e-9, 70.3)
    # docs/physics.md: theta = 70.3 deg, R = 250 nm -> h_a = 14.63 nm
    assert tip.transition_depth == pytest.approx(14.63e-9, abs=0.01e-9)
    h_a = tip.transition_depth
    d = 1e-6 * h_a
    below, above = tip.area(h_a - d), tip.area(h_a + d)
    assert above - below == pytest.approx(2 * d * float(tip.area_derivative(h_a)), rel=1e-4)
    assert float(tip.area_derivative(h_a - d)) == pytest.approx(
        float(tip.area_derivative(h_a + d)), rel=1e-5)
    # far beyond the tip radius, the area approaches the cone's (offset small against h)
    assert tip.area(1e-4) == pytest.approx(Cone(70.3).area(1e-4), rel=1e-2)


def test_truncated_cone_area():
    # the MD cone: a flat of radius r0 at the apex, A = k (h_c + r0/tan(theta))^2
    r0, theta = 2e-9, 70.3
    tip = Cone(theta, tip_radius=r0)
    sharp = Cone(theta)
    assert tip.area(0.0) == pytest.approx(math.pi * r0**2, rel=1e-12)
    h0 = r0 / math.tan(math.radians(theta))
    assert tip.truncation_depth == pytest.approx(h0, rel=1e-15)
    # deep indents approach the sharp cone: relative difference 2 h0/h + (h0/h)^2 -> 0
    for h in (1e-7, 1e-6, 1e-5):
        excess = tip.area(h) / sharp.area(h) - 1.0
        assert excess == pytest.approx(2 * h0 / h, rel=1.01 * h0 / (2 * h))
    h, d = 30e-9, 1e-13
    assert float(tip.area_derivative(h)) == pytest.approx(
        (tip.area(h + d) - tip.area(h - d)) / (2 * d), rel=1e-6)
    assert Cone(theta, tip_radius=0.0) == sharp and sharp.describe()["tip_radius"] == 0.0
    assert tip.describe()["tip_radius"] == r0


def test_truncated_cone_spec_round_trip():
    for text, r0 in (("cone:70.3:0.2nm", 0.2e-9), ("cone:70.3:2e-10", 2e-10),
                     ("berkovich:5nm", 5e-9)):
        tip = parse_tip(text)
        assert isinstance(tip, Cone) and tip.tip_radius == pytest.approx(r0, rel=1e-12)
        again = parse_tip(tip.spec)
        assert again.spec == tip.spec and again.tip_radius == pytest.approx(r0, rel=1e-12)
        assert again.area_coefficient == tip.area_coefficient
    assert parse_tip("cone:70.3:0.2nm").spec == "cone:70.3:2e-10"
    assert parse_tip("cone:70.3").spec == "cone:70.3"
    with pytest.raises(InputError, match="tip_radius"):
        parse_tip("cone:70.3:-1nm")
    with pytest.raises(InputError, match="tip_radius"):
        Cone(70.3, tip_radius=1.0)


def _reference_stiffness(tip, h_c, beta=1.034):
    E_r = FUSED_SILICA.reduced_modulus(DIAMOND)
    return 2 * beta * E_r * np.sqrt(tip.area(h_c)) / math.sqrt(math.pi)


def test_tip_radius_recovered_from_reference_indents():
    truth = SphericalCone(250e-9, 70.3)
    h_c = np.geomspace(5e-9, 300e-9, 12)
    fitted = fit_tip_radius(h_c, _reference_stiffness(truth, h_c))
    assert fitted.R == pytest.approx(250e-9, rel=1e-5)   # exact data: optimiser tolerance


def test_polynomial_area_calibration_recovers_a_blunted_tip():
    truth = PolynomialArea((24.494, 4.0e-7, 2.0e-12))
    h_c = np.geomspace(10e-9, 1e-6, 15)
    fitted = calibrate_area_function(h_c, _reference_stiffness(truth, h_c), terms=3)
    assert fitted.coefficients[0] == 24.494     # kept fixed at the ideal Berkovich
    np.testing.assert_allclose(fitted.coefficients[1:], truth.coefficients[1:], rtol=1e-6)
    assert fitted.area(50e-9) == pytest.approx(truth.area(50e-9), rel=1e-9)


def test_epsilon_from_exponent_published_values():
    assert epsilon_from_exponent(1.5) == pytest.approx(0.75, abs=1e-12)
    assert epsilon_from_exponent(2.0) == pytest.approx(2 * (1 - 2 / math.pi), abs=1e-12)
    # flat-punch limit: eps ~ 1 - sqrt(2 (m - 1) / pi), 8e-5 below 1 at m - 1 = 1e-8
    assert epsilon_from_exponent(1 + 1e-8) == pytest.approx(1.0, abs=2e-4)


def test_beta_values():
    assert beta_hay(70.3, 0.3) == pytest.approx(1.067, abs=5e-4)      # docs/physics.md
    assert beta_no_slip(0.3) == pytest.approx(1.0286, abs=5e-5)
    assert beta_no_slip(0.5) == 1.0
    assert beta_hay(70.3, 0.5) == pytest.approx(1.0, abs=1e-12)       # g = 0: no correction
    assert beta_hay(45.0, 0.25) == pytest.approx(1 + (0.5 / 3.0) / 1.0, rel=1e-12)


def test_parse_tip_forms_and_errors():
    assert parse_tip("berkovich").area_coefficient == 24.494
    assert parse_tip("cone:60").half_angle == 60
    assert parse_tip("sphere:5um").R == pytest.approx(5e-6)
    assert parse_tip("sphere:2e-6").R == pytest.approx(2e-6)
    sc = parse_tip("sphero-conical:250nm:70.3")
    assert (sc.R, sc.half_angle) == (pytest.approx(250e-9), 70.3)
    assert parse_tip("flat:1um").area(1e-7) == pytest.approx(math.pi * 1e-12)
    assert FlatPunch(1e-6).epsilon == 1.0
    with pytest.raises(InputError, match="cone half_angle = 95"):
        parse_tip("cone:95")
    with pytest.raises(InputError, match="not one of"):
        parse_tip("vickers")
    with pytest.raises(InputError, match="sphere radius"):
        parse_tip("sphere:5parsecs")
