"""A rigid base under a simulated sample stiffens its curve; the calibration says by how much.

The curves are written here: Hertz's rigid sphere on a half-space (Johnson 1985), with the
approach held back by Boussinesq's displacement at the base's depth H, u(H) = c P,
c = (1 + nu)(3 - 2 nu) / (2 pi E H) (the first-order block of docs/particles.md)."""

import math
import re

import numpy as np
import pytest

from filmscale.continuum.calibration.sphere import calibrate_sphere
from filmscale.continuum.indentation.curves import LoadDisplacementCurve

E, NU, R = 100e9, 0.3, 1e-6
E_STAR = E / (1 - NU**2)


def based_curve(H, *, depth=0.1 * R, noise=0.002, seed=0, points=200):
    P = np.linspace(1e-3, 1.0, points) * 4 / 3 * E_STAR * math.sqrt(R) * depth**1.5
    hertz = (3 * P / (4 * E_STAR * math.sqrt(R))) ** (2 / 3)
    held = (1 + NU) * (3 - 2 * NU) / (2 * math.pi * E * H) * P
    P = P + np.random.default_rng(seed).normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(hertz - held, P, segment=np.zeros(points, int),
                                 indenter=f"sphere:{R * 1e6:g}um", meta={"base_depth": H})


def stated_excess(cal) -> float:
    note = next(w for w in cal.warnings if "rigid base" in w)
    return float(re.search(r"E reads at least about ([\d.]+)% high", note).group(1)) / 100


@pytest.mark.parametrize("H", [2e-6, 4e-6, 8e-6])
def test_the_note_states_how_high_the_base_reads_e(H):
    """Measured: E 18.6, 9.1 and 4.8 % high where the note says 16.9, 8.5 and 4.3 % (it is
    first order, evaluated at the deepest point)."""
    cal = calibrate_sphere(based_curve(H), nu=NU)
    excess = cal.E.value / E - 1
    assert excess > 0.02
    assert stated_excess(cal) <= excess <= 1.25 * stated_excess(cal)


@pytest.mark.parametrize("H", [2e-6, 4e-6, 8e-6])
def test_with_the_zero_fitted_the_note_is_a_lower_estimate(H):
    """A fitted contact zero absorbs part of the base's displacement as an offset and the
    fit reads E higher still: measured 25.8, 12.4 and 6.5 % against 16.4, 8.4 and 4.2 %
    stated, about 1.5 times, as the note says."""
    cal = calibrate_sphere(based_curve(H), nu=NU, fit_zero=True)
    ratio = (cal.E.value / E - 1) / stated_excess(cal)
    assert 1.3 <= ratio <= 1.7


def test_no_note_without_a_base_or_far_from_it():
    far = calibrate_sphere(based_curve(1e-3), nu=NU)
    assert abs(far.E.value / E - 1) < 0.01
    assert not any("rigid base" in w for w in far.warnings)
    bare = calibrate_sphere(LoadDisplacementCurve(
        based_curve(1e-3).h, based_curve(1e-3).P, segment=np.zeros(200, int),
        indenter="sphere:1um"), nu=NU)
    assert not any("rigid base" in w for w in bare.warnings)


def test_a_base_within_three_contact_radii_is_beyond_the_estimate():
    depth = 0.01 * R
    a = math.sqrt(R * depth)
    cal = calibrate_sphere(based_curve(2.2 * a, depth=depth), nu=NU)
    assert any("beyond a first-order estimate" in w for w in cal.warnings)
