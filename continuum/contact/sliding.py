"""Stresses in an elastic half-space under a sliding Hertz contact (issue 34, homogeneous part).

Units are SI throughout: loads in N, lengths in m, moduli and stresses in Pa. Stresses are
positive in tension. Axes: x along the sliding direction, y across it, z the depth into the
half-space (z >= 0). The slider drags the surface in +x, so the surface traction on the
half-space is q = mu p in +x (full sliding, Coulomb friction): the leading edge of the contact
is x = +a and the trailing edge, where the surface is stretched, is x = -a.

Sources
-------
* Hertz contact quantities: Johnson, Contact Mechanics (1985), eqs 4.22-4.23 (sphere),
  4.43-4.45 (cylinder).
* Cylinder (plane strain): McEwen (1949) / Smith & Liu (1953) closed forms as written in
  Johnson (1985) eqs 4.50 (normal Hertz pressure) and 7.18 (tangential traction), with the
  functions m and n of eq 4.49. The tangential sigma_x is written for a traction in +x; its
  sign was fixed against a direct integration of the Flamant kernels (Johnson section 2.2).
* Sphere, normal Hertz pressure only (mu = 0): Hamilton (1983), Proc. IMechE 197C 53-59,
  explicit equations for the normal load (also Hamilton & Goodman 1966), with the axis limit
  r -> 0 of Huber (1904) / Johnson eq 3.45. Hamilton's equations for the tangential traction
  were not obtained from a reliable source: the tangential part (sphere with friction) is the
  numerical integral of Cerruti's point-force stresses (Johnson 1985 eq 3.87) over the traction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from filmscale.core.checks import check_real
from filmscale.core.errors import InputError

__all__ = [
    "effective_modulus", "hertz_sphere", "hertz_cylinder", "cylinder_stresses",
    "sphere_normal_stresses", "principal_stresses", "von_mises", "max_shear",
    "SlidingResult", "cylinder_sliding", "sphere_normal_result", "cylinder_surface_yield_friction",
    "sphere_tangential_stresses", "sphere_stresses", "sphere_sliding", "sphere_surface_yield_friction",
]

MODULUS_RANGE = (1e6, 1e14)     # Pa
NU_RANGE = (-1.0, 0.5)          # Poisson's ratio, open interval
MU_MAX = 10.0                   # friction coefficient upper bound
#: shallowest depth (in units of b) searched for a subsurface maximum of the stress measure
Z_MIN = 0.01
#: (r/a)^2 below which the sphere's axis (Huber) values are used
AXIS_R2 = 4e-8


def effective_modulus(E, nu, E_s=None, nu_s=None) -> float:
    """Contact modulus E* (Pa) from E, E_s (Pa) and nu, nu_s (1):
    1/E* = (1-nu^2)/E + (1-nu_s^2)/E_s (Johnson 1985 eq 4.22); a rigid slider if E_s is None."""
    E = _modulus("E", E)
    nu = check_poisson(nu)
    inv = (1.0 - nu * nu) / E
    if E_s is not None:
        E_s = _modulus("E_s", E_s)
        nu_s = check_poisson(0.0 if nu_s is None else nu_s, "nu_s")
        inv += (1.0 - nu_s * nu_s) / E_s
    elif nu_s is not None:
        raise InputError("nu_s was given without E_s: give the slider's E_s too")
    return 1.0 / inv


def _load(P):
    return check_real("P", P, low=0.0, high=1e9, low_open=True, unit="N")


def _length(name, v):
    return check_real(name, v, low=1e-12, high=1e3, unit="m")


def _modulus(name, E):
    return check_real(name, E, low=MODULUS_RANGE[0], high=MODULUS_RANGE[1], unit="Pa")


def check_friction(mu, name: str = "mu") -> float:
    """A friction coefficient in [0, MU_MAX], or InputError naming `name`."""
    return check_real(name, mu, low=0.0, high=MU_MAX)


def check_poisson(nu, name: str = "nu") -> float:
    """A Poisson's ratio in the open interval NU_RANGE, or InputError naming `name`."""
    return check_real(name, nu, low=NU_RANGE[0], high=NU_RANGE[1], low_open=True, high_open=True)


