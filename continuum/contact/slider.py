"""A slider's protrusion sliding on a target: the contact it makes, the stresses in each layer,
where the target yields first and whether repeated passes shake down (issue 34; what
`filmscale slide` reports, docs/sliding.md).

Sliding kinds. A protrusion is a sphere (the thermal flying-height bump, a corner) or a
cylinder of length L (an edge, plane strain). Each shape is a `SlidingKind` in `SLIDING_KINDS`:
its Hertz contact, its field on the x-z plane through the contact and its shakedown limit. They are peers of the impact kinds (`kinds.KINDS`) in a registry of their own
because the question differs: an impact kind answers over (V, R) for a moving mass, a sliding
kind over (normal load, friction) for a slider held at its load.

Contact. The surface tractions are Hertz's, p = p0 sqrt(1 - r^2/a^2) and q = mu p in the
sliding direction (+x), at the contact size the target gives for the load:
- a homogeneous target: Hertz (Johnson 1985 eqs 4.22-4.23 sphere, 4.43-4.45 cylinder);
- one film on a substrate: the self-consistent size a = (3 P R / (4 E*(a)))^(1/3) with the
  exact apparent modulus of the coated half-space at radius a (`coated.apparent_modulus`:
  flat-punch stiffness / 2a, Perriot & Barthel 2004);
- more films: the same with the Gao-weighted modulus of `profiles.StackProfile` at a.
The pressure keeps Hertz's shape: on a layered target the true profile differs (stiffer
films concentrate it), which is not computed here (docs/sliding.md says by how much for the
size). A cylinder's half-width b uses the modulus at radius b.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from filmscale.core.checks import check_real
from filmscale.core.errors import InputError
from filmscale.core.keys import REQUIRED, Key

from ..materials import ElasticPlastic, LayerStack

# scipy and the stress fields are imported where they are used: the scene reader imports this
# module for the sliding kinds' keys, and `filmscale impact` loads no scipy sub-package

#: points per layer across its depth, and along x, of the field that `slide` reports and plots
FIELD_NZ = 24
FIELD_NX = 201
#: the field spans |x| <= X_SPAN size and, below the films, down to DEPTH size
X_SPAN = 2.5
DEPTH = 3.0
#: a point this fraction of a layer's thickness above its bottom stands for the interface seen
#: from inside the layer (sxx and syy jump across it; szz and the shears do not)
FACE = 1e-9


@dataclass(frozen=True)
class Slider:
    """The sliding protrusion: ``shape`` "sphere" or "cylinder", radius R (m), a cylinder's
    length L (m), its material (None: rigid) and a label."""

    shape: str
    radius: float
    length: float | None = None
    material: ElasticPlastic | None = None
    name: str = "slider"

    def __post_init__(self):
        kind = sliding_kind(self.shape)
        object.__setattr__(self, "radius", check_real("slider.radius", self.radius, low=1e-12,
                                                      high=1.0, low_open=True, unit="m"))
        if kind.shape == "cylinder":
            if self.length is None:
                raise InputError("slider.length is required for a cylinder (its contact "
                                 "length L, m)")
            object.__setattr__(self, "length", check_real(
                "slider.length", self.length, low=1e-12, high=1.0, low_open=True, unit="m"))
        elif self.length is not None:
            raise InputError("slider.length applies to a cylinder only (slider.shape = "
                             f"\"{self.shape}\")")
        if self.material is not None and not isinstance(self.material, ElasticPlastic):
            raise InputError(f"slider.material must be an ElasticPlastic or None (rigid), got "
                             f"{type(self.material).__name__}")


#: the largest contact size over the top film's thickness: the layered solutions integrate
#: over wavenumbers up to ~45/h_1, so their cost grows as a/h_1 (on 2 cores one x-z field of a
#: map takes ~1 s at a/h_1 = 300 and ~10 s (cylinder) or ~25 s (sphere) at 3000)
FILM_RATIO_MAX = 2000.0


def check_film_ratio(stack: LayerStack, size: float, what: str = "the contact") -> None:
    """InputError, before any field is computed, when the top film is thinner than the
    contact size (m) over `FILM_RATIO_MAX`."""
    if stack.layers and size / stack.layers[0].thickness > FILM_RATIO_MAX:
        layer = stack.layers[0]
        raise InputError(
            f"target.layers[0] ({layer.material.name or 'the top film'}) is "
            f"{layer.thickness:.3g} m thick, 1/{size / layer.thickness:.0f} of {what} "
            f"({size:.3g} m): the layered stress solutions take up to 1/{FILM_RATIO_MAX:.0f} "
            "(their cost grows as the ratio); lower the load or leave the film out")


@dataclass(frozen=True)
class SlideContact:
    """The Hertz tractions of one load: contact size (a or b, m), p0 (Pa), the load (N) and
    the contact modulus E* (Pa) that gave them, and how (words)."""

    size: float
    p0: float
    load: float
    E_star: float
    method: str


@dataclass(frozen=True)
class SlidingKind:
    """One slider shape: ``hertz(load, slider, E_star)`` -> (size, p0); ``field(x, z, stack,
    size, p0, mu)`` -> the stresses on the grid meshgrid(x, z) of the plane y = 0 (dict of
    arrays, Pa); ``unit_fields`` its parts per unit pressure and friction (maps);
    ``shakedown(material, mu)`` -> p0 of the elastic shakedown limit of a homogeneous target
    (Pa), or None where it is not modelled."""

    name: str
    shape: str
    dimension: str                  #: "2-D" (plane strain) or "3-D"
    size_name: str                  #: the JSON key of the contact size
    hertz: Callable
    field: Callable
    #: ``unit_fields(x, z, stack, size)`` -> (normal, tangential) fields of p0 = 1 (and
    #: mu = 1) on meshgrid(x, z): the field of (p0, mu) is p0 (normal + mu tangential)
    unit_fields: Callable
    shakedown: Callable | None = None
    keys: tuple[Key, ...] = ()      #: [slider] keys only this shape reads
    summary: str = ""


SLIDING_KINDS: dict[str, SlidingKind] = {}


def register_sliding(kind: SlidingKind) -> SlidingKind:
    SLIDING_KINDS[kind.shape] = kind
    return kind


def sliding_kind(shape: str) -> SlidingKind:
    """The sliding kind of a slider shape; InputError naming the shapes otherwise."""
    if shape not in SLIDING_KINDS:
        raise InputError(f"slider.shape = {shape!r} is not one of: {', '.join(SLIDING_KINDS)}")
    return SLIDING_KINDS[shape]


# --- contact -------------------------------------------------------------------------------

def _contact_modulus(stack: LayerStack, slider: Slider, size: float) -> float:
    """E* (Pa) of the slider on ``stack`` at contact size ``size`` (m)."""
    if stack.is_homogeneous:
        target = stack.substrate.plane_strain_modulus
    elif len(stack.layers) == 1:
        from .coated import LAMBDA_MAX, apparent_modulus
        layer = stack.layers[0]
        lam = size / layer.thickness
        # (1 - 1e-12): a/t of the product rounds above LAMBDA_MAX otherwise
        target = apparent_modulus(min(size, LAMBDA_MAX * (1 - 1e-12) * layer.thickness),
                                  layer.thickness, layer.material, stack.substrate)
        if lam > LAMBDA_MAX:
            # beyond the solved range the film's share falls as t/a: interpolate linearly in
            # t/a between the solution at a/t = LAMBDA_MAX and the substrate's at t/a = 0
            E_s = stack.substrate.plane_strain_modulus
            target = E_s + (target - E_s) * LAMBDA_MAX / lam
    else:
        from .profiles import StackProfile
        E_p, _, _ = StackProfile(stack).properties(size * size / slider.radius, slider.radius)
        target = float(E_p)
    if slider.material is None:
        return target
    return 1.0 / (1.0 / target + 1.0 / slider.material.plane_strain_modulus)


def contact(stack: LayerStack, slider: Slider, load: float) -> SlideContact:
    """The Hertz tractions of ``slider`` pressed on ``stack`` by ``load`` (N)."""
    if not isinstance(stack, LayerStack):
        raise InputError(f"stack must be a LayerStack, got {type(stack).__name__}")
    load = check_real("normal_load", load, low=0.0, high=1e6, low_open=True, unit="N")
    kind = sliding_kind(slider.shape)
    if stack.is_homogeneous:
        E_star = _contact_modulus(stack, slider, 1.0)
        size, p0 = kind.hertz(load, slider, E_star)
        return SlideContact(size, p0, load, E_star, "Hertz on the homogeneous substrate")
    moduli = [m.plane_strain_modulus for m in stack.materials()]
    if slider.material is not None:
        moduli = [1.0 / (1.0 / E + 1.0 / slider.material.plane_strain_modulus) for E in moduli]
    # the size grows as the modulus falls: bracketed by the stiffest and softest materials
    lo, hi = (kind.hertz(load, slider, E)[0] for E in (max(moduli), min(moduli)))

    def gap(log_size):
        size = math.exp(log_size)
        return math.log(kind.hertz(load, slider, _contact_modulus(stack, slider, size))[0]
                        / size)
    if hi / lo - 1.0 < 1e-12:
        size = lo
    else:
        from scipy import optimize
        size = math.exp(optimize.brentq(gap, math.log(lo) - 1e-9, math.log(hi) + 1e-9,
                                        xtol=1e-12, rtol=1e-12))
    E_star = _contact_modulus(stack, slider, size)
    size, p0 = kind.hertz(load, slider, E_star)
    how = ("the coated half-space's apparent modulus" if len(stack.layers) == 1
           else "the Gao-weighted modulus of the stack")
    return SlideContact(size, p0, load, E_star,
                        f"Hertz pressure at the contact size of {how} (self-consistent)")


# --- what one sliding contact gives ------------------------------------------------------------

def layer_depths(stack: LayerStack, size: float, nz: int = FIELD_NZ,
                 depth: float = DEPTH) -> list[np.ndarray]:
    """Per layer (top first, substrate last) nz depths (m) from its top to just above its
    bottom (`FACE`); the substrate's, 3 nz of them (it spans far more of the field), from
    its top down to ``depth`` contact sizes below it."""
    tops = np.concatenate(([0.0], np.cumsum([l.thickness for l in stack.layers])))
    out = []
    for j in range(len(stack.layers)):
        z0, z1 = tops[j], tops[j + 1]
        out.append(np.linspace(z0, z1 - FACE * (z1 - z0), nz))
    out.append(np.linspace(tops[-1], tops[-1] + depth * size, 3 * nz))
    return out


@dataclass(frozen=True)
class LayerRow:
    """One layer's (or the substrate's) worst points; lengths in m, stresses in Pa."""

    name: str
    z_top: float
    z_bottom: float              #: math.inf for the substrate
    von_mises_max: float
    x: float
    z: float
    yield_ratio: float | None    #: von_mises_max / sigma_y (None: sigma_y infinite)
    tensile_max: float           #: largest principal stress in the layer (x-z plane)
    interface_shear_max: float | None  #: largest shear on its bottom interface (None: substrate)
    interface_shear_x: float | None

    def to_dict(self) -> dict:
        return {"name": self.name, "von_mises_max": self.von_mises_max, "x": self.x,
                "z": self.z, "yield_ratio": self.yield_ratio, "tensile_max": self.tensile_max,
                "interface_shear_max": self.interface_shear_max,
                "interface_shear_x": self.interface_shear_x, "z_top": self.z_top,
                "z_bottom": None if math.isinf(self.z_bottom) else self.z_bottom}


@dataclass(frozen=True)
class SlideResult:
    """One sliding contact: its tractions, the per-layer table, the first yield, the
    surface's largest tension, the shakedown answer and the x-z field (for plots)."""

    kind: str
    slider: Slider
    stack: LayerStack
    contact: SlideContact
    friction: float
    layers: tuple[LayerRow, ...]
    surface_tensile_max: float
    surface_tensile_x: float
    shakedown: dict
    model: dict
    field: dict = field(repr=False, default_factory=dict)

    @property
    def first_yield(self) -> dict | None:
        """The layer with the largest yield ratio, and where; None when none has sigma_y."""
        rated = [r for r in self.layers if r.yield_ratio is not None]
        if not rated:
            return None
        worst = max(rated, key=lambda r: r.yield_ratio)
        return {"layer": worst.name, "x": worst.x, "z": worst.z,
                "yield_ratio": worst.yield_ratio, "yielded": worst.yield_ratio >= 1.0}

    def to_dict(self) -> dict:
        kind = sliding_kind(self.slider.shape)
        size = {"contact_radius": self.contact.size}
        if kind.size_name != "contact_radius":
            size[kind.size_name] = self.contact.size
        body = self.slider.material
        slider = {"name": self.slider.name, "shape": self.slider.shape,
                  "radius": self.slider.radius, "length": self.slider.length,
                  "E": None if body is None else body.E, "nu": None if body is None else body.nu}
        return {"kind": self.kind, "slider": slider, "p0": self.contact.p0, **size,
                "normal_load": self.contact.load, "friction": self.friction,
                "contact_modulus": self.contact.E_star, "contact_method": self.contact.method,
                "layers": [r.to_dict() for r in self.layers], "first_yield": self.first_yield,
                "surface_tensile_max": self.surface_tensile_max,
                "surface_tensile_x": self.surface_tensile_x, "shakedown": self.shakedown,
                "model": self.model}


