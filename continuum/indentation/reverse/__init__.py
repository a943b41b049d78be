"""filmscale.continuum.indentation.reverse: sharp-indentation forward and reverse analysis
(Dao et al. 2001, Acta Mater. 49, 3899; Chollacoop, Dao & Suresh 2003, Acta Mater. 51, 3713).

The dimensionless functions and their constants (`functions`), the forward and reverse
analysis with Monte Carlo uncertainty (`dao`, `uncertainty`), the dual indenter (`dual`), a
surrogate fitted to the packaged finite-element cases (`surrogate`, `data`) and the measured
accuracy of each route (`validation`). Equations: docs/physics.md section 10.
"""

from filmscale.core.lazy import lazy_exports

#: public name -> the submodule that defines it (imported on first use, so that the
#: command line starts without loading scipy's heavier parts)
_WHERE = {
    "ForwardResult": "dao", "ReverseResult": "dao", "dao_forward": "dao", "dao_reverse": "dao",
    "dao_reverse_repeated": "dao",
    "DualResult": "dual", "dual_reverse": "dual",
    "E_I_DAO": "functions", "NU_I_DAO": "functions", "loading_curvature": "functions",
    "sharp_calibration": "functions", "sharp_tip": "functions",
    "CrossValidation": "validation", "cross_validate": "validation", "fe_error_table": "validation",
}

#: every name of the lazy table is public
__all__ = list(_WHERE)

__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
