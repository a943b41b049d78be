"""MD-like sphere curves with a known E: the exact elastic sphere of Sneddon (1965) up to a
pop-in, the contact law after it, optionally with a misplaced depth zero or a softening before
the burst (the shape MD Cu(001) curves have, docs/md-indentation.md)."""

import numpy as np

from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve

E, NU, SY, R = 120e9, 0.34, 8e9, 1.5e-9
E_STAR = E / (1 - NU**2)
LAW = contact_law("komvopoulos-ye-continuous")


def sneddon_load(delta, E_star):
    """P(delta) of a rigid sphere on a half-space: delta = (a/2) ln((R+a)/(R-a)),
    P = (E*/2)[(a^2 + R^2) ln((R+a)/(R-a)) - 2 a R], a found by bisection."""
    lo, hi = np.zeros_like(delta), np.full_like(delta, R * (1 - 1e-15))
    for _ in range(200):
        a = 0.5 * (lo + hi)
        low = a / 2 * np.log((R + a) / (R - a)) < delta
        lo, hi = np.where(low, a, lo), np.where(low, hi, a)
    a = 0.5 * (lo + hi)
    return E_star / 2 * ((a * a + R * R) * np.log((R + a) / (R - a)) - 2 * a * R)


def md_like_curve(rng, *, offset=0.0, softening=0.0, noise=0.005, points=200):
    """Hertz (E) up to a pop-in at 6 first-yield approaches, the law after it; ``offset``
    (m) is added to every recorded depth (a misplaced surface); ``softening`` lowers the
    Hertz load by up to that fraction, growing as (P / P_pop - 0.6) / 0.4 above 0.6 of the
    pop-in load (the pre-burst softening of MD curves)."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    delta = np.linspace(12 * dy / points, 12 * dy, points)
    # the rigid sphere's exact elastic load (Sneddon 1965), written here from its
    # parametric form: the pop-in at 6 dy lies at 0.13 R, where Hertz's paraboloid is 1.3 %
    # stiffer
    hertz = sneddon_load(delta, E_STAR)
    h_pop = 6 * dy
    P_pop = float(sneddon_load(np.array([h_pop]), E_STAR)[0])
    soft = 1 - softening * np.clip((hertz / P_pop - 0.6) / 0.4, 0.0, 1.0)
    P = np.where(delta <= h_pop, hertz * soft, LAW.contact(delta, R, E_STAR, SY, NU).force)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(delta + offset, P, segment=np.zeros(points, int),
                                 indenter=f"sphere:{R * 1e9:g}nm")
