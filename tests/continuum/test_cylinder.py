"""Finite-cylinder (line-contact) impact: both solution paths against oracles written here.

The oracles use Johnson's (1985) approach law in the load per unit length P' (the model
works in the half-width b), a root finder on it and adaptive quadrature or an explicit
Runge-Kutta integration of m x'' = -L P'(x)."""

import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.interpolate import CubicHermiteSpline
from scipy.optimize import brentq

from filmscale.continuum.contact.cylinder import (FULLY_PLASTIC_FACTOR, CylinderImpactModel,
                                                  cylinder_yield_factor, line_approach,
                                                  line_half_width, line_work)
from filmscale.continuum.contact.cylinder_fast import CylinderMaxima
from filmscale.continuum.contact.impact_map import CYLINDER_UNITS, cylinder_map
from filmscale.continuum.contact.profiles import StackProfile, TableProfile
from filmscale.continuum.contact.results import EXCEEDS_RADIUS, OK, CylinderImpactResult
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError, ModelRangeError

STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9, name="steel")
ELASTIC = ElasticPlastic(E=200e9, nu=0.3, sigma_y=math.inf, name="elastic steel")
SLIDER = ElasticPlastic(E=400e9, nu=0.23, name="AlTiC")
R, L, M = 1e-3, 5e-3, 1e-3


# --- independent oracle: Johnson's law in P' ------------------------------------------------

def johnson_approach(p, e_star, nu, d):
    """delta(P') = (2 P'/(pi E*)) (ln(2d/b) - nu/(2(1-nu))), b = 2 sqrt(P' R/(pi E*))."""
    b = 2.0 * math.sqrt(p * R / (math.pi * e_star))
    return 2.0 * p / (math.pi * e_star) * (math.log(2.0 * d / b) - nu / (2.0 * (1.0 - nu)))


def johnson_load(delta, e_star, nu, d):
    """P' (N/m) at approach delta, by brentq on the law in ln P'."""
    if delta <= 1e-200:       # the load there is below 1e-180 N/m
        return 0.0
    top = math.log(math.pi * e_star * (0.1 * d) ** 2 / R)     # b = d/5: the law increases
    return math.exp(brentq(lambda t: johnson_approach(math.exp(t), e_star, nu, d) - delta,
                           top - 500.0, top, xtol=1e-14, rtol=1e-15))


def johnson_impact(V, e_star, nu, d):
    """(delta_max, contact time) of the elastic impact: delta_max from m V^2/2 = L W(delta)
    and t_c = 2 integral_0^delta_max d(delta)/v(delta), in delta = delta_max (1 - u^2)."""
    def work(lo, hi):
        return quad(lambda x: johnson_load(x, e_star, nu, d), lo, hi, epsabs=0,
                    epsrel=1e-13, limit=200)[0]
    energy = 0.5 * M * V * V / L
    d_max = brentq(lambda x: work(0.0, x) - energy, 1e-12, 1e-4, xtol=1e-22, rtol=1e-14)

    def integrand(u):
        x = d_max * (1.0 - u * u)
        return 2.0 * d_max * u / math.sqrt(2.0 * L / M * work(x, d_max)) if 0 < u < 1 else 0.0
    return d_max, 2.0 * quad(integrand, 0.0, 1.0, epsabs=0, epsrel=1e-11)[0]


def test_yield_factor_matches_the_plane_strain_von_mises_maximum():
    # McEwen's stresses on the axis under p0 sqrt(1 - x^2/b^2), plane strain sigma_y =
    # nu (sigma_x + sigma_z); C = 1/max(von Mises/p0) over depth, surface included
    z = np.linspace(0.0, 4.0, 400001)
    r = np.sqrt(1.0 + z * z)
    sx, sz = -((1.0 + 2.0 * z * z) / r - 2.0 * z), -1.0 / r
    for nu in np.linspace(0.0, 0.5, 21):
        sy = nu * (sx + sz)
        vm = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))
        assert float(cylinder_yield_factor(nu)) == pytest.approx(1.0 / vm.max(), rel=1.5e-3)
    assert float(cylinder_yield_factor(0.3)) == pytest.approx(1.794, abs=1.5e-3)


