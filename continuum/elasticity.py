"""Anisotropic elastic constants: single-crystal stiffness to isotropic polycrystal moduli.

Stiffness matrices are 6x6 in Voigt notation, index order 11, 22, 33, 23, 13, 12, with
engineering shear strains (gamma_23 = 2 eps_23, ...), so that sigma = C eps and the compliance
is S = C^-1 (Nye, Physical Properties of Crystals, 1957, ch. VIII). Units: Pa for C, 1/Pa for S.

- Voigt (uniform strain) and Reuss (uniform stress) bounds of the bulk and shear moduli and
  their arithmetic mean, the Hill average (Hill, Proc. Phys. Soc. A 65 (1952) 349).
- Universal anisotropy index A^U = 5 G_V/G_R + K_V/K_R - 6 >= 0, zero only for local
  isotropy (Ranganathan & Ostoja-Starzewski, Phys. Rev. Lett. 101 (2008) 055504).
- Zener ratio A = 2 C44 / (C11 - C12) of a cubic crystal (Zener, Elasticity and Anelasticity
  of Metals, 1948).
- Indentation modulus of an anisotropic half-space for an axisymmetric indenter normal to a
  given crystal plane (Vlassak & Nix, J. Mech. Phys. Solids 42 (1994) 1223), from the
  Barnett-Lothe surface tensor (Barnett & Lothe, Phys. Norv. 7 (1973) 13): what a single
  crystal's Hertzian segment measures, which is not its polycrystal (Hill) modulus.
- Least-squares stiffness from strain-stress pairs, as produced by applying +-eps strains to
  a simulation cell and reading the stress (the finite-deformation route of LAMMPS's
  ``examples/ELASTIC``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from filmscale.core.checks import check_float_array, check_real
from filmscale.core.errors import InputError

from .materials import ElasticPlastic
from .materials import reduced_modulus as _reduced_modulus

#: smallest eigenvalue of an accepted stiffness, relative to the largest: below it C is
#: singular to working precision and S = C^-1 (hence the Reuss bound) is meaningless
SPD_RTOL = 1e-12
#: asymmetry |C - C^T| / max|C| accepted (and removed) by `voigt_reuss_hill`
SYMMETRY_RTOL = 1e-8


def _as_stiffness(C, name: str = "C") -> np.ndarray:
    """C as a finite, symmetric 6x6 float array; InputError otherwise."""
    arr = check_float_array(name, C, "a 6x6 array of numbers")
    if arr.shape != (6, 6):
        raise InputError(f"{name} must be a 6x6 Voigt stiffness matrix, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains non-finite entries")
    scale = np.max(np.abs(arr))
    if scale == 0.0:
        raise InputError(f"{name} is all zeros: a stiffness must be positive definite")
    asym = np.max(np.abs(arr - arr.T)) / scale
    if asym > SYMMETRY_RTOL:
        raise InputError(f"{name} is not symmetric: max |C - C^T| / max |C| = {asym:.3g} "
                         f"exceeds {SYMMETRY_RTOL:.0e}")
    return 0.5 * (arr + arr.T)


def _check_spd(C: np.ndarray, name: str = "C") -> None:
    eig = np.linalg.eigvalsh(C)
    if not eig[0] > SPD_RTOL * eig[-1]:
        raise InputError(f"{name} is not positive definite: smallest eigenvalue {eig[0]:.6g} Pa "
                         f"(largest {eig[-1]:.6g} Pa); a stable crystal needs every eigenvalue "
                         f"> {SPD_RTOL:.0e} x the largest")


@dataclass(frozen=True)
class IsotropicAverage:
    """Voigt, Reuss and Hill moduli of a random polycrystal of one crystal; SI units."""

    K_V: float       #: Voigt (upper) bound of the bulk modulus, Pa
    K_R: float       #: Reuss (lower) bound of the bulk modulus, Pa
    G_V: float       #: Voigt (upper) bound of the shear modulus, Pa
    G_R: float       #: Reuss (lower) bound of the shear modulus, Pa
    K: float         #: Hill bulk modulus (K_V + K_R)/2, Pa
    G: float         #: Hill shear modulus (G_V + G_R)/2, Pa
    E: float         #: Young's modulus 9KG/(3K+G) from the Hill moduli, Pa
    nu: float        #: Poisson ratio (3K-2G)/(2(3K+G)) from the Hill moduli
    A_U: float       #: universal anisotropy index 5 G_V/G_R + K_V/K_R - 6 (>= 0)

    def plane_strain_modulus(self) -> float:
        """E / (1 - nu^2), Pa: the reduced modulus against a rigid indenter."""
        return self.E / (1.0 - self.nu**2)

    def reduced_modulus(self, indenter: ElasticPlastic | None = None) -> float:
        """Reduced modulus E* against `indenter` (rigid when None), Pa.

        1/E* = (1 - nu^2)/E + (1 - nu_i^2)/E_i (Johnson, Contact Mechanics, 1985, eq. 4.22),
        with this polycrystal's Hill E and nu.
        """
        if indenter is not None and not isinstance(indenter, ElasticPlastic):
            raise InputError(f"indenter must be an ElasticPlastic or None (rigid), got "
                             f"{type(indenter).__name__}")
        return float(_reduced_modulus(self.plane_strain_modulus(), indenter))

    def to_dict(self) -> dict:
        """Every field as a float, SI units."""
        return {k: float(v) for k, v in asdict(self).items()}


def voigt_reuss_hill(C) -> IsotropicAverage:
    """Isotropic moduli of a random, untextured polycrystal from a single-crystal stiffness.

    Parameters
    ----------
    C : array_like, shape (6, 6)
        Stiffness in Voigt notation (order 11, 22, 33, 23, 13, 12; engineering shear
        strains), Pa. Must be symmetric (to `SYMMETRY_RTOL`) and positive definite.

    Returns
    -------
    IsotropicAverage

    Notes
    -----
    For any crystal symmetry (Hill 1952; Voigt 1928; Reuss 1929), with S = C^-1:

    - K_V = [(C11 + C22 + C33) + 2 (C12 + C23 + C31)] / 9
    - G_V = [(C11 + C22 + C33) - (C12 + C23 + C31) + 3 (C44 + C55 + C66)] / 15
    - 1/K_R = (S11 + S22 + S33) + 2 (S12 + S23 + S31)
    - 15/G_R = 4 (S11 + S22 + S33) - 4 (S12 + S23 + S31) + 3 (S44 + S55 + S66)

    K_V >= K_R and G_V >= G_R always; the Hill values are the means. E and nu follow from
    the Hill K and G by isotropic elasticity. A^U = 5 G_V/G_R + K_V/K_R - 6
    (Ranganathan & Ostoja-Starzewski 2008).

    Raises
    ------
    InputError
        C is not a finite symmetric 6x6 array, or is not positive definite (the message gives
        the smallest eigenvalue).
    """
    C = _as_stiffness(C)
    _check_spd(C)
    S = np.linalg.inv(C)
    d = np.diag(C)
    s = np.diag(S)
    c_off = C[0, 1] + C[1, 2] + C[2, 0]
    s_off = S[0, 1] + S[1, 2] + S[2, 0]
    K_V = (d[:3].sum() + 2.0 * c_off) / 9.0
    G_V = (d[:3].sum() - c_off + 3.0 * d[3:].sum()) / 15.0
    K_R = 1.0 / (s[:3].sum() + 2.0 * s_off)
    G_R = 15.0 / (4.0 * s[:3].sum() - 4.0 * s_off + 3.0 * s[3:].sum())
    K = 0.5 * (K_V + K_R)
    G = 0.5 * (G_V + G_R)
    return IsotropicAverage(
        K_V=float(K_V), K_R=float(K_R), G_V=float(G_V), G_R=float(G_R),
        K=float(K), G=float(G),
        E=float(9.0 * K * G / (3.0 * K + G)),
        nu=float((3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))),
        A_U=float(5.0 * G_V / G_R + K_V / K_R - 6.0),
    )


def cubic_stiffness(C11, C12, C44) -> np.ndarray:
    """6x6 Voigt stiffness of a cubic crystal in its cube axes, Pa.

    Parameters
    ----------
    C11, C12, C44 : float
        The three independent constants, Pa. Not checked for stability here
        (`voigt_reuss_hill` checks positive definiteness: C11 > |C12|, C11 + 2 C12 > 0,
        C44 > 0).
    """
    c11 = check_real("C11", C11, unit="Pa")
    c12 = check_real("C12", C12, unit="Pa")
    c44 = check_real("C44", C44, unit="Pa")
    C = np.zeros((6, 6))
    C[:3, :3] = c12
    C[[0, 1, 2], [0, 1, 2]] = c11
    C[[3, 4, 5], [3, 4, 5]] = c44
    return C


def hexagonal_stiffness(C11, C12, C13, C33, C44) -> np.ndarray:
    """6x6 Voigt stiffness of a hexagonal (transversely isotropic) crystal, c along 3, Pa.

    Parameters
    ----------
    C11, C12, C13, C33, C44 : float
        The five independent constants, Pa; C66 = (C11 - C12)/2 (Nye 1957, ch. VIII).
    """
    c11 = check_real("C11", C11, unit="Pa")
    c12 = check_real("C12", C12, unit="Pa")
    c13 = check_real("C13", C13, unit="Pa")
    c33 = check_real("C33", C33, unit="Pa")
    c44 = check_real("C44", C44, unit="Pa")
    C = np.zeros((6, 6))
    C[0, 0] = C[1, 1] = c11
    C[2, 2] = c33
    C[0, 1] = C[1, 0] = c12
    C[0, 2] = C[2, 0] = C[1, 2] = C[2, 1] = c13
    C[3, 3] = C[4, 4] = c44
    C[5, 5] = 0.5 * (c11 - c12)
    return C


def zener_ratio(C, *, rtol: float = 1e-6) -> float:
    """Zener anisotropy ratio A = 2 C44 / (C11 - C12) of a cubic stiffness (1 if isotropic).

    Parameters
    ----------
    C : array_like, shape (6, 6)
        Stiffness in cube axes, Pa. C11, C12 and C44 are the means of their three cubic
        equivalents (C11, C22, C33), (C12, C13, C23), (C44, C55, C66).
    rtol : float
        Largest accepted departure of any entry from that cubic form, relative to max |C|;
        raise it for constants fitted from noisy simulations.

    Raises
    ------
    InputError
        C is not cubic to `rtol`, or C11 = C12.
    """
    C = _as_stiffness(C)
    rtol = check_real("rtol", rtol, low=0.0)
    c11 = np.mean(np.diag(C)[:3])
    c12 = np.mean([C[0, 1], C[0, 2], C[1, 2]])
    c44 = np.mean(np.diag(C)[3:])
    dev = np.max(np.abs(C - cubic_stiffness(c11, c12, c44))) / np.max(np.abs(C))
    if dev > rtol:
        raise InputError(f"C is not cubic: its largest departure from the cubic form is "
                         f"{dev:.3g} of max |C|, above rtol = {rtol:.3g}")
    if c11 == c12:
        raise InputError("C has C11 = C12: the Zener ratio is undefined")
    return float(2.0 * c44 / (c11 - c12))


#: Voigt index of each tensor index pair
_VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])
#: quadrature points per half-turn in both angles of `indentation_modulus`: the integrands are
#: smooth and periodic, so the midpoint rule converges geometrically (Cu (001), Zener ratio
#: 3.2: 16 points are within 1e-5 of 32)
_ANGLES = 32


def _surface_L(c: np.ndarray, n: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Barnett-Lothe tensor L = -(1/pi) int_0^pi N3(w) dw for the surface direction n and
    the surface normal m, N3 = R T^-1 R^T - Q with (ab)_ik = c_ijkl a_j b_l."""
    w = math.pi * (np.arange(_ANGLES) + 0.5) / _ANGLES
    nn = np.cos(w)[:, None] * n + np.sin(w)[:, None] * m
    mm = -np.sin(w)[:, None] * n + np.cos(w)[:, None] * m
    Q = np.einsum("ijkl,wj,wl->wik", c, nn, nn)
    R = np.einsum("ijkl,wj,wl->wik", c, nn, mm)
    T = np.einsum("ijkl,wj,wl->wik", c, mm, mm)
    N3 = R @ np.linalg.solve(T, np.swapaxes(R, 1, 2)) - Q
    return -N3.mean(axis=0)


