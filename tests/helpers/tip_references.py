"""Reference indents for tip calibration (Oliver & Pharr 1992, 2004): noise-free or noisy
multi-cycle indents on fused silica with a blunted Berkovich tip and a known frame
compliance, and the same indents with their depth zero misplaced."""

import numpy as np

from filmscale.continuum.indentation.cycles import synthetic_multicycle
from filmscale.continuum.indentation.tips import FUSED_SILICA, PolynomialArea, berkovich
from filmscale.continuum.materials import DIAMOND

NM = 1e-9
#: a blunted Berkovich: A = 24.494 h^2 + 800 nm h + 4000 nm^1.5 h^0.5 (h in nm), 47 % above
#: the ideal area at 20 nm and 9 % at 360 nm
TRUE_AREA = PolynomialArea((berkovich().area_coefficient, 800 * NM, 4000 * NM**1.5),
                           berkovich())
C_F = 0.3e-6            #: frame compliance, m/N (0.3 nm/mN, a typical G200 frame)
E_R_SILICA = FUSED_SILICA.reduced_modulus(DIAMOND)


def reference_curves(noise=0.0):
    """Three multi-cycle indents on fused silica (H = 9 GPa), h_c 20 to 360 nm."""
    return [synthetic_multicycle(E_R_SILICA, 9e9, TRUE_AREA, frame_compliance=C_F, noise=noise,
                                 seed=k, h_c=np.geomspace(start, 8 * start, 4))
            for k, start in enumerate((20 * NM, 30 * NM, 45 * NM))]


def shifted(curves, offset):
    """The curves with every depth larger by ``offset``: an instrument's surface-find that
    fired ``offset`` early, the zero not re-found."""
    return [type(c)(c.h + offset, c.P, c.t, c.segment, indenter=c.indenter, meta=c.meta)
            for c in curves]