def test_line_law_closed_forms_against_johnson_in_load():
    e_star, nu, d = STEEL.plane_strain_modulus, 0.3, 2e-3
    for p in (1e2, 1e5, 1e7):
        delta = johnson_approach(p, e_star, nu, d)
        b = float(line_half_width(delta, R, d, nu))
        assert b == pytest.approx(2.0 * math.sqrt(p * R / (math.pi * e_star)), rel=1e-12)
        assert float(line_approach(b, R, d, nu)) == pytest.approx(delta, rel=1e-13)
        # work by parts in P': P' delta - integral delta dP'
        w = p * delta - quad(lambda q: johnson_approach(q, e_star, nu, d), 0.0, p,
                             epsabs=0, epsrel=1e-13)[0]
        assert float(line_work(b, R, e_star, d, nu)) == pytest.approx(w, rel=1e-11)


def test_datum_depth_shifts_the_approach_by_the_log_of_its_ratio():
    b = 3e-5
    near, far = (CylinderImpactModel(STEEL, L, datum_depth=d).approach(b, R) for d in (L, 10 * L))
    assert far - near == pytest.approx(b * b / (2 * R) * math.log(10.0), rel=1e-12)


def test_first_yield_against_the_closed_form():
    model = CylinderImpactModel(STEEL, L)
    tables = model.tables(R)
    e_star, c = STEEL.plane_strain_modulus, float(cylinder_yield_factor(0.3))
    b_y = 2.0 * R * c * STEEL.sigma_y / e_star
    assert tables.b_yield == pytest.approx(b_y, rel=1e-12)
    assert model.line_load(b_y, R, tables) == pytest.approx(
        math.pi * R * (c * STEEL.sigma_y) ** 2 / e_star, rel=1e-12)
    # the cap starts where the elastic mean pressure (pi/4) p0 reaches p_fp
    assert tables.b_plastic == pytest.approx(4 / math.pi * FULLY_PLASTIC_FACTOR / c * b_y,
                                             rel=1e-12)
    res = model.maxima(0.5, R, M)
    w_y = line_work(b_y, R, e_star, L, 0.3)
    assert res.yield_velocity == pytest.approx(math.sqrt(2 * L * w_y / M), rel=1e-12)
    assert res.yield_approach == pytest.approx(johnson_approach(
        math.pi * R * (c * STEEL.sigma_y) ** 2 / e_star, e_star, 0.3, L), rel=1e-12)


# --- elastic impact -------------------------------------------------------------------------

@pytest.mark.parametrize("V, impactor", [(0.05, None), (2.0, None), (1.0, SLIDER)])
def test_elastic_impact_conserves_energy_and_matches_the_independent_integration(V, impactor):
    model = CylinderImpactModel(ELASTIC, L, impactor=impactor)
    e_star = ELASTIC.reduced_modulus(impactor)
    d_max, t_c = johnson_impact(V, e_star, 0.3, L)
    fast, timed = model.maxima(V, R, M), model.history(V, R, M, rtol=1e-12).result
    for res in (fast, timed):
        assert res.regime == "elastic" and res.residual_depth == 0.0
        # energy: rebound speed equal to V to 1e-9 (integrator rtol 1e-12)
        assert res.restitution == pytest.approx(1.0, abs=1e-9)
        assert 0.5 * M * res.rebound_velocity**2 == pytest.approx(0.5 * M * V * V, rel=1e-9)
        assert res.work_loading == pytest.approx(0.5 * M * V * V, rel=1e-9)
        # oracle: quadrature of Johnson's law in P' with its own root finder, to 1e-8
        assert res.delta_max == pytest.approx(d_max, rel=1e-8)
        assert res.contact_time == pytest.approx(t_c, rel=1e-8)
        assert res.loading_time == pytest.approx(t_c / 2, rel=1e-8)
    assert fast.contact_half_width == pytest.approx(timed.contact_half_width, rel=1e-9)


