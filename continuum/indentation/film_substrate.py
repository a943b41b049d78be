"""A film's Young's modulus from indents that feel the substrate under it.

An indent into a film of thickness t on a substrate measures an apparent modulus between the
film's and the substrate's, weighted by how deep the elastic field reaches: the contact
radius a against t. Read as a depth profile, that trend looks like a size effect; a film /
substrate model reads it as what it is and returns the film's own modulus.

Every model gives the apparent plane-strain modulus E'_app (Pa) that a rigid indenter of
contact radius a sees; the measured reduced modulus is E_r = 1 / (1/E'_app + C_tip), with
C_tip = (1 - nu_i^2)/E_i the indenter's compliance (diamond by default), as
`TableProfile.from_measurements` removes it. E' = E/(1 - nu^2), mu = E/(2(1 + nu)).

- ``king``: King, Int. J. Solids Struct. 23 (1987) 1657, the Doerner-Nix form with t/a,

      1/E'_app = (1/E'_f)(1 - exp(-alpha t/a)) + (1/E'_s) exp(-alpha t/a).

  alpha(a/t) is King's: the value for which this formula gives the compliance of a rigid
  circular flat punch on the layered half-space, which King found to depend on a/t and the
  punch's shape but little on the moduli. King's table is not used here (it was not at hand
  to transcribe); `king_alpha` takes alpha in the limit of a small modulus mismatch, where
  the layered solution's compliance is, to first order, Gao's weighted one (Gao, Chiu & Lee,
  Int. J. Solids Struct. 29 (1992) 2471): exp(-alpha t/a) = 1 - I0(t/a), i.e.

      alpha(a/t) = -(a/t) ln(1 - I0(t/a, nu_a)),

  about 0.26 at a/t = 0.1, 0.60 at a/t = 1 and 0.69 at a/t = 3 (nu = 0.3). Against the
  layered flat-punch solution at a 2 % mismatch it is within 0.4 % for a/t <= 3 (tests).
- ``saha-nix``: Saha & Nix, Acta Mater. 50 (2002) 23: King's with t replaced by t - h_c
  (the film left under the tip), also in alpha's argument; an indent with h_c >= t sees
  the substrate alone.
- ``hay-crawford``: Hay & Crawford, J. Mater. Res. 26 (2011) 727, in shear moduli,

      1/mu_a = (1 - I0)/(mu_s + f I0 mu_f) + I0/mu_f,   f = 0.0626,

  I0 = I0(t/a, nu_a) Gao's weight (`profiles.gao_i0`) and E'_app = 2 mu_a/(1 - nu_a).
- ``exact``: the layered-elasticity solution of a film bonded to the substrate
  (`filmscale.continuum.contact.coated.apparent_modulus`: S/(2a) of the flat punch of radius
  a, which is the stiffness of any axisymmetric indenter at contact radius a).

nu_a is Gao's composite Poisson ratio, 1/(1 - nu_a) = I1/(1 - nu_f) + (1 - I1)/(1 - nu_s),
I1 = I1(t/a) (`profiles.gao_i1`); it equals both when film and substrate share one.

`film_modulus` fits E_f, the single unknown, by least squares of the model's E_r over the
indents with h_c >= t/10 (`MIN_DEPTH_FRACTION`): the range these models are for, where the
substrate is felt; shallower indents measure the film alone (Buckle's rule) and add nothing
on the substrate's share. The unknown is ln E_f, bounded; its standard error is
s^2 (J^T J)^-1 with s^2 the residuals' mean square over n - 1 degrees of freedom.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from filmscale.continuum.contact.profiles import gao_i0, gao_i1
from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError

#: the film / substrate models, in the order of the module docstring
FILM_MODELS = ("king", "saha-nix", "hay-crawford", "exact")
#: the fit takes the indents with h_c at least this fraction of the film thickness
MIN_DEPTH_FRACTION = 0.1
#: Hay & Crawford's empirical constant
HAY_CRAWFORD_F = 0.0626
#: bounds of the film's Young's modulus in the fit, Pa
E_BOUNDS = (1e6, 1e14)


def composite_poisson(x, nu_f: float, nu_s: float):
    """Gao's composite Poisson ratio at x = t/a:
    1/(1 - nu) = I1/(1 - nu_f) + (1 - I1)/(1 - nu_s)."""
    w = gao_i1(np.asarray(x, dtype=float))
    return 1.0 - 1.0 / (w / (1.0 - nu_f) + (1.0 - w) / (1.0 - nu_s))


def king_alpha(a_over_t, nu=0.3):
    """King's alpha at a/t in the small-mismatch limit (module docstring):
    -(a/t) ln(1 - I0(t/a, nu)), nu the composite Poisson ratio (a/t clipped to 1e-9-1e6)."""
    r = np.clip(np.asarray(a_over_t, dtype=float), 1e-9, 1e6)
    rest = 1.0 - gao_i0(1.0 / r, nu)
    return -r * np.log(np.clip(rest, 1e-300, 1.0))


def _exp_weight(x, nu_a):
    """exp(-alpha t/a) of King's formula at x = t/a (0 where x is infinite, 1 at x = 0)."""
    x = np.asarray(x, dtype=float)
    safe = np.where(x > 0, x, 1.0)
    # alpha t/a = -ln(1 - I0(x)) exactly: exp of it is 1 - I0(x)
    return np.where(x > 0, 1.0 - gao_i0(safe, nu_a), 1.0)


