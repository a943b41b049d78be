"""Sphere curves of a film on a substrate from the layered contact law (Gao weighting, the
impact model's own), with a known film: three tips whose contact radius spans 0.1 to 2 film
thicknesses."""

import numpy as np

from filmscale.continuum.calibration.target import SphereTarget
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.tips import Sphere
from filmscale.continuum.materials import ElasticPlastic

LAW = contact_law("komvopoulos-ye-continuous")
T, NU = 50e-9, 0.3                     # film thickness (m) and Poisson ratio
E_FILM, SY_FILM = 100e9, 2e9
E_STAR = E_FILM / (1 - NU**2)
#: three tips, each loaded to 4 x its first-yield approach over 300 points: the contact
#: radius spans 0.1 to 2 film thicknesses, so the curves see the film and the substrate
RADII = (0.1e-6, 0.5e-6, 2.5e-6)


def film_curves(ratio: float, rng, noise: float = 0.01, substrate=None):
    """Curves of the layered law with load noise ``noise`` of each P_max; the substrate is
    E_film/ratio and yields at 1.5 sigma_y,film unless given."""
    substrate = substrate or ElasticPlastic(E_FILM / ratio, 0.25, 1.5 * SY_FILM, name="sub")
    target = SphereTarget(NU, None, T, substrate)
    curves = []
    for R in RADII:
        delta_y = float(LAW.first_yield(R, E_STAR, SY_FILM, NU).approach)
        h = np.linspace(4 * delta_y / 300, 4 * delta_y, 300)
        P = target.forces(LAW, h, R, E_STAR, SY_FILM)[0]
        P = P + rng.normal(0.0, noise * P.max(), h.size)
        curves.append(LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                            indenter=Sphere(R)))
    return curves, substrate
