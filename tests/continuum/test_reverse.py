"""Sharp-indentation reverse analysis (docs/physics.md section 10) against independent
references: the round-trip oracle of docs/physics.md, the FE cases and accuracy figures of the
packaged data README (Lu et al. 2020 data, Dao et al. 2001 experiments), and
self-consistency."""

import dataclasses
import json
import math

import numpy as np
import pytest

from filmscale.continuum.indentation.reverse.dao import (dao_forward, dao_reverse,
                                                         dao_reverse_repeated)
from filmscale.continuum.indentation.reverse.data import dao2001_table
from filmscale.continuum.indentation.reverse.dual import dual_reverse
from filmscale.continuum.indentation.reverse.functions import (DAO_RATIO_RANGE, METHODS, PI1_DAO,
                                                               PI1_THETA, dao_pi1,
                                                               representative_strain,
                                                               sharp_calibration, sharp_tip)
from filmscale.continuum.indentation.reverse.surrogate import surrogate_hyperparameters
from filmscale.continuum.indentation.reverse.validation import cross_validate, fe_error_table
from filmscale.continuum.indentation.tips import Cone, berkovich
from filmscale.core.errors import InputError, ModelRangeError

ORACLE = dict(E=70.1e9, nu=0.33, sigma_y=0.5e9, n=0.122, h_m=1e-6)   # docs/physics.md section 10


def oracle_forward(**kw):
    return dao_forward(ORACLE["E"], ORACLE["nu"], ORACLE["sigma_y"], ORACLE["n"], ORACLE["h_m"],
                       E_i=1100e9, nu_i=0.07, **kw)


def reverse_of(f, **kw):
    return dao_reverse(f.C, f.dPdh, f.WpWt, f.h_m, **kw)


# --- oracle and self-consistency ------------------------------------------------------------

def test_round_trip_oracle_to_the_printed_digits():
    # docs/physics.md prints E* = 73.440 GPa, sigma_0.033 = 0.6173 GPa, C = 43.840 GPa,
    # dP/dh = 4.3354e5 N/m, W_p/W_t = 0.8242, h_r/h_m = 0.8713: half a unit of the last digit
    f = oracle_forward()
    assert f.E_star == pytest.approx(73.440e9, abs=0.0005e9)
    assert f.sigma_r == pytest.approx(0.6173e9, abs=0.00005e9)
    assert f.C == pytest.approx(43.840e9, abs=0.0005e9)
    assert f.dPdh == pytest.approx(4.3354e5, abs=0.00005e5)
    assert f.WpWt == pytest.approx(0.8242, abs=0.00005)
    assert f.hr_hm == pytest.approx(0.8713, abs=0.00005)
    assert f.warnings == ()


@pytest.mark.parametrize("E, nu, sigma_y, n, tip", [
    (70.1e9, 0.33, 0.5e9, 0.122, "berkovich"),
    (210e9, 0.30, 0.9e9, 0.15, "berkovich"),
    (10e9, 0.30, 0.1e9, 0.30, "berkovich"),
    (120e9, 0.25, 0.6e9, 0.40, "cone:70.3"),
])
def test_forward_then_reverse_recovers_the_material(E, nu, sigma_y, n, tip):
    # self-consistency: only root-finder tolerances (near machine precision) separate the two
    f = dao_forward(E, nu, sigma_y, n, 2e-6, tip=tip)
    r = dao_reverse(f.C, f.dPdh, f.WpWt, 2e-6, tip=tip, nu=nu)
    assert r.E_star == pytest.approx(f.E_star, rel=1e-9)
    assert r.E == pytest.approx(E, rel=1e-9)
    assert r.sigma_r == pytest.approx(f.sigma_r, rel=1e-9)
    assert r.n == pytest.approx(n, abs=1e-9)
    assert r.sigma_y == pytest.approx(sigma_y, rel=1e-8)
    assert r.hr_hm == pytest.approx(f.hr_hm, abs=1e-9)


