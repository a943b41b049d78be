"""Oblique impact of a sphere with Coulomb friction, tangential compliance and rotation.

A sphere (mass m, radius R, moment of inertia I = j m R^2) meets the target with normal speed
V and tangential speed V_t = V tan(theta), without spin. Equations: docs/physics.md section 5.

Model (Thornton 1997; Wu, Thornton & Li 2009):

- The normal motion is the scene's normal impact (`ImpactModel`: its contact law, loading and
  unloading), independent of the tangential force. This is the standard decoupling: the normal
  and tangential problems uncouple exactly for similar materials and nearly so otherwise.
- Tangential force: the incremental no-slip Mindlin spring dF_t = k_t du_c, k_t = 8 G* a with
  the contact radius a of the normal law, capped by Coulomb, |F_t| <= mu F_n. Many DEM codes use
  this rule; Di Renzo & Di Maio (2004, Chem. Eng. Sci. 59:525) found it reproduces the
  Maw-Barber-Fawcett solution of the full Mindlin-Deresiewicz problem closely, and for a Hertz
  contact it gives their gross-slip boundary psi_1 = 4 chi - 1 exactly. The load-history rules
  of Thornton & Yin (1991) are not used.
- Sign convention: x along the incident tangential velocity; omega > 0 is forward rolling, so
  the contact point slides at v_c = v_x - R omega; F_t > 0 acts on the sphere along -x:
  m dv_x/dt = -F_t, I d(omega)/dt = R F_t.
- Stick while |F_t| < mu F_n; slip (F_t = +-mu F_n) starts when the spring reaches the cap and
  ends when the cap shrinks faster than the spring would unload, s k_t v_c < mu dF_n/dt.

Two paths:

- ``"fast"``: the normal maxima by energy quadrature (`ImpactModel.maxima`) and the
  tangential results in closed form where one exists: no friction or no tangential speed
  (e_x = 1), or a Hertz (elastic, uniform target) contact that slips throughout
  (psi_1 >= 4 chi - 1): then J_t = mu J_n and e_x = 1 - mu (1 + e_n) / tan(theta). Any other
  impact goes to time integration (``path`` of the result says which was used).
- ``"time"``: the normal history (`ImpactModel.history`) interpolated (PCHIP) in time, and the
  tangential equations integrated with `solve_ivp`, with events for stick-to-slip and
  slip-to-stick.

Units: SI (m, kg, m/s, N, Pa, s), angles in degrees, spin in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator

from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.jsonable import to_jsonable

from .impact import ImpactModel, _impact_inputs
from .impact_map import ImpactMap, impact_map
from .results import ImpactResult

#: moment of inertia of a solid sphere in units of m R^2
SOLID_SPHERE = 0.4
REGIMES = ("stick", "slip", "stick-slip")
_MAX_SWITCHES = 1000    # stick/slip changes per impact; a few in practice


@dataclass(frozen=True)
class ObliqueResult:
    """One oblique impact; SI units, angles in degrees.

    Velocities after the impact are at separation; the sphere arrives without spin.
    """

    normal: ImpactResult                #: the normal impact (independent of friction)
    angle: float                        #: theta, incidence angle from the normal, degrees
    friction: float                     #: mu, Coulomb friction coefficient
    inertia_factor: float               #: j = I / (m R^2)
    tangential_velocity: float          #: V_t = V tan(theta), incident, m/s
    restitution_tangential: float       #: e_x = v_x' / V_t (centre); NaN when V_t = 0
    restitution_contact_point: float    #: e_c = v_c' / v_c (contact point); NaN when V_t = 0
    impulse_ratio: float                #: f = J_t / J_n = (1 - e_x) tan(theta) / (1 + e_n)
    rebound_angle: float                #: atan(v_x' / v_n') of the centre, degrees
    spin: float                         #: omega', rad/s (> 0: forward rolling)
    regime_tangential: str              #: "stick", "slip" or "stick-slip"
    path: str                           #: which solution gave the tangential results

    @property
    def restitution(self) -> float:
        """e_n, the normal coefficient of restitution."""
        return self.normal.restitution

    def to_dict(self) -> dict:
        """The normal results' fields plus the tangential ones, as JSON values."""
        out = self.normal.to_dict()
        out.update({k: to_jsonable(getattr(self, k)) for k in (
            "angle", "friction", "inertia_factor", "tangential_velocity",
            "restitution_tangential", "restitution_contact_point", "impulse_ratio",
            "rebound_angle", "spin", "regime_tangential")})
        out["path_tangential"] = self.path
        return out

    def summary(self) -> str:
        return "\n".join([
            self.normal.summary(),
            f"  oblique: angle {self.angle:g} deg, mu = {self.friction:g}, "
            f"I = {self.inertia_factor:g} m R^2 ({self.path})",
            f"  tangential restitution e_x      {self.restitution_tangential:.6f}",
            f"  contact-point restitution e_c   {self.restitution_contact_point:.6f}",
            f"  impulse ratio J_t/J_n           {self.impulse_ratio:.6f}",
            f"  rebound angle                   {self.rebound_angle:.4f} deg",
            f"  spin                            {self.spin:.6g} rad/s",
            f"  tangential regime               {self.regime_tangential}"])


