"""Normal impact of a sphere (mass m, radius R, velocity V) on a homogeneous or layered target.

m d2(delta)/dt2 = -P(delta), delta(0) = 0, d(delta)/dt(0) = V (the seed dissertation's
eq. 3.1): loading follows a contact law, unloading is Hertzian from the crater (or another
residual-depth model, see `restitution`). Two solution paths that must agree:

- `ImpactModel.maxima` (fast path, vectorised over arrays of V, R and m): delta_max from the
  energy balance integral_0^delta_max P d(delta) = m V^2 / 2 by safeguarded Newton on a
  Gauss-Legendre quadrature; loading time by quadrature of d(delta)/v(delta) in the variable
  u = sqrt(1 - delta/delta_max), which removes the square-root singularity at delta_max;
  unloading time in closed form (the unloading law is Hertzian).
- `ImpactModel.history` (time-integrated): scipy `solve_ivp` with terminal, directional
  events for contact, regime changes, maximum penetration and separation; full histories.

Every quadrature piece stops at the regime breakpoints (first crossings of the law's
thresholds) and spans at most a factor 2 in delta, so each piece integrates a smooth function.
Units: SI throughout (m, kg, m/s, N, Pa, s, J).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.contact.laws import ContactLaw
from filmscale.continuum.contact.results import (EXCEEDS_RADIUS, OK, STATUS_MESSAGES,
                                                 UNLOADING_INCONSISTENT, UNLOADING_OUT_OF_RANGE,
                                                 ImpactHistory, ImpactMaxima, ImpactResult,
                                                 exceeds_radius_message)
from filmscale.continuum.materials import ElasticPlastic, reduced_modulus
from filmscale.core.checks import (DENSITY_MIN, MASS_RANGE, RADIUS_RANGE, VELOCITY_RANGE,
                                   YIELD_STRAIN_HIGH, check_broadcast, check_choice, check_density,
                                   check_positive_array, check_real, sphere_density)
from filmscale.core.errors import InputError, ModelRangeError

from .blocks import solve_in_blocks
from .brackets import find_maximum, find_root
from .events import (Event, HistoryOptions, PiecewiseRun, Stop, check_history_options,
                     sampled_maximum)
from .hertz import HERTZ_DURATION_FACTOR, elastic_impact
from .profiles import DepthProfile, checked_bodies
from .quadrature import cumulative_matrix_unit, gauss_legendre_unit, integrate
from .restitution import UNLOADING_MODELS, Unloading, unload

_GEOMETRIC_DEPTH = 40  # work tables start at R 2^-40
# loading-time pieces: delta_max x (1, 3/4, 1/2, ..., 2^-5), then to 0. The largest loading-
# time error of 100 x 100 maps (five laws, bare glass and the 4-film disk; reference 20 nodes,
# 14 octaves) is the same to two digits with 5 octaves as with 8 (6e-12 to 2.5e-10, set by
# the rest of the path): deeper octaves only cost time
_TIME_OCTAVES = 5
_SCAN_PER_OCTAVE = 4   # severity scan for breakpoints in depth-dependent targets


@dataclass(frozen=True)
class ImpactModel:
    """A target, a contact law, an impactor material (None: rigid) and an unloading model.

    Parameters
    ----------
    target : DepthProfile, LayerStack or ElasticPlastic
        What is hit; stacks are weighted with `StackProfile`.
    law : ContactLaw
        Loading law (see `contact_laws.contact_law`).
    impactor : ElasticPlastic or None
        Elastic impactor material, entering the reduced modulus; None for a rigid sphere.
    unloading : str
        "auto" (the law's ``default_unloading``) or one of restitution.UNLOADING_MODELS.
    quadrature_nodes : int
        Gauss-Legendre nodes per quadrature piece of the fast path: 12 gives about 1e-11
        relative error, 8 about 2e-8, 6 about 2e-6 (benchmarks/impact_speed_vs_error.py).
    """

    target: DepthProfile
    law: ContactLaw
    impactor: ElasticPlastic | None = None
    unloading: str = "auto"
    quadrature_nodes: int = 12

    def __post_init__(self):
        if (isinstance(self.quadrature_nodes, bool) or int(self.quadrature_nodes) !=
                self.quadrature_nodes or not 4 <= self.quadrature_nodes <= 64):
            raise InputError(f"quadrature_nodes = {self.quadrature_nodes!r} must be an integer "
                             f"in [4, 64]")
        object.__setattr__(self, "target", checked_bodies(self.target, self.impactor))
        if not isinstance(self.law, ContactLaw):
            raise InputError(f"law must be a ContactLaw, got {type(self.law).__name__}")
        check_choice("unloading", self.unloading, ("auto",) + UNLOADING_MODELS)
        if self.unloading == "auto":
            object.__setattr__(self, "unloading", self.law.default_unloading)

    def describe(self) -> dict:
        """Plain description for provenance: target, law, unloading, impactor."""
        imp = self.impactor
        return {"target": self.target.describe(), "law": self.law.describe(),
                "unloading": self.unloading, "quadrature_nodes": self.quadrature_nodes,
                "impactor": None if imp is None else {"E": imp.E, "nu": imp.nu}}

    # --- local physics ---------------------------------------------------------------------

    def properties(self, delta, R):
        """(E*, sigma_y, nu) felt at approach delta by a sphere of radius R."""
        e_p, sigma_y, nu = self.target.properties(delta, R)
        return reduced_modulus(e_p, self.impactor), sigma_y, nu

    def _severity(self, delta, R):
        return self.law.severity(delta, R, *self.properties(delta, R))

    def _force_area(self, delta, R, branch):
        return self.law.force_area(delta, R, *self.properties(delta, R), branch)

    def _force(self, delta, R, branch):
        return self._force_area(delta, R, branch)[0]

    def warnings(self) -> tuple[str, ...]:
        """What the model leaves out for this target, and strengths few solids reach."""
        materials = self.target.materials()
        hardening = [f"{mat.name or 'material'} n={mat.n:g}" for mat in materials if mat.n > 0]
        strong = [f"{mat.name or 'material'} sigma_y/E={mat.sigma_y / mat.E:.2g}"
                  for mat in materials if mat.sigma_y > YIELD_STRAIN_HIGH * mat.E]
        out = ()
        if hardening:
            out += (f"hardening exponents ({', '.join(hardening)}) are ignored: the contact "
                    f"laws are elastic-perfectly plastic",)
        if strong:
            out += (f"yield strains above {YIELD_STRAIN_HIGH:g} ({', '.join(strong)}): only "
                    f"whiskers and nanopillars come near; check the units of sigma_y",)
        return out

    def _geometry_warnings(self, contact_radius, R) -> tuple[str, ...]:
        """A contact radius above R (Kogut-Etsion's A = 2 pi R w, Jackson-Green's area fit far
        past yield) means the law is used beyond its fitted range."""
        with np.errstate(invalid="ignore"):
            wide = int(np.sum(np.asarray(contact_radius) > np.asarray(R)))
        if not wide:
            return ()
        return (f"{self.law.name} gives a contact radius larger than the sphere radius at "
                f"{wide} point(s): the law is used beyond its fitted range there",)

    # --- regime breakpoints -------------------------------------------------------------------

    def breakpoints(self, R) -> np.ndarray:
        """Approach (m) at the first crossing of each threshold for each R (shape R.shape +
        (n_thresholds,)); inf where not reached at delta <= R."""
        R = np.asarray(R, dtype=float)
        thr = np.asarray(self.law.thresholds)
        if self.target.uniform:
            props = [p[..., None] for p in self.properties(np.zeros_like(R), R)]
            bp = self.law.approach_at_severity(thr, R[..., None], *props)
        else:
            bp = self._scan_breakpoints(R.ravel(), thr).reshape(R.shape + thr.shape)
        return np.where(bp <= R[..., None], bp, np.inf)

    def _scan_breakpoints(self, R, thr):
        octaves = 50
        rel = 2.0 ** np.linspace(-octaves, 0.0, octaves * _SCAN_PER_OCTAVE + 1)
        grid = R[:, None] * rel
        sev = self._severity(grid, R[:, None])
        out = np.full((R.size, thr.size), np.inf)
        for k, level in enumerate(thr):
            above = sev >= level
            found = above.any(axis=1)
            if not found.any():
                continue
            idx = np.argmax(above, axis=1)[found]
            rows = np.nonzero(found)[0]
            hi = grid[rows, idx]
            lo = np.where(idx > 0, grid[rows, np.maximum(idx - 1, 0)], 0.0)
            out[rows, k] = find_root(lambda d, r: self._severity(d, r) - level, lo, hi,
                                     args=(R[rows],))
        return out

    # --- fast path ------------------------------------------------------------------------

    def _work_table(self, R, bp):
        """Cumulative loading work at edges from 0 to R for each R (rows)."""
        rel = 2.0 ** -np.arange(_GEOMETRIC_DEPTH, -1, -1.0)
        knots = self.target.knots()
        extra = np.concatenate([np.where(np.isfinite(bp), bp, R[:, None]),
                                np.broadcast_to(np.minimum(knots, R[:, None]),
                                                (R.size, knots.size))], axis=1)
        edges = np.sort(np.concatenate([np.zeros((R.size, 1)), R[:, None] * rel, extra],
                                       axis=1), axis=1)
        branch = np.sum(bp[:, None, :] <= edges[:, :-1, None], axis=-1)
        seg = integrate(lambda d: self._force(d, R[:, None, None], branch[..., None]),
                        edges[:, :-1], edges[:, 1:], n=self.quadrature_nodes)
        work = np.concatenate([np.zeros((R.size, 1)), np.cumsum(seg, axis=1)], axis=1)
        return edges, branch, work

    def _solve_approach(self, energy, R, lo, hi, w_lo, w_hi, branch):
        """delta with W(lo) + integral_lo^delta P = energy, by Newton kept inside [lo, hi].

        Each point stops once its bracket is within a few ulps of delta or its Newton step is
        so small that the next one would be.
        """
        # start from the power law W = W_hi (delta/hi)^p through the piece's ends; the first
        # piece starts at 0 and is Hertzian for every law (p = 5/2)
        with np.errstate(divide="ignore", invalid="ignore"):
            p = np.where(lo > 0, np.log(w_hi / w_lo) / np.log(hi / lo), 2.5)
            x = np.clip(hi * (energy / w_hi) ** (1.0 / p), lo, hi)
        x = np.where(np.isfinite(x), x, 0.5 * (lo + hi))
        a, b = lo.copy(), hi.copy()
        active = np.arange(x.size)
        for _ in range(60):
            r, br, lo_k, xk = R[active], branch[active], lo[active], x[active]
            f = w_lo[active] + integrate(lambda d: self._force(d, r[:, None], br[:, None]),
                                         lo_k, xk, n=self.quadrature_nodes) - energy[active]
            ak = np.where(f <= 0, xk, a[active])
            bk = np.where(f > 0, xk, b[active])
            fp = self._force(xk, r, br)
            with np.errstate(divide="ignore", invalid="ignore"):
                x_new = xk - np.where(fp > 0, f / fp, np.inf)
            newton = (x_new >= ak) & (x_new <= bk)
            x_new = np.where(newton, x_new, 0.5 * (ak + bk))
            a[active], b[active], x[active] = ak, bk, x_new
            # Newton converges quadratically, error_(k+1) ~ (P' delta / 2P) error_k^2 / delta
            # with P' delta / P < 2 for every law: a Newton step below 1e-9 delta leaves
            # x_new within an ulp, with no further evaluation
            step = np.abs(x_new - xk)
            done = (newton & (step <= 1e-9 * np.abs(x_new))) | (bk - ak <= 4e-16 * np.abs(x_new))
            active = active[~done]
            if active.size == 0:
                return x
        raise ModelRangeError(f"maximum approach did not converge at {active.size} points, "
                              f"e.g. R = {R[active[0]]:.6g} m, energy = "
                              f"{energy[active[0]]:.6g} J")

    def maxima(self, velocity, radius, mass, progress=None) -> ImpactMaxima:
        """Maxima of the impacts at every broadcast (V, R, m) by energy quadrature.

        ``progress(done, total)``, if given, is called after each block of points.
        """
        V, R, m = impact_inputs(velocity, radius, mass)
        shape = V.shape
        V, R, m = V.ravel(), R.ravel(), m.ravel()
        energy = 0.5 * m * V**2

        inv, bp_u, edges, branches, work, yield_work_u = self._tables(R)
        bp = bp_u[inv]
        yield_work = yield_work_u[inv]

        status = np.where(energy > work[inv, -1], EXCEEDS_RADIUS, OK)
        ok = np.nonzero(status == OK)[0]
        n_fields = {k: np.full(V.size, np.nan) for k in ImpactMaxima.UNITS}
        n_fields.update(velocity=V, radius=R, mass=m, yield_approach=bp[:, 0],
                        yield_velocity=np.sqrt(2.0 * yield_work / m))
        regime = np.full(V.size, -1)
        yielded = np.zeros(V.size, dtype=bool)

        solve_in_blocks(ok, lambda block: self._fill_maxima(
            block, inv[block], energy, V, R, m, bp, edges, branches, work, n_fields, status,
            regime, yielded), progress)

        return ImpactMaxima(**{k: v.reshape(shape) for k, v in n_fields.items()},
                            yielded=yielded.reshape(shape), regime=regime.reshape(shape),
                            status=status.reshape(shape), regime_names=self.law.regime_names,
                            contact_law=self.law.name, unloading=self.unloading,
                            warnings=self.warnings() + self._geometry_warnings(
                                n_fields["contact_radius_max"], R))

    def _fill_maxima(self, ok, r, energy, V, R, m, bp, edges, branches, work, n_fields,
                     status, regime, yielded):
        """Solve the points ``ok`` (rows ``r`` of the work table) and write their results."""
        e_ok, R_ok, m_ok, V_ok, bp_ok = energy[ok], R[ok], m[ok], V[ok], bp[ok]
        j = np.minimum(np.sum(work[r] <= e_ok[:, None], axis=1) - 1, edges.shape[1] - 2)
        branch = branches[r, j]
        d_max = self._solve_approach(e_ok, R_ok, edges[r, j], edges[r, j + 1],
                                     work[r, j], work[r, j + 1], branch)
        hist = self._loading_history(d_max, R_ok, m_ok, bp_ok, branch)
        estar_max = self.properties(d_max, R_ok)[0]
        unl = unload(self.unloading, delta_max=d_max, force_max=hist["force_end"],
                     area_max=hist["area_end"], E_star=estar_max, R=R_ok,
                     yield_approach=bp_ok[:, 0])
        # an elastic contact unloads along its loading curve: e_y = 1, no crater
        elastic, beyond_fit = _unloading_case(branch < self.law.reversible_branches, unl)
        residual = np.where(elastic, 0.0, np.where(beyond_fit, np.nan, unl.residual_depth))
        e_y = np.where(elastic, 1.0, np.sqrt(np.where(beyond_fit, np.nan, unl.work) / e_ok))
        v_out = e_y * V_ok
        t_unload = np.where(elastic, hist["time"],
                            0.5 * HERTZ_DURATION_FACTOR * unl.elastic_recovery / v_out)
        status[ok] = _impact_status(elastic, beyond_fit, residual, d_max, e_y, 1e-12)
        n_fields["delta_max"][ok] = d_max
        n_fields["force_max"][ok] = hist["force_max"]
        n_fields["mean_pressure_max"][ok] = hist["mean_pressure_max"]
        n_fields["contact_radius_max"][ok] = np.sqrt(hist["area_max"] / np.pi)
        n_fields["loading_time"][ok] = hist["time"]
        n_fields["unloading_time"][ok] = t_unload
        n_fields["contact_time"][ok] = hist["time"] + t_unload
        n_fields["residual_depth"][ok] = residual
        n_fields["restitution"][ok] = e_y
        n_fields["rebound_velocity"][ok] = v_out
        regime[ok] = branch
        yielded[ok] = branch >= 1

    def _loading_history(self, d_max, R, m, bp, branch_end):
        """Loading time and the largest force, area and mean pressure over the loading.

        Pieces in delta end at d_max (3/4, 1/2, 1/4, ... 2^-5) and at the breakpoints below
        d_max; in each, Gauss nodes in u = sqrt(1 - delta/d_max). In u the nearest singularity
        (delta = 0) then lies at least 2.7 half-widths from every piece (Bernstein rho >= 5).
        The energy left, E - W(delta) = integral_delta^d_max P, is accumulated from d_max down
        with the spectral running-integral matrix.
        """
        n = self.quadrature_nodes
        x, w = gauss_legendre_unit(n)
        cum = cumulative_matrix_unit(n)
        geo = d_max[:, None] * np.concatenate([[0.75], 2.0 ** -np.arange(_TIME_OCTAVES + 1)])
        knots = np.broadcast_to(self.target.knots(), (d_max.size, self.target.knots().size))
        cuts = np.concatenate([geo, bp, knots, np.zeros((d_max.size, 1))], axis=1)
        cuts = np.where(cuts <= d_max[:, None], cuts, d_max[:, None])
        u_cuts = np.sqrt(np.clip(1.0 - cuts / d_max[:, None], 0.0, 1.0))
        if not self.law.continuous:
            # a force jump at a breakpoint just below d_max puts a near-singularity at a
            # distance ~u_b from u_b = sqrt(1 - b/d_max): grade the pieces above it by 4
            u_b = np.sqrt(np.clip(1.0 - np.max(np.where(bp < d_max[:, None], bp, 0.0), axis=1)
                                  / d_max, 0.0, 1.0))
            graded = np.minimum(u_b[:, None] * 4.0 ** np.arange(1, 11), 0.5)
            u_cuts = np.concatenate([u_cuts, graded], axis=1)
        u_edges = np.sort(u_cuts, axis=1)
        du = np.diff(u_edges, axis=1)                                  # (N, pieces)
        u = u_edges[:, :-1, None] + du[..., None] * x                  # (N, pieces, n)
        delta = d_max[:, None, None] * (1.0 - u * u)
        # evaluate the law on pieces of nonzero length only (most graded pieces are empty)
        live = du > 0
        d_live = delta[live]                                           # (pieces alive, n)
        rows = np.nonzero(live)[0]
        branch = np.sum(bp[rows][:, None, :] <= d_live[..., None], axis=-1)
        force, area = np.zeros_like(delta), np.zeros_like(delta)
        force[live], area[live] = self._force_area(d_live, R[rows][:, None], branch)
        g = force * 2.0 * d_max[:, None, None] * u                     # dW/du
        piece_total = du * (g @ w)
        start = np.concatenate([np.zeros((d_max.size, 1)), np.cumsum(piece_total, axis=1)[:, :-1]],
                               axis=1)
        remaining = start[..., None] + du[..., None] * np.einsum("ij,npj->npi", cum, g)
        speed = np.sqrt(2.0 * remaining / m[:, None, None])
        dt_du = np.divide(2.0 * d_max[:, None, None] * u, speed, out=np.zeros_like(u),
                          where=speed > 0)       # zero-length pieces have u = speed = 0
        time = np.sum(du * (dt_du @ w), axis=1)

        # candidates for maxima: nodes, both limits at each breakpoint (the law may jump
        # there), and d_max itself
        f_end, a_end = self._force_area(d_max, R, branch_end)
        crossed = bp < d_max[:, None]          # thresholds not crossed have no limits
        bp_in = np.where(crossed, bp, d_max[:, None])
        k = np.arange(bp.shape[1])
        limits = [self._force_area(bp_in, R[:, None], k + side) for side in (0, 1)]
        # nodes of empty pieces are no candidates (NaN depth): as zeros beside a peak they
        # would cut its bracket short
        cand_d = np.concatenate([np.where(live[..., None], delta, np.nan).reshape(d_max.size, -1),
                                 bp_in, bp_in, d_max[:, None]], axis=1)
        cand_f = np.concatenate([force.reshape(d_max.size, -1)]
                                + [np.where(crossed, f, f_end[:, None]) for f, _ in limits]
                                + [f_end[:, None]], axis=1)
        cand_a = np.concatenate([area.reshape(d_max.size, -1)]
                                + [np.where(crossed, a, a_end[:, None]) for _, a in limits]
                                + [a_end[:, None]], axis=1)
        out = {"time": time, "force_end": f_end, "area_end": a_end}
        for key in ("force_max", "area_max", "mean_pressure_max"):
            out[key] = self._refined_max(key, _quantity(key, cand_f, cand_a), cand_d, d_max,
                                         R, bp)
        return out

    def _refined_max(self, key, values, cand_d, d_max, R, bp):
        """Largest value over the candidates; an interior maximum at a Gauss node is refined
        by golden-section search between its neighbours."""
        rows = np.arange(values.shape[0])
        k = np.argmax(values, axis=1)
        best, d_best = values[rows, k], cand_d[rows, k]
        # the nearest candidates on either side (no sort: candidates come in any order)
        below, above = cand_d < d_best[:, None], cand_d > d_best[:, None]
        kl = np.argmax(np.where(below, cand_d, -np.inf), axis=1)
        kr = np.argmin(np.where(above, cand_d, np.inf), axis=1)
        # refine strict interior peaks only: a plateau (fully plastic p_m = H) is exact
        interior = (below.any(axis=1) & above.any(axis=1) & (values[rows, kl] < best)
                    & (values[rows, kr] < best))
        interior &= ~np.any(np.isclose(d_best[:, None],
                                       np.concatenate([bp, d_max[:, None]], axis=1),
                                       rtol=1e-14, atol=0), axis=1)
        rows = np.nonzero(interior)[0]
        if rows.size:
            lo, mid, hi = cand_d[rows, kl[rows]], d_best[rows], cand_d[rows, kr[rows]]
            bp_rows = bp[rows]

            def quantity(d, r, b0):
                branch = np.sum(b0 <= d[..., None], axis=-1)
                return _quantity(key, *self._force_area(d, r, branch))

            # bp rows travel as separate columns so that find_maximum can slice them
            _, refined = find_maximum(
                lambda d, r, *cols: quantity(d, r, np.stack(cols, axis=-1)),
                lo, mid, hi, args=(R[rows], *bp_rows.T))
            best[rows] = np.maximum(best[rows], refined)
        return best

    def _tables(self, R):
        """For the distinct radii in ``R`` (1-D): the index of each R among them, the
        breakpoints, the work table (edges, branches, work) and the work at first yield
        (inf where yield is not reached before delta = R)."""
        r_unique, inv = np.unique(R, return_inverse=True)
        bp = self.breakpoints(r_unique)
        edges, branches, work = self._work_table(r_unique, bp)
        hit = edges == bp[:, :1]          # a finite breakpoint is exactly one of the edges
        yield_work = np.where(hit.any(axis=1),
                              work[np.arange(r_unique.size), np.argmax(hit, axis=1)], np.inf)
        return inv, bp, edges, branches, work, yield_work

    def first_yield(self, radius, mass):
        """(approach, velocity) at first yield for each broadcast (R, m), in m and m/s; inf
        where yield is not reached before delta = R."""
        _, R, m = impact_inputs(1.0, radius, mass)
        inv, bp, _, _, _, yield_work = self._tables(R.ravel())
        approach = bp[:, 0][inv].reshape(R.shape)
        return approach, np.sqrt(2.0 * yield_work[inv].reshape(R.shape) / m)

    # --- time-integrated path ----------------------------------------------------------------

    def history(self, velocity, radius, mass, *, rtol=1e-8, gap=0.0, samples=400,
                method="DOP853") -> ImpactHistory:
        """One impact integrated in time with solve_ivp and events (`events`): a free flight
        to contact, loading pieces that end at the law's regime thresholds and at maximum
        approach, and the unloading to separation.

        Parameters
        ----------
        velocity, radius, mass : float
            V (m/s), R (m), m (kg).
        rtol : float
            Relative tolerance of the integrator (absolute tolerance 1e-3 rtol on the scaled
            state); 1e-8 gives maxima within about 5e-8 (benchmarks/impact_speed_vs_error.py).
        gap : float
            Initial distance to the surface, m: the sphere flies freely until the contact event.
        samples : int
            Points of dense output per phase in the returned histories.
        method : str
            A `scipy.integrate.solve_ivp` method.
        """
        V, R, m = (float(x) for x in impact_inputs(velocity, radius, mass))
        options = check_history_options(rtol, samples, method)
        gap = check_real("gap", gap, low=0.0, high=math.inf, high_open=True, unit="m")
        run = _SphereIntegration(self, V, R, m, options, gap)
        branch, left_limits = run.loading()
        d_max = run.pieces.y[0] * run.d_ref
        f_end, a_end = (float(v) for v in run.force_area(d_max, branch))
        yield_approach, yield_velocity = (float(v) for v in self.first_yield(R, m))
        elastic, beyond_fit, residual, state, e_y, t_sep = run.unloading(
            branch, d_max, f_end, a_end, yield_approach)
        time, delta, vel, phase, branch_arr = run.pieces.sample(run.t_ref, run.d_ref, V)
        force, area = run.sampled_force_area(delta, phase, branch_arr, state)
        maxima = run.loading_maxima(f_end, a_end, left_limits)
        # the integrated rebound speed carries the integrator's error: allow 100 rtol
        status = int(_impact_status(elastic, beyond_fit, residual, d_max, e_y,
                                    100 * options.rtol))
        events, t_sep = run.events, t_sep * run.t_ref
        contact_radius_max = math.sqrt(maxima["area_max"] / math.pi)
        result = ImpactResult(
            velocity=V, radius=R, mass=m, delta_max=d_max, force_max=maxima["force_max"],
            mean_pressure_max=maxima["mean_pressure_max"], contact_radius_max=contact_radius_max,
            contact_time=t_sep - events["contact"],
            loading_time=events["maximum approach"] - events["contact"],
            unloading_time=t_sep - events["maximum approach"],
            residual_depth=residual, restitution=e_y, rebound_velocity=e_y * V,
            yielded=branch >= 1,
            regime=self.law.regime_names[branch], yield_approach=yield_approach,
            yield_velocity=yield_velocity, contact_law=self.law.name, unloading=self.unloading,
            path="time-integration", status=status, message=STATUS_MESSAGES[status],
            warnings=self.warnings() + self._geometry_warnings(contact_radius_max, R))
        return ImpactHistory(result=result, time=time, delta=delta, velocity=vel, force=force,
                             contact_radius=np.sqrt(area / np.pi),
                             mean_pressure=_quantity("mean_pressure_max", force, area),
                             branch=branch_arr, phase=phase, events=events, nfev=run.nfev)


class _SphereIntegration:
    """One sphere impact in time: scales (the Hertz impact on the surface's modulus), the law
    at this R, the pieces, the event times (s) and the count of force evaluations."""

    def __init__(self, model: ImpactModel, V, R, m, options: HistoryOptions, gap):
        self.model, self.law, self.V, self.R, self.m = model, model.law, V, R, m
        self.options, self.nfev = options, 0
        # a uniform target's (E*, sigma_y, nu), read once
        self.surface = (tuple(float(p) for p in model.properties(0.0, R))
                        if model.target.uniform else None)
        self.d_ref = float(elastic_impact(m, R, V, model.properties(0.0, R)[0]).delta_max)
        self.t_ref = self.d_ref / V
        self.accel = self.d_ref / (m * V * V)
        self.pieces = PiecewiseRun(0.0, np.array([-gap / self.d_ref, 1.0]), options)
        if gap > 0:                               # free flight to the contact event
            self.pieces.advance(lambda t, y: [y[1], 0.0],
                                {"contact": Event(lambda t, y: y[0], 1)}, phase=0)
        self.events = {"contact": self.pieces.t * self.t_ref}

    def force_area(self, d, b):
        """(force N, area m^2) of the loading law's branch b at approach d (m)."""
        if self.surface is not None:
            return self.law.force_area(d, self.R, *self.surface, b)
        return self.model._force_area(d, self.R, b)

    def severity(self, y):
        """The law's severity at the scaled state y."""
        if self.surface is not None:
            return float(self.law.severity(self.depth(y), self.R, *self.surface))
        return float(self.model._severity(self.depth(y), self.R))

    def depth(self, y):
        """Approach in m, held in [0, R]: trial steps past R (the terminal event) or before
        contact never reach the law."""
        return min(max(y[0] * self.d_ref, 0.0), self.R)

    def loading(self):
        """Loading pieces from contact to the maximum approach, one per branch of the law:
        each ends at the maximum approach, the next regime threshold or the range limit
        (ModelRangeError). Returns the last branch and (approach m, branch) at each regime
        change."""
        branch, left_limits, names = 0, [], self.law.regime_names
        while True:
            stop = self.pieces.advance(self._loading_rhs(branch), self._loading_events(branch),
                                       phase=1, branch=branch,
                                       adjust=lambda s, b=branch: self._recrossed(s, b))
            if stop.event == "maximum approach":
                break
            if stop.event == "range limit":
                raise ModelRangeError(exceeds_radius_message(self.V, self.R, self.m))
            left_limits.append((self.pieces.y[0] * self.d_ref, branch))
            self.events[f"regime {names[branch + 1]}"] = self.pieces.t * self.t_ref
            branch += 1
        self.events["maximum approach"] = self.pieces.t * self.t_ref
        return branch, left_limits

    def _loading_rhs(self, branch):
        def rhs(_, y):
            self.nfev += 1
            return [y[1], -float(self.force_area(self.depth(y), branch)[0]) * self.accel]
        return rhs

    def _loading_events(self, branch):
        y_limit = self.R / self.d_ref
        events = {"maximum approach": Event(lambda t, y: y[1], -1),
                  "range limit": Event(lambda t, y: y[0] - y_limit, 1)}
        if branch < len(self.law.thresholds):
            level = self.law.thresholds[branch]
            events["regime threshold"] = Event(
                lambda t, y: self.severity(y) - level, 1)
        return events

    def _recrossed(self, stop: Stop, branch) -> Stop:
        """A threshold crossed and left again inside the step holding the maximum shows no
        sign change at the step ends: find it on the dense output and end the piece there."""
        if stop.event != "maximum approach" or branch >= len(self.law.thresholds):
            return stop
        sol, level = stop.sol, self.law.thresholds[branch]

        def above(t):
            return self.severity(sol.sol(t)) - level
        if above(stop.t) >= 0:
            from scipy.optimize import brentq
            t_below = max(t for t in sol.t if t < stop.t and above(t) < 0)
            t_end = brentq(above, t_below, stop.t, xtol=1e-15 * stop.t)
            return stop._replace(event="regime threshold", t=t_end, y=sol.sol(t_end))
        return stop

    def unloading(self, branch, d_max, f_end, a_end, yield_approach):
        """Unloading to separation (approach back at the residual depth): along the loading
        curve from a reversible branch, else by the unloading law; none beyond its fit.
        Returns (elastic, beyond_fit, residual depth m, (force, area) at an approach, e_y,
        scaled separation time)."""
        e_max = float(self.model.properties(d_max, self.R)[0])
        unl = unload(self.model.unloading, delta_max=d_max, force_max=f_end, area_max=a_end,
                     E_star=e_max, R=self.R, yield_approach=yield_approach)
        elastic, beyond_fit = _unloading_case(branch < self.law.reversible_branches, unl)
        if elastic:                               # unload along the loading curve
            residual = 0.0

            def state(d):
                return self.force_area(np.maximum(d, 0.0), branch)
        else:
            residual = math.nan if beyond_fit else float(unl.residual_depth)

            def state(d):
                return (unl.force(d, e_max),
                        np.pi * np.maximum(np.asarray(d) - residual, 0.0) * unl.radius)

        def rhs(_, y):
            self.nfev += 1
            return [y[1], -float(state(y[0] * self.d_ref)[0]) * self.accel]

        e_y = t_sep = math.nan
        if not beyond_fit:                        # else: loading only, as in the fast path
            y_sep = residual / self.d_ref
            stop = self.pieces.advance(rhs, {"separation": Event(lambda t, y: y[0] - y_sep, -1)},
                                       phase=2, branch=branch, stopped="before separation")
            t_sep, e_y = stop.t, -stop.y[1]
            self.events["separation"] = t_sep * self.t_ref
        return elastic, beyond_fit, residual, state, e_y, t_sep

    def sampled_force_area(self, delta, phase, branch, unloading_state):
        """Force (N) and area (m^2) at the samples: the loading law's branch while loading,
        the unloading state while unloading, 0 out of contact."""
        force, area = np.zeros_like(delta), np.zeros_like(delta)
        load = (phase == 1) & (delta > 0)
        for b in np.unique(branch[load]):
            sel = load & (branch == b)
            force[sel], area[sel] = self.force_area(delta[sel], int(b))
        unload_sel = phase == 2
        force[unload_sel], area[unload_sel] = unloading_state(delta[unload_sel])
        return force, area

    def loading_maxima(self, f_end, a_end, left_limits) -> dict:
        """Largest force, area and mean pressure over the loading: at d_max, at both sides of
        each regime change, or at an interior peak of the dense solution (then refined)."""
        keys = ("force_max", "area_max", "mean_pressure_max")
        maxima = {k: max([float(_quantity(k, f_end, a_end))]
                         + [float(_quantity(k, *self.force_area(d, b)))
                            for d, b0 in left_limits for b in (b0, b0 + 1)]) for k in keys}
        for piece in self.pieces.pieces:
            if piece.phase != 1:
                continue
            ts = np.linspace(piece.t_start, piece.t_end, self.options.samples)
            f_s, a_s = self.force_area(np.clip(piece.sol.sol(ts)[0] * self.d_ref, 0.0, self.R),
                                       piece.branch)
            for key in keys:
                def exact(t, key=key, piece=piece):
                    return float(_quantity(key, *self.force_area(self.depth(piece.sol.sol(t)),
                                                                 piece.branch)))
                maxima[key] = sampled_maximum(_quantity(key, f_s, a_s), ts, exact, maxima[key])
        return maxima

def impact_inputs(velocity, radius, mass):
    """Checked, broadcast float arrays (V, R, m) within their valid ranges, each (R, m) of a
    plausible mean density (`check_density`)."""
    V, R, m = check_broadcast(
        velocity=check_positive_array("velocity", velocity, "m/s", *VELOCITY_RANGE),
        radius=check_positive_array("radius", radius, "m", *RADIUS_RANGE),
        mass=check_positive_array("mass", mass, "kg", *MASS_RANGE))
    light = sphere_density(R, m) < DENSITY_MIN
    if np.any(light):
        check_density(float(R[light].flat[0]), float(m[light].flat[0]))
    return V, R, m


def _unloading_case(elastic, unl: Unloading):
    """(elastic, beyond_fit): an elastic contact retraces its loading; a residual-depth fit
    that leaves no elastic recovery is beyond its range (status 3)."""
    return elastic, ~np.asarray(elastic) & (np.asarray(unl.elastic_recovery) <= 0)


def _impact_status(elastic, beyond_fit, residual, d_max, e_y, e_tol):
    """Status codes: OK for elastic contacts; 3 beyond the residual fit; 2 if the unloading
    returns more energy than the loading took (e_y above 1 + e_tol, or a negative crater)."""
    with np.errstate(invalid="ignore"):
        bad = (residual < -1e-12 * d_max) | (e_y > 1.0 + e_tol)
    return np.select([elastic, beyond_fit, bad],
                     [OK, UNLOADING_OUT_OF_RANGE, UNLOADING_INCONSISTENT], OK)


def _quantity(key, force, area):
    """Force, area or mean pressure P/A (0 where A = 0) from arrays of force and area."""
    force, area = np.asarray(force, dtype=float), np.asarray(area, dtype=float)
    if key == "force_max":
        return force
    if key == "area_max":
        return area
    return np.divide(force, area, out=np.zeros(np.broadcast(force, area).shape), where=area > 0)


def solve_impact(target, law, velocity, radius, mass, *, impactor=None, unloading="auto",
                 path="fast", **options) -> ImpactResult:
    """One impact by the fast path (``path="fast"``) or time integration (``"time"``).

    Raises ModelRangeError when the approach would exceed R. See `ImpactModel`.
    """
    check_choice("path", path, ("fast", "time"))
    model = ImpactModel(target, law, impactor, unloading)
    if path == "time":
        return model.history(velocity, radius, mass, **options).result
    return model.maxima(velocity, radius, mass).result(())