def test_published_constants_are_consistent():
    # docs/physics.md: eps_r(theta) gives 0.0335 at 70.3 deg; Pi1 is monotone exactly between its
    # stationary points E*/sigma = 3.85 and 804 (derivative zero there to the printed digits)
    assert float(representative_strain(70.3)) == pytest.approx(0.0335, abs=5e-5)
    dpi1 = np.polyder(PI1_DAO)
    for ratio in DAO_RATIO_RANGE:
        assert abs(np.polyval(dpi1, math.log(ratio))) < 0.02 * abs(dao_pi1(math.log(ratio)))
    tip = sharp_calibration(sharp_tip("cone:60"))
    assert tip.pi1 == PI1_THETA[60.0] and tip.c_star == 1.1957
    berk = sharp_calibration(sharp_tip("berkovich"))
    assert (berk.c_star, berk.eps_r, berk.pi1) == (1.2370, 0.033, PI1_DAO)


# --- the packaged FE cases and Al 6061 -------------------------------------------------------

def test_fe_convention_rigid_indenter_nu_03_depth_02um():
    # the FE files omit h_m and the E* convention; E* = E/(1 - 0.3^2) with h_m = 0.2 um
    # reproduces the 70-deg dP/dh (Pi2) to about 1.4 % median, while E* = E misses by ~10 %
    t = dao2001_table("FEM_70deg.csv")

    def median_error(nu):
        pred = [dao_forward(E, nu, s, n, 0.2e-6, tip="cone:70.3", E_i=math.inf).dPdh
                for E, s, n in zip(t["E"], t["sigma_y"], t["n"])]
        return np.median(np.abs(np.array(pred) / t["dPdh"] - 1))

    assert median_error(0.3) < 0.02
    assert median_error(1e-9) > 0.05


def test_closed_form_within_the_readme_accuracy_on_fe_cases():
    # data README: forward C within about 4 % (median), reverse E* about 6-7 % and sigma_0.033
    # about 4-8 % (median). Measured: C 1.6 / 1.0 %, E* 7.6 / 5.3 %, sigma 7.8 / 3.7 %
    # (Berkovich / 70-deg); "about 6-7 %" is read as < 8 % for the 14 Berkovich cases.
    rows = {(r["file"], r["method"]): r for r in fe_error_table()}
    for name in ("Berkovich.csv", "FEM_70deg.csv"):
        row = rows[(name, "closed-form")]
        assert row["C_median"] < 0.04
        assert row["E_star_median"] < 0.08
        assert row["sigma_r_median"] < 0.08
    for name in ("FEM_50deg.csv", "FEM_60deg.csv", "FEM_80deg.csv"):
        assert rows[(name, "closed-form")]["C_median"] < 0.04      # Chollacoop Pi1_theta
    json.dumps(fe_error_table(), allow_nan=False)


def test_surrogate_beats_the_closed_form_in_nested_cross_validation():
    # measured (5 folds, seed 0, nested selection): surrogate E* 3.08 % median / 8.7 % p90,
    # sigma_0.033 3.13 % / 9.1 %; closed form 5.42 % / 12.1 % and 3.93 % / 12.9 %.
    # Bounds sit a little above the measured values (other seeds give 2.9-3.4 %).
    cv = cross_validate(k=5, seed=0)
    assert cv.surrogate.E_star_median < 0.036
    assert cv.surrogate.sigma_r_median < 0.036
    assert cv.surrogate.E_star_p90 < 0.10
    assert cv.surrogate.E_star_median < 0.7 * cv.closed_form.E_star_median
    assert cv.surrogate.sigma_r_median < cv.closed_form.sigma_r_median
    # a material of the Berkovich file recurs in the 70-deg file: both in one fold
    b = [i for i, f in enumerate(cv.file) if f == "Berkovich.csv"]
    c = {int(cv.case[i]): int(cv.fold[i]) for i, f in enumerate(cv.file) if f != "Berkovich.csv"}
    assert all(c[int(cv.case[i])] == cv.fold[i] for i in b)
    assert len(cv.hyperparameters) == 5
    json.dumps(cv.to_dict(), allow_nan=False)
    assert surrogate_hyperparameters()["cases"] == 114


