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

from filmscale.core.lazy import lazy_exports

#: public name -> the submodule that defines it (imported on first use, so that the
#: command line starts without loading scipy's heavier parts)
_WHERE = {
    "Calibration": "calibration", "calibrate_sharp": "calibration",
    "calibrate_sphere": "calibration",
    "ImpactModel": "contact", "StackProfile": "contact", "contact_law": "contact",
    "elastic_impact": "contact", "impact_map": "contact", "solve_impact": "contact",
    "LoadDisplacementCurve": "indentation", "Tip": "indentation", "hertz_fit": "indentation",
    "oliver_pharr": "indentation", "parse_tip": "indentation", "read_curves": "indentation",
    "dao_forward": "indentation.reverse", "dao_reverse": "indentation.reverse",
    "DIAMOND": "materials", "ElasticPlastic": "materials", "Layer": "materials",
    "LayerStack": "materials", "reduced_modulus": "materials",
}

#: every name of the lazy table is public
__all__ = list(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
