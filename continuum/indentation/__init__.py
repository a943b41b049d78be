"""filmscale.continuum.indentation: load-displacement curves and what they measure.

Curves and their checks (`curves`), readers and writers (`io`) and instrument exports
(`vendors`), multi-cycle tests (`cycles`), one `Tip` type for every scale (`tips`) and its
calibration with the frame compliance on a reference (`tip_calibration`), Oliver-Pharr
with frame compliance and the shallow-depth correction (`oliver_pharr`), spherical tips
and pop-in (`spherical`), the Nix-Gao size effect (`size_effect`), property profiles over
depth (`property_profile`), and the sharp-tip reverse analysis of Dao et al. in the
sub-package `reverse`. Equations: docs/physics.md
sections 9-10. SI units.
"""

from filmscale.continuum.indentation.curves import (LoadDisplacementCurve, check_curve,
                                                    synthetic_curve)
from filmscale.continuum.indentation.cycles import analyse_cycles
from filmscale.continuum.indentation.io import read_curves
from filmscale.continuum.indentation.oliver_pharr import (OliverPharrResult,
                                                          calibrate_frame_compliance, oliver_pharr,
                                                          shallow_depth_hardness)
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.indentation.size_effect import nix_gao_fit
from filmscale.continuum.indentation.spherical import detect_pop_in, elastic_limit, hertz_fit
from filmscale.continuum.indentation.tip_calibration import TipCalibration, calibrate_tip
from filmscale.continuum.indentation.tips import (Cone, FlatPunch, PolynomialArea, Sphere,
                                                  SphericalCone, Tip, calibrate_area_function,
                                                  fit_tip_radius, parse_tip)
from filmscale.continuum.indentation.vendors import ReadOptions

__all__ = [
    "LoadDisplacementCurve", "check_curve", "synthetic_curve", "read_curves", "ReadOptions",
    "analyse_cycles", "calibrate_tip", "TipCalibration",
    "Tip", "Sphere", "Cone", "SphericalCone", "FlatPunch", "PolynomialArea", "parse_tip",
    "calibrate_area_function", "fit_tip_radius",
    "oliver_pharr", "OliverPharrResult", "calibrate_frame_compliance", "shallow_depth_hardness",
    "hertz_fit", "detect_pop_in", "elastic_limit", "nix_gao_fit", "property_profile",
]
