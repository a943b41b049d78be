"""Elastic frictionless contact of a rigid axisymmetric indenter on a film bonded to a
half-space: the converged layered-elasticity solution that the Gao weighting
(`profiles.StackProfile`) approximates (docs/layered-contact.md).

Surface response. Under an axisymmetric pressure p(r) the surface of a film of thickness t
(plane-strain modulus E'_f = E_f/(1 - nu_f^2)) perfectly bonded to a substrate (E'_s) moves by
(Hankel transforms; Perriot & Barthel 2004, J. Mater. Res. 19, 600)

    u(r) = (2/E'_f) int_0^inf C(k t) p^(k) J0(k r) dk,   p^(k) = int_0^a p(r) J0(k r) r dr,

with the compliance kernel of the bonded layer (`_kernel`; mu the shear moduli,
kappa = 3 - 4 nu, alpha = mu_f/mu_s)

    C(x) = (1 + 4 b x e^-2x - a b e^-4x) / (1 - (a + b + 4 b x^2) e^-2x + a b e^-4x),
    a = (alpha kappa_s - kappa_f)/(1 + alpha kappa_s),   b = (alpha - 1)/(alpha + kappa_f),

C(0) = E'_f/E'_s, C(inf) = 1 (checked against a transfer-matrix solution of the layer,
tests/continuum/test_coated.py). Poisson ratios may differ.

Integral equation. Write the pressure through an auxiliary function g on [0, a]:

    p^(k) = int_0^a g(s) cos(k s) ds,   g(s) = (2/pi) int_s^a r p(r) dr / sqrt(r^2 - s^2),
    p(r) = g(a)/sqrt(a^2 - r^2) - int_r^a g'(s) ds / sqrt(s^2 - r^2),   P = 2 pi int_0^a g ds.

The Abel transform theta(x) = d/dx int_0^x r u(r) dr / sqrt(x^2 - r^2) of the displacement
(with int_0^x r J0(k r) dr / sqrt(x^2 - r^2) = sin(k x)/k) is, for 0 <= x <= a,

    theta(x) = (pi/E'_f) [ g(x) + (2/pi) int_0^a K(x, s) g(s) ds ],
    K(x, s) = int_0^inf (C(k t) - 1) cos(k x) cos(k s) dk
            = [Phi(|x - s|/t) + Phi((x + s)/t)] / (2 t),
    Phi(eta) = int_0^inf (C(u) - 1) cos(u eta) du.

Inside the contact u = delta - f(r); for the paraboloid f = r^2/(2R) (Hertz's geometry, used
for the sphere here as in Hertz) theta(x) = delta - x^2/R, a Fredholm equation of the second
kind for g. The pressure is bounded at the edge iff g(a) = 0, which fixes delta; a flat punch
(theta = delta) keeps the edge singularity and has stiffness S = P/delta. In units xi = x/a,
lambda = a/t, with h1, h2 the solutions for the right-hand sides 1 and xi^2 of

    h(xi) + (lambda/pi) int_0^1 [Phi(lambda |xi - s|) + Phi(lambda (xi + s))] h(s) ds = rhs(xi),

    delta = (a^2/R) h2(1)/h1(1),   P = 2 E'_f a (delta J1 - a^2 J2/R),   S = 2 E'_f a J1,

J = int_0^1 h. A homogeneous half-space (C = 1, h1 = 1, h2 = xi^2) gives Hertz, delta = a^2/R
and P = (4/3) E' a^3/R, and the flat punch S = 2 a E'.

Numerics. Phi is tabulated once per material pair (Gauss-Legendre panels in u up to u = 25,
where C - 1 < 1e-17, graded towards u = 0, where a stiff film's kernel drops within
u ~ E'_s/E'_f, and two periods of the highest frequency per 16-node panel) and interpolated by
a cubic spline (uniform steps 0.02 to eta = 8, then steps of 1 %); against a table 4x finer
the results move by < 1e-8. The equation is solved by Nystrom's method on Gauss-Legendre
panels of width <= 2 t (the solution has edge layers of width ~t); the nodes per panel double
from 8 until the load and the stiffness change by less than ``tol`` (default 1e-6; N is
returned by `coated_solution`: 16 for a/t <= 2, 80 at a/t = 10, 800 at a/t = 100). Kernel
matrices use the panels' Toeplitz/Hankel structure. An independent Ritz solution (pressure
series, Bessel transforms) agrees to 3e-6 (tests). One call takes ~1 ms with Phi's table
cached (40 ms at a/t = 100), 15-60 ms with the table built (0.4 s at a/t = 100).

Uses: the sphere's load-approach curve (`coated_contact`, `coated_sphere_load`) and the flat
punch stiffness (`flat_punch_stiffness`, `apparent_modulus`). For any axisymmetric indenter on
this (linear, axisymmetric) half-space dP/d(delta) equals the flat-punch stiffness at the
current contact radius, so S(a) serves film-on-substrate models of indentation unloading.

Stacks. The same equation holds for any bonded stack whose surface kernel C(k t_1) (t_1 the
top layer's thickness, C normalised by the top layer's half-space response) tends to 1: only
Phi changes. `stack_sphere_curve` and `stack_solution` take several layers on an elastic
half-space or on a rigid base (`RIGID`: the bottom face held still, as an MD slab's fixed
atoms or a particle block's base hold it). Their C is the plane-strain surface compliance of
the stack (the normal mode of `sliding_layered.psv_coefficients`' recursion, which equals the
axisymmetric Hankel kernel), with the rigid base's two displacement conditions in place of the
substrate's continuity; docs/layered-contact.md, "Stacks and rigid bases".
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from filmscale.continuum.contact.sliding_layered import (continuity_matrix, decaying_modes,
                                                         growing_modes)
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError

#: C - 1 is below 1e-17 beyond u = k t = 25 (it decays as u^2 exp(-2u))
_U_MAX = 25.0
#: Gauss-Legendre nodes per u panel; the eta table: uniform step to _ETA_SPLIT, then ratio
_U_NODES, _ETA_STEP, _ETA_SPLIT, _ETA_RATIO = 16, 0.02, 8.0, 1.01
#: Nystrom panels span at most this many film thicknesses; nodes per panel start here
_PANEL_T, _N0 = 2.0, 8
#: the solver refuses problems needing more nodes (a/t above ~ 300)
_N_MAX = 4800
#: contact radius over film thickness accepted (beyond, the film changes the substrate's
#: load by ~ (t/a) C'(0)/C(0), docs/layered-contact.md)
LAMBDA_MAX = 300.0
#: a stack's base that holds the bottom of its lowest layer still (bonded, no displacement)
RIGID = "rigid"


def _shear_ratio(film: ElasticPlastic, substrate: ElasticPlastic) -> float:
    """alpha = mu_f / mu_s, the film's shear modulus over the substrate's."""
    return film.shear_modulus / substrate.shear_modulus


def _compliance(x, ratio: float, nu_f: float, nu_s: float):
    """C(x = k t) (dimensionless; x = k t, k the wavenumber in 1/m, t the film thickness in
    m) for the shear-modulus ratio mu_f/mu_s and the Poisson ratios: the bonded-layer kernel
    of the module docstring (Perriot & Barthel 2004, J. Mater. Res. 19, 600)."""
    kf, ks = 3 - 4 * nu_f, 3 - 4 * nu_s
    a = (ratio * ks - kf) / (ratio * ks + 1)
    b = (ratio - 1) / (ratio + kf)
    e2 = np.exp(-2 * x)
    return (1 + 4 * b * x * e2 - a * b * e2**2) / \
        (1 - (a + b + 4 * b * x**2) * e2 + a * b * e2**2)


def _kernel(x, film: ElasticPlastic, substrate: ElasticPlastic):
    """C(k t) of a bonded layer (Perriot & Barthel 2004), with its Dundurs-type a and b."""
    return _compliance(x, _shear_ratio(film, substrate), film.nu, substrate.nu)


def _stack_compliance(u, h, E, nu, rigid: bool):
    """C(u = k t_1) (dimensionless; k the wavenumber in 1/m, t_1 the top layer's thickness in
    m) of bonded layers on a half-space or a rigid base: h the layers' thicknesses over t_1,
    E their Young's moduli over the top one's and nu their Poisson ratios (with one more E and
    nu for an elastic half-space under them). Perriot & Barthel's (2004) kernel, generalised:
    the surface u_z of the normal mode (D0 = 1, D1 = 0 at the surface; the Airy-function modes
    of `sliding_layered`) over the top layer's half-space value -2 (1 - nu_1^2)/E_1. The
    recursion runs from the bottom up: each interface gives the up-going pair of the layer above as a reflection of its down-going pair; a rigid base
    gives it from u_x = u_z = 0 at the lowest layer's bottom face."""
    u = np.atleast_1d(np.asarray(u, dtype=float))
    L, n = len(h), u.size
    M = [continuity_matrix(v, e) for v, e in zip(nu, E)]
    down0, up0 = decaying_modes(np.zeros(1))[0], growing_modes(np.zeros(1))[0]
    if rigid:
        t = u * h[-1]
        reflect = np.linalg.solve(np.broadcast_to(M[L - 1][2:] @ up0, (n, 2, 2)),
                                  -(M[L - 1][2:] @ decaying_modes(t)))
        above = M[L - 1] @ (down0 + growing_modes(-t) @ reflect)
        layers = range(L - 2, -1, -1)
    else:
        above = np.broadcast_to(M[L] @ down0, (n, 4, 2))
        layers = range(L - 1, -1, -1)
    for j in layers:
        t = u * h[j]
        A = np.empty((n, 4, 4))
        A[:, :, :2], A[:, :, 2:] = M[j] @ up0, -above
        reflect = np.linalg.solve(A, -(M[j] @ decaying_modes(t)))[:, :2]
        above = M[j] @ (down0 + growing_modes(-t) @ reflect)
    top = down0 + growing_modes(-u * h[0]) @ reflect
    normal = np.broadcast_to(np.array([[1.0], [0.0]]), (n, 2, 1))    # D0 = 1, D1 = 0
    u_z = np.einsum("j,njk,nk->n", M[0][3], top, np.linalg.solve(top[:, :2, :], normal)[..., 0])
    return u_z / (-2.0 * (1.0 - nu[0] ** 2) / E[0])


