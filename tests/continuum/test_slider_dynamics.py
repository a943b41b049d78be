"""An impactor with its own mass and moment of inertia, j = I/(m R^2) up to 1e8 (docs/physics.md
section 5; a slider corner: docs/slider-dynamics.md).

Oracles, none of them the implementation:

1. the rigid-body impulse balance: during the impact the only external impulse acts at the
   contact point, so the angular momentum about it is conserved, I omega' + m R v_x' = m R V_t
   (no initial spin; omega > 0 forward rolling, so friction raises omega as it lowers v_x);
2. an exact solution of the non-rotating limit (j -> infinity) for kappa = k_t/k_n = 1 (nu = 0):
   the stuck spring line moves as u(t) = (V_t/V) delta(t), so the contact point leaves at -V_t;
3. the gross-slip boundary psi_1 = max(1, 4 chi - 1), derived from the spring line
   (docs/physics.md section 5): Mindlin's initial slip (psi_1 >= 1) binds once the body turns
   little (j > kappa/(1 - kappa)), Maw, Barber & Fawcett's 4 chi - 1 for every sphere;
4. Coulomb's bound |J_t| <= mu J_n, reached in gross slip;
5. Newton-Euler for a rigid box (the effective mass of a slider corner, docs/slider-dynamics.md).
"""

import math
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.contact.oblique import (
    INERTIA_FACTOR_MAX, gross_slip_boundary, solve_oblique, stiffness_ratio)
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.workflows.scene import load_scene, parse_scene
from tests.helpers.scenes import MINIMAL

ROOT = Path(__file__).resolve().parents[2]
# the slider corner of examples/slider_corner_disk.toml: an Al2O3-TiC corner of radius 10 um
# on glass, its normal effective mass that of a corner of a 1.6 mg pico slider
TIC = ElasticPlastic(E=400e9, nu=0.23, sigma_y=20e9, name="Al2O3-TiC")
GLASS = ElasticPlastic(E=90e9, nu=0.25, sigma_y=2.4e9, name="glass")
R_C, M_C = 10e-6, 2.4e-7
DISK_SPEED = 15.0                   # m/s, tangential
STEEL0 = ElasticPlastic(E=200e9, nu=0.0, sigma_y=1.5e9, name="nu = 0")
STEEL = ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e9, name="steel")
R, M = 1e-3, 4.0 / 3.0 * math.pi * 1e-9 * 7800.0


def _balance(res):
    """(I omega' + m R v_x', m R V_t): the angular momentum about the contact point after and
    before the impact, from the result's public fields."""
    m, r, j = res.normal.mass, res.normal.radius, res.inertia_factor
    v_t = res.tangential_velocity
    return (j * m * r**2 * res.spin + m * r * res.restitution_tangential * v_t, m * r * v_t)


# (law, normal speed, incidence angle, mu, path, the path the result must report)
CORNER_CASES = [
    # a disk sliding under the corner: tan(theta) = 15 / 0.02, elastic, gross slip
    ("hertz", 0.02, math.degrees(math.atan(DISK_SPEED / 0.02)), 0.3, "fast",
     "closed form (gross slip)"),
    ("hertz", 0.02, math.degrees(math.atan(DISK_SPEED / 0.02)), 0.3, "time", "time-integration"),
    # elastic-plastic at 0.2 m/s (the example's speed), gross slip, integrated
    ("komvopoulos-ye-continuous", 0.2, math.degrees(math.atan(DISK_SPEED / 0.2)), 0.3, "fast",
     "time-integration"),
    # small angles: stick and stick-slip, integrated
    ("hertz", 0.02, 1.0, 0.3, "fast", "time-integration"),
    ("komvopoulos-ye-continuous", 0.2, 5.0, 0.3, "fast", "time-integration"),
]


@pytest.mark.parametrize("j", [1.0, 100.0, 3000.0])
@pytest.mark.parametrize("law, V, theta, mu, path, used", CORNER_CASES)
def test_slider_corner_conserves_angular_momentum_about_the_contact_point(
        j, law, V, theta, mu, path, used):
    """I omega' + m R v_x' = m R V_t. Tolerance 1e-12 relative: the closed form is exact and
    the time path applies equal and opposite half-step impulses to v_x and R omega (its
    rounding over 4000 half steps is at most 1e-14 here); a j used as 1/j, or the spin's lever
    arm taken twice, breaks it by order 1."""
    model = ImpactModel(GLASS, contact_law(law), TIC)
    res = solve_oblique(model, V, R_C, M_C, theta, mu, inertia_factor=j, path=path)
    assert res.path == used
    after, before = _balance(res)
    assert after == pytest.approx(before, rel=1e-12)
    assert res.spin > 0 and res.inertia_factor == j
    # Coulomb: |J_t| <= mu J_n, and the spin is R J_t / I with J_t = f J_n
    assert 0 < res.impulse_ratio <= mu * (1 + 1e-9)
    j_n = M_C * V * (1 + res.restitution)
    assert res.spin == pytest.approx(R_C * res.impulse_ratio * j_n / (j * M_C * R_C**2),
                                     rel=1e-9)


