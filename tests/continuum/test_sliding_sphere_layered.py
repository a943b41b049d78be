"""Sliding sphere on a layer stack (continuum.contact.sliding_sphere_layered), against oracles.

Units in the checks: lengths in a, stresses in p0 (the module's private `_field`, on the scaled
stack `_scaled`), and SI through the public API. Oracles: the homogeneous half-space field
`sliding.sphere_stresses` (Hamilton 1983 normal closed form + Cerruti quadrature, verified on
its own in test_sliding_homogeneous.py), interface continuity by Hooke's law, equilibrium of the
resultants over a plane, the thick- and thin-film limits, Hamilton's trailing-edge tension.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from filmscale.continuum.contact import sliding_sphere_layered as ssl
from filmscale.continuum.contact.sliding import sphere_sliding, sphere_stresses
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.errors import InputError

A = 1e-4                                                      # contact radius used, m
STEEL = ElasticPlastic(E=210e9, nu=0.3, sigma_y=1.5e9, name="steel")
TIN = ElasticPlastic(E=400e9, nu=0.22, sigma_y=4e9, name="TiN")
AL = ElasticPlastic(E=70e9, nu=0.34, sigma_y=3e8, name="Al")
DLC = ElasticPlastic(E=150e9, nu=0.25, sigma_y=5e9, name="DLC")
CR = ElasticPlastic(E=280e9, nu=0.21, sigma_y=1e9, name="Cr")
KEYS = ("sxx", "syy", "szz", "sxy", "syz", "txz")
P = 2.0 * math.pi / 3.0                                       # total load in units p0 a^2


def stack(*layers, substrate):
    return LayerStack(tuple(Layer(h * A, m) for h, m in layers), substrate)


def worst(a, b, keys=KEYS):
    return max(float(np.max(np.abs(a[k] - b[k]))) for k in keys)


def unit_field(x, y, z, st, mu, **kw):
    """The stresses (units p0) at points in units of a."""
    x, y, z = (np.ravel(v).astype(float) for v in np.broadcast_arrays(x, y, z))
    return ssl._field(x, y, z, ssl._scaled(st, A), mu, **kw)


# ------------------------------------------------------------- (1) identical layers
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_identical_layers_give_the_homogeneous_field(mu):
    st = stack((0.3, STEEL), (0.5, STEEL), (0.2, STEEL), substrate=STEEL)
    rng = np.random.default_rng(1)
    # points inside every layer and the substrate, on each interface (both sides), surface
    x, y = rng.uniform(-2, 2, 100), rng.uniform(-2, 2, 100)
    z = np.concatenate((rng.uniform(0, 0.3, 20), rng.uniform(0.3, 0.8, 20),
                        rng.uniform(0.8, 1.0, 20), rng.uniform(1.0, 3.0, 20),
                        np.repeat([0.3, 0.8, 1.0, 0.0], 5)))
    ref = sphere_stresses(x, y, z, 1.0, 1.0, mu, STEEL.nu)
    for side in ("below", "above"):
        out = ssl.layered_sphere_stresses(x * A, y * A, z * A, st, A, 1.0, mu, side=side)
        assert worst(out, ref) < 1e-6
    # the spectral integral of the layered solution on its own (no closed-form part)
    zin = np.maximum(z, 0.1)
    out = unit_field(x, y, zin, st, mu, subtract=False)
    assert worst(out, sphere_stresses(x, y, zin, 1.0, 1.0, mu, STEEL.nu)) < 1e-6


# ------------------------------------------------------------- (2) the spectral machinery
def test_spectral_integral_alone_reproduces_the_half_space_field():
    """The full spectral integral (P-SV and SH depth functions, rotation to (x, y), the
    angular harmonics J0..J3, every sign), no closed-form part, against Hamilton + Cerruti
    off the y = 0 plane; z >= 0.1 a, where the k-integral converges within the cut."""
    rng = np.random.default_rng(7)
    r, phi = rng.uniform(0, 2.5, 80), rng.uniform(0, 2 * math.pi, 80)
    x, y, z = r * np.cos(phi), r * np.sin(phi), rng.uniform(0.1, 2.5, 80)
    x[0] = y[0] = 0.0                                            # on the axis
    out = unit_field(x, y, z, LayerStack((), AL), 0.3, subtract=False)
    ref = sphere_stresses(x, y, z, 1.0, 1.0, 0.3, AL.nu)
    assert worst(out, ref) < 1e-6
    assert np.max(np.abs(ref["sxy"][1:])) > 0.01 and np.max(np.abs(ref["syz"])) > 0.01


# ------------------------------------------------------------- (3) interface conditions
def strains(s, m):
    """eps_xx, eps_yy, eps_xy by Hooke's law."""
    return ((s["sxx"] - m.nu * (s["syy"] + s["szz"])) / m.E,
            (s["syy"] - m.nu * (s["sxx"] + s["szz"])) / m.E,
            (1 + m.nu) * s["sxy"] / m.E)


