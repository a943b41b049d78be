"""Frame compliance and tip area function from indents on a reference of known modulus.

Oliver & Pharr, J. Mater. Res. 7 (1992) 1564, sec. IV.B, and 19 (2004) 3, sec. 2.4: the
measured compliance of an indent is the frame's and the contact's in series,

    C_total = C_f + sqrt(pi) / (2 beta E_r sqrt(A(h_c))),

with E_r the reduced modulus of the reference against the indenter. On a reference of known
E_r every indent then gives the area at its contact depth, A_i = (pi/4) (S_i / (beta E_r))^2,
where S_i = 1 / (C_total,i - C_f) is the stiffness of the contact alone, and
h_c,i = h_max,i - C_f P_max,i - eps P_max,i / S_i. Oliver and Pharr iterate between C_f (from
the deepest indents) and the area function A(h_c) = C0 h_c^2 + C1 h_c + C2 h_c^(1/2) + ...;
here the same model is solved as one least-squares problem over one fixed set of indents:
for a trial C_f every indent is frame-corrected (an unloading is fitted again; a CSM point's
stiffness is the contact's in series, 1/S = 1/S_measured - C_f), the area function is fitted
to the implied areas (C0 kept at the nominal tip's unless ``fit_c0``), and C_f minimises the
remaining relative area misfit. C_f is bounded by [0, 0.95 / S_max): beyond it the stiffest
indent would have a negative contact compliance. A trial at which any indent of the set can no
longer be analysed is outside the bounds too, so the objective never changes its indents.

Continuous-stiffness (CSM) tests calibrate from their stiffness at every depth, as NanoSuite's
tip calibration does: each loading point is an indent. The result is judged before it is
used (`TipCalibration.problem`): a misfit beyond what the indents' own scatter explains, or an
area function that is not positive and increasing over the calibrated depths, is refused.

Reference constants (docs/indentation.md, "Calibrating the tip and frame"): fused silica
E = 72.0 GPa, nu = 0.17, and tungsten E = 409.8 GPa, nu = 0.28, the values of Oliver & Pharr
(1992) table I; the diamond indenter E_i = 1141 GPa, nu_i = 0.07 (same paper).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError, ModelRangeError
from filmscale.core.noise import noise_sigma
from filmscale.core.quantities import to_si

from .curves import LoadDisplacementCurve
from .cycles import cycle_curves
from .io import UNITS
from .oliver_pharr import oliver_pharr
from .tips import (FUSED_SILICA, POLYNOMIAL_EXPONENTS, Cone, PolynomialArea,
                   calibrate_area_function, parse_tip, reference_areas)

#: reference materials of Oliver & Pharr (1992) table I
REFERENCES = {
    "fused-silica": FUSED_SILICA,
    "tungsten": ElasticPlastic(409.8e9, 0.28, name="tungsten"),
}
FIT_CHOICES = ("frame", "area", "both")
METHOD_CHOICES = ("auto", "unloading", "csm")
#: the quality gate: a fit is refused above this rms relative area misfit ...
MISFIT_LIMIT = 0.10
#: ... or above this many times the indents' own scatter (but never below `MISFIT_FLOOR`)
SCATTER_FACTOR = 3.0
MISFIT_FLOOR = 0.02
#: a fitted area below this fraction of the ideal tip's (C0 h^2) is refused: wear and
#: blunting add area; an area this far below the ideal pyramid's means a misplaced depth zero
IDEAL_AREA_FRACTION = 0.8
#: CSM points shallower than this fraction of a test's deepest point (or 10 nm) are left out:
#: their stiffness is mostly the oscillation's noise
CSM_MIN_DEPTH = (0.02, 10e-9)
#: first line of the area files `TipCalibration.area_file_text` writes
AREA_FILE_HEADER = "# filmscale indent calibrate: tip area function and frame compliance"


def parse_reference(text) -> ElasticPlastic:
    """The reference material: ``fused-silica``, ``tungsten`` or ``E=72GPa,nu=0.17`` (E in Pa
    when no unit is given)."""
    if isinstance(text, ElasticPlastic):
        return text
    name = str(text).strip().lower()
    if name in REFERENCES:
        return REFERENCES[name]
    fields = {}
    for item in str(text).split(","):
        key, eq, value = item.partition("=")
        fields[key.strip().lower()] = value.strip() if eq else None
    if set(fields) != {"e", "nu"} or None in fields.values():
        raise InputError(f"reference = {text!r} is not one of {', '.join(REFERENCES)} or "
                         "E=...,nu=... (E in Pa or with units: 72 GPa)")
    E = to_si("reference E", fields["e"], "Pa")
    try:
        nu = float(fields["nu"])
    except ValueError:
        raise InputError(f"reference = {text!r}: nu must be a number") from None
    E = check_real("reference E", E, low=1e8, high=2e12, unit="Pa")
    return ElasticPlastic(E, nu, name="custom reference")


@dataclass(frozen=True)
class TipCalibration:
    """A calibrated frame compliance and area function, with the indents behind them and the
    judgement of the fit (`problem`)."""

    area: PolynomialArea        #: the area function (SI coefficients, its calibrated h_c range)
    frame_compliance: float     #: C_f, m/N
    reference: ElasticPlastic
    E_r: float                  #: reduced modulus of the reference against the indenter, Pa
    fit: str                    #: frame, area or both
    h_c: np.ndarray             #: contact depth of each indent, m
    S: np.ndarray               #: contact stiffness of each indent (frame removed), N/m
    P_max: np.ndarray           #: peak load of each indent, N
    area_error: np.ndarray      #: A(h_c) / A_implied - 1 of each indent
    names: tuple = ()           #: the indent behind each row (test, cycle or CSM depth)
    bounds: tuple = (0.0, math.inf)   #: the C_f search range, m/N
    method: str = "unloading"   #: unloading (one indent per unloading) or csm (per point)
    left_out: tuple = ()        #: (name, reason) of every curve or cycle not analysable
    scatter: float = math.nan   #: indent-to-indent scatter of the relative areas

    @property
    def rms_area_error(self) -> float:
        return float(np.sqrt(np.mean(self.area_error**2)))

    def stiffness_squared_over_load(self) -> tuple[float, float]:
        """(mean of S^2/P over the deeper half of the indents, Pa; its trend per doubling of
        depth, as a fraction of the mean): on a homogeneous reference S^2/P = 4 beta^2
        E_r^2 / (pi H) is independent of the area, so a trend left in it is frame compliance
        (or a depth-dependent hardness) that the fit did not take out; NanoSuite's CSM tip
        calibration reads the frame from the same ratio."""
        deep = self.h_c >= np.median(self.h_c)
        ratio = self.S[deep]**2 / self.P_max[deep]
        if ratio.size < 3 or np.ptp(np.log(self.h_c[deep])) == 0:
            return float(np.mean(ratio)) if ratio.size else math.nan, math.nan
        slope = np.polyfit(np.log2(self.h_c[deep]), ratio, 1)[0]
        return float(np.mean(ratio)), float(slope / np.mean(ratio))

    @property
    def misfit_limit(self) -> float:
        """The rms misfit the gate accepts: `SCATTER_FACTOR` times the scatter, at least
        `MISFIT_FLOOR`, at most `MISFIT_LIMIT`."""
        scatter = self.scatter if math.isfinite(self.scatter) else MISFIT_LIMIT
        return min(MISFIT_LIMIT, max(MISFIT_FLOOR, SCATTER_FACTOR * scatter))

    def problem(self) -> str | None:
        """Why this calibration must not be used, in one sentence naming the worst indent;
        None when it passes."""
        lo, hi = float(self.h_c.min()), float(self.h_c.max())
        grid = np.linspace(lo, hi, 200)
        A, dA = np.asarray(self.area.area(grid)), np.asarray(self.area.area_derivative(grid))
        if not np.all(A > 0) or not np.all(dA > 0):
            k = int(np.argmax((A <= 0) | (dA <= 0)))
            what = "not positive" if A[k] <= 0 else "decreasing"
            return (f"the area function is {what} at h_c = {grid[k] * 1e9:.4g} nm, inside the "
                    f"calibrated range {lo * 1e9:.4g}-{hi * 1e9:.4g} nm")
        ideal = np.asarray(self.area.base.area(grid), dtype=float)
        ratio = A / ideal
        if np.any(ratio < IDEAL_AREA_FRACTION):
            k = int(np.argmin(ratio))
            return (f"the area function is {1 - ratio[k]:.0%} below the ideal "
                    f"{self.area.base.spec}'s at h_c = {grid[k] * 1e9:.4g} nm (at most "
                    f"{1 - IDEAL_AREA_FRACTION:.0%}: a worn tip has more area, not less); the "
                    "depth zero is likely misplaced: re-find it (--surface)")
        rms, limit = self.rms_area_error, self.misfit_limit
        if rms > limit:
            k = int(np.argmax(np.abs(self.area_error)))
            name = self.names[k] if k < len(self.names) else f"indent {k + 1}"
            return (f"rms area misfit {rms:.1%} exceeds the {limit:.1%} the indents' scatter "
                    f"allows ({SCATTER_FACTOR:g} x {self.scatter:.2%}, within "
                    f"{MISFIT_FLOOR:.0%}-{MISFIT_LIMIT:.0%}); worst: {name} at h_c = "
                    f"{self.h_c[k] * 1e9:.4g} nm, area off by {self.area_error[k]:+.1%}")
        return None

    def to_dict(self) -> dict:
        return {"coefficients": list(self.area.coefficients), "tip": self.area.base.spec,
                "frame_compliance": self.frame_compliance, "reference": self.reference.name,
                "reference_E": self.reference.E, "reference_nu": self.reference.nu,
                "E_r": self.E_r, "fit": self.fit, "method": self.method,
                "frame_compliance_bounds": list(self.bounds),
                "h_c_range": [float(self.h_c.min()), float(self.h_c.max())],
                "names": list(self.names), "h_c": self.h_c.tolist(),
                "S": self.S.tolist(), "P_max": self.P_max.tolist(),
                "area_error": self.area_error.tolist(), "rms_area_error": self.rms_area_error,
                "scatter": self.scatter, "misfit_limit": self.misfit_limit,
                "problem": self.problem(),
                "stiffness_squared_over_load": dict(zip(
                    ("mean", "trend_per_doubling"), self.stiffness_squared_over_load())),
                "left_out": [{"name": n, "reason": r} for n, r in self.left_out]}

    def coefficients_in(self, length_unit: str = "nm") -> list[float]:
        """C0, C1, ... with h in ``length_unit`` and A in its square."""
        u = UNITS[length_unit]
        return [c / u**(2.0 - p) for c, p in zip(self.area.coefficients, POLYNOMIAL_EXPONENTS)]

    def summary(self) -> str:
        coef = ", ".join(f"{c:.6g}" for c in self.coefficients_in("nm"))
        what = "CSM points" if self.method == "csm" else "indents"
        lines = [
            f"reference {self.reference.name}: E = {self.reference.E / 1e9:.4g} GPa, "
            f"nu = {self.reference.nu:.3g}, E_r = {self.E_r / 1e9:.4g} GPa",
            f"{self.h_c.size} {what}, h_c {self.h_c.min() * 1e9:.4g} to "
            f"{self.h_c.max() * 1e9:.4g} nm, P_max {self.P_max.min() * 1e3:.4g} to "
            f"{self.P_max.max() * 1e3:.4g} mN",
            f"frame compliance C_f = {self.frame_compliance * 1e6:.4g} nm/mN"
            + (f" (fitted in {self.bounds[0] * 1e6:.3g}-{self.bounds[1] * 1e6:.4g} nm/mN"
               + ("; at the lower bound: the instrument may have removed the frame already"
                  if self.frame_compliance <= self.bounds[0] else "") + ")"
               if self.fit != "area" else " (given)"),
            f"area function (h_c in nm, A in nm^2): C = [{coef}]"
            f"{' (fitted)' if self.fit != 'frame' else ' (given)'}",
            f"rms area misfit {100 * self.rms_area_error:.3g} % (indent-to-indent scatter "
            f"{100 * self.scatter:.3g} %, limit {100 * self.misfit_limit:.3g} %)"]
        mean, trend = self.stiffness_squared_over_load()
        if math.isfinite(trend):
            lines.append(f"S^2/P over the deeper half: {mean / 1e9:.4g} GPa, trend "
                         f"{100 * trend:+.2g} % per doubling of depth (flat: the frame is out)")
        lines += [f"left out {name}: {reason}" for name, reason in self.left_out]
        return "\n".join(lines)

    def area_file_text(self, length_unit: str = "nm") -> str:
        """The TOML that ``indent analyze --area-file`` reads (`io.read_area_function`)."""
        u = UNITS[length_unit]
        coef = ", ".join(f"{c:.10g}" for c in self.coefficients_in(length_unit))
        lo, hi = self.h_c.min() / u, self.h_c.max() / u
        return (f"{AREA_FILE_HEADER}\n# fit {self.fit} ({self.method}): {self.area.base.spec} "
                f"tip on {self.reference.name} (E = {self.reference.E / 1e9:.4g} GPa, nu = "
                f"{self.reference.nu:.3g})\n"
                f"# {self.h_c.size} {'CSM points' if self.method == 'csm' else 'indents'}, "
                f"h_c {lo:.4g} to {hi:.4g} {length_unit}; rms area misfit "
                f"{100 * self.rms_area_error:.3g} % (limit {100 * self.misfit_limit:.3g} %)\n"
                f"# A = C0 h^2 + C1 h + C2 h^(1/2) + ..., h in {length_unit}, A in "
                f"{length_unit}^2\n"
                f"C = [{coef}]\nlength_unit = \"{length_unit}\"\n"
                f"# the contact depths it was calibrated on; analyses flag depths outside\n"
                f"h_c_range = [{lo:.10g}, {hi:.10g}]\n"
                f"# m/N; indent analyze removes it unless --frame-compliance is given\n"
                f"frame_compliance = {self.frame_compliance:.10g}\n")


def _label(curve: LoadDisplacementCurve, k: int) -> str:
    meta = curve.meta
    name = meta.get("name") or meta.get("sheet") or meta.get("source") or f"curve {k + 1}"
    return str(name)


class _Indents:
    """The fixed set of reference indents and their (h_c, S, P_max) at a trial C_f."""

    def __init__(self, curves, method: str, window, tip, names=None):
        self.tip, self.window, self.method = tip, window, method
        self.parts, self.names, self.left_out = [], [], []
        points, measured = [], []
        for k, curve in enumerate(curves):
            if not isinstance(curve, LoadDisplacementCurve):
                raise InputError(f"reference curve {k} is not a LoadDisplacementCurve")
            name = names[k] if names is not None else _label(curve, k)
            if method == "csm":
                got = _csm_points(curve)
                if got is None:
                    self.left_out.append((name, "no CSM stiffness at a positive depth"))
                    continue
                points.append(got)
                self.names += [f"{name} at {h * 1e9:.0f} nm" for h in got[0]]
                continue
            parts = cycle_curves(curve)
            if not parts:
                self.left_out.append((name, "no unloading that sheds 10 % of its load"))
            for j, part in enumerate(parts):
                label = f"{name}#{j + 1}" if len(parts) > 1 else name
                result = oliver_pharr(part, tip, window=window, check=False)
                if result.ok and result.S > 0:
                    self.parts.append(part)
                    self.names.append(label)
                    measured.append((result.h_c, result.S, result.P_max))
                else:
                    self.left_out.append((label, result.message or "no positive stiffness"))
        if method == "csm":
            self.h, self.P, self.S_measured = (np.concatenate([p[i] for p in points])
                                               if points else np.empty(0) for i in range(3))
        else:       # the unloadings as fitted: the trial C_f = 0, kept rather than refitted
            self.S_measured = np.array([m[1] for m in measured], dtype=float)
            h_c, S, P = (np.array(v, dtype=float) for v in zip(*measured)) if measured \
                else (np.empty(0),) * 3
            self._unframed = (h_c, S, P) if np.all(h_c > 0) else None
        self.names = tuple(self.names)

    def __len__(self) -> int:
        return len(self.names)

    def stiffest(self) -> float:
        """The largest measured stiffness (frame included), N/m."""
        return float(self.S_measured.max())

    def at(self, C_f: float):
        """(h_c, S, P) of every indent with C_f removed; None when any indent cannot be
        analysed there (the trial is outside the bounds)."""
        if self.method == "csm":
            with np.errstate(divide="ignore", invalid="ignore"):
                inverse = 1.0 / self.S_measured - C_f
                S = 1.0 / inverse
            h_c = self.h - C_f * self.P - self.tip.epsilon * self.P / S
            ok = np.all(inverse > 0) and np.all(h_c > 0)
            return (h_c, S, self.P) if ok else None
        if C_f == 0:
            return self._unframed
        out = []
        for part in self.parts:
            result = oliver_pharr(part.frame_corrected(C_f), self.tip,
                                  window=self.window, check=False)
            if not (result.ok and result.S > 0 and result.h_c > 0):
                return None
            out.append((result.h_c, result.S, result.P_max))
        return tuple(np.array(v, dtype=float) for v in zip(*out))


def _csm_points(curve: LoadDisplacementCurve):
    """(h, P, S) of the loading points of a CSM test deep enough to calibrate on
    (`CSM_MIN_DEPTH`); None when there are none."""
    from .csm import contact_stiffness, loading_points
    c = curve.finite()
    S = contact_stiffness(c)
    if S is None:
        return None
    load = loading_points(c)
    h_min = max(CSM_MIN_DEPTH[0] * float(np.max(c.h)), CSM_MIN_DEPTH[1])
    sel = load & np.isfinite(S) & (S > 0) & (c.P > 0) & (c.h >= h_min)
    return (c.h[sel], c.P[sel], S[sel]) if sel.any() else None


def _depth_groups(indents: _Indents) -> int:
    """How many distinct contact depths the indents span: the 10 %-wide bins of depth that
    hold at least one (a CSM test fills every bin it crosses)."""
    got = indents.at(0.0)
    if got is None:
        return len(indents)
    h = got[0][got[0] > 0]
    return int(np.unique(np.floor(np.log(h) / math.log(1.1))).size) if h.size else 0


def _scatter(h_c, error) -> float:
    """Indent-to-indent scatter of the relative area residuals: the white-noise deviation
    of the residuals taken in order of depth (`core.noise.noise_sigma`), which a smooth
    misfit does not raise."""
    order = np.argsort(h_c, kind="stable")
    return float(noise_sigma(error[order])) if error.size >= 4 else math.nan


def calibrate_tip(curves, reference="fused-silica", *, tip="berkovich", fit="both", terms=4,
                  frame_compliance=0.0, area=None, window=(0.2, 0.98),
                  indenter: ElasticPlastic = DIAMOND, fit_c0: bool = False,
                  method: str = "auto", names=None) -> TipCalibration:
    """Frame compliance and area function from curves measured on a reference.

    Parameters
    ----------
    curves : sequence of LoadDisplacementCurve
        Curves on the reference (frame not removed beyond what the instrument removed), over
        a range of depths; every unloading cycle of a multi-cycle test is one indent, every
        loading point of a CSM test too (``method``).
    reference : str or ElasticPlastic
        ``fused-silica`` (72.0 GPa, 0.17), ``tungsten`` (409.8 GPa, 0.28) or a material.
    tip : str or Tip
        The nominal tip: its eps and beta, and C0 of the fitted area function.
    fit : 'frame', 'area' or 'both'
        Fit C_f with the area function fixed (``area``, else the nominal tip's), the area
        function with C_f fixed (``frame_compliance``), or both together.
    terms : int
        Area coefficients C0 .. C(terms-1), 2 to 9.
    frame_compliance : float
        C_f (m/N) for ``fit='area'``.
    area : Tip or None
        The area function for ``fit='frame'`` (default: the nominal tip).
    window : (float, float)
        Unloading fit window, fractions of each cycle's P_max.
    indenter : ElasticPlastic
        The indenter (diamond by default).
    fit_c0 : bool
        Fit C0 too, instead of keeping the nominal tip's (a real tip's C0 differs).
    method : 'auto', 'unloading' or 'csm'
        Indents from unloadings, or from every loading point of CSM tests (their harmonic
        contact stiffness); auto: csm when every curve carries the stiffness channel.
    names : sequence of str or None
        A name per curve for the report (default: the curve's sheet or source).

    Returns a `TipCalibration`, whose `problem` says whether it may be used; InputError when
    fewer indents than free parameters could be analysed.
    """
    check_choice("fit", fit, FIT_CHOICES)
    check_choice("method", method, METHOD_CHOICES)
    reference = parse_reference(reference)
    base = parse_tip(tip)
    if not isinstance(base, Cone):
        raise InputError(f"tip = {base.spec}: the area function is calibrated for a pyramid "
                         "or cone (berkovich, cube-corner, cone:THETA)")
    terms = int(check_real("terms", terms, low=2, high=9))
    C_given = check_real("frame_compliance", frame_compliance, low=0.0, high=1.0, unit="m/N")
    fixed_area = parse_tip(area) if area is not None else base
    if not isinstance(fixed_area, PolynomialArea):      # what an area file can hold
        if fixed_area is not base or base.tip_radius:
            raise InputError(f"area = {fixed_area.spec}: the fixed area function must be a "
                             "polynomial (an area file) or the sharp nominal tip")
        fixed_area = PolynomialArea((base.area_coefficient,), base)
    curves = list(curves)
    if method == "auto":
        method = "csm" if curves and all("S" in c.channels or "S_total" in c.channels
                                         for c in curves
                                         if isinstance(c, LoadDisplacementCurve)) else "unloading"
    indents = _Indents(curves, method, window, base, names)
    free_area = terms - 1 + int(bool(fit_c0))
    params = {"frame": 1, "area": free_area, "both": free_area + 1}[fit]
    if len(indents) < params + 1:
        raise InputError(f"{len(indents)} reference indents cannot fit {params} parameters: "
                         f"give at least {params + 1} indents (curves, unloading cycles or "
                         "CSM points)")
    depths = _depth_groups(indents)
    if depths < params + 1:
        raise InputError(f"the {len(indents)} reference indents lie at {depths} distinct "
                         f"depth{'s' if depths > 1 else ''} (within 10 %), too few to fit "
                         f"{params} parameters: indent at {params + 1} or more depths, use fewer "
                         "--terms, or calibrate from CSM tests")
    E_r = reference.reduced_modulus(indenter)

    def solve(C_f):
        got = indents.at(C_f)
        if got is None:
            return None
        h_c, S, P = got
        implied = reference_areas(S, beta=base.beta, reference=reference, indenter=indenter)
        shape = fixed_area if fit == "frame" else calibrate_area_function(
            h_c, S, terms=terms, base=base, reference=reference, indenter=indenter,
            fix_C0=not fit_c0)
        return shape, h_c, S, P, np.asarray(shape.area(h_c)) / implied - 1.0

    def misfit(C_f):
        got = solve(C_f)
        return math.inf if got is None else float(np.mean(got[4]**2))

    bounds = (0.0, 0.95 / indents.stiffest())
    if fit == "area":
        C_f = C_given
        bounds = (C_f, C_f)
    else:
        C_f = _minimise(misfit, bounds)
    got = solve(C_f)
    if got is None:
        raise ModelRangeError(f"the {len(indents)} reference indents cannot all be analysed "
                              f"with C_f = {C_f:.4g} m/N (a contact depth or compliance is not "
                              "positive)")
    shape, h_c, S, P, error = got
    shape = PolynomialArea(shape.coefficients, base, (float(h_c.min()), float(h_c.max())))
    return TipCalibration(shape, float(C_f), reference, float(E_r), fit, h_c, S, P, error,
                          indents.names, tuple(float(b) for b in bounds), method,
                          tuple(indents.left_out), _scatter(h_c, error))


def _minimise(misfit, bounds) -> float:
    """C_f in ``bounds`` minimising ``misfit``: a grid of 40 points, then Brent's bounded
    search between the best point's neighbours."""
    from scipy.optimize import minimize_scalar
    lo, hi = bounds
    grid = np.linspace(lo, hi, 40)
    values = np.array([misfit(c) for c in grid])
    if not np.isfinite(values).any():
        raise ModelRangeError("no frame compliance in [0, 0.95 / S_max) leaves every "
                              "reference indent analysable")
    k = int(np.argmin(values))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    best = minimize_scalar(misfit, bounds=(a, b), method="bounded",
                           options={"xatol": 1e-6 * (hi - lo)})
    return float(best.x) if best.fun <= values[k] else float(grid[k])