def indentation_modulus(C, normal=(0.0, 0.0, 1.0)) -> float:
    """Indentation modulus M of an anisotropic half-space whose surface normal is ``normal``
    (crystal axes of C), against a rigid axisymmetric indenter, Pa; E / (1 - nu^2) when C is
    isotropic.

    Parameters
    ----------
    C : array_like, shape (6, 6)
        Stiffness in Voigt notation in the crystal axes, Pa (symmetric, positive definite).
    normal : sequence of 3 floats
        Surface normal in the same axes, e.g. (0, 0, 1) for (001), (1, 1, 1) for (111).

    Notes
    -----
    Vlassak & Nix (1994): a normal surface traction of wave vector k displaces the surface by
    (L(k)^-1)_nn t / |k|, with L the Barnett-Lothe tensor of the in-plane direction of k. An
    axisymmetric pressure therefore displaces the centre as an isotropic half-space of
    modulus M = 2 / <(L^-1)_nn>, the mean taken over in-plane directions. (The contact is
    not exactly circular; Vlassak & Nix find the effect on M below 1 % for cubic metals.)
    For Cu (C11, C12, C44 = 168.4, 121.4, 75.4 GPa) M is 134.0 GPa on (001) and 151.6 GPa
    on (111), against a Hill E/(1 - nu^2) of 144.6 GPa.
    """
    C = _as_stiffness(C)
    _check_spd(C)
    m = check_float_array("normal", normal, "three numbers")
    if m.shape != (3,) or not np.all(np.isfinite(m)) or not np.linalg.norm(m) > 0:
        raise InputError(f"normal = {normal!r} must be three finite numbers, not all zero")
    m = m / np.linalg.norm(m)
    c = C[_VOIGT[:, :, None, None], _VOIGT[None, None, :, :]]
    e1 = np.cross(m, [1.0, 0.0, 0.0] if abs(m[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(m, e1)
    # L(phi + pi) = L(phi): half a turn of in-plane directions suffices
    phis = math.pi * np.arange(_ANGLES) / _ANGLES
    compliance = [np.linalg.solve(_surface_L(c, math.cos(p) * e1 + math.sin(p) * e2, m), m) @ m
                  for p in phis]
    return float(2.0 / np.mean(compliance))


@dataclass(frozen=True)
class StiffnessFit:
    """Least-squares stiffness from strain-stress pairs; unpacks as ``C, residual = fit``."""

    C: np.ndarray         #: symmetrised 6x6 Voigt stiffness, Pa
    residual: float       #: rms stress misfit / (max|C| rms strain), dimensionless
    asymmetry: float      #: max |C_fit - C_fit^T| / max |C| before symmetrising
    n_pairs: int          #: number of strain-stress pairs used

    def __iter__(self):
        yield self.C
        yield self.residual

    def to_dict(self) -> dict:
        return {"C": self.C.tolist(), "residual": self.residual, "asymmetry": self.asymmetry,
                "n_pairs": self.n_pairs}


def stiffness_from_stress_strain(strains, stresses) -> StiffnessFit:
    """Least-squares 6x6 stiffness C from k >= 6 strain-stress pairs, sigma_i = C eps_i.

    Parameters
    ----------
    strains : array_like, shape (k, 6)
        Voigt strain vectors (eps11, eps22, eps33, gamma23, gamma13, gamma12), engineering
        shear strains, dimensionless. Together they must span all six components (rank 6);
        the usual set is +-eps along each component, k = 12.
    stresses : array_like, shape (k, 6)
        The matching Voigt stress vectors, Pa, in the same component order. With LAMMPS's
        pressure-tensor sign (positive in compression) the caller negates them first.

    Returns
    -------
    StiffnessFit
        ``C`` minimises sum_i |C eps_i - sigma_i|^2 and is then symmetrised, (C + C^T)/2.
        ``residual`` is the rms of the stress misfit of the symmetrised C divided by
        max|C| times the rms strain magnitude: a relative misfit, of the order of the relative
        error of the entries of C, independent of the strain amplitude.

    Raises
    ------
    InputError
        Wrong shapes, fewer than 6 pairs, non-finite values, or strains of rank < 6.
    """
    eps = _as_pairs("strains", strains)
    sig = _as_pairs("stresses", stresses)
    if eps.shape != sig.shape:
        raise InputError(f"strains and stresses must have the same shape, got {eps.shape} "
                         f"and {sig.shape}")
    k = eps.shape[0]
    if k < 6:
        raise InputError(f"strains holds {k} pairs: at least 6 are needed for 36 unknowns")
    rank = np.linalg.matrix_rank(eps)
    if rank < 6:
        raise InputError(f"strains has rank {rank}: the strain vectors must span all six "
                         f"Voigt components")
    X, *_ = np.linalg.lstsq(eps, sig, rcond=None)     # eps @ X = sig, so X = C^T
    C_fit = X.T
    scale = np.max(np.abs(C_fit))
    if scale == 0.0:
        raise InputError("stresses are all zero: the fitted stiffness vanishes")
    asym = float(np.max(np.abs(C_fit - C_fit.T)) / scale)
    C = 0.5 * (C_fit + C_fit.T)
    misfit = eps @ C.T - sig
    rms_strain = math.sqrt(np.mean(np.sum(eps**2, axis=1)))
    residual = float(math.sqrt(np.mean(np.sum(misfit**2, axis=1)))
                     / (np.max(np.abs(C)) * rms_strain))
    return StiffnessFit(C=C, residual=residual, asymmetry=asym, n_pairs=int(k))


def _as_pairs(name: str, values) -> np.ndarray:
    arr = check_float_array(name, values, "a (k, 6) array of numbers")
    if arr.ndim != 2 or arr.shape[1] != 6:
        raise InputError(f"{name} must have shape (k, 6) (Voigt vectors), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains non-finite values")
    return arr