def test_elastic_contact_time_against_an_explicit_runge_kutta_integration():
    # a different integrator (RK45, no scaling) on the force from the root finder above
    V, e_star = 1.0, ELASTIC.plane_strain_modulus

    def rhs(_, y):
        return [y[1], -L * johnson_load(max(y[0], 0.0), e_star, 0.3, L) / M]
    sep = lambda t, y: y[0]  # noqa: E731
    sep.terminal, sep.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1e-3), [0.0, V], method="RK45", rtol=1e-10, atol=1e-20,
                    events=sep, dense_output=True)
    t_c = sol.t_events[0][0]
    res = CylinderImpactModel(ELASTIC, L).maxima(V, R, M)
    assert res.contact_time == pytest.approx(t_c, rel=1e-7)
    assert res.restitution == pytest.approx(-sol.y_events[0][0][1] / V, abs=1e-7)


# --- elastic-plastic impact ------------------------------------------------------------------

@pytest.mark.parametrize("V", [2.0, 10.0])
def test_plastic_impact_dissipates_and_both_paths_agree(V):
    model = CylinderImpactModel(STEEL, L)
    fast, timed = model.maxima(V, R, M), model.history(V, R, M, rtol=1e-11).result
    for res in (fast, timed):
        assert res.regime == "fully plastic"
        assert 0.0 < res.restitution < 1.0
        assert 0.0 < res.residual_depth < res.delta_max
        assert res.dissipated == pytest.approx(res.work_loading - res.work_unloading, rel=1e-14)
        assert res.dissipated > 0
        # energy in = loading work; energy out = elastic work returned
        assert res.work_loading == pytest.approx(0.5 * M * V * V, rel=1e-8)
        assert 0.5 * M * res.rebound_velocity**2 == pytest.approx(res.work_unloading, rel=1e-8)
        assert res.mean_pressure_max == pytest.approx(FULLY_PLASTIC_FACTOR * STEEL.sigma_y,
                                                      rel=1e-12)
    for key in ("delta_max", "contact_time", "restitution", "residual_depth",
                "contact_half_width", "force_max"):
        assert getattr(fast, key) == pytest.approx(getattr(timed, key), rel=1e-7), key


def test_restitution_is_continuous_at_the_cap():
    model = CylinderImpactModel(STEEL, L)
    tables = model.tables(R)
    v_cap = math.sqrt(2 * L * model.work(0.0, tables.b_plastic, R, tables) / M)
    below, above = (model.maxima(v_cap * f, R, M) for f in (1 - 1e-6, 1 + 1e-6))
    assert below.restitution == 1.0 and below.regime == "contained plastic"
    assert above.restitution == pytest.approx(1.0, abs=1e-5)
    assert above.residual_depth < 1e-5 * above.delta_max


# --- layered targets --------------------------------------------------------------------------

def test_film_equal_to_substrate_gives_the_homogeneous_answer():
    # a StackProfile keeps the layered path (quadrature, root finding) that a homogeneous
    # LayerStack would skip
    stack = StackProfile(LayerStack([Layer(20e-6, STEEL)], STEEL))
    for V in (0.5, 5.0):
        ref = CylinderImpactModel(STEEL, L).maxima(V, R, M)
        model = CylinderImpactModel(stack, L)
        for res in (model.maxima(V, R, M), model.history(V, R, M).result):
            for key in ("delta_max", "contact_time", "restitution", "residual_depth",
                        "yield_velocity"):
                assert getattr(res, key) == pytest.approx(getattr(ref, key), rel=1e-8), key


def test_thick_film_gives_the_film_and_thin_film_the_substrate_answer():
    film = ElasticPlastic(E=100e9, nu=0.25, sigma_y=0.5e9, name="film")
    V = 3.0
    cases = ((LayerStack([Layer(0.1, film)], STEEL), film),      # t/b ~ 2e3
             (LayerStack([Layer(1e-9, film)], STEEL), STEEL))    # t/b ~ 2e-5
    for stack, alone in cases:
        ref = CylinderImpactModel(alone, L).maxima(V, R, M)
        res = CylinderImpactModel(stack, L).maxima(V, R, M)
        # Gao weights depart from 0 or 1 by O(t/b) or O(b/t): 1e-3 at these ratios
        for key in ("delta_max", "contact_time", "restitution", "residual_depth"):
            assert getattr(res, key) == pytest.approx(getattr(ref, key), rel=2e-3), key