@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
def test_interface_continuity(film, sub):
    st = stack((0.3, film), (0.4, sub), substrate=film)
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-2, 2, 10), rng.uniform(0.1, 2, 10) * rng.choice([-1, 1], 10)
    for zi, above, below in ((0.3, film, sub), (0.7, sub, film)):
        lo = unit_field(x, y, zi, st, 0.3, side="below")
        up = unit_field(x, y, zi, st, 0.3, side="above")
        for k in ("szz", "txz", "syz"):
            assert np.max(np.abs(lo[k] - up[k])) < 1e-8
        assert np.max(np.abs(lo["sxx"] - up["sxx"])) > 0.05         # it does jump
        e_up, e_lo = strains(up, above), strains(lo, below)
        scale = max(float(np.max(np.abs(e))) for e in e_up)
        for eu, el in zip(e_up, e_lo):
            assert np.max(np.abs(eu - el)) < 1e-6 * scale
    # the surface tractions are the Hertz ones
    x, y = rng.uniform(-1.5, 1.5, 40), rng.uniform(-1.5, 1.5, 40)
    s0 = unit_field(x, y, 0.0, st, 0.3)
    p = np.sqrt(np.clip(1 - x * x - y * y, 0, None))
    assert np.max(np.abs(s0["szz"] + p)) < 1e-8
    assert np.max(np.abs(s0["txz"] + 0.3 * p)) < 1e-8
    assert np.max(np.abs(s0["syz"])) < 1e-8


# ------------------------------------------------------------- (4) equilibrium
def test_equilibrium_of_resultants():
    """Over a plane z = const (in the film, in the substrate): int szz = -P, int sxz = -mu P,
    int syz = 0, to 1e-5 P. Quadrature: polar, Gauss-Legendre in r (8 nodes a panel, 0.1 a
    panels to r = 3 a, geometric to R = 80 a) and the trapezoid rule with 4 angles, exact here:
    the stack is axisymmetric and the load has angular harmonics 0 and 1, so every Cartesian
    stress carries harmonics 0..3 only. Beyond R: the angle-averaged stress of a load of finite
    size decays in odd inverse powers of r (the Hankel transform of a k-function analytic at
    k = 0: its odd powers give r^-3, r^-5, ...); c3, c5, c7 fitted on r in [R/2, R] and
    integrated to infinity (the tail is ~1 % of mu P at z = a; the fit's error, measured against
    R = 30, 60, 100 a, falls as R^-5.5; at R = 80 a the resultants come out within 4.4e-6 P)."""
    mu, R = 0.3, 80.0
    st = stack((0.3, TIN), (0.2, DLC), substrate=AL)
    g, w = np.polynomial.legendre.leggauss(8)
    edges = np.unique(np.concatenate((np.linspace(0, 3, 31), np.geomspace(3, R, 19))))
    lo, hi = edges[:-1, None], edges[1:, None]
    r = (0.5 * (lo + hi) + 0.5 * (hi - lo) * g).ravel()
    wr = (0.5 * (hi - lo) * w).ravel() * r
    phi = 2 * math.pi * (np.arange(4) + 0.5) / 4
    Rr, Ph = np.meshgrid(r, phi, indexing="ij")
    far = r > R / 2
    basis = np.stack([r[far] ** -3, r[far] ** -5, r[far] ** -7], axis=1)
    for zz in (0.15, 1.0):                                     # in the film, in the substrate
        o = unit_field(Rr * np.cos(Ph), Rr * np.sin(Ph), zz, st, mu)
        res = {}
        for k in ("szz", "txz", "syz"):
            avg = o[k].reshape(Rr.shape).mean(axis=1)
            c = np.linalg.lstsq(basis, avg[far], rcond=None)[0]
            tail = 2 * math.pi * (c[0] / R + c[1] / (3 * R ** 3) + c[2] / (5 * R ** 5))
            res[k] = 2 * math.pi * wr @ avg + tail
        assert res["szz"] == pytest.approx(-P, abs=1e-5 * P)
        assert res["txz"] == pytest.approx(-mu * P, abs=1e-5 * P)
        assert abs(res["syz"]) < 1e-5 * P