def grid_field(kind, stack, size, p0, mu, nx, nz):
    """The x-z field per layer: x (m), the depths per layer and the stresses per layer (one
    evaluation over every depth: the layered spectra are computed once)."""
    x = np.linspace(-X_SPAN * size, X_SPAN * size, nx)
    depths = layer_depths(stack, size, nz)
    whole = kind.field(x, np.concatenate(depths), stack, size, p0, mu)
    cuts = np.cumsum([z.size for z in depths])[:-1]
    parts = {k: np.split(v, cuts, axis=0) for k, v in whole.items()}
    return x, depths, [{k: parts[k][j] for k in parts} for j in range(len(depths))]


#: local refinement of a grid maximum: points per side of each zoomed grid and zoom levels;
#: each level spans half the one before about its best point, so a ridge that runs across
#: cells is followed (the final spacing is 1/24 of a cell)
ZOOM_POINTS = 7
ZOOM_LEVELS = 4


def _zoom(measure, x0, z0, dx, dz, x_lim, z_lim):
    """The largest ``measure(x, z)`` (vectorised over a grid) near (x0, z0): `ZOOM_LEVELS`
    grids of `ZOOM_POINTS`^2 points, the first spanning +-1 cell, each next one half as wide
    about the best point so far, clipped to the box; dz = 0 searches along x only.
    Returns (value, x, z)."""
    best = None
    for _ in range(ZOOM_LEVELS):
        xs = np.unique(np.clip(np.linspace(x0 - dx, x0 + dx, ZOOM_POINTS), *x_lim))
        zs = np.unique(np.clip(np.linspace(z0 - dz, z0 + dz, ZOOM_POINTS if dz else 1),
                               *z_lim))
        values = measure(xs, zs)
        i, j = np.unravel_index(int(np.argmax(values)), values.shape)
        if best is None or values[i, j] > best[0]:
            best = (float(values[i, j]), float(xs[j]), float(zs[i]))
        x0, z0 = best[1], best[2]
        dx, dz = 0.5 * dx, 0.5 * dz
    return best