def hertz_sphere(P, R, E_star) -> tuple[float, float]:
    """Sphere on a flat (P in N, R in m, E* in Pa): contact radius a = (3PR/4E*)^(1/3) (m) and
    p0 = 3P/(2 pi a^2) (Pa) (Johnson 1985 eqs 4.22-4.23)."""
    P, R = _load(P), _length("R", R)
    E_star = _modulus("E_star", E_star)
    a = (3.0 * P * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return a, 3.0 * P / (2.0 * math.pi * a * a)


def hertz_cylinder(P, L, R, E_star) -> tuple[float, float]:
    """Cylinder (length L and radius R in m, total load P in N, E* in Pa, P' = P/L): half-width
    b = sqrt(4P'R/(pi E*)) (m), p0 = 2P'/(pi b) (Pa) (Johnson 1985 eqs 4.43-4.45)."""
    P, L, R = _load(P), _length("L", L), _length("R", R)
    E_star = _modulus("E_star", E_star)
    w = P / L
    b = math.sqrt(4.0 * w * R / (math.pi * E_star))
    return b, 2.0 * w / (math.pi * b)


def _depth(z):
    z = np.asarray(z, dtype=float)
    if np.any(~np.isfinite(z)) or np.any(z < 0):
        raise InputError("z must be finite depths >= 0 m into the half-space")
    return z


def cylinder_stresses(x, z, b, p0, mu, nu) -> dict[str, np.ndarray]:
    """Plane-strain stresses (Pa) at (x, z) (m) under p = p0 sqrt(1-x^2/b^2), q = mu p in +x.

    Returns sxx, szz, txz, syy = nu (sxx + szz), and the zero sxy, syz (tension positive).
    b in m, p0 in Pa. McEwen (1949) / Smith & Liu (1953) closed forms, Johnson (1985) eqs 4.49,
    4.50 (normal pressure) and 7.18 (tangential traction).
    """
    b = _length("b", b)
    p0 = check_real("p0", p0, low=0.0, high=1e14, unit="Pa")
    mu, nu = check_friction(mu), check_poisson(nu)
    x = np.asarray(x, dtype=float)
    z = _depth(z)
    x, z = np.broadcast_arrays(x, z)
    A = b * b - x * x + z * z
    S = np.sqrt(A * A + 4.0 * x * x * z * z)
    # Johnson eq 4.49, m^2 = (S + A)/2, n^2 = (S - A)/2, with m^2 n^2 = x^2 z^2 used for the
    # smaller of the two so that neither loses digits far from the contact
    big = 0.5 * (S + np.abs(A))
    small = np.where(big > 0, x * x * z * z / np.where(big > 0, big, 1.0), 0.0)
    m = np.sqrt(np.where(A >= 0, big, small))
    n = np.sign(x) * np.sqrt(np.where(A >= 0, small, big))
    D = m * m + n * n
    edge = D == 0.0                                                      # x = +-b on z = 0
    D = np.where(edge, 1.0, D)
    f1 = (z * z + n * n) / D
    f2 = (m * m - z * z) / D
    k = p0 / b
    q0 = mu * p0
    sxx = -k * (m * (1.0 + f1) - 2.0 * z)                               # eq 4.50a
    szz = -k * m * (1.0 - f1)                                           # eq 4.50b
    txz = -k * n * f2                                                   # eq 4.50c
    kq = q0 / b
    sxx = sxx + kq * (n * (2.0 + f2) - 2.0 * x)                         # eq 7.18a, q in +x
    szz = szz - kq * n * f2                                             # eq 7.18b
    txz = txz - kq * (m * (1.0 + f1) - 2.0 * z)                         # eq 7.18c
    # the edge point itself: the limit from the surface, where p = 0 and sxx = -2 q0 x/b
    sxx = np.where(edge, -2.0 * q0 * np.sign(x), sxx)
    szz = np.where(edge, 0.0, szz)
    txz = np.where(edge, 0.0, txz)
    zero = np.zeros_like(sxx)
    return {"sxx": sxx, "syy": nu * (sxx + szz), "szz": szz,
            "sxy": zero, "syz": zero, "txz": txz}


def sphere_normal_stresses(x, y, z, a, p0, nu) -> dict[str, np.ndarray]:
    """All six stresses (Pa) at (x, y, z) (m) under the Hertz pressure of a sphere (mu = 0).

    Hamilton (1983) explicit equations for the normal load; near the axis (r < 2e-4 a, where the
    1/r^2 terms lose digits) the Huber closed form (Johnson eq 3.45): error < 2e-7 p0 there.
    """
    a = _length("a", a)
    p0 = check_real("p0", p0, low=0.0, high=1e14, unit="Pa")
    nu = check_poisson(nu)
    x, y, z = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), _depth(z))
    x, y, z = x / a, y / a, z / a                          # work in units of a (a = 1)
    r2 = x * x + y * y
    axis = r2 < AXIS_R2                                      # cancellation in 1/r^2 terms
    r2s = np.where(axis, 1.0, r2)
    A = r2 + z * z - 1.0
    S = np.sqrt(A * A + 4.0 * z * z)
    edge = S < 1e-300                                       # r = a on the surface
    S = np.where(edge, 1e-300, S)
    # M^2 N^2 = z^2 gives the smaller of M, N without cancellation far from the contact
    big = 0.5 * (S + np.abs(A))
    small = np.where(big > 0, z * z / np.where(big > 0, big, 1.0), 0.0)
    M = np.sqrt(np.where(A >= 0, big, small))
    N = np.sqrt(np.where(A >= 0, small, big))
    phi = np.arctan2(1.0, M)
    G = M * M - N * N + z * M - N
    H = 2.0 * M * N + M + z * N
    GH = np.where(G * G + H * H == 0.0, 1.0, G * G + H * H)
    common = (1.0 - nu) * N * z * z - (1.0 - 2.0 * nu) / 3.0 * (N * S + 2.0 * A * N + 1.0) - nu * M * z
    sxx = (1 + nu) * z * phi + ((y * y - x * x) / r2s * common - N * (x * x + 2 * nu * y * y)
                                - M * x * x * z / S) / r2s
    syy = (1 + nu) * z * phi + ((x * x - y * y) / r2s * common - N * (y * y + 2 * nu * x * x)
                                - M * y * y * z / S) / r2s
    szz = -N + z * M / S
    sxy = (x * y * (1 - 2 * nu) / r2s ** 2 * (-N * r2 + 2.0 / 3.0 * N * (S + 2 * A)
                                             - z * (z * N + M) + 2.0 / 3.0)
           + x * y * z / r2s ** 2 * (-M * r2 / S - z * N + M))
    sxz = -z * (x * N / S - x * z * H / GH)
    syz = -z * (y * N / S - y * z * H / GH)
    # on the axis: Huber
    zs = np.where(z == 0.0, 1.0, z)
    s_ax = np.where(z == 0.0, -(1 + 2 * nu) / 2.0,
                    (1 + nu) * (z * np.arctan(1.0 / zs) - 1.0) + 0.5 / (1.0 + z * z))
    sxx = np.where(axis, s_ax, sxx)
    syy = np.where(axis, s_ax, syy)
    szz = np.where(axis, -1.0 / (1.0 + z * z), szz)
    sxy = np.where(axis, 0.0, sxy)
    sxz = np.where(axis, 0.0, sxz)
    syz = np.where(axis, 0.0, syz)
    out = {"sxx": sxx, "syy": syy, "szz": szz, "sxy": sxy, "syz": syz, "txz": sxz}
    return {k: p0 * v for k, v in out.items()}


