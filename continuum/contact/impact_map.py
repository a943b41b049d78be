"""Impact maps: the maxima over a grid of impact velocity V and sphere or cylinder radius R.

Points beyond the model's range (a sphere's approach above R, a cylinder's contact wider than
min(R, d/5)) are marked (``out_of_range``) and hold NaN instead of stopping the map;
``field`` returns any result as an (n_R, n_V) array in SI units; ``to_xarray`` and
``to_dataframe`` give the whole map as a labelled dataset or a long table (xarray and pandas
are imported only there).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from filmscale.continuum.contact.results import EXCEEDS_RADIUS, OK, STATUS_MESSAGES
from filmscale.core.checks import check_choice, check_float_array, check_positive, check_real
from filmscale.core.errors import InputError, ModelRangeError

from .cylinder import REGIME_NAMES, CylinderImpactModel, check_cylinder_mass
from .impact import ImpactMaxima, ImpactModel

#: the quantities a map shows, with units (the dissertation's Figs. 3.2-3.5 and more)
MAP_FIELDS = {"delta_max": "m", "mean_pressure_max": "Pa", "force_max": "N",
              "contact_radius_max": "m", "contact_time": "s", "residual_depth": "m",
              "restitution": "1"}
#: the quantities a cylinder map shows: a line contact has a half-width, not a radius
CYLINDER_MAP_FIELDS = {"delta_max": "m", "mean_pressure_max": "Pa", "force_max": "N",
                       "contact_half_width": "m", "contact_time": "s", "residual_depth": "m",
                       "restitution": "1"}
#: every float result of a cylinder map, with units
CYLINDER_UNITS = {**CYLINDER_MAP_FIELDS, "line_load_max": "N/m", "loading_time": "s",
                  "unloading_time": "s", "rebound_velocity": "m/s", "work_loading": "J",
                  "work_unloading": "J", "dissipated": "J", "yield_approach": "m",
                  "yield_velocity": "m/s"}
#: a cylinder map's status codes: those of sphere maps, the range being the line contact's
CYLINDER_STATUS_MESSAGES = {OK: "ok", EXCEEDS_RADIUS: "the contact half-width would exceed "
                            "min(R, d/5), where the line-contact laws stop holding: not "
                            "computed"}


def row_dimension(arrays: dict) -> str:
    """The quantity a map's rows vary: "angle" for an oblique map over (V, angle), "radius"
    otherwise (the other one, if present, is repeated along the rows)."""
    angle = arrays.get("angle")
    return "angle" if angle is not None and np.ptp(angle) > 0 else "radius"


#: the units of a map's axes and flags
AXIS_UNITS = {"velocity": "m/s", "radius": "m", "mass": "kg", "angle": "degrees",
              "status": "1", "regime": "1", "yielded": "1"}


def map_dataset(arrays: dict, attrs: dict | None = None, units: dict | None = None):
    """An xarray Dataset of a map's arrays (the ``to_dict`` form, or a map read from a file):
    dimensions (row, "velocity") with the row quantity of `row_dimension`, the other row
    quantity and the mass as coordinates, every (row, V) array a variable; ``units``
    attributes from ``units`` (the map's result units; SI, angles in degrees)."""
    import xarray as xr
    units = AXIS_UNITS | (units or {})
    row = row_dimension(arrays)
    coords = {"velocity": ("velocity", np.asarray(arrays["velocity"]), {"units": "m/s"}),
              "mass": ((), float(arrays["mass"]), {"units": "kg"})}
    for name in ("radius", "angle"):
        if name in arrays:
            coords[name] = (row, np.asarray(arrays[name], dtype=float), {"units": units[name]})
    data = {k: ((row, "velocity"), np.asarray(v), {"units": units.get(k, "1")})
            for k, v in arrays.items() if k not in coords}
    return xr.Dataset(data, coords=coords, attrs=attrs or {})


class _Tables:
    """The map as xarray and pandas objects, for notebooks."""

    def to_xarray(self):
        """A Dataset over (radius or angle, velocity): every result field with its units, the
        out-of-range points NaN, ``yielded`` boolean; attributes: shape, regime names."""
        attrs = {"shape": self.shape, "kind": self.kind,
                 "regime_names": list(self.regime_names), "range_limit": self.range_limit,
                 **self.attrs}
        return map_dataset(self.to_dict(), attrs, self.units)

    def to_dataframe(self):
        """A long table: one row per (radius or angle, velocity) point, a column per field,
        SI units (``df.attrs["units"]`` names them)."""
        ds = self.to_xarray()
        df = ds.to_dataframe()
        df.attrs["units"] = {k: v.attrs.get("units", "1") for k, v in ds.variables.items()}
        return df


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
class ImpactMap(_Tables):
    """Maxima on the grid ``radius`` (rows) x ``velocity`` (columns).

    An oblique map (`continuum.contact.oblique.oblique_map`) adds the incidence angle of each
    row and its tangential results with their units; its rows vary the radius or the angle,
    the other repeated.
    """

    velocity: np.ndarray        #: V, m/s, shape (n_V,)
    radius: np.ndarray          #: R, m, shape (n_R,)
    mass: float                 #: kg
    maxima: ImpactMaxima        #: fields of shape (n_R, n_V)
    angle: np.ndarray | None = None     #: incidence of each row (oblique), degrees
    #: oblique results (`oblique.OBLIQUE_FIELDS`), each of shape (n_R, n_V)
    tangential: dict = dataclasses.field(default_factory=dict)
    #: the unit of each tangential result
    tangential_units: dict = dataclasses.field(default_factory=dict)
    shape: ClassVar[str] = "sphere"
    fields: ClassVar[dict] = MAP_FIELDS
    range_limit: ClassVar[str] = "approach > R"
    status_messages: ClassVar[dict] = STATUS_MESSAGES
    attrs: ClassVar[dict] = {}

    @property
    def kind(self) -> str:
        """The registered model kind (`kinds.KINDS`) that made the map."""
        return "sphere-oblique" if self.tangential else "sphere"

    @property
    def units(self) -> dict[str, str]:
        """The unit of every result field."""
        return {**{k: v for k, v in ImpactMaxima.UNITS.items()
                   if k not in ("velocity", "radius", "mass")}, **self.tangential_units}

    @property
    def out_of_range(self) -> np.ndarray:
        """True where the approach would exceed R (not computed)."""
        return self.maxima.status == EXCEEDS_RADIUS

    @property
    def yielded(self) -> np.ndarray:
        return self.maxima.yielded

    @property
    def regime_names(self) -> tuple[str, ...]:
        return self.maxima.regime_names

    def field(self, name: str) -> np.ndarray:
        """One result as an (n_R, n_V) float array, NaN where out of range."""
        check_choice("map field", name, tuple(ImpactMaxima.UNITS) + tuple(self.tangential))
        if name in self.tangential:
            return np.asarray(self.tangential[name], dtype=float)
        return np.asarray(getattr(self.maxima, name), dtype=float)

    @classmethod
    def from_arrays(cls, arrays: dict, regime_names=(), contact_law: str = "",
                    tangential_units: dict | None = None) -> ImpactMap:
        """The map of a ``to_dict`` (as a map file or a scene result holds it);
        ``tangential_units`` names the oblique results it may hold, with their units."""
        V, R = np.asarray(arrays["velocity"]), np.asarray(arrays["radius"])
        shape = (R.size, V.size)
        fields = {k: np.asarray(arrays[k]) for k in ImpactMaxima.UNITS
                  if k not in ("velocity", "radius", "mass")}
        maxima = ImpactMaxima(
            velocity=np.broadcast_to(V[None, :], shape), radius=np.broadcast_to(R[:, None], shape),
            mass=np.full(shape, float(arrays["mass"])), yielded=np.asarray(arrays["yielded"], bool),
            regime=np.asarray(arrays["regime"]), status=np.asarray(arrays["status"]),
            regime_names=tuple(regime_names), contact_law=contact_law, unloading="", **fields)
        units = tangential_units or {}
        tangential = {k: np.asarray(arrays[k]) for k in arrays if k in units}
        return cls(velocity=V, radius=R, mass=float(arrays["mass"]), maxima=maxima,
                   angle=None if "angle" not in arrays else np.asarray(arrays["angle"]),
                   tangential=tangential,
                   tangential_units={k: units[k] for k in tangential})

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


def _map_axes(velocity, radius) -> tuple[np.ndarray, np.ndarray]:
    velocity = np.atleast_1d(check_float_array("velocity", velocity))
    radius = np.atleast_1d(check_float_array("radius", radius))
    if velocity.ndim != 1 or radius.ndim != 1:
        raise InputError(f"impact map axes must be 1-D arrays of velocity and radius, got "
                         f"shapes {velocity.shape} and {radius.shape}")
    if velocity.size * radius.size > MAX_MAP_POINTS:
        raise InputError(f"impact map of {velocity.size} x {radius.size} points exceeds "
                         f"{MAX_MAP_POINTS} points: use fewer velocities or radii")
    return velocity, radius


def impact_map(model: ImpactModel, velocity, radius, mass, progress=None) -> ImpactMap:
    """Fast-path maxima of ``model`` for every (R, V) pair of the two 1-D axes.

    ``progress(done, total)`` is passed on to `ImpactModel.maxima`.
    """
    velocity, radius = _map_axes(velocity, radius)
    mass = check_positive("mass", mass, "kg")
    maxima = model.maxima(velocity[None, :], radius[:, None], mass, progress=progress)
    return ImpactMap(velocity=velocity, radius=radius, mass=mass, maxima=maxima)


@dataclass(frozen=True)
class GridMap(_Tables):
    """Maxima of a model kind on the grid ``radius`` (rows) x ``velocity`` (columns), held as
    a dict of fields: the map of the cylinder (vectorised, `cylinder_map`) and of any kind
    whose map is computed one point at a time (`kinds.point_map`). What the kind declares
    (its fields, units, regimes, status codes, range) travels with the map."""

    velocity: np.ndarray        #: V, m/s, shape (n_V,)
    radius: np.ndarray          #: R, m, shape (n_R,)
    mass: float                 #: kg
    values: dict                #: field name -> (n_R, n_V) floats, NaN out of range
    regime: np.ndarray          #: index into ``regime_names``, -1 out of range
    status: np.ndarray          #: a key of ``status_messages``
    kind: str                   #: the registered model kind
    shape: str                  #: the impactor shape
    fields: dict                #: the fields a plot shows, with units
    units: dict                 #: every field of ``values``, with units
    regime_names: tuple[str, ...]
    status_messages: dict
    range_limit: str            #: what the out-of-range points exceed, in words
    #: the body's own lengths, m (a cylinder's length L), written as root attributes of a file
    attrs: dict = dataclasses.field(default_factory=dict)

    @property
    def out_of_range(self) -> np.ndarray:
        """True where the model's range is exceeded (not computed)."""
        return self.status == EXCEEDS_RADIUS

    @property
    def yielded(self) -> np.ndarray:
        return self.regime >= 1

    @property
    def length(self) -> float | None:
        """A cylinder's contact length L (m); None for other shapes."""
        return self.attrs.get("length")

    def field(self, name: str) -> np.ndarray:
        """One result as an (n_R, n_V) float array, NaN where out of range."""
        check_choice("map field", name, tuple(self.units))
        return self.values[name]

    def to_dict(self) -> dict:
        """Arrays in SI for the store: axes, every result field, status and regime."""
        return {"velocity": self.velocity, "radius": self.radius, "mass": self.mass,
                "status": self.status, "regime": self.regime, "yielded": self.yielded,
                **self.values}


def grid_map(model, velocity, radius, mass, *, kind: str, shape: str, fields: dict,
             units: dict, regime_names, status_messages, range_limit: str,
             attrs: dict | None = None, progress=None) -> GridMap:
    """``model.maxima(V, R, mass)`` (one impact, a result carrying every field of ``units``
    and its ``regime`` name) at every (R, V) pair of the two 1-D axes; points where the model
    raises ModelRangeError are out of range. ``progress(done, total)`` after each radius."""
    velocity, radius = _map_axes(velocity, radius)
    mass = check_positive("mass", mass, "kg")
    shape_ = (radius.size, velocity.size)
    values = {k: np.full(shape_, np.nan) for k in units}
    regime = np.full(shape_, -1)
    status = np.full(shape_, EXCEEDS_RADIUS)
    for i, R in enumerate(radius):
        for j, V in enumerate(velocity):
            try:
                res = model.maxima(V, R, mass)
            except ModelRangeError:
                continue
            for k in units:
                values[k][i, j] = getattr(res, k)
            regime[i, j], status[i, j] = regime_names.index(res.regime), OK
        if progress is not None:
            progress((i + 1) * velocity.size, velocity.size * radius.size)
    return GridMap(velocity=velocity, radius=radius, mass=mass, values=values, regime=regime,
                   status=status, kind=kind, shape=shape, fields=dict(fields),
                   units=dict(units), regime_names=tuple(regime_names),
                   status_messages=dict(status_messages), range_limit=range_limit,
                   attrs=attrs or {})


#: a cylinder map with ``progress`` reports after each of at most this many blocks of radii
_CYLINDER_PROGRESS_BLOCKS = 20


def cylinder_map(model: CylinderImpactModel, velocity, radius, mass,
                 progress=None) -> GridMap:
    """`CylinderImpactModel.maxima` at every (R, V) pair of the two 1-D axes, all points
    together by its vectorised fast path (`cylinder_fast`: about 0.3 s for 100 x 100 points
    on a uniform target, 1.5 s on a one-film stack); points beyond the line-contact laws'
    range are out of range (NaN).

    ``progress(done, total)`` is called after each block of radii: each radius up to 20
    radii, 20 blocks beyond.
    """
    velocity, radius = _map_axes(velocity, radius)
    mass = check_positive("mass", mass, "kg")
    # the lightest allowed mass grows with R: check the largest radius once
    check_cylinder_mass(float(radius.max()), model.length, mass)
    shape = (radius.size, velocity.size)
    values = {k: np.full(shape, np.nan) for k in CYLINDER_UNITS}
    regime = np.full(shape, -1)
    status = np.full(shape, EXCEEDS_RADIUS)
    rows = np.arange(radius.size)
    blocks = ([rows] if progress is None
              else np.array_split(rows, min(radius.size, _CYLINDER_PROGRESS_BLOCKS)))
    for block in blocks:
        found = model.maxima(velocity[None, :], radius[block, None], mass)
        for k in CYLINDER_UNITS:
            values[k][block] = getattr(found, k)
        regime[block], status[block] = found.regime, found.status
        if progress is not None:
            progress((int(block[-1]) + 1) * velocity.size, velocity.size * radius.size)
    return GridMap(velocity=velocity, radius=radius, mass=mass, values=values, regime=regime,
                   status=status, kind="cylinder", shape="cylinder",
                   fields=dict(CYLINDER_MAP_FIELDS), units=dict(CYLINDER_UNITS),
                   regime_names=REGIME_NAMES, status_messages=dict(CYLINDER_STATUS_MESSAGES),
                   range_limit="half-width > min(R, d/5)", attrs={"length": model.length})
