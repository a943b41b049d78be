"""What a calibration returns: calibrated parameters with their uncertainty, the layer's
material, and the cross-scale check of the calibrated forward model against its curves."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.spherical import elastic_limit
from filmscale.continuum.materials import ElasticPlastic, modulus_from_reduced
from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError
from filmscale.core.noise import noise_sigma
from filmscale.core.quantities import eng

#: relative standard deviation above which a fitted parameter is reported as not identified
IDENTIFIABLE_RSD = 0.3
#: what a curve point was fitted for (`Calibration.fit_roles`; a point may carry both)
FITS_E, FITS_SIGMA_Y = 1, 2


def _float(x) -> float:
    """A number read back from JSON, where NaN and infinities are written as null."""
    return math.nan if x is None else float(x)


#: a cross-scale check without a stated tolerance passes at this many times the curves' own
#: noise (rms misfit over rms noise: 1 for a model that explains everything but the noise),
#: and never below MIN_TOLERANCE
NOISE_FACTOR, MIN_TOLERANCE = 2.0, 0.005
#: ranges a cross-scale check may leave out: nothing, the loading up to the bottom of the
#: first pop-in, or the pop-in's burst alone (from its peak to its bottom)
EXCLUDES = ("", "pop-in", "burst")


@dataclass(frozen=True)
class Parameter:
    """A calibrated value with one standard deviation (NaN when the data do not bound it)."""

    value: float
    std: float
    unit: str
    identified: bool
    reason: str = ""      #: why not identified, or how the value was fixed
    #: the data bound the value only from below (an elastic curve's sigma_y): shown ">="
    lower_bound: bool = False

    @classmethod
    def from_dict(cls, d: dict) -> Parameter:
        """The parameter `dataclasses.asdict` gave, read back (JSON nulls become NaN)."""
        return cls(**{**d, "value": _float(d["value"]), "std": _float(d["std"])})

    def text(self) -> str:
        tag = "" if self.identified else f"  [not identified: {self.reason}]"
        if math.isnan(self.value):
            return tag.strip()
        bound = ">= " if self.lower_bound else ""
        return bound + eng(self.value, self.unit, std=self.std) + tag


@dataclass(frozen=True)
class Calibration:
    """E, sigma_y and n of one layer, the fit's quality and where they came from."""

    layer: str
    route: str                      #: "sphere", "sharp" or "joint" (several sources)
    E: Parameter
    sigma_y: Parameter
    n: Parameter
    nu: float                       #: Poisson ratio assumed (not fitted)
    uncertainty: str                #: how the standard deviations were obtained
    rms: float                      #: rms misfit / largest load (sphere) or NaN (sharp)
    points: int                     #: load points (sphere) or curves (sharp) used
    sources: tuple[str, ...]
    model: str                      #: contact law or reverse-analysis method
    warnings: tuple[str, ...] = ()
    #: Nix-Gao length of sigma_y (m) when curves at several depths give one; sigma_y is
    #: then the macroscopic (deep) value
    h_star: Parameter | None = None
    #: the source of each fitted curve (joint calibrations; empty: one source)
    curve_sources: tuple[str, ...] = ()
    #: each source's own calibration, as dicts with its ``source`` (joint calibrations)
    components: tuple = ()
    #: the curves' load noise over the largest load when known beyond the curves themselves
    #: (an MD ensemble's seed-to-seed scatter); NaN: estimated from the curves
    curve_noise: float = math.nan
    #: the pop-in statistics of curves with a pop-in (`pop_in.PopInStatistics` as a dict:
    #: the pop-in law's third parameter), or None
    pop_in: dict | None = None
    #: the contact zero h0 (m) of a sphere calibration: the law was evaluated at the approach
    #: h - h0 (0 when the zero was held at the curves' h = 0; an ensemble's: its members' mean)
    contact_zero: float = 0.0
    #: correlation coefficient of the E and sigma_y estimates (0: uncorrelated or unknown;
    #: sphere fits give it from their covariance, an ensemble from its members' scatter)
    correlation: float = 0.0
    #: the curves' load drops were found not followed by yield (an amorphous film's: the
    #: loading climbs back onto the elastic law), so they are no pop-in and the cross-check
    #: does not split the curves at them
    elastic_drops: bool = False
    fitted_curves: tuple = field(default=(), repr=False, compare=False)
    #: per point of each fitted curve, what it was fitted for: a sum of `FITS_E` and
    #: `FITS_SIGMA_Y` (0: not fitted; empty: not recorded)
    fit_roles: tuple = field(default=(), repr=False, compare=False)

    def material(self) -> ElasticPlastic:
        """The calibrated layer as the continuum package's material. A sigma_y that the
        data only bound from below enters as that bound: the layer yields no later than
        the data allow (the conservative side for damage)."""
        return ElasticPlastic(self.E.value, self.nu, self.sigma_y.value, self.n.value,
                              self.layer)

    def to_dict(self) -> dict:
        d = asdict(self)
        d.pop("fitted_curves")
        d.pop("fit_roles")
        return d

    @classmethod
    def from_dict(cls, d: dict, fitted_curves=(), fit_roles=()) -> Calibration:
        """The calibration `to_dict` gave, read back (JSON nulls become NaN)."""
        d = dict(d)
        for key in ("E", "sigma_y", "n", "h_star"):
            if d.get(key) is not None:
                d[key] = Parameter.from_dict(d[key])
        for key in ("sources", "warnings", "curve_sources", "components"):
            d[key] = tuple(d.get(key, ()))
        d["rms"] = _float(d["rms"])
        d["curve_noise"] = _float(d.get("curve_noise"))
        if d.get("pop_in"):
            d["pop_in"] = {k: math.nan if v is None else v for k, v in d["pop_in"].items()}
        return cls(**d, fitted_curves=tuple(fitted_curves), fit_roles=tuple(fit_roles))

    def cross_check(self, tolerance: float | None = None, source: str = "",
                    exclude: str = "") -> CrossCheck:
        """The calibrated forward model (the contact law, or Dao's forward C for sharp tips)
        against every loading point of the curves it was calibrated on (with ``source``:
        that source's curves of a joint calibration): rms misfit over the largest load of
        each curve, passed when at most ``tolerance``.

        ``tolerance`` None: `NOISE_FACTOR` times the curves' own noise (`noise_sigma` of the
        load over its largest value, rms over the curves), at least `MIN_TOLERANCE`: the
        model must explain the curves to within their noise. ``exclude="burst"`` leaves out
        each curve's first pop-in from its peak to the bottom of its load drop, the one part
        the pop-in law (`calibration.pop_in`) does not model; ``exclude="pop-in"`` leaves out
        the loading up to that bottom (the elastic overshoot too), so that the check judges
        the flow after it alone. Curves with a pop-in get the misfit of each part in
        ``parts`` and, when the check fails, the parts that fail and why in ``lacks``."""
        check_choice("exclude", exclude, EXCLUDES)
        curves = [c for i, c in enumerate(self.fitted_curves)
                  if not source or not self.curve_sources or self.curve_sources[i] == source]
        if not curves:
            raise InputError(f"calibration of {self.layer} holds no fitted curves"
                             + (f" of {source}" if source else ""))
        ensemble = math.isfinite(self.curve_noise)
        noise = self.curve_noise if ensemble else float(np.sqrt(np.mean(
            [(noise_sigma(P) / P.max())**2 for h, P, F in curves])))
        if tolerance is None:
            tolerance = max(NOISE_FACTOR * noise, MIN_TOLERANCE)
            basis = (f"{NOISE_FACTOR:g} x the " + ("seed-to-seed scatter" if ensemble else
                                                   "curves' noise") + f" {noise:.2%}")
        else:
            tolerance = check_real("tolerance", tolerance, low=0.0, low_open=True, high=1.0)
            basis = "stated"
        resid, pieces, excluded = [], {"elastic": [], "burst": [], "flow": []}, 0
        for h, P, F in curves:
            r = (F - P) / P.max()
            span = None if self.elastic_drops else pop_in_range(h, P)
            if span is None:
                pieces["flow"].append(r)
            else:
                peak, bottom = span
                pieces["elastic"].append(r[:peak + 1])
                pieces["burst"].append(r[peak + 1:bottom + 1])
                pieces["flow"].append(r[bottom + 1:])
                if exclude:
                    start = 0 if exclude == "pop-in" else peak + 1
                    excluded += bottom + 1 - start
                    r = np.concatenate([r[:start], r[bottom + 1:]])
            resid.append(r)
        resid = np.concatenate(resid)
        if resid.size == 0:
            raise InputError(f"calibration of {self.layer}: excluding the {exclude} range "
                             "leaves no point to check")
        rms = float(np.sqrt(np.mean(resid**2)))
        passed = rms <= tolerance
        parts = {name: float(np.sqrt(np.mean(np.concatenate(v)**2)))
                 for name, v in pieces.items() if v and np.concatenate(v).size}
        lacks = "" if passed or not pieces["elastic"] else _what_fails(parts, tolerance, exclude)
        return CrossCheck(self.model, rms, float(np.max(np.abs(resid))), tolerance, passed,
                          int(resid.size), source, noise, basis, exclude, excluded, lacks,
                          parts if pieces["elastic"] else {})

    def summary(self) -> str:
        lines = [f"Calibration of {self.layer} ({self.route}: {self.model}; "
                 f"uncertainty: {self.uncertainty})",
                 f"  E       = {self.E.text()}",
                 f"  sigma_y = {self.sigma_y.text()}",
                 f"  n       = {self.n.text()}",
                 f"  nu      = {self.nu:g} (assumed)"]
        if not math.isnan(self.rms):
            lines.append(f"  fit: rms misfit {self.rms:.2%} of the largest load over "
                         f"{self.points} points")
        if self.h_star is not None:
            law = "" if math.isnan(self.h_star.value) else " (Nix-Gao: sigma_y sqrt(1 + h*/h))"
            lines.append(f"  h*      = {self.h_star.text()}{law}")
        if self.pop_in:
            p = self.pop_in
            lines.append(f"  pop-in  = {eng(p['load'], 'N', std=p['load_std'])} at "
                         f"{eng(p['depth'], 'm', std=p['depth_std'])}; shear stress "
                         f"{eng(p['shear_stress'], 'Pa', std=p['shear_stress_std'])} "
                         f"({p['members']} members)")
        for c in self.components:
            lines.append(f"  from {c['source']} ({c['route']}): E {eng(c['E']['value'], 'Pa')} "
                         f"alone, {eng(c['E_joint']['value'], 'Pa')} in the joint fit; sigma_y "
                         f"{eng(c['sigma_y']['value'], 'Pa')} alone")
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class CrossCheck:
    """A calibrated parameter set run forward against the curves it came from."""

    model: str
    rms: float            #: rms misfit / largest load
    worst: float          #: largest |misfit| / largest load
    tolerance: float
    passed: bool
    points: int
    source: str = ""      #: the source whose curves were checked ("": all)
    noise: float = math.nan   #: the curves' own load noise / largest load (rms)
    basis: str = ""       #: where the tolerance comes from
    excluded: str = ""    #: the range left out ("pop-in") or ""
    excluded_points: int = 0
    lacks: str = ""       #: what the law lacks, when the check fails for a known reason
    #: rms misfit / largest load of each part of curves with a pop-in: the elastic loading
    #: up to it ("elastic"), the burst ("burst") and the flow after it ("flow")
    parts: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return asdict(self)

    def text(self) -> str:
        verdict = "passed" if self.passed else "FAILED"
        of = f" of {self.source}" if self.source else ""
        out = (f"cross-scale check{of} {verdict}: {self.model} with the calibrated parameters "
               f"reproduces the curves to {self.rms:.1%} rms (worst point {self.worst:.1%}) "
               f"of the largest load; tolerance {self.tolerance:.1%}"
               + (f" ({self.basis})" if self.basis else ""))
        if self.excluded:
            out += f"; {self.excluded_points} points of the {self.excluded} range left out"
        return out + (f"; {self.lacks}" if self.lacks else "")


