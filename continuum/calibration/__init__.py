"""filmscale.continuum.calibration: load-displacement curves -> the material of a layer.

`calibrate` chooses the route by the tip (`route`): spherical curves through the contact
laws (`sphere`), on a half-space or as a film on a substrate (`target`); sharp curves
through Dao's reverse analysis with the Nix-Gao size effect (`sharp`); several sources of one
layer at once (`joint`); an MD ensemble member by member (`ensemble`). Every route returns a `Calibration` (`result`): E, sigma_y and n with their
standard deviations, the layer's material and the cross-scale check of the calibrated
forward model against its curves. SI units.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the submodule that defines it (imported on first use, so that the
#: command line starts without loading scipy's heavier parts)
_WHERE = {
    "calibrate_ensemble": "ensemble",
    "CalibrationPart": "joint", "combine": "joint", "sharp_part": "joint", "sphere_part": "joint",
    "Calibration": "result", "CrossCheck": "result", "Parameter": "result",
    "calibrate": "route",
    "calibrate_sharp": "sharp", "size_effect": "sharp", "with_size_effect": "sharp",
    "calibrate_sphere": "sphere",
    "SphereTarget": "target",
    "PopInStatistics": "pop_in",
}

#: every name of the lazy table is public
__all__ = list(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
