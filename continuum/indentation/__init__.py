"""filmscale.continuum.indentation: load-displacement curves and what they measure.

Curves and their checks (`curves`), readers and writers (`io`) and instrument exports
(`vendors`; NanoSuite workbooks `workbooks`, Hysitron files `hld`), the contact point
(`surface`), continuous-stiffness tests (`csm`), multi-cycle tests (`cycles`), one `Tip` type for every scale (`tips`) and its
calibration with the frame compliance on a reference (`tip_calibration`), Oliver-Pharr
with frame compliance and the shallow-depth correction (`oliver_pharr`), spherical tips
and pop-in (`spherical`), the Nix-Gao size effect (`size_effect`), property profiles over
depth (`property_profile`), and the sharp-tip reverse analysis of Dao et al. in the
sub-package `reverse`. Equations: docs/physics.md
sections 9-10. SI units.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the submodule that defines it (imported on first use, so that the
#: command line starts without loading scipy's heavier parts)
_WHERE = {
    "LoadDisplacementCurve": "curves", "check_curve": "curves", "synthetic_curve": "synthetic",
    "read_curves": "io", "ReadOptions": "vendors", "analyse_cycles": "cycles",
    "calibrate_tip": "tip_calibration", "TipCalibration": "tip_calibration",
    "OliverPharrResult": "oliver_pharr", "calibrate_frame_compliance": "oliver_pharr",
    "oliver_pharr": "oliver_pharr", "shallow_depth_hardness": "oliver_pharr",
    "property_profile": "property_profile",
    "nix_gao_fit": "size_effect",
    "detect_pop_in": "spherical", "elastic_limit": "spherical", "hertz_fit": "spherical",
    "Cone": "tips", "FlatPunch": "tips", "PolynomialArea": "tips", "Sphere": "tips",
    "SphericalCone": "tips", "Tip": "tips", "calibrate_area_function": "tips",
    "fit_tip_radius": "tips", "parse_tip": "tips",
    "csm_analysis": "csm", "CSMResult": "csm", "find_surface": "surface",
    "film_modulus": "film_substrate", "FilmModulus": "film_substrate",
    "depth_trend": "size_effect",
}

#: every name of the lazy table is public
__all__ = list(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