def test_layered_paths_agree():
    stack = LayerStack([Layer(30e-6, ElasticPlastic(E=120e9, nu=0.25, sigma_y=0.8e9))], STEEL)
    model = CylinderImpactModel(stack, L)
    fast, timed = model.maxima(4.0, R, M), model.history(4.0, R, M).result
    for key in ("delta_max", "contact_time", "restitution", "residual_depth"):
        assert getattr(fast, key) == pytest.approx(getattr(timed, key), rel=1e-8), key


# --- inputs and range -------------------------------------------------------------------------

def test_inputs_are_checked():
    with pytest.raises(InputError, match="length"):
        CylinderImpactModel(STEEL, 0.0)
    with pytest.raises(InputError, match="datum_depth"):
        CylinderImpactModel(STEEL, L, datum_depth=-1.0)
    with pytest.raises(InputError, match="mass"):     # lighter than the cylinder itself
        CylinderImpactModel(STEEL, L).maxima(1.0, R, 1e-12)
    with pytest.raises(ModelRangeError, match="half-width"):
        CylinderImpactModel(STEEL, L, datum_depth=1e-4).maxima(100.0, R, M)


def test_result_is_jsonable_and_says_cylinder():
    res = CylinderImpactModel(STEEL, L).maxima(2.0, R, M)
    out = res.to_dict()
    assert out["shape"] == "cylinder" and out["contact_half_width"] > 0
    assert "cylinder" in res.summary() and "end effects" in res.summary()


# --- sampled histories --------------------------------------------------------------------------

def test_elastic_history_conserves_energy_and_is_symmetric():
    V, rtol = 1.0, 1e-10
    model = CylinderImpactModel(ELASTIC, L)
    hist = model.history(V, R, M, rtol=rtol)
    e_star = ELASTIC.plane_strain_modulus
    # oracle: the closed-form work W(b) of the elastic law at each sample's half-width,
    # and delta(b) from the law itself; dense output of DOP853 at rtol 1e-10 keeps both
    # within 1e-8 of the impact energy and the sampled approach
    energy = 0.5 * M * hist.velocity**2 + L * line_work(hist.contact_half_width, R, e_star, L,
                                                         0.3)
    assert np.max(np.abs(energy / (0.5 * M * V * V) - 1.0)) < 1e-8
    assert np.allclose(line_approach(hist.contact_half_width, R, L, 0.3), hist.delta,
                       rtol=1e-12, atol=1e-12 * hist.delta.max())
    res = hist.result
    assert res.loading_time == pytest.approx(res.unloading_time, rel=100 * rtol)
    assert hist.events["maximum approach"] == pytest.approx(res.loading_time, rel=1e-15)
    assert hist.events["separation"] == pytest.approx(res.contact_time, rel=1e-15)
    # time symmetry: delta(t_max - s) = delta(t_max + s), the loading side interpolated
    # between its samples by cubic Hermite on (delta, velocity)
    t_max = hist.events["maximum approach"]
    load, unload = hist.phase == 1, hist.phase == 2
    spline = CubicHermiteSpline(hist.time[load], hist.delta[load], hist.velocity[load])
    mirrored = spline(t_max - (hist.time[unload] - t_max))
    assert np.max(np.abs(mirrored - hist.delta[unload])) < 1e-8 * res.delta_max
    assert np.all(hist.branch == 0) and hist.time[0] == 0.0


