"""filmscale.continuum.indentation.reverse: sharp-indentation forward and reverse analysis
(Dao et al. 2001, Acta Mater. 49, 3899; Chollacoop, Dao & Suresh 2003, Acta Mater. 51, 3713).

The dimensionless functions and their constants (`functions`), the forward and reverse
analysis with Monte Carlo uncertainty (`dao`, `uncertainty`), the dual indenter (`dual`), a
surrogate fitted to the packaged finite-element cases (`surrogate`, `data`) and the measured
accuracy of each route (`validation`). Equations: docs/physics.md section 10.
"""

from filmscale.continuum.indentation.reverse.dao import (ForwardResult, ReverseResult, dao_forward,
                                                         dao_reverse, dao_reverse_repeated)
from filmscale.continuum.indentation.reverse.dual import DualResult, dual_reverse
from filmscale.continuum.indentation.reverse.functions import (E_I_DAO, NU_I_DAO, loading_curvature,
                                                               sharp_calibration, sharp_tip)
from filmscale.continuum.indentation.reverse.validation import (CrossValidation, cross_validate,
                                                                fe_error_table)

__all__ = [
    "dao_forward", "dao_reverse", "dao_reverse_repeated", "dual_reverse",
    "ForwardResult", "ReverseResult", "DualResult", "sharp_tip", "sharp_calibration",
    "loading_curvature",
    "E_I_DAO", "NU_I_DAO", "cross_validate", "CrossValidation", "fe_error_table",
]
