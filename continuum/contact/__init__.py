"""filmscale.continuum.contact: a material (or layer stack) -> the impact of a rigid body.

Hertz contact and elastic impact (`hertz`), elastic-plastic sphere contact laws (`laws`),
depth profiles of layered targets (`profiles`), unloading and restitution (`restitution`),
the impact model with its maxima fast path and time integration (`impact`) and impact maps
(`impact_map`), oblique impact (`oblique`) and the line-contact impact of a finite cylinder
(`cylinder`). Equations: docs/physics.md sections 1-7. SI units.

This sub-package imports nothing of `indentation` or `calibration`.
"""

from filmscale.continuum.contact.cylinder import CylinderImpactModel, CylinderImpactResult
from filmscale.continuum.contact.hertz import (elastic_impact, elastic_impact_time, first_yield,
                                               yield_velocity)
from filmscale.continuum.contact.impact import ImpactModel, solve_impact
from filmscale.continuum.contact.impact_map import MAP_FIELDS, ImpactMap, impact_map
from filmscale.continuum.contact.laws import (LAW_NAMES, ContactLaw, Hertz, JacksonGreen,
                                              KogutEtsion, KomvopoulosYe, Thornton, contact_law)
from filmscale.continuum.contact.oblique import ObliqueResult, solve_oblique
from filmscale.continuum.contact.profiles import (DepthProfile, StackProfile, TableProfile,
                                                  UniformProfile)
from filmscale.continuum.contact.restitution import UNLOADING_MODELS, thornton_restitution
from filmscale.continuum.contact.results import ImpactHistory, ImpactMaxima, ImpactResult

__all__ = [
    "contact_law", "LAW_NAMES", "ContactLaw", "Hertz", "KomvopoulosYe", "KogutEtsion",
    "JacksonGreen", "Thornton",
    "elastic_impact", "elastic_impact_time", "first_yield", "yield_velocity",
    "DepthProfile", "UniformProfile", "StackProfile", "TableProfile",
    "ImpactModel", "ImpactResult", "ImpactMaxima", "ImpactHistory", "solve_impact",
    "solve_oblique", "ObliqueResult", "CylinderImpactModel", "CylinderImpactResult",
    "impact_map", "ImpactMap", "MAP_FIELDS", "UNLOADING_MODELS", "thornton_restitution",
]
