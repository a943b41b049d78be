"""Normal impact of a finite cylinder (radius R, length L, axis parallel to the surface: the
edge of a slider) of mass m at speed V on a homogeneous or layered half-space.

Line contact per unit length, P' = P/L, end effects neglected (plane strain over the whole
length L; the ends perturb the pressure within about b of each end, which is small for
L >> b). Equations: docs/physics.md section 6; Johnson, Contact Mechanics (1985), section 5.6
for the elastic line contact, Green (2005) for first yield. Every law is written in the contact
half-width b, which makes the elastic approach explicit:

- Elastic [C2]: P' = pi E* b^2/(4R), delta = (b^2/(2R)) (ln(2d/b) - nu/(2(1-nu))). The
  approach is measured from a datum at depth d below the surface: a line load on a half-space
  has no finite approach without one. ``datum_depth`` sets d; the default d = L takes the depth
  where a contact of finite length L stops looking two-dimensional. Changing d by a factor k
  shifts delta by (b^2/(2R)) ln k at equal load (docs/physics.md section 6).
- First yield [C2]: p0 = E* b/(2R) = C(nu) sigma_Y with Green's plane-strain von Mises fit
  C = 1.164 + 2.975 nu - 2.906 nu^2 (1.795 at nu = 0.3; yield below the surface), or
  C = 1/(1 - 2 nu) where the surface yields first (nu below about 0.19).
- Beyond first yield [R]: the plastic zone stays contained below the surface and the load
  follows the elastic law until the elastic mean pressure (pi/4) p0 reaches the fully plastic
  value p_fp = (2 + pi) sigma_Y/sqrt(3) = 2.97 sigma_Y (slip-line field of a flat punch,
  Johnson 1985 section 6.3); from there the mean pressure stays at p_fp, P' = 2 b p_fp, with b
  and delta still related by the elastic law (a Thornton-type cap on the mean pressure). On a
  uniform target the cap starts at b = (4/pi) (p_fp/(C sigma_Y)) b_Y = 2.1 b_Y (nu = 0.3).
- Unloading [R]: from the capped branch, elastic with the logarithmic law around the crater
  radius R_new = pi E* b_max^2/(4 P'_max) = R at the cap's start, so that the residual depth
  grows continuously from 0; the residual depth is delta_max minus the elastic recovery. From
  the elastic branches the contact unloads along its loading curve. e_y = sqrt(W_unload/W_load).

Layered targets use the same depth profiles as the sphere [R]: properties are read at the
sphere approach with the same contact half-width, delta_s = b^2/R (a = b for the stack
weights). The impactor's compliance enters through E* only.

Three solution paths, which must agree: `CylinderImpactModel.maxima` (the fast path,
vectorised over arrays of V, R and m, `cylinder_fast`: energy quadrature
m V^2/2 = integral_0^delta_max P d(delta) on Gauss-Legendre work tables, times by fixed-node
quadrature of d(delta)/v), `CylinderImpactModel.maxima_adaptive` (the same balance, one
impact, by adaptive quadrature and brentq: the reference of the fast path) and
`CylinderImpactModel.history` (solve_ivp with terminal directional events, and sampled
histories). SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.materials import ElasticPlastic, reduced_modulus
from filmscale.core.checks import (DENSITY_MIN, MASS_RANGE, RADIUS_RANGE, VELOCITY_RANGE,
                                   check_real)
from filmscale.core.errors import InputError, ModelRangeError

from .events import Event, HistoryOptions, PiecewiseRun, check_history_options
from .profiles import DepthProfile, checked_bodies
from .quadrature import integrate
from .results import CylinderImpactHistory, CylinderImpactResult

#: p_fp / sigma_Y for a fully plastic line contact: (2 + pi) k with von Mises k = sigma_Y/sqrt(3)
FULLY_PLASTIC_FACTOR = (2.0 + math.pi) / math.sqrt(3.0)
#: the logarithmic law needs b << d: contacts wider than d/5 are out of range
WIDTH_LIMIT = 0.2
REGIME_NAMES = ("elastic", "contained plastic", "fully plastic")
_QUAD = dict(epsabs=0.0, epsrel=1e-12, limit=200)
_OCTAVES = 60     # work quadrature pieces: b_hi x (1, 1/2, ..., 2^-60), then to b_lo


def cylinder_yield_factor(nu):
    """C(nu) = p0/sigma_Y at first yield of a plane-strain line contact (von Mises): the
    smaller of Green's (2005) fit 1.164 + 2.975 nu - 2.906 nu^2 for yield below the surface
    and 1/(1 - 2 nu) for yield at the surface, which comes first for nu below about 0.19.
    Within 0.15 % of the exact on-axis value for nu in [0, 0.5]."""
    nu = np.asarray(nu, dtype=float)
    with np.errstate(divide="ignore"):
        surface = 1.0 / (1.0 - 2.0 * nu)      # inf at nu = 0.5
    return np.minimum(1.164 + 2.975 * nu - 2.906 * nu * nu, surface)


def poisson_term(nu):
    """kappa = nu/(2(1 - nu)), the Poisson ratio's term of the line approach."""
    return nu / (2.0 * (1.0 - nu))


