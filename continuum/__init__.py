"""filmscale.continuum: contact, impact and indentation models in numpy/scipy (no LAMMPS).

Public API, SI units throughout:

- materials: `ElasticPlastic`, `Layer`, `LayerStack`, `DIAMOND`, `reduced_modulus`
- depth profiles: `UniformProfile`, `StackProfile` (Gao weights), `TableProfile`
- contact laws: `contact_law(name)` with `LAW_NAMES`; `Hertz`, `KomvopoulosYe`,
  `KogutEtsion`, `JacksonGreen`, `Thornton`
- closed forms: `elastic_impact`, `elastic_impact_time`, `first_yield`, `yield_velocity`,
  `thornton_restitution`
- impact: `ImpactModel` (``maxima`` fast path, ``history`` time integration), `solve_impact`,
  `impact_map`
"""

from .contact_laws import (LAW_NAMES, ContactLaw, Hertz, JacksonGreen, KogutEtsion,
                           KomvopoulosYe, Thornton, contact_law)
from .errors import InputError, ModelRangeError
from .hertz import elastic_impact, elastic_impact_time, first_yield, yield_velocity
from .impact import ImpactHistory, ImpactMaxima, ImpactModel, ImpactResult, solve_impact
from .impact_map import MAP_FIELDS, ImpactMap, axis, impact_map
from .materials import DIAMOND, ElasticPlastic, Layer, LayerStack, reduced_modulus
from .profiles import DepthProfile, StackProfile, TableProfile, UniformProfile
from .restitution import UNLOADING_MODELS, johnson_restitution, thornton_restitution

__all__ = [
    "LAW_NAMES", "ContactLaw", "Hertz", "JacksonGreen", "KogutEtsion", "KomvopoulosYe",
    "Thornton", "contact_law", "InputError", "ModelRangeError", "elastic_impact",
    "elastic_impact_time", "first_yield", "yield_velocity", "ImpactHistory", "ImpactMaxima",
    "ImpactModel", "ImpactResult", "solve_impact", "MAP_FIELDS", "ImpactMap", "axis", "impact_map",
    "DIAMOND", "ElasticPlastic", "Layer", "LayerStack", "reduced_modulus", "DepthProfile",
    "StackProfile", "TableProfile", "UniformProfile", "UNLOADING_MODELS",
    "johnson_restitution", "thornton_restitution",
]
