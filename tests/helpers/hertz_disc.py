"""Quadrature nodes over the Hertz pressure on the unit contact disc, shared by the second
methods of tests/continuum/test_sliding_homogeneous.py and benchmarks/sliding_fields.py."""

from __future__ import annotations

import math

import numpy as np


def hertz_disc_nodes(nb=160, nphi=320):
    """(xs, ys, dP) over the unit disc with r = sin(beta): Gauss-Legendre in beta on
    [0, pi/2] (nb nodes), trapezoid in the angle (nphi nodes); dP = sqrt(1 - r^2) dA, the
    Hertz pressure (p0 = 1) times the area element, so sum(dP) -> 2 pi / 3."""
    gb, wb = np.polynomial.legendre.leggauss(nb)
    beta, wbeta = (gb + 1) * math.pi / 4, wb * math.pi / 4
    phi = np.arange(nphi) * 2 * math.pi / nphi
    B, F = np.meshgrid(beta, phi, indexing="ij")
    r = np.sin(B)
    dP = np.cos(B) ** 2 * np.sin(B) * wbeta[:, None] * (2 * math.pi / nphi)
    return r * np.cos(F), r * np.sin(F), dP