def _tensor(s) -> np.ndarray:
    sxx, syy, szz = (np.asarray(s[k], float) for k in ("sxx", "syy", "szz"))
    sxy, syz, sxz = (np.asarray(s[k], float) for k in ("sxy", "syz", "txz"))
    sxx, syy, szz, sxy, syz, sxz = np.broadcast_arrays(sxx, syy, szz, sxy, syz, sxz)
    T = np.empty(sxx.shape + (3, 3))
    T[..., 0, 0], T[..., 1, 1], T[..., 2, 2] = sxx, syy, szz
    T[..., 0, 1] = T[..., 1, 0] = sxy
    T[..., 1, 2] = T[..., 2, 1] = syz
    T[..., 0, 2] = T[..., 2, 0] = sxz
    return T


def principal_stresses(s) -> np.ndarray:
    """Principal stresses (Pa), last axis ordered s1 >= s2 >= s3."""
    return np.linalg.eigvalsh(_tensor(s))[..., ::-1]


def max_shear(s) -> np.ndarray:
    """Largest principal shear stress (s1 - s3)/2 (Pa) (Tresca)."""
    p = principal_stresses(s)
    return 0.5 * (p[..., 0] - p[..., 2])


def von_mises(s) -> np.ndarray:
    """Von Mises equivalent stress (Pa)."""
    sxx, syy, szz = (np.asarray(s[k], float) for k in ("sxx", "syy", "szz"))
    sxy, syz, sxz = (np.asarray(s[k], float) for k in ("sxy", "syz", "txz"))
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (sxy ** 2 + syz ** 2 + sxz ** 2))