def _layer_row(kind, stack, size, p0, mu, x, z, f, name, sigma_y, j, refine):
    """One layer's row of the table from its grid field ``f`` (depths z), refined locally."""
    from .sliding import principal_stresses, von_mises
    n_layers = len(stack.layers)
    x_lim = (float(x[0]), float(x[-1]))
    z_lim = (float(z[0]), float(z[-1]))
    dx, dz = float(x[1] - x[0]), float(z[1] - z[0])

    def grid_max(values, dz_cell, measure):
        i, k = np.unravel_index(int(np.argmax(values)), values.shape)
        best = (float(values[i, k]), float(x[k]), float(z[i]))
        if refine:
            found = _zoom(measure, best[1], best[2], dx, dz_cell, x_lim, z_lim)
            best = max(best, found)
        return best

    def vm(xs, zs):
        return von_mises(kind.field(xs, zs, stack, size, p0, mu))

    vm_max, vx, vz = grid_max(von_mises(f), dz, vm)
    t_max = float(np.max(principal_stresses(f)[..., 0]))        # on the grid
    shear = shear_x = None
    if j < n_layers:
        bottom = np.abs(f["txz"][-1:])
        z_lim = (float(z[-1]), float(z[-1]))

        def interface(xs, zs):
            return np.abs(kind.field(xs, zs, stack, size, p0, mu)["txz"])
        shear, shear_x, _ = grid_max(bottom, 0.0, interface)
    tops = np.concatenate(([0.0], np.cumsum([l.thickness for l in stack.layers])))
    return LayerRow(name, float(tops[j]), float(tops[j + 1]) if j < n_layers else math.inf,
                    vm_max, vx, vz, None if math.isinf(sigma_y) else vm_max / sigma_y,
                    t_max, shear, shear_x)