def test_al6061_indents_loose_check():
    # data README: on the six measured Al 6061 indents the closed form gives E* about 15 %
    # high (measured: +16.5 % on the mean); loose bounds because measured data are harder than
    # the FE database. The surrogate, trained on FE, lands closer (measured +5 %).
    t = dao2001_table("Al6061.csv")
    kw = dict(nu=0.33, E_i=1100e9, nu_i=0.07)
    closed = dao_reverse_repeated(t["C"], t["dPdh"], t["WpWt"], t["h_m"], **kw)
    sur = dao_reverse_repeated(t["C"], t["dPdh"], t["WpWt"], t["h_m"], method="surrogate", **kw)
    E_star, s033 = t["E_star"][0], t["sigma_0.033"][0]
    assert 0.10 < closed.E_star / E_star - 1 < 0.25
    assert abs(closed.sigma_r / s033 - 1) < 0.10
    assert abs(sur.E_star / E_star - 1) < abs(closed.E_star / E_star - 1)
    assert abs(sur.E_star / E_star - 1) < 0.10
    assert abs(sur.sigma_r / s033 - 1) < 0.10
    assert closed.samples == 6 and closed.E_star_std > 0


# --- dual indenter -----------------------------------------------------------------------------

@pytest.mark.parametrize("tip2", ["cone:50", "cone:60", "cone:80", "cone:65"])
def test_dual_indenter_recovers_a_known_material(tip2):
    # synthetic C, dP/dh, W_p/W_t (Berkovich) and C2 from the same functions: exact recovery
    E, nu, sigma_y, n = 100e9, 0.3, 0.4e9, 0.2
    b = dao_forward(E, nu, sigma_y, n, 1e-6)
    c2 = dao_forward(E, nu, sigma_y, n, 1e-6, tip=tip2).C
    r = dual_reverse(b.C, b.dPdh, b.WpWt, 1e-6, c2, tip2=tip2)
    assert r.n == pytest.approx(n, abs=1e-9)
    assert r.sigma_y == pytest.approx(sigma_y, rel=1e-9)
    assert r.E == pytest.approx(E, rel=1e-9)
    assert r.sigma_r2 == pytest.approx(
        dao_forward(E, nu, sigma_y, n, 1e-6, tip=tip2).sigma_r, rel=1e-9)
    assert any("interpolated" in w for w in r.warnings) == (tip2 == "cone:65")


def test_dual_indenter_no_hardening_and_fe_accuracy():
    E, nu, sigma_y = 100e9, 0.3, 0.4e9
    b = dao_forward(E, nu, sigma_y, 0.0, 1e-6)
    c2 = dao_forward(E, nu, sigma_y, 0.0, 1e-6, tip="cone:60").C
    exact = dual_reverse(b.C, b.dPdh, b.WpWt, 1e-6, c2, tip2="cone:60")
    assert exact.n == pytest.approx(0.0, abs=1e-9) and exact.warnings == ()
    # the 60 deg tip (larger strain) reads a lower stress: no hardening, n = 0, with a warning
    soft = dual_reverse(b.C, b.dPdh, b.WpWt, 1e-6, 0.97 * c2, tip2="cone:60")
    assert soft.n == 0.0 and soft.sigma_y == pytest.approx(soft.sigma_r, rel=1e-12)
    assert any("no hardening" in w for w in soft.warnings)
    # FE: pairing the 70.3 and 50 deg cones pins n to 0.017 (median) against 0.13 for one tip
    rows = {r["file"]: r for r in fe_error_table()}
    assert rows["FEM_70deg.csv + FEM_50deg.csv"]["n_median"] < 0.03
    with pytest.raises(ModelRangeError, match="eps_r"):
        dual_reverse(b.C, b.dPdh, b.WpWt, 1e-6, b.C, tip2="cone:70.3")


# --- uncertainty -----------------------------------------------------------------------------

def test_zero_input_std_gives_zero_output_std():
    r = reverse_of(oracle_forward(), nu=0.33)
    assert (r.E_star_std, r.sigma_r_std, r.n_std, r.sigma_y_std, r.E_std) == (0, 0, 0, 0, 0)
    assert r.samples == 0 and r.seed is None