@dataclass(frozen=True)
class SlidingResult:
    """What a user reads for one sliding contact; lengths in m, stresses in Pa."""

    half_width: float          # a (sphere) or b (cylinder), m
    p0: float                  # peak Hertz pressure, Pa
    vm_max: float              # largest von Mises stress in the half-space, Pa
    vm_x: float                # where it is, m
    vm_z: float
    yield_ratio: float | None  # vm_max / sigma_y (None without sigma_y)
    tensile_max: float         # largest surface tensile stress (sigma_xx at x = -b), Pa
    at_surface: bool           # the largest von Mises is on the surface
    vm_y: float = 0.0          # across the sliding direction (sphere), m


def _cyl_vm(x, z, nu, mu):
    return von_mises(cylinder_stresses(x, z, 1.0, 1.0, mu, nu))


def _cyl_peaks(nu, mu, measure=_cyl_vm):
    """(largest value at the surface, x) and (largest below the surface, x, z) in units b, p0."""
    xs = np.linspace(-1.5, 1.5, 3001)
    vs = measure(xs, 0.0, nu, mu)
    i = int(np.argmax(vs))
    res = optimize.minimize_scalar(lambda t: -measure(t, 0.0, nu, mu),
                                   bounds=(xs[max(i - 1, 0)], xs[min(i + 1, xs.size - 1)]),
                                   method="bounded", options={"xatol": 1e-12})
    surf = (float(-res.fun), float(res.x))
    X, Z = np.meshgrid(np.linspace(-1.2, 1.2, 121), np.linspace(Z_MIN, 1.2, 60))
    V = measure(X, Z, nu, mu)
    j = np.unravel_index(int(np.argmax(V)), V.shape)
    fun = lambda v: -float(measure(v[0], v[1], nu, mu))         # noqa: E731
    r = optimize.minimize(fun, [X[j], Z[j]], method="L-BFGS-B",
                          bounds=[(-1.5, 1.5), (Z_MIN, 1.5)],
                          options={"ftol": 1e-15, "gtol": 1e-11, "maxiter": 2000})
    sub = (float(-r.fun), float(r.x[0]), float(r.x[1]))
    return surf, sub


def cylinder_sliding(P, L, R, E, nu, mu, sigma_y=None, E_s=None, nu_s=None) -> SlidingResult:
    """Sliding cylinder (radius R, length L in m, total load P in N) on a half-space (E in Pa,
    nu); sigma_y in Pa. Hertz line contact (Johnson 1985 eqs 4.43-4.45) and the
    McEwen / Smith & Liu field (Johnson eqs 4.49, 4.50, 7.18); see docs/sliding.md."""
    E_star = effective_modulus(E, nu, E_s, nu_s)
    nu, mu = check_poisson(nu), check_friction(mu)
    b, p0 = hertz_cylinder(P, L, R, E_star)
    if sigma_y is not None:
        sigma_y = check_real("sigma_y", sigma_y, low=0.0, high=1e12, low_open=True, unit="Pa")
    (vs, xs), (vi, xi, zi) = _cyl_peaks(nu, mu)
    surface = vs >= vi
    vm, xm, zm = (vs, xs, 0.0) if surface else (vi, xi, zi)
    return SlidingResult(b, p0, vm * p0, xm * b, zm * b,
                         None if sigma_y is None else vm * p0 / sigma_y, 2.0 * mu * p0, surface)


