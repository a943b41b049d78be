"""Load-displacement curves: the contract between scales, their segments and their data checks.

A `LoadDisplacementCurve` holds depth h (m), load P (N), optional time t (s), a segment
label per point (load, hold, unload; detected from the load rate when not given) and optional
per-point instrument channels in SI (`CHANNELS`: the CSM harmonic contact stiffness, the
instrument's own hardness and modulus, ...). MD runs, particle runs and instrument files all
produce this one type; every analysis takes it.

Where an unloading starts is found from the loads themselves (`unloading_start`): a hold at
the peak whose load sags or creeps stays before it, wherever a rate filter put the label.

`check_curve` flags what would spoil an analysis (no unloading, too few unloading points, NaN
rows, reversals, load or displacement offsets, drift during a hold) without raising: a batch
of thousands of files keeps going and each result carries its flags. Frame-compliance and
thermal-drift corrections return new curves (Fischer-Cripps, *Nanoindentation*, 2011, ch. 3;
ISO 14577-1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from types import MappingProxyType

import numpy as np

from filmscale.core.checks import (MODULUS_PLAUSIBLE, SLIP_UNITS, check_float_array,
                                   check_real)
from filmscale.core.errors import InputError
from filmscale.core.noise import noise_sigma

from .tips import Tip, parse_tip

LOAD, HOLD, UNLOAD = 0, 1, 2
SEGMENT_NAMES = ("load", "hold", "unload")
#: |dP/dt| below this fraction of the curve's typical (90th percentile) rate is a hold
HOLD_RATE_FRACTION = 0.05
#: ... or below this many standard deviations of the rate that load noise alone produces
NOISE_SIGMAS = 4.0
#: the unloading from the peak must shed at least this fraction of P_max (noise blips do not)
UNLOADING_MIN_DROP = 0.1
#: a hold before an unloading sheds load at under this fraction of the unloading's rate
HOLD_SLOPE_RATIO = 0.35
#: ... and the break between them must lower the squared residual by this F ratio
BREAK_F = 25.0
#: meta["segment_source"] of a curve whose labels an instrument file gave (markers, segments)
SEGMENTS_FROM_FILE = "file"
#: ... or that `cycles.cycle_curves` cut at a cycle's unloading start: labels to keep as given
SEGMENTS_FROM_CYCLE = "cycle"

#: per-point channels a curve may carry, with their SI unit
CHANNELS = {
    "S": "N/m",              # harmonic contact stiffness (CSM), frame removed
    "S_total": "N/m",        # harmonic stiffness of contact and frame in series
    "K_frame": "N/m",        # harmonic frame stiffness
    "h_harmonic": "m",       # harmonic displacement amplitude (RMS)
    "P_harmonic": "N",       # harmonic load amplitude (RMS)
    "H_vendor": "Pa",        # the instrument's own hardness channel
    "E_vendor": "Pa",        # the instrument's own modulus channel
}


@dataclass(frozen=True)
class CurveFlag:
    """A data problem found in a curve: a short ``code`` and a sentence for people."""

    code: str
    message: str

    def __str__(self) -> str:
        return f"{self.code}: {self.message}"


@dataclass(frozen=True)
class LoadDisplacementCurve:
    """An indentation load-displacement record in SI.

    Parameters
    ----------
    h : array_like
        Indenter displacement into the surface, m (0 at the undeformed surface).
    P : array_like
        Load, N.
    t : array_like or None
        Time, s.
    segment : array_like or None
        Per-point label: 0/'load', 1/'hold', 2/'unload'. Detected from the load rate when None.
    indenter : Tip, str or None
        The tip that made the curve, as a `filmscale.continuum.indentation.tips.Tip` (text
        such as ``berkovich`` or ``sphere:5um`` is parsed with `parse_tip`); None when
        unknown. MD and particle runs hand over their tip object, so a cone keeps its apex
        radius.
    meta : mapping
        Provenance: source file, instrument or simulation inputs, seeds, versions.
    channels : mapping
        Per-point instrument channels by name (`CHANNELS`), in SI, one value per point; NaN
        where the instrument gave none.

    Non-finite rows are kept (so `check_curve` can report them) and dropped by `finite()`,
    which every analysis calls first.
    """

    h: np.ndarray
    P: np.ndarray
    t: np.ndarray | None = None
    segment: np.ndarray | None = None
    indenter: Tip | None = None
    meta: MappingProxyType = field(default_factory=dict)
    channels: MappingProxyType = field(default_factory=dict)

    def __post_init__(self):
        h = _column("h", self.h)
        P = _column("P", self.P)
        if h.size != P.size:
            raise InputError(f"curve h and P differ in length: {h.size} and {P.size}")
        if h.size < 2:
            raise InputError(f"a curve needs at least 2 points, got {h.size}")
        t = None if self.t is None else _column("t", self.t)
        if t is not None and t.size != h.size:
            raise InputError(f"curve t has {t.size} points but h has {h.size}")
        object.__setattr__(self, "h", h)
        object.__setattr__(self, "P", P)
        object.__setattr__(self, "t", t)
        seg = self.segment
        if seg is None:
            seg = detect_segments(h, P, t)
        else:
            seg = _segment_codes(seg, h.size)
        seg.setflags(write=False)
        object.__setattr__(self, "segment", seg)
        object.__setattr__(self, "meta", MappingProxyType(dict(self.meta)))
        object.__setattr__(self, "indenter", parse_tip(self.indenter) if self.indenter else None)
        channels = {}
        for name, values in dict(self.channels).items():
            if name not in CHANNELS:
                raise InputError(f"curve channel {name!r} is not one of {', '.join(CHANNELS)}")
            arr = _column(name, values)
            if arr.size != h.size:
                raise InputError(f"curve channel {name} has {arr.size} points but h has {h.size}")
            channels[name] = arr
        object.__setattr__(self, "channels", MappingProxyType(channels))

    def __len__(self) -> int:
        return self.h.size

    @cached_property
    def peak(self) -> int:
        """Index of the largest finite load."""
        return int(np.nanargmax(self.P))

    @property
    def P_max(self) -> float:
        """Largest finite load, N."""
        return float(self.P[self.peak])

    @property
    def h_max(self) -> float:
        """Depth at the largest load, m (the start of unloading after a hold is `unloading`'s)."""
        return float(self.h[self.peak])

    def finite(self) -> LoadDisplacementCurve:
        """This curve without rows that hold NaN or infinities."""
        ok = np.isfinite(self.h) & np.isfinite(self.P)
        if self.t is not None:
            ok &= np.isfinite(self.t)
        if ok.all():
            return self
        if ok.sum() < 2:
            raise InputError("the curve has fewer than 2 finite points")
        return replace(self, h=self.h[ok], P=self.P[ok], t=None if self.t is None else self.t[ok],
                       segment=self.segment[ok],
                       channels={k: v[ok] for k, v in self.channels.items()})

    @cached_property
    def _runs(self) -> tuple[tuple[int, int, int], ...]:
        return tuple(segment_runs(self.segment))

    def runs(self) -> list[tuple[int, int, int]]:
        """Contiguous segments as (label, start, stop) with stop exclusive."""
        return list(self._runs)

    @property
    def segments_given(self) -> bool:
        """True when the labels are to be kept as given: an instrument file's segment markers,
        or a cycle cut at its unloading start."""
        return self.meta.get("segment_source") in (SEGMENTS_FROM_FILE, SEGMENTS_FROM_CYCLE)

    def unloading(self) -> slice:
        """Index range of the unloading that starts from the peak load (`_unloading`)."""
        return self._unloading

    @cached_property
    def _unloading(self) -> slice:
        """Index range of the unloading that starts from the peak load.

        The first unload run after the largest load that sheds at least 10 % of it (shorter
        dips in a noisy hold are skipped); a drift hold part-way down ends it. It begins where
        the file's markers say, else at `unloading_start`: after a hold at the peak, however
        its load sags and wherever the rate filter put the boundary. Empty slice when there is
        none.
        """
        peak = self.peak
        P_max = self.P[peak]
        for label, start, stop in self._runs:
            if label == UNLOAD and stop > peak + 1:
                begin = max(start - 1, peak)
                if P_max - np.nanmin(self.P[begin:stop]) >= UNLOADING_MIN_DROP * abs(P_max):
                    top = begin if self.segments_given else peak
                    return slice(self.unloading_begin(top, stop), stop)
        return slice(0, 0)

    def unloading_begin(self, top: int, stop: int) -> int:
        """Where the unloading after the load peak at ``top`` begins: the point before the
        first unload label when the labels are given (an instrument's markers, a cut cycle),
        else `unloading_start`, after a hold however its load sags."""
        if self.segments_given:
            marked = np.flatnonzero(self.segment[top:stop] == UNLOAD)
            if marked.size:
                return top + max(int(marked[0]) - 1, 0)
        return unloading_start(self.P, self.t, top, stop)

    def loading(self) -> slice:
        """Everything before the unloading from the peak (loading and the hold at peak)."""
        unl = self.unloading()
        return slice(0, unl.start + 1 if unl.stop > unl.start else len(self))

    def loading_curvature(self, from_fraction: float = 0.0) -> float:
        """Kick's-law curvature C (Pa): the least-squares fit P = C h^2 (no intercept) to the
        loading points (segment LOAD) with h > from_fraction h_max. C = sum(P h^2)/sum(h^4);
        meaningful for sharp (self-similar) tips, as in Dao et al. (2001, Acta Mater. 49,
        3899). NaN when no point qualifies."""
        from_fraction = check_real("from_fraction", from_fraction, low=0.0, high=1.0,
                                   high_open=True)
        c = self.finite()
        load = c.segment == LOAD
        sel = load & (c.h > from_fraction * c.h[load].max()) if load.any() else load
        h, P = c.h[sel], c.P[sel]
        denominator = float(np.sum(h**4))
        return float(np.sum(P * h**2) / denominator) if denominator > 0 else math.nan

    def frame_corrected(self, C_f: float) -> LoadDisplacementCurve:
        """h - C_f P: the displacement of the sample alone, given frame compliance C_f (m/N)."""
        C_f = check_real("frame compliance C_f", C_f, low=0.0, high=1.0, unit="m/N")
        meta = {**self.meta, "frame_compliance": C_f}
        channels = dict(self.channels)
        if "S" in channels:         # springs in series: the contact alone is stiffer
            with np.errstate(divide="ignore", invalid="ignore"):
                inverse = 1.0 / channels["S"] - C_f
                channels["S"] = np.where(inverse > 0, 1.0 / inverse, np.nan)
        return replace(self, h=self.h - C_f * self.P, segment=self.segment, meta=meta,
                       channels=channels)

    def shifted(self, h0: float) -> LoadDisplacementCurve:
        """h - h0: the depth zero moved to h0 (m), where the surface was re-found."""
        h0 = check_real("surface shift h0", h0, low=-1.0, high=1.0, unit="m")
        meta = {**self.meta, "surface_shift": h0 + float(self.meta.get("surface_shift", 0.0))}
        return replace(self, h=self.h - h0, segment=self.segment, meta=meta)

    def drift_corrected(self, rate: float) -> LoadDisplacementCurve:
        """h - rate (t - t0): removes a thermal drift of `rate` (m/s) measured on a hold."""
        if self.t is None:
            raise InputError("drift correction needs the curve's time column t")
        rate = check_real("drift rate", rate, low=-1.0, high=1.0, unit="m/s")
        meta = {**self.meta, "drift_rate": rate}
        return replace(self, h=self.h - rate * (self.t - self.t[0]), segment=self.segment,
                       meta=meta)

    def to_dataframe(self):
        """The curve as a pandas table (pandas imported here): columns h (m), P (N), t (s,
        when the curve has times) and segment ("load", "hold", "unload"), one row per point;
        ``df.attrs`` holds the units, the tip and the provenance."""
        import pandas as pd
        columns = {"h": self.h, "P": self.P, **({"t": self.t} if self.t is not None else {}),
                   "segment": pd.Categorical.from_codes(self.segment, SEGMENT_NAMES),
                   **self.channels}
        df = pd.DataFrame(columns)
        df.attrs.update(units={"h": "m", "P": "N", "t": "s",
                               **{k: CHANNELS[k] for k in self.channels}},
                        indenter=self.indenter.spec if self.indenter else "",
                        meta=dict(self.meta))
        return df

    def to_xarray(self):
        """The curve as an xarray Dataset over its points: h (m) and P (N) with ``units``
        attributes, t (s) as a coordinate when the curve has times, segment names."""
        import xarray as xr
        coords = {"segment": ("point", np.array(SEGMENT_NAMES)[self.segment])}
        if self.t is not None:
            coords["t"] = ("point", self.t, {"units": "s"})
        return xr.Dataset({"h": ("point", self.h, {"units": "m"}),
                           "P": ("point", self.P, {"units": "N"}),
                           **{k: ("point", v, {"units": CHANNELS[k]})
                              for k, v in self.channels.items()}}, coords=coords,
                          attrs={"indenter": self.indenter.spec if self.indenter else ""})

    def to_dict(self) -> dict:
        return {"h": self.h.tolist(), "P": self.P.tolist(),
                "t": None if self.t is None else self.t.tolist(),
                "segment": [SEGMENT_NAMES[s] for s in self.segment],
                "indenter": self.indenter.spec if self.indenter else "",
                "meta": dict(self.meta),
                "channels": {k: v.tolist() for k, v in self.channels.items()}}


def _column(name, values) -> np.ndarray:
    arr = check_float_array(f"curve {name}", values)
    if arr.ndim != 1:
        raise InputError(f"curve {name} must be 1-D, got shape {arr.shape}")
    arr.setflags(write=False)
    return arr


def _segment_codes(seg, n) -> np.ndarray:
    arr = np.asarray(seg)
    if arr.dtype.kind in "US":
        lookup = {name: k for k, name in enumerate(SEGMENT_NAMES)}
        unknown = sorted(set(arr.tolist()) - set(lookup))
        if unknown:
            raise InputError(f"segment labels {unknown} are not among {SEGMENT_NAMES}")
        arr = np.array([lookup[s] for s in arr.tolist()])
    arr = np.array(arr, dtype=np.int8)
    if arr.shape != (n,):
        raise InputError(f"segment must have one label per point ({n}), got shape {arr.shape}")
    if arr.size and (arr.min() < 0 or arr.max() > 2):
        raise InputError("segment codes must be 0 (load), 1 (hold) or 2 (unload)")
    return arr


def segment_runs(labels) -> list[tuple[int, int, int]]:
    """Contiguous runs of equal ``labels`` as (label, start, stop), stop exclusive."""
    if labels.size == 0:
        return []
    edges = np.flatnonzero(np.diff(labels)) + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges, [labels.size]])
    return [(int(labels[a]), int(a), int(b)) for a, b in zip(starts, stops)]