def _film_key(film: ElasticPlastic, substrate: ElasticPlastic) -> tuple:
    """The kernel of a film on a half-space, as a hashable key of `_kernel_values`."""
    return ("film", float(_shear_ratio(film, substrate)), float(film.nu), float(substrate.nu))


def _stack_key(layers, base) -> tuple:
    """The kernel of bonded ``layers`` [(thickness, material)] on ``base`` (a material or
    `RIGID`), as a hashable key of `_kernel_values` (lengths over the top layer's thickness,
    moduli over its E)."""
    t1, E1 = layers[0][0], layers[0][1].E
    mats = [m for _, m in layers] + ([] if base == RIGID else [base])
    return ("stack", tuple(float(t / t1) for t, _ in layers), tuple(float(m.E / E1) for m in mats),
            tuple(float(m.nu) for m in mats), base == RIGID)


def _kernel_values(u, key: tuple):
    """C(u) of the kernel a `_film_key` or `_stack_key` names."""
    if key[0] == "film":
        return _compliance(u, *key[1:])
    return _stack_compliance(u, *key[1:])


def _gauss_panels(edges, n):
    """Gauss-Legendre nodes and weights of n points on each panel between ``edges``."""
    x, w = np.polynomial.legendre.leggauss(n)
    edges = np.asarray(edges, dtype=float)
    lo, h = edges[:-1, None], np.diff(edges)[:, None]
    return (lo + 0.5 * h * (x + 1)).ravel(), (0.5 * h * w).ravel()