def line_approach(b, R, datum, nu):
    """Elastic approach (m) of a line contact of half-width b (m) on a cylinder of radius R
    (m), measured from the datum depth d (m): (b^2/(2R)) (ln(2d/b) - nu/(2(1-nu)))
    (Johnson 1985, section 5.6; docs/physics.md section 6)."""
    b = np.asarray(b, dtype=float)
    safe = np.where(b > 0, b, 1.0)
    return np.where(b > 0, safe * safe / (2.0 * R)
                    * (np.log(2.0 * datum / safe) - poisson_term(nu)), 0.0)


def line_load(b, R, E_star):
    """Elastic load per unit length (N/m) at half-width b (m) on radius R (m), E* (Pa):
    P' = pi E* b^2/(4R) (Johnson 1985, eq. 4.43)."""
    return np.pi * E_star * np.asarray(b, dtype=float) ** 2 / (4.0 * R)


def line_work(b, R, E_star, datum, nu):
    """Elastic work per unit length (J/m) of loading to half-width b, integral P' d(delta):
    pi E* b^4/(16 R^2) (ln(2d/b) - nu/(2(1-nu)) - 1/4), for constant E* and nu: `line_load`
    integrated by parts against `line_approach` (docs/physics.md section 6)."""
    b = np.asarray(b, dtype=float)
    safe = np.where(b > 0, b, 1.0)
    return np.where(b > 0, np.pi * E_star * safe**4 / (16.0 * R * R)
                    * (np.log(2.0 * datum / safe) - poisson_term(nu) - 0.25), 0.0)


def line_half_width(delta, R, datum, nu):
    """Inverse of `line_approach` for constant nu, by the Lambert W function: with
    u = ln(2d/b) - kappa, u exp(-2u) = delta R exp(2 kappa)/(2 d^2) on the branch u > 1/2."""
    # function-level scipy imports keep the command line's start-up fast (docs/architecture.md)
    from scipy.special import lambertw
    delta = np.asarray(delta, dtype=float)
    z = np.maximum(delta, 0.0) * R * np.exp(2.0 * poisson_term(nu)) / (2.0 * datum * datum)
    with np.errstate(divide="ignore"):
        u = -0.5 * lambertw(-2.0 * z, k=-1).real
    return np.where(delta > 0, 2.0 * datum * np.exp(-poisson_term(nu) - u), 0.0)


def range_message(V, R, m, b_limit, datum) -> str:
    """Why an impact is out of the line-contact laws' range (b_limit = min(R, d/5))."""
    return (f"cylinder impact at V = {V:.6g} m/s, R = {R:.6g} m, m = {m:.6g} kg needs a "
            f"contact half-width above {b_limit:.6g} m = min(R, {WIDTH_LIMIT:g} d), where "
            f"the line-contact laws stop holding (d = {datum:.6g} m)")


