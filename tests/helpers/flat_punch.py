"""A throw-away model kind: a rigid flat-ended cylindrical punch of radius R hitting an elastic
half-space. Its contact stiffness is Sneddon's k = 2 R E* at every approach, so the impact is
a linear spring: delta_max = V sqrt(m/k), contact time pi sqrt(m/k), no loss (Johnson 1985,
section 3.8 and 11.4). Registered by tests to show that a kind reaches every command without
editing them."""

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.contact.kinds import ModelKind

UNITS = {"delta_max": "m", "force_max": "N", "mean_pressure_max": "Pa", "contact_time": "s",
         "restitution": "1"}


def punch_closed_form(V, R, m, E_star) -> dict:
    """The linear-spring impact of the punch, written here from the closed form."""
    k = 2.0 * R * E_star
    delta = V * math.sqrt(m / k)
    return {"delta_max": delta, "force_max": k * delta,
            "mean_pressure_max": k * delta / (math.pi * R * R),
            "contact_time": math.pi * math.sqrt(m / k), "restitution": 1.0}


@dataclass(frozen=True)
class PunchResult:
    velocity: float
    radius: float
    mass: float
    delta_max: float
    force_max: float
    mean_pressure_max: float
    contact_time: float
    restitution: float
    yielded: bool = False
    regime: str = "elastic"
    path: str = "closed form"

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def summary(self) -> str:
        return (f"flat punch R = {self.radius:g} m: delta_max = {self.delta_max:.6g} m, "
                f"force_max = {self.force_max:.6g} N")


@dataclass(frozen=True)
class FlatPunch:
    """The punch on the substrate of ``target`` (a half-space: films are ignored)."""

    target: object

    @property
    def E_star(self) -> float:
        body = getattr(self.target, "stack", self.target)         # a Gao profile's stack
        body = getattr(body, "substrate", body)
        return body.E / (1.0 - body.nu ** 2)

    def describe(self) -> dict:
        return {"kind": "flat-punch", "E_star": self.E_star}

    def maxima(self, V, R, m) -> PunchResult:
        return PunchResult(velocity=V, radius=R, mass=m,
                           **punch_closed_form(V, R, m, self.E_star))


def _body(radius, mass, options, names):
    """No density limit: the punch is the end of a larger slider."""


FLAT_PUNCH = ModelKind(
    name="flat-punch", shape="flat-punch",
    summary="rigid flat punch on an elastic half-space (a test's throw-away kind)",
    build=lambda target, impactor, options: FlatPunch(target),
    solve=lambda model, V, R, m, options: model.maxima(V, R, m),
    check_body=_body, fields=UNITS, units=UNITS)


def punch_map_reference(velocity, radius, mass, E_star) -> dict:
    """The closed form over a (radius, velocity) grid."""
    out = {k: np.empty((len(radius), len(velocity))) for k in UNITS}
    for i, R in enumerate(radius):
        for j, V in enumerate(velocity):
            for k, v in punch_closed_form(V, R, mass, E_star).items():
                out[k][i, j] = v
    return out
