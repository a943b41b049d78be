"""Continuous stiffness measurement (CSM): hardness and modulus at every depth of the loading.

A CSM test superposes a small oscillation on the loading, and the instrument records the
harmonic contact stiffness S at every point. Each point is then an Oliver-Pharr analysis of
its own (Oliver & Pharr, J. Mater. Res. 19 (2004) 3, sec. 3.3; Hay, Agee & Herbert, Exp.
Tech. 34 (2010) 86):

    h_c = h - eps P / S,   A = A(h_c),   E_r = sqrt(pi) S / (2 beta sqrt(A)),   H = P / A,
    E = (1 - nu^2) / (1/E_r - (1 - nu_i^2)/E_i),

the formulas of the KLA NanoSuite G-Series CSM method for its ``Contact Depth``, ``Reduced
Modulus``, ``Hardness`` and ``Modulus`` channels. S is the contact's alone: the
``Harmonic Contact Stiffness`` channel (the instrument's harmonic frame stiffness removed);
when a file gives only the combined ``Harmonic Stiffness`` and the ``Harmonic Frame
Stiffness``, 1/S = 1/S_total - 1/K_frame. Hay et al.'s peak correction (depth and load
plus sqrt(2) times their harmonic amplitudes) is already in NanoSuite's exported depth and
load; ``harmonic_peaks=True`` applies it to records of mean values that carry the amplitude
channels.

Averages are taken over a depth range (NanoSuite's ``Minimum/Maximum Calculation Depth``, 100
to 200 nm by default there), as the instrument's ``Results`` sheet gives them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from filmscale.continuum.materials import DIAMOND, ElasticPlastic, modulus_from_reduced
from filmscale.core.checks import check_real
from filmscale.core.errors import InputError
from filmscale.core.jsonable import to_jsonable

from .curves import LOAD, LoadDisplacementCurve
from .tips import Tip, parse_tip

OK, FAILED = 0, 1
ARRAYS = ("h", "h_c", "S", "A", "E_r", "E", "H")


@dataclass(frozen=True)
class CSMResult:
    """Properties at every loading point of a CSM test, and their averages over a depth range.

    Arrays over the loading points with a positive stiffness and contact area: ``h`` (m),
    ``h_c`` (m), ``S`` (N/m), ``A`` (m^2), ``E_r``, ``E`` (NaN without nu) and ``H`` (Pa).
    """

    h: np.ndarray
    h_c: np.ndarray
    S: np.ndarray
    A: np.ndarray
    E_r: np.ndarray
    E: np.ndarray
    H: np.ndarray
    depth_range: tuple           #: (low, high) depths of the averages, m
    E_r_mean: float              #: mean over the depth range, Pa
    E_mean: float
    H_mean: float
    E_r_std: float               #: standard deviation over the depth range, Pa
    E_std: float
    H_std: float
    n_range: int                 #: points in the depth range
    h_c_mean: float              #: mean contact depth in the range, m
    epsilon: float
    beta: float
    nu: float | None
    tip: str
    vendor_difference: dict = field(default_factory=dict)  #: median E/E_vendor - 1, H/H_vendor - 1
    status: int = OK
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.status == OK

    def to_dict(self) -> dict:
        """JSON-ready: ``csm`` holds the arrays (SI), the rest the averages and settings."""
        return {"csm": {k: getattr(self, k).tolist() for k in ARRAYS},
                **{k: to_jsonable(getattr(self, k)) for k in self.__dataclass_fields__
                   if k not in ARRAYS}}

    def summary(self) -> str:
        if not self.ok:
            return f"not analysed: {self.message}"
        lo, hi = self.depth_range
        text = (f"CSM over {lo * 1e9:.4g}-{hi * 1e9:.4g} nm ({self.n_range} points): "
                f"E_r = {self.E_r_mean / 1e9:.4g} +- {self.E_r_std / 1e9:.2g} GPa, "
                f"H = {self.H_mean / 1e9:.4g} +- {self.H_std / 1e9:.2g} GPa")
        if self.nu is not None:
            text += f", E = {self.E_mean / 1e9:.4g} +- {self.E_std / 1e9:.2g} GPa"
        if self.vendor_difference:
            text += "; against the instrument's own channels: " + ", ".join(
                f"{k} {v:+.2%}" for k, v in self.vendor_difference.items())
        return text


def contact_stiffness(curve: LoadDisplacementCurve, frame_stiffness_correction: float = 0.0):
    """The harmonic contact stiffness S (N/m) at every point: the ``S`` channel, else
    1/(1/S_total - 1/(K_frame + correction)) from the combined and frame channels; None
    when the curve carries neither."""
    ch = curve.channels
    if "S" in ch:
        return ch["S"]
    if "S_total" in ch and "K_frame" in ch:
        with np.errstate(divide="ignore", invalid="ignore"):
            inverse = 1.0 / ch["S_total"] - 1.0 / (ch["K_frame"] + frame_stiffness_correction)
            return np.where(inverse > 0, 1.0 / inverse, np.nan)
    return None


def loading_points(curve: LoadDisplacementCurve) -> np.ndarray:
    """Boolean mask of the points of ``curve``'s first loading (`LoadDisplacementCurve.loading`)
    labelled load."""
    end = curve.loading().stop
    load = np.zeros(curve.h.size, dtype=bool)
    load[:end] = curve.segment[:end] == LOAD
    return load


def _failed(message, tip, eps, beta, nu, depth_range=(math.nan, math.nan)) -> CSMResult:
    empty = np.empty(0)
    nan = math.nan
    return CSMResult(*(empty,) * 7, tuple(depth_range), nan, nan, nan, nan, nan, nan, 0, nan,
                     eps, beta, nu, tip.spec, {}, FAILED, message)


def csm_analysis(curve: LoadDisplacementCurve, tip: Tip | str, *, depth_range=None,
                 epsilon=None, beta=None, nu=None, indenter: ElasticPlastic = DIAMOND,
                 harmonic_peaks: bool = False) -> CSMResult:
    """CSM analysis of one curve (module docstring).

    Parameters
    ----------
    curve : LoadDisplacementCurve
        With the ``S`` channel (or ``S_total`` and ``K_frame``); frame compliance beyond the
        instrument's, drift and the surface already dealt with.
    tip : Tip or str
        The area function (a `PolynomialArea` from the file or a calibration, or a nominal tip).
    depth_range : (float, float) or None
        Depths (m) of the averages; None: the file's (``meta["vendor"]["depth_range"]``), else
        every analysed point.
    epsilon, beta : float or None
        None: the tip's.
    nu : float or None
        Sample Poisson ratio: E from E_r.
    indenter : ElasticPlastic
        The indenter (diamond, 1141 GPa and 0.07, by default).
    harmonic_peaks : bool
        Add sqrt(2) times the harmonic displacement and load amplitudes to h and P (records
        of mean values; NanoSuite's exports already hold the peak values).

    Returns a `CSMResult`; status FAILED, with the reason, when the curve has no stiffness
    channel or no loading point with a positive contact area.
    """
    tip = parse_tip(tip)
    eps = tip.epsilon if epsilon is None else check_real("epsilon", epsilon, low=0.5, high=1.0)
    beta = tip.beta if beta is None else check_real("beta", beta, low=0.5, high=2.0)
    if nu is not None:
        nu = check_real("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    vendor = curve.meta.get("vendor", {}) or {}
    if depth_range is None:
        depth_range = vendor.get("depth_range")
    if depth_range is not None:
        lo = check_real("depth range start", depth_range[0], low=0.0, unit="m")
        hi = check_real("depth range end", depth_range[1], low=lo, low_open=True, unit="m")
        depth_range = (lo, hi)
    c = curve.finite()
    S = contact_stiffness(c, float(vendor.get("harmonic_frame_stiffness_correction") or 0.0))
    if S is None:
        return _failed("no CSM stiffness channel (Harmonic Contact Stiffness, or Harmonic "
                       "Stiffness with Harmonic Frame Stiffness)", tip, eps, beta, nu,
                       depth_range or (math.nan, math.nan))
    h, P = c.h, c.P
    if harmonic_peaks:
        for name, values in (("h_harmonic", h), ("P_harmonic", P)):
            if name not in c.channels:
                raise InputError(f"harmonic_peaks needs the {name} channel")
        h = h + math.sqrt(2.0) * np.nan_to_num(c.channels["h_harmonic"])
        P = P + math.sqrt(2.0) * np.nan_to_num(c.channels["P_harmonic"])
    load = loading_points(c)
    with np.errstate(divide="ignore", invalid="ignore"):
        sel = load & np.isfinite(S) & (S > 0) & (h > 0) & (P > 0)
        h_c = h[sel] - eps * P[sel] / S[sel]
        A = np.asarray(tip.area(np.maximum(h_c, 0.0)), dtype=float)
    good = (h_c > 0) & np.isfinite(A) & (A > 0)
    if not good.any():
        return _failed("no loading point with a positive stiffness and contact area", tip, eps,
                       beta, nu, depth_range or (math.nan, math.nan))
    hh, h_c, SS, A, PP = h[sel][good], h_c[good], S[sel][good], A[good], P[sel][good]
    E_r = math.sqrt(math.pi) * SS / (2.0 * beta * np.sqrt(A))
    H = PP / A
    E = modulus_from_reduced(E_r, nu, indenter.compliance) if nu is not None \
        else np.full(E_r.size, np.nan)
    if depth_range is None:
        depth_range = (float(hh.min()), float(hh.max()))
    inside = (hh >= depth_range[0]) & (hh <= depth_range[1])
    n = int(inside.sum())

    def stats(x):
        if n == 0:
            return math.nan, math.nan
        return float(np.mean(x[inside])), float(np.std(x[inside], ddof=1)) if n > 1 else 0.0

    (E_r_mean, E_r_std), (E_mean, E_std), (H_mean, H_std) = stats(E_r), stats(E), stats(H)
    difference = {}
    for key, ours, channel in (("E", E, "E_vendor"), ("H", H, "H_vendor")):
        if channel in c.channels:
            theirs = c.channels[channel][sel][good]
            both = inside & np.isfinite(ours) & np.isfinite(theirs) & (theirs > 0)
            if both.any():
                difference[key] = float(np.median(ours[both] / theirs[both] - 1.0))
    return CSMResult(hh, h_c, SS, A, E_r, E, H, tuple(depth_range), E_r_mean, E_mean, H_mean,
                     E_r_std, E_std, H_std, n, float(np.mean(h_c[inside])) if n else math.nan,
                     eps, beta, nu, tip.spec, difference)