@lru_cache(maxsize=32)
def _phi_table(key: tuple, eta_max: float):
    """Cubic spline of Phi(eta) = int_0^inf (C(u) - 1) cos(u eta) du on [0, eta_max]."""
    width = min(0.25, 4 * math.pi / eta_max)       # two periods of cos(u eta_max)
    # graded towards u = 0 down to 1e-6: a stiff film's C drops within u ~ E'_s/E'_f
    edges = np.concatenate([[0.0], np.geomspace(1e-6, width, 25),
                            np.arange(2 * width, _U_MAX + width, width)])
    u, w = _gauss_panels(edges, _U_NODES)
    f = (_kernel_values(u, key) - 1.0) * w
    n_geo = max(2, math.ceil(math.log(eta_max / _ETA_SPLIT) / math.log(_ETA_RATIO)) + 1)
    eta = np.concatenate([np.arange(0.0, _ETA_SPLIT, _ETA_STEP),
                          np.geomspace(_ETA_SPLIT, eta_max, n_geo)])
    values = np.empty_like(eta)
    for i in range(0, eta.size, 256):             # bounded memory
        values[i:i + 256] = np.cos(np.outer(eta[i:i + 256], u)) @ f
    from scipy.interpolate import CubicSpline
    return CubicSpline(eta, values, bc_type=((1, 0.0), "not-a-knot"))