@pytest.mark.parametrize("material, V", [(ELASTIC, 1.0), (STEEL, 0.3), (STEEL, 5.0)])
def test_history_maxima_equal_the_maxima_path(material, V):
    rtol = 1e-10
    model = CylinderImpactModel(material, L)
    hist, fast = model.history(V, R, M, rtol=rtol), model.maxima(V, R, M)
    # the sampled extremes fall on the event at maximum approach: within 100 rtol
    for key, sampled in (("delta_max", hist.delta), ("force_max", hist.force),
                         ("contact_half_width", hist.contact_half_width),
                         ("mean_pressure_max", hist.mean_pressure)):
        assert np.max(sampled) == pytest.approx(getattr(fast, key), rel=100 * rtol), key
        assert getattr(hist.result, key) == pytest.approx(getattr(fast, key), rel=100 * rtol)
    for key in ("contact_time", "restitution", "residual_depth"):
        assert getattr(hist.result, key) == pytest.approx(getattr(fast, key), rel=1e-7), key
    # the mean pressure is P'/(2b) at every sample in contact
    inside = hist.contact_half_width > 0
    assert np.allclose(hist.mean_pressure[inside] * 2 * L * hist.contact_half_width[inside],
                       hist.force[inside], rtol=1e-14)
    assert hist.branch.max() == ("elastic", "contained plastic",
                                 "fully plastic").index(fast.regime)


def test_plastic_history_unloads_to_the_residual_depth():
    model = CylinderImpactModel(STEEL, L)
    hist = model.history(5.0, R, M, rtol=1e-10)
    res = hist.result
    assert list(hist.events) == ["contact", "regime contained plastic",
                                 "regime fully plastic", "maximum approach", "separation"]
    assert hist.delta[-1] == pytest.approx(res.residual_depth, rel=1e-9)
    assert hist.force[-1] == pytest.approx(0.0, abs=1e-9 * res.force_max)
    assert -hist.velocity[-1] == pytest.approx(res.rebound_velocity, rel=1e-12)
    # loading branches change where the half-width crosses first yield and the cap
    tables = model.tables(R)
    load = hist.phase == 1
    assert np.array_equal(hist.branch[load],
                          (hist.contact_half_width[load] >= tables.b_yield).astype(int)
                          + (hist.contact_half_width[load] >= tables.b_plastic))
    assert np.all(hist.branch[~load] == 2) and np.all(np.diff(hist.time) >= 0)
    with pytest.raises(InputError, match="samples"):
        model.history(5.0, R, M, samples=1)


# --- maps -------------------------------------------------------------------------------------

def test_map_values_are_the_single_impacts():
    model = CylinderImpactModel(STEEL, L, datum_depth=1e-3)      # b <= 2e-4 m: V = 100 is out
    velocity, radius = np.array([0.2, 3.0, 100.0]), np.array([1e-3, 2e-3])
    calls = []
    mp = cylinder_map(model, velocity, radius, M, progress=lambda *a: calls.append(a))
    assert calls == [(3, 6), (6, 6)]
    assert mp.out_of_range.tolist() == [[False, False, True], [False, False, True]]
    for i, R_ in enumerate(radius):
        for j, V in enumerate(velocity[:2]):
            res = model.maxima(V, R_, M)
            # the same fast path, point by point: exact (it works element-wise)
            for key in CYLINDER_UNITS:
                assert mp.field(key)[i, j] == getattr(res, key), key
            assert mp.regime_names[mp.regime[i, j]] == res.regime
            assert mp.yielded[i, j] == res.yielded
    assert np.isnan(mp.field("delta_max")[:, 2]).all() and (mp.regime[:, 2] == -1).all()
    assert mp.field("delta_max").shape == (2, 3)
    with pytest.raises(InputError, match="map field"):
        mp.field("contact_radius_max")
    with pytest.raises(InputError, match="lighter than a cylinder"):    # checked at the largest R
        cylinder_map(model, velocity, [1e-3, 0.5], M)


# --- the vectorised fast path ---------------------------------------------------------------

