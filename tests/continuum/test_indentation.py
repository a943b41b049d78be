"""Oliver-Pharr and its corrections against curves built from known properties."""

import dataclasses
import math

import numpy as np
import pytest

from filmscale.continuum.indentation import (calibrate_frame_compliance, detect_pop_in, hertz_fit,
                                             nix_gao_fit, oliver_pharr)
from filmscale.continuum.indentation.curves import LOAD, LoadDisplacementCurve
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.oliver_pharr import (FAILED, elastic_indent, sample_modulus,
                                                          shallow_depth_hardness)
from filmscale.continuum.indentation.spherical import pop_in_shear_stress
from filmscale.continuum.indentation.tips import Cone, Sphere, berkovich, parse_tip
from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.core.errors import InputError

E_R, H = 120e9, 12e9


@pytest.mark.parametrize("tip", ["berkovich", "cube-corner", "cone:60", "sphere:2um",
                                 "sphero-conical:200nm:70.3"])
@pytest.mark.parametrize("m", [1.2, 1.5, 2.0])
def test_synthetic_curves_recovered(tip, m):
    tip = parse_tip(tip)
    c = synthetic_curve(E_R, H, tip, h_c=150e-9, m=m)
    r = oliver_pharr(c, tip)
    # exact data: the power-law fit converges to round-off
    assert r.ok and not r.flags
    assert (r.E_r, r.H, r.h_c, r.m) == (pytest.approx(E_R, rel=1e-8), pytest.approx(H, rel=1e-8),
                                        pytest.approx(150e-9, rel=1e-8), pytest.approx(m, rel=1e-8))


def test_noisy_curve_recovered_within_one_percent():
    tip = berkovich()
    for seed in range(5):
        # load noise 0.2 % of P_max, unlabelled segments: the 1 % target
        c = synthetic_curve(E_R, H, tip, h_c=80e-9, m=1.4, noise=0.002, seed=seed)
        r = oliver_pharr(LoadDisplacementCurve(c.h, c.P, c.t), tip)
        assert r.E_r == pytest.approx(E_R, rel=0.01)
        assert r.H == pytest.approx(H, rel=0.01)


def test_work_quantities_closed_form():
    tip = berkovich()
    c = synthetic_curve(E_R, H, tip, h_c=100e-9, m=1.5, n_load=4001, n_unload=4000)
    r = oliver_pharr(c, tip)
    # loading P = P_max (h/h_max)^2 -> W_t = P_max h_max / 3; unloading power law ->
    # W_e = P_max (h_max - h_f) / (m + 1); trapezoid error ~ 1/n^2
    assert r.W_t == pytest.approx(r.P_max * r.h_max / 3, rel=1e-6)
    assert r.W_e == pytest.approx(r.P_max * (r.h_max - r.h_f) / 2.5, rel=1e-6)
    assert r.We_Wt == pytest.approx(r.W_e / r.W_t)


def test_epsilon_and_beta_options():
    cone = Cone(70.3)
    eps2 = 2 * (1 - 2 / math.pi)
    c = synthetic_curve(E_R, H, cone, h_c=100e-9, m=2.0, epsilon=eps2, beta=1.067)
    r = oliver_pharr(c, cone, epsilon="exponent", beta="hay", nu=0.3)
    assert r.epsilon == pytest.approx(eps2, rel=1e-8)
    assert r.beta == pytest.approx(1.067, abs=5e-4)
    assert r.E_r == pytest.approx(E_R, rel=5e-4)        # beta given to 4 digits
    r2 = oliver_pharr(c, cone, epsilon=eps2, beta=1.067)
    assert r2.h_c == pytest.approx(100e-9, rel=1e-8)
    with pytest.raises(InputError, match="needs the sample Poisson ratio"):
        oliver_pharr(c, cone, beta="no-slip")
    with pytest.raises(InputError, match="beta = 'sticky'"):
        oliver_pharr(c, cone, beta="sticky", nu=0.3)


