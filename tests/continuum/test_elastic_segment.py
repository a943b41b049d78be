"""What a sphere calibration takes as the elastic segment of a curve with a pop-in, and where it
puts the contact zero. Oracles: curves generated with a known E (the exact elastic sphere of
Sneddon 1965 before the pop-in, the contact law after it), with a known zero offset, or with
a known softening before the burst (the shape MD Cu(001) curves have,
docs/md-indentation.md)."""

import numpy as np
import pytest

from filmscale.continuum.calibration import calibrate
from filmscale.continuum.calibration.sphere import HERTZ_FRACTION, calibrate_sphere
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.core.errors import InputError

E, NU, SY, R = 120e9, 0.34, 8e9, 1.5e-9
E_STAR = E / (1 - NU**2)
LAW = contact_law("komvopoulos-ye-continuous")


def sneddon_load(delta, E_star):
    """P(delta) of a rigid sphere on a half-space: delta = (a/2) ln((R+a)/(R-a)),
    P = (E*/2)[(a^2 + R^2) ln((R+a)/(R-a)) - 2 a R], a found by bisection."""
    lo, hi = np.zeros_like(delta), np.full_like(delta, R * (1 - 1e-15))
    for _ in range(200):
        a = 0.5 * (lo + hi)
        low = a / 2 * np.log((R + a) / (R - a)) < delta
        lo, hi = np.where(low, a, lo), np.where(low, hi, a)
    a = 0.5 * (lo + hi)
    return E_star / 2 * ((a * a + R * R) * np.log((R + a) / (R - a)) - 2 * a * R)


def md_like_curve(rng, *, offset=0.0, softening=0.0, noise=0.005, points=200):
    """Hertz (E) up to a pop-in at 6 first-yield approaches, the law after it; ``offset``
    (m) is added to every recorded depth (a misplaced surface); ``softening`` lowers the
    Hertz load by up to that fraction, growing as (P / P_pop - 0.6) / 0.4 above 0.6 of the
    pop-in load (the pre-burst softening of MD curves)."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    delta = np.linspace(12 * dy / points, 12 * dy, points)
    # the rigid sphere's exact elastic load (Sneddon 1965), written here from its
    # parametric form: the pop-in at 6 dy lies at 0.13 R, where Hertz's paraboloid is 1.3 %
    # stiffer
    hertz = sneddon_load(delta, E_STAR)
    h_pop = 6 * dy
    P_pop = float(sneddon_load(np.array([h_pop]), E_STAR)[0])
    soft = 1 - softening * np.clip((hertz / P_pop - 0.6) / 0.4, 0.0, 1.0)
    P = np.where(delta <= h_pop, hertz * soft, LAW.contact(delta, R, E_STAR, SY, NU).force)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(delta + offset, P, segment=np.zeros(points, int),
                                 indenter=f"sphere:{R * 1e9:g}nm")


def test_softening_before_the_pop_in_stays_out_of_E():
    """A 12 % softening over the last 40 % of the pop-in load (MD Cu(001) shows 10-30 %;
    at 15 % the softened peak of this curve sinks to the law's load after the pop-in and no
    drop is left to detect): E from the elastic points below HERTZ_FRACTION of the pop-in
    load is within 3 % and 3 std of the truth; the same fit up to the burst (fraction 1) is
    more than 3 % low."""
    assert HERTZ_FRACTION <= 0.6           # the softening starts at 0.6 of the pop-in load
    curve = md_like_curve(np.random.default_rng(3), softening=0.12)
    cal = calibrate_sphere(curve, nu=NU)
    assert abs(cal.E.value - E) < 0.03 * E and abs(cal.E.value - E) < 3 * cal.E.std
    assert any(f"below {HERTZ_FRACTION:g} of its load" in w for w in cal.warnings)
    to_burst = calibrate_sphere(curve, nu=NU, hertz_fraction=1.0)
    assert (E - to_burst.E.value) / E > 0.03


@pytest.mark.parametrize("offset_fraction", [-0.08, 0.08])
def test_a_fitted_contact_zero_recovers_E_from_a_misplaced_surface(offset_fraction):
    """Depths recorded 8 % of the pop-in depth off the true zero (either way): with the zero
    fitted, E within 3 % and 3 std and the offset within 20 % of itself; with it fixed, E is
    more than 5 % off (P ~ h^1.5 turns a depth shift into a modulus error)."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    offset = offset_fraction * 6 * dy
    curve = md_like_curve(np.random.default_rng(5), offset=offset)
    fit = calibrate(curve, nu=NU, tip_material="rigid", contact_zero="fit")
    assert abs(fit.E.value - E) < 0.03 * E and abs(fit.E.value - E) < 3 * fit.E.std
    note = next(w for w in fit.warnings if w.startswith("contact zero fitted"))
    h0 = float(note.split("h0 = ")[1].split(" m")[0])
    assert h0 == pytest.approx(offset, rel=0.2)
    fixed = calibrate(curve, nu=NU, tip_material="rigid", contact_zero="fixed")
    assert abs(fixed.E.value - E) / E > 0.05


def test_the_contact_zero_is_fitted_for_rigid_tips_and_fixed_for_diamond():
    """The default follows the tip material: a rigid tip (a simulated surface) fits the zero
    (the offset curve gives E within 3 %), a diamond tip holds it (the result carries 0)."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    curve = md_like_curve(np.random.default_rng(5), offset=0.48 * dy)
    rigid = calibrate(curve, nu=NU, tip_material="rigid")
    assert rigid.contact_zero != 0.0 and rigid.E.value == pytest.approx(E, rel=0.03)
    assert calibrate(curve, nu=NU, tip_material="diamond").contact_zero == 0.0


def test_a_fitted_zero_on_a_smooth_curve_and_its_refusals():
    """Without a pop-in the zero is fitted with E and sigma_y together (joint path): the
    law's own curve shifted by 5 % of its depth gives back E within 3 %. A sharp tip refuses
    a fitted zero; an unknown choice is named."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    delta = np.linspace(20 * dy / 150, 20 * dy, 150)
    P = LAW.contact(delta, R, E_STAR, SY, NU).force
    P = P + np.random.default_rng(8).normal(0.0, 0.005 * P.max(), P.size)
    curve = LoadDisplacementCurve(delta + 1.0 * dy, P, segment=np.zeros(150, int),
                                  indenter=f"sphere:{R * 1e9:g}nm")
    fit = calibrate(curve, nu=NU, tip_material="rigid", contact_zero="fit")
    assert fit.E.value == pytest.approx(E, rel=0.03)
    assert fit.sigma_y.value == pytest.approx(SY, rel=0.1)
    with pytest.raises(InputError, match="contact zero"):
        calibrate(curve, nu=NU, tip="berkovich", contact_zero="fit")
    with pytest.raises(InputError, match="contact zero = 'auto'"):
        calibrate(curve, nu=NU, contact_zero="auto")