# ------------------------------------------------------------- (5) thick film
@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
def test_thick_film_gives_the_film_field_near_the_contact(film, sub):
    """Near the contact (r, z <= 2a) a film of H = 20 a is the film's half-space to 1 % p0 in
    szz and sxz (they vanish at the surface). The in-plane stresses carry the substrate's
    correction, the response to a load P at distance H: of order P/H^2 in 3-D (P'/H in plane
    strain); measured 1.5e-3 p0 for TiN on Al at H = 20 a, so within 1 % too, and it falls as
    1/H^2 (checked between H = 40 a and 100 a)."""
    rng = np.random.default_rng(3)
    r, phi = rng.uniform(0, 2, 60), rng.uniform(0, 2 * math.pi, 60)
    x, y, z = r * np.cos(phi), r * np.sin(phi), rng.uniform(0, 2, 60)
    ref = sphere_stresses(x, y, z, 1.0, 1.0, 0.3, film.nu)
    dev = {}
    for H in (20.0, 40.0, 100.0):
        out = unit_field(x, y, z, stack((H, film), substrate=sub), 0.3)
        dev[H] = {k: float(np.max(np.abs(out[k] - ref[k]))) for k in KEYS}
    assert dev[20.0]["szz"] < 1e-2 and dev[20.0]["txz"] < 1e-2
    assert max(dev[20.0].values()) < 1e-2
    for k in ("sxx", "syy"):
        assert dev[100.0][k] * 100 ** 2 == pytest.approx(dev[40.0][k] * 40 ** 2, rel=0.05)


# ------------------------------------------------------------- (6) very thin film
@pytest.mark.parametrize("film,sub", [(TIN, AL), (AL, TIN)])
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_very_thin_film_gives_the_substrate_field(film, sub, mu):
    """Limit h -> 0 (h = 1e-3 a): below the film (z >= 0.1 a) the field is the homogeneous
    substrate's (sphere_stresses with the substrate's nu); tolerance 1e-2 p0 (a film perturbs
    the field by O(h/a) times the modulus contrast)."""
    st = stack((1e-3, film), substrate=sub)
    X, Y, Z = (v.ravel() for v in np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-1, 1, 5),
                                               np.linspace(0.1, 2, 5)))
    out = unit_field(X, Y, Z, st, mu)
    assert worst(out, sphere_stresses(X, Y, Z, 1.0, 1.0, mu, sub.nu)) < 1e-2


# ------------------------------------------------------------- (7) per-layer summary
@pytest.mark.parametrize("mu", [0.2, 0.5])
def test_sliding_summary_of_a_half_space_matches_sphere_sliding(mu):
    """A stack without layers is the homogeneous half-space: its largest von Mises stress
    equals `sphere_sliding`'s (which searches y >= 0 in 3-D; the maximum lies on y = 0, below
    the surface for mu = 0.2 and at the trailing edge for mu = 0.5), rel 1e-3; the surface
    tension at the trailing edge is Hamilton's (1983) p0 ((1 - 2nu)/3 + (4 + nu) pi mu / 8),
    rel 1e-6."""
    r = ssl.layered_sphere_sliding(LayerStack((), STEEL), A, 1e9, mu)
    ref = sphere_sliding(1.0, 1e-2, STEEL.E, STEEL.nu, mu)
    assert len(r.layers) == 1 and r.layers[0].z_bottom == math.inf
    assert r.layers[0].vm_max / 1e9 == pytest.approx(ref.vm_max / ref.p0, rel=1e-3)
    hamilton = (1 - 2 * STEEL.nu) / 3 + (4 + STEEL.nu) * math.pi * mu / 8
    assert r.tensile_max / 1e9 == pytest.approx(hamilton, rel=1e-6)
    assert r.tensile_x == pytest.approx(-A, abs=1e-6 * A)
    assert r.half_width == A and r.layers[0].interface_txz_max is None


def test_sliding_summary_stiff_film():
    st = stack((0.2, TIN), (0.1, CR), substrate=AL)
    r = ssl.layered_sphere_sliding(st, A, 1e9, 0.3, nx=41, nz=6, refine=False)
    assert [p.name for p in r.layers] == ["TiN", "Cr", "Al"]
    for p in r.layers:
        assert p.z_top <= p.vm_z <= p.z_bottom and abs(p.vm_x) <= 2 * A and p.vm_max > 0
    assert r.layers[0].interface_txz_max > 0 and r.layers[2].interface_txz_max is None
    # the soft substrate under a stiff coating is closest to yield
    assert r.layers[2].yield_ratio > r.layers[0].yield_ratio