FILM = ElasticPlastic(E=120e9, nu=0.25, sigma_y=0.8e9, name="film")
#: surface yield first (nu < 0.19), an elastic slider and a datum of its own
LOW_NU = ElasticPlastic(E=150e9, nu=0.12, sigma_y=0.6e9, name="low nu")
FAST_CASES = {
    "uniform": lambda: CylinderImpactModel(STEEL, L),
    "slider, nu 0.12, d = 2 mm": lambda: CylinderImpactModel(LOW_NU, L, SLIDER, 2e-3),
    "30 um film": lambda: CylinderImpactModel(LayerStack([Layer(30e-6, FILM)], STEEL), L),
    "two films, Nix-Gao": lambda: CylinderImpactModel(StackProfile(LayerStack(
        [Layer(2e-6, ElasticPlastic(E=300e9, nu=0.2, sigma_y=4e9)), Layer(20e-6, FILM)],
        STEEL), h_star=(1e-7, 0.0, 0.0)), L, SLIDER),
    "measured table": lambda: CylinderImpactModel(TableProfile(
        depths=np.array([1e-7, 1e-6, 1e-5]), plane_strain_modulus=np.array([150e9, 200e9,
                                                                             220e9]),
        hardness=np.array([6e9, 4e9, 3e9]), hardness_factor=2.8, nu=0.3), L),
}
#: every float result of a point
RESULT_FIELDS = tuple(k for k in CylinderMaxima.UNITS if k not in ("velocity", "radius",
                                                                   "mass"))


def _regime_speeds(model, R_):
    """Speeds (m/s) of an elastic, a contained-plastic, a fully plastic and an out-of-range
    impact: from the adaptive path's work to first yield, to the cap and to the range
    limit."""
    tables = model.tables(R_)
    v_y, v_cap, v_lim = (math.sqrt(2 * L * model.work(0.0, b, R_, tables) / M)
                         for b in (tables.b_yield, tables.b_plastic, tables.b_limit))
    return np.array([0.5 * v_y, math.sqrt(v_y * v_cap), 4.0 * v_cap, 1.5 * v_lim])


@pytest.mark.parametrize("case", list(FAST_CASES))
def test_fast_path_agrees_with_the_adaptive_path(case):
    # the point-by-point reference: adaptive quadrature (epsrel 1e-12) and brentq; maps must
    # stay within 1e-9 of it (the fast path is within about 3e-11,
    # benchmarks/cylinder_map_speed.py)
    model = FAST_CASES[case]()
    V = _regime_speeds(model, R)
    fast = model.maxima(V, R, M)
    assert isinstance(fast, CylinderMaxima) and fast.status.shape == (4,)
    assert fast.regime.tolist() == [0, 1, 2, -1]
    assert fast.status.tolist() == [OK, OK, OK, EXCEEDS_RADIUS]
    for i in range(3):
        ref = model.maxima_adaptive(V[i], R, M)
        one = fast.result(i)
        assert one.regime == ref.regime and one.yielded == ref.yielded
        for key in RESULT_FIELDS:
            assert getattr(one, key) == pytest.approx(getattr(ref, key), rel=1e-9), key
    with pytest.raises(ModelRangeError, match="half-width"):
        model.maxima_adaptive(V[3], R, M)
    for key in RESULT_FIELDS:           # out of range: NaN, as the map shows it
        assert np.isnan(getattr(fast, key)[3]), key


@pytest.mark.parametrize("case", ["uniform", "slider, nu 0.12, d = 2 mm", "30 um film"])
def test_fast_path_agrees_with_the_time_integration(case):
    # as the sphere's fast path (tests/continuum/test_impact.py): the history at its default
    # rtol 1e-10, to 1e-6 relative; the residual depth to 1e-6 of the approach
    model = FAST_CASES[case]()
    V = _regime_speeds(model, R)
    fast = model.maxima(V, R, M)
    for i in range(3):
        slow = model.history(V[i], R, M).result
        one = fast.result(i)
        assert one.regime == slow.regime == ("elastic", "contained plastic",
                                             "fully plastic")[i]
        for key in RESULT_FIELDS:
            if key == "residual_depth":
                assert slow.residual_depth == pytest.approx(one.residual_depth,
                                                            abs=1e-6 * one.delta_max)
            else:
                assert getattr(slow, key) == pytest.approx(getattr(one, key), rel=1e-6), key
    with pytest.raises(ModelRangeError, match="half-width"):
        model.history(V[3], R, M)


