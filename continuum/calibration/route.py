"""One entry point from curves to a calibrated layer: `calibrate` chooses the route by the
tip. `filmscale calibrate` and the scene pipeline both call it."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from filmscale.continuum.contact.laws import FIT_LAW, ContactLaw
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.reverse import E_I_DAO, NU_I_DAO
from filmscale.continuum.indentation.tips import Sphere, parse_tip
from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.core.checks import check_choice
from filmscale.core.errors import InputError

from .result import Calibration
from .sharp import calibrate_sharp, with_size_effect
from .sphere import calibrate_sphere
from .target import CONTACT_ZEROS, TIP_MATERIALS


def default_contact_zero(tip_material: str) -> str:
    """A rigid tip means a simulated surface (MD, particle model), whose zero is fitted; a
    diamond tip means a measured curve, whose zero is the instrument's surface detection."""
    return "fit" if check_choice("tip material", tip_material, TIP_MATERIALS) == "rigid" \
        else "fixed"


def tip_counterpart(tip_material: str) -> tuple[ElasticPlastic | None, float, float]:
    """(a sphere's indenter material, a sharp tip's E_i, nu_i) for ``tip_material``: rigid
    gives (None, inf, 0); diamond gives `DIAMOND` (1141 GPa) for spheres and Dao's 1100 GPa,
    0.07 for sharp tips (the values the reverse analysis was validated with)."""
    check_choice("tip material", tip_material, TIP_MATERIALS)
    return (None, math.inf, 0.0) if tip_material == "rigid" else (DIAMOND, E_I_DAO, NU_I_DAO)


def sharp_tip_of(curves) -> object | None:
    """The one sharp tip of the curves, None when all are spheres; InputError for a mix."""
    spheres = [isinstance(c.indenter, Sphere) for c in curves]
    if all(spheres):
        return None
    tips = {c.indenter for c in curves}
    if any(spheres) or len(tips) != 1 or None in tips:
        raise InputError(f"the curves mix indenters ({', '.join(sorted(map(str, tips)))}); "
                         "calibrate from one tip shape")
    return tips.pop()


def calibrate(curves, *, nu: float, tip=None, tip_material: str = "diamond",
              thickness: float | None = None, substrate: ElasticPlastic | None = None,
              law: str | ContactLaw = FIT_LAW,
              layer: str = "layer", contact_zero: str | None = None) -> Calibration:
    """E, sigma_y (and n for sharp tips) of a layer from its curves.

    Spherical tips go through the contact law (`calibrate_sphere`), on a half-space or, with
    ``thickness`` and ``substrate``, on the film-on-substrate stack; a sharp tip through Dao's
    reverse analysis (`calibrate_sharp`), with the Nix-Gao size effect of sigma_y when the
    curves reach three or more depths (`with_size_effect`).

    Parameters
    ----------
    curves : LoadDisplacementCurve or sequence
    nu : float
        The layer's Poisson ratio (assumed).
    tip : Tip or str, optional
        The tip of every curve (``sphere:5um``, ``berkovich``, ...); default each curve's own.
    tip_material : {"rigid", "diamond"}
        Rigid for MD and particle runs, diamond (the default) for measured curves.
    thickness, substrate : float (m), ElasticPlastic, optional
        The layer is a film of this thickness on this substrate (sphere tips only).
    law : str or ContactLaw
        The sphere contact law.
    layer : str
        The layer's name in the result.
    contact_zero : {"fit", "fixed"}, optional
        Sphere tips: fit the contact zero with E* (`calibrate_sphere`'s ``fit_zero``) or hold
        it at the curves' h = 0. Default `default_contact_zero`: fit for a rigid tip (an MD
        or particle surface: on MD Cu the fitted zero makes E independent of the tip's wall
        stiffness, docs/md-indentation.md), fixed for diamond. Sharp tips refuse "fit":
        Dao's analysis has no zero to fit.
    """
    curves = [curves] if isinstance(curves, LoadDisplacementCurve) else list(curves)
    if not curves:
        raise InputError("calibrate needs at least one curve")
    if tip is not None:
        tip = parse_tip(tip)
        curves = [replace(c, indenter=tip) for c in curves]
    missing = [str(c.meta.get("source", i)) for i, c in enumerate(curves) if c.indenter is None]
    if missing:
        raise InputError(f"curve(s) {', '.join(missing)} name no indenter: give the tip")
    indenter, E_i, nu_i = tip_counterpart(tip_material)
    zero = check_choice("contact zero", default_contact_zero(tip_material)
                        if contact_zero is None else contact_zero, CONTACT_ZEROS)
    sharp = sharp_tip_of(curves)
    if sharp is None:
        return calibrate_sphere(curves, nu=nu, law=law, layer=layer, indenter=indenter,
                                thickness=thickness, substrate=substrate,
                                fit_zero=zero == "fit")
    if contact_zero == "fit":
        raise InputError(f"tip {sharp}: contact zero = 'fit' is for sphere tips; Dao's "
                         "reverse analysis of sharp tips has no zero to fit")
    if thickness is not None or substrate is not None:
        raise InputError(f"tip {sharp}: a film on a substrate is calibrated with a sphere; "
                         "Dao's reverse analysis of sharp tips holds for a half-space (leave "
                         "out the film thickness and substrate)")
    cal = calibrate_sharp(curves, nu=nu, tip=sharp, layer=layer, E_i=E_i, nu_i=nu_i)
    depths = {round(float(np.max(c.h)), 12) for c in curves}
    return with_size_effect(cal, curves, sharp, E_i=E_i, nu_i=nu_i) if len(depths) >= 3 \
        else cal