# ------------------------------------------------------------- (8) the y = 0 grid
def test_xz_grid_equals_the_general_points():
    """`layered_sphere_xz` (per distinct |x| and depth, matrix products) against
    `layered_sphere_stresses` on the same points among 100 scattered others (which takes the
    per-point path and another k-rule): 1e-12 p0, rounding."""
    st = stack((0.1, TIN), (0.2, CR), substrate=AL)
    x = np.linspace(-2.5, 2.5, 41)
    z = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.7, 1.5])
    grid = ssl.layered_sphere_xz(x * A, z * A, st, A, 1.0, 0.3)
    assert grid["sxx"].shape == (7, 41)
    X, Z = np.meshgrid(x, z)
    rng = np.random.default_rng(2)
    xs = np.concatenate((X.ravel(), rng.uniform(-2, 2, 100)))
    ys = np.concatenate((np.zeros(X.size), rng.uniform(-2, 2, 100)))
    zs = np.concatenate((Z.ravel(), rng.uniform(0.02, 2, 100)))
    out = ssl.layered_sphere_stresses(xs * A, ys * A, zs * A, st, A, 1.0, 0.3)
    assert worst({k: v[:X.size].reshape(X.shape) for k, v in out.items()}, grid) < 1e-12
    assert np.all(grid["sxy"] == 0) and np.all(grid["syz"] == 0)


def test_public_api_units_and_shapes():
    """The dimensional API equals p0 times the unit field (a = 1, p0 = 1), atol 1e-6 Pa on
    stresses of order 1e9 Pa (rounding)."""
    st = stack((0.2, TIN), substrate=STEEL)
    x = np.linspace(-2, 2, 5)[:, None] * A
    z = np.array([0.0, 0.1, 0.2, 0.5]) * A
    out = ssl.layered_sphere_stresses(x, 0.3 * A, z, st, A, 2e9, 0.2)
    assert out["sxx"].shape == (5, 4) and set(out) == set(KEYS)
    ref = unit_field(*(v / A for v in np.broadcast_arrays(x, 0.3 * A, z)), st, 0.2)
    for k in KEYS:
        assert np.allclose(out[k].ravel(), 2e9 * ref[k], rtol=0, atol=1e-6)


# ------------------------------------------------------------- (9) input checks
@pytest.mark.parametrize("kw,name", [
    ({"a": -1.0}, "a"), ({"a": 0.0}, "a"), ({"p0": -1.0}, "p0"), ({"p0": float("nan")}, "p0"),
    ({"mu": -0.1}, "mu"), ({"mu": float("nan")}, "mu"), ({"z": -1e-6}, "z"),
    ({"x": float("inf")}, "x"), ({"side": "middle"}, "side"), ({"stack": STEEL}, "stack")])
def test_input_errors_name_the_parameter(kw, name):
    args = {"x": 0.0, "y": 0.0, "z": 1e-5, "stack": stack((0.2, TIN), substrate=STEEL),
            "a": A, "p0": 1e9, "mu": 0.2}
    args.update(kw)
    with pytest.raises(InputError, match=name):
        ssl.layered_sphere_stresses(**args)


def test_grid_and_summary_input_errors():
    st = stack((0.2, TIN), substrate=STEEL)
    with pytest.raises(InputError, match="z"):
        ssl.layered_sphere_xz([0.0], [-1e-6], st, A, 1e9, 0.2)
    with pytest.raises(InputError, match="a"):
        ssl.layered_sphere_xz([0.0], [0.0], st, -A, 1e9, 0.2)
    with pytest.raises(InputError, match="stack"):
        ssl.layered_sphere_sliding(None, A, 1e9, 0.2)
    with pytest.raises(InputError, match="nx"):
        ssl.layered_sphere_sliding(st, A, 1e9, 0.2, nx=3)
    with pytest.raises(InputError, match="mu"):
        ssl.layered_sphere_sliding(st, A, 1e9, -0.2)


def test_xz_rows_below_the_top_film_are_the_whole_spectral_integral():
    """`layered_sphere_xz` integrates the rows below the top film (on a half-space, below
    SPECTRAL_DEPTH) spectrally, with no Cerruti quadrature: they agree with the closed forms
    plus the correction within the quadrature's own error near the rim (5e-8 q0 at z ~ 0.2 a,
    docs/sliding.md), here 1e-7 p0, including points by the rim."""
    x = np.concatenate((np.linspace(-2.0, 2.0, 21), [-0.98, 0.98]))
    for st, z in ((stack((0.05, TIN), (0.2, CR), substrate=AL), [0.0, 0.02, 0.05, 0.1, 0.22, 0.6]),
                  (LayerStack((), AL), [0.0, 0.01, 0.05, 0.22, 1.0])):
        z = np.array(z)
        grid = ssl.layered_sphere_xz(x * A, z * A, st, A, 1.0, 0.4)
        X, Z = np.meshgrid(x, z)
        ref = ssl._field(X.ravel(), np.zeros(X.size), Z.ravel(), ssl._scaled(st, A), 0.4)
        assert all(v.shape == X.shape for v in grid.values())
        assert worst(grid, {k: v.reshape(X.shape) for k, v in ref.items()}) < 1e-7
