"""Depth profiles: Gao weights, multilayer limits, measured tables."""

import numpy as np
import pytest

from filmscale.continuum.contact.profiles import (StackProfile, TableProfile, UniformProfile,
                                                  gao_i0, gao_i1)
from filmscale.continuum.materials import DIAMOND, ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError

GLASS = ElasticPlastic(E=90e9, nu=0.25, sigma_y=2.4e9, name="glass")
DLC = ElasticPlastic(E=200e9, nu=0.25, sigma_y=8e9, name="DLC")


def test_gao_weights_published_values_and_limits():
    assert gao_i0(1.0, 0.3) == pytest.approx(0.4494, abs=5e-5)   # docs/physics.md section 7
    assert gao_i1(1.0) == pytest.approx(0.7206, abs=5e-5)
    assert gao_i0(0.0, 0.3) == 0.0 and gao_i1(0.0) == 0.0
    assert gao_i0(1e9, 0.3) == pytest.approx(1.0, abs=1e-8)
    assert gao_i1(1e9) == pytest.approx(1.0, abs=1e-8)
    x = np.geomspace(1e-6, 1e6, 2000)
    for nu in (0.0, 0.25, 0.45):
        assert np.all(np.diff(gao_i0(x, nu)) > 0)
    assert np.all(np.diff(gao_i1(x)) > 0)


def test_identical_film_and_substrate_is_homogeneous():
    film = ElasticPlastic(E=GLASS.E, nu=GLASS.nu, sigma_y=GLASS.sigma_y, name="same")
    stack = LayerStack([Layer(5e-9, film), Layer(20e-9, film)], GLASS)
    delta = np.geomspace(1e-12, 1e-6, 50)
    got = StackProfile(stack).properties(delta, 10e-6)
    want = UniformProfile(GLASS).properties(delta, 10e-6)
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=1e-14)


def test_single_layer_reduces_to_gao():
    film = ElasticPlastic(E=200e9, nu=GLASS.nu, sigma_y=8e9, name="film")   # same nu
    t, R = 20e-9, 5e-6
    delta = np.geomspace(1e-12, 1e-6, 40)
    e_p, s_y, nu = StackProfile(LayerStack([Layer(t, film)], GLASS)).properties(delta, R)
    i0 = gao_i0(t / np.sqrt(R * delta), GLASS.nu)
    want = GLASS.plane_strain_modulus + (film.plane_strain_modulus
                                         - GLASS.plane_strain_modulus) * i0
    np.testing.assert_allclose(e_p, want, rtol=1e-13)
    np.testing.assert_allclose(s_y, GLASS.sigma_y + (film.sigma_y - GLASS.sigma_y) * i0,
                               rtol=1e-13)
    np.testing.assert_allclose(nu, GLASS.nu, rtol=1e-14)


def test_thick_film_gives_film_and_deep_contact_gives_substrate():
    stack = LayerStack([Layer(10e-6, DLC)], GLASS)
    prof = StackProfile(stack)
    R = 10e-6
    shallow = 1e-10                               # a = 32 nm << t = 10 um
    e_p, s_y, nu = prof.properties(shallow, R)
    # error bound: (1 - I0(t/a)) x contrast
    bound = (1 - gao_i0(10e-6 / np.sqrt(R * shallow), 0.25)) * 2
    assert e_p == pytest.approx(DLC.plane_strain_modulus, rel=bound)
    assert s_y == pytest.approx(DLC.sigma_y, rel=bound)
    thin = StackProfile(LayerStack([Layer(1e-9, DLC)], GLASS))
    deep = 9e-6                                    # a = 9.5 um >> t = 1 nm
    bound = gao_i0(1e-9 / np.sqrt(R * deep), 0.25) * 2
    assert thin.properties(deep, R)[0] == pytest.approx(GLASS.plane_strain_modulus, rel=bound)


def test_multilayer_weights_are_positive_and_sum_to_one():
    layers = [Layer(t, ElasticPlastic(E=e, nu=n, sigma_y=s, name=str(i)))
              for i, (t, e, n, s) in enumerate([(4e-9, 200e9, 0.2, 8e9), (16e-9, 180e9, 0.3, 5e9),
                                               (8e-9, 150e9, 0.35, 3.5e9)])]
    prof = StackProfile(LayerStack(layers, GLASS))
    w1, w0 = prof.weights(np.geomspace(1e-12, 1e-5, 100), 3e-6)
    for w in (w1, w0):
        assert np.all(w >= 0)
        np.testing.assert_allclose(w.sum(axis=-1), 1.0, rtol=1e-14)