def sphere_normal_result(P, R, E, nu, sigma_y=None, E_s=None, nu_s=None) -> SlidingResult:
    """Frictionless (mu = 0) sphere: the largest von Mises is on the axis (found there)."""
    E_star = effective_modulus(E, nu, E_s, nu_s)
    nu = check_poisson(nu)
    a, p0 = hertz_sphere(P, R, E_star)
    if sigma_y is not None:
        sigma_y = check_real("sigma_y", sigma_y, low=0.0, high=1e12, low_open=True, unit="Pa")
    f = lambda t: -von_mises(sphere_normal_stresses(0.0, 0.0, t, 1.0, 1.0, nu))  # noqa: E731
    r = optimize.minimize_scalar(f, bounds=(0.0, 3.0), method="bounded", options={"xatol": 1e-12})
    vm = float(-r.fun)
    return SlidingResult(a, p0, vm * p0, 0.0, float(r.x) * a,
                         None if sigma_y is None else vm * p0 / sigma_y,
                         (1.0 - 2.0 * nu) / 3.0 * p0, False)


def cylinder_surface_yield_friction(nu, criterion="von_mises") -> float:
    """Friction mu (1) at which the largest von Mises (or Tresca) stress of a sliding cylinder
    reaches the surface (Johnson 1985 section 7.2: about 0.25 at nu = 0.3)."""
    nu = check_poisson(nu)
    if criterion == "von_mises":
        measure = _cyl_vm
    elif criterion == "tresca":
        def measure(x, z, nu_, mu_):
            return max_shear(cylinder_stresses(x, z, 1.0, 1.0, mu_, nu_))
    else:
        raise InputError(f"criterion = {criterion!r} is not one of 'von_mises', 'tresca'")

    def gap(mu):
        (vs, _), (vi, _, _) = _cyl_peaks(nu, mu, measure)
        return vs - vi

    return float(optimize.brentq(gap, 0.05, 0.6, xtol=1e-6))


def _melan_feasible(load: float, d: np.ndarray, t: np.ndarray) -> bool:
    """Whether, at ``load`` = p0/k, each depth (row) admits a residual stress rho(z) with
    |d + rho/2| <= sqrt(1 - t^2) at every x of the row (d = (sxx - szz)/(2 p0), t = txz/p0 in
    units of k once scaled by ``load``)."""
    tau = load * t
    if np.any(np.abs(tau) > 1.0):
        return False
    slack = np.sqrt(1.0 - tau * tau)
    half = load * d
    return bool(np.all(np.max(half - slack, axis=1) <= np.min(half + slack, axis=1)))


