"""Sphere-on-flat contact laws: approach delta -> force P, contact area A, regime.

Every law is written for local properties (E*, sigma_Y, nu), which may vary with depth in a
layered target, and for a *branch*: the index of the regime reached so far. Each law has a
severity variable s(delta) (a strain or a normalised interference) and thresholds where its
formula changes; ``branch = number of thresholds reached``. Under monotone loading of a
homogeneous target the branch follows from s(delta); in a layered target s can fall while
loading continues, and the regime is then taken from the largest s reached so far
(docs/physics.md section 3). Within a branch a formula is evaluated with s no lower than the
branch's own lower threshold, so a yielded contact never returns to a lower formula.

Units: delta, R in m; E_star, sigma_y in Pa; forces in N; areas in m^2. All methods broadcast.

Sources (docs/physics.md sections 1-3): Hertz (Johnson 1985); Komvopoulos & Ye, J. Tribol. 123
(2001) 632 [R: constants reconstructed]; Kogut & Etsion, J. Appl. Mech. 69 (2002) 657;
Jackson & Green, J. Tribol. 127 (2005) 343; Thornton, J. Appl. Mech. 64 (1997) 383.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError

from .hertz import first_yield_unchecked as _hertz_first_yield
from .hertz import hertz_force_unchecked, pressure_factor_unchecked, checked
from .quadrature import integrate


@dataclass(frozen=True)
class ContactState:
    """Force, area and regime of a contact at given approaches; SI units."""

    force: np.ndarray           #: P, N
    area: np.ndarray            #: A, m^2
    branch: np.ndarray          #: regime index into the law's ``regime_names``

    @property
    def contact_radius(self) -> np.ndarray:
        """a = sqrt(A / pi), m."""
        return np.sqrt(self.area / np.pi)

    @property
    def mean_pressure(self) -> np.ndarray:
        """p_m = P / A, Pa (0 where A = 0)."""
        area = np.asarray(self.area)
        return np.divide(self.force, area, out=np.zeros(np.broadcast(self.force, area).shape),
                         where=area > 0)


@dataclass(frozen=True)
class LawYield:
    """First yield of a law for a homogeneous target; SI units."""

    approach: np.ndarray        #: delta_Y, m
    force: np.ndarray           #: P_Y, N
    contact_radius: np.ndarray  #: a_Y, m
    work: np.ndarray            #: integral of P from 0 to delta_Y, J
    velocity: np.ndarray | None  #: impact speed that just reaches yield, m/s (given a mass)


class ContactLaw:
    """Base class: subclasses define the severity, thresholds and branch formulas."""

    name: str = ""
    thresholds: tuple[float, ...] = ()
    regime_names: tuple[str, ...] = ()
    #: the force is continuous in delta at every threshold
    continuous: bool = True
    #: k_T = H / sigma_Y: the mean pressure of fully plastic contact in units of sigma_Y
    hardness_factor: float = 2.8
    #: residual-depth model used when the caller asks for "auto" unloading
    default_unloading: str = "crater"
    #: branches below this index are elastic: unloading retraces loading (e_y = 1)
    reversible_branches: int = 1

    def critical_approach(self, R, E_star, sigma_y, nu):
        """delta_c, m, for laws whose severity is delta / delta_c (all but Komvopoulos-Ye)."""
        raise NotImplementedError

    def severity(self, delta, R, E_star, sigma_y, nu):
        return np.asarray(delta, dtype=float) / self.critical_approach(R, E_star, sigma_y, nu)

    def approach_at_severity(self, value, R, E_star, sigma_y, nu):
        """Inverse of ``severity`` for constant properties, m."""
        return value * self.critical_approach(R, E_star, sigma_y, nu)

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        """(P, A) on the given branch; see the module docstring."""
        raise NotImplementedError

    def branch_of(self, severity):
        """Number of thresholds reached by ``severity``."""
        return np.searchsorted(np.asarray(self.thresholds), severity, side="right")

    def contact(self, delta, R, E_star, sigma_y, nu) -> ContactState:
        """Contact state under monotone loading of a homogeneous target: approach delta (m),
        sphere radius R (m), E* and sigma_y (Pa; inf: never yields), Poisson ratio nu."""
        return self.unchecked_contact(*checked(delta=delta, R=R, E_star=E_star,
                                               sigma_y=sigma_y, nu=nu))

    def unchecked_contact(self, delta, R, E_star, sigma_y, nu) -> ContactState:
        """`contact` without its input checks: for fits that evaluate it many times with
        trial values (a NaN there is the fit's to handle)."""
        delta = np.asarray(delta, dtype=float)
        branch = self.branch_of(self.severity(delta, R, E_star, sigma_y, nu))
        force, area = self.force_area(delta, R, E_star, sigma_y, nu, branch)
        return ContactState(force=force, area=area, branch=branch)

    def first_yield(self, R, E_star, sigma_y, nu, mass=None) -> LawYield:
        """Approach, force, contact radius, work and (with ``mass``) velocity at first yield.

        Yield is the law's first threshold. The work is the integral of the elastic branch
        (Gauss-Legendre in sqrt(delta): exact for a Hertz force); the velocity is
        sqrt(2 W / m). R in m, E* and sigma_y in Pa, mass in kg.
        """
        R, E_star, sigma_y, nu = checked(R=R, E_star=E_star, sigma_y=sigma_y, nu=nu)
        if mass is not None:
            mass = checked(m=mass)[0]
        approach = self.approach_at_severity(self.thresholds[0], R, E_star, sigma_y, nu)
        force, area = self.force_area(approach, R, E_star, sigma_y, nu, 0)
        args = [np.asarray(v, dtype=float)[..., None] for v in (R, E_star, sigma_y, nu)]
        work = integrate(lambda d: self.force_area(d, *args, 0)[0], 0.0, approach, n=16)
        velocity = None if mass is None else np.sqrt(2.0 * work / mass)
        return LawYield(approach=approach, force=force, contact_radius=np.sqrt(area / np.pi),
                        work=work, velocity=velocity)

    def describe(self) -> dict:
        """Plain description for provenance."""
        return {"contact_law": self.name, "thresholds": list(self.thresholds),
                "regimes": list(self.regime_names), "continuous": self.continuous,
                "hardness_factor": self.hardness_factor}

    def _clamped(self, severity, branch):
        """Severity raised to at least the lower threshold of its branch."""
        if np.ndim(branch) == 0:
            return severity if branch == 0 else np.maximum(severity, self.thresholds[branch - 1])
        lower = np.concatenate(([-np.inf], self.thresholds))[np.asarray(branch)]
        return np.maximum(severity, lower)


def _by_branch(branch, *formulas):
    """Value of formulas[branch] (the last one for every higher branch). A scalar branch
    evaluates one formula only (the time integrator's case); an array selects elementwise."""
    if np.ndim(branch) == 0:
        return formulas[min(int(branch), len(formulas) - 1)]()
    branch = np.asarray(branch)
    with np.errstate(all="ignore"):     # every formula runs on every point, most off-branch
        values = [f() for f in formulas]
    return np.select([branch == k for k in range(len(formulas) - 1)], values[:-1], values[-1])


def _hertz_or_plastic(branch, first_plastic, plastic, delta, R, E_star):
    """(P, A): Hertz on branches below ``first_plastic``, plastic() from it on; a scalar
    branch evaluates one of them only."""
    if np.ndim(branch) == 0 and branch < first_plastic:
        return hertz_force_unchecked(delta, R, E_star), _hertz_area(delta, R)
    if np.ndim(branch) == 0:
        return plastic()
    selected = np.asarray(branch) >= first_plastic
    with np.errstate(all="ignore"):     # the plastic formula also runs on elastic points
        f_p, a_p = plastic()
    return (np.where(selected, f_p, hertz_force_unchecked(delta, R, E_star)),
            np.where(selected, a_p, _hertz_area(delta, R)))


def _hertz_area(delta, R):
    return np.pi * R * delta


# --- Hertz ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Hertz(ContactLaw):
    """Hertz contact at every depth; severity delta / delta_Y with delta_Y from first yield
    of docs/physics.md section 2, so that a result can say that yield was exceeded."""

    name = "hertz"
    thresholds = (1.0,)
    regime_names = ("elastic", "elastic (first yield exceeded)")
    reversible_branches = 2

    def critical_approach(self, R, E_star, sigma_y, nu):
        return _hertz_first_yield(R, E_star, sigma_y, nu).approach

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        delta = np.asarray(delta, dtype=float)
        return hertz_force_unchecked(delta, R, E_star), _hertz_area(delta, R)


# --- Komvopoulos & Ye 2001 ----------------------------------------------------------------------

#: Constants of the Komvopoulos-Ye law as reconstructed in docs/physics.md section 3 [R]:
#: p_m/sigma_Y = K_EL eps (elastic), SLOPE ln(eps) + C1 (elastic-plastic), PLATEAU (fully
#: plastic); A_t/A = 2 (elastic), Q2 ln(eps)^2 + Q1 ln(eps) + C2, TAIL (eps > EPS3).
KY_LITERAL = {"EPS1": 1.78, "EPS2": 21.0, "EPS3": 400.0,
              "K_EL": 4.0 * math.sqrt(2.0) / (3.0 * math.pi), "SLOPE": 0.70, "C1": 0.66,
              "Q2": 0.05, "Q1": -0.57, "C2": 2.4, "PLATEAU": 2.8, "TAIL": 0.72}


def _ky_continuous_constants(c) -> dict:
    """The literal constants with C1, C2, PLATEAU and TAIL re-derived so that p_m and A (hence
    P) are exactly continuous at each breakpoint: 0.66475, 2.31204, 2.79593, 0.69174.
    docs/physics.md quotes 0.665, 2.312, 2.8 and 0.70, which leave jumps up to 1.2 %. The plateau,
    hence k_T for measured profiles, is 2.796 instead of 2.8."""
    l1, l2, l3 = math.log(c["EPS1"]), math.log(c["EPS2"]), math.log(c["EPS3"])
    out = dict(c)
    out["C1"] = c["K_EL"] * c["EPS1"] - c["SLOPE"] * l1
    out["C2"] = 2.0 - c["Q2"] * l1**2 - c["Q1"] * l1
    out["PLATEAU"] = c["SLOPE"] * l2 + out["C1"]
    out["TAIL"] = c["Q2"] * l3**2 + c["Q1"] * l3 + out["C2"]
    return out


KY_CONTINUOUS = MappingProxyType(_ky_continuous_constants(KY_LITERAL))
KY_LITERAL = MappingProxyType(KY_LITERAL)


@dataclass(frozen=True)
class KomvopoulosYe(ContactLaw):
    """Rigid sphere on an elastic-perfectly plastic half-space (Komvopoulos & Ye 2001) [R].

    Representative strain eps = E* delta / (sigma_Y sqrt(delta (2R - delta))); truncated area
    A_t = pi delta (2R - delta); P = p_m A with p_m/sigma_Y and A_t/A from docs/physics.md
    section 3.
    ``continuous=False`` uses the literal constants (force jumps of -4.6 % at eps = 1.78 and
    +8.3 % at eps = 400); ``continuous=True`` the variant continuous at every breakpoint.
    Valid for loading and delta <= R.
    """

    continuous: bool = False
    constants: MappingProxyType = field(init=False, repr=False, compare=False)
    regime_names = ("elastic", "elastic-plastic", "fully plastic", "fully plastic with pile-up")
    default_unloading = "crater"

    def __post_init__(self):
        object.__setattr__(self, "constants", KY_CONTINUOUS if self.continuous else KY_LITERAL)

    @property
    def name(self) -> str:
        return "komvopoulos-ye-continuous" if self.continuous else "komvopoulos-ye"

    @property
    def thresholds(self) -> tuple[float, ...]:
        c = self.constants
        return (c["EPS1"], c["EPS2"], c["EPS3"])

    @property
    def hardness_factor(self) -> float:
        return self.constants["PLATEAU"]

    def severity(self, delta, R, E_star, sigma_y, nu):
        delta = np.asarray(delta, dtype=float)
        return (E_star / sigma_y) * np.sqrt(delta / (2.0 * R - delta))

    def approach_at_severity(self, value, R, E_star, sigma_y, nu):
        k = np.square(value * sigma_y / E_star)
        return 2.0 * R / (1.0 + 1.0 / k)        # 2R k/(1+k), finite for sigma_Y = inf

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        c = self.constants
        delta = np.asarray(delta, dtype=float)
        branch = np.asarray(branch)
        eps = self._clamped(self.severity(delta, R, E_star, sigma_y, nu), branch)

        @functools.cache         # one logarithm for the three formulas that read it
        def ln_eps():            # read on plastic branches only, where eps >= EPS1
            return np.log(np.maximum(eps, c["EPS1"]))

        @functools.cache
        def quad():
            ln = ln_eps()
            return c["Q2"] * ln**2 + c["Q1"] * ln + c["C2"]

        # elastic p_m = K_EL eps sigma_Y written without sigma_Y, which may be inf (no yield)
        mean_pressure = _by_branch(
            branch, lambda: c["K_EL"] * E_star * np.sqrt(delta / (2.0 * R - delta)),
            lambda: (c["SLOPE"] * ln_eps() + c["C1"]) * sigma_y, lambda: c["PLATEAU"] * sigma_y)
        area_ratio = _by_branch(branch, lambda: 2.0, quad, quad, lambda: c["TAIL"])
        area = np.pi * delta * (2.0 * R - delta) / area_ratio
        return mean_pressure * area, area

    def describe(self) -> dict:
        d = super().describe()
        d["constants"] = {k: float(v) for k, v in self.constants.items()}
        d["reconstructed"] = True
        return d


# --- Kogut & Etsion 2002 ----------------------------------------------------------------------

@dataclass(frozen=True)
class KogutEtsion(ContactLaw):
    """Deformable sphere on a rigid flat (Kogut & Etsion 2002), used here for a rigid sphere
    on a deformable flat (they agree while elastic). K = 0.454 + 0.41 nu, H = 2.8 sigma_Y,
    w_c = (pi K H / (2E*))^2 R. The published fits jump at w/w_c = 1, 6 and 110."""

    name = "kogut-etsion"
    thresholds = (1.0, 6.0, 110.0)
    regime_names = ("elastic", "elastic-plastic (1 <= w/w_c <= 6)",
                    "elastic-plastic (6 < w/w_c <= 110)", "fully plastic")
    continuous = False
    hardness_factor = 2.8
    default_unloading = "jackson-chusoipin-green"

    def _critical(self, R, E_star, sigma_y, nu):
        kh = (0.454 + 0.41 * np.asarray(nu)) * self.hardness_factor * sigma_y
        w_c = np.square(np.pi * kh / (2.0 * E_star)) * R
        p_c = (np.pi**3 / 6.0) * kh**3 * np.square(R) / np.square(E_star)
        return w_c, p_c

    def critical_approach(self, R, E_star, sigma_y, nu):
        return self._critical(R, E_star, sigma_y, nu)[0]

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        delta = np.asarray(delta, dtype=float)
        branch = np.asarray(branch)
        w_c, p_c = self._critical(R, E_star, sigma_y, nu)
        ws = self._clamped(delta / w_c, branch)
        a_c = np.pi * R * w_c
        force = _by_branch(branch, lambda: hertz_force_unchecked(delta, R, E_star),
                           lambda: 1.03 * p_c * ws**1.425, lambda: 1.40 * p_c * ws**1.263,
                           lambda: 2.0 * np.pi * R * ws * w_c * self.hardness_factor * sigma_y)
        area = _by_branch(branch, lambda: _hertz_area(delta, R),
                          lambda: 0.93 * a_c * ws**1.136, lambda: 0.94 * a_c * ws**1.146,
                          lambda: 2.0 * np.pi * R * ws * w_c)
        return force, area


# --- Jackson & Green 2005 ---------------------------------------------------------------------

@dataclass(frozen=True)
class JacksonGreen(ContactLaw):
    """Deformable sphere on a rigid flat (Jackson & Green 2005). Yield at w* = w/w_c = 1 with
    w_c from C(nu) = 1.295 exp(0.736 nu); the force stays Hertzian up to w* = 1.9, then
    P/P_c = exp(-w*^(5/12)/4) w*^(3/2) + (4 H_G/(C sigma_Y)) (1 - exp(-w*^(5/9)/25)) w*,
    A = pi R w (w*/1.9)^B, B = 0.14 exp(23 sigma_Y/E*),
    H_G/sigma_Y = 2.84 (1 - exp(-0.82 (a/R)^(-0.7)))."""

    name = "jackson-green"
    thresholds = (1.0, 1.9)
    regime_names = ("elastic", "elastic-plastic (Hertzian force)", "elastic-plastic")
    continuous = False
    hardness_factor = 2.84
    default_unloading = "jackson-chusoipin-green"

    def _critical(self, R, E_star, sigma_y, nu):
        c_sy = pressure_factor_unchecked(nu) * sigma_y
        w_c = np.square(np.pi * c_sy / (2.0 * E_star)) * R
        p_c = (np.pi**3 / 6.0) * c_sy**3 * np.square(R) / np.square(E_star)
        return w_c, p_c, c_sy

    def critical_approach(self, R, E_star, sigma_y, nu):
        return self._critical(R, E_star, sigma_y, nu)[0]

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        delta = np.asarray(delta, dtype=float)
        w_c, p_c, c_sy = self._critical(R, E_star, sigma_y, nu)

        def plastic():
            ws = np.maximum(delta / w_c, 1.9)
            w = ws * w_c
            area = np.pi * R * w * (ws / 1.9) ** (0.14 * np.exp(23.0 * sigma_y / E_star))
            a_over_r = np.sqrt(area / np.pi) / R
            h_g = 2.84 * sigma_y * (1.0 - np.exp(-0.82 * a_over_r ** -0.7))
            force = p_c * (np.exp(-0.25 * ws ** (5.0 / 12.0)) * ws**1.5
                           + 4.0 * h_g / c_sy * (1.0 - np.exp(-ws ** (5.0 / 9.0) / 25.0)) * ws)
            return force, area

        return _hertz_or_plastic(branch, 2, plastic, delta, R, E_star)


# --- Thornton 1997 ----------------------------------------------------------------------------

@dataclass(frozen=True)
class Thornton(ContactLaw):
    """Truncated Hertz (Thornton 1997): Hertz until p0 reaches the limiting pressure
    p_y = f sigma_Y at a_y = pi p_y R / (2E*); beyond, P = P_y + pi p_y (a^2 - a_y^2),
    a^2 = R delta. ``limiting_pressure_factor`` f defaults to 2.8, so that the mean pressure
    tends to the Tabor hardness."""

    limiting_pressure_factor: float = 2.8
    name = "thornton"
    thresholds = (1.0,)
    regime_names = ("elastic", "plastic (truncated Hertz)")
    default_unloading = "crater"

    def __post_init__(self):
        check_real("limiting_pressure_factor", self.limiting_pressure_factor, low=1.0,
                   high=5.0)

    @property
    def hardness_factor(self) -> float:
        return self.limiting_pressure_factor

    def critical_approach(self, R, E_star, sigma_y, nu):
        return np.square(np.pi * self.limiting_pressure_factor * sigma_y / (2.0 * E_star)) * R

    def force_area(self, delta, R, E_star, sigma_y, nu, branch):
        delta = np.asarray(delta, dtype=float)
        d_y = self.critical_approach(R, E_star, sigma_y, nu)

        def plastic():
            d_eff = np.maximum(delta, d_y)
            force = (hertz_force_unchecked(d_y, R, E_star)
                     + np.pi * self.limiting_pressure_factor * sigma_y * R * (d_eff - d_y))
            return force, _hertz_area(d_eff, R)

        return _hertz_or_plastic(branch, 1, plastic, delta, R, E_star)

    def describe(self) -> dict:
        d = super().describe()
        d["limiting_pressure_factor"] = self.limiting_pressure_factor
        return d


#: Names accepted in scene files and by ``contact_law``, with their constructors.
_LAWS = {
    "hertz": Hertz,
    "komvopoulos-ye": lambda: KomvopoulosYe(continuous=False),
    "komvopoulos-ye-continuous": lambda: KomvopoulosYe(continuous=True),
    "kogut-etsion": KogutEtsion,
    "jackson-green": JacksonGreen,
    "thornton": Thornton,
}
LAW_NAMES = tuple(_LAWS)
#: the law of an impact scene without [model] contact_law: the published Komvopoulos-Ye
#: form as fitted to FE, with its regime jumps (docs/impact-model.md)
DEFAULT_LAW = "komvopoulos-ye"
#: the law `calibrate` fits by default: the same law made continuous at its regime changes,
#: because a least-squares fit over a curve cannot follow a jump in force
FIT_LAW = "komvopoulos-ye-continuous"


def contact_law(name: str, **options) -> ContactLaw:
    """The contact law called ``name`` (one of LAW_NAMES); options go to its constructor
    (``limiting_pressure_factor`` for Thornton)."""
    check_choice("contact_law", name, LAW_NAMES)
    if options and name != "thornton":
        raise InputError(f"contact law {name!r} takes no options, got {sorted(options)}")
    return _LAWS[name](**options)
