"""Curves of one Cu-like layer at two scales, both from one Nix-Gao law of sigma_y: an MD
sphere (the contact law with sigma_y(delta) at each approach, as the impact model evaluates a
profile) and Berkovich indents (Dao's forward functions with sigma_y(h_m))."""

import math

import numpy as np

from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.materials import ElasticPlastic
from tests.helpers.curves import synthetic_sharp_curve

LAW = contact_law("komvopoulos-ye-continuous")
E, NU = 130e9, 0.34              # a Cu-like film
E_STAR = E / (1 - NU**2)
SY0, H_STAR = 0.3e9, 2e-6        # sigma_y = 0.3 GPa sqrt(1 + 2 um / d): 13 GPa at 1 nm
R_MD, H_MD = 5e-9, 2e-9          # an MD sphere of 5 nm pushed 2 nm in
DEPTHS = (1e-6, 2e-6, 5e-6)      # Berkovich indents


def strength(d, sy0=SY0, h_star=H_STAR):
    """sigma_y at depth ``d`` by Nix-Gao: sy0 sqrt(1 + h_star / d)."""
    return sy0 * np.sqrt(1 + h_star / np.asarray(d))


def md_curve(rng, E_md=E, h_star=H_STAR, pop_at=None, noise=0.005, points=100,
             indenter=None):
    """Sphere loading through the law with sigma_y(delta) at each approach; with ``pop_at``
    the pristine crystal follows Hertz up to that depth and drops onto the law there. The
    tip is rigid (MD) unless an ``indenter`` is given."""
    h = np.linspace(H_MD / points, H_MD, points)
    E_s = ElasticPlastic(E_md, NU).reduced_modulus(indenter)
    P = LAW.contact(h, R_MD, E_s, strength(h, h_star=h_star), NU).force
    if pop_at is not None:
        P = np.where(h <= pop_at, 4 / 3 * E_s * math.sqrt(R_MD) * h**1.5, P)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int), indenter="sphere:5nm",
                                 meta={"source": "md"})


def sharp_curves(h_star=H_STAR):
    """Berkovich curves at DEPTHS, each with sigma_y at its own depth (n = 0.1)."""
    return [synthetic_sharp_curve(E, NU, float(strength(d, h_star=h_star)), 0.1, d)[1]
            for d in DEPTHS]