def oblique_inputs(angle, friction, inertia_factor=SOLID_SPHERE):
    """(angle, friction, inertia_factor) checked: theta in [0, 90) degrees, mu in [0, 10],
    j in (0, 1] (a solid sphere 0.4, a thin shell 2/3)."""
    return (check_real("angle", angle, low=0.0, high=90.0, high_open=True, unit="degrees"),
            check_real("friction", friction, low=0.0, high=10.0),
            check_real("inertia_factor", inertia_factor, low=0.0, high=1.0, low_open=True))


def tangential_modulus(model: ImpactModel, delta, R):
    """G* (Pa) of Mindlin's k_t = 8 G* a: 1/G* = (2 - nu1)/G1 + (2 - nu2)/G2, target
    properties at approach delta (Johnson 1985, eq. 7.42)."""
    e_p, _, nu = model.target.properties(delta, R)
    compliance = 2.0 * (2.0 - nu) / (e_p * (1.0 - nu))    # (2 - nu)/G from E/(1 - nu^2)
    imp = model.impactor
    if imp is not None:
        compliance = compliance + 2.0 * (2.0 - imp.nu) / (imp.plane_strain_modulus
                                                           * (1.0 - imp.nu))
    return 1.0 / compliance


def stiffness_ratio(model: ImpactModel, delta, R) -> float:
    """kappa = k_t / k_n = 4 G* / E* of an elastic contact at approach delta
    (2 (1 - nu) / (2 - nu) for a rigid sphere)."""
    return float(4.0 * tangential_modulus(model, delta, R) / model.properties(delta, R)[0])


def solve_oblique(model: ImpactModel, velocity, radius, mass, angle, friction, *,
                  inertia_factor=SOLID_SPHERE, path="fast", rtol=1e-8,
                  samples=2000) -> ObliqueResult:
    """One oblique impact of a sphere without initial spin.

    Parameters
    ----------
    model : ImpactModel
        Target, normal contact law, impactor material and unloading.
    velocity, radius, mass : float
        Normal speed V (m/s), R (m), m (kg); the tangential speed is V tan(angle).
    angle : float
        Incidence angle theta from the normal, degrees, in [0, 90).
    friction : float
        Coulomb coefficient mu >= 0.
    inertia_factor : float
        j = I / (m R^2): 0.4 for a solid sphere.
    path : str
        "fast" (closed form where one exists, else time integration) or "time".
    rtol : float
        Relative tolerance of the normal and tangential integrations. The interpolated normal
        history sets the error floor: with 2000 samples J_t in gross slip is within about
        1e-8 of mu J_n (benchmarks/impact_speed_vs_error.py).
    samples : int
        Normal-history points per phase behind the interpolated F_n(t) and a(t).
    """
    V, R, m = (float(x) for x in _impact_inputs(velocity, radius, mass))
    theta, mu, j = oblique_inputs(angle, friction, inertia_factor)
    check_choice("path", path, ("fast", "time"))
    if not isinstance(model, ImpactModel):
        raise InputError(f"model must be an ImpactModel, got {type(model).__name__}")
    if path == "fast":
        done = _closed_form(model, model.maxima(V, R, m).result(()), theta, mu, j)
        if done is not None:
            return done
    hist = model.history(V, R, m, rtol=rtol, samples=samples)
    return (_closed_form(model, hist.result, theta, mu, j, gross_slip=False)
            or _integrate(model, hist, theta, mu, j, rtol))