def test_table_recovers_exact_piecewise_linear_data_and_converts_indenter_modulus():
    knots = np.array([2e-9, 20e-9, 60e-9, 200e-9])
    e_p_knots = np.array([180e9, 160e9, 120e9, 100e9])
    h_knots = np.array([20e9, 12e9, 8e9, 6e9])
    h_c = np.linspace(2e-9, 200e-9, 60)
    e_p = np.interp(h_c, knots, e_p_knots)
    E_r = 1.0 / (1.0 / e_p + DIAMOND.compliance)      # what a diamond tip measures
    H = np.interp(h_c, knots, h_knots)
    prof = TableProfile.from_measurements(h_c, E_r, H, breakpoints=knots[1:-1],
                                          hardness_factor=2.8)
    np.testing.assert_allclose(prof.plane_strain_modulus, e_p_knots, rtol=1e-10)
    np.testing.assert_allclose(prof.hardness, h_knots, rtol=1e-10)
    e, s, nu = prof.properties(np.array([1e-9, 40e-9, 1e-6]), 1e-5)
    np.testing.assert_allclose(e, [180e9, 140e9, 100e9], rtol=1e-10)  # constant beyond ends
    np.testing.assert_allclose(s, np.array([20e9, 10e9, 6e9]) / 2.8, rtol=1e-10)


def test_table_input_errors_name_the_column():
    with pytest.raises(InputError, match="H has"):
        TableProfile.from_measurements([1e-9, 2e-9], [1e11, 1e11], [1e10, -1.0])
    with pytest.raises(InputError, match="differ in length"):
        TableProfile.from_measurements([1e-9, 2e-9], [1e11], [1e10, 1e10])
    with pytest.raises(InputError, match="not below"):
        TableProfile.from_measurements([1e-9, 2e-9], [2e12, 2e12], [1e10, 1e10])
    with pytest.raises(InputError, match="without enough indents"):
        TableProfile.from_measurements([1e-9, 2e-9, 3e-9], [1e11] * 3, [1e10] * 3,
                                       breakpoints=[1.1e-9, 1.2e-9])


def test_nix_gao_size_effect_scales_each_layers_sigma_y():
    """sigma_y(delta) = sigma_y sqrt(1 + h*/delta) (Nix & Gao 1998): exact on a homogeneous
    target, the macroscopic value when delta >> h*, and on a stack only the film's share
    (its I0 weight) moves."""
    from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
    sub = ElasticPlastic(90e9, 0.25, 2.4e9)
    film = ElasticPlastic(200e9, 0.3, 8e9)
    delta = np.geomspace(1e-10, 1e-5, 30)
    _, sy, _ = StackProfile(LayerStack((), sub), (1e-7,)).properties(delta, 1e-6)
    np.testing.assert_allclose(sy, 2.4e9 * np.sqrt(1 + 1e-7 / delta), rtol=1e-14)
    stack = LayerStack([Layer(5e-9, film)], sub)
    plain, sized = StackProfile(stack), StackProfile(stack, (2e-8,))
    _, w0 = plain.weights(delta, 1e-6)
    extra = sized.properties(delta, 1e-6)[1] - plain.properties(delta, 1e-6)[1]
    # atol: the difference of two sums of order 1e9 Pa loses about 1e-7 Pa to round-off
    np.testing.assert_allclose(extra, w0[:, 0] * 8e9 * (np.sqrt(1 + 2e-8 / delta) - 1),
                               rtol=1e-12, atol=1e-3)
    with pytest.raises(InputError, match="h_star"):
        StackProfile(stack, (1e-8, 1e-8, 1e-8))


@pytest.mark.parametrize("h_star", [(), (2e-8, 0.0, 5e-9, 1e-8)])
def test_properties_equal_the_explicit_weighted_sums(h_star):
    # properties telescopes sum_j w_j p_j over the interfaces; the layer weights of `weights`
    # (a second route through the same Gao terms) must give the same numbers to rounding
    layers = [Layer(t, ElasticPlastic(E=e, nu=n, sigma_y=s, name=str(i)))
              for i, (t, e, n, s) in enumerate([(4e-9, 200e9, 0.2, 8e9), (16e-9, 180e9, 0.3, 5e9),
                                               (8e-9, 150e9, 0.35, 3.5e9)])]
    prof = StackProfile(LayerStack(layers, GLASS), h_star)
    delta = np.geomspace(1e-12, 1e-5, 60)[:, None]
    R = np.array([1e-7, 3e-6, 5e-5])
    e_p, s_y, nu = prof.properties(delta, R)
    assert e_p.shape == s_y.shape == nu.shape == (60, 3)
    w1, w0 = prof.weights(delta, R)
    mats = prof.materials()
    np.testing.assert_allclose(e_p, w0 @ [m.plane_strain_modulus for m in mats], rtol=1e-13)
    np.testing.assert_allclose(s_y, np.sum(w0 * prof.strengths(delta), axis=-1),
                               rtol=1e-13)
    np.testing.assert_allclose(nu, w1 @ [m.nu for m in mats], rtol=1e-13)