def cylinder_shakedown_pressure(mu, nu=0.3, grid: int = 801) -> float:
    """p0/k of the elastic shakedown limit of a cylinder sliding repeatedly on a homogeneous
    half-space in plane strain (Johnson 1985 section 9.2; Johnson & Jefferis 1963): the largest
    p0 for which Melan's theorem finds a steady residual stress rho_xx(z), independent of x,
    that keeps the in-plane Tresca stress ((sxx + rho - szz)/2)^2 + txz^2 within k^2 everywhere.
    k is the yield stress in shear (sigma_y / sqrt(3) by von Mises, sigma_y / 2 by Tresca).
    Found by bisection to 1e-6 on a (x, z) grid of ``grid`` x ``grid // 4`` points over
    |x| <= 4 b, 0 <= z <= 2 b."""
    mu, nu = check_friction(mu), check_poisson(nu)
    x = np.linspace(-4.0, 4.0, int(grid))
    z = np.linspace(0.0, 2.0, max(int(grid) // 4, 50))
    X, Z = np.meshgrid(x, z)
    s = cylinder_stresses(X, Z, 1.0, 1.0, mu, nu)
    d, t = 0.5 * (s["sxx"] - s["szz"]), s["txz"]
    low, high = 0.0, 1.0 / max(float(np.max(np.abs(t))), 1e-12)
    while high - low > 1e-6 * high:
        mid = 0.5 * (low + high)
        low, high = (mid, high) if _melan_feasible(mid, d, t) else (low, mid)
    return low


# ------------------------------------------------------------------ sphere with friction
# The field of the tangential traction q = mu p0 sqrt(1 - r^2/a^2) in +x is the integral of
# Cerruti's point-force stresses over the Hertz circle. Kernel: Johnson (1985) eq 3.87a-f (a
# force Q = 1 in +x on the surface, at depth z and in-plane offset (X, Y) = field - source); it
# was checked in development against the stresses from Johnson's Cerruti displacements (eq 3.86)
# by finite differences (agreement 1e-9). Hamilton's (1983) explicit equations for this part
# were not obtained from a reliable source, so the integral is evaluated numerically.
#: quadrature sizes (angle about the point's projection, and along each ray)
SPH_N_THETA, SPH_N_RAY = 64, 48


def _cerruti(X, Y, z, nu):
    """Johnson (1985) eq 3.87: stresses per unit tangential point force in +x (tension +)."""
    R2 = X * X + Y * Y + z * z
    R = np.sqrt(R2)
    k = 1.0 / (2.0 * math.pi * R2 * R)
    c = (1.0 - 2.0 * nu) / (R + z) ** 2
    w = 2.0 * R / (R + z)
    return {"sxx": k * X * (-3.0 * X * X / R2 + c * (R2 - Y * Y * (1.0 + w))),
            "syy": k * X * (-3.0 * Y * Y / R2 + c * (3.0 * R2 - X * X * (1.0 + w))),
            "szz": -3.0 * k * X * z * z / R2,
            "sxy": k * Y * (-3.0 * X * X / R2 + c * (X * X * (1.0 + w) - R2)),
            "syz": -3.0 * k * X * Y * z / R2,
            "txz": -3.0 * k * X * X * z / R2}


def _theta_nodes(x, y, n):
    """Angles about (x, y) covering the unit disc, and their weights, shape (npts, n).

    Inside the disc: the full circle, trapezoid rule (periodic integrand). Outside: the cone of
    half-angle asin(1/r) towards the centre, Gauss-Legendre (the integrand is smooth in it)."""
    r = np.hypot(x, y)
    inside = r < 1.0
    t, w = np.polynomial.legendre.leggauss(n)
    alpha = np.arcsin(np.minimum(1.0, 1.0 / np.where(inside, 1.0, r)))[:, None]
    tc = np.arctan2(-y, -x)[:, None]
    th = np.where(inside[:, None], 2.0 * math.pi * np.arange(n) / n, tc + alpha * t)
    wt = np.where(inside[:, None], 2.0 * math.pi / n, alpha * w)
    return th, wt


def _tangential_sub(x, y, z, nu, n_theta, n_ray):
    """Tangential-traction stresses (units q0 = 1, a = 1) at points with z > 0 (1-D arrays).

    Polar coordinates centred on the point's projection; along each ray rho = z sinh(u) removes
    the 1/rho^2 peak of the kernel (rho drho / (rho^2 + z^2) = tanh(u) du), and a sine map in u
    absorbs the square-root ends of q on the rim."""
    th, wt = _theta_nodes(x, y, n_theta)
    ct, st = np.cos(th), np.sin(th)
    c = -(x[:, None] * ct + y[:, None] * st)                 # chord centre along the ray
    h2 = c * c - (x * x + y * y)[:, None] + 1.0
    h = np.sqrt(np.maximum(h2, 0.0))
    zz = z[:, None]
    r1 = np.maximum(c - h, 0.0)
    r2 = np.maximum(c + h, 0.0)
    u1, u2 = np.arcsinh(r1 / zz), np.arcsinh(r2 / zz)
    s, ws = np.polynomial.legendre.leggauss(n_ray)
    phi = 0.5 * math.pi * s
    um, hu = 0.5 * (u1 + u2), 0.5 * (u2 - u1)
    u = um[..., None] + hu[..., None] * np.sin(phi)
    rho = zz[..., None] * np.sinh(u)
    q = np.sqrt(np.maximum(h2[..., None] - (rho - c[..., None]) ** 2, 0.0))
    jac = (hu[..., None] * np.cos(phi) * (0.5 * math.pi) * ws) * zz[..., None] * np.cosh(u) * rho
    wgt = q * jac * wt[..., None]
    K = _cerruti(-rho * ct[..., None], -rho * st[..., None], zz[..., None], nu)
    return {k: np.sum(v * wgt, axis=(1, 2)) for k, v in K.items()}


def _tangential_surface(x, y, nu, n=64):
    """Tangential-traction stresses on z = 0 (units q0 = 1, a = 1), 1-D arrays.

    On the surface the kernel is g(theta)/rho^2 with g odd, so along each line through the point
    the radial integral is the finite Hilbert transform of the semi-ellipse q, in closed form:
    PV int q/rho drho = pi (c - sign(c) sqrt(r^2 - 1)) (the root only outside the disc), where c
    is the chord's centre. Plus the local value txz = -q (the traction itself)."""
    r2 = x * x + y * y
    inside = r2 < 1.0
    th_c, wt_c = _theta_nodes(x, y, n)
    th = np.where(inside[:, None], th_c / 2.0, th_c)          # a line covers theta and theta + pi
    wt = np.where(inside[:, None], wt_c / 2.0, wt_c)
    ct, st = np.cos(th), np.sin(th)
    c = -(x[:, None] * ct + y[:, None] * st)
    h2 = c * c - r2[:, None] + 1.0
    J = math.pi * (c - np.sign(c) * np.sqrt(np.maximum(r2 - 1.0, 0.0))[:, None])
    J = np.where(h2 > 0.0, J, 0.0)
    K = _cerruti(-ct, -st, np.zeros_like(ct), nu)
    out = {k: np.sum(v * J * wt, axis=1) for k, v in K.items()}
    out["szz"] = np.zeros_like(x)
    out["syz"] = np.zeros_like(x)
    out["txz"] = -np.sqrt(np.maximum(1.0 - r2, 0.0))
    return out


def sphere_tangential_stresses(x, y, z, a, q0, nu, n_theta=SPH_N_THETA, n_ray=SPH_N_RAY,
                               chunk=256) -> dict[str, np.ndarray]:
    """All six stresses (Pa) under the traction q = q0 sqrt(1 - r^2/a^2) in +x on the circle r < a.

    x, y, z and a in m, q0 in Pa. Numerical integration of Cerruti's point-force stresses
    (Johnson 1985 eq 3.87; see `_tangential_sub`); on z = 0 a
    closed-form radial integral (`_tangential_surface`). Accuracy: see docs/sliding.md."""
    a = _length("a", a)
    q0 = check_real("q0", q0, low=0.0, high=1e14, unit="Pa")
    nu = check_poisson(nu)
    x, y, z = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float), _depth(z))
    shape = x.shape
    xf, yf, zf = (v.ravel() / a for v in (x, y, z))
    out = {k: np.zeros(xf.size) for k in ("sxx", "syy", "szz", "sxy", "syz", "txz")}
    surf = zf == 0.0
    if np.any(surf):
        s = _tangential_surface(xf[surf], yf[surf], nu)
        for k in out:
            out[k][surf] = s[k]
    idx = np.flatnonzero(~surf)
    for i in range(0, idx.size, chunk):
        j = idx[i:i + chunk]
        s = _tangential_sub(xf[j], yf[j], zf[j], nu, n_theta, n_ray)
        for k in out:
            out[k][j] = s[k]
    return {k: q0 * v.reshape(shape) for k, v in out.items()}


