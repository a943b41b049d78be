"""Isotropic elastic-plastic materials, the reduced modulus, and layer stacks.

Units: E and sigma_y in Pa, thickness in m. The reduced (effective) modulus follows
1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Johnson, Contact Mechanics, 1985, eq. 4.22); some
texts write E' = 2 E*, this package never does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.core.checks import (MODULUS_MAX, THICKNESS_MAX, check_modulus, check_real,
                                   check_yield_strength)
from filmscale.core.errors import InputError


@dataclass(frozen=True)
class ElasticPlastic:
    """Isotropic elastic-plastic material with power-law hardening.

    Parameters
    ----------
    E : float
        Young's modulus, Pa.
    nu : float
        Poisson ratio, in (-1, 0.5).
    sigma_y : float
        Uniaxial yield strength, Pa; ``math.inf`` for a material that never yields.
    n : float
        Power-law hardening exponent in [0, 1): sigma = sigma_y (1 + E eps_p / sigma_y)^n
        (Dao et al. 2001). The impact contact laws are elastic-perfectly plastic and ignore it.
    name : str
        Label used in reports.

    A material is checked when it is made: E must be that of a real solid
    (`filmscale.core.checks.MODULUS_PLAUSIBLE`, 0.1 GPa to 2 TPa; a unit slip such as 90 for
    90 GPa is refused with the value meant), sigma_y > 0 and below E (yield strains of 1 and
    more do not exist), nu in (-1, 0.5) and n in [0, 1); InputError names the parameter
    (``name.E`` when the material has a name). Fits that try values outside these ranges
    build their trial materials with `_trial`.
    """

    E: float
    nu: float
    sigma_y: float = math.inf
    n: float = 0.0
    name: str = ""

    def __post_init__(self):
        self._check(plausible=True)

    @classmethod
    def _trial(cls, E, nu, sigma_y=math.inf, n=0.0, name: str = "") -> "ElasticPlastic":
        """A material of a fit's trial values: range-checked (E in (0, MODULUS_MAX], sigma_y
        > 0, nu and n as always) but not for physical plausibility, because least squares
        and scans step through moduli and strengths no real solid has (a film's E from 1 MPa
        to 100 TPa in `film_modulus`, sigma_y above a trial E) on their way to the answer.
        Internal: what a user makes goes through the checked constructor."""
        material = object.__new__(cls)
        for key, value in (("E", E), ("nu", nu), ("sigma_y", sigma_y), ("n", n),
                           ("name", name)):
            object.__setattr__(material, key, value)
        material._check(plausible=False)
        return material

    def _check(self, plausible: bool) -> None:
        label = f"{self.name}." if self.name else ""
        E = check_real(f"{label}E", self.E, low=0.0, low_open=True, high=MODULUS_MAX,
                       unit="Pa")
        nu = check_real(f"{label}nu", self.nu, low=-1.0, high=0.5, low_open=True,
                        high_open=True)
        sy = check_real(f"{label}sigma_y", self.sigma_y, low=0.0, high=math.inf,
                        low_open=True, unit="Pa")
        n = check_real(f"{label}n", self.n, low=0.0, high=1.0, high_open=True)
        if plausible:
            check_modulus(f"{label}E", E, "Young's modulus")
            check_yield_strength(f"{label}sigma_y", sy, E, f"{label}E")
        for key, value in (("E", E), ("nu", nu), ("sigma_y", sy), ("n", n)):
            object.__setattr__(self, key, value)

    @property
    def plane_strain_modulus(self) -> float:
        """E / (1 - nu^2), Pa: this body's share of the reduced modulus."""
        return self.E / (1.0 - self.nu**2)

    @property
    def bulk_modulus(self) -> float:
        """K = E / (3 (1 - 2 nu)), Pa (isotropic elasticity)."""
        return self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)), Pa (isotropic elasticity)."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def compliance(self) -> float:
        """(1 - nu^2) / E, 1/Pa."""
        return (1.0 - self.nu**2) / self.E

    def reduced_modulus(self, counterface: "ElasticPlastic | None" = None) -> float:
        """Reduced modulus E* against `counterface` (rigid when None), Pa."""
        return reduced_modulus(self.plane_strain_modulus, counterface)


def reduced_modulus(plane_strain_modulus, counterface: ElasticPlastic | None = None):
    """E* from a body's plane-strain modulus E/(1-nu^2) (Pa, scalar or array) and a counterface.

    ``counterface=None`` means a rigid counterface, E* = E/(1-nu^2).
    """
    if counterface is None:
        return plane_strain_modulus
    return 1.0 / (1.0 / plane_strain_modulus + counterface.compliance)