def _closed_form(model, normal, theta, mu, j, gross_slip=True) -> ObliqueResult | None:
    """The tangential results without integration where they exist: no tangential force, or
    (``gross_slip``) a Hertz contact that slips throughout; None otherwise."""
    V, R = normal.velocity, normal.radius
    v_t = V * math.tan(math.radians(theta))
    if mu == 0.0 or v_t == 0.0:
        return _result(normal, theta, mu, j, v_t, 0.0, "stick" if v_t == 0 else "slip",
                       "closed form (no tangential force)")
    # the reversible branches of every law are Hertzian (kappa constant, the MBF boundary)
    elastic = model.law.regime_names.index(normal.regime) < model.law.reversible_branches
    if gross_slip and model.target.uniform and elastic:
        kappa = stiffness_ratio(model, 0.0, R)
        chi = 0.5 * kappa * (1.0 + 1.0 / j)
        if kappa * v_t / (mu * V) >= 4.0 * chi - 1.0:
            j_t = mu * V * (1.0 + normal.restitution)      # slip throughout: J_t / m = mu J_n / m
            return _result(normal, theta, mu, j, v_t - j_t, j_t / j, "slip",
                           "closed form (gross slip)")
    return None


def _result(normal, theta, mu, j, v_x, w, regime, path) -> ObliqueResult:
    """Assemble the result from the rebound v_x (m/s) and w = R omega (m/s)."""
    V, R = normal.velocity, normal.radius
    v_t = V * math.tan(math.radians(theta))
    v_n = normal.restitution * V
    j_n = V + v_n                                   # normal impulse / m
    e_x = v_x / v_t if v_t > 0 else math.nan
    e_c = (v_x - w) / v_t if v_t > 0 else math.nan
    return ObliqueResult(
        normal=normal, angle=theta, friction=mu, inertia_factor=j, tangential_velocity=v_t,
        restitution_tangential=e_x, restitution_contact_point=e_c,
        impulse_ratio=(v_t - v_x) / j_n, rebound_angle=math.degrees(math.atan2(v_x, v_n)),
        spin=w / R, regime_tangential=regime, path=path)