def model_modulus(model: str, a, h_c, *, thickness: float, film: ElasticPlastic,
                  substrate: ElasticPlastic) -> np.ndarray:
    """The apparent plane-strain modulus E'_app (Pa) of ``model`` that a rigid indenter of
    contact radius ``a`` (m) at contact depth ``h_c`` (m) sees on ``film`` of ``thickness``
    (m) bonded to ``substrate`` (equations: module docstring)."""
    model = check_choice("film model", model, FILM_MODELS)
    a, h_c = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(h_c, dtype=float))
    t = float(thickness)
    ef, es = film.plane_strain_modulus, substrate.plane_strain_modulus
    if model == "exact":
        from filmscale.continuum.contact.coated import apparent_modulus
        flat = np.array([apparent_modulus(float(r), t, film, substrate)
                         for r in a.ravel()], dtype=float)
        return flat.reshape(a.shape)
    t_eff = np.maximum(t - h_c, 0.0) if model == "saha-nix" else np.full(a.shape, t)
    x = t_eff / a
    nu_a = composite_poisson(x, film.nu, substrate.nu)
    if model in ("king", "saha-nix"):
        w = _exp_weight(x, nu_a)
        return 1.0 / ((1.0 - w) / ef + w / es)
    # hay-crawford
    i0 = np.where(x > 0, gao_i0(np.where(x > 0, x, 1.0), nu_a), 0.0)
    mu_f, mu_s = film.shear_modulus, substrate.shear_modulus
    mu_a = 1.0 / ((1.0 - i0) / (mu_s + HAY_CRAWFORD_F * i0 * mu_f) + i0 / mu_f)
    return 2.0 * mu_a / (1.0 - nu_a)