def test_the_corner_spins_less_as_its_inertia_grows():
    """In gross slip J_t = mu J_n whatever j, so omega' = R mu J_n / I falls as 1/j while v_x'
    (the centre's) stays the rigid-body value; at the 1e8 bound the spin is that of a body that
    does not turn to 1e-8."""
    model = ImpactModel(GLASS, contact_law("hertz"), TIC)
    theta = math.degrees(math.atan(DISK_SPEED / 0.02))
    runs = {j: solve_oblique(model, 0.02, R_C, M_C, theta, 0.3, inertia_factor=j)
            for j in (0.4, 1.0, 100.0, 3000.0, INERTIA_FACTOR_MAX)}
    e_x = 1 - 0.3 * (1 + runs[1.0].restitution) / math.tan(math.radians(theta))
    for j, res in runs.items():
        assert res.regime_tangential == "slip"
        assert res.restitution_tangential == pytest.approx(e_x, rel=1e-12)
        assert res.spin * j == pytest.approx(runs[1.0].spin, rel=1e-12)


@pytest.mark.parametrize("j, tol", [(INERTIA_FACTOR_MAX, 1e-5), (3000.0, 1e-5)])
def test_a_body_that_does_not_turn_leaves_its_contact_point_reversed(j, tol):
    """Oracle 2. For nu = 0 (kappa = 1) the tangential spring line obeys the normal motion's own
    equations: while every spring sticks, m du''/dt = -F_t with dF_t/dt = 8 G* a du/dt =
    2 E* a du/dt, and m d''delta/dt = -F_n with dF_n/dt = 2 E* a d delta/dt. So
    u(t) = (V_t/V) delta(t) when the body does not turn (w = 0): each spring then carries
    kappa V_t/(mu V) = psi_1 times its Coulomb limit at every instant, the contact sticks
    throughout (no micro-slip at all) when psi_1 < 1, and the contact point leaves at -V_t:
    e_c = e_x = -1. A finite j gives e_c = -1 + O(1/j^2) and, by oracle 1,
    e_x = 1 - (1 - e_c)/(1 + 1/j). Tolerance 1e-5: the time path's step error here is
    about 3e-7."""
    model = ImpactModel(STEEL0, contact_law("hertz"))
    assert stiffness_ratio(model, 0.0, R) == pytest.approx(1.0, rel=1e-12)
    mu, psi_1 = 0.2, 0.3
    res = solve_oblique(model, 0.1, R, M, math.degrees(math.atan(psi_1 * mu)), mu,
                        inertia_factor=j, path="time")
    assert res.regime_tangential == "stick"
    assert res.restitution_contact_point == pytest.approx(-1.0, abs=tol)
    assert res.restitution_tangential == pytest.approx(
        1 - (1 - res.restitution_contact_point) / (1 + 1 / j), abs=1e-12)
    if j == INERTIA_FACTOR_MAX:
        assert res.restitution_tangential == pytest.approx(-1.0, abs=tol)
        # the spin vanishes as 1/j: R omega' = J_t/(j m) = (1 - e_x) V_t / j
        assert 0 < res.spin * R / res.tangential_velocity < 3.0 / j


def test_gross_slip_boundary_of_a_body_that_turns_little():
    """Oracle 3 for nu = 0.3 (kappa = 0.82, so 4 chi - 1 < 1 once j > 4.7): the time path
    (no closed form used) slides throughout just above psi_1 = max(1, 4 chi - 1) and not
    just below, and above it meets MBF's branch psi_2 = psi_1 - 4 chi within 1e-6 (J_t = mu J_n
    once every spring slides, but for the last half step of the integrator, about 1e-8 of it).
    The fast path takes the closed form only where the
    boundary allows: at psi_1 = 0.7, above 4 chi - 1 = 0.65 but below 1, it integrates and
    agrees with the time path (the old boundary 4 chi - 1 gave J_t/J_n = mu there, 25 % above
    the integrated 0.16 mu/0.2)."""
    nu, mu, V = 0.3, 0.2, 0.1
    model = ImpactModel(STEEL, contact_law("hertz"))
    kappa = 2 * (1 - nu) / (2 - nu)
    assert gross_slip_boundary(kappa, 0.4) == pytest.approx(4 * 1.441 - 1, abs=4e-3)
    for j in (100.0, 3000.0, INERTIA_FACTOR_MAX):
        chi = 0.5 * kappa * (1 + 1 / j)
        assert 4 * chi - 1 < 0.9 and gross_slip_boundary(kappa, j) == 1.0
        for psi_1 in (0.97, 1.03):
            res = solve_oblique(model, V, R, M, math.degrees(math.atan(psi_1 * mu / kappa)), mu,
                                inertia_factor=j, path="time")
            if psi_1 > 1:
                assert res.regime_tangential == "slip"
                assert psi_1 * res.restitution_contact_point == pytest.approx(
                    psi_1 - 4 * chi, abs=1e-6)
                assert res.impulse_ratio == pytest.approx(mu, rel=1e-6)
            else:
                assert res.regime_tangential != "slip"
                assert res.impulse_ratio < mu * (1 - 1e-5)
    theta = math.degrees(math.atan(0.7 * mu / kappa))
    fast = solve_oblique(model, V, R, M, theta, mu, inertia_factor=3000.0)
    time_ = solve_oblique(model, V, R, M, theta, mu, inertia_factor=3000.0, path="time")
    assert fast.path == "time-integration" and fast.regime_tangential == "stick-slip"
    assert fast.impulse_ratio == pytest.approx(time_.impulse_ratio, rel=1e-12)
    assert fast.impulse_ratio < 0.85 * mu


