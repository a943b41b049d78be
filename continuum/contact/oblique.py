"""Oblique impact of a sphere with Coulomb friction, tangential compliance and rotation.

An impactor with a spherical tip of radius R, its own mass m and its own moment of inertia
I = j m R^2 about the tip's centre, where its centre of mass lies, meets the target with
normal speed V and tangential speed V_t = V tan(theta), without spin. A sphere has j <= 2/3
(0.4 solid, 2/3 thin shell); a body with mass beyond R has j > 1, up to
`INERTIA_FACTOR_MAX` (1e8: a body that does not turn). Equations: docs/physics.md section 5;
the mass and inertia of a slider corner, whose centre of mass is far from the corner:
docs/slider-dynamics.md.

Model (Thornton 1997; Wu, Thornton & Li 2009 for the decoupling; Popov & Hess 2015 for the
tangential contact):

- The normal motion is the scene's normal impact (`ImpactModel`: its contact law, loading and
  unloading), independent of the tangential force. This is the standard decoupling: the normal
  and tangential problems uncouple exactly for similar materials and nearly so otherwise.
- Tangential contact: the Mindlin-Deresiewicz problem (micro-slip at the edge, the history of
  loading and unloading) solved by the method of dimensionality reduction (MDR; Popov & Hess
  2015, chapters 3 and 5). The circular contact maps onto a line of independent springs
  |x| <= a: tangential stiffness 4 G* dx each (all of them stuck: 8 G* a, Mindlin's), normal
  line load q(x) = (3 F_n / (4 a^3)) (a^2 - x^2) (Hertz's; for an elastic-plastic law the
  same shape with that law's F_n and a, an approximation), each spring obeying Coulomb's law
  |f(x)| <= mu q(x) dx on its own, and a spring that leaves the contact losing its force. For
  a Hertz contact this is the exact Mindlin-Deresiewicz solution for any history (Popov & Hess
  2015), so it gives Maw, Barber & Fawcett's curves, including the reversal of the contact
  point at small angles, and the gross-slip boundary psi_1 = max(1, 4 chi - 1)
  (`gross_slip_boundary`: MBF's 4 chi - 1 for every sphere, and 1, Mindlin's initial slip,
  for a body that turns little).
- Sign convention: x along the incident tangential velocity; omega > 0 is forward rolling, so
  the contact point slides at v_c = v_x - R omega; F_t > 0 acts on the sphere along -x:
  m dv_x/dt = -F_t, I d(omega)/dt = R F_t.
- Regime: "slip" when the whole contact slides (|F_t| = mu F_n) at every step, "stick" when it
  never does (only Mindlin's micro-slip at the edge), "stick-slip" otherwise.

Two paths:

- ``"fast"``: the normal maxima by energy quadrature (`ImpactModel.maxima`) and the
  tangential results in closed form where one exists: no friction or no tangential speed
  (e_x = 1), or a Hertz (elastic, uniform target) contact that slips throughout
  (psi_1 >= max(1, 4 chi - 1)): then J_t = mu J_n and e_x = 1 - mu (1 + e_n) / tan(theta)
  for any j (the spin is then R J_t / I). Any other impact goes to time integration
  (``path`` of the result says which was used).
- ``"time"``: the normal history (`ImpactModel.history`) interpolated (PCHIP) in time and
  the spring line stepped through the contact at fixed steps (velocity Verlet; the normal
  force rescaled so that its impulse is the history's m V (1 + e_n) exactly).

Units: SI (m, kg, m/s, N, Pa, s), angles in degrees, spin in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from filmscale.core.checks import check_choice, check_int, check_real
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.jsonable import to_jsonable

from .impact import ImpactModel, impact_inputs
from .impact_map import ImpactMap, impact_map
from .results import ImpactResult

#: moment of inertia of a solid sphere in units of m R^2
SOLID_SPHERE = 0.4
#: the largest inertia factor j = I / (m R^2): at 1e8 the spin's share 1 / (1 + j) of the
#: contact point's tangential compliance is 1e-8, below every tolerance of the model, so a
#: larger j changes no result but the (vanishing) spin; state 1e8 for a body that does not
#: turn (docs/physics.md section 5).
INERTIA_FACTOR_MAX = 1e8
REGIMES = ("stick", "slip", "stick-slip")
#: time steps and springs (one side) of the time path: e_x within about 1e-3 of converged
STEPS, SPRINGS = 2000, 400


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
            f"  tangential restitution e_x      {self.restitution_tangential:.4f}",
            f"  contact-point restitution e_c   {self.restitution_contact_point:.4f}",
            f"  impulse ratio J_t/J_n           {self.impulse_ratio:.4f}",
            f"  rebound angle                   {self.rebound_angle:.4g} deg",
            f"  spin                            {self.spin:.4g} rad/s",
            f"  tangential regime               {self.regime_tangential}"])


def oblique_inputs(angle, friction, inertia_factor=SOLID_SPHERE):
    """(angle, friction, inertia_factor) checked: theta in [0, 90) degrees, mu in [0, 10],
    j in (0, 1e8] (a solid sphere 0.4, a thin shell 2/3, a body that does not turn 1e8)."""
    return (check_real("angle", angle, low=0.0, high=90.0, high_open=True, unit="degrees"),
            check_real("friction", friction, low=0.0, high=10.0),
            check_real("inertia_factor", inertia_factor, low=0.0, high=INERTIA_FACTOR_MAX,
                       low_open=True))


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


def gross_slip_boundary(kappa: float, j: float) -> float:
    """The psi_1 = kappa V_t / (mu V) above which an elastic (Hertz) contact slides throughout
    the impact, for k_t / k_n = kappa and inertia factor j: max(1, 4 chi - 1), with
    chi = (kappa / 2) (1 + 1/j).

    Sliding throughout puts every spring of the MDR line at its Coulomb limit, whose
    displacement mu q(x) / (4 G*) = mu (a^2 - x^2) / (kappa R) grows at mu d(delta)/dt / kappa
    at every x; the contact point slides at v_c = V_t - (1 + 1/j) mu (V - d(delta)/dt). So
    v_c >= mu d(delta)/dt / kappa throughout, linear in d(delta)/dt, which runs from V to -V:
    psi_1 >= 1 at the start (Mindlin's initial slip) and psi_1 >= 4 chi - 1 at the end
    (Maw, Barber & Fawcett). The end binds when chi > 1/2, which holds for every sphere
    (j <= 1 gives chi >= kappa >= 2/3); the start binds for a body that turns little,
    j > kappa / (1 - kappa) (4.7 at nu = 0.3)."""
    chi = 0.5 * kappa * (1.0 + 1.0 / j)
    return max(1.0, 4.0 * chi - 1.0)


def solve_oblique(model: ImpactModel, velocity, radius, mass, angle, friction, *,
                  inertia_factor=SOLID_SPHERE, path="fast", rtol=1e-8,
                  samples=2000, steps=STEPS, springs=SPRINGS) -> ObliqueResult:
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
        j = I / (m R^2), I about the tip's centre (the centre of mass): 0.4 for a solid
        sphere, up to 1e8 (a body that does not turn); a slider corner:
        docs/slider-dynamics.md.
    path : str
        "fast" (closed form where one exists, else time integration) or "time".
    rtol : float
        Relative tolerance of the normal history's integration.
    samples : int
        Normal-history points per phase behind the interpolated F_n(t) and a(t).
    steps, springs : int
        Time steps through the contact and springs on one side of the MDR line of the time
        path; the defaults keep the tangential restitution within about 1e-3 of the converged
        value (benchmarks/impact_speed_vs_error.py).
    """
    V, R, m = (float(x) for x in impact_inputs(velocity, radius, mass))
    theta, mu, j = oblique_inputs(angle, friction, inertia_factor)
    check_choice("path", path, ("fast", "time"))
    steps, springs = check_int("steps", steps, 10, 10**7), check_int("springs", springs, 2, 10**5)
    if not isinstance(model, ImpactModel):
        raise InputError(f"model must be an ImpactModel, got {type(model).__name__}")
    if path == "fast":
        done = _closed_form(model, model.maxima(V, R, m).result(()), theta, mu, j)
        if done is not None:
            return done
    hist = model.history(V, R, m, rtol=rtol, samples=samples)
    return (_closed_form(model, hist.result, theta, mu, j, gross_slip=False)
            or _integrate(model, hist, theta, mu, j, steps, springs))


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
        if kappa * v_t / (mu * V) >= gross_slip_boundary(kappa, j):
            j_t = mu * V * (1.0 + normal.restitution)      # slip throughout: J_t / m = mu J_n / m
            # m dv_x = -J_t, I d(omega) = R J_t: R d(omega) = J_t / (j m)
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


def _integrate(model, hist, theta, mu, j, steps, springs) -> ObliqueResult:
    """The tangential motion stepped through the contact on the MDR spring line (module
    docstring) against the interpolated normal history."""
    from scipy.interpolate import PchipInterpolator
    normal = hist.result
    R, m, V = normal.radius, normal.mass, normal.velocity
    v_t = V * math.tan(math.radians(theta))
    if not math.isfinite(normal.contact_time):
        raise ModelRangeError("the unloading model gives no separation (status "
                              f"{normal.status}: {normal.message}): no tangential rebound")
    contact = hist.phase >= 1
    t, idx = np.unique(hist.time[contact], return_index=True)
    t = t - t[0]
    dt = t[-1] / steps
    mid = (np.arange(steps) + 0.5) * dt
    f_n = np.clip(PchipInterpolator(t, hist.force[contact][idx])(mid), 0.0, None)
    f_n *= m * V * (1.0 + normal.restitution) / (f_n.sum() * dt)
    a = np.clip(PchipInterpolator(t, _continuous_radius(hist)[contact][idx])(mid), 0.0, None)
    delta = np.clip(PchipInterpolator(t, hist.delta[contact][idx])(mid), 0.0, R)
    stiffness = 4.0 * tangential_modulus(model, delta, R) * np.ones(steps)   # per unit length
    # one side of the symmetric spring line, x in [0, a_max]; cell k is [x_k, x_k + dx]
    dx = a.max() / springs
    x = np.arange(springs) * dx
    x_cubed = x**3
    force = np.zeros(springs)                   # spring forces of one side, N
    v, w, f_t = v_t, 0.0, 0.0                   # w = R omega
    slid = stuck = False
    for n in range(steps):
        v, w = v - 0.5 * f_t / m * dt, w + 0.5 * f_t / (j * m) * dt
        top = np.clip(a[n], x, x + dx)          # the part of each cell in contact
        length = top - x
        # each cell's share of the line load (a^2 - x^2), integrated exactly over the cell
        share = a[n] ** 2 * length - (top ** 3 - x_cubed) / 3.0
        total = share.sum()
        if total <= 0.0:
            force[:] = 0.0
            f_t = 0.0
        else:
            limit = (0.5 * mu * f_n[n] / total) * share
            force = np.clip(np.where(length > 0.0, force + stiffness[n] * length * (v - w) * dt,
                                     0.0), -limit, limit)
            f_t = 2.0 * force.sum()
            if abs(f_t) >= mu * f_n[n] * (1.0 - 1e-9):
                slid = True
            else:
                stuck = True
        v, w = v - 0.5 * f_t / m * dt, w + 0.5 * f_t / (j * m) * dt
    kind = "stick-slip" if slid and stuck else ("slip" if slid else "stick")
    return _result(normal, theta, mu, j, v, w, kind, "time-integration")


def _continuous_radius(hist) -> np.ndarray:
    """The history's contact radius with its unloading part scaled to start from the loading
    radius at maximum approach. The Hertz unloading of a residual-depth fit
    (jackson-chusoipin-green, brake) may start from another radius than the loading law's
    area gives (about twice it for Jackson-Green at 5 m/s on aluminium); a contact does not
    grow as it unloads, and the spring line must not gain a stuck annulus at that instant."""
    a = hist.contact_radius.copy()
    loading, unloading = np.flatnonzero(hist.phase == 1), np.flatnonzero(hist.phase == 2)
    if loading.size and unloading.size and a[unloading[0]] > 0.0:
        a[unloading] *= a[loading[-1]] / a[unloading[0]]
    return a


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
                res = _integrate(model, histories[key], theta, mu, j, STEPS, SPRINGS)
            for k in OBLIQUE_FIELDS:
                value = getattr(res, k)
                out[k][r, c] = REGIMES.index(value) if k == "regime_tangential" else value
        if progress is not None:
            progress((r + 1) * base.velocity.size, angles.size * base.velocity.size)
    out["regime_tangential"] = np.where(np.isnan(out["regime_tangential"]), -1,
                                        out["regime_tangential"]).astype(int)
    return replace(base, angle=angles, tangential=out, tangential_units=dict(OBLIQUE_FIELDS))