def _shakedown(kind, stack, slider, c, mu) -> dict:
    if not stack.is_homogeneous:
        return {"modelled": False, "reason": "the shakedown of a layered target (Melan's "
                "theorem with layered residual stresses) is not modelled"}
    if kind.shakedown is None:
        return {"modelled": False, "reason": f"the shakedown of a {kind.shape} (three-"
                "dimensional residual stresses) is not modelled; the cylinder's is"}
    sub = stack.substrate
    if math.isinf(sub.sigma_y):
        return {"modelled": False, "reason": "the substrate has no yield strength"}
    p0_limit = kind.shakedown(sub, mu)
    return {"modelled": True, "p0_limit": p0_limit,
            "load_limit": c.load * (p0_limit / c.p0) ** 2,     # p0 ~ sqrt(P) on a line
            "shakes_down": bool(c.p0 <= p0_limit),
            "source": "Melan's static theorem, Johnson 1985 section 9.2"}


def slide(stack: LayerStack, slider: Slider, load: float, mu: float,
          nx: int = FIELD_NX, nz: int = FIELD_NZ, refine: bool = True) -> SlideResult:
    """One sliding contact of ``slider`` on ``stack`` under ``load`` (N) with friction ``mu``:
    the Hertz tractions (`contact`); on the x-z plane through the contact (|x| <= X_SPAN a,
    ``nx`` points; ``nz`` depths per layer), each layer's largest von Mises stress and where,
    its largest principal stress and the largest shear on its bottom interface, each grid
    maximum refined by zoomed grids (``refine``, `_zoom`); the surface's largest tension; the
    shakedown answer."""
    from .sliding import check_friction, principal_stresses
    mu = check_friction(mu)
    if not isinstance(nx, int) or not 11 <= nx <= 2001:
        raise InputError(f"nx = {nx!r} must be an integer in [11, 2001]")
    if not isinstance(nz, int) or not 3 <= nz <= 400:
        raise InputError(f"nz = {nz!r} must be an integer in [3, 400]")
    kind = sliding_kind(slider.shape)
    c = contact(stack, slider, load)
    check_film_ratio(stack, c.size, f"the contact size at {load:.3g} N")
    x, depths, fields = grid_field(kind, stack, c.size, c.p0, mu, nx, nz)
    mats = stack.materials()
    rows = tuple(_layer_row(kind, stack, c.size, c.p0, mu, x, z, f,
                            m.name or (f"layer {j + 1}" if j < len(stack.layers) else "substrate"),
                            m.sigma_y, j, refine)
                 for j, (m, z, f) in enumerate(zip(mats, depths, fields)))
    surface = principal_stresses({k: v[:1] for k, v in fields[0].items()})[0, :, 0]
    i = int(np.argmax(surface))
    model = {"dimension": kind.dimension, "target": "homogeneous" if stack.is_homogeneous
             else f"{len(stack.layers)} layers on a substrate", "field_grid": [nx, nz],
             "search": f"grid, then {ZOOM_LEVELS} zoomed grids per maximum" if refine
             else "grid"}
    return SlideResult(kind.name, slider, stack, c, mu, rows, float(surface[i]), float(x[i]),
                       _shakedown(kind, stack, slider, c, mu), model,
                       {"x": x, "depths": depths, "stresses": fields})


