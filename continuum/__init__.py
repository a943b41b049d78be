"""filmscale.continuum: contact, indentation and impact physics in numpy/scipy (no LAMMPS).

The sub-packages follow the data flow of a study, SI units throughout:

- `filmscale.continuum.indentation`: load-displacement curves and their analysis
  (Oliver-Pharr, spherical tips and pop-in, size effect, property profiles), with the
  sharp-tip reverse analysis in `indentation.reverse`;
- `filmscale.continuum.calibration`: curves -> material (E, sigma_y, n) from sphere, sharp
  and joint sources, with uncertainties and the cross-scale check;
- `filmscale.continuum.contact`: material -> impact (contact laws, Hertz, depth profiles of
  layered targets, restitution, the impact model and maps).

The names below are the ones most studies need; each sub-package lists its own.
See docs/api.md.
"""

from filmscale.continuum.calibration import Calibration, calibrate_sharp, calibrate_sphere
from filmscale.continuum.contact import (ImpactModel, StackProfile, contact_law, elastic_impact,
                                         impact_map, solve_impact)
from filmscale.continuum.indentation import (LoadDisplacementCurve, Tip, hertz_fit, oliver_pharr,
                                             parse_tip, read_curves)
from filmscale.continuum.indentation.reverse import dao_forward, dao_reverse
from filmscale.continuum.materials import (DIAMOND, ElasticPlastic, Layer, LayerStack,
                                           reduced_modulus)

__all__ = [
    "ElasticPlastic", "Layer", "LayerStack", "DIAMOND", "reduced_modulus",
    "LoadDisplacementCurve", "read_curves", "Tip", "parse_tip", "oliver_pharr", "hertz_fit",
    "dao_forward", "dao_reverse",
    "calibrate_sphere", "calibrate_sharp", "Calibration",
    "contact_law", "StackProfile", "ImpactModel", "solve_impact", "impact_map",
    "elastic_impact",
]