def test_tangential_impulse_never_exceeds_coulomb_and_reaches_it_in_gross_slip():
    """Oracle 4 over incidence angles, an elastic-plastic corner with j = 3000 (time path):
    J_t/J_n <= mu to rounding, = mu within 1e-6 wherever the whole contact slides throughout
    (the integrator's last half step leaves about 1e-8 of the impulse out), and it grows with
    the angle up to the gross-slip value."""
    model = ImpactModel(GLASS, contact_law("komvopoulos-ye-continuous"), TIC)
    mu = 0.3
    ratios = []
    for theta in (2.0, 10.0, 30.0, 60.0, 85.0, 89.0):
        res = solve_oblique(model, 0.2, R_C, M_C, theta, mu, inertia_factor=3000.0)
        assert 0 < res.impulse_ratio <= mu * (1 + 1e-9)
        if res.regime_tangential == "slip":
            assert res.impulse_ratio == pytest.approx(mu, rel=1e-6)
        ratios.append(res.impulse_ratio)
    assert res.regime_tangential == "slip"
    assert np.all(np.diff(ratios) >= -1e-9)


def _box_corner_mobility(L, W, t):
    """M times the contact point's velocity change per unit impulse (3 x 3), bottom corner
    (L/2, W/2, -t/2) of a uniform box L x W x t, by Newton-Euler written out: dv = J/M,
    d(omega) = I^-1 (r x J), dv_P = dv + d(omega) x r, one unit impulse per axis."""
    inertia = np.array([W**2 + t**2, L**2 + t**2, L**2 + W**2]) / 12.0     # I / M
    r = np.array([L / 2, W / 2, -t / 2])
    out = np.empty((3, 3))
    for k, impulse in enumerate(np.eye(3)):
        spin = np.cross(r, impulse) / inertia
        out[:, k] = impulse + np.cross(spin, r)
    return out


def test_the_example_states_a_pico_slider_corner_effective_mass():
    """Oracle 5: a pico slider (1.25 x 1.0 x 0.3 mm of Al2O3-TiC, 4.2 g/cm^3: 1.6 mg) hit at a
    bottom corner along the disk normal moves its corner as a body of mass
    m_n = 1/(1/M + sum_k (r x n)_k^2 / I_k) = M / 6.59 (docs/slider-dynamics.md), which
    examples/slider_corner_disk.toml states (to the 2 digits it gives); a thin box's corner
    tends to M/7 (t -> 0)."""
    L, W, t = 1.25e-3, 1.0e-3, 0.3e-3
    slider_mass = 4200.0 * L * W * t
    assert slider_mass == pytest.approx(1.575e-6, rel=1e-12)
    mobility = _box_corner_mobility(L, W, t)
    r, n = np.array([L / 2, W / 2, -t / 2]), np.array([0.0, 0.0, 1.0])
    inertia = np.array([W**2 + t**2, L**2 + t**2, L**2 + W**2]) / 12.0
    assert mobility[2, 2] == pytest.approx(1 + np.sum(np.cross(r, n) ** 2 / inertia), rel=1e-12)
    assert mobility[2, 2] == pytest.approx(6.589, abs=1e-3)
    assert _box_corner_mobility(1.0, 0.8, 1e-6)[2, 2] == pytest.approx(7.0, rel=1e-6)
    # tangential mobility below the normal one: no inertia factor j > 0 states it exactly
    assert mobility[0, 0] / mobility[2, 2] < 1 and mobility[1, 1] / mobility[2, 2] < 1
    example = load_scene(ROOT / "examples" / "slider_corner_disk.toml")
    assert example.impactor.mass == pytest.approx(slider_mass / mobility[2, 2], rel=0.02)


def test_a_scene_states_an_inertia_factor_up_to_the_bound():
    text = MINIMAL.replace("velocity = 0.2", "velocity = 0.2\nangle = 80\ninertia_factor = {}")
    assert parse_scene(text.format(3000)).impactor.inertia_factor == 3000.0
    assert parse_scene(text.format("1e8")).impactor.inertia_factor == 1e8
    with pytest.raises(InputError, match=r"inertia_factor = 2e\+08 is outside the valid range "
                                         r"\(0, 1e\+08\]"):
        parse_scene(text.format("2e8"))
