"""A rigid base under a simulated sample stiffens its curve. The calibration models a film's
stated base in its exact elastic branch; where it does not (a half-space, or
``model_base=False``), it says by how much the base reads E high.

The note's curves are written here: Hertz's rigid sphere on a half-space (Johnson 1985), with the
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


def test_a_film_on_a_slab_with_its_base_in_the_model_reads_its_own_e():
    """A film on a substrate slab on a rigid base, the curve from the exact stack solution
    (`coated.stack_sphere_curve`, checked against closed forms in test_coated_stack.py): with
    ``base_depth`` in the curve's meta the calibration models the base and returns the film's
    E within its std, noting nothing. Without it the same curve is misread: measured, the
    elastic-plastic law fits the base's stiffening better than the unbased elastic solution
    and reads E 22 % low with a sigma_y it calls identified."""
    from filmscale.continuum.contact.coated import RIGID, stack_sphere_curve
    from filmscale.continuum.materials import ElasticPlastic
    film, substrate = ElasticPlastic(E, NU, 1e9), ElasticPlastic(300e9, 0.2, 5e9)
    t, H, depth = 0.5e-6, 1.5e-6, 0.05e-6
    h = np.linspace(1e-3, 1.0, 150) * depth
    P = stack_sphere_curve(h, R, [(t, film), (H - t, substrate)], RIGID)
    P = P + np.random.default_rng(3).normal(0.0, 0.002 * P.max(), P.size)

    def curve(meta):
        return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                     indenter="sphere:1um", meta=meta)
    modelled = calibrate_sphere(curve({"base_depth": H}), nu=NU, thickness=t,
                                substrate=substrate)
    assert abs(modelled.E.value / E - 1) < max(3 * modelled.E.std / E, 0.005)
    assert any("exact layered solution" in w and "rigid base 1.5" in w for w in modelled.warnings)
    assert not any("reads" in w and "high" in w for w in modelled.warnings)
    free = calibrate_sphere(curve({}), nu=NU, thickness=t, substrate=substrate)
    assert abs(free.E.value / E - 1) > 0.05
    # model_base=False keeps the base out of the model and says so
    noted = calibrate_sphere(curve({"base_depth": H}), nu=NU, thickness=t, substrate=substrate,
                             model_base=False)
    assert abs(noted.E.value / E - 1) > 0.05
    assert any("rigid base" in w and "high" in w for w in noted.warnings)


def test_seeds_of_one_slab_share_its_base_and_different_slabs_do_not():
    """Seeds of one MD spec state base depths a few tenths of a per cent apart (their
    surfaces' thermal heights): one base at their mean. Slabs 10 % apart: the note."""
    from filmscale.continuum.contact.coated import RIGID, stack_sphere_curve
    from filmscale.continuum.materials import ElasticPlastic
    film, substrate = ElasticPlastic(E, NU, 1e9), ElasticPlastic(300e9, 0.2, 5e9)
    t, H = 0.5e-6, 1.5e-6
    h = np.linspace(1e-3, 1.0, 120) * 0.05e-6

    def curves(depths):
        return [LoadDisplacementCurve(h, stack_sphere_curve(h, R, [(t, film), (H - t, substrate)],
                                                             RIGID),
                                      segment=np.zeros(h.size, int), indenter="sphere:1um",
                                      meta={"base_depth": d}) for d in depths]
    seeds = calibrate_sphere(curves([H, 1.003 * H, 0.998 * H]), nu=NU, thickness=t,
                             substrate=substrate)
    assert any("exact layered solution" in w and "rigid base" in w for w in seeds.warnings)
    assert seeds.E.value == pytest.approx(E, rel=0.005)
    slabs = calibrate_sphere(curves([H, 1.1 * H]), nu=NU, thickness=t, substrate=substrate)
    assert not any("exact layered solution" in w and "rigid base" in w for w in slabs.warnings)
    assert any("rigid base" in w and "high" in w for w in slabs.warnings)