def sphere_stresses(x, y, z, a, p0, mu, nu) -> dict[str, np.ndarray]:
    """All six stresses (Pa) under a sliding sphere: Hertz pressure plus q = mu p in +x.

    mu = 0 returns `sphere_normal_stresses` exactly."""
    mu = check_friction(mu)
    s = sphere_normal_stresses(x, y, z, a, p0, nu)
    if mu == 0.0:
        return s
    t = sphere_tangential_stresses(x, y, z, a, mu * p0, nu)
    return {k: s[k] + t[k] for k in s}


def _sph_measure(criterion):
    if criterion == "von_mises":
        return von_mises
    if criterion == "tresca":
        return max_shear
    raise InputError(f"criterion = {criterion!r} is not one of 'von_mises', 'tresca'")


def _sph_peaks(nu, mu, measure=von_mises):
    """(largest value on z = 0, x, y) and (largest below, x, y, z), units a and p0; y >= 0 by
    the symmetry y -> -y. A grid search, then Nelder-Mead from its best point."""
    def f(v, z=None):
        zz = v[2] if z is None else z
        if zz < 0 or abs(v[0]) > 1.6 or not 0 <= v[1] <= 1.6 or (z is None and zz < Z_MIN):
            return 1e3
        return -float(measure(sphere_stresses(v[0], v[1], zz, 1.0, 1.0, mu, nu)))

    X, Y = np.meshgrid(np.linspace(-1.5, 1.5, 61), np.linspace(0.0, 1.2, 25))
    V = measure(sphere_stresses(X, Y, 0.0, 1.0, 1.0, mu, nu))
    j = np.unravel_index(int(np.argmax(V)), V.shape)
    opts = {"xatol": 1e-7, "fatol": 1e-12, "maxiter": 4000}
    r = optimize.minimize(lambda v: f(v, 0.0), [X[j], Y[j]], method="Nelder-Mead", options=opts)
    surf = (float(-r.fun), float(r.x[0]), float(abs(r.x[1])))
    X, Y, Z = np.meshgrid(np.linspace(-1.2, 1.2, 25), np.linspace(0.0, 1.0, 6),
                          np.linspace(Z_MIN, 1.0, 23), indexing="ij")
    V = measure(sphere_stresses(X, Y, Z, 1.0, 1.0, mu, nu))
    j = np.unravel_index(int(np.argmax(V)), V.shape)
    r = optimize.minimize(f, [X[j], Y[j], Z[j]], method="Nelder-Mead", options=opts)
    sub = (float(-r.fun), float(r.x[0]), float(abs(r.x[1])), float(r.x[2]))
    return surf, sub