def _integrate(model, hist, theta, mu, j, rtol) -> ObliqueResult:
    """Tangential equations in time against the interpolated normal history."""
    normal = hist.result
    R, m = normal.radius, normal.mass
    v_t = normal.velocity * math.tan(math.radians(theta))
    if not math.isfinite(normal.contact_time):
        raise ModelRangeError("the unloading model gives no separation (status "
                              f"{normal.status}: {normal.message}): no tangential rebound")
    contact = hist.phase >= 1
    t, idx = np.unique(hist.time[contact], return_index=True)
    delta = hist.delta[contact][idx]
    force = hist.force[contact][idx]
    k_t = 8.0 * tangential_modulus(model, np.clip(delta, 0.0, R), R) \
        * hist.contact_radius[contact][idx]
    # scales: time T (contact time), velocity V_t, force m V_t / T
    T = normal.contact_time
    tau = (t - t[0]) / T
    f_n = PchipInterpolator(tau, force * T / (m * v_t))
    df_n = f_n.derivative()
    k_s = PchipInterpolator(tau, k_t * T * T / m)
    rot = 1.0 / j                                   # m R^2 / I

    def rhs(regime):
        def fun(s, y):
            f = y[2] if regime == 0 else regime * mu * float(f_n(s))
            df = k_s(s) * (y[0] - y[1]) if regime == 0 else regime * mu * df_n(s)
            return [-f, rot * f, float(df)]
        return fun

    def event(fun, direction):
        fun.terminal, fun.direction = True, direction
        return fun

    stick_events = [event(lambda s, y: y[2] - mu * float(f_n(s)), 1),
                    event(lambda s, y: y[2] + mu * float(f_n(s)), -1)]

    def slip_events(sign):
        return [event(lambda s, y: sign * float(k_s(s)) * (y[0] - y[1])
                      - mu * float(df_n(s)), -1)]

    # the first instants are Hertzian: F_t / F_n = kappa v_c / v_n, so the contact slips from
    # the start when kappa V_t >= mu V
    regime = 1 if stiffness_ratio(model, 0.0, R) * v_t >= mu * normal.velocity else 0
    seen = set()
    s0, y0 = 0.0, np.array([1.0, 0.0, 0.0])
    options = dict(method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    for _ in range(_MAX_SWITCHES):
        seen.add("stick" if regime == 0 else "slip")
        evs = stick_events if regime == 0 else slip_events(regime)
        sol = solve_ivp(rhs(regime), (s0, tau[-1]), y0, events=evs, **options)
        if sol.status < 0:
            raise ModelRangeError(f"tangential integration failed: {sol.message}")
        hit = [k for k, te in enumerate(sol.t_events) if te.size]
        if not hit:
            break
        k = min(hit, key=lambda k: sol.t_events[k][0])
        s0, y0 = sol.t_events[k][0], sol.y_events[k][0].copy()
        if regime == 0:
            regime = 1 if k == 0 else -1
            y0[2] = regime * mu * float(f_n(s0))
        else:
            regime = 0
    else:
        raise ModelRangeError(f"the contact switched between stick and slip more than "
                              f"{_MAX_SWITCHES} times: no converged tangential solution")
    kind = "stick-slip" if len(seen) == 2 else seen.pop()
    return _result(normal, theta, mu, j, sol.y[0, -1] * v_t, sol.y[1, -1] * v_t, kind,
                   "time-integration")


#: the tangential fields of an oblique map, with units; the regime is an index into REGIMES
#: (-1 where not computed)
OBLIQUE_FIELDS = {"restitution_tangential": "1", "restitution_contact_point": "1",
                  "impulse_ratio": "1", "rebound_angle": "degrees", "spin": "rad/s",
                  "regime_tangential": "1"}


def oblique_map(model: ImpactModel, velocity, radius, mass, angle, friction, *,
                inertia_factor=SOLID_SPHERE, rtol=1e-8, progress=None) -> ImpactMap:
    """Oblique impacts over ``velocity`` (columns) and either ``radius`` or ``angle`` (rows,
    a 1-D array; the other one value, repeated per row in the map's ``radius`` or ``angle``).

    The normal maxima come from `impact_map`; each point's tangential results from the closed
    forms where they exist, else from time integration (about 0.5 s a point; the normal
    history of a (V, R) pair serves every angle). ``progress(done, total)`` after each row.
    """
    rows_are_angles = np.ndim(angle) == 1
    if rows_are_angles == (np.ndim(radius) == 1):
        raise InputError("an oblique map takes radius or angle as its rows (a 1-D array) and "
                         "the other as one value")
    if rows_are_angles:
        angles = np.array([oblique_inputs(a, friction, inertia_factor)[0] for a in angle])
        radius = np.full(angles.size, check_real("radius", radius, low=0.0, low_open=True,
                                                 unit="m"))
    else:
        angles = np.full(np.size(radius), oblique_inputs(angle, friction, inertia_factor)[0])
    _, mu, j = oblique_inputs(0.0, friction, inertia_factor)
    base = impact_map(model, velocity, radius, mass)
    out = {k: np.full(base.maxima.status.shape, np.nan) for k in OBLIQUE_FIELDS}
    histories = {}
    for r, theta in enumerate(angles):
        for c in range(base.velocity.size):
            if base.out_of_range[r, c]:
                continue
            normal = base.maxima.result((r, c))
            if not math.isfinite(normal.contact_time):     # no separation: no rebound
                continue
            res = _closed_form(model, normal, theta, mu, j)
            if res is None:
                key = (normal.velocity, normal.radius)
                if key not in histories:
                    histories[key] = model.history(*key, base.mass, rtol=rtol, samples=2000)
                res = _integrate(model, histories[key], theta, mu, j, rtol)
            for k in OBLIQUE_FIELDS:
                value = getattr(res, k)
                out[k][r, c] = REGIMES.index(value) if k == "regime_tangential" else value
        if progress is not None:
            progress((r + 1) * base.velocity.size, angles.size * base.velocity.size)
    out["regime_tangential"] = np.where(np.isnan(out["regime_tangential"]), -1,
                                        out["regime_tangential"]).astype(int)
    return replace(base, angle=angles, tangential=out)