def modulus_from_reduced(E_r, nu, counterface_compliance=0.0):
    """Young's modulus E (Pa) of a body from a reduced modulus E_r (Pa, scalar or array).

    E = (1 - nu^2) / (1/E_r - (1 - nu_c^2)/E_c), inverting Johnson (1985) eq. 4.22, with the
    counterface's compliance (1 - nu_c^2)/E_c in 1/Pa (0: rigid). NaN where E_r is not below
    what the counterface allows.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        rest = 1.0 / np.asarray(E_r, dtype=float) - counterface_compliance
        return np.where(rest > 0, (1.0 - np.asarray(nu) ** 2) / rest, np.nan)


def check_plausible(material: ElasticPlastic, label: str = "") -> ElasticPlastic:
    """``material`` when it could be a real solid: E within `MODULUS_PLAUSIBLE` and sigma_y
    below E (`filmscale.core.checks`); else InputError naming ``label.E`` or
    ``label.sigma_y`` (``label``: the material's name by default) and the likely unit slip.
    The models call it at their entry: `ElasticPlastic` checks the same when it is made, and
    this catches a fit's unchecked trial material (`ElasticPlastic._trial`) that reaches a
    model."""
    label = label or material.name or "material"
    check_modulus(f"{label}.E", material.E, "Young's modulus")
    check_yield_strength(f"{label}.sigma_y", material.sigma_y, material.E, f"{label}.E")
    return material


def check_layer_count(name: str, count: int) -> int:
    """``count`` when it is at most `MAX_LAYERS`, else InputError naming ``name``."""
    if count > MAX_LAYERS:
        raise InputError(f"{name} has {count} layers, more than the limit of {MAX_LAYERS} "
                         "(real film stacks have tens; every layer costs each contact point "
                         "a term of the Gao weighting)")
    return count


#: Diamond indenter, the usual nanoindentation counterface (docs/physics.md section 9).
DIAMOND = ElasticPlastic(E=1141e9, nu=0.07, name="diamond")


@dataclass(frozen=True)
class Layer:
    """One film of a stack: thickness (m) and material."""

    thickness: float
    material: ElasticPlastic

    def __post_init__(self):
        if not isinstance(self.material, ElasticPlastic):
            raise InputError(f"a layer's material must be an ElasticPlastic, got "
                             f"{type(self.material).__name__}")
        name = self.material.name or "layer"
        object.__setattr__(self, "thickness",
                           check_real(f"{name}.thickness", self.thickness, low=0.0,
                                      low_open=True, high=THICKNESS_MAX, unit="m"))


#: the most layers a stack takes: real magnetic disks have fewer than 20 and multilayer
#: mirrors and superlattices a few hundred, while the Gao weighting costs every contact point
#: a term per layer: at 1000 layers one impact takes 0.1 s and a 20 x 20 impact map 9 s and
#: 1.2 GB (the weights of a 1024-point chunk over the layers); a 230,000-layer scene ran out
#: of 3 GB of memory after 77 s
MAX_LAYERS = 1000


@dataclass(frozen=True)
class LayerStack:
    """Films on a substrate, top layer first. An empty `layers` is a homogeneous half-space.
    At most `MAX_LAYERS` layers."""

    layers: tuple[Layer, ...]
    substrate: ElasticPlastic

    def __post_init__(self):
        if not isinstance(self.substrate, ElasticPlastic):
            raise InputError(f"a layer stack needs a substrate (an ElasticPlastic), got "
                             f"{self.substrate!r}")
        if isinstance(self.layers, (str, bytes)) or not hasattr(self.layers, "__iter__"):
            raise InputError(f"layers must be a sequence of Layer objects (empty for a "
                             f"half-space), got {self.layers!r}")
        layers = tuple(self.layers)
        check_layer_count("layers", len(layers))
        for layer in layers:
            if not isinstance(layer, Layer):
                raise InputError(f"layers must hold Layer objects, got {type(layer).__name__}")
        object.__setattr__(self, "layers", layers)

    @property
    def is_homogeneous(self) -> bool:
        return not self.layers

    @property
    def interface_depths(self) -> tuple[float, ...]:
        """Depth of the bottom of each layer below the free surface, m (z_1 ... z_N)."""
        depths, z = [], 0.0
        for layer in self.layers:
            z += layer.thickness
            depths.append(z)
        return tuple(depths)

    def materials(self) -> tuple[ElasticPlastic, ...]:
        """Layer materials top first, then the substrate."""
        return tuple(layer.material for layer in self.layers) + (self.substrate,)