def _phi(lam: float, key: tuple):
    """Phi's spline covering eta <= 2 lambda (tables for powers of 2, at least 16)."""
    return _phi_table(key, 2.0 ** max(4, math.ceil(math.log2(2 * lam))))


def _nystrom(lam: float, phi, m: int, n: int):
    """Solve for h1, h2 on m panels of n nodes: (J1, J2, h1(1), h2(1))."""
    xl, wl = np.polynomial.legendre.leggauss(n)
    xl, wl = 0.5 * (xl + 1), 0.5 * wl                      # on [0, 1]
    hp = 1.0 / m
    x = ((np.arange(m)[:, None] + xl) * hp).ravel()
    w = np.tile(wl * hp, m)
    # Phi(lambda |x_i - x_j|) and Phi(lambda (x_i + x_j)) depend on the panels' difference
    # and sum and the local nodes only: 2 (2m - 1) n^2 spline values instead of 2 N^2
    d = np.arange(-(m - 1), m)[:, None, None] + xl[:, None] - xl[None, :]
    e = np.arange(2 * m - 1)[:, None, None] + xl[:, None] + xl[None, :]
    diff, summ = phi(lam * hp * np.abs(d)), phi(lam * hp * e)
    p = np.arange(m)
    K = diff[p[:, None] - p[None, :] + m - 1] + summ[p[:, None] + p[None, :]]
    K = K.transpose(0, 2, 1, 3).reshape(m * n, m * n)
    A = (lam / math.pi) * K * w
    A[np.diag_indices_from(A)] += 1.0
    H = np.linalg.solve(A, np.column_stack([np.ones_like(x), x * x]))
    # Nystrom interpolation of h at the contact edge xi = 1
    k_edge = (lam / math.pi) * (phi(lam * (1.0 - x)) + phi(lam * (1.0 + x))) * w
    J1, J2 = w @ H
    e1, e2 = 1.0 - k_edge @ H
    return J1, J2, e1, e2


class _Dimensionless(NamedTuple):
    q: float         # delta R / a^2 of the paraboloid
    p: float         # P R / (E'_f a^3)
    s: float         # S / (E'_f a), flat punch
    nodes: int
    change: float    # relative change of p and s from the previous (half) node count


@lru_cache(maxsize=256)
def _solve_cached(lam, key, tol) -> _Dimensionless:
    phi = _phi(lam, key)
    m = max(1, math.ceil(lam / _PANEL_T))
    n, old = _N0, None
    while True:
        J1, J2, e1, e2 = _nystrom(lam, phi, m, n)
        q = e2 / e1
        new = np.array([q, 2.0 * (q * J1 - J2), 2.0 * J1])
        if old is not None:
            change = float(np.max(np.abs(new[1:] / old[1:] - 1.0)))
            if change < tol:
                return _Dimensionless(*map(float, new), m * n, change)
        if 2 * m * n > _N_MAX:
            raise InputError(f"the coated contact did not converge to {tol:g} within "
                             f"{m * n} nodes (a/t = {lam:g})")
        old, n = new, 2 * n


def _solve_key(a, thickness, key, tol) -> _Dimensionless:
    """The dimensionless solution at contact radius ``a`` (m) for the kernel ``key`` of a top
    layer of ``thickness`` (m)."""
    lam = check_positive("a", a, "m") / check_positive("thickness", thickness, "m")
    check_real("a/thickness", lam, low=0.0, high=LAMBDA_MAX, low_open=True)
    check_real("tol", tol, low=1e-12, high=1e-2)
    return _solve_cached(float(lam), key, float(tol))


def _solve(a, thickness, film, substrate, tol) -> _Dimensionless:
    for m in (film, substrate):
        if not isinstance(m, ElasticPlastic):
            raise InputError(f"film and substrate must be ElasticPlastic, got {m!r}")
    return _solve_key(a, thickness, _film_key(film, substrate), tol)


def _checked_stack(layers, base) -> tuple:
    """``layers`` as a tuple of (thickness, ElasticPlastic), top first, and ``base``, checked."""
    try:
        layers = tuple((t, m) for t, m in layers)
    except (TypeError, ValueError):
        raise InputError("layers must be (thickness in m, ElasticPlastic) pairs, top first") \
            from None
    if not layers:
        raise InputError("layers is empty: a stack needs at least one layer over its base")
    for k, (t, m) in enumerate(layers):
        check_positive(f"layers[{k}] thickness", t, "m")
        if not isinstance(m, ElasticPlastic):
            raise InputError(f"layers[{k}] material must be ElasticPlastic, got {m!r}")
    if base != RIGID and not isinstance(base, ElasticPlastic):
        raise InputError(f"base = {base!r} is neither an ElasticPlastic half-space nor "
                         f"{RIGID!r}")
    return layers, base


