"""Stresses in a multilayer under a sliding Hertz sphere (issue 34, 3-D).

Units are SI: lengths in m, stresses in Pa, tension positive. Axes as in `sliding`: x along the
sliding direction, y across it, z the depth below the free surface (z >= 0). The target is a
`LayerStack` (bonded isotropic elastic layers, top first, on an elastic half-space). The surface
tractions are p = p0 sqrt(1 - r^2/a^2) (compressive) and q = mu p in +x on r < a, so that
szz(x, y, 0) = -p, sxz(x, y, 0) = -q and syz(x, y, 0) = 0, as in `sliding.sphere_stresses`.

Method
------
Two-dimensional Fourier transform in (x, y). A mode e^{i k xi} of wave vector k (magnitude k,
axis xi along it, eta across) splits into
* P-SV, plane strain in (xi, z): the per-wavenumber problem of `sliding_layered` (Airy function
  per layer, reflection recursion `psv_coefficients`), with depth functions N_n (normal case)
  and T_n (tangential case) and sigma_etaeta = nu_layer (sigma_xixi + sigma_zz);
* SH, anti-plane: u_eta = W(z) e^{i k xi}, W'' = k^2 W, with W and G W' (G the shear modulus)
  continuous at the interfaces; per layer G k W = A e^{-u} + B e^{v} (u, v measured from the
  layer's top and bottom, so every exponential is <= 1, the substrate A only), solved by the
  same bottom-up recursion (scalar here). Unit load: tau_etaz = -Z1, tau_xieta = i Z0.
A mode of amplitudes P (pressure) and Q_xi, Q_eta (traction) gives sigma_zz = -P N0 + i Q_xi T0,
sigma_xixi = P N2 - i Q_xi T2, tau_xiz = -i P N1 - Q_xi T1, tau_etaz = -Q_eta Z1,
tau_xieta = i Q_eta Z0. With q along +x, Q_xi = mu P cos(theta), Q_eta = -mu P sin(theta), so
after rotating back to (x, y) every stress is a trigonometric polynomial of degree <= 3 in the
angle theta of k, and the angle integral is analytic (int e^{i k r cos(theta - phi)} cos(n theta)
d theta = 2 pi i^n J_n(k r) cos(n phi)): each stress at (r cos phi, r sin phi, z) is a sum of
cos(n phi) or sin(n phi) times one-dimensional integrals over k of j1(k a) J_n(k r) times depth
functions, j1 the spherical Bessel function: (1/2 pi) k P(k) with P(k) = 2 pi p0 a^2
(sin ka - ka cos ka)/(ka)^3, the Hankel transform of the Hertz pressure.

Stability and synthesis are those of `sliding_layered`: field = homogeneous half-space field
(`sphere_stresses` with the top layer's nu: Hamilton's normal closed form plus the Cerruti
quadrature of the traction) + layered correction, the k-integral of (layered - homogeneous)
depth functions, which decays as e^{-k l} (l = 2 h_1 - z in the top layer, z below it), cut at
k l = 45 and integrated by composite 16-point Gauss-Legendre panels fine enough for J_n(k r) and
for j1(k a). J_n(k r) are tabulated per distinct radius and the depth functions per distinct
depth, so a grid (the y = 0 plane of `layered_sphere_xz`) is a sum of matrix products; no FFT,
no wrap-around. A point on an interface belongs to the layer below (``side="below"``) or above.

Sources: Johnson, Contact Mechanics (1985) (Hertz, Boussinesq-Cerruti); O'Sullivan & King,
J. Tribology 110 (1988) 235-240 (sliding sphere on a layered half-space by transforms); the
Hankel transform of the Hertz pressure (Sneddon, Fourier Transforms, 1951).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

from filmscale.continuum.contact.sliding import (check_friction, principal_stresses,
                                                 sphere_stresses, von_mises)
from filmscale.continuum.contact.sliding_layered import (LayeredSlidingResult, LayerPeak,
                                                         decaying_modes, growing_modes,
                                                         GL_NODES, halfspace_modes,
                                                         psv_coefficients, wavenumber_panels)
from filmscale.continuum.materials import LayerStack
from filmscale.core.checks import check_real
from filmscale.core.errors import InputError

__all__ = ["layered_sphere_stresses", "layered_sphere_xz", "layered_sphere_sliding",
           "sh_coefficients"]

#: k l at which the layered correction is cut off (e^{-45} 45^2 ~ 6e-17)
DECAY_CUT = 45.0
#: doubles held at once by one block of the synthesis
CHUNK_CELLS = 2_000_000
#: coefficient sets (k nodes x layers) kept for the whole integral at once
CACHE_CELLS = 4_000_000
#: arguments below which J2, J3 come from scipy's jv (forward recurrence above: stable there)
BESSEL_RECURRENCE = 8.0
KEYS = ("sxx", "syy", "szz", "sxy", "syz", "txz")
#: Bessel order of each radial integral (the depth-function combinations of `_combinations`)
ORDER = (0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 3)


# ------------------------------------------------------------------ input checks
def _common(stack, a, p0, mu):
    if not isinstance(stack, LayerStack):
        raise InputError(f"stack must be a LayerStack (layers on a substrate), got "
                         f"{type(stack).__name__}")
    a = check_real("a", a, low=1e-12, high=1e3, unit="m")
    p0 = check_real("p0", p0, low=0.0, high=1e14, unit="Pa")
    return stack, a, p0, check_friction(mu)


def _array(name, v, depth=False):
    try:
        v = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number or an array of numbers (m)") from None
    if np.any(~np.isfinite(v)) or (depth and np.any(v < 0)):
        what = "depths >= 0 m below the surface" if depth else "positions (m)"
        raise InputError(f"{name} must be finite {what}")
    return v


def _points(x, y, z):
    x, y, z = _array("x", x), _array("y", y), _array("z", z, depth=True)
    try:
        return np.broadcast_arrays(x, y, z)
    except ValueError:
        raise InputError(f"x, y, z (shapes {x.shape}, {y.shape}, {z.shape}) do not "
                         "broadcast") from None


def _side(side):
    if side not in ("below", "above"):
        raise InputError(f"side = {side!r} is not 'below' or 'above' (which layer a point on "
                         "an interface belongs to)")
    return side


@dataclass(frozen=True)
class _Scaled:
    """The stack in units of a (thicknesses) and of the substrate's E (moduli)."""

    h: np.ndarray
    tops: np.ndarray
    nus: np.ndarray
    Es: np.ndarray
    Gs: np.ndarray