def end_effect_warnings(length, b_max) -> tuple[str, ...]:
    """The warning of a contact length below 10 half-widths (end effects not small)."""
    if length < 10.0 * b_max:
        return (f"contact length L = {length:.4g} m is below 10 contact half-widths "
                f"({b_max:.4g} m): end effects are no longer small",)
    return ()


def check_cylinder_mass(radius, length, mass, names=("radius", "length", "mass")) -> float:
    """The moving mass must at least be that of the cylinder itself at DENSITY_MIN:
    m / (pi R^2 L) >= DENSITY_MIN (kg/m^3); InputError naming the keys otherwise."""
    density = mass / (math.pi * radius * radius * length)
    if density < DENSITY_MIN:
        raise InputError(f"{names[2]} = {mass:.6g} kg is lighter than a cylinder of "
                         f"{names[0]} = {radius:.6g} m and {names[1]} = {length:.6g} m at "
                         f"{DENSITY_MIN:g} kg/m^3 (m/(pi R^2 L) = {density:.3g} kg/m^3): "
                         f"check the units")
    return density


@dataclass(frozen=True)
class CylinderBreakpoints:
    """Per-radius breakpoints, as elastic half-widths b (m): first yield, the fully plastic
    cap, the range limit; inf where not reached before the limit."""

    b_yield: float
    b_plastic: float
    b_limit: float


