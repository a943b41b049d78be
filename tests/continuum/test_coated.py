"""The coated half-space contact (`continuum.contact.coated`): its limits."""

import numpy as np
import pytest

from filmscale.continuum.contact.coated import coated_contact, coated_sphere_load
from filmscale.continuum.contact.hertz import hertz_force
from filmscale.continuum.materials import ElasticPlastic

R = 1e-6
FILM = ElasticPlastic(200e9, 0.3, name="film")
SUB = ElasticPlastic(70e9, 0.3, name="sub")
T_FILM = 0.375e-6


def test_coated_solution_limits():
    film, sub = FILM, SUB
    E_sub = sub.plane_strain_modulus
    d = np.array([0.02, 0.1]) * R
    same = coated_sphere_load(d, R, T_FILM, sub, sub)
    np.testing.assert_allclose(same, hertz_force(d, R, E_sub), rtol=1e-4)
    # a film 100x thinner than the contact radius: the substrate within 3 % (measured
    # +1.6 %); a film 300x thicker: the film within 1 % (measured -0.4 %: the far substrate
    # still adds compliance of order a/t)
    a = 0.3e-6
    for t, E_p in ((3e-9, E_sub), (1e-4, film.plane_strain_modulus)):
        delta, P = coated_contact(a, R, t, film, sub)
        assert P / hertz_force(delta, R, E_p) == pytest.approx(1.0, rel=0.03 if t < a else 0.01)
