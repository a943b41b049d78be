"""filmscale.continuum.calibration: load-displacement curves -> the material of a layer.

Spherical curves through the contact laws (`sphere`), sharp curves through Dao's reverse
analysis with the Nix-Gao size effect (`sharp`), several sources of one layer at once
(`joint`); every route returns a `Calibration` (`result`): E, sigma_y and n with their
standard deviations, the layer's material and the cross-scale check of the calibrated
forward model against its curves. SI units.
"""

from filmscale.continuum.calibration.joint import CalibrationPart, combine, sharp_part, sphere_part
from filmscale.continuum.calibration.result import Calibration, CrossCheck, Parameter
from filmscale.continuum.calibration.sharp import calibrate_sharp, size_effect, with_size_effect
from filmscale.continuum.calibration.sphere import calibrate_sphere

__all__ = [
    "calibrate_sphere", "calibrate_sharp", "with_size_effect", "size_effect",
    "combine", "sphere_part", "sharp_part", "CalibrationPart",
    "Calibration", "Parameter", "CrossCheck",
]