def _scaled(stack, a):
    h = np.array([layer.thickness for layer in stack.layers], dtype=float) / a
    mats = stack.materials()
    nus = np.array([m.nu for m in mats])
    Es = np.array([m.E for m in mats]) / stack.substrate.E
    return _Scaled(h, np.concatenate(([0.0], np.cumsum(h))), nus, Es, Es / (2.0 * (1.0 + nus)))


def _layer_of(z, tops, side):
    """Index of the layer (0..L, L the substrate) holding each depth z (units a)."""
    return np.searchsorted(tops[1:], z, side="right" if side == "below" else "left")


# ------------------------------------------------------------------ the per-k solution
def sh_coefficients(s, h, Gs):
    """Anti-plane (SH) coefficients for wavenumbers s (1/length) and layer thicknesses h.

    In layer j, G_j k W = A_j e^{-u} + B_j e^{v} (u = s (z - top) >= 0, v = s (z - bottom) <= 0;
    the substrate has A only), with G k W and G W' continuous through the interfaces and the
    surface condition G W' = -1 (tau_etaz = -Q_eta per unit Q_eta). Gs: shear moduli of the
    layers and the substrate (any common scale). Returns A (L+1, Ns) and B (L, Ns).
    """
    L = len(h)
    R = np.empty((L, s.size))
    S = np.empty((L, s.size))
    # (Y0 / G, Y1) at the top of the layer below, per unit of its A: Y0 = G k W, Y1 = G W'
    T0, T1 = np.full(s.size, 1.0 / Gs[L]), np.full(s.size, -1.0)
    for j in range(L - 1, -1, -1):
        e = np.exp(-s * h[j])
        den = Gs[j] * T0 - T1                       # > 0: no cancellation, |R_j| <= e
        R[j] = e * (Gs[j] * T0 + T1) / den
        S[j] = 2.0 * e / den
        re = R[j] * e
        T0, T1 = (1.0 + re) / Gs[j], re - 1.0
    A = np.empty((L + 1, s.size))
    B = np.empty((L, s.size))
    A[0] = 1.0 / (1.0 - R[0] * np.exp(-s * h[0])) if L else 1.0
    for j in range(L):
        B[j] = R[j] * A[j]
        A[j + 1] = S[j] * A[j]
    return A, B


def _coefficients(s, st):
    ab, cd = psv_coefficients(s, st.h, st.nus, st.Es)
    A, B = sh_coefficients(s, st.h, st.Gs)
    return ab, cd, A, B


def _combinations(s, coeffs, zu, lu, st, subtract):
    """The 11 depth-function combinations (ORDER gives each one's Bessel order), shape
    (11, Ns, depths), at the depths zu of layers lu; less the homogeneous ones (nu of the top
    layer) when ``subtract``."""
    ab, cd, A, B = coeffs
    L = len(st.h)
    out = np.empty((len(ORDER), s.size, zu.size))
    for j in np.unique(lu):
        sel = np.nonzero(lu == j)[0]
        u = s[:, None] * (zu[None, sel] - st.tops[j])
        D = decaying_modes(u)[..., :3, :] @ ab[j][:, None]          # (Ns, nsel, 3, 2)
        Z0 = A[j][:, None] * np.exp(-u)
        Z1 = Z0.copy()
        if j < L:
            v = s[:, None] * (zu[None, sel] - st.tops[j + 1])
            D = D + growing_modes(v)[..., :3, :] @ cd[j][:, None]
            up = B[j][:, None] * np.exp(v)
            Z0 += up
            Z1 -= up
        N0, N1, N2 = D[..., 0, 0], D[..., 1, 0], D[..., 2, 0]
        T0, T1, T2 = D[..., 0, 1], D[..., 1, 1], D[..., 2, 1]
        EN, ET = st.nus[j] * (N2 - N0), st.nus[j] * (T2 - T0)
        if subtract:
            kz = s[:, None] * zu[None, sel]
            H = halfspace_modes(kz)
            e = np.exp(-kz)
            N0, N1, N2 = N0 - H[..., 0, 0], N1 - H[..., 1, 0], N2 - H[..., 2, 0]
            T0, T1, T2 = T0 - H[..., 0, 1], T1 - H[..., 1, 1], T2 - H[..., 2, 1]
            EN = EN - st.nus[0] * (H[..., 2, 0] - H[..., 0, 0])
            ET = ET - st.nus[0] * (H[..., 2, 1] - H[..., 0, 1])
            Z0, Z1 = Z0 - e, Z1 - e
        for i, g in enumerate((N0, T1 + Z1, N2 + EN, T0, N1, 3 * T2 + ET - 2 * Z0,
                               T2 + 3 * ET + 2 * Z0, T2 - ET - 2 * Z0, T1 - Z1, N2 - EN,
                               ET - T2 - 2 * Z0)):
            out[i][:, sel] = g
    return out


def _assemble(I, c1, s1, mu):
    """Stresses (units p0) from the radial integrals I (11, ...) and cos, sin of the azimuth."""
    c2, s2 = c1 * c1 - s1 * s1, 2.0 * s1 * c1
    c3, s3 = c1 * c2 - s1 * s2, s1 * c2 + c1 * s2
    q = 0.25 * mu
    return {"sxx": 0.5 * (I[2] - c2 * I[9]) + q * (c1 * I[5] + c3 * I[10]),
            "syy": 0.5 * (I[2] + c2 * I[9]) + q * (c1 * I[6] - c3 * I[10]),
            "szz": -I[0] - mu * c1 * I[3],
            "sxy": -0.5 * s2 * I[9] + q * (s1 * I[7] + s3 * I[10]),
            "syz": s1 * I[4] + 2.0 * q * s2 * I[8],
            "txz": c1 * I[4] - 2.0 * q * (I[1] - c2 * I[8])}


def _bessel(x):
    """J0..J3 of x >= 0, shape (4, ...)."""
    out = np.empty((4,) + x.shape)
    out[0], out[1] = special.j0(x), special.j1(x)
    small = x < BESSEL_RECURRENCE
    xi = 1.0 / np.where(small, 1.0, x)
    out[2] = 2.0 * xi * out[1] - out[0]
    out[3] = 4.0 * xi * out[2] - out[1]
    if np.any(small):
        xs = x[small]
        out[2][small] = special.jv(2, xs)
        out[3][small] = special.jv(3, xs)
    return out


def _nodes(l_min, r_max, L_max):
    """Composite Gauss-Legendre nodes on [0, DECAY_CUT / l_min] (units 1/a) and their weights
    times the load's j1(s) (the Hertz pressure's transform, (1/2 pi) k P(k) in units p0 a)."""
    s, w = wavenumber_panels(r_max, l_min, L_max, DECAY_CUT)
    return s, w * special.spherical_jn(1, s)


def _reach(z, lay, st, subtract):
    """The decay length l of each point's integrand (it falls as e^{-k l})."""
    if subtract:
        return np.where(lay == 0, 2.0 * st.h[0] - z, z)
    if np.any(z <= 0):
        raise InputError("z must be > 0 for the unsubtracted spectral integral")
    return z


def _cut(s, ell):
    """How many nodes s (whole panels) reach DECAY_CUT / l for every l of ``ell``."""
    m = int(np.searchsorted(s, DECAY_CUT / float(np.min(ell))))
    return min(-(-m // GL_NODES) * GL_NODES, s.size)


def _cached(s, st):
    """All the coefficients at once when they are small enough, else None (made per block)."""
    return _coefficients(s, st) if s.size * (len(st.h) + 1) <= CACHE_CELLS else None


def _correction(x, y, z, lay, st, mu, subtract=True, nodes=None, coeffs=None):
    """Layered correction (``subtract``) or the whole spectral field, units a and p0, at
    1-D points (x, y, z) with layer indices ``lay``; nodes (k, weights) and their coefficients
    may be given (reused across calls)."""
    r = np.hypot(x, y)
    ell = _reach(z, lay, st, subtract)
    if nodes is None:
        nodes = _nodes(float(np.min(ell)), float(np.max(r, initial=0.0)),
                       float(np.max(z, initial=0.0)) + 2.0 * st.tops[-1])
        coeffs = _cached(nodes[0], st)
    s_all, w_all = nodes

    def coef(sl):
        return _coefficients(s_all[sl], st) if coeffs is None else \
            tuple(c[:, sl] for c in coeffs)

    n = len(ORDER)
    ru, ir = np.unique(r, return_inverse=True)
    zu, iz = np.unique(np.stack([z, lay.astype(float)], axis=1), axis=0, return_inverse=True)
    ir, iz = ir.ravel(), iz.ravel()
    if ru.size * zu.shape[0] <= 4 * r.size + 4096:
        # grid path: J_n per distinct radius times depth functions per distinct depth
        I = np.zeros((n, ru.size, zu.shape[0]))
        chunk = int(np.clip(CHUNK_CELLS // (n * zu.shape[0] + 4 * 512), 16, 4096))
        m = _cut(s_all, ell)
        for c0 in range(0, m, chunk):
            sl = slice(c0, min(c0 + chunk, m))
            s = s_all[sl]
            G = _combinations(s, coef(sl), zu[:, 0], zu[:, 1].astype(int), st, subtract)
            G *= w_all[sl][None, :, None]
            for b0 in range(0, ru.size, 512):
                J = _bessel(np.outer(ru[b0:b0 + 512], s))
                for c in range(n):
                    I[c, b0:b0 + 512] += J[ORDER[c]] @ G[c]
        I = I[:, ir, iz]
    else:
        # scattered points: blocks of up to 256 points whose l agree within a factor 2, each
        # with its own depth functions, integrated over the whole panels below DECAY_CUT / l
        I = np.zeros((n, r.size))
        order = np.argsort(-ell, kind="stable")
        octave = np.floor(np.log2(ell[order]))
        starts = np.flatnonzero(np.diff(octave, prepend=np.inf))
        blocks = [order[q0:min(q0 + 256, p1)]
                  for p0, p1 in zip(starts, np.append(starts[1:], r.size))
                  for q0 in range(p0, p1, 256)]
        for blk in blocks:
            zb, ib = np.unique(zu[iz[blk]], axis=0, return_inverse=True)
            ib = ib.ravel()
            m = _cut(s_all, ell[blk])
            for c0 in range(0, m, 2048):
                sl = slice(c0, min(c0 + 2048, m))
                s = s_all[sl]
                G = _combinations(s, coef(sl), zb[:, 0], zb[:, 1].astype(int), st, subtract)
                G = G[:, :, ib] * w_all[sl][None, :, None]
                J = _bessel(np.outer(r[blk], s))
                for c in range(n):
                    I[c, blk] += np.einsum("pk,kp->p", J[ORDER[c]], G[c])
    safe = np.where(r > 0, r, 1.0)
    return _assemble(I, np.where(r > 0, x / safe, 1.0), np.where(r > 0, y / safe, 0.0), mu)


def _field(x, y, z, st, mu, side="below", subtract=True, lay=None, nodes=None, coeffs=None):
    """Stresses in units of p0 at 1-D points (units a) of the scaled stack ``st``.

    ``subtract=False`` integrates the full spectrum (no closed-form part, z > 0 only): the
    tests' check of the spectral machinery on its own."""
    if lay is None:
        lay = _layer_of(z, st.tops, side)
    out = {k: np.zeros(x.shape) for k in KEYS}
    if x.size == 0:
        return out
    if subtract:
        out = {k: v.copy() for k, v in sphere_stresses(x, y, z, 1.0, 1.0, mu, st.nus[0]).items()}
    if len(st.h) or not subtract:
        corr = _correction(x, y, z, lay, st, mu, subtract, nodes, coeffs)
        for k in KEYS:
            out[k] += corr[k]
    return out


# ------------------------------------------------------------------ public API
def layered_sphere_stresses(x, y, z, stack, a, p0, mu, side="below") -> dict[str, np.ndarray]:
    """All six stresses (Pa) at (x, y, z) (m) in ``stack`` under p = p0 sqrt(1 - r^2/a^2) and
    q = mu p in +x on r < a (a in m, p0 in Pa; tension positive, z >= 0 the depth).

    Keys as `sliding.sphere_stresses`: sxx, syy, szz, sxy, syz, txz, with the broadcast shape of
    x, y, z. A point on an interface belongs to the layer below (``side="below"``) or above.
    """
    stack, a, p0, mu = _common(stack, a, p0, mu)
    side = _side(side)
    x, y, z = _points(x, y, z)
    out = _field(x.ravel() / a, y.ravel() / a, z.ravel() / a, _scaled(stack, a), mu, side)
    return {k: p0 * v.reshape(x.shape) for k, v in out.items()}


#: on a homogeneous target, the depth (units a) from which `layered_sphere_xz` integrates the
#: whole field spectrally (its integrand decays as e^{-k z}: 45/z wavenumbers a row)
SPECTRAL_DEPTH = 0.05


def layered_sphere_xz(x, z, stack, a, p0, mu) -> dict[str, np.ndarray]:
    """The field (Pa) on the plane y = 0 through the contact, on X, Z = meshgrid(x, z) (1-D
    x and z in m; arrays of shape (z.size, x.size)); a point on an interface belongs to the
    layer below. sxy = syz = 0 there (symmetry).

    Rows in the top film (on a homogeneous target, above `SPECTRAL_DEPTH` a) are the closed
    forms plus the layered correction; the rows below them are the whole spectral integral,
    which needs no Cerruti quadrature (~0.3 ms a point) and no more wavenumbers than the
    correction of the rows above (the two agree within the quadrature's error, 5e-8 p0 near
    the rim: tests/continuum/test_sliding_sphere_layered.py)."""
    stack, a, p0, mu = _common(stack, a, p0, mu)
    x, z = _array("x", x), _array("z", z, depth=True)
    if x.ndim != 1 or z.ndim != 1:
        raise InputError(f"x and z must be 1-D arrays (got shapes {x.shape}, {z.shape})")
    st = _scaled(stack, a)
    zs = z / a
    top = st.h[0] if len(st.h) else SPECTRAL_DEPTH
    deep = zs >= top
    # the deep rows in groups whose depths lie within a factor 2, each to its own 45/z
    octave = np.floor(np.log2(np.where(deep, zs, top) / top)).astype(int)
    groups = [(~deep, True)] + [(deep & (octave == o), False) for o in np.unique(octave[deep])]
    out = {k: np.empty((z.size, x.size)) for k in KEYS}
    for rows, subtract in groups:
        if rows.any():
            X, Z = np.meshgrid(x / a, zs[rows])
            part = _field(X.ravel(), np.zeros(X.size), Z.ravel(), st, mu, subtract=subtract)
            for k in KEYS:
                out[k][rows] = part[k].reshape(X.shape)
    res = {k: p0 * v for k, v in out.items()}
    res["sxy"] = np.zeros((z.size, x.size))
    res["syz"] = np.zeros((z.size, x.size))
    return res


def _count(name, v, low, high):
    if not isinstance(v, int) or isinstance(v, bool) or not low <= v <= high:
        raise InputError(f"{name} = {v!r} must be an integer in [{low}, {high}]")
    return v


def layered_sphere_sliding(stack, a, p0, mu, x_span=2.0, depth=3.0, nx=161, nz=24,
                           refine=True) -> LayeredSlidingResult:
    """Per-layer peaks on the plane y = 0 under the sliding Hertz tractions (a in m, p0 in Pa).

    Searched on x in [-x_span a, x_span a] (nx points) and, in each layer, nz depths from its
    top to its bottom (the substrate down to max(depth a, 2 a below its top)); each layer's
    largest von Mises stress is then refined by a bounded local search when ``refine``.
    Interface shear: the largest sqrt(sxz^2 + syz^2) = |sxz| (y = 0) on each layer's bottom
    interface. tensile_max: the largest principal stress on the surface (y = 0). The peaks of
    the homogeneous sphere lie on y = 0 (the symmetry plane); off-plane maxima are not sought.
    ``half_width`` of the result holds the contact radius a.
    """
    stack, a, p0, mu = _common(stack, a, p0, mu)
    x_span = check_real("x_span", x_span, low=1.0, high=50.0)
    depth = check_real("depth", depth, low=0.1, high=100.0)
    nx, nz = _count("nx", nx, 11, 4001), _count("nz", nz, 3, 400)
    st = _scaled(stack, a)
    L = len(st.h)
    z_end = max(depth, st.tops[L] + 2.0)
    nodes = coeffs = None
    if L:          # one k-rule for every point searched: l >= h_1 everywhere
        nodes = _nodes(st.h[0], x_span, z_end + 2.0 * st.tops[-1])
        coeffs = _cached(nodes[0], st)

    def field(xv, zv, j, hom=None):
        xv, zv = np.broadcast_arrays(np.atleast_1d(np.asarray(xv, float)),
                                     np.atleast_1d(np.asarray(zv, float)))
        xv, zv = xv.ravel(), zv.ravel()
        yv = np.zeros(xv.shape)
        out = sphere_stresses(xv, yv, zv, 1.0, 1.0, mu, st.nus[0]) if hom is None else hom
        out = {k: v.copy() for k, v in out.items()}
        if L:
            corr = _correction(xv, yv, zv, np.full(xv.shape, j), st, mu, True, nodes, coeffs)
            for k in KEYS:
                out[k] += corr[k]
        return out

    xs = np.linspace(-x_span, x_span, nx)
    rows = [np.linspace(st.tops[j], st.tops[j + 1] if j < L else z_end, nz) for j in range(L + 1)]
    zall, inv = np.unique(np.concatenate(rows), return_inverse=True)
    X, Z = np.meshgrid(xs, zall)
    hom = sphere_stresses(X.ravel(), np.zeros(X.size), Z.ravel(), 1.0, 1.0, mu, st.nus[0])
    hom = {k: v.reshape(X.shape) for k, v in hom.items()}      # once per point, all layers
    peaks = []
    for j, mat in enumerate(stack.materials()):
        z0, z1 = rows[j][0], rows[j][-1]
        rr = inv[j * nz:(j + 1) * nz]
        Xj, Zj = X[rr], Z[rr]
        s = field(Xj, Zj, j, {k: v[rr].ravel() for k, v in hom.items()})
        vals = von_mises(s).reshape(Xj.shape)
        k = np.unravel_index(int(np.argmax(vals)), vals.shape)
        best = (float(vals[k]), float(Xj[k]), float(Zj[k]))
        if refine:
            r = optimize.minimize(lambda v: -float(von_mises(field(v[0], v[1], j))[0]),
                                  [best[1], best[2]], method="L-BFGS-B",
                                  bounds=[(-x_span, x_span), (z0, z1)],
                                  options={"ftol": 1e-13, "maxiter": 200})
            if -r.fun > best[0]:
                best = (float(-r.fun), float(r.x[0]), float(r.x[1]))
        t_max = t_x = None
        if j < L:
            tau = np.abs(s["txz"].reshape(Xj.shape)[-1])
            i = int(np.argmax(tau))
            t_max, t_x = float(tau[i]), float(xs[i])
            if refine:
                r = optimize.minimize_scalar(lambda t: -abs(float(field(t, z1, j)["txz"][0])),
                                             bounds=(xs[max(i - 1, 0)], xs[min(i + 1, nx - 1)]),
                                             method="bounded", options={"xatol": 1e-10})
                if -r.fun > t_max:
                    t_max, t_x = float(-r.fun), float(r.x)
            t_max, t_x = t_max * p0, t_x * a
        ratio = None if math.isinf(mat.sigma_y) else best[0] * p0 / mat.sigma_y
        peaks.append(LayerPeak(mat.name or ("substrate" if j == L else f"layer {j + 1}"),
                               z0 * a, (z1 * a if j < L else math.inf),
                               best[0] * p0, best[1] * a, best[2] * a, ratio, t_max, t_x))
    # the largest principal stress on the surface (y = 0)
    xf = np.linspace(-x_span, x_span, 4 * nx + 1)
    s1 = principal_stresses(field(xf, 0.0, 0))[..., 0]
    i = int(np.argmax(s1))
    t_best, t_at = float(s1[i]), float(xf[i])
    if refine:
        r = optimize.minimize_scalar(
            lambda t: -float(principal_stresses(field(t, 0.0, 0))[0, 0]),
            bounds=(xf[max(i - 1, 0)], xf[min(i + 1, xf.size - 1)]), method="bounded",
            options={"xatol": 1e-10})
        if -r.fun > t_best:
            t_best, t_at = float(-r.fun), float(r.x)
    return LayeredSlidingResult(a, p0, mu, tuple(peaks), t_best * p0, t_at * a)