def test_monte_carlo_std_is_linear_reproducible_and_matches_linearisation():
    f = oracle_forward()
    std = dict(C_std=2e-3 * f.C, dPdh_std=2e-3 * f.dPdh, WpWt_std=1e-3)
    r1 = reverse_of(f, nu=0.33, **std)
    r2 = reverse_of(f, nu=0.33, **{k: 2 * v for k, v in std.items()})
    # common random numbers: doubling a small input std doubles each output std (to ~1 %)
    for key in ("E_star_std", "sigma_r_std", "n_std", "sigma_y_std"):
        assert getattr(r2, key) == pytest.approx(2 * getattr(r1, key), rel=0.01)
    assert reverse_of(f, nu=0.33, **std).to_dict() == r1.to_dict()
    assert reverse_of(f, nu=0.33, seed=1, **std).E_star_std != r1.E_star_std
    # independent reference: first-order propagation with central differences; 2000 draws
    # estimate a std to about 1.6 %, so 6 % is four standard errors
    base = dict(C=f.C, dPdh=f.dPdh, WpWt=f.WpWt)
    var = {"E_star": 0.0, "sigma_r": 0.0}
    for name, s in zip(base, std.values()):
        h = 1e-3 * s
        up = dao_reverse(**{**base, name: base[name] + h}, h_m=f.h_m, nu=0.33)
        dn = dao_reverse(**{**base, name: base[name] - h}, h_m=f.h_m, nu=0.33)
        for q in var:
            var[q] += ((getattr(up, q) - getattr(dn, q)) / (2 * h) * s) ** 2
    assert r1.E_star_std == pytest.approx(math.sqrt(var["E_star"]), rel=0.06)
    assert r1.sigma_r_std == pytest.approx(math.sqrt(var["sigma_r"]), rel=0.06)


def test_repeated_indents_mean_and_scatter():
    f = oracle_forward()
    C = f.C * np.array([0.99, 1.0, 1.01])
    S = f.dPdh * np.array([1.0, 1.005, 0.995])
    r = dao_reverse_repeated(C, S, [f.WpWt] * 3, f.h_m, nu=0.33)
    single = [dao_reverse(c, s, f.WpWt, f.h_m, nu=0.33) for c, s in zip(C, S)]
    assert r.E_star == pytest.approx(np.mean([x.E_star for x in single]), rel=1e-12)
    assert r.E_star_std == pytest.approx(np.std([x.E_star for x in single], ddof=1), rel=1e-9)
    same = dao_reverse_repeated([f.C] * 4, [f.dPdh] * 4, [f.WpWt] * 4, f.h_m, nu=0.33)
    assert same.E_star_std == pytest.approx(0.0, abs=1e-12 * f.E_star) and same.samples == 4
    with pytest.raises(InputError, match="one value per indent"):
        dao_reverse_repeated([f.C] * 3, [f.dPdh] * 2, [f.WpWt] * 3, f.h_m)
    with pytest.raises(InputError, match="at least 2"):
        dao_reverse_repeated([f.C], [f.dPdh], [f.WpWt], f.h_m)


def test_dual_uncertainty_and_reproducibility():
    E, nu, sigma_y, n = 100e9, 0.3, 0.4e9, 0.2
    b = dao_forward(E, nu, sigma_y, n, 1e-6)
    c2 = dao_forward(E, nu, sigma_y, n, 1e-6, tip="cone:50").C
    args = (b.C, b.dPdh, b.WpWt, 1e-6, c2)
    r0 = dual_reverse(*args, tip2="cone:50")
    assert r0.n_std == 0 and r0.samples == 0
    r1 = dual_reverse(*args, tip2="cone:50", C2_std=0.005 * c2, samples=500)
    r2 = dual_reverse(*args, tip2="cone:50", C2_std=0.01 * c2, samples=500)
    assert r1.n_std > 0 and r1.E_star_std == 0       # C2 does not enter E*
    assert r2.n_std == pytest.approx(2 * r1.n_std, rel=0.05)
    assert dual_reverse(*args, tip2="cone:50", C2_std=0.005 * c2, samples=500) == r1
    json.dumps(r1.to_dict(), allow_nan=False)


# --- warnings ---------------------------------------------------------------------------------

