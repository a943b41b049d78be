"""First-yield maps of a sliding contact over normal load and friction (`filmscale slide-map`,
issue 34; docs/sliding.md).

The stresses are linear in the tractions: at one load (one contact size a and peak pressure
p0) the field is p0 (N + mu T), with N the field of the normal pressure and T that of a unit
friction. Each load therefore costs two field evaluations on the layer grid
(`slider.layer_depths` x `slider.FIELD_NX`-like x points) and every friction of the map is a
cheap combination of them. A homogeneous target's field in units of (a, p0) does not depend on
the load, so its whole map costs two evaluations. The maxima are those of the grid (no local
search): their error is the grid's, measured against `slider.slide` in
tests/continuum/test_slide.py and benchmarks/slide_map_speed.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from filmscale.core.errors import InputError

from ..materials import LayerStack
from .sliding import principal_stresses, von_mises
from .slider import Slider, check_film_ratio, contact, layer_depths, sliding_kind

#: the grid of a map: x points over |x| <= MAP_X_SPAN a and depths per layer (coarser than
#: `slide`'s field; the maxima of a sliding contact lie within |x| <= 1.2 a, the surface's at
#: the trailing edge x = -a)
MAP_NX = 121
MAP_NZ = 16
MAP_X_SPAN = 1.5
#: the most points of a map (loads x frictions)
MAP_POINTS_MAX = 250_000

#: units of every array of a map (SI)
SLIDE_MAP_UNITS = {
    "normal_load": "N", "friction": "1", "contact_size": "m", "p0": "Pa",
    "yield_ratio_max": "1", "first_yield_layer": "1", "first_yield_x": "m",
    "first_yield_z": "m", "surface_tensile_max": "Pa", "layer_yield_ratio": "1",
    "layer_von_mises_max": "Pa", "interface_shear_max": "Pa", "first_yield_load": "N",
    "first_yield_load_layer": "1", "first_yield_load_z": "m", "shakedown_load": "N",
}


@dataclass(frozen=True)
class SlideMap:
    """A map over loads (columns) and frictions (rows). Arrays (frictions, loads) unless
    said: ``layer_*`` are (layers, frictions, loads), ``interface_shear_max`` (interfaces,
    frictions, loads), ``contact_size``, ``p0`` (loads), ``first_yield_load*`` and
    ``shakedown_load`` (frictions). Layer indices count from the top film (0) to the
    substrate (``layer_names[-1]``); -1 where no layer has a yield strength."""

    kind: str
    normal_load: np.ndarray
    friction: np.ndarray
    layer_names: tuple[str, ...]
    values: dict = field(repr=False)
    grid: tuple[int, int] = (MAP_NX, MAP_NZ)

    def __getitem__(self, key):
        return self.values[key]

    def to_dict(self) -> dict:
        return {"normal_load": self.normal_load, "friction": self.friction, **self.values}


def _unit_fields(kind, stack, size, nx, nz):
    """(N, T) per layer at p0 = 1 Pa (and mu = 1 for T): dicts of (depths, x) arrays."""
    x = np.linspace(-MAP_X_SPAN * size, MAP_X_SPAN * size, nx)
    depths = layer_depths(stack, size, nz)
    cuts = np.cumsum([z.size for z in depths])[:-1]
    parts = []
    for whole in kind.unit_fields(x, np.concatenate(depths), stack, size):
        split = {k: np.split(v, cuts, axis=0) for k, v in whole.items()}
        parts.append([{k: split[k][j] for k in split} for j in range(len(depths))])
    return x, depths, parts[0], parts[1]


def _first_crossing(loads, ratio):
    """The load (log-interpolated) where ``ratio`` first reaches 1, and the index of the grid
    load just above; NaN, -1 when it does not within the axis."""
    above = np.nonzero(ratio >= 1.0)[0]
    if not above.size:
        return math.nan, -1
    i = int(above[0])
    if i == 0:
        return float(loads[0]) if ratio[0] == 1.0 else math.nan, 0
    r0, r1 = math.log(ratio[i - 1]), math.log(ratio[i])
    t = -r0 / (r1 - r0) if r1 > r0 else 1.0
    return float(math.exp(math.log(loads[i - 1]) + t * math.log(loads[i] / loads[i - 1]))), i


def slide_map(stack: LayerStack, slider: Slider, loads, frictions, nx: int = MAP_NX,
              nz: int = MAP_NZ, progress=None) -> SlideMap:
    """First yield over ``loads`` (N, increasing) x ``frictions`` (increasing, >= 0);
    ``progress(done, total)`` is called after each load."""
    kind = sliding_kind(slider.shape)
    loads = np.asarray(loads, dtype=float)
    frictions = np.asarray(frictions, dtype=float)
    for name, a in (("normal_load", loads), ("friction", frictions)):
        if a.ndim != 1 or a.size < 1 or not np.all(np.isfinite(a)) or np.any(np.diff(a) <= 0):
            raise InputError(f"{name} must be a non-empty increasing 1-D axis, got {a!r}")
    if loads[0] <= 0 or frictions[0] < 0:
        raise InputError("the map's loads must be > 0 N and its frictions >= 0")
    if loads.size * frictions.size > MAP_POINTS_MAX:
        raise InputError(f"the slide map has {frictions.size} x {loads.size} points, more than "
                         f"the limit of {MAP_POINTS_MAX}")
    # the largest load has the largest contact: refused here, before any field
    check_film_ratio(stack, contact(stack, slider, float(loads[-1])).size,
                     f"the contact size at the map's largest load, {loads[-1]:.3g} N")
    mats = stack.materials()
    names = tuple(m.name or (f"layer {j + 1}" if j < len(stack.layers) else "substrate")
                  for j, m in enumerate(mats))
    sigma_y = np.array([m.sigma_y for m in mats])
    n_l, n_f, n_p = len(mats), frictions.size, loads.size
    layer_vm = np.empty((n_l, n_f, n_p))
    layer_x = np.empty((n_l, n_f, n_p))
    layer_z = np.empty((n_l, n_f, n_p))
    tensile = np.empty((n_f, n_p))
    shear = np.empty((max(n_l - 1, 0), n_f, n_p))
    sizes, p0s = np.empty(n_p), np.empty(n_p)
    unit = None
    for i, load in enumerate(loads):
        c = contact(stack, slider, float(load))
        sizes[i], p0s[i] = c.size, c.p0
        if unit is None or not stack.is_homogeneous:
            unit = _unit_fields(kind, stack, c.size, nx, nz)
            base = c.size
        x, depths, normal, tangential = unit
        scale = c.size / base                      # homogeneous: the field scales with a
        for j in range(n_l):
            s = {k: normal[j][k][None] + frictions[:, None, None] * tangential[j][k][None]
                 for k in normal[j]}
            vm = von_mises(s) * c.p0                                   # (frictions, z, x)
            flat = vm.reshape(n_f, -1)
            at = np.argmax(flat, axis=1)
            layer_vm[j, :, i] = flat[np.arange(n_f), at]
            iz, ix = np.unravel_index(at, vm.shape[1:])
            layer_x[j, :, i], layer_z[j, :, i] = x[ix] * scale, depths[j][iz] * scale
            if j == 0:
                top = {k: v[:, :1] for k, v in s.items()}
                tensile[:, i] = principal_stresses(top)[..., 0].max(axis=(1, 2)) * c.p0
            if j < n_l - 1:
                shear[j, :, i] = np.abs(s["txz"][:, -1, :]).max(axis=1) * c.p0
        if progress is not None:
            progress(i + 1, loads.size)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = layer_vm / sigma_y[:, None, None]
    rated = np.isfinite(sigma_y)
    values = {"contact_size": sizes, "p0": p0s, "layer_von_mises_max": layer_vm,
              "layer_yield_ratio": np.where(rated[:, None, None], ratio, np.nan),
              "surface_tensile_max": tensile, "interface_shear_max": shear}
    if rated.any():
        masked = np.where(rated[:, None, None], ratio, -np.inf)
        first = np.argmax(masked, axis=0)
        f_idx, p_idx = np.indices(first.shape)
        values["yield_ratio_max"] = masked[first, f_idx, p_idx]
        values["first_yield_layer"] = first
        values["first_yield_x"] = layer_x[first, f_idx, p_idx]
        values["first_yield_z"] = layer_z[first, f_idx, p_idx]
    else:
        values["yield_ratio_max"] = np.full((n_f, n_p), np.nan)
        for key in ("first_yield_layer", "first_yield_x", "first_yield_z"):
            values[key] = np.full((n_f, n_p), -1 if key.endswith("layer") else np.nan)
    load_at = np.full(n_f, np.nan)
    layer_at = np.full(n_f, -1)
    z_at = np.full(n_f, np.nan)
    for f in range(n_f):
        load_at[f], i = _first_crossing(loads, values["yield_ratio_max"][f])
        if i >= 0:
            layer_at[f], z_at[f] = values["first_yield_layer"][f, i], values["first_yield_z"][f, i]
    values |= {"first_yield_load": load_at, "first_yield_load_layer": layer_at,
               "first_yield_load_z": z_at}
    if stack.is_homogeneous and kind.shakedown is not None and rated[-1]:
        # p0 grows as sqrt(load) on a line contact: the load at the shakedown p0
        p0_sd = np.array([kind.shakedown(stack.substrate, float(mu)) for mu in frictions])
        values["shakedown_load"] = loads[0] * (p0_sd / p0s[0]) ** 2
    return SlideMap(kind.name, loads, frictions, names, values, (nx, nz))
