"""Impact maps: the fast-path maxima over a grid of impact velocity V and sphere radius R.

Points whose approach would exceed R are marked (``out_of_range``) and hold NaN instead of
stopping the map; `ImpactMap.field` returns any result as an (n_R, n_V) array in SI units.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.contact.results import EXCEEDS_RADIUS
from filmscale.core.checks import check_choice, check_float_array, check_positive, check_real
from filmscale.core.errors import InputError

from .impact import ImpactMaxima, ImpactModel

#: the quantities a map shows, with units (the dissertation's Figs. 3.2-3.5 and more)
MAP_FIELDS = {"delta_max": "m", "mean_pressure_max": "Pa", "force_max": "N",
              "contact_radius_max": "m", "contact_time": "s", "residual_depth": "m",
              "restitution": "1"}


def axis(low, high, count, spacing: str = "log", name: str = "axis",
         bounds: tuple[float, float] = (0.0, np.inf), unit: str = "") -> np.ndarray:
    """``count`` values from ``low`` to ``high``, log- or linearly spaced, both within
    ``bounds`` (open below)."""
    low = check_real(f"{name} minimum", low, low=bounds[0], high=bounds[1], low_open=True,
                     unit=unit)
    high = check_real(f"{name} maximum", high, low=bounds[0], high=bounds[1], low_open=True,
                      unit=unit)
    if (isinstance(count, bool) or not isinstance(count, (int, float, np.integer))
            or int(count) != count or not 1 <= int(count) <= 100_000):
        raise InputError(f"{name} count = {count!r} must be an integer in [1, 100000]")
    if high < low:
        raise InputError(f"{name} maximum {high:g} is below its minimum {low:g}")
    check_choice(f"{name} spacing", spacing, ("log", "linear"))
    count = int(count)
    return np.geomspace(low, high, count) if spacing == "log" else np.linspace(low, high, count)


@dataclass(frozen=True)
class ImpactMap:
    """Maxima on the grid ``radius`` (rows) x ``velocity`` (columns).

    An oblique map (`continuum.contact.oblique.oblique_map`) adds the incidence angle of each
    row and its tangential results; its rows vary the radius or the angle, the other repeated.
    """

    velocity: np.ndarray        #: V, m/s, shape (n_V,)
    radius: np.ndarray          #: R, m, shape (n_R,)
    mass: float                 #: kg
    maxima: ImpactMaxima        #: fields of shape (n_R, n_V)
    angle: np.ndarray | None = None     #: incidence of each row (oblique), degrees
    #: oblique results (`oblique.OBLIQUE_FIELDS`), each of shape (n_R, n_V)
    tangential: dict = dataclasses.field(default_factory=dict)

    @property
    def out_of_range(self) -> np.ndarray:
        """True where the approach would exceed R (not computed)."""
        return self.maxima.status == EXCEEDS_RADIUS

    def field(self, name: str) -> np.ndarray:
        """One result as an (n_R, n_V) float array, NaN where out of range."""
        check_choice("map field", name, tuple(ImpactMaxima.UNITS) + tuple(self.tangential))
        if name in self.tangential:
            return np.asarray(self.tangential[name], dtype=float)
        return np.asarray(getattr(self.maxima, name), dtype=float)

    def to_dict(self) -> dict:
        """Arrays in SI for the store: axes, every result field, status and regime."""
        out = {"velocity": self.velocity, "radius": self.radius, "mass": self.mass,
               "status": self.maxima.status, "regime": self.maxima.regime,
               "yielded": self.maxima.yielded}
        out.update({k: self.field(k) for k in ImpactMaxima.UNITS
                    if k not in ("velocity", "radius", "mass")})
        if self.angle is not None:
            out["angle"] = self.angle
        out.update(self.tangential)
        return out


#: largest map: the fast path holds about 2 kB per point in blocks, results 150 B per point
MAX_MAP_POINTS = 4_000_000


def impact_map(model: ImpactModel, velocity, radius, mass, progress=None) -> ImpactMap:
    """Fast-path maxima of ``model`` for every (R, V) pair of the two 1-D axes.

    ``progress(done, total)`` is passed on to `ImpactModel.maxima`.
    """
    velocity = np.atleast_1d(check_float_array("velocity", velocity))
    radius = np.atleast_1d(check_float_array("radius", radius))
    if velocity.ndim != 1 or radius.ndim != 1:
        raise InputError(f"impact map axes must be 1-D arrays of velocity and radius, got "
                         f"shapes {velocity.shape} and {radius.shape}")
    if velocity.size * radius.size > MAX_MAP_POINTS:
        raise InputError(f"impact map of {velocity.size} x {radius.size} points exceeds "
                         f"{MAX_MAP_POINTS} points: use fewer velocities or radii")
    mass = check_positive("mass", mass, "kg")
    maxima = model.maxima(velocity[None, :], radius[:, None], mass, progress=progress)
    return ImpactMap(velocity=velocity, radius=radius, mass=mass, maxima=maxima)