def field_von_mises(result: SlideResult) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """(x, depths per layer, von Mises per layer) of a result's x-z field (m, Pa)."""
    from .sliding import von_mises
    f = result.field
    return f["x"], f["depths"], [von_mises(s) for s in f["stresses"]]


# --- the kinds -----------------------------------------------------------------------------

def _sphere_hertz(load, slider, E_star):
    from .sliding import hertz_sphere
    return hertz_sphere(load, slider.radius, E_star)


def _cylinder_hertz(load, slider, E_star):
    from .sliding import hertz_cylinder
    return hertz_cylinder(load, slider.length, slider.radius, E_star)


def _cylinder_field(x, z, stack, size, p0, mu):
    from .sliding_layered import layered_cylinder_stresses
    X, Z = np.meshgrid(x, z)
    return layered_cylinder_stresses(X, Z, stack, size, p0, mu)


#: where the maps cut the cylinder's layered correction (s l; ~1e-10 p0 left, far below
#: the maps' grid error; `slide` keeps the module's 45)
MAP_DECAY_CUT = 30.0


def _cylinder_unit_fields(x, z, stack, size):
    from .sliding_layered import layered_cylinder_unit_fields
    return layered_cylinder_unit_fields(x, z, stack, size, cut=MAP_DECAY_CUT)