@dataclass(frozen=True)
class CylinderImpactModel:
    """A target, a contact length and an impactor material (None: rigid).

    Parameters
    ----------
    target : DepthProfile, LayerStack or ElasticPlastic
        What is hit.
    length : float
        L, length of the line contact, m.
    impactor : ElasticPlastic or None
        Elastic impactor material, entering the reduced modulus; None for a rigid cylinder.
    datum_depth : float or None
        d, depth (m) of the datum of the approach; None: d = L.
    """

    target: DepthProfile
    length: float
    impactor: ElasticPlastic | None = None
    datum_depth: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "target", checked_bodies(self.target, self.impactor))
        length = check_real("length", self.length, low=RADIUS_RANGE[0], high=RADIUS_RANGE[1],
                            low_open=True, unit="m")
        object.__setattr__(self, "length", length)
        datum = length if self.datum_depth is None else self.datum_depth
        object.__setattr__(self, "datum_depth", check_real(
            "datum_depth", datum, low=0.0, high=math.inf, low_open=True, high_open=True,
            unit="m"))

    def describe(self) -> dict:
        """Plain description for provenance."""
        imp = self.impactor
        return {"shape": "cylinder", "target": self.target.describe(), "length": self.length,
                "datum_depth": self.datum_depth,
                "impactor": None if imp is None else {"E": imp.E, "nu": imp.nu},
                "plastic_law": "mean pressure capped at (2 + pi) sigma_Y/sqrt(3)"}

    # --- local physics ---------------------------------------------------------------------

    def properties(self, b, R):
        """(E*, sigma_Y, nu) felt by a contact of half-width b (m), read at delta_s = b^2/R."""
        b = np.asarray(b, dtype=float)
        e_p, sigma_y, nu = self.target.properties(b * b / R, R)
        return reduced_modulus(e_p, self.impactor), sigma_y, nu

    def approach(self, b, R):
        """Approach (m) at half-width b (m), loading and unloading alike."""
        return line_approach(b, R, self.datum_depth, self.properties(b, R)[2])

    def half_width(self, delta, R, tables: CylinderBreakpoints):
        """Half-width (m) at approach delta (m): Lambert W for a uniform target, else a
        bracketing root in ln b."""
        if self.target.uniform:
            return float(line_half_width(delta, R, self.datum_depth,
                                         float(self.properties(0.0, R)[2])))
        if delta <= 0:
            return 0.0
        return _solve_increasing(lambda b: float(self.approach(b, R)) - delta, tables.b_limit)

    def line_load(self, b, R, tables: CylinderBreakpoints):
        """Loading P' (N/m) at half-width b (m): elastic, capped at 2 b p_fp past the cap."""
        b = np.asarray(b, dtype=float)
        e_star, sigma_y, _ = self.properties(b, R)
        with np.errstate(invalid="ignore"):     # 0 x inf: the cap of a target that never yields
            return np.where(b < tables.b_plastic, line_load(b, R, e_star),
                            2.0 * b * FULLY_PLASTIC_FACTOR * sigma_y)[()]

    def approach_slope(self, b, R, nu=None):
        """d(delta)/db (b > 0), m/m; nu's change with b (layered targets) by central
        differences. ``nu``: the Poisson ratio at b where the caller has it."""
        b = np.asarray(b, dtype=float)
        nu = self.properties(b, R)[2] if nu is None else nu
        out = b / R * (np.log(2.0 * self.datum_depth / b) - poisson_term(nu) - 0.5)
        if not self.target.uniform:
            h = 1e-5
            k_hi, k_lo = (poisson_term(self.properties(b * (1 + s * h), R)[2]) for s in (1, -1))
            out = out - b * b / (2.0 * R) * (k_hi - k_lo) / (2.0 * b * h)
        return out[()]

    def work(self, b_lo, b_hi, R, tables: CylinderBreakpoints):
        """Loading work per unit length (J/m) from half-width b_lo to b_hi: the elastic part
        in closed form for a uniform target, else by Gauss-Legendre quadrature on geometric
        pieces; split at the cap."""
        cut = min(max(tables.b_plastic, b_lo), b_hi)
        if b_lo < cut < b_hi:
            return self.work(b_lo, cut, R, tables) + self.work(cut, b_hi, R, tables)
        if self.target.uniform:
            e_star, sigma_y, nu = (float(p) for p in self.properties(0.0, R))
            d = self.datum_depth
            if b_hi <= tables.b_plastic:
                return float(line_work(b_hi, R, e_star, d, nu)
                             - line_work(b_lo, R, e_star, d, nu))
            # integral of 2 s p_fp (s/R)(ln(2d/s) - kappa - 1/2) ds
            return float(np.diff(2.0 * FULLY_PLASTIC_FACTOR * sigma_y / (3.0 * R)
                                 * np.array([b_lo, b_hi])**3
                                 * (np.log(2.0 * d / np.array([b_lo, b_hi])) - poisson_term(nu)
                                    - 1.0 / 6.0))[0])
        # pieces spanning a factor 2 at most, cut at the profile's kinks (depth delta_s =
        # b^2/R), keep the integrand smooth in each
        inner = np.concatenate([b_hi * 2.0 ** -np.arange(_OCTAVES + 1.0),
                                np.sqrt(R * self.target.knots())])
        edges = np.unique(np.concatenate([[b_lo], np.clip(inner, b_lo, b_hi)]))
        return float(np.sum(integrate(lambda s: self.line_load(s, R, tables)
                                      * self.approach_slope(s, R), edges[:-1], edges[1:], n=16)))

    # --- breakpoints -----------------------------------------------------------------------

    def tables(self, R) -> CylinderBreakpoints:
        """First yield and the fully plastic cap for a cylinder of radius R (m)."""
        b_limit = min(R, WIDTH_LIMIT * self.datum_depth)

        def severity(b, level):
            e_star, sigma_y, nu = self.properties(b, R)
            p0 = e_star * b / (2.0 * R)
            return (p0 / (level(nu) * sigma_y) - 1.0)[()]

        b_y = _first_root(lambda b: severity(b, cylinder_yield_factor), b_limit)
        # the elastic mean pressure (pi/4) p0 reaches p_fp
        b_p = _first_root(lambda b: severity(b, lambda nu: 4.0 / np.pi * FULLY_PLASTIC_FACTOR),
                          b_limit, start=b_y) if math.isfinite(b_y) else math.inf
        return CylinderBreakpoints(b_y, b_p, b_limit)

    def _range_error(self, V, R, m, tables):
        return ModelRangeError(range_message(V, R, m, tables.b_limit, self.datum_depth))

    def _inputs(self, velocity, radius, mass):
        V = check_real("velocity", velocity, low=0.0, high=VELOCITY_RANGE[1], low_open=True,
                       unit="m/s")
        R = check_real("radius", radius, low=RADIUS_RANGE[0], high=RADIUS_RANGE[1], unit="m")
        m = check_real("mass", mass, low=0.0, high=MASS_RANGE[1], low_open=True, unit="kg")
        check_cylinder_mass(R, self.length, m)
        return V, R, m

    def _unloading(self, b_max, R, tables: CylinderBreakpoints):
        """Elastic unloading around the crater radius R_new = pi E* b_max^2/(4 P'_max), with
        the properties at b_max: (R_new, E*, nu, residual depth, work returned per unit
        length); None from the elastic branches, which unload along their loading curve."""
        if b_max < tables.b_plastic:
            return None
        e_star, _, nu = (float(p) for p in self.properties(b_max, R))
        r_new = math.pi * e_star * b_max**2 / (4.0 * self.line_load(b_max, R, tables))
        recovery = float(line_approach(b_max, r_new, self.datum_depth, nu))
        residual = float(self.approach(b_max, R)) - recovery
        return (r_new, e_star, nu, residual,
                float(line_work(b_max, r_new, e_star, self.datum_depth, nu)))

    def _result(self, V, R, m, b_max, tables, loading_time, unloading_time, rebound, path):
        L = self.length
        p_max = self.line_load(b_max, R, tables)
        w_load = L * self.work(0.0, b_max, R, tables)
        unl = self._unloading(b_max, R, tables)
        residual, w_unl = (0.0, w_load) if unl is None else (unl[3], L * unl[4])
        yield_work = (L * self.work(0.0, tables.b_yield, R, tables)
                      if math.isfinite(tables.b_yield) else math.inf)
        warnings = end_effect_warnings(L, b_max)
        regime = 2 if b_max >= tables.b_plastic else int(b_max >= tables.b_yield)
        return CylinderImpactResult(
            velocity=V, radius=R, length=L, mass=m, datum_depth=self.datum_depth,
            delta_max=float(self.approach(b_max, R)), force_max=L * p_max, line_load_max=p_max,
            mean_pressure_max=p_max / (2.0 * b_max), contact_half_width=b_max,
            contact_time=loading_time + unloading_time, loading_time=loading_time,
            unloading_time=unloading_time, residual_depth=residual, restitution=rebound / V,
            rebound_velocity=rebound, work_loading=w_load, work_unloading=w_unl,
            dissipated=w_load - w_unl, yielded=regime >= 1, regime=REGIME_NAMES[regime],
            yield_approach=(float(self.approach(tables.b_yield, R))
                            if math.isfinite(tables.b_yield) else math.inf),
            yield_velocity=math.sqrt(2.0 * yield_work / m), path=path, warnings=warnings)

    # --- fast path ---------------------------------------------------------------------------

    def maxima(self, velocity, radius, mass, progress=None, nodes: int = 12):
        """Maxima by energy quadrature, vectorised (`cylinder_fast.solve_maxima`).

        Scalars V (m/s), R (m), m (kg) give one `CylinderImpactResult` (ModelRangeError out
        of range); arrays give a `cylinder_fast.CylinderMaxima` over their broadcast shape,
        with NaN and status EXCEEDS_RADIUS where the contact would be wider than
        min(R, d/5). ``nodes`` Gauss nodes per time piece (12: within about 3e-11 of
        `maxima_adaptive`); ``progress(done, total)`` after each block of points.
        """
        from .cylinder_fast import solve_maxima
        if all(np.ndim(x) == 0 for x in (velocity, radius, mass)):
            V, R, m = self._inputs(velocity, radius, mass)
            return solve_maxima(self, V, R, m, nodes).result(())
        return solve_maxima(self, velocity, radius, mass, nodes, progress)

    def maxima_adaptive(self, velocity, radius, mass) -> CylinderImpactResult:
        """One impact by energy quadrature with adaptive quadrature and brentq (about 40 ms
        on a uniform target, 0.2 s on a layered one): the reference of the vectorised
        `maxima`. m V^2/2 = L integral P' d(delta), solved for the largest half-width b_max;
        loading and unloading times by quadrature of d(delta)/v in the variable
        b = b_max (1 - u^2), which removes the square-root singularity at the turning
        point."""
        from scipy.integrate import quad
        V, R, m = self._inputs(velocity, radius, mass)
        tables = self.tables(R)
        L = self.length
        energy = 0.5 * m * V * V / L          # per unit length
        if energy > self.work(0.0, tables.b_limit, R, tables):
            raise self._range_error(V, R, m, tables)
        b_max = _solve_increasing(lambda b: self.work(0.0, b, R, tables) - energy,
                                  tables.b_limit)
        kink = ([math.sqrt(1.0 - tables.b_plastic / b_max)]
                if b_max > tables.b_plastic else None)

        def loading(u):
            # the kinetic energy left at b is the work still to come
            s = b_max * (1.0 - u * u)
            return _turning_integrand(u, b_max, self.approach_slope(s, R),
                                      self.approach_slope(b_max, R),
                                      self.work(s, b_max, R, tables),
                                      self.line_load(b_max, R, tables), 2.0 * L / m)

        t_load = quad(loading, 0.0, 1.0, points=kink, **_QUAD)[0]
        unl = self._unloading(b_max, R, tables)
        if unl is None:
            return self._result(V, R, m, b_max, tables, t_load, t_load, V, "energy-quadrature")
        r_new, e_star, nu, _, w_unl = unl
        d = self.datum_depth

        def slope(s):
            return s / r_new * (math.log(2.0 * d / s) - poisson_term(nu) - 0.5) if s > 0 else 0.0

        def unloading(u):
            s = b_max * (1.0 - u * u)
            left = float(line_work(b_max, r_new, e_star, d, nu)
                         - line_work(s, r_new, e_star, d, nu))
            return _turning_integrand(u, b_max, slope(s), slope(b_max), left,
                                      float(line_load(b_max, r_new, e_star)), 2.0 * L / m)

        t_unload = quad(unloading, 0.0, 1.0, **_QUAD)[0]
        return self._result(V, R, m, b_max, tables, t_load, t_unload,
                            math.sqrt(2.0 * L * w_unl / m), "energy-quadrature")

    # --- time-integrated path ------------------------------------------------------------------

    def history(self, velocity, radius, mass, *, rtol=1e-10, samples=400,
                method="DOP853") -> CylinderImpactHistory:
        """One impact integrated in time: m d2(delta)/dt2 = -L P'(delta) with terminal,
        directional events for maximum approach, the fully plastic cap, the range limit and
        separation (`events`).

        Parameters
        ----------
        velocity, radius, mass : float
            V (m/s), R (m), m (kg).
        rtol : float
            Relative tolerance of the integrator (absolute tolerance 1e-3 rtol on the scaled
            state).
        samples : int
            Points of dense output per phase in the returned histories.
        method : str
            A `scipy.integrate.solve_ivp` method.
        """
        V, R, m = self._inputs(velocity, radius, mass)
        options = check_history_options(rtol, samples, method)
        tables = self.tables(R)
        run = _CylinderIntegration(self, V, R, m, tables, options)
        run.loading()
        b_max = self.half_width(run.pieces.y[0] * run.d_ref, R, tables)
        t_load = run.pieces.t * run.t_ref
        unl = self._unloading(b_max, R, tables)
        residual = 0.0 if unl is None else unl[3]
        width_of, load_of, t_sep, rebound = run.unloading(unl, residual)
        result = self._result(V, R, m, b_max, tables, t_load, t_sep - t_load, rebound,
                              "time-integration")
        time, delta, vel, phase, _ = run.pieces.sample(run.t_ref, run.d_ref, V)
        width, line, branch = run.sampled(delta, phase, width_of, load_of, residual,
                                          REGIME_NAMES.index(result.regime))
        with np.errstate(invalid="ignore", divide="ignore"):
            mean_p = np.where(width > 0, line / (2.0 * width), 0.0)
        return CylinderImpactHistory(
            result=result, time=time, delta=delta, velocity=vel, force=self.length * line,
            contact_half_width=width, mean_pressure=mean_p, branch=branch, phase=phase,
            events=run.events, nfev=sum(p.sol.nfev for p in run.pieces.pieces))


