"""Frame compliance and tip area function from indents on a reference of known modulus.

Oliver & Pharr, J. Mater. Res. 7 (1992) 1564, sec. IV.B, and 19 (2004) 3, sec. 2.4: the
measured compliance of an indent is the frame's and the contact's in series,

    C_total = C_f + sqrt(pi) / (2 beta E_r sqrt(A(h_c))),

with E_r the reduced modulus of the reference against the indenter. On a reference of known
E_r every indent then gives the area at its contact depth, A_i = (pi/4) (S_i / (beta E_r))^2,
where S_i = 1 / (C_total,i - C_f) is the stiffness of the contact alone, and
h_c,i = h_max,i - C_f P_max,i - eps P_max,i / S_i. Oliver and Pharr iterate between C_f (from
the deepest indents) and the area function A(h_c) = C0 h_c^2 + C1 h_c + C2 h_c^(1/2) + ...;
here the same model is solved as one least-squares problem: for a trial C_f every curve is
frame-corrected and its unloading fitted again, the area function is fitted to the implied
areas with C0 kept at the nominal tip's (so the deepest indents fix C_f, as in the paper),
and C_f minimises the remaining relative area misfit.

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
from filmscale.core.errors import InputError
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
    """A calibrated frame compliance and area function, with the indents behind them."""

    area: PolynomialArea        #: the area function (SI coefficients)
    frame_compliance: float     #: C_f, m/N
    reference: ElasticPlastic
    E_r: float                  #: reduced modulus of the reference against the indenter, Pa
    fit: str                    #: frame, area or both
    h_c: np.ndarray             #: contact depth of each indent, m
    S: np.ndarray               #: contact stiffness of each indent (frame removed), N/m
    P_max: np.ndarray           #: peak load of each indent, N
    area_error: np.ndarray      #: A(h_c) / A_implied - 1 of each indent

    @property
    def rms_area_error(self) -> float:
        return float(np.sqrt(np.mean(self.area_error**2)))

    def to_dict(self) -> dict:
        return {"coefficients": list(self.area.coefficients), "tip": self.area.base.spec,
                "frame_compliance": self.frame_compliance, "reference": self.reference.name,
                "reference_E": self.reference.E, "reference_nu": self.reference.nu,
                "E_r": self.E_r, "fit": self.fit, "h_c": self.h_c.tolist(),
                "S": self.S.tolist(), "P_max": self.P_max.tolist(),
                "area_error": self.area_error.tolist(), "rms_area_error": self.rms_area_error}

    def coefficients_in(self, length_unit: str = "nm") -> list[float]:
        """C0, C1, ... with h in ``length_unit`` and A in its square."""
        u = UNITS[length_unit]
        return [c / u**(2.0 - p) for c, p in zip(self.area.coefficients, POLYNOMIAL_EXPONENTS)]

    def summary(self) -> str:
        coef = ", ".join(f"{c:.6g}" for c in self.coefficients_in("nm"))
        return "\n".join([
            f"reference {self.reference.name}: E = {self.reference.E / 1e9:.4g} GPa, "
            f"nu = {self.reference.nu:.3g}, E_r = {self.E_r / 1e9:.4g} GPa",
            f"{self.h_c.size} indents, h_c {self.h_c.min() * 1e9:.4g} to "
            f"{self.h_c.max() * 1e9:.4g} nm, P_max {self.P_max.min() * 1e3:.4g} to "
            f"{self.P_max.max() * 1e3:.4g} mN",
            f"frame compliance C_f = {self.frame_compliance * 1e6:.4g} nm/mN"
            f"{' (fitted)' if self.fit != 'area' else ' (given)'}",
            f"area function (h_c in nm, A in nm^2): C = [{coef}]"
            f"{' (fitted)' if self.fit != 'frame' else ' (given)'}",
            f"rms area misfit {100 * self.rms_area_error:.3g} %"])

    def area_file_text(self, length_unit: str = "nm") -> str:
        """The TOML that ``indent analyze --area-file`` reads (`io.read_area_function`)."""
        coef = ", ".join(f"{c:.10g}" for c in self.coefficients_in(length_unit))
        return (f"{AREA_FILE_HEADER}\n# fit {self.fit}: {self.area.base.spec} tip on "
                f"{self.reference.name} (E = {self.reference.E / 1e9:.4g} GPa, nu = "
                f"{self.reference.nu:.3g})\n"
                f"# {self.h_c.size} indents, h_c {self.h_c.min() * 1e9:.4g} to "
                f"{self.h_c.max() * 1e9:.4g} nm; rms area misfit "
                f"{100 * self.rms_area_error:.3g} %\n"
                f"# A = C0 h^2 + C1 h + C2 h^(1/2) + ..., h in {length_unit}, A in "
                f"{length_unit}^2\n"
                f"C = [{coef}]\nlength_unit = \"{length_unit}\"\n"
                f"# m/N; indent analyze removes it unless --frame-compliance is given\n"
                f"frame_compliance = {self.frame_compliance:.10g}\n")


def _indents(parts, C_f: float, window, tip):
    """(h_c, S, P_max) of every reference cycle with frame compliance C_f removed (the area
    function does not enter them: the nominal tip serves)."""
    out = []
    for part in parts:
        result = oliver_pharr(part.frame_corrected(C_f) if C_f else part, tip,
                              window=window, check=False)
        out.append((result.h_c, result.S, result.P_max) if result.ok else (math.nan,) * 3)
    return np.array(out, dtype=float).reshape(-1, 3).T


def _reference_parts(curves) -> list[LoadDisplacementCurve]:
    parts = []
    for k, curve in enumerate(curves):
        if not isinstance(curve, LoadDisplacementCurve):
            raise InputError(f"reference curve {k} is not a LoadDisplacementCurve")
        parts += cycle_curves(curve)
    return parts


def calibrate_tip(curves, reference="fused-silica", *, tip="berkovich", fit="both", terms=4,
                  frame_compliance=0.0, area=None, window=(0.2, 0.98),
                  indenter: ElasticPlastic = DIAMOND) -> TipCalibration:
    """Frame compliance and area function from curves measured on a reference.

    Parameters
    ----------
    curves : sequence of LoadDisplacementCurve
        Raw curves (frame not removed) on the reference, over a range of depths; every
        unloading cycle of a multi-cycle test is one indent.
    reference : str or ElasticPlastic
        ``fused-silica`` (72.0 GPa, 0.17), ``tungsten`` (409.8 GPa, 0.28) or a material.
    tip : str or Tip
        The nominal tip: its eps and beta, and C0 of the fitted area function.
    fit : 'frame', 'area' or 'both'
        Fit C_f with the area function fixed (``area``, else the nominal tip's), the area
        function with C_f fixed (``frame_compliance``), or both together.
    terms : int
        Area coefficients C0 .. C(terms-1), 2 to 9 (C0 stays the nominal tip's).
    frame_compliance : float
        C_f (m/N) for ``fit='area'``.
    area : Tip or None
        The area function for ``fit='frame'`` (default: the nominal tip).
    window : (float, float)
        Unloading fit window, fractions of each cycle's P_max.
    indenter : ElasticPlastic
        The indenter (diamond by default).

    Returns a `TipCalibration`; InputError when fewer indents than free parameters could be
    analysed.
    """
    check_choice("fit", fit, FIT_CHOICES)
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
    parts = _reference_parts(curves)
    need = {"frame": 2, "area": terms, "both": terms + 1}[fit]
    if len(parts) < need:
        raise InputError(f"{len(parts)} reference indents cannot fit {need - 1} parameters: "
                         f"give at least {need} indents (curves or unloading cycles)")
    E_r = reference.reduced_modulus(indenter)

    def solve(C_f):
        h_c, S, P = _indents(parts, C_f, window, base)
        ok = np.isfinite(h_c) & (h_c > 0) & np.isfinite(S) & (S > 0)
        if ok.sum() < need:
            return None
        h_c, S, P = h_c[ok], S[ok], P[ok]
        implied = reference_areas(S, beta=base.beta, reference=reference, indenter=indenter)
        shape = fixed_area if fit == "frame" else calibrate_area_function(
            h_c, S, terms=terms, base=base, reference=reference, indenter=indenter)
        return shape, h_c, S, P, np.asarray(shape.area(h_c)) / implied - 1.0

    def misfit(C_f):
        got = solve(C_f)
        return math.inf if got is None else float(np.mean(got[4]**2))

    if fit == "area":
        C_f = C_given
    else:
        C_f = _minimise(misfit, parts, window, base)
    got = solve(C_f)
    if got is None:
        raise InputError(f"fewer than {need} of the {len(parts)} reference indents could be "
                         "analysed (no unloading, or a fit that failed)")
    shape, h_c, S, P, error = got
    return TipCalibration(shape, float(C_f), reference, float(E_r), fit, h_c, S, P, error)


def _minimise(misfit, parts, window, tip) -> float:
    """C_f in [0, 0.95 of the smallest total compliance] minimising ``misfit``: a grid of
    40 points, then Brent's bounded search between the best point's neighbours."""
    from scipy.optimize import minimize_scalar
    _, S_total, _ = _indents(parts, 0.0, window, tip)
    S_total = S_total[np.isfinite(S_total) & (S_total > 0)]
    if S_total.size == 0:
        raise InputError("no reference indent could be analysed (no unloading)")
    hi = 0.95 / float(S_total.max())
    grid = np.linspace(0.0, hi, 40)
    values = np.array([misfit(c) for c in grid])
    k = int(np.argmin(values))
    lo, up = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    best = minimize_scalar(misfit, bounds=(lo, up), method="bounded",
                           options={"xatol": 1e-6 * hi})
    return float(best.x) if best.fun <= values[k] else float(grid[k])
