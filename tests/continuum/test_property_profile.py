"""Property-depth profiles: grouping, layer assignment, and the impact model's profile."""

import numpy as np
import pytest

from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.materials import DIAMOND, ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError

E_P_KNOTS = [200e9, 150e9, 100e9]     # target plane-strain modulus at 0, 20, 100 nm


def indents(jitter=0.02, seed=0):
    """Five repeats at each of six depths; E_p and H piecewise linear with a kink at 20 nm."""
    depths = np.repeat([5e-9, 10e-9, 15e-9, 30e-9, 50e-9, 80e-9], 5)
    rng = np.random.default_rng(seed)
    h_c = depths * (1 + rng.uniform(-jitter, jitter, depths.size))
    E_p = np.interp(h_c, [0, 20e-9, 100e-9], E_P_KNOTS)
    E_r = 1 / (1 / E_p + DIAMOND.compliance)
    H = np.interp(h_c, [0, 20e-9, 100e-9], [20e9, 14e9, 8e9])
    return h_c, E_r, H


def test_groups_and_layers():
    h_c, E_r, H = indents(jitter=0.0)
    p = property_profile(h_c, E_r * (1 + 0.01 * np.tile([-2, -1, 0, 1, 2], 6)), H,
                         interfaces=[20e-9], layer_names=["DLC", "substrate"])
    assert p.group_n.tolist() == [5] * 6
    assert np.all(p.layer[h_c < 20e-9] == 0) and np.all(p.layer[h_c > 20e-9] == 1)
    # +-1, +-2 % steps: sample std = sqrt(10/4) % of the mean
    np.testing.assert_allclose(p.group_E_r_std / p.group_E_r, np.sqrt(2.5) / 100, rtol=1e-12)
    stats = p.layer_statistics()
    assert [s["n"] for s in stats] == [15, 15] and stats[0]["layer"] == "DLC"


def test_profile_fit_reproduces_piecewise_truth_and_feeds_impact():
    h_c, E_r, H = indents()
    stack = LayerStack([Layer(20e-9, ElasticPlastic(200e9, 0.25, 8e9, name="DLC"))],
                       ElasticPlastic(120e9, 0.3, 3e9, name="substrate"))
    profile = property_profile(h_c, E_r, H, layers=stack).to_depth_profile(nu=0.25)
    # noise-free piecewise-linear data with the kink at the interface: fitted exactly
    E_p, s_y, _ = profile.properties(np.array([10e-9, 20e-9, 60e-9]), 1e-6)
    np.testing.assert_allclose(E_p, np.interp([10e-9, 20e-9, 60e-9], [0, 20e-9, 100e-9],
                                              E_P_KNOTS), rtol=1e-9)
    np.testing.assert_allclose(s_y * 2.8, [17e9, 14e9, 11e9], rtol=1e-9)
    result = ImpactModel(profile, contact_law("komvopoulos-ye")).maxima(0.5, 10e-6, 1.6e-6)
    assert np.isfinite(result.delta_max) and result.delta_max > 0


def test_failed_indents_left_out_and_bad_interfaces_rejected():
    h_c, E_r, H = indents()
    E_r = E_r.copy()
    E_r[3] = np.nan
    assert property_profile(h_c, E_r, H).h_c.size == h_c.size - 1
    with pytest.raises(InputError, match="increasing"):
        property_profile(h_c, E_r, H, interfaces=[30e-9, 20e-9])
    with pytest.raises(InputError, match="layer names"):
        property_profile(h_c, E_r, H, interfaces=[20e-9], layer_names=["a"])
