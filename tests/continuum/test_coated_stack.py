"""The exact contact of a rigid sphere on a bonded stack of layers on a half-space or a rigid
base (`coated.stack_sphere_curve`, `coated.stack_solution`), against references written here:
the closed-form kernel of one film (Perriot & Barthel 2004), one film cut into two, the
long-wave limit of a layer on a rigid base, the thin bonded layer in uniaxial strain, and a
rigid base against a very stiff half-space."""

import math

import numpy as np
import pytest

from filmscale.continuum.contact import coated
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError

FILM = ElasticPlastic(100e9, 0.3, 1e9)
SUB = ElasticPlastic(570e9, 0.2, 5e9)
R = 1e-6


def confined(m: ElasticPlastic) -> float:
    """The modulus of uniaxial strain, E (1 - nu) / ((1 + nu)(1 - 2 nu))."""
    return m.E * (1 - m.nu) / ((1 + m.nu) * (1 - 2 * m.nu))


@pytest.mark.parametrize("ratio", [1 / 5.7, 5.7, 100.0])
def test_one_layer_on_a_half_space_is_the_closed_form_kernel(ratio):
    """E_f / E_s = ``ratio``; C(u) at u = k t from 1e-4 to 10."""
    sub = ElasticPlastic(FILM.E / ratio, 0.2, 1e6)
    u = np.array([1e-4, 0.01, 0.3, 1.0, 3.0, 10.0])
    closed = coated._compliance(u, FILM.shear_modulus / sub.shear_modulus, FILM.nu, sub.nu)
    stack = coated._stack_compliance(u, (1.0,), (1.0, sub.E / FILM.E), (FILM.nu, sub.nu), False)
    assert stack == pytest.approx(closed, rel=1e-10)


def test_one_film_cut_into_two_is_the_same_film():
    delta = np.geomspace(1e-10, 2e-8, 12)
    t = 20e-9
    one = coated.coated_sphere_curve(delta, R, t, FILM, SUB)
    two = coated.stack_sphere_curve(delta, R, [(0.3 * t, FILM), (0.7 * t, FILM)], SUB)
    assert two == pytest.approx(one, rel=1e-6)


def test_a_layer_on_a_rigid_base_at_long_waves_compresses_in_uniaxial_strain():
    """k H << 1: the surface sinks by p sum(h_j / M_j), so C = k sum(h_j / M_j) E'_1 / 2."""
    lower = ElasticPlastic(2 * FILM.E, 0.2, 1e6)
    u = np.array([1e-6, 1e-5, 1e-4])
    C = coated._stack_compliance(u, (1.0, 3.0), (1.0, lower.E / FILM.E), (FILM.nu, lower.nu),
                                 True)
    sinks = 1.0 / confined(FILM) + 3.0 / confined(lower)      # per unit pressure and t_1
    assert C == pytest.approx(u * sinks * FILM.plane_strain_modulus / 2, rel=1e-3)


def test_a_thin_layer_on_a_rigid_base_tends_to_uniaxial_strain():
    """a >> H: p = M (delta - r^2/2R) / H inside a = sqrt(2 R delta), so P = pi M a^4 / (4 H R)
    and S = pi a^2 M / H; the exact solution approaches both as H/a (error halving with H)."""
    H, M = 1e-9, confined(FILM)
    errors = []
    for lam in (20, 40, 80):
        a = lam * H
        c = coated.stack_solution(a, R, [(H, FILM)], coated.RIGID)
        errors.append(c.load / (math.pi * M * a**4 / (4 * H * R)) - 1)
        assert c.delta == pytest.approx(a * a / (2 * R), rel=0.6 * H / a + 1e-3)
        assert c.stiffness == pytest.approx(math.pi * a * a * M / H, rel=0.6 * H / a + 1e-3)
    assert 0 < errors[-1] < 0.01
    assert errors[0] / errors[1] == pytest.approx(2, rel=0.05)
    assert errors[1] / errors[2] == pytest.approx(2, rel=0.05)


def test_a_rigid_base_is_the_limit_of_a_stiff_half_space():
    """The same layers on a half-space 10 and 100 times stiffer than the lower layer: the
    load approaches the rigid base's as the base's compliance, 1/stiffness."""
    delta = np.geomspace(1e-10, 3e-9, 8)
    layers = [(2e-9, FILM), (5e-9, SUB)]
    rigid = coated.stack_sphere_curve(delta, R / 100, layers, coated.RIGID)
    gaps = [np.max(np.abs(coated.stack_sphere_curve(
        delta, R / 100, layers, ElasticPlastic._trial(SUB.E * f, SUB.nu, 1e6)) / rigid - 1))
        for f in (10, 100)]
    assert gaps[1] < 0.01
    assert gaps[0] / gaps[1] == pytest.approx(10, rel=0.15)
    # and the base stiffens the contact: above the same layers on the half-space
    free = coated.stack_sphere_curve(delta, R / 100, layers, SUB)
    assert np.all(rigid > free)


def test_a_deep_rigid_base_is_a_rigid_sink_of_order_p_over_e_h():
    """H >> a (the thick-film limit of docs/layered-contact.md): the load at a contact radius
    stays Hertz's, and the base holds the approach back by a constant times P/(E H); the
    constant is the same at H = 100 a and 1000 a, and below Boussinesq's displacement of a
    half-space's point at depth H, (1 + nu)(3 - 2 nu)/(2 pi) (Johnson 1985, 3.2), which
    holds a point where the base holds a plane (measured: 0.399 against 0.497)."""
    a, r = 1e-9, 1e-8
    constants = []
    for k in (100, 1000):
        c = coated.stack_solution(a, r, [(k * a, FILM)], coated.RIGID)
        assert c.load == pytest.approx(4 / 3 * FILM.plane_strain_modulus * a**3 / r, rel=1e-5)
        constants.append((a * a / r - c.delta) / (c.load / (FILM.E * k * a)))
    assert constants[0] == pytest.approx(constants[1], rel=1e-3)
    assert 0 < constants[1] < (1 + FILM.nu) * (3 - 2 * FILM.nu) / (2 * math.pi)


@pytest.mark.parametrize("layers, base, match", [
    ([], coated.RIGID, "layers is empty"),
    ([(-1e-9, FILM)], coated.RIGID, r"layers\[0\] thickness"),
    ([(1e-9, "diamond")], coated.RIGID, r"layers\[0\] material"),
    ([(1e-9, FILM)], "granite", "base"),
])
def test_bad_stacks_are_refused_by_name(layers, base, match):
    with pytest.raises(InputError, match=match):
        coated.stack_sphere_curve([1e-10], R, layers, base)
