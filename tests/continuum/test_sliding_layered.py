"""Sliding line contact on a layer stack (continuum.contact.sliding_layered), against oracles.

Units in the checks: lengths in b, stresses in p0 (the module's private `_field`), and SI through
the public API. Oracles: the homogeneous closed form `sliding.cylinder_stresses` (verified on its
own in test_sliding_homogeneous.py), interface continuity, equilibrium of the resultants.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from filmscale.continuum.contact import sliding_layered as sl
from filmscale.continuum.contact.sliding import cylinder_sliding, cylinder_stresses
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError

B = 1e-4                                                      # contact half-width used, m
STEEL = ElasticPlastic(E=210e9, nu=0.3, sigma_y=1.5e9, name="steel")
TIN = ElasticPlastic(E=400e9, nu=0.22, sigma_y=4e9, name="TiN")
AL = ElasticPlastic(E=70e9, nu=0.34, sigma_y=3e8, name="Al")
DLC = ElasticPlastic(E=150e9, nu=0.25, sigma_y=5e9, name="DLC")
CR = ElasticPlastic(E=280e9, nu=0.21, sigma_y=1e9, name="Cr")
KEYS = ("sxx", "syy", "szz", "txz")


def stack(*layers, substrate):
    return LayerStack(tuple(Layer(h * B, m) for h, m in layers), substrate)


def worst(a, b, keys=KEYS):
    return max(float(np.max(np.abs(a[k] - b[k]))) for k in keys)


# ------------------------------------------------------------- (1) identical layers
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_identical_layers_give_the_homogeneous_closed_form(mu):
    st = stack((0.3, STEEL), (0.5, STEEL), (0.2, STEEL), substrate=STEEL)
    rng = np.random.default_rng(1)
    # points inside every layer and the substrate, on each interface (both sides), surface
    x = rng.uniform(-3, 3, 160)
    z = np.concatenate((rng.uniform(0, 0.3, 30), rng.uniform(0.3, 0.8, 30),
                        rng.uniform(0.8, 1.0, 30), rng.uniform(1.0, 3.0, 30),
                        np.repeat([0.3, 0.8, 1.0, 0.0], 10)))
    ref = cylinder_stresses(x, z, 1.0, 1.0, mu, STEEL.nu)
    for side in ("below", "above"):
        out = sl.layered_cylinder_stresses(x * B, z * B, st, B, 1.0, mu, side=side)
        assert worst(out, ref) < 1e-6
    # the spectral integral on its own (no closed-form part), inside the layers
    zin = np.maximum(z, 0.05)
    out = sl._field(x, zin, st, mu, subtract=False, b=B)
    assert worst(out, cylinder_stresses(x, zin, 1.0, 1.0, mu, STEEL.nu)) < 1e-6


def test_spectral_integral_alone_reproduces_closed_form_for_a_half_space():
    x = np.linspace(-3, 3, 25)
    z = np.linspace(0.05, 3, 20)
    X, Z = (a.ravel() for a in np.meshgrid(x, z))
    out = sl._field(X, Z, LayerStack((), AL), 0.3, subtract=False)
    assert worst(out, cylinder_stresses(X, Z, 1.0, 1.0, 0.3, AL.nu)) < 1e-6


# ------------------------------------------------------------- (2) thick film
@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
def test_thick_film_gives_the_film_field_near_the_contact(film, sub):
    X, Z = (a.ravel() for a in np.meshgrid(np.linspace(-2, 2, 21), np.linspace(0, 2, 11)))
    dev = {}
    for H in (20.0, 100.0):
        out = sl._field(X, Z, stack((H, film), substrate=sub), 0.3, b=B)
        ref = cylinder_stresses(X, Z, 1.0, 1.0, 0.3, film.nu)
        dev[H] = {k: float(np.max(np.abs(out[k] - ref[k]))) for k in KEYS}
        # sigma_zz and tau_xz vanish at the surface: within 1 % p0 already at H = 20 b
        assert dev[H]["szz"] < 1e-2 and dev[H]["txz"] < 1e-2
    # sigma_xx (and sigma_yy) carry the substrate's far-field correction, of order P'/H
    # (dimensional analysis: the only length of the correction is H): it falls as 1/H
    for k in ("sxx", "syy"):
        assert dev[100.0][k] * 100 == pytest.approx(dev[20.0][k] * 20, rel=0.05)
    assert dev[100.0]["sxx"] < 1.5e-2
    out = sl._field(X, Z, stack((1000.0, film), substrate=sub), 0.3, b=B)
    assert worst(out, cylinder_stresses(X, Z, 1.0, 1.0, 0.3, film.nu)) < 2e-3


# ------------------------------------------------------------- (3) interface conditions
def eps_xx(s, m):
    return ((1 - m.nu ** 2) * s["sxx"] - m.nu * (1 + m.nu) * s["szz"]) / m.E


@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_interface_continuity(film, sub, mu):
    st = stack((0.3, film), (0.4, sub), substrate=film)
    x = np.linspace(-3, 3, 61)
    for zi, above, below in ((0.3, film, sub), (0.7, sub, film)):
        z = np.full_like(x, zi)
        lo = sl._field(x, z, st, mu, side="below", b=B)
        up = sl._field(x, z, st, mu, side="above", b=B)
        assert np.max(np.abs(lo["szz"] - up["szz"])) < 1e-8
        assert np.max(np.abs(lo["txz"] - up["txz"])) < 1e-8
        assert np.max(np.abs(lo["sxx"] - up["sxx"])) > 0.05        # it does jump
        e_up, e_lo = eps_xx(up, above), eps_xx(lo, below)
        assert np.max(np.abs(e_up - e_lo)) < 1e-6 * np.max(np.abs(e_up))
        assert np.allclose(up["syy"], above.nu * (up["sxx"] + up["szz"]))
        assert np.allclose(lo["syy"], below.nu * (lo["sxx"] + lo["szz"]))
    # the surface tractions are the Hertz ones
    s0 = sl._field(x, np.zeros_like(x), st, mu, b=B)
    p = np.sqrt(np.clip(1 - x * x, 0, None))
    assert np.max(np.abs(s0["szz"] + p)) < 1e-8
    assert np.max(np.abs(s0["txz"] + mu * p)) < 1e-8


# ------------------------------------------------------------- (4) equilibrium
def _x_rule(X=300.0):
    g, w = np.polynomial.legendre.leggauss(24)
    edges = np.unique(np.concatenate((np.linspace(-3, 3, 25), np.geomspace(3, X, 24),
                                      -np.geomspace(3, X, 24))))
    a, b = edges[:-1, None], edges[1:, None]
    return (0.5 * (a + b) + 0.5 * (b - a) * g).ravel(), (0.5 * (b - a) * w).ravel()


def test_equilibrium_of_resultants(film=TIN, sub=AL):
    mu, Pp, Xm = 0.3, math.pi / 2, 300.0                  # P' = pi p0 b / 2
    st = stack((0.3, film), (0.2, DLC), substrate=sub)
    xs, ws = _x_rule(Xm)
    for zz in (0.15, 1.0):               # in the film, in the substrate
        o = sl._field(xs, np.full_like(xs, zz), st, mu, b=B)
        # tails beyond |x| = X: tau ~ C/x^2 (sigma_zz ~ 1/x^4: negligible); C from the ends
        far = sl._field(np.array([-Xm, Xm]), np.full(2, zz), st, mu, b=B)
        C = 0.5 * Xm ** 2 * float(far["txz"][0] + far["txz"][1])
        assert ws @ o["szz"] == pytest.approx(-Pp, abs=1e-5 * Pp)
        assert ws @ o["txz"] + 2 * C / Xm == pytest.approx(-mu * Pp, abs=1e-5 * Pp)


# ------------------------------------------------------------- (5) very thin film
@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_very_thin_film_gives_the_substrate_field(film, sub, mu):
    """Limit h -> 0 (h = 1e-3 b): the field is the homogeneous substrate's, McEwen's closed
    form (cylinder_stresses with the substrate's nu); tolerance 1e-2 p0 (a film of any
    thickness perturbs the field by O(h/b) times the modulus contrast)."""
    h = 1e-3
    st = stack((h, film), substrate=sub)
    X, Z = (a.ravel() for a in np.meshgrid(np.linspace(-2, 2, 41), np.linspace(0.1, 2, 8)))
    out = sl._field(X, Z, st, mu, b=B)
    assert worst(out, cylinder_stresses(X, Z, 1.0, 1.0, mu, sub.nu)) < 1e-2
    # right below the film, away from the contact edges (whose sqrt behaviour the film
    # smooths over a few film thicknesses: 0.02-0.05 p0 there for TiN on Al)
    x = np.concatenate((np.linspace(-0.7, 0.7, 15), [-2, -1.5, -1.3, 1.3, 1.5, 2]))
    z = np.full_like(x, 2 * h)
    out = sl._field(x, z, st, mu, b=B)
    assert worst(out, cylinder_stresses(x, z, 1.0, 1.0, mu, sub.nu)) < 1e-2


# ------------------------------------------------------------- API and per-layer result
def test_public_api_units_and_shapes():
    """Units: the dimensional API equals p0 times the unit field (b = 1, p0 = 1) of `_field`,
    atol 1e-6 Pa on stresses of order 1e9 Pa (rounding); plane strain, so sxy = syz = 0."""
    st = stack((0.2, TIN), substrate=STEEL)
    x = np.linspace(-2, 2, 7)[:, None] * B
    z = np.array([0.0, 0.1, 0.2, 0.5]) * B
    out = sl.layered_cylinder_stresses(x, z, st, B, 2e9, 0.2)
    assert out["sxx"].shape == (7, 4)
    ref = sl._field(*(a.ravel() / B for a in np.broadcast_arrays(x, z)), st, 0.2, b=B)
    assert np.allclose(out["szz"].ravel(), 2e9 * ref["szz"], atol=1e-6)
    assert np.all(out["sxy"] == 0) and np.all(out["syz"] == 0)


def test_sliding_summary_on_identical_layers_matches_homogeneous():
    """Limit: a steel film on steel is homogeneous steel, so the summary equals the
    homogeneous `cylinder_sliding` (von Mises maximum, rel 1e-4, the grid's resolution) and
    the surface tensile maximum 2 mu p0 at the trailing edge x = -b (closed form, McEwen
    1949; rel 1e-3, and 0.02 b in position: the x grid's spacing)."""
    st = stack((0.3, STEEL), substrate=STEEL)
    r = sl.layered_cylinder_sliding(st, B, 1e9, 0.2, nx=81, nz=12)
    ref = cylinder_sliding(1.0, 1.0, 1e-2, 210e9, 0.3, 0.2)     # (b, p0 from P, L, R)
    vm = max(p.vm_max for p in r.layers) / 1e9
    assert vm == pytest.approx(ref.vm_max / ref.p0, rel=1e-4)
    assert r.tensile_max == pytest.approx(2 * 0.2 * 1e9, rel=1e-3)
    assert r.tensile_x == pytest.approx(-B, abs=0.02 * B)
    assert len(r.layers) == 2 and r.layers[1].z_bottom == math.inf
    assert r.layers[0].yield_ratio == pytest.approx(r.layers[0].vm_max / 1.5e9)
    assert r.layers[0].interface_txz_max > 0 and r.layers[1].interface_txz_max is None


def test_sliding_summary_stiff_film():
    st = stack((0.2, TIN), (0.1, CR), substrate=AL)
    r = sl.layered_cylinder_sliding(st, B, 1e9, 0.3, nx=61, nz=8, refine=False)
    assert [p.name for p in r.layers] == ["TiN", "Cr", "Al"]
    for p in r.layers:
        assert p.z_top <= p.vm_z <= p.z_bottom and abs(p.vm_x) <= 2 * B
        assert p.vm_max > 0
    # the soft substrate under a stiff coating is closest to yield
    assert r.layers[2].yield_ratio > r.layers[0].yield_ratio


# ------------------------------------------------------------- input checks
@pytest.mark.parametrize("kw,name", [
    ({"b": -1.0}, "b"), ({"p0": float("nan")}, "p0"), ({"mu": -0.1}, "mu"),
    ({"z": -1e-6}, "z"), ({"x": float("inf")}, "x"), ({"side": "middle"}, "side"),
    ({"stack": STEEL}, "stack")])
def test_input_errors_name_the_parameter(kw, name):
    args = {"x": 0.0, "z": 1e-5, "stack": stack((0.2, TIN), substrate=STEEL), "b": B,
            "p0": 1e9, "mu": 0.2}
    args.update(kw)
    with pytest.raises(InputError, match=name):
        sl.layered_cylinder_stresses(**args)


def test_summary_input_errors():
    st = stack((0.2, TIN), substrate=STEEL)
    with pytest.raises(InputError, match="nx"):
        sl.layered_cylinder_sliding(st, B, 1e9, 0.2, nx=3)
    with pytest.raises(InputError, match="x_span"):
        sl.layered_cylinder_sliding(st, B, 1e9, 0.2, x_span=0.1)