def test_clean_case_has_no_warnings():
    f = oracle_forward()
    for method in METHODS:
        assert reverse_of(f, nu=0.33, method=method).warnings == ()


def test_residual_depth_outside_pi4_verification_range_warns():
    f = dao_forward(30e9, 0.3, 3e9, 0.2, 1e-6)
    assert f.hr_hm < 0.5 and any("h_r/h_m" in w for w in f.warnings)
    assert any("h_r/h_m" in w for w in reverse_of(f).warnings)


def test_hardening_exponent_at_a_bound_warns():
    low = dao_forward(100e9, 0.3, 0.3e9, 0.0, 1e-6)
    r = dao_reverse(low.C, 0.97 * low.dPdh, low.WpWt, 1e-6)
    assert r.n == 0.0 and any("bound 0 " in w for w in r.warnings)
    high = dao_forward(100e9, 0.3, 0.3e9, 0.5, 1e-6)
    r = dao_reverse(0.97 * high.C, 1.01 * high.dPdh, high.WpWt, 1e-6)
    assert r.n == 0.5 and any("bound 0.5" in w for w in r.warnings)


def test_ill_conditioned_and_poorly_determined_n_warn():
    f = dao_forward(10e9, 0.3, 0.5e9, 0.1, 1e-6)       # E*/sigma_0.033 = 20.7
    assert any("ill-conditioned" in w for w in reverse_of(f).warnings)
    g = dao_forward(10e9, 0.3, 0.3e9, 0.1, 1e-6)       # E*/sigma_0.033 = 34: well conditioned
    assert reverse_of(g).warnings == ()
    r = reverse_of(g, C_std=0.01 * g.C, dPdh_std=0.01 * g.dPdh)
    assert r.n_std > 0.1 and any("poorly determined" in w for w in r.warnings)


def test_several_pi2_roots_warn():
    f = dao_forward(50e9, 0.3, 3e9, 0.3, 1e-6)         # E*/sigma = 15: Pi2 not monotone in n
    assert any("several roots" in w for w in reverse_of(f).warnings)


def test_monte_carlo_draws_outside_the_model_warn():
    r = reverse_of(oracle_forward(), nu=0.33, WpWt_std=0.2)
    assert 0 < r.samples < 2000 and any("dropped" in w for w in r.warnings)


def test_out_of_range_closed_form_raises_and_surrogate_warns():
    f = oracle_forward()
    with pytest.raises(ModelRangeError, match="3.85 < E\\*/sigma_r < 804"):
        dao_reverse(3 * f.C, f.dPdh, f.WpWt, f.h_m)
    assert any("outside the FE training cases" in w
               for w in dao_reverse(3 * f.C, f.dPdh, f.WpWt, f.h_m, method="surrogate").warnings)
    fallback = dao_reverse(0.2 * f.C, f.dPdh, f.WpWt, f.h_m, method="surrogate")
    assert any("direct regression" in w for w in fallback.warnings)
    with pytest.raises(ModelRangeError, match="range of Pi5"):
        dao_reverse(f.C, f.dPdh, 0.999, f.h_m)
    with pytest.raises(ModelRangeError, match="indenter"):
        dao_reverse(f.C, f.dPdh, f.WpWt, f.h_m, E_i=60e9)


# --- tips ---------------------------------------------------------------------------------------

def test_tips_beyond_the_dao_geometry():
    E, nu, sigma_y, n = 100e9, 0.3, 0.4e9, 0.2
    f60 = dao_forward(E, nu, sigma_y, n, 1e-6, tip="cone:60")
    assert math.isnan(f60.dPdh) and any("70.3 deg geometry only" in w for w in f60.warnings)
    assert json.loads(json.dumps(f60.to_dict(), allow_nan=False))["dPdh"] is None
    with pytest.raises(ModelRangeError, match="Pi2, Pi4 and Pi5"):
        dao_reverse(f60.C, 1e5, 0.8, 1e-6, tip="cone:60")
    # interpolation in ln tan(theta) meets the tabulated angles continuously
    for theta in (60.0, 70.3):
        near = dao_forward(E, nu, sigma_y, n, 1e-6, tip=f"cone:{theta - 1e-3:g}").C
        at = dao_forward(E, nu, sigma_y, n, 1e-6, tip=f"cone:{theta:g}").C
        assert near == pytest.approx(at, rel=1e-3)
    # cube corner: uncalibrated unless the user supplies eps_r and Pi1
    with pytest.raises(ModelRangeError, match="no Pi1 calibration"):
        dao_forward(E, nu, sigma_y, n, 1e-6, tip="cube-corner")
    cc = dataclasses.replace(sharp_tip("cube-corner"), eps_r=0.1, pi1=PI1_THETA[50.0])
    cal = sharp_calibration(cc)
    assert cal.x_range[0] < math.log(E / sigma_y) < cal.x_range[1]
    assert dao_forward(E, nu, sigma_y, n, 1e-6, tip=cc).C > 0


