"""What the impact models return: for a sphere one impact (`ImpactResult`), the maxima of many
impacts at once (`ImpactMaxima`, the fast path) and a time history (`ImpactHistory`); for a
cylinder one impact (`CylinderImpactResult`) and its history (`CylinderImpactHistory`). SI
units."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from filmscale.core.errors import ModelRangeError
from filmscale.core.jsonable import to_jsonable
from filmscale.core.quantities import eng

#: status codes of a fast-path point
OK, EXCEEDS_RADIUS, UNLOADING_INCONSISTENT, UNLOADING_OUT_OF_RANGE = 0, 1, 2, 3



STATUS_MESSAGES = {
    OK: "ok",
    EXCEEDS_RADIUS: "the approach would exceed the sphere radius R, where the contact laws "
                    "stop holding: not computed",
    UNLOADING_INCONSISTENT: "the unloading model returns more energy than the loading took "
                            "(elastic recovery above the approach or e_y > 1): an artefact of "
                            "a contact law that jumps at its yield point",
    UNLOADING_OUT_OF_RANGE: "the residual-depth fit leaves no elastic recovery this far past "
                            "yield (jackson-chusoipin-green beyond delta_max/delta_Y ~ 1e4): "
                            "loading maxima computed, unloading results not",
}


def rebound_lines(result) -> list[str]:
    """The summary lines an impact result of any shape shares: contact time, residual depth,
    restitution and the regime reached."""
    return [
        f"  contact time          {eng(result.contact_time, 's')} "
        f"(loading {eng(result.loading_time, 's')}, "
        f"unloading {eng(result.unloading_time, 's')})",
        f"  residual depth        {eng(result.residual_depth, 'm')}",
        f"  restitution e_y       {result.restitution:.4f}",
        f"  regime reached        {result.regime} "
        f"({'yielded' if result.yielded else 'no yield'}; first yield at "
        f"V_Y = {eng(result.yield_velocity, 'm/s')})",
    ]


@dataclass(frozen=True)
class ImpactResult:
    """One impact; SI units. ``status``/``message`` say whether it holds (see STATUS_MESSAGES)."""

    velocity: float             #: V, incident normal velocity, m/s
    radius: float               #: R, m
    mass: float                 #: m, kg
    delta_max: float            #: maximum approach, m
    force_max: float            #: largest contact force, N
    mean_pressure_max: float    #: largest mean contact pressure P/A, Pa
    contact_radius_max: float   #: largest contact radius, m
    contact_time: float         #: duration of contact, s
    loading_time: float         #: contact to maximum approach, s
    unloading_time: float       #: maximum approach to separation, s
    residual_depth: float       #: depth of the crater left behind, m
    restitution: float          #: e_y = rebound speed / V
    rebound_velocity: float     #: m/s
    yielded: bool               #: the law's first-yield threshold was reached
    regime: str                 #: regime at maximum approach
    yield_approach: float       #: approach at first yield, m (inf if never reached before R)
    yield_velocity: float       #: impact speed that just reaches first yield, m/s
    contact_law: str
    unloading: str
    path: str                   #: "energy-quadrature" or "time-integration"
    status: int = OK
    message: str = "ok"
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """The result as JSON values (infinities, such as a yield approach never reached,
        become None)."""
        return to_jsonable(self)

    def summary(self) -> str:
        lines = [
            f"Impact of a sphere R = {eng(self.radius, 'm')}, m = {eng(self.mass, 'kg')} at "
            f"V = {eng(self.velocity, 'm/s')} ({self.contact_law}, unloading: "
            f"{self.unloading}, {self.path})",
            f"  maximum approach      {eng(self.delta_max, 'm')}",
            f"  maximum force         {eng(self.force_max, 'N')}",
            f"  maximum mean pressure {eng(self.mean_pressure_max, 'Pa')}",
            f"  maximum contact radius {eng(self.contact_radius_max, 'm')}",
            *rebound_lines(self),
        ]
        if self.status != OK:
            lines.append(f"  status: {self.message}")
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class ImpactMaxima:
    """Fast-path results over arrays of (V, R, m); every field has the broadcast shape.

    Points with ``status == EXCEEDS_RADIUS`` hold NaN (regime -1).
    """

    velocity: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    delta_max: np.ndarray
    force_max: np.ndarray
    mean_pressure_max: np.ndarray
    contact_radius_max: np.ndarray
    contact_time: np.ndarray
    loading_time: np.ndarray
    unloading_time: np.ndarray
    residual_depth: np.ndarray
    restitution: np.ndarray
    rebound_velocity: np.ndarray
    yielded: np.ndarray
    regime: np.ndarray          #: branch index into ``regime_names``
    yield_approach: np.ndarray
    yield_velocity: np.ndarray
    status: np.ndarray
    regime_names: tuple[str, ...]
    contact_law: str
    unloading: str
    warnings: tuple[str, ...] = ()

    #: fields holding arrays of floats in SI, with their units
    UNITS = {"velocity": "m/s", "radius": "m", "mass": "kg", "delta_max": "m",
             "force_max": "N", "mean_pressure_max": "Pa", "contact_radius_max": "m",
             "contact_time": "s", "loading_time": "s", "unloading_time": "s",
             "residual_depth": "m", "restitution": "1", "rebound_velocity": "m/s",
             "yield_approach": "m", "yield_velocity": "m/s"}

    def result(self, index=()) -> ImpactResult:
        """The single impact at ``index``; raises ModelRangeError if it was not computed."""
        status = int(self.status[index])
        if status == EXCEEDS_RADIUS:
            raise ModelRangeError(exceeds_radius_message(self.velocity[index], self.radius[index],
                                                  self.mass[index]))
        values = {k: float(getattr(self, k)[index]) for k in self.UNITS}
        return ImpactResult(**values, yielded=bool(self.yielded[index]),
                            regime=self.regime_names[int(self.regime[index])],
                            contact_law=self.contact_law, unloading=self.unloading,
                            path="energy-quadrature", status=status,
                            message=STATUS_MESSAGES[status], warnings=self.warnings)


@dataclass(frozen=True)
class ImpactHistory:
    """Time-integrated impact: the maxima plus sampled histories (SI units).

    ``phase`` is 0 before contact, 1 loading, 2 unloading; ``branch`` the law's regime index.
    """

    result: ImpactResult
    time: np.ndarray            #: s
    delta: np.ndarray           #: approach, m (negative before contact)
    velocity: np.ndarray        #: d(delta)/dt, m/s
    force: np.ndarray           #: N
    contact_radius: np.ndarray  #: m
    mean_pressure: np.ndarray   #: Pa
    branch: np.ndarray
    phase: np.ndarray
    events: dict = field(default_factory=dict)  #: event name -> time, s
    nfev: int = 0               #: contact-force evaluations by the integrator

    #: the unit of each sampled history
    HISTORY_UNITS = {"time": "s", "delta": "m", "velocity": "m/s", "force": "N",
                     "contact_radius": "m", "mean_pressure": "Pa", "branch": "1", "phase": "1"}

    def to_dataframe(self):
        """The sampled histories as a pandas table indexed by time (s), one column per
        quantity in SI (``df.attrs["units"]``); pandas is imported here."""
        import pandas as pd
        df = pd.DataFrame({k: getattr(self, k) for k in self.HISTORY_UNITS}).set_index("time")
        df.attrs["units"] = dict(self.HISTORY_UNITS)
        return df



def exceeds_radius_message(V, R, m) -> str:
    return (f"approach exceeds the sphere radius at V = {V:.6g} m/s, R = {R:.6g} m, "
            f"m = {m:.6g} kg: the contact laws hold for delta <= R only")


@dataclass(frozen=True)
class CylinderImpactResult:
    """One cylinder impact; SI units. Forces are totals over the length (P = L P')."""

    velocity: float             #: V, incident normal velocity, m/s
    radius: float               #: R, cylinder radius, m
    length: float               #: L, contact length, m
    mass: float                 #: m, moving mass, kg
    datum_depth: float          #: d, depth of the approach datum, m
    delta_max: float            #: maximum approach, m
    force_max: float            #: largest contact force, N
    line_load_max: float        #: largest load per unit length, N/m
    mean_pressure_max: float    #: largest mean contact pressure P'/(2b), Pa
    contact_half_width: float   #: largest contact half-width b, m
    contact_time: float         #: duration of contact, s
    loading_time: float         #: contact to maximum approach, s
    unloading_time: float       #: maximum approach to separation, s
    residual_depth: float       #: depth of the groove left behind, m
    restitution: float          #: e_y = rebound speed / V
    rebound_velocity: float     #: m/s
    work_loading: float         #: integral of P over the loading approach, J
    work_unloading: float       #: work returned on unloading, J
    dissipated: float           #: work_loading - work_unloading, J
    yielded: bool               #: first yield (p0 = C sigma_Y) was reached
    regime: str                 #: regime at maximum approach, one of REGIME_NAMES
    yield_approach: float       #: approach at first yield, m (inf if out of range)
    yield_velocity: float       #: impact speed that just reaches first yield, m/s
    path: str                   #: "energy-quadrature" or "time-integration"
    shape: str = "cylinder"
    approximation: str = ("plane strain over the length L, end effects neglected; approach "
                          "from the datum depth d")
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """The result as JSON values (infinities become None)."""
        return to_jsonable(self)

    def summary(self) -> str:
        lines = [
            f"Impact of a cylinder R = {eng(self.radius, 'm')}, L = {eng(self.length, 'm')}, "
            f"m = {eng(self.mass, 'kg')} at V = {eng(self.velocity, 'm/s')} (line contact, "
            f"datum d = {eng(self.datum_depth, 'm')}, {self.path})",
            f"  maximum approach      {eng(self.delta_max, 'm')}",
            f"  maximum force         {eng(self.force_max, 'N')} "
            f"({eng(self.line_load_max, 'N/m')})",
            f"  maximum mean pressure {eng(self.mean_pressure_max, 'Pa')}",
            f"  contact half-width    {eng(self.contact_half_width, 'm')}",
            *rebound_lines(self),
            f"  approximation         {self.approximation}",
        ]
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class CylinderImpactHistory:
    """Time-integrated cylinder impact: the maxima plus sampled histories (SI units).

    ``phase`` is 1 loading, 2 unloading (contact starts at t = 0); ``branch`` indexes
    REGIME_NAMES: the regime of each loading sample, the regime at maximum approach while
    unloading.
    """

    result: CylinderImpactResult
    time: np.ndarray                #: s
    delta: np.ndarray               #: approach from the datum, m
    velocity: np.ndarray            #: d(delta)/dt, m/s
    force: np.ndarray               #: total force L P', N
    contact_half_width: np.ndarray  #: b, m
    mean_pressure: np.ndarray       #: P'/(2b), Pa
    branch: np.ndarray
    phase: np.ndarray
    events: dict = field(default_factory=dict)  #: event name -> time, s
    nfev: int = 0                   #: right-hand-side evaluations of the integrator