class CoatedContact(NamedTuple):
    """A rigid paraboloid (sphere) at contact radius a on the coated half-space."""

    delta: float       #: approach, m
    load: float        #: N
    stiffness: float   #: dP/d(delta) = the flat-punch stiffness at radius a, N/m
    nodes: int         #: Gauss-Legendre nodes N of the accepted solution
    change: float      #: relative change of load and stiffness from N/2 nodes to N


def coated_solution(a: float, R: float, thickness: float, film: ElasticPlastic,
                    substrate: ElasticPlastic, tol: float = 1e-6) -> CoatedContact:
    """The converged contact of a rigid sphere of radius ``R`` (m; paraboloid profile
    r^2/(2R)) at contact radius ``a`` (m) on a film of ``thickness`` (m) bonded to
    ``substrate``: approach, load, stiffness and the node count N at which the load and the
    stiffness changed by less than ``tol`` (relative) from N/2; a/t <= 300."""
    R = check_positive("R", R, "m")
    sol = _solve(a, thickness, film, substrate, tol)
    E_p = film.plane_strain_modulus
    return CoatedContact(sol.q * a * a / R, sol.p * E_p * a**3 / R, sol.s * E_p * a,
                         sol.nodes, sol.change)


def coated_contact(a: float, R: float, thickness: float, film: ElasticPlastic,
                   substrate: ElasticPlastic) -> tuple[float, float]:
    """Approach delta (m) and load P (N) of a rigid sphere of radius R (m) at contact
    radius ``a`` (m) on a film of ``thickness`` (m) bonded to ``substrate``: the converged
    solution (`coated_solution`, load to 1e-6)."""
    c = coated_solution(a, R, thickness, film, substrate)
    return c.delta, c.load


def flat_punch_stiffness(a: float, thickness: float, film: ElasticPlastic,
                         substrate: ElasticPlastic, tol: float = 1e-6) -> float:
    """Normal stiffness S (N/m) of a rigid flat punch of radius ``a`` (m) on a film of
    ``thickness`` (m) bonded to ``substrate``; 2 a E' on a homogeneous half-space.

    It is also dP/d(delta) of any rigid axisymmetric indenter (sphere, cone, ...) whose
    contact radius is ``a`` (frictionless, linear elastic), hence the contact stiffness of a
    film-on-substrate indentation at contact radius a."""
    return _solve(a, thickness, film, substrate, tol).s * film.plane_strain_modulus * a


def apparent_modulus(a: float, thickness: float, film: ElasticPlastic,
                     substrate: ElasticPlastic, tol: float = 1e-6) -> float:
    """The plane-strain modulus (Pa) an indent of contact radius ``a`` 'sees':
    S/(2a), with S the flat-punch stiffness; E'_f for a/t -> 0, E'_s for a/t -> inf."""
    return 0.5 * _solve(a, thickness, film, substrate, tol).s * film.plane_strain_modulus


def coated_sphere_load(delta, R: float, thickness: float, film: ElasticPlastic,
                       substrate: ElasticPlastic) -> np.ndarray:
    """Elastic load (N) of a rigid sphere of radius R (m) pressed to approach ``delta``
    (m, array) into the coated half-space: for each approach the contact radius is found
    (Brent, in log a, to 1e-11 relative), then the converged load."""
    delta = np.atleast_1d(np.asarray(delta, dtype=float))
    check_positive("delta", float(delta.min()), "m")
    R, t = check_positive("R", R, "m"), check_positive("thickness", thickness, "m")
    from scipy.optimize import brentq
    E_p = film.plane_strain_modulus

    def solution(log_lam):
        return _solve(t * math.exp(log_lam), t, film, substrate, 1e-6)

    out = np.empty_like(delta)
    for i, d in enumerate(delta.ravel()):
        # delta(a) = q(lambda) a^2/R increases with a: solve lambda^2 q(lambda) = R delta/t^2,
        # bracketed from Hertz's a = sqrt(R delta) outwards
        target = math.log(R * d / (t * t))

        def gap(log_lam, target=target):
            return 2.0 * log_lam + math.log(solution(log_lam).q) - target
        lo = hi = 0.5 * target
        while gap(lo) > 0:
            lo -= 1.0
        while gap(hi) < 0:
            hi += 1.0
        log_lam = lo if lo == hi else brentq(gap, lo, hi, xtol=1e-11, rtol=1e-12)
        a = t * math.exp(log_lam)
        out.flat[i] = solution(log_lam).p * E_p * a**3 / R
    return out


