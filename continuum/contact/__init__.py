"""filmscale.continuum.contact: a material (or layer stack) -> the impact of a rigid body.

Hertz contact and elastic impact (`hertz`), elastic-plastic sphere contact laws (`laws`),
the exact elastic rigid sphere and a law wrapper with it as elastic branch (`sneddon`), the
exact elastic film-on-substrate solution (`coated`),
depth profiles of layered targets (`profiles`), unloading and restitution (`restitution`),
the impact model with its maxima fast path and time integration (`impact`) and impact maps
(`impact_map`), oblique impact (`oblique`) and the line-contact impact of a finite cylinder
(`cylinder`). Equations: docs/physics.md sections 1-7. SI units.

This sub-package imports nothing of `indentation` or `calibration`.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the submodule that defines it (imported on first use, so that the
#: command line starts without loading scipy's heavier parts)
_WHERE = {
    "CylinderImpactModel": "cylinder", "CylinderImpactResult": "results",
    "elastic_impact": "hertz", "elastic_impact_time": "hertz", "first_yield": "hertz",
    "yield_velocity": "hertz",
    "ImpactModel": "impact", "solve_impact": "impact",
    "MAP_FIELDS": "impact_map", "ImpactMap": "impact_map", "impact_map": "impact_map",
    "LAW_NAMES": "laws", "ContactLaw": "laws", "Hertz": "laws", "JacksonGreen": "laws",
    "KogutEtsion": "laws", "KomvopoulosYe": "laws", "Thornton": "laws", "contact_law": "laws",
    "ObliqueResult": "oblique", "solve_oblique": "oblique", "oblique_map": "oblique",
    "CylinderImpactHistory": "results", "GridMap": "impact_map",
    "cylinder_map": "impact_map",
    "SneddonElastic": "sneddon", "sneddon_force": "sneddon",
    "coated_solution": "coated", "coated_sphere_load": "coated",
    "flat_punch_stiffness": "coated", "apparent_modulus": "coated",
    "stack_sphere_curve": "coated", "stack_solution": "coated",
    "DepthProfile": "profiles", "StackProfile": "profiles", "TableProfile": "profiles",
    "UniformProfile": "profiles",
    "UNLOADING_MODELS": "restitution", "thornton_restitution": "restitution",
    "ModelKind": "kinds", "KINDS": "kinds", "register": "kinds", "kind_named": "kinds",
    "kind_for": "kinds",
    "ImpactHistory": "results", "ImpactMaxima": "results", "ImpactResult": "results",
}

#: every name of the lazy table is public
__all__ = list(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
