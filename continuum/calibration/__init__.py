"""filmscale.continuum.calibration: load-displacement curves -> the material of a layer.

`calibrate` chooses the route by the tip (`route`): spherical curves through the contact
laws (`sphere`), on a half-space or as a film on a substrate (`target`); sharp curves
through Dao's reverse analysis with the Nix-Gao size effect (`sharp`); several sources of one
layer at once (`joint`); an MD ensemble member by member (`ensemble`). Every route returns a `Calibration` (`result`): E, sigma_y and n with their
standard deviations, the layer's material and the cross-scale check of the calibrated
forward model against its curves. SI units.
"""

from filmscale.continuum.calibration.ensemble import calibrate_ensemble
from filmscale.continuum.calibration.joint import CalibrationPart, combine, sharp_part, sphere_part
from filmscale.continuum.calibration.result import Calibration, CrossCheck, Parameter
from filmscale.continuum.calibration.route import calibrate
from filmscale.continuum.calibration.sharp import calibrate_sharp, size_effect, with_size_effect
from filmscale.continuum.calibration.sphere import calibrate_sphere
from filmscale.continuum.calibration.target import SphereTarget

__all__ = [
    "calibrate", "calibrate_ensemble", "SphereTarget", "calibrate_sphere", "calibrate_sharp", "with_size_effect", "size_effect",
    "combine", "sphere_part", "sharp_part", "CalibrationPart",
    "Calibration", "Parameter", "CrossCheck",
]