@dataclass(frozen=True)
class FilmModulus:
    """A film's Young's modulus fitted by a film / substrate model (`film_modulus`)."""

    model: str
    E: float                  #: the film's Young's modulus, Pa
    E_std: float              #: its standard error, Pa (inf when the indents do not fix it)
    nu: float                 #: the film's Poisson ratio, assumed
    points: int               #: indents fitted
    residual_rms: float       #: rms of the E_r residuals, Pa
    depth_range: tuple        #: (lowest, deepest) h_c fitted, m
    thickness: float          #: film thickness, m
    substrate_E: float        #: Pa
    substrate_nu: float
    indenter_compliance: float  #: (1 - nu_i^2)/E_i removed from E_r, 1/Pa (0: rigid)
    min_depth: float          #: indents shallower than this were left out, m
    h_c: np.ndarray = field(repr=False)        #: contact depths fitted, m
    a: np.ndarray = field(repr=False)          #: their contact radii, m
    E_r: np.ndarray = field(repr=False)        #: their measured reduced moduli, Pa
    residuals: np.ndarray = field(repr=False)  #: model minus measured E_r, Pa
    skipped: int = 0          #: indents outside the model's range

    @property
    def film(self) -> ElasticPlastic:
        return ElasticPlastic(self.E, self.nu, name="film")

    @property
    def substrate(self) -> ElasticPlastic:
        return ElasticPlastic(self.substrate_E, self.substrate_nu, name="substrate")

    def reduced_modulus(self, a, h_c) -> np.ndarray:
        """The model's E_r (Pa, against the indenter) at contact radius a and depth h_c (m)."""
        # the fitted E may sit at a bound of `E_BOUNDS`, outside the plausible range: the
        # model curve is still drawn (`ElasticPlastic._trial`)
        film = ElasticPlastic._trial(self.E, self.nu, name="film")
        substrate = ElasticPlastic._trial(self.substrate_E, self.substrate_nu, name="substrate")
        e = model_modulus(self.model, a, h_c, thickness=self.thickness, film=film,
                          substrate=substrate)
        return 1.0 / (1.0 / e + self.indenter_compliance)

    def to_dict(self) -> dict:
        return {"model": self.model, "E": self.E, "E_std": self.E_std, "nu": self.nu,
                "points": self.points, "skipped": self.skipped,
                "residual_rms": self.residual_rms,
                "depth_range": [float(v) for v in self.depth_range],
                "min_depth": self.min_depth, "thickness": self.thickness,
                "substrate": {"E": self.substrate_E, "nu": self.substrate_nu},
                "indenter_compliance": self.indenter_compliance,
                "h_c": self.h_c.tolist(), "a": self.a.tolist(), "E_r": self.E_r.tolist(),
                "residuals": self.residuals.tolist()}

    def summary(self) -> str:
        lo, hi = self.depth_range
        std = "-" if not math.isfinite(self.E_std) else f"{self.E_std / 1e9:.2g}"
        tenth = " = t/10" if math.isclose(self.min_depth, MIN_DEPTH_FRACTION * self.thickness) \
            else ""
        return (f"film ({self.model}, t = {self.thickness * 1e9:.4g} nm on E_s = "
                f"{self.substrate_E / 1e9:.4g} GPa, nu_s = {self.substrate_nu:g}): "
                f"E = {self.E / 1e9:.4g} +- {std} GPa (nu = {self.nu:g}), {self.points} "
                f"indents with h_c {lo * 1e9:.4g}-{hi * 1e9:.4g} nm (h_c >= "
                f"{self.min_depth * 1e9:.4g} nm{tenth}), residual rms "
                f"{self.residual_rms / 1e9:.2g} GPa in E_r")