def pop_in_range(h, P) -> tuple[int, int] | None:
    """(peak, bottom): indices of the last point before the first pop-in (`elastic_limit`)
    and of the bottom of its load drop on a loading record, the first point after the peak
    that has lost 80 % of the load the peak loses at most afterwards (the load then
    fluctuates on its flow plateau); None without a pop-in."""
    peak = elastic_limit(LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int)))
    if peak is None:
        return None
    after = P[peak:]
    return peak, peak + int(np.argmax(after <= after[0] - 0.8 * (after[0] - after.min())))


def pop_in_bottom(h, P) -> int | None:
    """Index of the bottom of the first pop-in's load drop (`pop_in_range`), or None."""
    span = pop_in_range(h, P)
    return None if span is None else span[1]


def _what_fails(parts: dict, tolerance: float, exclude: str) -> str:
    """Which part of curves with a pop-in the forward model misses, and by how much."""
    why = {"elastic": "the elastic loading before the pop-in (a crystal under the "
                      "near-theoretical shear stress softens, which linear elasticity lacks; "
                      "or the law has no pop-in and yields too early)",
           "burst": "the pop-in's burst (the law drops from Hertz to its flow branch in one "
                    "step)",
           "flow": "the flow after the pop-in (a crystal that has just nucleated "
                   "dislocations, not a continuum's hardening)"}
    left_out = {"pop-in": ("elastic", "burst"), "burst": ("burst",)}.get(exclude, ())
    missed = [f"{why[name]}: {rms:.1%} rms" for name, rms in parts.items()
              if name not in left_out and rms > tolerance]
    return ("the model misses " + "; ".join(missed)) if missed else ""


def modulus_parameter(E_star, std_lnE, nu, compliance) -> Parameter:
    E = float(modulus_from_reduced(E_star, nu, compliance))
    dE = E**2 / ((1 - nu**2) * E_star) * std_lnE      # dE/dE* times the std of E*
    return Parameter(E, float(dE), "Pa", bool(std_lnE < IDENTIFIABLE_RSD))