def _sphere_unit_fields(x, z, stack, size):
    from .sliding_sphere_layered import layered_sphere_xz
    normal = layered_sphere_xz(x, z, stack, size, 1.0, 0.0)
    both = layered_sphere_xz(x, z, stack, size, 1.0, 1.0)
    return normal, {k: both[k] - normal[k] for k in normal}


def _cylinder_shakedown(material, mu):
    from .sliding import cylinder_shakedown_pressure
    return cylinder_shakedown_pressure(mu, material.nu) * material.sigma_y / math.sqrt(3.0)


def _sphere_field(x, z, stack, size, p0, mu):
    from .sliding_sphere_layered import layered_sphere_xz
    return layered_sphere_xz(x, z, stack, size, p0, mu)


register_sliding(SlidingKind(
    name="sliding-sphere", shape="sphere", dimension="3-D", size_name="contact_radius",
    hertz=_sphere_hertz, field=_sphere_field, unit_fields=_sphere_unit_fields,
    summary="a sliding sphere (bump, corner): Hamilton's normal field, Cerruti's tangential "
            "one, layered corrections by Hankel transforms"))
register_sliding(SlidingKind(
    name="sliding-cylinder", shape="cylinder", dimension="2-D",
    size_name="contact_half_width", hertz=_cylinder_hertz, field=_cylinder_field,
    unit_fields=_cylinder_unit_fields, shakedown=_cylinder_shakedown,
    keys=(Key("length", "m", REQUIRED, 1e-12, 1.0, low_open=True, section="slider",
              doc="contact length L of a cylinder"),),
    summary="a sliding cylinder (edge) in plane strain: McEwen / Smith-Liu, layered by "
            "Airy functions per wavenumber"))