def film_modulus(h_c, E_r, a=None, *, thickness: float, substrate: ElasticPlastic,
                 model: str = "king", nu: float = 0.3,
                 indenter: ElasticPlastic | None = DIAMOND, tip=None,
                 min_depth: float | None = None) -> FilmModulus:
    """The film's Young's modulus from indents at contact depths ``h_c`` (m) with reduced
    moduli ``E_r`` (Pa, against ``indenter``; None: a rigid one) and contact radii ``a`` (m;
    a = sqrt(A_c/pi)), on a film of ``thickness`` (m) bonded to ``substrate``, by ``model``
    (one of `FILM_MODELS`). Without ``a`` the radii come from ``tip`` (a `Tip`, or text such
    as "berkovich") and h_c: a = sqrt(tip.area(h_c)/pi). ``nu`` is the film's Poisson ratio.

    Fitted: the indents with h_c >= ``min_depth`` (default t/10, `MIN_DEPTH_FRACTION`), and
    for saha-nix h_c < t (deeper ones are the substrate's alone). InputError with fewer than
    2 such indents.
    """
    model = check_choice("film model", model, FILM_MODELS)
    t = check_real("film thickness", thickness, low=0.0, high=1.0, low_open=True, unit="m")
    if not isinstance(substrate, ElasticPlastic):
        raise InputError(f"substrate must be an ElasticPlastic material, got "
                         f"{type(substrate).__name__}")
    nu = check_real("film nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    h_c = np.asarray(h_c, dtype=float).ravel()
    E_r = np.asarray(E_r, dtype=float).ravel()
    if a is None:
        if tip is None:
            raise InputError("film_modulus needs the contact radii a or the tip that gives "
                             "them from h_c")
        if isinstance(tip, str):
            from .tips import parse_tip
            tip = parse_tip(tip)
        a = np.sqrt(np.asarray(tip.area(h_c), dtype=float) / math.pi)
    a = np.asarray(a, dtype=float).ravel()
    if not (h_c.size == E_r.size == a.size):
        raise InputError(f"h_c, E_r and a differ in length: {h_c.size}, {E_r.size}, {a.size}")
    compliance = 0.0 if indenter is None else indenter.compliance
    ok = np.isfinite(h_c) & np.isfinite(E_r) & np.isfinite(a) & (h_c > 0) & (E_r > 0) & (a > 0)
    ok &= 1.0 / np.where(E_r > 0, E_r, np.inf) > compliance
    lowest = t * MIN_DEPTH_FRACTION if min_depth is None else \
        check_real("min_depth", min_depth, low=0.0, unit="m")
    use = ok & (h_c >= lowest)
    if model == "saha-nix":
        use &= h_c < t
    n = int(use.sum())
    if n < 2:
        extra = " and h_c < t" if model == "saha-nix" else ""
        raise InputError(f"film model {model}: {n} indent(s) with h_c >= {lowest * 1e9:.4g} nm "
                         f"(the film is {t * 1e9:.4g} nm thick){extra}; the fit needs at "
                         f"least 2 indents that feel the substrate")
    hs, es, rs = h_c[use], E_r[use], a[use]

    def predict(log_e):
        # trial moduli span E_BOUNDS (1 MPa - 100 TPa), beyond the plausible range; exp of
        # the log of the upper bound may round above it
        film = ElasticPlastic._trial(min(math.exp(float(log_e)), E_BOUNDS[1]), nu,
                                     name="film")
        e = model_modulus(model, rs, hs, thickness=t, film=film, substrate=substrate)
        return 1.0 / (1.0 / e + compliance)

    # the start: the best of a coarse scan of ln E_f, a factor 30 either side of the
    # indents' median modulus (the model's E_r rises with E_f: the minimum is bracketed)
    lo, hi = math.log(E_BOUNDS[0]), math.log(E_BOUNDS[1])
    e_p = 1.0 / (1.0 / es - compliance)
    centre = math.log(float(np.median(e_p)) * (1.0 - nu**2))
    grid = np.clip(centre + np.linspace(-math.log(30.0), math.log(30.0), 13), lo, hi)
    ssr = [float(np.sum((predict(g) - es) ** 2)) for g in grid]
    k = int(np.argmin(ssr))
    from scipy.optimize import least_squares
    result = least_squares(lambda p: (predict(p[0]) - es) / es.mean(), [grid[k]],
                           bounds=([lo], [hi]), x_scale=[1.0], xtol=1e-12, ftol=1e-12,
                           gtol=1e-12, diff_step=[1e-6])
    log_e = float(result.x[0])
    resid = predict(log_e) - es
    E = min(math.exp(log_e), E_BOUNDS[1])
    # var(ln E_f) = s^2 (J^T J)^-1, J = d E_r / d ln E_f by central differences
    step = 1e-6
    jac = (predict(log_e + step) - predict(log_e - step)) / (2.0 * step)
    jtj = float(jac @ jac)
    s2 = float(resid @ resid) / (n - 1)
    E_std = E * math.sqrt(s2 / jtj) if jtj > 0 else math.inf
    if min(abs(log_e - lo), abs(log_e - hi)) < 1e-6:
        raise InputError(f"film model {model}: the fit ran to the bound E = {E:.4g} Pa: the "
                         f"indents do not fit a film of {t * 1e9:.4g} nm on this substrate")
    return FilmModulus(model, E, E_std, nu, n, float(np.sqrt(np.mean(resid**2))),
                       (float(hs.min()), float(hs.max())), t, substrate.E, substrate.nu,
                       compliance, float(lowest), hs, rs, es, resid,
                       int(ok.sum()) - n)

