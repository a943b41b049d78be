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
- indentation curves: `LoadDisplacementCurve`, `check_curve`, `synthetic_curve`, `read_curves`
- tips: `parse_tip`, `Cone`, `Sphere`, `SphericalCone`, `FlatPunch`, `PolynomialArea`,
  `calibrate_area_function`, `fit_tip_radius`
- indentation analysis: `oliver_pharr`, `calibrate_frame_compliance`, `shallow_depth_hardness`,
  `hertz_fit`, `detect_pop_in`, `nix_gao_fit`, `property_profile`
- reverse analysis: `dao_forward`, `dao_reverse`, `dao_reverse_repeated`, `dual_reverse`,
  `cross_validate`
"""

from .contact_laws import (LAW_NAMES, ContactLaw, Hertz, JacksonGreen, KogutEtsion,
                           KomvopoulosYe, Thornton, contact_law)
from .curves import LoadDisplacementCurve, check_curve, drift_rate, synthetic_curve
from .errors import InputError, ModelRangeError
from .hertz import elastic_impact, elastic_impact_time, first_yield, yield_velocity
from .impact import ImpactHistory, ImpactMaxima, ImpactModel, ImpactResult, solve_impact
from .impact_map import MAP_FIELDS, ImpactMap, axis, impact_map
from .indentation import (LoadDrop, OliverPharrResult, calibrate_frame_compliance,
                          detect_load_drop, detect_pop_in, elastic_limit, hertz_fit,
                          nix_gao_fit, oliver_pharr, pop_in_shear_stress,
                          shallow_depth_hardness)
from .io import read_curves
from .materials import DIAMOND, ElasticPlastic, Layer, LayerStack, reduced_modulus
from .profiles import DepthProfile, StackProfile, TableProfile, UniformProfile
from .property_profile import PropertyDepthProfile, property_profile
from .restitution import UNLOADING_MODELS, johnson_restitution, thornton_restitution
from .reverse import (CrossValidation, DualResult, ForwardResult, ReverseResult, SharpTip,
                      cross_validate, dao_forward, dao_reverse, dao_reverse_repeated,
                      dual_reverse, fe_error_table, sharp_tip)
from .tips import (Cone, FlatPunch, PolynomialArea, Sphere, SphericalCone, Tip,
                   calibrate_area_function, fit_tip_radius, parse_tip)

__all__ = [
    "LAW_NAMES", "ContactLaw", "Hertz", "JacksonGreen", "KogutEtsion", "KomvopoulosYe",
    "Thornton", "contact_law", "InputError", "ModelRangeError", "elastic_impact",
    "elastic_impact_time", "first_yield", "yield_velocity", "ImpactHistory", "ImpactMaxima",
    "ImpactModel", "ImpactResult", "solve_impact", "MAP_FIELDS", "ImpactMap", "axis", "impact_map",
    "DIAMOND", "ElasticPlastic", "Layer", "LayerStack", "reduced_modulus", "DepthProfile",
    "StackProfile", "TableProfile", "UniformProfile", "UNLOADING_MODELS",
    "johnson_restitution", "thornton_restitution",
    "LoadDisplacementCurve", "check_curve", "drift_rate", "synthetic_curve", "read_curves",
    "OliverPharrResult", "oliver_pharr", "calibrate_frame_compliance", "shallow_depth_hardness",
    "hertz_fit", "detect_pop_in", "elastic_limit", "LoadDrop", "detect_load_drop",
    "pop_in_shear_stress",
    "nix_gao_fit",
    "PropertyDepthProfile", "property_profile",
    "Tip", "Cone", "Sphere", "SphericalCone", "FlatPunch", "PolynomialArea", "parse_tip",
    "calibrate_area_function", "fit_tip_radius",
    "ForwardResult", "ReverseResult", "DualResult", "SharpTip", "sharp_tip", "CrossValidation",
    "dao_forward", "dao_reverse", "dao_reverse_repeated", "dual_reverse", "cross_validate",
    "fe_error_table",
]
