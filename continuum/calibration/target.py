"""What a calibration curve was measured on: the forward model of a sphere calibration.

A curve of an MD run is a film of known thickness on the MD substrate; a particle-model curve
has its own layers; a measured curve is a film on the substrate the user states, or a
half-space. `SphereTarget` evaluates the contact law over a curve's approaches with the
calibrated layer in its place:

- a half-space of the layer: E*, sigma_y and nu are the layer's, uniform;
- a film of ``thickness`` on ``substrate``: E_p = E/(1 - nu^2), sigma_y and nu are weighted
  with Gao, Chiu & Lee (1992) at the contact radius a = sqrt(R delta), exactly as the impact
  model weights a layer stack (`filmscale.continuum.contact.profiles.StackProfile`,
  docs/physics.md section 7), so that the calibrated film goes unchanged into a scene's stack.

A simulated film's slab stands on a rigid base (an MD slab's fixed atoms, a particle block's
base): with ``base_depth`` H (m, below the surface) the exact elastic branch is the film on
H - t of substrate on that base (`coated.stack_sphere_curve`), so the base's stiffening is in
the model rather than in E. A half-space keeps the law's own elastic branch and a note on
the base: on MD crystals the exact based solution read E well under the crystal's face (a
5 nm Cu(001) slab 0.86 of its indentation modulus, against 1.04 without the base;
docs/pipeline.md, "A rigid base under a simulated sample").

The tip counts through ``indenter`` (None: rigid, as the MD and particle tips are; a
diamond tip for measured curves): 1/E* = 1/E_p + (1 - nu_i^2)/E_i. The regime of the law at
each point is the one of the largest severity reached so far (a layered target's severity
need not rise monotonically; docs/physics.md section 3).

The calibration's unknowns are the layer's reduced modulus against the tip, E*_layer, and
its sigma_y; a substrate whose sigma_y is not stated (infinite) is given the film's sigma_y,
so that only the elastic mismatch of the substrate is modelled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.contact.hertz import hertz_force_unchecked
from filmscale.continuum.contact.laws import ContactLaw
from filmscale.continuum.contact.profiles import StackProfile
from filmscale.continuum.contact.sneddon import SneddonElastic, sneddon_force
from filmscale.continuum.materials import (ElasticPlastic, Layer, LayerStack,
                                           modulus_from_reduced, reduced_modulus)
from filmscale.core.checks import THICKNESS_MAX, check_real
from filmscale.core.errors import InputError
from filmscale.core.quantities import eng

#: what a tip is made of: rigid (the tips of MD and particle runs) or diamond (measured)
TIP_MATERIALS = ("rigid", "diamond")
#: a film's elastic loading comes from the exact layered solution up to this contact radius
#: in film thicknesses (0.04 s a solution there); beyond, the film's share is below 1 % and
#: the Gao weighting serves
EXACT_MAX_RADIUS = 100.0
#: how a sphere calibration places the contact zero: fitted with E* or fixed at the
#: curve's h = 0
CONTACT_ZEROS = ("fit", "fixed")


@dataclass(frozen=True)
class SphereTarget:
    """The layer under calibration (Poisson ratio ``nu``), alone or as a film of
    ``thickness`` (m) on ``substrate``, pressed by a tip of material ``indenter``; a film's
    slab may stand on a rigid base ``base_depth`` (m) under the surface."""

    nu: float
    indenter: ElasticPlastic | None = None
    thickness: float | None = None
    substrate: ElasticPlastic | None = None
    base_depth: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "nu", check_real("nu", self.nu, low=-1.0, high=0.5,
                                                  low_open=True, high_open=True))
        if (self.thickness is None) != (self.substrate is None):
            raise InputError("a film calibration needs both the film thickness and the "
                             "substrate (or neither, for a half-space of the layer)")
        if self.thickness is not None:
            check_real("film thickness", self.thickness, low=0.0, low_open=True,
                       high=THICKNESS_MAX, unit="m")
            if not isinstance(self.substrate, ElasticPlastic):
                raise InputError(f"substrate must be an ElasticPlastic material, got "
                                 f"{self.substrate!r}")
        if self.base_depth is not None:
            if not self.layered:
                raise InputError("base_depth is a film's slab's: a half-space keeps the law's "
                                 "own elastic branch, without a base")
            check_real("base_depth", self.base_depth, low=self.thickness, low_open=True,
                       high=THICKNESS_MAX, unit="m")

    @property
    def layered(self) -> bool:
        return self.thickness is not None

    @property
    def compliance(self) -> float:
        """(1 - nu_i^2)/E_i of the tip, 1/Pa (0 for a rigid tip)."""
        return 0.0 if self.indenter is None else self.indenter.compliance

    def layer_modulus(self, E_star) -> float:
        """The layer's Young's modulus E (Pa) from its reduced modulus against the tip."""
        return float(modulus_from_reduced(E_star, self.nu, self.compliance))

    def properties(self, delta, R, E_star, sigma_y, yielding_substrate: bool = True):
        """(E*, sigma_y, nu) felt at approaches ``delta`` (m) by a sphere of radius R (m)
        when the layer has reduced modulus ``E_star`` and yield strength ``sigma_y`` (Pa).
        ``yielding_substrate=False`` gives the substrate the layer's sigma_y whatever it is
        stated to be (the Hertz branch of a fit, where nothing may yield)."""
        if not self.layered:
            return E_star, sigma_y, self.nu
        # a fit's trial E* and sigma_y: unchecked for plausibility (`ElasticPlastic._trial`)
        film = ElasticPlastic._trial(self.layer_modulus(E_star), self.nu, sigma_y)
        substrate = self.substrate
        if not (yielding_substrate and math.isfinite(substrate.sigma_y)):
            substrate = ElasticPlastic._trial(substrate.E, substrate.nu, sigma_y, substrate.n,
                                              substrate.name)
        e_p, s_y, nu = StackProfile(LayerStack((Layer(self.thickness, film),),
                                               substrate)).properties(delta, R)
        return reduced_modulus(e_p, self.indenter), s_y, nu

    def film_weights(self, delta, R):
        """Gao's (I1, I0) weights of the film and the substrate at approaches ``delta`` (m)
        under a sphere of radius R (they depend on the Poisson ratios only), or None for a
        half-space: what `felt` combines."""
        if not self.layered:
            return None
        film = ElasticPlastic._trial(self.substrate.E, self.nu, 1.0)  # E, sigma_y do not count
        profile = StackProfile(LayerStack((Layer(self.thickness, film),), self.substrate))
        return profile.weights(np.asarray(delta, dtype=float), R)

    def felt(self, E_star, sigma_y, weights):
        """(E*, sigma_y, nu) felt through `film_weights` when the film has reduced modulus
        ``E_star`` and strength ``sigma_y`` (Pa; arrays over the approaches allowed): the
        Gao-weighted plane-strain moduli, strengths and Poisson ratios (a substrate without
        sigma_y takes the film's), E_p made reduced against the tip."""
        w1, w0 = weights
        film_Ep = self.layer_modulus(E_star) / (1.0 - self.nu**2)
        s = self.substrate
        sub_sy = s.sigma_y if math.isfinite(s.sigma_y) else sigma_y
        E_p = w0[..., 0] * film_Ep + w0[..., 1] * s.plane_strain_modulus
        return (reduced_modulus(E_p, self.indenter), w0[..., 0] * sigma_y + w0[..., 1] * sub_sy,
                w1[..., 0] * self.nu + w1[..., 1] * s.nu)

    def forces(self, law: ContactLaw, delta, R, E_star, sigma_y, yielding_substrate=True):
        """(force (N), branch) of ``law`` over a loading record of approaches ``delta``."""
        delta = np.asarray(delta, dtype=float)
        props = self.properties(delta, R, E_star, sigma_y, yielding_substrate)
        severity = np.maximum.accumulate(np.atleast_1d(law.severity(delta, R, *props)))
        branch = law.branch_of(severity)
        return law.force_area(delta, R, *props, branch)[0], branch

    def exact_elastic(self, delta_max: float, R: float) -> bool:
        """Whether the elastic loading before a pop-in is taken from the exact layered
        solution (`contact.coated`): a film under a rigid tip (the solution's indenter),
        at contact radii up to `EXACT_MAX_RADIUS` film thicknesses."""
        return (self.layered and self.indenter is None
                and math.sqrt(R * delta_max) <= EXACT_MAX_RADIUS * self.thickness)

    def hertz(self, delta, R, E_star, law: ContactLaw | None = None, exact: bool = False):
        """The elastic force (N) at approaches ``delta``: the loading before a pop-in.

        A half-space (or ``exact`` False): Hertz's paraboloid (Johnson 1985) with the reduced
        modulus felt at each approach (Gao-weighted on a film), or Sneddon's exact sphere
        when ``law`` has Sneddon's elastic branch (`contact.sneddon.SneddonElastic`).
        ``exact`` (a film, `exact_elastic`): the converged layered solution of a rigid
        paraboloid (`coated.coated_sphere_curve`; with ``base_depth``, the film and the
        substrate above it on the rigid base: `coated.stack_sphere_curve`), times
        Sneddon's ratio of the sphere to the paraboloid on a half-space when ``law`` has
        Sneddon's branch (the two corrections combined to first order)."""
        if exact:
            from filmscale.continuum.contact.coated import (RIGID, coated_sphere_curve,
                                                            stack_sphere_curve)
            film = ElasticPlastic._trial(self.layer_modulus(E_star), self.nu, 1.0)
            if self.base_depth is None:
                force = coated_sphere_curve(delta, R, self.thickness, film, self.substrate)
            else:
                force = stack_sphere_curve(delta, R, [
                    (self.thickness, film),
                    (self.base_depth - self.thickness, self.substrate)], RIGID)
            if isinstance(law, SneddonElastic):
                d = np.asarray(delta, dtype=float)
                shape = np.ones(d.shape)
                positive = d > 0
                shape[positive] = (sneddon_force(d[positive], R, 1.0)
                                   / hertz_force_unchecked(d[positive], R, 1.0))
                force = force * shape
            return force
        # the reduced modulus does not depend on sigma_y: any finite value serves
        felt = self.properties(delta, R, E_star, 1.0, False)[0]
        if isinstance(law, SneddonElastic):
            return sneddon_force(delta, R, felt)
        return hertz_force_unchecked(delta, R, felt)

    def exact_note(self) -> str:
        """What a calibration says when its elastic loading took the exact solution."""
        base = ("" if self.base_depth is None else
                f", on the slab's rigid base {eng(self.base_depth, 'm', 3)} under the surface")
        return "elastic loading on the film: the exact layered solution (Perriot & Barthel " \
            "2004)" + base

    def describe(self) -> str:
        tip = "rigid tip" if self.indenter is None else f"{self.indenter.name or 'elastic'} tip"
        if not self.layered:
            return f"half-space of the layer, {tip}"
        s = self.substrate
        strength = (f"sigma_y {eng(s.sigma_y, 'Pa', 3)}" if math.isfinite(s.sigma_y)
                    else "sigma_y taken as the film's")
        return (f"film of {eng(self.thickness, 'm', 3)} on {s.name or 'substrate'} "
                f"(E {eng(s.E, 'Pa', 3)}, "
                f"nu {s.nu:.3g}, {strength}), Gao-weighted"
                + ("" if self.base_depth is None else
                   f" (exact elastic branch on a rigid base {eng(self.base_depth, 'm', 3)} "
                   "down)") + f"; {tip}")