class _CylinderIntegration:
    """One cylinder impact in time: the scales (the elastic impact against the surface's
    properties), the loading law, the pieces and the event times (s)."""

    def __init__(self, model: CylinderImpactModel, V, R, m, tables: CylinderBreakpoints,
                 options: HistoryOptions):
        self.model, self.V, self.R, self.m, self.tables = model, V, R, m, tables
        L, datum = model.length, model.datum_depth
        e0, _, nu0 = (float(p) for p in model.properties(0.0, R))
        energy = 0.5 * m * V * V / L

        def surface_work(b):
            return float(line_work(b, R, e0, datum, nu0))
        b_ref = (_solve_increasing(lambda b: surface_work(b) - energy, tables.b_limit)
                 if surface_work(tables.b_limit) > energy else tables.b_limit)
        self.d_ref = float(line_approach(b_ref, R, datum, nu0))
        self.t_ref, self.accel = self.d_ref / V, self.d_ref * L / (m * V * V)
        self.d_limit = float(model.approach(tables.b_limit, R))
        self.pieces = PiecewiseRun(0.0, np.array([0.0, 1.0]), options)
        self.events = {"contact": 0.0}

    def loading_width(self, delta):
        """Half-width (m) at approach delta (m), held in the laws' range [0, d_limit]."""
        return self.model.half_width(min(max(delta, 0.0), self.d_limit), self.R, self.tables)

    def loading_rhs(self, _, y):
        b = self.loading_width(y[0] * self.d_ref)
        return [y[1], -self.model.line_load(b, self.R, self.tables) * self.accel]

    def loading(self):
        """Loading pieces to the maximum approach: one to the fully plastic cap, whose kink is
        a stop so that no step straddles it, then one to the range limit (ModelRangeError).
        First yield changes no law: a non-terminal event only dates it."""
        model, tables, R = self.model, self.tables, self.R
        limits = [self.d_limit]
        if tables.b_plastic < tables.b_limit:
            limits.insert(0, float(model.approach(tables.b_plastic, R)))
        y_yield = (float(model.approach(tables.b_yield, R)) / self.d_ref
                   if tables.b_yield < tables.b_limit else math.inf)
        for limit in limits:
            y_stop = limit / self.d_ref
            stop = self.pieces.advance(self.loading_rhs, {
                "maximum approach": Event(lambda t, y: y[1], -1),
                "cap or range limit": Event(lambda t, y: y[0] - y_stop, 1),
                "first yield": Event(lambda t, y: y[0] - y_yield, 1, terminal=False)}, phase=1)
            if stop.fired["first yield"].size:
                self.events[f"regime {REGIME_NAMES[1]}"] = float(
                    stop.fired["first yield"][0] * self.t_ref)
            if stop.event == "maximum approach":
                self.events["maximum approach"] = float(stop.t * self.t_ref)
                return
            self.events[f"regime {REGIME_NAMES[2]}"] = float(stop.t * self.t_ref)
        raise model._range_error(self.V, R, self.m, tables)

    def unloading(self, unl, residual):
        """The unloading piece to separation (approach back at the residual depth): along the
        loading curve from the elastic branches (``unl`` None), else by the elastic law
        around the crater radius (`CylinderImpactModel._unloading`). Returns the half-width
        (m) at an array of approaches, the load per unit length (N/m) at half-widths, the
        separation time (s) and the rebound speed (m/s)."""
        model, R, tables = self.model, self.R, self.tables
        if unl is None:
            rhs = self.loading_rhs

            def width_of(delta):
                return np.array([model.half_width(min(x, self.d_limit), R, tables)
                                 for x in delta])

            def load_of(b):
                return model.line_load(b, R, tables)
        else:
            r_new, e_star, nu = unl[:3]

            def width_of(delta):
                return line_half_width(delta - residual, r_new, model.datum_depth, nu)

            def load_of(b):
                return line_load(b, r_new, e_star)

            def rhs(_, y):
                b = float(width_of(y[0] * self.d_ref))
                return [y[1], -float(load_of(b)) * self.accel]
        y_sep = residual / self.d_ref
        stop = self.pieces.advance(rhs, {"separation": Event(lambda t, y: y[0] - y_sep, -1)},
                                   phase=2, stopped="before separation")
        t_sep = stop.t * self.t_ref
        self.events["separation"] = float(t_sep)
        return width_of, load_of, t_sep, -stop.y[1] * self.V

    def sampled(self, delta, phase, width_of, load_of, residual, regime):
        """Half-width (m), load per unit length (N/m) and branch at the samples: the loading
        law's while loading (the branch where b crosses first yield and the cap), the
        unloading's after (the branch at maximum approach, ``regime``)."""
        tables = self.tables
        load = phase == 1
        width = np.empty_like(delta)
        # dense output overshoots the events by round-off: keep delta inside the laws' range
        width[load] = [self.loading_width(x) for x in delta[load]]
        width[~load] = width_of(np.maximum(delta[~load], residual))
        line = np.where(load, self.model.line_load(width, self.R, tables), load_of(width))
        branch = np.where(load, np.where(width >= tables.b_plastic, 2,
                                         (width >= tables.b_yield).astype(int)), regime)
        return width, line, branch