def coated_sphere_curve(delta, R: float, thickness: float, film: ElasticPlastic,
                        substrate: ElasticPlastic, radii: int = 24) -> np.ndarray:
    """`coated_sphere_load` for fits that evaluate a whole loading curve many times: the
    converged solution at ``radii`` contact radii whose approaches bracket the given ones
    (geometric in a, widened until they do), interpolated by a cubic spline in
    (ln delta, ln P); 0 at approaches <= 0. About 10 times faster than `coated_sphere_load`
    on a 100-point curve and within 1e-5 of it (test)."""
    t = check_positive("thickness", thickness, "m")
    for m in (film, substrate):
        if not isinstance(m, ElasticPlastic):
            raise InputError(f"film and substrate must be ElasticPlastic, got {m!r}")
    return _sphere_curve(delta, R, t, film.plane_strain_modulus, _film_key(film, substrate),
                         radii)


def stack_sphere_curve(delta, R: float, layers, base=RIGID, radii: int = 24) -> np.ndarray:
    """Elastic load (N) of a rigid sphere of radius ``R`` (m; paraboloid r^2/(2R)) at
    approaches ``delta`` (m) into bonded ``layers`` [(thickness m, ElasticPlastic), top first]
    on ``base``: an elastic half-space (ElasticPlastic) or `RIGID` (the lowest layer's bottom
    held still). Perriot & Barthel's (2004) Fredholm equation with the stack's kernel
    (module docstring, "Stacks"); as `coated_sphere_curve` (spline over ``radii`` converged
    solutions); 0 at approaches <= 0. The top layer's contact radius a/t_1 must stay <=
    `LAMBDA_MAX`."""
    layers, base = _checked_stack(layers, base)
    t1, top = layers[0]
    return _sphere_curve(delta, R, t1, top.plane_strain_modulus, _stack_key(layers, base),
                         radii)


def stack_solution(a: float, R: float, layers, base=RIGID, tol: float = 1e-6) -> CoatedContact:
    """`coated_solution` for bonded ``layers`` on ``base`` (as `stack_sphere_curve`): the
    approach, load and flat-punch stiffness of a rigid sphere at contact radius ``a`` (m)."""
    R = check_positive("R", R, "m")
    layers, base = _checked_stack(layers, base)
    t1, top = layers[0]
    sol = _solve_key(a, t1, _stack_key(layers, base), tol)
    E_p = top.plane_strain_modulus
    return CoatedContact(sol.q * a * a / R, sol.p * E_p * a**3 / R, sol.s * E_p * a,
                         sol.nodes, sol.change)


def _sphere_curve(delta, R, t, E_p, key, radii) -> np.ndarray:
    """Loads (N) at approaches ``delta`` (m) from ``radii`` solutions of the kernel ``key``
    (top layer ``t`` m thick, plane-strain modulus ``E_p``), splined in (ln delta, ln P)."""
    from scipy.interpolate import CubicSpline
    delta = np.asarray(delta, dtype=float)
    out = np.zeros(delta.shape)
    positive = delta > 0
    if not positive.any():
        return out
    R = check_positive("R", R, "m")
    d_min, d_max = float(delta[positive].min()), float(delta[positive].max())

    def approach(a):
        return _solve_key(a, t, key, 1e-6).q * a * a / R
    # Hertz's a = sqrt(R delta) to start; a stiff film on a soft substrate sinks as a whole,
    # so its approach at a given radius can be far larger: widen until bracketed
    lo, hi = math.sqrt(R * d_min), math.sqrt(R * d_max)
    while approach(lo) > d_min:
        lo /= 2
    while approach(hi) < d_max:
        hi *= 2
    a = np.geomspace(lo, hi, max(radii, 8))
    sols = [_solve_key(float(r), t, key, 1e-6) for r in a]
    d = np.array([s.q for s in sols]) * a * a / R
    P = np.array([s.p for s in sols]) * E_p * a**3 / R
    out[positive] = np.exp(CubicSpline(np.log(d), np.log(P))(np.log(delta[positive])))
    return out