def test_sample_modulus_inverts_the_reduced_modulus():
    sample = ElasticPlastic(70.1e9, 0.33)
    E_r = sample.reduced_modulus(DIAMOND)
    assert sample_modulus(E_r, 0.33, DIAMOND) == pytest.approx(70.1e9, rel=1e-12)
    assert math.isnan(sample_modulus(2e12, 0.3, DIAMOND))    # stiffer than diamond allows


def test_failed_analysis_is_a_result_not_an_exception():
    c = synthetic_curve(E_R, H, berkovich(), h_c=100e-9)
    load_only = LoadDisplacementCurve(c.h[:240], c.P[:240], c.t[:240])
    r = oliver_pharr(load_only, "berkovich")
    assert r.status == FAILED and "no unloading" in r.message
    assert "no_unloading" in r.flag_codes and r.to_dict()["E_r"] is None


def test_frame_compliance_from_exact_compliances():
    # 1/S = C_f + k / sqrt(P): the line's intercept is C_f exactly
    P = np.array([1e-3, 3e-3, 1e-2, 3e-2, 1e-1])
    fc = calibrate_frame_compliance(P, 1.0 / (5e-8 + 2e-7 / np.sqrt(P)))
    assert fc.C_f == pytest.approx(5e-8, rel=1e-9) and fc.slope == pytest.approx(2e-7)


def test_frame_compliance_end_to_end():
    tip, C_f = berkovich(), 0.5e-9                  # 0.5 nm/mN
    depths = np.geomspace(100e-9, 2e-6, 6)
    curves = [synthetic_curve(72e9, 9e9, tip, h_c=h, m=1.35, n_unload=400) for h in depths]
    measured = [dataclasses.replace(c, h=c.h + C_f * c.P) for c in curves]
    rs = [oliver_pharr(c, tip) for c in measured]
    fc = calibrate_frame_compliance([r.P_max for r in rs], [r.S for r in rs])
    # the frame spring bends the unloading away from a power law: the fitted S is a few
    # tenths of a percent off, which the intercept carries at the percent level
    assert fc.C_f == pytest.approx(C_f, rel=0.03)
    corrected = oliver_pharr(measured[-1].frame_corrected(fc.C_f), tip)
    assert corrected.E_r == pytest.approx(72e9, rel=0.01)


def test_shallow_depth_hardness_limits():
    tip = berkovich()
    # h_e -> 0 (stiff elastic indent, h_me = 0.75 P_e/S_e): Oliver-Pharr's P_max / A_c
    P, h_c = 1e-4, 50e-9
    H0 = shallow_depth_hardness(P, h_c, tip, P_e=1e-6, h_me=0.75e-6 / 100.0, S_e=100.0)
    assert H0 == pytest.approx(P / tip.area(h_c), rel=1e-12)
    # h_e = h_c / 2 doubles it: A_c / (pi D_c) = h_c, so H = P h_c / (A_c h_r)
    H2 = shallow_depth_hardness(P, h_c, tip, P_e=1e-6, h_me=25e-9 + 0.75e-6 / 100.0, S_e=100.0)
    assert H2 == pytest.approx(2 * P / tip.area(h_c), rel=1e-12)
    with pytest.raises(InputError, match="is not beyond the elastic depth"):
        shallow_depth_hardness(P, 10e-9, tip, P_e=1e-6, h_me=30e-9, S_e=100.0)


def test_elastic_indent_is_the_largest_without_hysteresis():
    # an elastic Hertz indent that unloads along its loading, and plastic Berkovich indents
    elastic = oliver_pharr(hertz_curve(1e-6, 100e9, 30e-9, unload=True), Sphere(1e-6))
    plastic = oliver_pharr(synthetic_curve(E_R, H, berkovich(), h_c=60e-9), berkovich())
    assert elastic.W_p / elastic.W_t < 0.01
    rs = [plastic, elastic, plastic]
    assert elastic_indent(*([getattr(r, k) for r in rs] for k in ("P_max", "W_p", "W_t"))) == 1