def sphere_sliding(P, R, E, nu, mu, sigma_y=None, E_s=None, nu_s=None) -> SlidingResult:
    """Sliding sphere (radius R, load P, friction mu) on a half-space (E, nu).

    tensile_max is the surface sigma_xx at the trailing edge (x = -a, y = 0), the largest
    surface tension: p0 ((1 - 2nu)/3 + (4 + nu) pi mu / 8) (Hamilton 1983)."""
    E_star = effective_modulus(E, nu, E_s, nu_s)
    nu, mu = check_poisson(nu), check_friction(mu)
    a, p0 = hertz_sphere(P, R, E_star)
    if sigma_y is not None:
        sigma_y = check_real("sigma_y", sigma_y, low=0.0, high=1e12, low_open=True, unit="Pa")
    (vs, xs, ys), (vi, xi, yi, zi) = _sph_peaks(nu, mu)
    surface = vs >= vi
    vm, xm, ym, zm = (vs, xs, ys, 0.0) if surface else (vi, xi, yi, zi)
    tens = float(sphere_stresses(-1.0, 0.0, 0.0, 1.0, 1.0, mu, nu)["sxx"])
    return SlidingResult(a, p0, vm * p0, xm * a, zm * a,
                         None if sigma_y is None else vm * p0 / sigma_y, tens * p0, surface,
                         ym * a)


def sphere_surface_yield_friction(nu, criterion="von_mises") -> float:
    """Friction mu at which the largest von Mises (or Tresca) stress of a sliding sphere moves
    to the surface."""
    nu = check_poisson(nu)
    measure = _sph_measure(criterion)

    def gap(mu):
        (vs, _, _), (vi, _, _, _) = _sph_peaks(nu, mu, measure)
        return vs - vi

    return float(optimize.brentq(gap, 0.1, 0.6, xtol=1e-5))