def _turning_integrand(u, b_turn, slope, slope_turn, left, load_turn, scale):
    """d(delta)/v in the variable b = b_turn (1 - u^2): slope 2 b_turn u / sqrt(scale left),
    with ``left`` the work (J/m) still to come before the turning point and scale = 2L/m.
    Below u = 1e-4 the difference ``left`` loses digits: there its expansion
    load_turn slope_turn b_turn u^2 (error O(u^2)) gives the limit value."""
    if u >= 1.0:
        return 0.0
    if u < 1e-4:
        return 2.0 * math.sqrt(slope_turn * b_turn / (scale * load_turn))
    return slope * 2.0 * b_turn * u / math.sqrt(scale * left)


def _first_root(f, hi, start=0.0, per_octave=4, octaves=60):
    """Smallest x in (start, hi] with f(x) >= 0 (f < 0 just before), by a geometric scan
    from hi 2^-octaves (or from start) and brentq; inf if f stays negative. ``f`` takes
    arrays."""
    from scipy.optimize import brentq
    lo = max(start, hi * 2.0**-octaves)
    if lo >= hi:
        return math.inf
    grid = np.geomspace(lo, hi, int(per_octave * math.log2(hi / lo)) + 2)
    above = np.asarray(f(grid)) >= 0
    if not above.any():
        return math.inf
    k = int(np.argmax(above))
    return float(grid[0]) if k == 0 else brentq(f, grid[k - 1], grid[k], xtol=1e-15 * grid[k],
                                                rtol=1e-15)


def _solve_increasing(f, hi):
    """Root of an increasing f on (0, hi] with f(0+) < 0 <= f(hi), bracketed in ln x."""
    from scipy.optimize import brentq
    top = math.log(hi)
    return math.exp(brentq(lambda t: f(math.exp(t)), top - 200.0, top, xtol=1e-15,
                           rtol=1e-15))