def hertz_curve(R, E_r, h_max, *, n=300, unload=False, pop_in=None, noise=0.0, seed=None):
    """Load-controlled Hertz loading P = 4/3 E_r sqrt(R) h^1.5, optionally a burst."""
    P_max = 4 / 3 * E_r * math.sqrt(R) * h_max**1.5
    P = np.linspace(0, P_max, n)
    h = (3 * P / (4 * E_r * math.sqrt(R)))**(2 / 3)
    if pop_in is not None:
        k, jump = pop_in
        h[k:] += jump
    if noise:
        h = h + np.random.default_rng(seed).normal(0, noise * h_max, n)
    seg = np.full(n, LOAD)
    if unload:
        P = np.concatenate([P, P[-2::-1]])
        h = np.concatenate([h, h[-2::-1]])
        seg = np.concatenate([seg, np.full(n - 1, 2)])
    return LoadDisplacementCurve(h, P, segment=seg)


def test_hertz_fit_recovers_modulus_or_radius():
    c = hertz_curve(5e-6, 80e9, 20e-9)
    assert hertz_fit(c, R=5e-6).E_r == pytest.approx(80e9, rel=1e-10)
    assert hertz_fit(c, E_r=80e9).R == pytest.approx(5e-6, rel=1e-10)
    shifted = dataclasses.replace(c, h=c.h + 2e-9)
    fit = hertz_fit(shifted, R=5e-6, fit_offset=True)
    assert fit.h_0 == pytest.approx(2e-9, rel=1e-4) and fit.E_r == pytest.approx(80e9, rel=1e-4)


@pytest.mark.parametrize("shift", [-5e-9, -20e-9, -2e-9])
def test_hertz_fit_finds_a_contact_above_the_nominal_surface(shift):
    """A surface placed too deep: the load starts at negative depth (an amorphous or rough
    top whose mean height lies below its highest atoms). The zero and E_r come back, as
    P = (4/3) E_r sqrt(R) (h - h_0)^1.5 written out here says."""
    R, E_r = 5e-6, 80e9
    h = np.linspace(0.0, 20e-9, 200)[1:] + shift
    P = 4.0 / 3.0 * E_r * np.sqrt(R) * (h - shift) ** 1.5
    fit = hertz_fit(LoadDisplacementCurve(h, P), R=R, fit_offset=True)
    assert fit.h_0 == pytest.approx(shift, abs=1e-3 * 20e-9)
    assert fit.E_r == pytest.approx(E_r, rel=1e-3)


def test_pop_in_found_and_hertz_fit_stops_there():
    c = hertz_curve(1e-6, 150e9, 15e-9, pop_in=(180, 4e-9), noise=2e-4, seed=0)
    pop = detect_pop_in(c)
    assert pop is not None and pop.index == 179
    assert pop.jump == pytest.approx(4e-9, rel=0.1)
    assert hertz_fit(c, R=1e-6).E_r == pytest.approx(150e9, rel=0.02)   # noise 2e-4 h_max
    assert detect_pop_in(hertz_curve(1e-6, 150e9, 15e-9, noise=2e-4, seed=0)) is None


def test_pop_in_shear_stress_is_031_p0():
    P, E_r, R = 1e-3, 100e9, 1e-6
    a = (3 * P * R / (4 * E_r))**(1 / 3)           # Hertz contact radius
    p0 = 3 * P / (2 * math.pi * a * a)
    assert pop_in_shear_stress(P, E_r, R) == pytest.approx(0.31 * p0, rel=1e-12)


def test_nix_gao_fit():
    h = np.geomspace(20e-9, 2e-6, 12)
    truth = 2e9 * np.sqrt(1 + 300e-9 / h)
    fit = nix_gao_fit(h, truth)
    assert (fit.H0, fit.h_star) == (pytest.approx(2e9, rel=1e-10), pytest.approx(300e-9, rel=1e-9))
    rng = np.random.default_rng(4)
    noisy = nix_gao_fit(np.repeat(h, 5), np.repeat(truth, 5) * (1 + rng.normal(0, 0.02, 60)))
    # 2 % scatter: the truth lies within 3 standard errors
    assert abs(noisy.H0 - 2e9) < 3 * noisy.H0_std
    assert abs(noisy.h_star - 300e-9) < 3 * noisy.h_star_std
    with pytest.raises(InputError, match="at least 3"):
        nix_gao_fit([1e-7, 2e-7], [1e9, 1e9])


