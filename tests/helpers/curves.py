"""Synthetic load-displacement curves from independent forward models, and the files the
tests write them to: the sphere contact law with Gaussian load noise (and a pop-in), Dao's
forward functions for Berkovich curves, and a curve table for scene calibrations."""

import numpy as np

from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.continuum.indentation.io import write_curve_group
from filmscale.continuum.indentation.reverse.dao import dao_forward
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.files import atomic_h5

#: the sphere curves' material (an aluminium alloy) and tip radius
E, NU, SY = 70e9, 0.3, 0.3e9
E_STAR = E / (1 - NU**2)
R = 5e-6
LAW = contact_law("komvopoulos-ye-continuous")


def sphere_curve(h_max, noise, rng, R=R, points=80):
    """The law's loading of (E, SY, NU) under a sphere of radius ``R`` to ``h_max`` over
    ``points`` depths, with Gaussian load noise of ``noise`` x P_max drawn from ``rng``."""
    h = np.linspace(h_max / points, h_max, points)
    P = LAW.contact(h, R, E_STAR, SY, NU).force
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                 indenter=f"sphere:{R * 1e6:g}um")


def pop_in_curve(rng, E_pristine, noise=0.005, points=200):
    """An MD-like displacement-controlled loading: Hertz with ``E_pristine`` (the defect-free
    crystal) up to a pop-in at 6 first-yield approaches, where the load drops onto the
    elastic-plastic law (E, SY) and follows it to 15 approaches."""
    dy = float(LAW.first_yield(R, E_STAR, SY, NU).approach)
    h = np.linspace(15 * dy / points, 15 * dy, points)
    hertz = 4 / 3 * E_pristine / (1 - NU**2) * np.sqrt(R) * h**1.5
    P = np.where(h <= 6 * dy, hertz, LAW.contact(h, R, E_STAR, SY, NU).force)
    P = P + rng.normal(0.0, noise * P.max(), P.size)
    return LoadDisplacementCurve(h, P, segment=np.zeros(h.size, int),
                                 indenter=f"sphere:{R * 1e6:g}um")


def synthetic_sharp_curve(E, nu, sy, n, h_m, tip="berkovich", points=200):
    """Loading P = C h^2 and a power-law unloading P = B (h - h_f)^m with the forward
    slope and work ratio: S = m P_m/(h_m - h_f) and W_e = P_m (h_m - h_f)/(m + 1) give
    m/(m + 1) = S W_e / P_m^2."""
    f = dao_forward(E, nu, sy, n, h_m, tip=tip)
    W_t = f.C * h_m**3 / 3
    W_e = (1 - f.WpWt) * W_t
    k = f.dPdh * W_e / f.P_m**2
    m = k / (1 - k)
    span = (m + 1) * W_e / f.P_m
    h_load = np.linspace(h_m / points, h_m, points)
    h_unl = np.linspace(h_m, h_m - span, points)[1:]
    P_unl = f.P_m * ((h_unl - (h_m - span)) / span)**m
    h = np.concatenate([h_load, h_unl])
    P = np.concatenate([f.C * h_load**2, P_unl])
    seg = np.concatenate([np.zeros(points, int), np.full(points - 1, 2)])
    return f, LoadDisplacementCurve(h, P, segment=seg, indenter=tip)


def sized_curves(sy0=0.5e9, h_star=0.3e-6, depths=(0.1e-6, 0.2e-6, 0.5e-6, 1e-6, 3e-6)):
    """Dao forward Berkovich curves of Al 7075 whose sigma_y follows Nix-Gao with depth."""
    return [synthetic_sharp_curve(70.1e9, 0.33, sy0 * np.sqrt(1 + h_star / h), 0.122, h)[1]
            for h in depths]


def sphere_curve_file(folder) -> tuple[float, float]:
    """film.csv: the contact law's loading of E = 120 GPa, sigma_y = 3 GPa (nu 0.3) under a
    5 um diamond sphere to 20 first-yield approaches, with 1 % load noise; (E, sigma_y)."""
    from filmscale.continuum.materials import DIAMOND
    E, nu, sy, R = 120e9, 0.3, 3e9, 5e-6
    law = contact_law("komvopoulos-ye-continuous")
    E_r = ElasticPlastic(E, nu, sy).reduced_modulus(DIAMOND)
    dy = float(law.first_yield(R, E_r, sy, nu).approach)
    h = np.linspace(0.2 * dy, 20 * dy, 120)
    P = law.contact(h, R, E_r, sy, nu).force
    P = P + np.random.default_rng(2).normal(0.0, 0.01 * P.max(), h.size)
    (folder / "film.csv").write_text(
        "h [nm], P [uN]\n" + "".join(f"{a * 1e9:.6f}, {b * 1e6:.8f}\n" for a, b in zip(h, P)))
    return E, sy


def write_curves(path, curves) -> str:
    """The curves as one HDF5 file (groups c0, c1, ...) at ``path``; its name."""
    with atomic_h5(path) as f:
        for i, c in enumerate(curves):
            write_curve_group(f.create_group(f"c{i}"), c)
    return str(path)