def test_sharp_tips_are_cones_calibrated_by_the_reverse_analysis():
    berk = sharp_tip("berkovich")
    assert isinstance(berk, Cone) and berk == berkovich()
    assert (berk.eps_r, berk.pi1, berk.c_star) == (None, None, None)   # published: resolved
    assert sharp_tip(berk) is berk and sharp_tip(" Cube_Corner ") == sharp_tip("cube-corner")
    # a calibration of the tip's own replaces the published one, field by field
    own = sharp_calibration(dataclasses.replace(berk, c_star=1.3))
    assert (own.c_star, own.eps_r, own.pi1, own.dao_functions) == (1.3, 0.033, PI1_DAO, True)
    cal = sharp_calibration("cone:65")
    assert cal.interpolated and cal.name == "cone:65"
    assert cal.eps_r == pytest.approx(float(representative_strain(65.0)), rel=1e-15)
    with pytest.raises(InputError, match="tip eps_r"):
        dataclasses.replace(berk, eps_r=1.5)
    with pytest.raises(InputError, match="4 numbers"):
        dataclasses.replace(berk, pi1=(1.0, 2.0))
    # a truncated cone is not sharp: refused as text, out of the model's range as a Cone
    with pytest.raises(InputError, match="tip"):
        sharp_tip("cone:70.3:5nm")
    with pytest.raises(ModelRangeError, match="truncated"):
        dao_forward(70e9, 0.3, 0.5e9, 0.1, 1e-6, tip=Cone(70.3, tip_radius=5e-9))


# --- bad inputs -------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [
    (dict(C=-1.0), "C"), (dict(dPdh=0.0), "dPdh"), (dict(WpWt=1.2), "WpWt"),
    (dict(WpWt=0.0), "WpWt"), (dict(WpWt=1.0), "WpWt"), (dict(h_m=-1e-6), "h_m"),
    (dict(tip="vickers"), "tip"), (dict(tip="cone:45"), "tip"), (dict(tip="cone:85"), "tip"),
    (dict(tip="cone:abc"), "tip"), (dict(method="fem"), "method"), (dict(nu=0.5), "nu"),
    (dict(C_std=-1.0), "C_std"), (dict(samples=1), "samples"), (dict(seed=-1), "seed"),
    (dict(seed=1.5), "seed"), (dict(E_i=0.0), "E_i"),
])
def test_bad_inputs_raise_input_error_naming_the_parameter(kwargs, name):
    args = dict(C=43.84e9, dPdh=4.3354e5, WpWt=0.8242, h_m=1e-6)
    args.update(kwargs)
    with pytest.raises(InputError, match=name):
        dao_reverse(**args)


def test_bad_forward_and_cv_inputs():
    with pytest.raises(InputError, match="sigma_y"):
        dao_forward(70e9, 0.3, -1.0, 0.1, 1e-6)
    with pytest.raises(ModelRangeError, match="n = 0.7"):
        dao_forward(70e9, 0.3, 0.5e9, 0.7, 1e-6)
    with pytest.raises(InputError, match="k"):
        cross_validate(k=1)
    with pytest.raises(InputError, match="selection"):
        cross_validate(selection="peeking")
    with pytest.raises(InputError, match="C2"):
        dual_reverse(43.84e9, 4.3354e5, 0.8242, 1e-6, -1.0, tip2="cone:60")
