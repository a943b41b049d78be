"""Indenter tips: projected contact area A(h_c), the geometry constant eps and beta.

Every tip gives the projected area A (m^2) at contact depth h_c (m), its derivative, the
half-angle of its equivalent cone (degrees, None for a sphere or flat punch), the default
geometry constant ``epsilon`` of Oliver-Pharr and the default correction factor ``beta`` of
E_r = sqrt(pi) S / (2 beta sqrt(A_c)).

Sources (docs/physics.md section 9): ideal areas Fischer-Cripps, *Nanoindentation* (2011) table 1.1;
beta of pyramids King (1987); Hay, Bolshakov & Pharr, J. Mater. Res. 14 (1999) 2296 for cones;
Borodich & Keer (2004) for no-slip contact; polynomial area Oliver & Pharr, J. Mater. Res. 7
(1992) 1564; spherical-conical tip with tangent transition, e.g. Fischer-Cripps (2011) sec. 1.2.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace

import numpy as np

from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.core.checks import check_positive, check_real
from filmscale.core.errors import InputError
from filmscale.core.quantities import to_si

BERKOVICH_AREA = 24.494     #: A / h_c^2 of the ideal Berkovich (65.27 deg face angle)
BERKOVICH_CONE = 70.30      #: half-angle of the cone with the Berkovich area, degrees
CUBE_CORNER_AREA = 2.598    #: A / h_c^2 of the ideal cube corner
CUBE_CORNER_CONE = 42.28    #: equivalent cone half-angle, degrees
BETA_TRIANGULAR = 1.034     #: King (1987), three-sided pyramids
EPS_CONE = 2.0 * (math.pi - 2.0) / math.pi   #: 0.7268... (Sneddon cone)
EPS_PARABOLOID = 0.75       #: recommended for Berkovich (Oliver & Pharr 1992)
EPS_FLAT = 1.0
HALF_ANGLE_RANGE = (1.0, 89.0)   #: degrees: cones outside this are not indenters
LENGTH_RANGE = (1e-10, 1e-2)     #: tip radius, m

#: fused silica, the usual area-function reference (E = 72 GPa, nu = 0.17)
FUSED_SILICA = ElasticPlastic(72e9, 0.17, name="fused silica")


def epsilon_from_exponent(m):
    """Pharr-Bolshakov geometry constant for an unloading exponent m in (1, 10].

    eps(m) = m [1 - 2 Gamma(m / (2 (m - 1))) (m - 1) / (sqrt(pi) Gamma(1 / (2 (m - 1))))]
    (Pharr & Bolshakov, J. Mater. Res. 17 (2002) 2660): 0.750 at m = 1.5, 0.7268 at m = 2;
    it tends to 1 (flat punch) as m -> 1.
    """
    m = check_real("unloading exponent m", m, low=1.0, high=10.0, low_open=True)
    ratio = math.exp(math.lgamma(m / (2.0 * (m - 1.0))) - math.lgamma(1.0 / (2.0 * (m - 1.0))))
    return float(m * (1.0 - 2.0 * ratio * (m - 1.0) / math.sqrt(math.pi)))


def beta_hay(half_angle, nu):
    """Hay-Bolshakov-Pharr (1999) beta of a cone of `half_angle` degrees on a sample of ratio nu.

    theta > 60 deg: beta = pi (pi/4 + 0.15483073 cot(theta) g) / (pi/2 - 0.83119312 cot(theta)
    g)^2 with g = (1 - 2 nu) / (4 (1 - nu)); theta <= 60 deg: beta = 1 + g' with
    g' = (1 - 2 nu) / (4 (1 - nu) tan(theta)). 1.067 at 70.3 deg and nu = 0.3.
    """
    theta = math.radians(check_real("half_angle", half_angle, low=HALF_ANGLE_RANGE[0],
                                    high=HALF_ANGLE_RANGE[1], unit="deg"))
    nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True)
    g = (1.0 - 2.0 * nu) / (4.0 * (1.0 - nu))
    if theta <= math.radians(60.0):
        return 1.0 + g / math.tan(theta)
    cot = 1.0 / math.tan(theta)
    return math.pi * (math.pi / 4 + 0.15483073 * cot * g) / (math.pi / 2 - 0.83119312 * cot * g)**2


def beta_no_slip(nu):
    """Borodich-Keer (2004) no-slip beta = (1 - nu) ln(3 - 4 nu) / (1 - 2 nu); 1 at nu = 0.5."""
    nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True)
    if abs(0.5 - nu) < 1e-9:
        return 1.0
    return (1.0 - nu) * math.log(3.0 - 4.0 * nu) / (1.0 - 2.0 * nu)


@dataclass(frozen=True)
class Tip:
    """Base class: subclasses define ``area`` and ``area_derivative`` (SI)."""

    #: the textual form this tip is parsed from (``berkovich``, ``cone:70.3``, ...)
    spec: str = field(init=False, default="")
    epsilon: float = field(init=False, default=EPS_PARABOLOID)
    beta: float = field(init=False, default=1.0)

    @property
    def half_angle(self) -> float | None:
        """Equivalent cone half-angle, degrees (None for a sphere or a flat punch)."""
        return None

    def area(self, h_c):
        raise NotImplementedError

    def area_derivative(self, h_c):
        raise NotImplementedError

    def describe(self) -> dict:
        return {"tip": self.spec, "epsilon": self.epsilon, "beta": self.beta,
                "half_angle": self.half_angle}

    def __str__(self) -> str:
        """The text form `parse_tip` reads back (``sphere:5e-06``, ``berkovich``, ...)."""
        return self.spec


def _depth(h_c):
    return np.clip(np.asarray(h_c, dtype=float), 0.0, None)


@dataclass(frozen=True)
class Cone(Tip):
    """A cone (or a pyramid through its equivalent cone): A = k h_c^2 with k = pi tan^2(theta).

    With a flat truncation of radius r0 at the apex (what LAMMPS ``fix indent cone`` builds),
    A = k (h_c + h_0)^2 with h_0 = r0 / tan(theta): pi r0^2 at h_c = 0 for a cone, and the
    sharp area times (1 + h_0/h_c)^2 deeper.

    Parameters
    ----------
    half_angle : float
        Half-angle, degrees.
    area_coefficient : float or None
        k in A = k h_c^2; None gives the cone's pi tan^2(theta).
    name : str
        ``cone``, ``berkovich`` or ``cube-corner``: sets the defaults of eps (0.727 for a cone,
        0.75 for pyramids, Oliver & Pharr 1992) and beta (1 for a cone, 1.034 for three-sided
        pyramids, King 1987).
    eps_r : float or None
        Representative plastic strain of the sharp-indentation (Dao) analysis, in (0, 1].
    pi1 : tuple of 4 floats or None
        (A, B, C, D) of Pi1_theta = C / sigma_r = A x^3 + B x^2 + C x + D with
        x = ln(E*/sigma_r).
    c_star : float or None
        c* in dP/dh = c* E* sqrt(A_m).
    tip_radius : float
        Radius r0 of the flat truncation at the apex, m (0: sharp).

    ``eps_r``, ``pi1`` and ``c_star`` calibrate the reverse analysis
    (`filmscale.continuum.indentation.reverse`); None uses the published calibration for this
    angle (Dao et al. 2001 for Berkovich and 70.3 deg, Chollacoop et al. 2003 for 50-80 deg,
    none for the cube corner).
    """

    half_angle_deg: float = 70.3
    area_coefficient: float | None = None
    name: str = "cone"
    eps_r: float | None = None
    pi1: tuple[float, float, float, float] | None = None
    c_star: float | None = None
    tip_radius: float = 0.0

    def __post_init__(self):
        theta = check_real("cone half_angle", self.half_angle_deg, low=HALF_ANGLE_RANGE[0],
                           high=HALF_ANGLE_RANGE[1], unit="deg")
        object.__setattr__(self, "half_angle_deg", theta)
        k = self.area_coefficient
        if k is None:
            k = math.pi * math.tan(math.radians(theta))**2
        object.__setattr__(self, "area_coefficient", check_positive("area coefficient", k))
        r0 = check_real("cone tip_radius", self.tip_radius, low=0.0, high=LENGTH_RANGE[1],
                        unit="m")
        object.__setattr__(self, "tip_radius", r0)
        self._check_calibration()
        pyramid = self.name in ("berkovich", "cube-corner")
        spec = self.name if pyramid else f"cone:{theta:g}"
        if r0 > 0:
            spec += f":{r0:g}"
        object.__setattr__(self, "spec", spec)
        object.__setattr__(self, "epsilon", EPS_PARABOLOID if pyramid else EPS_CONE)
        object.__setattr__(self, "beta", BETA_TRIANGULAR if pyramid else 1.0)

    def _check_calibration(self):
        if self.eps_r is not None:
            object.__setattr__(self, "eps_r", check_real("tip eps_r", self.eps_r, low=0.0,
                                                         high=1.0, low_open=True))
        if self.c_star is not None:
            object.__setattr__(self, "c_star", check_positive("tip c_star", self.c_star))
        if self.pi1 is not None:
            coeffs = tuple(self.pi1) if isinstance(self.pi1, (tuple, list)) else ()
            if len(coeffs) != 4:
                raise InputError(f"tip pi1 must be 4 numbers (A, B, C, D), got {self.pi1!r}")
            object.__setattr__(self, "pi1", tuple(check_real(f"tip pi1[{i}]", c)
                                                  for i, c in enumerate(coeffs)))

    @property
    def half_angle(self) -> float:
        return self.half_angle_deg

    @property
    def truncation_depth(self) -> float:
        """h_0 = r0 / tan(theta), m: the depth the truncation removes from the apex."""
        return self.tip_radius / math.tan(math.radians(self.half_angle_deg))

    def area(self, h_c):
        return self.area_coefficient * (_depth(h_c) + self.truncation_depth)**2

    def area_derivative(self, h_c):
        return 2.0 * self.area_coefficient * (_depth(h_c) + self.truncation_depth)

    def describe(self) -> dict:
        return {**super().describe(), "tip_radius": self.tip_radius}


def berkovich() -> Cone:
    """Ideal Berkovich: A = 24.494 h_c^2, equivalent cone 70.30 deg."""
    return Cone(BERKOVICH_CONE, BERKOVICH_AREA, "berkovich")


def cube_corner() -> Cone:
    """Ideal cube corner: A = 2.598 h_c^2, equivalent cone 42.28 deg."""
    return Cone(CUBE_CORNER_CONE, CUBE_CORNER_AREA, "cube-corner")


@dataclass(frozen=True)
class Sphere(Tip):
    """Spherical cap of radius R (m): A = pi (2 R h_c - h_c^2), pi R^2 beyond h_c = R."""

    R: float = 1e-6

    def __post_init__(self):
        object.__setattr__(self, "R", check_real("sphere radius R", self.R, low=LENGTH_RANGE[0],
                                                 high=LENGTH_RANGE[1], unit="m"))
        object.__setattr__(self, "spec", f"sphere:{self.R:g}")
        object.__setattr__(self, "epsilon", EPS_PARABOLOID)

    def area(self, h_c):
        h = np.minimum(_depth(h_c), self.R)
        return math.pi * (2.0 * self.R * h - h * h)

    def area_derivative(self, h_c):
        h = np.minimum(_depth(h_c), self.R)
        return 2.0 * math.pi * (self.R - h)


@dataclass(frozen=True)
class SphericalCone(Tip):
    """A cone of half-angle theta whose apex is a sphere of radius R, tangent at h_a.

    A = pi (2 R h_c - h_c^2) for h_c <= h_a = R (1 - sin theta); beyond,
    A = pi tan^2(theta) (h_c + h_0)^2 with h_0 = R (1/sin theta - 1). A and dA/dh are
    continuous at h_a (theta = 70.3 deg, R = 250 nm: h_a = 14.63 nm).
    """

    R: float = 100e-9
    half_angle_deg: float = BERKOVICH_CONE

    def __post_init__(self):
        object.__setattr__(self, "R", check_real("tip radius R", self.R, low=LENGTH_RANGE[0],
                                                 high=LENGTH_RANGE[1], unit="m"))
        theta = check_real("spherical-cone half_angle", self.half_angle_deg,
                           low=HALF_ANGLE_RANGE[0], high=HALF_ANGLE_RANGE[1], unit="deg")
        object.__setattr__(self, "half_angle_deg", theta)
        object.__setattr__(self, "spec", f"sphero-conical:{self.R:g}:{theta:g}")
        object.__setattr__(self, "epsilon", EPS_PARABOLOID)

    @property
    def half_angle(self) -> float:
        return self.half_angle_deg

    @property
    def transition_depth(self) -> float:
        """h_a = R (1 - sin theta), m."""
        return self.R * (1.0 - math.sin(math.radians(self.half_angle_deg)))

    @property
    def _offset(self) -> float:
        return self.R * (1.0 / math.sin(math.radians(self.half_angle_deg)) - 1.0)

    def area(self, h_c):
        h = _depth(h_c)
        tan2 = math.tan(math.radians(self.half_angle_deg))**2
        return np.where(h <= self.transition_depth, math.pi * (2.0 * self.R * h - h * h),
                        math.pi * tan2 * (h + self._offset)**2)

    def area_derivative(self, h_c):
        h = _depth(h_c)
        tan2 = math.tan(math.radians(self.half_angle_deg))**2
        return np.where(h <= self.transition_depth, 2.0 * math.pi * (self.R - h),
                        2.0 * math.pi * tan2 * (h + self._offset))


@dataclass(frozen=True)
class FlatPunch(Tip):
    """Cylindrical flat punch of radius a (m): A = pi a^2 at any depth, eps = 1."""

    radius: float = 1e-6

    def __post_init__(self):
        object.__setattr__(self, "radius", check_real("punch radius", self.radius,
                                                      low=LENGTH_RANGE[0], high=LENGTH_RANGE[1],
                                                      unit="m"))
        object.__setattr__(self, "spec", f"flat:{self.radius:g}")
        object.__setattr__(self, "epsilon", EPS_FLAT)

    def area(self, h_c):
        return np.full(np.shape(h_c), math.pi * self.radius**2)

    def area_derivative(self, h_c):
        return np.zeros(np.shape(h_c))


#: exponents of the polynomial area function: h^2, h, h^(1/2), ..., h^(1/128)
POLYNOMIAL_EXPONENTS = tuple(2.0 ** (1 - k) for k in range(9))


@dataclass(frozen=True)
class PolynomialArea(Tip):
    """Oliver-Pharr area function A = C0 h^2 + C1 h + C2 h^(1/2) + ... + C8 h^(1/128).

    Coefficients in SI: C_k in m^(2 - 2^(1-k)). ``base`` is the nominal tip (its
    half-angle, eps and beta are kept). ``h_range`` (m) is the range of contact depths it was
    calibrated on, when known: analyses flag contact depths outside it.
    """

    coefficients: tuple = (BERKOVICH_AREA,)
    base: Tip = field(default_factory=berkovich)
    h_range: tuple | None = None

    def __post_init__(self):
        coef = tuple(float(c) for c in self.coefficients)
        if not 1 <= len(coef) <= 9 or not all(math.isfinite(c) for c in coef):
            raise InputError(f"area function needs 1 to 9 finite coefficients C0..C8, "
                             f"got {self.coefficients!r}")
        object.__setattr__(self, "coefficients", coef)
        if self.h_range is not None:
            lo, hi = (float(v) for v in self.h_range)
            if not 0.0 <= lo < hi:
                raise InputError(f"area function h_range = {self.h_range!r} must be "
                                 "(low, high) depths with 0 <= low < high, m")
            object.__setattr__(self, "h_range", (lo, hi))
        object.__setattr__(self, "spec", f"{self.base.spec}+polynomial")
        object.__setattr__(self, "epsilon", self.base.epsilon)
        object.__setattr__(self, "beta", self.base.beta)

    @property
    def half_angle(self):
        return self.base.half_angle

    def area(self, h_c):
        h = _depth(h_c)
        return sum(c * h**p for c, p in zip(self.coefficients, POLYNOMIAL_EXPONENTS))

    def area_derivative(self, h_c):
        h = np.maximum(_depth(h_c), 1e-300)
        return sum(c * p * h**(p - 1.0) for c, p in zip(self.coefficients, POLYNOMIAL_EXPONENTS))

    def describe(self) -> dict:
        return {**super().describe(), "coefficients": list(self.coefficients)}


def reference_areas(S, *, beta=BETA_TRIANGULAR, reference=FUSED_SILICA, indenter=DIAMOND):
    """Areas (m^2) implied by stiffnesses S (N/m) on a reference of known modulus.

    A_i = (pi / 4) (S_i / (beta E_r))^2 with E_r of the reference against the indenter.
    """
    S = np.asarray(S, dtype=float)
    E_r = reference.reduced_modulus(indenter)
    return math.pi / 4.0 * (S / (beta * E_r))**2


def _reference_indents(h_c, S):
    h_c, S = np.asarray(h_c, dtype=float), np.asarray(S, dtype=float)
    if h_c.ndim != 1 or h_c.shape != S.shape:
        raise InputError(f"h_c and S must be 1-D arrays of one length, got shapes "
                         f"{h_c.shape} and {S.shape}")
    for name, v in (("h_c", h_c), ("S", S)):
        if not np.all(np.isfinite(v) & (v > 0)):
            raise InputError(f"reference indents: every {name} must be finite and > 0")
    return h_c, S


def calibrate_area_function(h_c, S, *, terms=4, base=None, fix_C0=True, beta=None,
                            reference=FUSED_SILICA, indenter=DIAMOND) -> PolynomialArea:
    """Fit the polynomial area function to reference indents (Oliver & Pharr 1992).

    Parameters
    ----------
    h_c, S : array_like
        Contact depth (m) and unloading stiffness (N/m) of indents on the reference, made
        with the frame compliance already removed.
    terms : int
        Number of coefficients C0..C(terms-1), 1 to 9; at most one fewer than the indents.
    base : Tip
        Nominal tip; Berkovich by default.
    fix_C0 : bool
        Keep C0 at the nominal tip's area coefficient (the usual practice: the other terms
        describe the blunting) instead of fitting it.
    beta : float
        beta of E_r = sqrt(pi) S / (2 beta sqrt(A)); the base tip's by default.
    reference, indenter : ElasticPlastic
        The reference material (fused silica, E = 72 GPa, nu = 0.17) and the indenter.

    The fit minimises the relative area error, so shallow and deep indents weigh alike.
    """
    h_c, S = _reference_indents(h_c, S)
    base = berkovich() if base is None else base
    terms = int(check_real("terms", terms, low=1, high=9))
    free = terms - 1 if fix_C0 else terms
    if h_c.size < free + 1:
        raise InputError(f"{h_c.size} reference indents cannot fit {free} free area "
                         f"coefficients: give at least {free + 1} indents or fewer terms")
    if not isinstance(base, Cone) and fix_C0:
        raise InputError("fix_C0 needs a conical or pyramidal base tip with an area coefficient")
    A = reference_areas(S, beta=base.beta if beta is None else beta, reference=reference,
                        indenter=indenter)
    powers = np.stack([h_c**p for p in POLYNOMIAL_EXPONENTS[:terms]], axis=1) / A[:, None]
    target = np.ones_like(A)
    if fix_C0:
        c0 = base.area_coefficient
        coef = _scaled_lstsq(powers[:, 1:], target - c0 * powers[:, 0])
        coef = np.concatenate([[c0], coef])
    else:
        coef = _scaled_lstsq(powers, target)
    return PolynomialArea(tuple(coef), base)


def _scaled_lstsq(M, y) -> np.ndarray:
    """Least squares with every column scaled to unit norm first: the columns h^2/A ...
    h^(1/128)/A span ten orders of magnitude in SI, and lstsq's cut-off of small singular
    values would otherwise drop the terms that matter."""
    norms = np.linalg.norm(M, axis=0)
    norms[norms == 0] = 1.0
    return np.linalg.lstsq(M / norms, y, rcond=None)[0] / norms


def fit_tip_radius(h_c, S, *, half_angle=BERKOVICH_CONE, beta=BETA_TRIANGULAR,
                   reference=FUSED_SILICA, indenter=DIAMOND,
                   bounds=(1e-9, 10e-6)) -> SphericalCone:
    """Radius R (m) of a spherical-conical tip from reference indents.

    Minimises the summed squared relative error between the tip's A(h_c) and the areas
    A_i = (pi/4) (S_i / (beta E_r))^2 implied by the reference's known modulus; R is searched
    in log space within ``bounds`` (m).
    """
    from scipy.optimize import minimize_scalar
    h_c, S = _reference_indents(h_c, S)
    A = reference_areas(S, beta=beta, reference=reference, indenter=indenter)
    lo = check_real("tip radius lower bound", bounds[0], low=LENGTH_RANGE[0], high=LENGTH_RANGE[1])
    hi = check_real("tip radius upper bound", bounds[1], low=lo, high=LENGTH_RANGE[1],
                    low_open=True)

    def misfit(log_r):
        model = SphericalCone(math.exp(log_r), half_angle).area(h_c)
        return float(np.sum((model / A - 1.0)**2))

    best = minimize_scalar(misfit, bounds=(math.log(lo), math.log(hi)), method="bounded",
                           options={"xatol": 1e-8})
    return SphericalCone(math.exp(best.x), half_angle)


_LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9}
_NUMBER = re.compile(r"^\s*([0-9.eE+-]+)\s*([a-zµ]*)\s*$")
TIP_FORMS = ("berkovich[:R0]", "cube-corner[:R0]", "cone:THETA[:R0]", "sphere:R",
             "sphero-conical:R[:THETA]", "flat:RADIUS")


def parse_length(text: str, what: str) -> float:
    """A length in m from text such as 250nm, 5um, 2e-6 (m when no unit), or any length
    pint reads ("5 µm", "0.5 mil")."""
    match = _NUMBER.match(text)
    if match and match.group(2) in ("", *_LENGTH_UNITS):
        try:        # the common units without pint: tips are parsed once per curve
            return float(match.group(1)) * _LENGTH_UNITS.get(match.group(2) or "m")
        except ValueError:
            pass
    return to_si(what, text, "m")


def _truncation(text: str) -> float:
    return parse_length(text, "cone tip_radius")


def parse_tip(spec: str) -> Tip:
    """A tip from its text: berkovich, cube-corner, cone:70.3, sphere:5um,
    sphero-conical:250nm:70.3, flat:1um. Lengths are in m unless a unit (nm, um, mm) follows;
    angles in degrees. A cone or pyramid may end in the radius r0 of a flat truncation at its
    apex: cone:70.3:0.2nm, cone:70.3:2e-10, berkovich:5nm."""
    if isinstance(spec, Tip):
        return spec
    if not isinstance(spec, str):
        raise InputError(f"tip must be text such as {', '.join(TIP_FORMS)}, got {spec!r}")
    name, _, rest = spec.strip().lower().partition(":")
    args = rest.split(":") if rest else []
    try:
        if name in ("berkovich", "cube-corner") and len(args) <= 1:
            tip = berkovich() if name == "berkovich" else cube_corner()
            return replace(tip, tip_radius=_truncation(args[0])) if args else tip
        if name == "cone" and len(args) in (1, 2):
            return Cone(float(args[0]), tip_radius=_truncation(args[1]) if len(args) == 2 else 0.0)
        if name == "sphere" and len(args) == 1:
            return Sphere(parse_length(args[0], "sphere radius"))
        if name == "sphero-conical" and len(args) in (1, 2):
            angle = float(args[1]) if len(args) == 2 else BERKOVICH_CONE
            return SphericalCone(parse_length(args[0], "tip radius"), angle)
        if name == "flat" and len(args) == 1:
            return FlatPunch(parse_length(args[0], "punch radius"))
    except InputError:
        raise
    except ValueError:      # float() of a malformed angle
        pass
    raise InputError(f"tip = {spec!r} is not one of: {', '.join(TIP_FORMS)}")