# ---- load drops under displacement control (MD pop-ins) ----------------------------------------

def _hertz_with_drop(noise, seed=3):
    """Hertz loading P = K h^1.5 that loses 30 % of its load at h = 0.5 nm and then rises
    along a softer branch: the shape of an MD pop-in under displacement control."""
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    rng = np.random.default_rng(seed)
    h = np.linspace(-0.1e-9, 0.8e-9, 400)
    K = 40e-9 / (0.5e-9)**1.5
    P = np.where(h < 0.5e-9, K * np.clip(h, 0, None)**1.5,
                 0.7 * 40e-9 + 30e-9 * (h - 0.5e-9) / 0.3e-9)
    P = P + noise * rng.standard_normal(h.size) * (h > 0)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int)), h, P


def test_load_drop_found_at_the_peak_with_its_size():
    from filmscale.continuum.indentation.spherical import detect_load_drop
    curve, h, P = _hertz_with_drop(noise=0.2e-9)
    drop = detect_load_drop(curve)
    # the last point before the fall is within one depth step (2.3 pm) of 0.5 nm; the drop
    # is 30 % of 40 nN to within a few noise sigmas (0.2 nN each)
    assert drop.h == pytest.approx(0.5e-9, abs=2.5e-12)
    assert drop.P == pytest.approx(40e-9, abs=1e-9)
    assert drop.drop == pytest.approx(12e-9, abs=1.5e-9)
    assert drop.significance > 20


def test_no_load_drop_on_noisy_monotonic_loading():
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    from filmscale.continuum.indentation.spherical import detect_load_drop
    rng = np.random.default_rng(5)
    h = np.linspace(0, 1e-9, 400)
    P = 50e-9 * (h / 1e-9)**1.5 + 0.1e-9 * rng.standard_normal(h.size)
    assert detect_load_drop(LoadDisplacementCurve(h, P, segment=np.zeros(400, int))) is None


def test_hertz_fit_stops_at_a_load_drop():
    """Displacement control (MD): the Hertz points end at the load drop. K = 40 nN/0.5^1.5
    nm^1.5 before it (noiseless), so E_r = 3 K / (4 sqrt(R)) to round-off; the points after
    the drop, if used, would pull E_r down by tens of %."""
    from filmscale.continuum.indentation.spherical import elastic_limit
    curve, h, P = _hertz_with_drop(noise=0.0)
    K = 40e-9 / (0.5e-9)**1.5
    R = 2e-9
    assert elastic_limit(curve) == int(np.flatnonzero(h < 0.5e-9)[-1])
    assert hertz_fit(curve, R=R).E_r == pytest.approx(3 * K / (4 * np.sqrt(R)), rel=1e-9)


def test_contact_oscillations_are_not_pop_ins():
    """A particle model's contact oscillation (a 1 % dip early in the loading, the shape of
    the TLSPH ci curve) is a load drop to `detect_load_drop` but not a pop-in to
    `elastic_limit`, which needs 2 % of P_max; a 30 % drop is one."""
    from filmscale.continuum.indentation.curves import LoadDisplacementCurve
    from filmscale.continuum.indentation.spherical import detect_load_drop, elastic_limit
    h = np.linspace(0, 100e-9, 400)
    P = 1e-3 * (h / 100e-9)**1.5
    P = P - 1e-5 * np.exp(-((h - 5e-9) / 1e-9)**2)          # 1 % of P_max
    curve = LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int))
    assert detect_load_drop(curve) is not None
    assert elastic_limit(curve) is None
    drop, *_ = _hertz_with_drop(noise=0.0)
    assert elastic_limit(drop) is not None
