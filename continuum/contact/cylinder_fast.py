"""Vectorised maxima of the finite-cylinder impact: `CylinderImpactModel.maxima` on arrays of
(V, R, m), the fast path of cylinder maps (docs/physics.md section 6).

The energy balance of the adaptive reference (`CylinderImpactModel.maxima_adaptive`),
m V^2/2 = L integral_0^b_max P' d(delta), solved at every point together, as the sphere's
fast path (`impact.ImpactModel.maxima`) does:

- per distinct radius, the breakpoints b_Y and b_fp as half-widths (closed form on a uniform
  target; on a layered one a geometric severity scan, 4 points an octave, and Chandrupatla's
  bracketed root, `brackets.find_root`) and a table of the loading work W(b) at the edges
  b_lim 2^-k (k = 0..60), the breakpoints and the profile's knots: closed form on a uniform
  target, 16-node Gauss-Legendre pieces on a layered one;
- b_max by safeguarded Newton (dW/db = P' d(delta)/db) inside the table's piece that holds
  the energy, on the closed form or on W(lo) plus the Gauss-Legendre integral from lo to b;
- the loading and unloading times as integrals of d(delta)/v in u, b = b_max (1 - u^2) (no
  square-root singularity at the turning point), on pieces ending at b/b_max = 3/4, 1/2, ...,
  2^-_TIME_OCTAVES and at the cap and the knots, ``nodes`` Gauss nodes each; the work still to
  come, whose square root is the speed, is accumulated from the turning point by the spectral
  running-integral matrix (`quadrature.cumulative_matrix_unit`), so no difference of two
  works loses digits near the turning point.

Every step works point by point (element-wise numpy, reductions along each point's own
nodes), so that a point's result does not depend on the other points solved with it: a map
holds the very numbers of single `maxima` calls, except on stacks of several films, whose
profile sums over interfaces by matrix products that round by the array's size (1e-16 in
the properties, 1e-13 in the results). SI units.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from filmscale.core.checks import (DENSITY_MIN, MASS_RANGE, RADIUS_RANGE, VELOCITY_RANGE,
                                   check_broadcast, check_real_array)
from filmscale.core.errors import ModelRangeError

from .blocks import solve_in_blocks
from .brackets import find_root
from .cylinder import (FULLY_PLASTIC_FACTOR, REGIME_NAMES, WIDTH_LIMIT, check_cylinder_mass,
                       cylinder_yield_factor, end_effect_warnings, line_approach, line_load,
                       line_work, poisson_term, range_message)
from .quadrature import cumulative_matrix_unit, gauss_legendre_unit, integrate
from .results import EXCEEDS_RADIUS, OK, CylinderImpactResult

_WORK_OCTAVES = 60      # work table edges b_lim 2^-k, k = 0..60, as the adaptive path's pieces
_WORK_NODES = 16        # Gauss nodes per work piece (layered targets)
_SCAN_PER_OCTAVE = 4    # severity scan of layered targets, as the adaptive path's
# time pieces: b_max x (1, 3/4, 1/2, ..., 2^-_TIME_OCTAVES), then to 0. Near b = 0 the
# integrand goes as b ln b; the last piece holds about 4^-octaves of the time. Largest time
# error over maps of five targets (uniform, layered, measured table) against 24 nodes and 30
# octaves, at 12 nodes: 9e-11 with 8 octaves, 1.5e-11 with 10, 1.2e-11 with 12 or more; at 10
# octaves, 8 nodes: 5e-7, 10: 3e-9, 16: 2e-12
_TIME_OCTAVES = 10
# graded time pieces beside a kink near the turning point: u_c 4^k, k = 1.._GRADED, to 1/2
_GRADED = 6


@dataclass(frozen=True)
class CylinderMaxima:
    """Fast-path results over arrays of (V, R, m); every field has the broadcast shape.

    Points with ``status == EXCEEDS_RADIUS`` (contact wider than min(R, d/5)) hold NaN and
    regime -1. ``result(index)`` gives one point as a `CylinderImpactResult`.
    """

    velocity: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    delta_max: np.ndarray
    force_max: np.ndarray
    line_load_max: np.ndarray
    mean_pressure_max: np.ndarray
    contact_half_width: np.ndarray
    contact_time: np.ndarray
    loading_time: np.ndarray
    unloading_time: np.ndarray
    residual_depth: np.ndarray
    restitution: np.ndarray
    rebound_velocity: np.ndarray
    work_loading: np.ndarray
    work_unloading: np.ndarray
    dissipated: np.ndarray
    yield_approach: np.ndarray
    yield_velocity: np.ndarray
    yielded: np.ndarray
    regime: np.ndarray          #: index into ``regime_names``, -1 out of range
    status: np.ndarray          #: OK or EXCEEDS_RADIUS
    length: float               #: L, m
    datum_depth: float          #: d, m
    regime_names: tuple[str, ...] = REGIME_NAMES

    #: fields holding arrays of floats in SI, with their units
    UNITS: ClassVar[dict] = {
        "velocity": "m/s", "radius": "m", "mass": "kg", "delta_max": "m", "force_max": "N",
        "line_load_max": "N/m", "mean_pressure_max": "Pa", "contact_half_width": "m",
        "contact_time": "s", "loading_time": "s", "unloading_time": "s",
        "residual_depth": "m", "restitution": "1", "rebound_velocity": "m/s",
        "work_loading": "J", "work_unloading": "J", "dissipated": "J", "yield_approach": "m",
        "yield_velocity": "m/s"}

    def result(self, index=()) -> CylinderImpactResult:
        """The single impact at ``index``; ModelRangeError if it was out of range."""
        V, R, m = (float(getattr(self, k)[index]) for k in ("velocity", "radius", "mass"))
        if int(self.status[index]) == EXCEEDS_RADIUS:
            raise ModelRangeError(range_message(V, R, m, min(R, WIDTH_LIMIT * self.datum_depth),
                                                self.datum_depth))
        values = {k: float(getattr(self, k)[index]) for k in self.UNITS}
        return CylinderImpactResult(
            **values, length=self.length, datum_depth=self.datum_depth,
            yielded=bool(self.yielded[index]),
            regime=self.regime_names[int(self.regime[index])], path="energy-quadrature",
            warnings=end_effect_warnings(self.length, values["contact_half_width"]))


def cylinder_inputs(model, velocity, radius, mass):
    """Checked, broadcast float arrays (V, R, m) within the ranges of the scalar path, each
    (R, m) at least as heavy as the cylinder itself (`check_cylinder_mass`)."""
    V, R, m = check_broadcast(
        velocity=check_real_array("velocity", velocity, low=0.0, high=VELOCITY_RANGE[1],
                                  low_open=True, unit="m/s"),
        radius=check_real_array("radius", radius, low=RADIUS_RANGE[0], high=RADIUS_RANGE[1],
                                unit="m"),
        mass=check_real_array("mass", mass, low=0.0, high=MASS_RANGE[1], low_open=True,
                              unit="kg"))
    density = m / (np.pi * R * R * model.length)
    if density.size and float(density.min()) < DENSITY_MIN:
        k = np.unravel_index(np.argmin(density), density.shape)
        check_cylinder_mass(float(R[k]), model.length, float(m[k]))
    return V, R, m


def solve_maxima(model, velocity, radius, mass, nodes: int = 12,
                 progress=None) -> CylinderMaxima:
    """The maxima of ``model`` (a `CylinderImpactModel`) at every broadcast (V, R, m), with
    ``nodes`` Gauss nodes per time piece; ``progress(done, total)`` after each block."""
    V, R, m = cylinder_inputs(model, velocity, radius, mass)
    shape = V.shape
    V, R, m = (np.ascontiguousarray(x, dtype=float).ravel() for x in (V, R, m))
    L = model.length
    energy = 0.5 * m * V * V / L          # per unit length
    tables = _Tables.build(model, R)
    inv = tables.inverse
    status = np.where(energy > tables.work[inv, -1], EXCEEDS_RADIUS, OK)
    fields = {k: np.full(V.size, np.nan) for k in CylinderMaxima.UNITS}
    fields.update(velocity=V, radius=R, mass=m)
    regime = np.full(V.size, -1)
    ok = np.nonzero(status == OK)[0]
    b_y = tables.b_yield[inv[ok]]
    fields["yield_approach"][ok] = np.where(
        np.isfinite(b_y), model.approach(np.where(np.isfinite(b_y), b_y, 1.0), R[ok]), np.inf)
    fields["yield_velocity"][ok] = np.sqrt(2.0 * L * tables.yield_work[inv[ok]] / m[ok])
    solve_in_blocks(ok, lambda block: _solve_block(model, tables, block, energy, V, R, m,
                                                   nodes, fields, regime), progress)
    return CylinderMaxima(**{k: v.reshape(shape) for k, v in fields.items()},
                          yielded=(regime >= 1).reshape(shape), regime=regime.reshape(shape),
                          status=status.reshape(shape), length=L,
                          datum_depth=model.datum_depth)


# --- per-radius tables ----------------------------------------------------------------------

@dataclass(frozen=True)
class _Tables:
    """Breakpoints and the loading work table of each distinct radius (rows)."""

    inverse: np.ndarray         #: row of each point
    radius: np.ndarray          #: (rows,), m
    b_limit: np.ndarray         #: min(R, d/5), m
    b_yield: np.ndarray         #: first yield, m (inf: not before b_limit)
    b_plastic: np.ndarray       #: the fully plastic cap, m (inf: not before b_limit)
    edges: np.ndarray           #: (rows, edges) half-widths, m, from 0 to b_limit
    work: np.ndarray            #: (rows, edges) loading work to each edge, J/m
    yield_work: np.ndarray      #: loading work to first yield, J/m (inf: not reached)

    @classmethod
    def build(cls, model, R) -> _Tables:
        r, inverse = np.unique(R, return_inverse=True)
        b_limit = np.minimum(r, WIDTH_LIMIT * model.datum_depth)
        b_y, b_p = _breakpoints(model, r, b_limit)
        rel = 2.0 ** -np.arange(_WORK_OCTAVES, -1, -1.0)
        extra = np.concatenate([b_y[:, None], b_p[:, None],
                                np.sqrt(r[:, None] * model.target.knots()[None, :])], axis=1)
        extra = np.where(extra <= b_limit[:, None], extra, b_limit[:, None])
        edges = np.sort(np.concatenate([np.zeros((r.size, 1)), b_limit[:, None] * rel, extra],
                                       axis=1), axis=1)
        if model.target.uniform:
            work = _uniform_work(model, edges, r[:, None], b_p[:, None])
            yield_work = np.where(np.isfinite(b_y), _uniform_work(
                model, np.where(np.isfinite(b_y), b_y, 0.0), r, b_p), np.inf)
        else:
            seg = integrate(lambda s: _power(model, s, r[:, None, None], b_p[:, None, None]),
                            edges[:, :-1], edges[:, 1:], n=_WORK_NODES)
            work = np.concatenate([np.zeros((r.size, 1)), np.cumsum(seg, axis=1)], axis=1)
            hit = edges == b_y[:, None]      # a finite b_Y is one of the edges
            yield_work = np.where(hit.any(axis=1),
                                  work[np.arange(r.size), np.argmax(hit, axis=1)], np.inf)
        return cls(inverse.reshape(-1), r, b_limit, b_y, b_p, edges, work, yield_work)


def _breakpoints(model, r, b_limit):
    """(b_Y, b_fp) of each radius: where p0 = E* b/(2R) reaches C(nu) sigma_Y, and where the
    elastic mean pressure (pi/4) p0 reaches the fully plastic (2 + pi) sigma_Y/sqrt(3); inf
    beyond b_limit (the cap only after first yield)."""
    cap = 4.0 / np.pi * FULLY_PLASTIC_FACTOR
    if model.target.uniform:
        e_star, sigma_y, nu = model.properties(np.zeros_like(r), r)
        with np.errstate(invalid="ignore"):     # inf / inf: a target that never yields
            b_y = 2.0 * r * cylinder_yield_factor(nu) * sigma_y / e_star
            b_p = 2.0 * r * cap * sigma_y / e_star
        b_y = np.where(b_y <= b_limit, b_y, np.inf)
        return b_y, np.where(np.isfinite(b_y) & (b_p <= b_limit), b_p, np.inf)

    def severity(level):
        def f(b, R):
            e_star, sigma_y, nu = model.properties(b, R)
            return e_star * b / (2.0 * R) / (level(nu) * sigma_y) - 1.0
        return f

    b_y = _first_root(severity(cylinder_yield_factor), r, b_limit * 2.0 ** -60, b_limit)
    b_p = _first_root(severity(lambda nu: cap), r, b_y, b_limit)
    return b_y, b_p


def _first_root(f, r, lo, hi):
    """Smallest b in (lo, hi] of each row with f(b, R) >= 0 (f < 0 just below), inf where
    none: a geometric scan, _SCAN_PER_OCTAVE points an octave, then find_root."""
    out = np.full(r.shape, np.inf)
    rows = np.nonzero(np.isfinite(lo) & (lo < hi))[0]
    if rows.size == 0:
        return out
    lo, hi, rr = lo[rows], hi[rows], r[rows]
    count = (_SCAN_PER_OCTAVE * np.log2(hi / lo)).astype(int) + 2
    t = np.minimum(np.arange(count.max())[None, :] / (count[:, None] - 1.0), 1.0)
    grid = np.where(t < 1.0, lo[:, None] * np.exp(t * np.log(hi / lo)[:, None]), hi[:, None])
    above = f(grid, rr[:, None]) >= 0
    found = above.any(axis=1)
    k = np.argmax(above, axis=1)
    rows, k, grid, rr = rows[found], k[found], grid[found], rr[found]
    first = k == 0
    out[rows[first]] = grid[first, 0]
    inner = ~first
    if inner.any():
        idx = np.nonzero(inner)[0]
        out[rows[inner]] = find_root(f, grid[idx, k[inner] - 1], grid[idx, k[inner]],
                                     args=(rr[inner],))
    return out


def _load(model, b, R, b_p, props=None):
    """P' (N/m) at half-width b: `CylinderImpactModel.line_load` with the cap ``b_p`` of each
    point; ``props``: (E*, sigma_Y, nu) at b where the caller has them."""
    e_star, sigma_y, _ = model.properties(b, R) if props is None else props
    with np.errstate(invalid="ignore"):     # 0 x inf: the cap of a target that never yields
        return np.where(b < b_p, line_load(b, R, e_star), 2.0 * b * FULLY_PLASTIC_FACTOR * sigma_y)


def _solve_width(excess, power, lo, hi, w_lo, w_hi, args):
    """b in [lo, hi] with excess(b, *args) = W(b) - energy = 0, by Newton (derivative
    power(b, *args) = dW/db > 0) kept inside the bracket, bisection where a step leaves it.

    The start is the power law W = w_hi (b/hi)^p through the piece's ends (p = 4, the
    elastic law's, from b = 0). A point stops once its Newton step is below 1e-9 b: Newton
    converges quadratically, the next error ~ (W''/2W') step^2 ~ 1e-18 b, or once its bracket
    is within a few ulps."""
    energy = args[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(lo > 0, np.log(w_hi / w_lo) / np.log(hi / lo), 4.0)
        x = np.clip(hi * (energy / w_hi) ** (1.0 / p), lo, hi)
    x = np.where(np.isfinite(x), x, 0.5 * (lo + hi))
    a, b = lo.copy(), hi.copy()
    active = np.arange(x.size)
    for _ in range(100):
        sub = tuple(arg[active] for arg in args)
        xk = x[active]
        f = excess(xk, *sub)
        ak = np.where(f <= 0, xk, a[active])
        bk = np.where(f > 0, xk, b[active])
        fp = power(xk, *sub)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_new = xk - np.where(fp > 0, f / fp, np.inf)
        newton = (x_new >= ak) & (x_new <= bk)
        x_new = np.where(newton, x_new, 0.5 * (ak + bk))
        a[active], b[active], x[active] = ak, bk, x_new
        done = ((newton & (np.abs(x_new - xk) <= 1e-9 * x_new))
                | (bk - ak <= 4e-16 * x_new) | (f == 0))
        active = active[~done]
        if active.size == 0:
            return x
    raise ModelRangeError(f"cylinder maximum half-width did not converge at {active.size} "
                          f"points")


def _power_and_slope(model, b, R, b_p):
    """(dW/db = P'(b) d(delta)/db in J/m^2, d(delta)/db) at half-widths b."""
    props = model.properties(b, R)
    slope = model.approach_slope(b, R, props[2])
    return _load(model, b, R, b_p, props) * slope, slope


def _power(model, b, R, b_p):
    """dW/db = P'(b) d(delta)/db, J/m^2."""
    return _power_and_slope(model, b, R, b_p)[0]


def _uniform_work(model, b, R, b_p):
    """Loading work (J/m) to half-width b on a uniform target, closed form: the elastic
    `line_work` to min(b, b_fp), then integral_b_fp^b 2 s p_fp (s/R)(ln(2d/s) - kappa - 1/2)
    ds = [2 p_fp s^3/(3R) (ln(2d/s) - kappa - 1/6)] (as `CylinderImpactModel.work`)."""
    e_star, sigma_y, nu = (np.broadcast_to(p, np.broadcast(b, R).shape)
                           for p in model.properties(np.zeros_like(R), R))
    d = model.datum_depth
    elastic = line_work(np.minimum(b, b_p), R, e_star, d, nu)
    capped = b > b_p
    if not np.any(capped):
        return elastic
    b_hi, b_lo = np.where(capped, b, 1.0), np.where(capped, b_p, 1.0)

    def g(s):
        return (2.0 * FULLY_PLASTIC_FACTOR * sigma_y / (3.0 * R) * s**3
                * (np.log(2.0 * d / s) - poisson_term(nu) - 1.0 / 6.0))
    return np.where(capped, elastic + (g(b_hi) - g(b_lo)), elastic)


# --- per-point solution -----------------------------------------------------------------------

def _solve_block(model, tables, ok, energy, V, R, m, nodes, fields, regime):
    """Solve the points ``ok`` and write their results into ``fields`` and ``regime``."""
    L, d = model.length, model.datum_depth
    row = tables.inverse[ok]
    e_ok, R_ok, m_ok, V_ok = energy[ok], R[ok], m[ok], V[ok]
    b_p, b_y = tables.b_plastic[row], tables.b_yield[row]
    work, edges = tables.work[row], tables.edges[row]
    j = np.clip(np.sum(work <= e_ok[:, None], axis=1) - 1, 0, edges.shape[1] - 2)
    pick = np.arange(ok.size)
    lo, hi, w_lo = edges[pick, j], edges[pick, j + 1], work[pick, j]

    if model.target.uniform:
        def excess(b, e, r, cap, *_):
            return _uniform_work(model, b, r, cap) - e
    else:
        def excess(b, e, r, cap, start, w_start):
            return w_start + integrate(lambda s: _power(model, s, r[:, None], cap[:, None]),
                                       start, b, n=_WORK_NODES) - e
    args = (e_ok, R_ok, b_p, lo, w_lo)
    b_max = _solve_width(excess, lambda b, e, r, cap, *_: _power(model, b, r, cap), lo, hi,
                         w_lo, work[pick, j + 1], args)
    w_load = excess(b_max, *args) + e_ok
    p_max = _load(model, b_max, R_ok, b_p)
    scale = 2.0 * L / m_ok

    # loading time: pieces cut at the cap and the profile's knots below b_max
    knots = np.broadcast_to(np.sqrt(R_ok[:, None] * model.target.knots()[None, :]),
                            (ok.size, model.target.knots().size))
    cuts = np.concatenate([b_p[:, None], knots], axis=1)
    t_load = _turning_time(b_max, cuts, lambda s, k: _power_and_slope(
        model, s, R_ok[k][:, None], b_p[k][:, None]), scale, nodes)

    # unloading from the capped branch: the elastic law around R_new, with the properties at
    # b_max (`CylinderImpactModel._unloading`); from the elastic branches: the loading curve
    capped = b_max >= b_p
    t_unload, rebound = t_load.copy(), V_ok.copy()
    residual, w_unl = np.zeros(ok.size), w_load.copy()
    c = np.nonzero(capped)[0]
    if c.size:
        b_c, R_c = b_max[c], R_ok[c]
        e_star, _, nu = model.properties(b_c, R_c)
        r_new = np.pi * e_star * b_c**2 / (4.0 * p_max[c])
        residual[c] = model.approach(b_c, R_c) - line_approach(b_c, r_new, d, nu)
        w_unl[c] = line_work(b_c, r_new, e_star, d, nu)
        rebound[c] = np.sqrt(2.0 * L * w_unl[c] / m_ok[c])

        def unloading(s, k):
            r_k, e_k, nu_k = r_new[k][:, None], e_star[k][:, None], nu[k][:, None]
            slope = s / r_k * (np.log(2.0 * d / s) - poisson_term(nu_k) - 0.5)
            return line_load(s, r_k, e_k) * slope, slope
        t_unload[c] = _turning_time(b_c, np.empty((c.size, 0)), unloading, scale[c], nodes)

    out = {"delta_max": model.approach(b_max, R_ok), "force_max": L * p_max,
           "line_load_max": p_max, "mean_pressure_max": p_max / (2.0 * b_max),
           "contact_half_width": b_max, "contact_time": t_load + t_unload,
           "loading_time": t_load, "unloading_time": t_unload, "residual_depth": residual,
           "restitution": rebound / V_ok, "rebound_velocity": rebound,
           "work_loading": L * w_load, "work_unloading": L * w_unl,
           "dissipated": L * w_load - L * w_unl}
    for key, value in out.items():
        fields[key][ok] = value
    regime[ok] = np.where(capped, 2, (b_max >= b_y).astype(int))


def _turning_time(b_max, cuts, power_and_slope, scale, n):
    """Time (s) from contact to the turning point b_max (or back): integral of
    d(delta)/v over b in (0, b_max), in u with b = b_max (1 - u^2), where the speed
    v = sqrt(scale (W(b_max) - W(b))) and ``power_and_slope(b, k)`` gives dW/db and
    d(delta)/db at half-widths b (rows: the points ``k``). Pieces end at b/b_max = 3/4,
    1/2, ..., 2^-_TIME_OCTAVES, 0 and at ``cuts`` (m) below b_max, n Gauss nodes each."""
    x, w = gauss_legendre_unit(n)
    cum = cumulative_matrix_unit(n)
    # a kink of the law at u_c (the cap, a knot) leaves the speed's continuation across it
    # a zero about u_c beyond: pieces graded by 4 from the kink nearest the turning point
    # keep that near-singularity 2/3 of a piece's half-length or more away (as the sphere's
    # jumps)
    u_kink = np.sqrt(np.clip(1.0 - cuts / b_max[:, None], 0.0, 1.0))
    u_near = np.min(np.where(u_kink > 0, u_kink, np.inf), axis=1, initial=np.inf)
    graded = np.minimum(u_near[:, None] * 4.0 ** np.arange(1, _GRADED + 1), 0.5)
    geo = b_max[:, None] * np.concatenate([[0.75], 2.0 ** -np.arange(_TIME_OCTAVES + 1.0)])
    cuts = np.concatenate([geo, cuts, np.zeros((b_max.size, 1))], axis=1)
    cuts = np.where(cuts <= b_max[:, None], cuts, b_max[:, None])
    u_edges = np.sort(np.concatenate([np.sqrt(np.clip(1.0 - cuts / b_max[:, None], 0.0, 1.0)),
                                      graded], axis=1), axis=1)
    du = np.diff(u_edges, axis=1)                                   # (N, pieces)
    u = u_edges[:, :-1, None] + du[..., None] * x                   # (N, pieces, n)
    b = b_max[:, None, None] * (1.0 - u * u)
    live = du > 0              # pieces of nonzero length only: cuts at b_max are empty
    rows = np.nonzero(live)[0]
    power, slope = np.zeros_like(u), np.zeros_like(u)
    power[live], slope[live] = power_and_slope(b[live], rows)
    g = power * 2.0 * b_max[:, None, None] * u                      # d(W(b_max) - W(b))/du
    piece = du * np.sum(g * w, axis=-1)
    start = np.concatenate([np.zeros((b_max.size, 1)), np.cumsum(piece, axis=1)[:, :-1]],
                           axis=1)
    left = start[..., None] + du[..., None] * np.einsum("ij,npj->npi", cum, g)
    speed = np.sqrt(scale[:, None, None] * left)
    dt_du = np.divide(slope * 2.0 * b_max[:, None, None] * u, speed, out=np.zeros_like(u),
                      where=speed > 0)
    return np.sum(du * np.sum(dt_du * w, axis=-1), axis=1)

