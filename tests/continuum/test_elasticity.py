"""Voigt-Reuss-Hill averages and stiffness fits against closed forms and published moduli."""

import numpy as np
import pytest

from filmscale.continuum.elasticity import (IsotropicAverage, cubic_stiffness, hexagonal_stiffness,
                                            indentation_modulus, stiffness_from_stress_strain,
                                            voigt_reuss_hill, zener_ratio)
from filmscale.continuum.materials import DIAMOND, ElasticPlastic, reduced_modulus
from filmscale.core.errors import InputError

GPa = 1e9

# copper at room temperature, Simmons & Wang, Single Crystal Elastic Constants and Calculated
# Aggregate Properties (MIT Press, 1971)
CU = dict(C11=168.4 * GPa, C12=121.4 * GPa, C44=75.4 * GPa)


def _isotropic(E, nu):
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    return cubic_stiffness(lam + 2 * mu, lam, mu)


@pytest.mark.parametrize("E, nu", [(70e9, 0.33), (210e9, 0.29), (1141e9, 0.07), (5e9, -0.2)])
def test_isotropic_stiffness_returns_its_own_moduli(E, nu):
    avg = voigt_reuss_hill(_isotropic(E, nu))
    # an isotropic C makes every bound coincide: only round-off separates them (1e-12)
    K, G = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    for got, want in [(avg.E, E), (avg.K_V, K), (avg.K_R, K), (avg.G_V, G), (avg.G_R, G)]:
        assert got == pytest.approx(want, rel=1e-12)
    assert avg.nu == pytest.approx(nu, rel=1e-12)
    assert avg.A_U == pytest.approx(0.0, abs=1e-12)
    # the material's own K and G agree with those read off its stiffness tensor
    mat = ElasticPlastic(E, nu)
    assert mat.bulk_modulus == pytest.approx(avg.K_V, rel=1e-12)
    assert mat.shear_modulus == pytest.approx(avg.G_V, rel=1e-12)
    assert zener_ratio(_isotropic(E, nu)) == pytest.approx(1.0, rel=1e-12)


def test_copper_hill_average_matches_cubic_closed_forms():
    c11, c12, c44 = CU["C11"], CU["C12"], CU["C44"]
    avg = voigt_reuss_hill(cubic_stiffness(c11, c12, c44))
    # cubic closed forms (Hill 1952): K_V = K_R = (C11 + 2 C12)/3,
    # G_V = (C11 - C12 + 3 C44)/5, G_R = 5 (C11 - C12) C44 / (4 C44 + 3 (C11 - C12));
    # same arithmetic by another route, so agreement to round-off (1e-12)
    K = (c11 + 2 * c12) / 3
    G_V = (c11 - c12 + 3 * c44) / 5
    G_R = 5 * (c11 - c12) * c44 / (4 * c44 + 3 * (c11 - c12))
    assert (avg.K_V, avg.K_R, avg.G_V, avg.G_R) == (
        pytest.approx(K, rel=1e-12), pytest.approx(K, rel=1e-12),
        pytest.approx(G_V, rel=1e-12), pytest.approx(G_R, rel=1e-12))
    assert avg.G == pytest.approx(0.5 * (G_V + G_R), rel=1e-12)
    # for cubic crystals K_V = K_R, so A^U = 5 (G_V/G_R - 1)
    assert avg.A_U == pytest.approx(5 * (G_V / G_R - 1), rel=1e-12)
    # Zener ratio of copper: 2 x 75.4 / 47.0 = 3.209 (exact arithmetic on the inputs)
    assert zener_ratio(cubic_stiffness(c11, c12, c44)) == pytest.approx(150.8 / 47.0, rel=1e-12)


def test_copper_hill_modulus_against_measured_polycrystal():
    avg = voigt_reuss_hill(cubic_stiffness(**CU))
    # Polycrystalline copper, Kaye & Laby, Tables of Physical and Chemical Constants
    # (16th ed., 1995, sec. 2.2.2): E = 129.8 GPa, nu = 0.343. The Hill average is an
    # estimate, not a bound; for cubic metals it lies within a few per cent of measured
    # untextured aggregates (here 127.4 GPa, -1.8 %), hence 3 % on E and 0.01 on nu.
    assert avg.E == pytest.approx(129.8 * GPa, rel=0.03)
    assert avg.nu == pytest.approx(0.343, abs=0.01)
    # the measured modulus must lie between the Voigt and Reuss Young's moduli (a theorem)
    E_V = 9 * avg.K_V * avg.G_V / (3 * avg.K_V + avg.G_V)
    E_R = 9 * avg.K_R * avg.G_R / (3 * avg.K_R + avg.G_R)
    assert E_R < 129.8 * GPa < E_V