def test_scalars_give_a_result_and_arrays_broadcast():
    model = CylinderImpactModel(STEEL, L)
    one = model.maxima(3.0, R, M)
    assert isinstance(one, CylinderImpactResult) and one.path == "energy-quadrature"
    V, radii = np.array([[0.2, 3.0, 500.0]]), np.array([[1e-3], [2e-3]])
    grid = model.maxima(V, radii, M)
    assert grid.delta_max.shape == grid.status.shape == grid.regime.shape == (2, 3)
    assert grid.mass.shape == (2, 3) and np.all(grid.mass == M)
    assert grid.result((0, 1)) == one           # element-wise: the same numbers
    assert grid.status[:, 2].tolist() == [EXCEEDS_RADIUS] * 2
    with pytest.raises(ModelRangeError, match="half-width above"):
        grid.result((1, 2))
    # growth with V and fall with R at fixed V, as every map shows
    assert np.all(np.diff(model.maxima(np.geomspace(0.01, 50, 30), R, M).delta_max) > 0)
    assert np.all(np.diff(model.maxima(3.0, np.geomspace(5e-4, 5e-3, 10), M).delta_max) < 0)
    # the end-effect warning of a contact wider than L/10 comes with the point's result
    short = CylinderImpactModel(STEEL, 1e-3, datum_depth=5e-3)
    found = short.maxima(np.array([0.5, 20.0]), R, 1e-3)
    assert [bool(found.result(i).warnings) for i in (0, 1)] == [False, True]
    assert "end effects" in found.result(1).warnings[0]
    assert found.result(1).warnings == short.maxima_adaptive(20.0, R, 1e-3).warnings


def test_array_inputs_are_checked():
    model = CylinderImpactModel(STEEL, L)
    with pytest.raises(InputError, match="velocity"):
        model.maxima(np.array([1.0, -1.0]), R, M)
    with pytest.raises(InputError, match="radius"):
        model.maxima(1.0, np.array([1e-3, 2e3]), M)
    with pytest.raises(InputError, match="lighter than a cylinder"):
        model.maxima(1.0, np.array([1e-3, 0.5]), M)
    with pytest.raises(InputError, match="shapes"):
        model.maxima(np.ones(3), np.full(2, R), M)


def test_layered_map_equals_the_single_impacts():
    model = FAST_CASES["two films, Nix-Gao"]()
    velocity, radius = np.array([0.5, 3.0, 20.0]), np.array([5e-4, 1e-3])
    mp = cylinder_map(model, velocity, radius, M)
    for i, R_ in enumerate(radius):
        for j, V in enumerate(velocity):
            res = model.maxima(V, R_, M)
            # the profile's matrix products over two interfaces round by the array's size
            for key in CYLINDER_UNITS:
                assert mp.field(key)[i, j] == pytest.approx(getattr(res, key), rel=1e-12), key
            assert mp.regime_names[mp.regime[i, j]] == res.regime


def test_the_fast_path_and_its_map_load_no_scipy_sub_package():
    # `filmscale impact` and `impact-map` on a cylinder scene: scipy.optimize alone takes
    # 0.45 s to import (tests/workflows/test_terminal.py holds the same for the sphere)
    code = ("import sys\n"
            "from filmscale.continuum.contact.cylinder import CylinderImpactModel\n"
            "from filmscale.continuum.contact.impact_map import cylinder_map\n"
            "from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack\n"
            "steel = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1e9)\n"
            "film = ElasticPlastic(E=120e9, nu=0.25, sigma_y=0.8e9)\n"
            "for target in (steel, LayerStack([Layer(30e-6, film)], steel)):\n"
            "    model = CylinderImpactModel(target, 5e-3)\n"
            "    model.maxima(5.0, 1e-3, 1e-3)\n"
            "    cylinder_map(model, [0.1, 5.0, 500.0], [5e-4, 1e-3], 1e-3)\n"
            "print(' '.join(sorted(m for m in sys.modules if m.startswith('scipy.'))))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == []
