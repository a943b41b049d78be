"""Plane-strain stresses in a multilayer under a sliding Hertz line contact (issue 34, 2-D).

Units are SI: lengths in m, stresses in Pa, tension positive. Axes as in `sliding`: x along the
sliding direction, z the depth below the free surface (z >= 0). The target is a `LayerStack`
(perfectly bonded isotropic elastic layers, top first, on an elastic half-space). The surface
tractions on it are p(x) = p0 sqrt(1 - x^2/b^2) (compressive) and q = mu p in +x, so that
sigma_zz(x, 0) = -p and tau_xz(x, 0) = -q, as in `sliding.cylinder_stresses`.

Method
------
Fourier transform in x. For a wavenumber k (s = |k| b) the Airy stress function in each layer
is phi = F(z) e^{ikx} with F'''' - 2k^2 F'' + k^4 F = 0; in layer j (top z_{j-1}, bottom z_j)

    F = (a + b u) e^{-u} + (c + d v) e^{v},   u = s (z - z_{j-1}) >= 0,  v = s (z - z_j) <= 0,

so every exponential is referenced to the layer face where it is largest and is <= 1; the
substrate has only the decaying pair (a, b). With D_n = F^(n)/|k|^n the stresses per mode are
sigma_zz ~ D0, tau_xz ~ D1, sigma_xx ~ D2, and the four interface conditions are continuity of

    D0 (sigma_zz),  D1 (tau_xz),  [(1-nu^2) D2 + nu (1+nu) D0] / E (eps_xx, i.e. u_x),
    (1+nu) [(2-nu) D1 - (1-nu) D3] / E (u_z).

Stability: the system is solved by a recursion from the substrate up (the "reflection matrix"
form): at each interface one 4x4 solve gives the up-going pair (c_j, d_j) = R_j (a_j, b_j) and the
next layer's down-going pair (a_{j+1}, b_{j+1}) = S_j (a_j, b_j). The matrices solved have O(1)
entries (moduli are scaled by the substrate's E) and R_j, S_j carry the factor e^{-s h_j}, so
nothing overflows for any s h; for s h beyond ~700 the factors underflow to 0, which is exact to
double precision. The two surface conditions then fix (a_1, b_1) with a 2x2 solve, per load case.

Synthesis: the Hertz tractions have the closed-form transform p^(k) = p0 pi b J1(kb)/(kb), q^ =
mu p^. The field is split into the homogeneous half-space field (in plane strain sigma_xx,
sigma_zz and tau_xz of a homogeneous half-space under given tractions do not depend on its
elastic constants; they are the closed forms of `sliding.cylinder_stresses`) plus the layered
correction, the Fourier integral of (D_layered - D_homogeneous). The correction's integrand
decays at least as e^{-s l(z)} with l = 2 h_1 - z in the top layer and l = z below it (never below
h_1), so it is integrated over s in [0, S], S = 45 / min l, by composite 16-point Gauss-Legendre
panels whose width resolves the oscillation of J1(s) cos(s x/b) (|x|/b + 1 per unit s) and the
slowest exponential of the stack. No FFT: the points (x, z) are arbitrary and there is no
wrap-around. Cost grows like b / h_1 for thin top films (see the module docs in docs/sliding.md).

A point exactly on an interface belongs to the layer below (``side="below"``, default) or above
(``side="above"``); sigma_zz and tau_xz are continuous there, sigma_xx and sigma_yy jump.
sigma_yy = nu_layer (sigma_xx + sigma_zz) (plane strain).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

from filmscale.continuum.contact.sliding import (check_friction, cylinder_stresses,
                                                 principal_stresses, von_mises)
from filmscale.continuum.materials import LayerStack
from filmscale.core.checks import check_real
from filmscale.core.errors import InputError

__all__ = ["wavenumber_panels", "layered_cylinder_stresses", "layered_cylinder_sliding", "layered_cylinder_unit_fields",
           "LayerPeak",
           "LayeredSlidingResult", "psv_coefficients", "decaying_modes", "growing_modes",
           "halfspace_modes", "continuity_matrix"]

#: s l at which the layered correction is cut off (e^{-45} (45)^2 ~ 6e-17)
DECAY_CUT = 45.0
#: Gauss-Legendre nodes per panel in s
GL_NODES = 16
#: s-nodes handled at once (bounded memory: layers x chunk x 8 doubles per chunk)
CHUNK_CELLS = 2_000_000


# ------------------------------------------------------------------ input checks
def _check_stack(stack):
    if not isinstance(stack, LayerStack):
        raise InputError(f"stack must be a LayerStack (layers on a substrate), got "
                         f"{type(stack).__name__}")
    return stack


def _common(stack, b, p0, mu):
    stack = _check_stack(stack)
    b = check_real("b", b, low=1e-12, high=1e3, unit="m")
    p0 = check_real("p0", p0, low=0.0, high=1e14, unit="Pa")
    mu = check_friction(mu)
    return stack, b, p0, mu


def _points(x, z):
    try:
        x = np.asarray(x, dtype=float)
        z = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise InputError("x and z must be numbers or arrays of numbers (m)") from None
    if np.any(~np.isfinite(x)):
        raise InputError("x must be finite positions (m)")
    if np.any(~np.isfinite(z)) or np.any(z < 0):
        raise InputError("z must be finite depths >= 0 m below the surface")
    try:
        x, z = np.broadcast_arrays(x, z)
    except ValueError:
        raise InputError(f"x (shape {x.shape}) and z (shape {z.shape}) do not broadcast") \
            from None
    return x, z


def _side(side):
    if side not in ("below", "above"):
        raise InputError(f"side = {side!r} is not 'below' or 'above' (which layer a point on "
                         "an interface belongs to)")
    return side


# ------------------------------------------------------------------ the per-k solution
def continuity_matrix(nu, E):
    """Rows: D -> (D0, D1, eps_xx-like, u_z-like), the quantities continuous across a bonded
    interface (E scaled: only ratios of the layers' E count)."""
    M = np.zeros((4, 4))
    M[0, 0] = 1.0
    M[1, 1] = 1.0
    M[2, 0] = nu * (1 + nu) / E
    M[2, 2] = (1 - nu * nu) / E
    M[3, 1] = (1 + nu) * (2 - nu) / E
    M[3, 3] = -(1 + nu) * (1 - nu) / E
    return M


def decaying_modes(u):
    """D_n of (a + b u) e^{-u}: array (..., 4, 2) acting on (a, b)."""
    e = np.exp(-u)
    out = np.empty(np.shape(u) + (4, 2))
    out[..., 0, 0], out[..., 0, 1] = e, u * e
    out[..., 1, 0], out[..., 1, 1] = -e, (1 - u) * e
    out[..., 2, 0], out[..., 2, 1] = e, (u - 2) * e
    out[..., 3, 0], out[..., 3, 1] = -e, (3 - u) * e
    return out


def growing_modes(v):
    """D_n of (c + d v) e^{v} (v <= 0): array (..., 4, 2) acting on (c, d)."""
    e = np.exp(v)
    out = np.empty(np.shape(v) + (4, 2))
    for n in range(4):
        out[..., n, 0] = e
        out[..., n, 1] = (n + v) * e
    return out


def psv_coefficients(s, h, nus, Es):
    """Per-layer coefficients for wavenumbers s (units 1/b), layer thicknesses h (units b).

    Returns ab (L+1, Ns, 2, 2) and cd (L, Ns, 2, 2): [..., pair, load case], load case 0 the
    normal (D0 = 1, D1 = 0 at the surface), 1 the tangential (D0 = 0, D1 = 1).
    """
    L = len(h)
    Ns = s.size
    Ms = [continuity_matrix(nu, E) for nu, E in zip(nus, Es)]
    R = np.zeros((L, Ns, 2, 2))
    S = np.zeros((L, Ns, 2, 2))
    # top of the substrate: T = M Dd(0)
    T = np.broadcast_to(Ms[L] @ decaying_modes(np.zeros(1))[0], (Ns, 4, 2))
    up0 = growing_modes(np.zeros(1))[0]
    for j in range(L - 1, -1, -1):
        t = s * h[j]
        A = np.empty((Ns, 4, 4))
        A[:, :, :2] = Ms[j] @ up0
        A[:, :, 2:] = -T
        rhs = -(Ms[j] @ decaying_modes(t))
        X = np.linalg.solve(A, rhs)
        R[j], S[j] = X[:, :2], X[:, 2:]
        # top of layer j seen from above: M_j (Dd(0) + Du(-t) R_j)
        T = Ms[j] @ (decaying_modes(np.zeros(1))[0] + growing_modes(-t) @ R[j])
    top = decaying_modes(np.zeros(1))[0] + (growing_modes(-s * h[0]) @ R[0] if L else 0.0)
    B = np.broadcast_to(top[..., :2, :], (Ns, 2, 2))
    ab = np.empty((L + 1, Ns, 2, 2))
    ab[0] = np.linalg.solve(B, np.broadcast_to(np.eye(2), (Ns, 2, 2)))
    cd = np.empty((L, Ns, 2, 2))
    for j in range(L):
        cd[j] = R[j] @ ab[j]
        ab[j + 1] = S[j] @ ab[j]
    return ab, cd


def halfspace_modes(u):
    """D0..D2 of the homogeneous half-space, (..., 3, 2): normal F = (1+u)e^-u, tangential u e^-u."""
    e = np.exp(-u)
    out = np.empty(np.shape(u) + (3, 2))
    out[..., 0, 0], out[..., 0, 1] = (1 + u) * e, u * e
    out[..., 1, 0], out[..., 1, 1] = -u * e, (1 - u) * e
    out[..., 2, 0], out[..., 2, 1] = (u - 1) * e, (u - 2) * e
    return out


def _layer_of(z, tops, side):
    """Index of the layer (0..L, L the substrate) holding each depth z (units b)."""
    bottoms = np.asarray(tops[1:])
    if side == "below":
        return np.searchsorted(bottoms, z, side="right")
    return np.searchsorted(bottoms, z, side="left")


def wavenumber_panels(x_max, l_min, L_max, cut=DECAY_CUT):
    """Composite Gauss-Legendre nodes and weights on [0, cut / l_min] (wavenumbers in units of
    the contact size): `GL_NODES` a panel, panels at most 2.5 wide and narrow enough for the
    oscillation of cos(s x) (or J_n(s r)) up to ``x_max`` and for the slowest exponential,
    e^{-s L_max}."""
    s_max = cut / l_min
    width = min(2.5, 8.0 / (1.0 + x_max), 8.0 / max(L_max, 1e-300))
    n_pan = max(int(math.ceil(s_max / width)), 4)
    g, w = np.polynomial.legendre.leggauss(GL_NODES)
    edges = np.linspace(0.0, s_max, n_pan + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    s = (mid[:, None] + half[:, None] * g[None, :]).ravel()
    ws = (half[:, None] * w[None, :]).ravel()
    return s, ws


def _field(x, z, stack, mu, side="below", subtract=True, b=1.0):
    """Stresses in units of p0 at (x, z) in units of b (1-D arrays of equal length); the
    stack's thicknesses are divided by b (m).

    ``subtract=False`` integrates the full spectrum (no closed-form part); it needs z > 0 and
    serves the tests as a check of the spectral machinery on its own.
    """
    h = np.array([layer.thickness for layer in stack.layers], dtype=float) / b
    mats = stack.materials()
    E_ref = stack.substrate.E
    nus = [m.nu for m in mats]
    Es = [m.E / E_ref for m in mats]
    return _field_scaled(x, z, h, nus, Es, mu, side, subtract)


def _field_scaled(x, z, h, nus, Es, mu, side, subtract):
    normal, tangential, nu_pt = _unit_parts(x, z, h, nus, Es, side, subtract)
    out = {k: normal[k] + mu * tangential[k] for k in normal}
    out["syy"] = nu_pt * (out["sxx"] + out["szz"])
    return out


#: depths are integrated in groups whose decay lengths l lie within this factor of each
#: other, each group to its own cut-off DECAY_CUT / l_group (a deep row needs far fewer
#: wavenumbers than a row in a thin top film)
GROUP_FACTOR = 2.0


def _unit_parts(x, z, h, nus, Es, side, subtract, cut=DECAY_CUT):
    """(normal, tangential) fields (sxx, szz, txz) of unit p0 and unit mu at the points, and
    each point's Poisson ratio; the correction cut at s l = ``cut``."""
    L = len(h)
    tops = np.concatenate(([0.0], np.cumsum(h)))
    lay = _layer_of(z, tops, side)
    nu_pt = np.asarray(nus)[lay]
    keys = ("sxx", "szz", "txz")
    normal = {k: np.zeros(x.shape) for k in keys}
    tangential = {k: np.zeros(x.shape) for k in keys}
    if subtract:
        hom0 = cylinder_stresses(x, z, 1.0, 1.0, 0.0, 0.25)
        hom1 = cylinder_stresses(x, z, 1.0, 1.0, 1.0, 0.25)
        for k in keys:
            normal[k] += hom0[k]
            tangential[k] += hom1[k] - hom0[k]
    if L or not subtract:
        if subtract:
            h1 = h[0]
            ell = np.where(z < h1, 2.0 * h1 - z, z)
        else:
            if np.any(z <= 0):
                raise InputError("z must be > 0 for the unsubtracted spectral integral")
            ell = z
        if not z.size:
            return normal, tangential, nu_pt
        l_min = float(np.min(ell))
        L_max = float(np.max(z, initial=0.0)) + 2.0 * tops[-1]
        x_max = float(np.max(np.abs(x), initial=0.0))
        group = np.floor(np.log(ell / l_min) / math.log(GROUP_FACTOR)).astype(int)
        for g in np.unique(group):
            sel = np.nonzero(group == g)[0]
            s, ws = wavenumber_panels(x_max, float(np.min(ell[sel])), L_max, cut)
            parts = _synthesise(x[sel], z[sel], lay[sel], tops, h, nus, Es, s, ws, subtract)
            for k in keys:
                normal[k][sel] += parts[0][k]
                tangential[k][sel] += parts[1][k]
    return normal, tangential, nu_pt


def _synthesise(x, z, lay, tops, h, nus, Es, s_all, w_all, subtract):
    """The layered correction (or, unsubtracted, the whole spectral integral) of the normal
    and of the unit tangential load: two dicts of sxx, szz, txz at the points."""
    L = len(h)
    xu, ix = np.unique(x, return_inverse=True)
    zl = np.stack([z, lay.astype(float)], axis=1)
    zu, iz = np.unique(zl, axis=0, return_inverse=True)
    ix, iz = ix.ravel(), iz.ravel()
    grid = xu.size * zu.shape[0] <= 4 * x.size + 4096
    zu_z, zu_l = zu[:, 0], zu[:, 1].astype(int)
    shape = (xu.size, zu.shape[0]) if grid else (x.size,)
    acc = [{k: np.zeros(shape) for k in ("sxx", "szz", "txz")} for _ in range(2)]
    chunk = max(64, min(8192, CHUNK_CELLS // (L + 1)))
    for c0 in range(0, s_all.size, chunk):
        s = s_all[c0:c0 + chunk]
        wk = w_all[c0:c0 + chunk] * special.j1(s) / s          # p^/(pi p0 b) weights
        ab, cd = psv_coefficients(s, h, nus, Es)
        # spectra at the distinct depths: G[n, load, s, depth]
        G = np.empty((3, 2, s.size, zu_z.size))
        for j in np.unique(zu_l):
            sel = np.nonzero(zu_l == j)[0]
            u = s[:, None] * (zu_z[None, sel] - tops[j])
            D = decaying_modes(u)[..., :3, :] @ ab[j][:, None]      # (Ns, nsel, 3, 2)
            if j < L:
                v = s[:, None] * (zu_z[None, sel] - tops[j + 1])
                D = D + growing_modes(v)[..., :3, :] @ cd[j][:, None]
            if subtract:
                D = D - halfspace_modes(s[:, None] * zu_z[None, sel])
            G[:, :, :, sel] = np.moveaxis(D, (2, 3), (0, 1))
        G *= wk[None, None, :, None]
        # normal load: szz ~ -cos D0, sxx ~ cos D2, txz ~ sin D1; tangential: sin, sin, -cos
        if grid:
            C = np.cos(np.outer(xu, s))
            Sn = np.sin(np.outer(xu, s))
            for load, (even, odd, sign) in enumerate(((C, Sn, 1.0), (Sn, C, -1.0))):
                acc[load]["szz"] -= even @ G[0, load]
                acc[load]["sxx"] += even @ G[2, load]
                acc[load]["txz"] += sign * (odd @ G[1, load])
        else:
            for p0_ in range(0, x.size, 256):
                sl_ = slice(p0_, p0_ + 256)
                arg = np.outer(x[sl_], s)
                C, Sn = np.cos(arg), np.sin(arg)
                g = G[:, :, :, iz[sl_]]                              # (3, 2, Ns, npts)
                for load, (even, odd, sign) in enumerate(((C, Sn, 1.0), (Sn, C, -1.0))):
                    acc[load]["szz"][sl_] -= np.einsum("ps,sp->p", even, g[0, load])
                    acc[load]["sxx"][sl_] += np.einsum("ps,sp->p", even, g[2, load])
                    acc[load]["txz"][sl_] += sign * np.einsum("ps,sp->p", odd, g[1, load])
    if grid:
        return tuple({k: v[ix, iz] for k, v in part.items()} for part in acc)
    return tuple(acc)


# ------------------------------------------------------------------ public API
def layered_cylinder_stresses(x, z, stack, b, p0, mu, side="below") -> dict[str, np.ndarray]:
    """Plane-strain stresses (Pa) at (x, z) (m) in ``stack`` under p = p0 sqrt(1 - x^2/b^2)
    and q = mu p in +x (tension positive, z >= 0 the depth below the free surface).

    Returns sxx, syy, szz, txz (and the zero sxy, syz) with the broadcast shape of x and z.
    A point on an interface belongs to the layer below (``side="below"``) or above.
    """
    stack, b, p0, mu = _common(stack, b, p0, mu)
    side = _side(side)
    x, z = _points(x, z)
    shape = x.shape
    out = _field(x.ravel() / b, z.ravel() / b, stack, mu, side, b=b)
    res = {k: p0 * v.reshape(shape) for k, v in out.items()}
    res["sxy"] = np.zeros(shape)
    res["syz"] = np.zeros(shape)
    return res


def layered_cylinder_unit_fields(x, z, stack, b, cut=DECAY_CUT) -> tuple[dict, dict]:
    """The plane-strain fields on X, Z = meshgrid(x, z) (1-D x and z in m; a point on an
    interface belongs to the layer below) of the normal Hertz pressure with p0 = 1 and of
    the tangential traction with p0 = 1 and mu = 1: the field of (p0, mu) is
    p0 (normal + mu tangential). ``cut``: s l where the layered correction is cut (its
    integrand decays as (s l)^2 e^{-s l}: 30 leaves ~1e-10 p0, the default 45 ~1e-17). Dicts of sxx, syy, szz, txz (and the zero sxy, syz) arrays
    (z.size, x.size)."""
    stack = _check_stack(stack)
    b = check_real("b", b, low=1e-12, high=1e3, unit="m")
    x, z = np.asarray(x, dtype=float), np.asarray(z, dtype=float)
    if x.ndim != 1 or z.ndim != 1:
        raise InputError(f"x and z must be 1-D arrays (got shapes {x.shape}, {z.shape})")
    X, Z = _points(*np.meshgrid(x, z))
    h = np.array([layer.thickness for layer in stack.layers], dtype=float) / b
    mats = stack.materials()
    Es = [m.E / stack.substrate.E for m in mats]
    nus = [m.nu for m in mats]
    cut = check_real("cut", cut, low=10.0, high=100.0)
    normal, tangential, nu_pt = _unit_parts(X.ravel() / b, Z.ravel() / b, h, nus, Es,
                                            "below", True, cut)
    out = []
    for part in (normal, tangential):
        part["syy"] = nu_pt * (part["sxx"] + part["szz"])
        part["sxy"] = part["syz"] = np.zeros(X.size)
        out.append({k: v.reshape(X.shape) for k, v in part.items()})
    return out[0], out[1]


@dataclass(frozen=True)
class LayerPeak:
    """One layer's (or the substrate's) worst point; lengths in m, stresses in Pa."""

    name: str
    z_top: float
    z_bottom: float            # math.inf for the substrate
    vm_max: float              # largest von Mises stress in the layer
    vm_x: float
    vm_z: float
    yield_ratio: float | None  # vm_max / sigma_y (None when sigma_y is infinite)
    interface_txz_max: float | None  # largest |tau_xz| on the layer's bottom interface
    interface_txz_x: float | None


@dataclass(frozen=True)
class LayeredSlidingResult:
    """Per-layer peaks of a sliding line contact on a layer stack."""

    half_width: float
    p0: float
    mu: float
    layers: tuple[LayerPeak, ...]   # top layer first, the substrate last
    tensile_max: float              # largest principal stress on the surface, Pa
    tensile_x: float                # where, m


def layered_cylinder_sliding(stack, b, p0, mu, x_span=2.0, depth=3.0, nx=161, nz=24,
                             refine=True) -> LayeredSlidingResult:
    """Per-layer peaks under the sliding Hertz tractions (b in m, p0 in Pa).

    Searched on x in [-x_span b, x_span b] (nx points) and, in each layer, nz depths from its
    top to its bottom (the substrate down to max(depth b, 2 b below its top)); each layer's
    largest von Mises stress is then refined by a bounded local search when ``refine``.
    Interface shear: max |tau_xz| on each interface over the x grid (refined likewise).
    """
    stack, b, p0, mu = _common(stack, b, p0, mu)
    x_span = check_real("x_span", x_span, low=1.0, high=50.0)
    depth = check_real("depth", depth, low=0.1, high=100.0)
    if not isinstance(nx, int) or isinstance(nx, bool) or not 11 <= nx <= 4001:
        raise InputError(f"nx = {nx!r} must be an integer in [11, 4001]")
    if not isinstance(nz, int) or isinstance(nz, bool) or not 3 <= nz <= 400:
        raise InputError(f"nz = {nz!r} must be an integer in [3, 400]")
    h = np.array([layer.thickness for layer in stack.layers], dtype=float) / b
    tops = np.concatenate(([0.0], np.cumsum(h)))
    mats = stack.materials()
    nus = [m.nu for m in mats]
    Es = [m.E / stack.substrate.E for m in mats]
    xs = np.linspace(-x_span, x_span, nx)

    def field(xv, zv, side):
        xv, zv = np.broadcast_arrays(np.atleast_1d(np.asarray(xv, float)),
                                     np.atleast_1d(np.asarray(zv, float)))
        xv, zv = xv.ravel(), zv.ravel()
        out = _field_scaled(xv, zv, h, nus, Es, mu, side, True)
        out["sxy"] = out["syz"] = np.zeros(xv.shape)
        return out

    peaks = []
    for j, mat in enumerate(mats):
        z0 = tops[j]
        z1 = tops[j + 1] if j < len(h) else max(depth, z0 + 2.0)
        zs = np.linspace(z0, z1, nz)
        X, Z = np.meshgrid(xs, zs)
        # the layer's own side of each face: below its top, above its bottom
        vals = np.empty(X.shape)
        vals[:-1] = von_mises(field(X[:-1], Z[:-1], "below")).reshape(X[:-1].shape)
        vals[-1] = von_mises(field(X[-1], Z[-1], "above" if j < len(h) else "below"))
        k = np.unravel_index(int(np.argmax(vals)), vals.shape)
        best = (float(vals[k]), float(X[k]), float(Z[k]))
        if refine:
            lo, hi = z0 + 1e-12 * max(z1, 1.0), z1 - 1e-12 * max(z1, 1.0)

            def neg(v):
                side = "above" if (j < len(h) and v[1] >= z1) else "below"
                return -float(von_mises(field(v[0], v[1], side))[0])

            r = optimize.minimize(neg, [best[1], min(max(best[2], lo), hi)],
                                  method="L-BFGS-B",
                                  bounds=[(-x_span, x_span), (z0, z1)],
                                  options={"ftol": 1e-13, "maxiter": 200})
            if -r.fun > best[0]:
                best = (float(-r.fun), float(r.x[0]), float(r.x[1]))
        t_max = t_x = None
        if j < len(h):
            tau = np.abs(field(xs, z1, "below")["txz"])
            i = int(np.argmax(tau))
            t_max, t_x = float(tau[i]), float(xs[i])
            if refine:
                lo_, hi_ = xs[max(i - 1, 0)], xs[min(i + 1, nx - 1)]
                r = optimize.minimize_scalar(lambda t: -abs(float(field(t, z1, "below")["txz"][0])),
                                             bounds=(lo_, hi_), method="bounded",
                                             options={"xatol": 1e-10})
                if -r.fun > t_max:
                    t_max, t_x = float(-r.fun), float(r.x)
            t_max, t_x = t_max * p0, t_x * b
        sy = mat.sigma_y
        ratio = None if math.isinf(sy) else best[0] * p0 / sy
        peaks.append(LayerPeak(mat.name or ("substrate" if j == len(h) else f"layer {j + 1}"),
                               z0 * b, (z1 * b if j < len(h) else math.inf),
                               best[0] * p0, best[1] * b, best[2] * b, ratio, t_max, t_x))
    # surface tensile stress: the largest principal stress on z = 0
    xf = np.linspace(-x_span, x_span, 4 * nx + 1)
    s1 = principal_stresses(field(xf, 0.0, "below"))[..., 0]
    i = int(np.argmax(s1))
    return LayeredSlidingResult(b, p0, mu, tuple(peaks), float(s1[i]) * p0, float(xf[i]) * b)