def test_voigt_above_hill_above_reuss_for_random_stiffnesses():
    rng = np.random.default_rng(20240611)
    for _ in range(200):
        M = rng.normal(size=(6, 6))
        C = (M @ M.T + 0.05 * np.eye(6)) * 100 * GPa
        avg = voigt_reuss_hill(C)
        # Hill (1952): Voigt >= Reuss for every SPD stiffness; 1e-12 absorbs round-off
        # when a random draw is nearly isotropic
        assert avg.K_V >= avg.K >= avg.K_R * (1 - 1e-12)
        assert avg.G_V >= avg.G >= avg.G_R * (1 - 1e-12)
        assert avg.A_U >= -1e-12


def test_hexagonal_voigt_closed_form_and_isotropic_limit():
    # titanium (Simmons & Wang 1971); any hexagonal set tests the algebra
    c11, c12, c13, c33, c44 = 162.4 * GPa, 92.0 * GPa, 69.0 * GPa, 180.7 * GPa, 46.7 * GPa
    avg = voigt_reuss_hill(hexagonal_stiffness(c11, c12, c13, c33, c44))
    # hexagonal Voigt bounds: K_V = (2 C11 + C33 + 2 C12 + 4 C13)/9,
    # G_V = (7 C11 + 2 C33 - 5 C12 - 4 C13 + 12 C44)/30 (C66 = (C11 - C12)/2), round-off only
    assert avg.K_V == pytest.approx((2 * c11 + c33 + 2 * c12 + 4 * c13) / 9, rel=1e-12)
    assert avg.G_V == pytest.approx((7 * c11 + 2 * c33 - 5 * c12 - 4 * c13 + 12 * c44) / 30,
                                    rel=1e-12)
    # C11 = C33, C12 = C13, C44 = (C11 - C12)/2 is isotropic: A^U = 0 to round-off
    iso = voigt_reuss_hill(hexagonal_stiffness(200 * GPa, 80 * GPa, 80 * GPa, 200 * GPa,
                                               60 * GPa))
    assert iso.A_U == pytest.approx(0.0, abs=1e-12)
    assert iso.G == pytest.approx(60 * GPa, rel=1e-12)


def test_reduced_modulus_and_to_dict():
    avg = voigt_reuss_hill(cubic_stiffness(**CU))
    Eps = avg.E / (1 - avg.nu**2)
    assert avg.plane_strain_modulus() == pytest.approx(Eps, rel=1e-15)
    assert avg.reduced_modulus() == pytest.approx(Eps, rel=1e-15)
    assert avg.reduced_modulus(DIAMOND) == pytest.approx(reduced_modulus(Eps, DIAMOND),
                                                         rel=1e-15)
    # Johnson (1985) eq. 4.22 written out
    assert avg.reduced_modulus(DIAMOND) == pytest.approx(
        1 / ((1 - avg.nu**2) / avg.E + (1 - 0.07**2) / 1141e9), rel=1e-12)
    d = avg.to_dict()
    assert set(d) == set(IsotropicAverage.__dataclass_fields__)
    assert all(isinstance(v, float) for v in d.values())
    with pytest.raises(InputError, match="indenter"):
        avg.reduced_modulus("diamond")


def test_stiffness_recovered_from_synthetic_stress_strain():
    rng = np.random.default_rng(7)
    M = rng.normal(size=(6, 6))
    C_true = (M @ M.T + np.eye(6)) * 50 * GPa
    eps = 1e-3
    strains = np.vstack([eps * np.eye(6), -eps * np.eye(6)])     # +-eps on each component
    stresses = strains @ C_true.T
    fit = stiffness_from_stress_strain(strains, stresses)
    # exact linear data: least squares recovers C to round-off (1e-10 of max |C|)
    assert np.max(np.abs(fit.C - C_true)) <= 1e-10 * np.max(np.abs(C_true))
    assert fit.residual < 1e-10 and fit.asymmetry < 1e-10 and fit.n_pairs == 12
    C, residual = fit                                            # tuple-style unpacking
    assert C is fit.C and residual == fit.residual
    assert set(fit.to_dict()) == {"C", "residual", "asymmetry", "n_pairs"}


def test_stiffness_fit_reports_noise_as_relative_residual():
    C_true = cubic_stiffness(**CU)
    rng = np.random.default_rng(3)
    strains = np.vstack([1e-3 * np.eye(6), -1e-3 * np.eye(6)])
    noise = 1e-3 * np.max(np.abs(C_true)) * 1e-3          # 0.1 % of the largest stress
    stresses = strains @ C_true.T + rng.normal(scale=noise, size=(12, 6))
    fit = stiffness_from_stress_strain(strains, stresses)
    # residual = rms misfit / (max|C| rms strain); the misfit keeps (k - 6)/k of the noise
    # variance in each of 6 components: sqrt(6 x 6/12) x 1e-6 / 1e-3 = 1.7e-3; the bounds
    # leave a factor ~2 either side for the scatter of a 36-degree-of-freedom chi-square
    assert 3e-4 < fit.residual < 3e-3
    assert zener_ratio(fit.C, rtol=1e-2) == pytest.approx(zener_ratio(C_true), rel=1e-2)