@lru_cache(maxsize=64)
def derivative_kernel(window: int) -> np.ndarray:
    """Savitzky-Golay first derivative (quadratic, odd ``window``), in convolution order: on a
    symmetric window the quadratic term drops out of the slope at the centre, leaving the
    least-squares line's slope, -j / sum(j^2) (scipy.signal, whose import takes a second,
    gives the same kernel; the curve tests compare them)."""
    j = np.arange(-(window // 2), window // 2 + 1, dtype=float)
    return -j / float(j @ j)


def _quantile(x, q: float) -> float:
    """The q-quantile of x by selection (np.partition): numpy's median and percentile cost
    ten times more on short arrays, and a batch calls this tens of thousands of times."""
    k = min(int(q * (x.size - 1) + 0.5), x.size - 1)
    return float(np.partition(x, k)[k])


def _line(x, y) -> tuple[float, float, float]:
    """Least-squares line y = a + b x: (a, b, sum of squared residuals)."""
    dx = x - x.mean()
    sxx = float(dx @ dx)
    b = float(dx @ (y - y.mean())) / sxx if sxx > 0 else 0.0
    a = float(y.mean()) - b * float(x.mean())
    r = y - (a + b * x)
    return a, b, float(r @ r)


def _prefix_line_sse(x, y) -> np.ndarray:
    """Sum of squared residuals of the least-squares line through the first k + 1 points,
    for every k (cumulative sums: one pass for every break point)."""
    n = np.arange(1, x.size + 1, dtype=float)
    sx, sy = np.cumsum(x), np.cumsum(y)
    sxx, sxy, syy = np.cumsum(x * x), np.cumsum(x * y), np.cumsum(y * y)
    with np.errstate(divide="ignore", invalid="ignore"):
        vxx = sxx - sx * sx / n
        vxy = sxy - sx * sy / n
        vyy = syy - sy * sy / n
        sse = np.where(vxx > 0, vyy - vxy * vxy / vxx, 0.0)
    return np.maximum(sse, 0.0)


def unloading_start(P, t, top: int, stop: int) -> int:
    """Index where an unloading that follows the load peak at ``top`` begins.

    A hold at the peak may sag (load relaxes) or creep, so the largest load is often its
    first point and a rate filter smears its end. Between ``top`` and the point where the load
    has fallen half-way to its lowest value before ``stop``, two straight lines P(t) are fitted
    on either side of every break point; the break that leaves the least squared residual
    ends the hold when it explains far more than the noise (an F ratio over `BREAK_F` against
    one line) and the first line sheds load at under `HOLD_SLOPE_RATIO` of the second's rate
    (at least 3 points before it, 5 after). Otherwise the unloading starts at ``top``.
    Without times the sample index stands in for time.
    """
    P = np.asarray(P, dtype=float)
    part = P[top:stop]
    if part.size < 8 or not np.all(np.isfinite(part)):
        return top
    half = part[0] - 0.5 * (part[0] - part.min())
    end = int(np.argmax(part <= half)) + 1
    if end < 8:
        return top
    x = (np.asarray(t, dtype=float)[top:top + end] if t is not None
         else np.arange(end, dtype=float))
    if not np.all(np.isfinite(x)):
        x = np.arange(end, dtype=float)
    y = part[:end]
    left = _prefix_line_sse(x, y)                     # lines through points 0..k
    right = _prefix_line_sse(x[::-1], y[::-1])[::-1]  # lines through points k..end-1
    k = np.arange(2, end - 5)                         # 3 points in the hold, 5 after it
    if k.size == 0:
        return top
    two = left[k] + right[k]
    best = int(np.argmin(two))
    # the break must explain far more than noise does (an F ratio of the two-line fit
    # against one line; noise alone, at its best break, stays under 10)
    one = float(left[end - 1])
    significant = one - two[best] > BREAK_F * 2.0 * two[best] / max(end - 4, 1)
    best = int(k[best])
    hold, unload = _line(x[:best + 1], y[:best + 1])[1], _line(x[best:], y[best:])[1]
    if significant and unload < 0 and abs(hold) < HOLD_SLOPE_RATIO * abs(unload):
        return top + best
    return top


def _rate(P, t):
    """(dP/dt smoothed by a Savitzky-Golay filter (per median sampling interval), the
    standard deviation that the load noise
    gives it). dP per sample stands in for dP/dt when t is None.

    The window starts at 2 % of the points (at least 5) and widens, up to 10 %, until the
    noise in the smoothed rate is under a sixteenth of the typical rate, so that holds stay
    separable from loading and unloading even on noisy records.
    """
    n = P.size
    largest = (n - 1) if n % 2 == 0 else n
    window = min(max(5, n // 50) | 1, largest)
    if window < 3:
        rate = np.gradient(P)
        return rate, 0.0, _quantile(np.abs(rate), 0.9)
    sigma = noise_sigma(P)
    step = 1.0
    if t is not None:
        step = _quantile(np.diff(t), 0.5)
    while True:
        kernel = derivative_kernel(window)
        half = window // 2      # edges repeat the end values (scipy.ndimage's "nearest")
        padded = np.concatenate([np.full(half, P[0]), P, np.full(half, P[-1])])
        rate = np.convolve(padded, kernel, mode="valid") / step
        noise = sigma * float(np.linalg.norm(kernel)) / step
        scale = _quantile(np.abs(rate), 0.9)
        wider = min(max(n // 10, 5) | 1, largest)
        if NOISE_SIGMAS * noise <= 0.25 * scale or window >= wider:
            return rate, noise, scale
        window = min(window * 2 + 1, wider)


def detect_segments(h, P, t=None, *, min_run=3) -> np.ndarray:
    """Label each point load (0), hold (1) or unload (2) from the smoothed load rate.

    A point is a hold where |dP/dt| is under 5 % of the curve's 90th-percentile rate, or
    under four standard deviations of what the load noise gives the smoothed rate. Holds and
    unloading blips at under 10 % of the peak load before the peak are loading (P ~ h^2
    rises slowly from contact); runs shorter than ``min_run`` points join their neighbour.
    Non-finite rows get the label of the previous finite one. Without time, the sample index
    stands in for time (instruments sample at a steady rate).
    """
    h, P = np.asarray(h, dtype=float), np.asarray(P, dtype=float)
    ok = np.isfinite(h) & np.isfinite(P)
    if t is not None:
        t = np.asarray(t, dtype=float)
        ok &= np.isfinite(t)
    labels = np.zeros(P.size, dtype=np.int8)
    idx = np.flatnonzero(ok)
    if idx.size < 3:
        return labels
    tt = None
    if t is not None and np.all(np.diff(t[idx]) > 0):
        tt = t[idx]
    rate, noise, scale = _rate(P[idx], tt)
    lab = np.where(rate > 0, LOAD, UNLOAD).astype(np.int8)
    lab[np.abs(rate) < max(HOLD_RATE_FRACTION * scale, NOISE_SIGMAS * noise)] = HOLD
    Pi = P[idx]
    peak, low = int(np.argmax(Pi)), 0.1 * float(np.max(Pi))
    # noise at first contact, where P ~ h^2 rises slowly
    for label, start, stop in segment_runs(lab):
        if label != LOAD and stop <= peak and np.mean(Pi[start:stop]) < low:
            lab[start:stop] = LOAD
    for _ in range(2):      # short holds first become load/unload, then short blips merge
        for label, start, stop in segment_runs(lab):
            if stop - start < min_run and not (start == 0 and stop == lab.size):
                lab[start:stop] = lab[start - 1] if start > 0 else lab[stop]
    labels[idx] = lab
    fill = np.maximum.accumulate(np.where(ok, np.arange(P.size), 0))
    return labels[fill]


# ---- data checks -------------------------------------------------------------------------

#: codes of the data checks, in the order they are run
FLAG_CODES = ("nan_data", "non_monotonic", "no_unloading", "few_unloading_points",
              "zero_load_offset", "displacement_offset", "hold_drift")
MIN_UNLOADING_POINTS = 10     #: in the 20-98 % fit window (ISO 14577 asks for a dense fit)
OFFSET_FRACTION = 0.03        #: displacement offset flagged above this fraction of h_max
LOAD_OFFSET_FRACTION = 0.01   #: loads below -1 % of P_max (beyond the noise): unzeroed load cell
DRIFT_FRACTION = 0.01         #: drift over the test above 1 % of h_max is flagged
#: a drift hold's mean load must exceed this fraction of P_max: below it (the size of a load
#: zero's offset, `LOAD_OFFSET_FRACTION`) the tip may be out of contact; drift holds sit at
#: about 10 % of P_max (ISO 14577-1)
DRIFT_HOLD_MIN_LOAD = 0.01


def displacement_offset(curve: LoadDisplacementCurve) -> float:
    """Depth (m) at which the loading curve extrapolates to zero load.

    Fits h = h_0 + k P^(1/m) to the loading between 2 % and 50 % of P_max by linear least
    squares, for m = 2 (self-similar elastic-plastic, Kick's law) and m = 3/2 (Hertz), and
    keeps the better fit; h_0 should be 0 when the surface was found correctly.
    """
    c = curve.finite()
    load = c.loading()
    h, P = c.h[load], c.P[load]
    sel = (P > 0.02 * c.P_max) & (P < 0.5 * c.P_max) & (c.segment[load] == LOAD)
    if sel.sum() < 4:
        return 0.0
    fits = [_line(P[sel]**(1.0 / m), h[sel]) for m in (2.0, 1.5)]
    return min(fits, key=lambda fit: fit[2])[0]


def _hold_drift_rates(c: LoadDisplacementCurve):
    """(mean load, drift rate m/s) of each hold below half the peak load after the peak
    (drift holds come during or after unloading, where creep has died out) and above
    `DRIFT_HOLD_MIN_LOAD` of it: where the load has fallen to its zero (the tail of an
    unloading that drifts to -0.2 % of P_max) the tip is leaving the surface, and the depth
    there measures the actuator, not the drift of a contact."""
    out = []
    if c.t is None:
        return out
    for label, start, stop in c.runs():
        if label != HOLD or stop - start < 5 or start < c.peak:
            continue
        if DRIFT_HOLD_MIN_LOAD * c.P_max < np.mean(c.P[start:stop]) < 0.5 * c.P_max:
            skip = start + (stop - start) // 5     # the first fifth still carries creep
            rate = _line(c.t[skip:stop], c.h[skip:stop])[1]
            out.append((float(np.mean(c.P[start:stop])), float(rate)))
    return out


def drift_rate(curve: LoadDisplacementCurve) -> float:
    """Thermal drift rate (m/s) from the last hold below half the peak load.

    The slope of h against t over the hold, leaving out its first fifth where creep of the
    contact still adds to the drift (ISO 14577-1 annex). Raises InputError when the curve has
    no time column or no such hold.
    """
    c = curve.finite()
    if c.t is None:
        raise InputError("drift rate needs the curve's time column t")
    rates = _hold_drift_rates(c)
    if not rates:
        raise InputError("the curve has no hold below half the peak load to measure drift on")
    return rates[-1][1]


def check_curve(curve: LoadDisplacementCurve, window=(0.2, 0.98)) -> tuple[CurveFlag, ...]:
    """The data checks of a curve, as flags; an empty tuple for a clean curve."""
    flags = []
    bad = ~(np.isfinite(curve.h) & np.isfinite(curve.P))
    if curve.t is not None:
        bad |= ~np.isfinite(curve.t)
    if bad.any():
        flags.append(CurveFlag("nan_data", f"{int(bad.sum())} rows with NaN or infinite values "
                               f"were left out"))
    if bad.all() or (~bad).sum() < 3:
        return tuple(flags)
    c = curve.finite()
    P_max = c.P_max
    h_span = float(np.ptp(c.h)) or 1.0
    load = c.loading()
    h_load = c.h[load][c.segment[load] == LOAD]
    reversal = float(np.max(np.maximum.accumulate(h_load) - h_load)) if h_load.size else 0.0
    if c.t is not None and np.any(np.diff(c.t) <= 0):
        flags.append(CurveFlag("non_monotonic", "time does not increase at every point"))
    elif reversal > 0.02 * h_span:
        flags.append(CurveFlag("non_monotonic", f"depth falls back by {reversal:.3g} m during "
                               f"loading ({100 * reversal / h_span:.1f} % of the depth range)"))
    unl = c.unloading()
    if unl.stop - unl.start < 2:
        flags.append(CurveFlag("no_unloading", "no unloading segment after the peak load"))
    else:
        P_unl = c.P[unl]
        n_fit = int(np.sum((P_unl >= window[0] * P_max) & (P_unl <= window[1] * P_max)))
        if n_fit < MIN_UNLOADING_POINTS:
            flags.append(CurveFlag("few_unloading_points", f"{n_fit} unloading points in the "
                                   f"{window[0]:.0%}-{window[1]:.0%} fit window (fewer than "
                                   f"{MIN_UNLOADING_POINTS})"))
    if P_max <= 0:
        flags.append(CurveFlag("zero_load_offset", "the load never rises above zero"))
    elif np.min(c.P) < -LOAD_OFFSET_FRACTION * P_max - NOISE_SIGMAS * noise_sigma(c.P):
        flags.append(CurveFlag("zero_load_offset", f"loads down to {np.min(c.P):.3g} N: the "
                               f"zero of load is offset"))
    else:
        h0 = displacement_offset(c)
        if abs(h0) > OFFSET_FRACTION * max(c.h_max, h_span):
            flags.append(CurveFlag("displacement_offset", f"loading extrapolates to zero load "
                                   f"at h = {h0:.3g} m, not 0: the surface was misplaced"))
    duration = float(np.ptp(c.t)) if c.t is not None else 0.0
    for load_mean, rate in _hold_drift_rates(c):
        if abs(rate) * duration > DRIFT_FRACTION * max(c.h_max, h_span):
            flags.append(CurveFlag("hold_drift", f"drift of {rate:.3g} m/s during the hold at "
                                   f"{load_mean:.3g} N moves the depth by "
                                   f"{abs(rate) * duration:.3g} m over the test"))
            break
    return tuple(flags)


#: factors a unit slip multiplies a curve's depths or loads by (nm read as m: 1e-9)
DEPTH_SLIPS = (1e-10, 1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e9)
LOAD_SLIPS = (1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e9)


def _unit_slip(si: str, factor: float) -> str:
    """The words of a slip: ``in nm read as m`` for a factor 1e-9 of metres, ``in m read
    as nm`` for 1e9."""
    named = {round(math.log10(f)): unit for f, unit in SLIP_UNITS[si].items()}
    e = round(math.log10(factor))
    if e in named:
        return f"in {named[e]} read as {si}"
    return f"in {si} read as {named[-e]}" if -e in named else f"off by a factor {factor:g}"


def implausible_modulus(E_r: float, how: str, rescaled) -> CurveFlag | None:
    """The flag of a curve whose implied reduced modulus E_r (Pa) lies outside
    `MODULUS_PLAUSIBLE`, the range of real solids: a unit slip in its depths or loads. None
    when E_r is plausible. ``rescaled(depth_factor, load_factor)`` is the E_r of the curve
    with its depths and loads so multiplied: the flag names the slip that brings E_r nearest
    100 GPa, depths before loads."""
    low, high = MODULUS_PLAUSIBLE
    if low <= E_r <= high:
        return None
    message = (f"the curve implies E_r = {E_r:.3g} Pa ({how}), outside the {low / 1e9:g} GPa "
               f"- {high / 1e12:g} TPa of real solids")
    options = [("depths", "m", f, rescaled(f, 1.0)) for f in DEPTH_SLIPS] + \
        [("loads", "N", f, rescaled(1.0, f)) for f in LOAD_SLIPS]
    fits = [o for o in options if low <= o[3] <= high]
    if fits:
        def distance(option):
            return abs(math.log(option[3] / 100e9))
        best = min(distance(o) for o in fits)
        # a sharp tip's E_r goes as P/h^2: depths x 1e3 and loads x 1e-6 cannot be told apart
        slips = [o for o in fits if distance(o) <= best + 1e-6]
        message += ("; are its " + ", or its ".join(
            f"{kind} {_unit_slip(si, factor)} ({kind} x {factor:g})"
            for kind, si, factor, _ in slips) + f"? (that gives E_r = {slips[0][3]:.3g} Pa)")
    return CurveFlag("implausible_modulus", message)