def test_bad_stiffness_raises_input_error():
    C = cubic_stiffness(**CU)
    unstable = cubic_stiffness(100 * GPa, 120 * GPa, 50 * GPa)   # C11 < C12: shear unstable
    with pytest.raises(InputError, match=r"C is not positive definite: smallest eigenvalue -"):
        voigt_reuss_hill(unstable)
    with pytest.raises(InputError, match="C is not positive definite"):
        voigt_reuss_hill(cubic_stiffness(100 * GPa, 50 * GPa, 0.0))
    asym = C.copy()
    asym[0, 3] = 1 * GPa
    with pytest.raises(InputError, match="not symmetric"):
        voigt_reuss_hill(asym)
    with pytest.raises(InputError, match="6x6"):
        voigt_reuss_hill(np.eye(3))
    with pytest.raises(InputError, match="non-finite"):
        voigt_reuss_hill(np.full((6, 6), np.nan))
    with pytest.raises(InputError, match="not cubic"):
        zener_ratio(hexagonal_stiffness(162e9, 92e9, 69e9, 180e9, 46e9))
    with pytest.raises(InputError, match="rank 5"):
        stiffness_from_stress_strain(np.eye(6)[[0, 1, 2, 3, 4, 4]], np.eye(6))
    with pytest.raises(InputError, match="at least 6"):
        stiffness_from_stress_strain(np.eye(6)[:5], np.eye(6)[:5])
    with pytest.raises(InputError, match="C11"):
        cubic_stiffness("a", 1.0, 1.0)


@pytest.mark.parametrize("E, nu", [(70e9, 0.33), (210e9, 0.29), (5e9, -0.2)])
@pytest.mark.parametrize("normal", [(0, 0, 1), (1, 1, 1), (0.3, -1.2, 0.7)])
def test_indentation_modulus_of_an_isotropic_solid_is_its_plane_strain_modulus(E, nu, normal):
    # every in-plane direction gives L^-1_nn = 2 (1 - nu^2)/E: only round-off remains
    assert indentation_modulus(_isotropic(E, nu), normal) == pytest.approx(E / (1 - nu**2),
                                                                          rel=1e-10)


def test_indentation_modulus_along_a_hexagonal_axis_matches_its_closed_form():
    # transverse isotropy about the indentation axis: Delafargue & Ulm, Int. J. Solids Struct.
    # 41 (2004) 7351, M = 2 sqrt((C11 C33 - C13^2)/C11 / (1/C44 + 2/(sqrt(C11 C33) + C13)));
    # exact for this symmetry (the contact is circular), so only the quadrature's error
    # remains (1e-8). Titanium, Simmons & Wang (1971).
    c11, c12, c13, c33, c44 = 162.4 * GPa, 92.0 * GPa, 69.0 * GPa, 180.7 * GPa, 46.7 * GPa
    closed = 2 * np.sqrt((c11 * c33 - c13**2) / c11 / (1 / c44 + 2 / (np.sqrt(c11 * c33) + c13)))
    C = hexagonal_stiffness(c11, c12, c13, c33, c44)
    assert indentation_modulus(C, (0, 0, 1)) == pytest.approx(closed, rel=1e-8)


def _rotated(C, Q):
    """C in axes rotated by the orthogonal matrix Q (rows: the new axes in the old frame)."""
    from filmscale.continuum.elasticity import _VOIGT
    c = C[_VOIGT[:, :, None, None], _VOIGT[None, None, :, :]]
    c = np.einsum("ai,bj,ck,dl,ijkl->abcd", Q, Q, Q, Q, c)
    out = np.empty((6, 6))
    pairs = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    for I, (i, j) in enumerate(pairs):
        for J, (k, l) in enumerate(pairs):
            out[I, J] = c[i, j, k, l]
    return out


def test_copper_indentation_modulus_orders_the_faces_and_follows_rotations():
    C = cubic_stiffness(CU["C11"], CU["C12"], CU["C44"])
    m001, m110, m111 = (indentation_modulus(C, n) for n in ((0, 0, 1), (1, 1, 0), (1, 1, 1)))
    hill = voigt_reuss_hill(C).plane_strain_modulus()
    # a Zener ratio above 1 makes (001) the most compliant face and (111) the stiffest
    # (Vlassak & Nix 1994, their cubic results); the polycrystal lies between
    assert m001 < m110 < m111 and m001 < hill < m111
    # cubic symmetry: the three cube faces are one face (quadrature in different frames)
    for n in ((1, 0, 0), (0, 1, 0), (0, 0, -1)):
        assert indentation_modulus(C, n) == pytest.approx(m001, rel=1e-8)
    # a rotation of crystal and normal together changes nothing: (111) made the z axis
    z = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    x = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    Q = np.array([x, np.cross(z, x), z])
    assert indentation_modulus(_rotated(C, Q), (0, 0, 1)) == pytest.approx(m111, rel=1e-8)


@pytest.mark.parametrize("normal", [(0, 0, 0), (1, 2), "001", (np.nan, 0, 1)])
def test_indentation_modulus_refuses_a_bad_normal(normal):
    C = cubic_stiffness(CU["C11"], CU["C12"], CU["C44"])
    with pytest.raises(InputError, match="normal"):
        indentation_modulus(C, normal)
