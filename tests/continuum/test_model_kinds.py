"""The contract every registered model kind passes (docs/architecture.md, "How to add a model
kind"). Oracles: Hertz's closed-form elastic impact of a sphere (Johnson 1985, 11.4), the
elastic limit's conservation of energy (restitution 1, rebound speed V), a film of the
substrate's own material (the layered target equals the half-space), the kind's own scalar
solution at each point (vectorised = scalar, map = points), its time integration (history =
maxima) and the declared units."""

import math

import numpy as np
import pytest

from filmscale.continuum.contact.kinds import KINDS, kind_named, map_units, shapes
from filmscale.continuum.contact.results import EXCEEDS_RADIUS, OK
from filmscale.continuum.materials import ElasticPlastic, Layer, LayerStack
from filmscale.core.keys import Key

shapes()        # the package's own kinds registered
SUBSTRATE = ElasticPlastic(90e9, 0.25, 2.4e9, name="glass")
#: per kind: (options, mass (kg), a radius (m), an elastic speed, a plastic speed)
CASES = {
    "sphere": ({}, 1.6e-6, 10e-6, 1e-4, 2.0),
    "sphere-oblique": ({"angle": 30.0, "friction": 0.0, "inertia_factor": 0.4}, 1.6e-6,
                       10e-6, 1e-4, 2.0),
    "cylinder": ({"length": 5e-3, "datum_depth": None}, 1e-3, 1e-3, 1e-3, 20.0),
}
BUILTIN = tuple(CASES)
SIZE_UNITS = {"contact_radius": "m", "contact_half_width": "m"}


def _options(name: str) -> dict:
    kind = kind_named(name)
    base = {k.name: k.default for k in kind.keys} | CASES[name][0]
    if "contact_law" in base:
        from filmscale.continuum.contact.laws import contact_law
        base["contact_law"] = contact_law(base["contact_law"])
    return base | {"rtol": 1e-10, "path": "fast"}


def _model(name, target=SUBSTRATE):
    return kind_named(name).build(target, None, _options(name))


def test_the_package_kinds_are_registered_in_order():
    assert list(KINDS)[:3] == list(BUILTIN)
    assert shapes()[:2] == ("sphere", "cylinder")


@pytest.mark.parametrize("name", BUILTIN)
def test_declarations_are_complete_and_in_si(name):
    kind = kind_named(name)
    assert kind.summary and set(kind.fields) <= set(kind.units)
    known = {"m", "N", "Pa", "s", "1", "m/s", "J", "N/m", "degrees", "rad/s"}
    assert set(kind.units.values()) <= known
    assert all(isinstance(k, Key) and k.section in ("impactor", "model", "contact")
               for k in kind.keys)
    assert kind.size in SIZE_UNITS
    assert set(kind.units) <= set(map_units())


@pytest.mark.parametrize("name", BUILTIN)
def test_the_elastic_limit_conserves_energy(name):
    """Far below first yield every kind rebounds at the impact speed."""
    kind = kind_named(name)
    _, m, R, v_elastic, _ = CASES[name]
    res = kind.solve(_model(name), v_elastic, R, m, _options(name))
    normal = getattr(res, "normal", res)
    assert not normal.yielded
    assert normal.restitution == pytest.approx(1.0, abs=1e-9)
    assert normal.rebound_velocity == pytest.approx(v_elastic, rel=1e-9)


def test_the_sphere_kinds_match_hertz_in_the_elastic_limit():
    E_star = SUBSTRATE.E / (1 - SUBSTRATE.nu ** 2)
    _, m, R, V, _ = CASES["sphere"]
    delta = (15 * m * V * V / (16 * E_star * math.sqrt(R))) ** 0.4
    for name in ("sphere", "sphere-oblique"):
        res = kind_named(name).solve(_model(name), V, R, m, _options(name))
        assert getattr(res, "normal", res).delta_max == pytest.approx(delta, rel=1e-9)


@pytest.mark.parametrize("name", BUILTIN)
def test_a_film_of_the_substrate_material_is_the_half_space(name):
    _, m, R, _, V = CASES[name]
    film = LayerStack((Layer(R / 50, SUBSTRATE),), SUBSTRATE)
    kind = kind_named(name)
    bare = kind.maxima(_model(name), V, R, m)
    layered = kind.maxima(_model(name, film), V, R, m)
    for field in ("delta_max", "force_max", "restitution"):
        assert layered[field] == pytest.approx(bare[field], rel=1e-9)


@pytest.mark.parametrize("name", BUILTIN)
def test_vectorised_maxima_equal_the_scalar_solution(name):
    kind = kind_named(name)
    _, m, R, v_el, v_pl = CASES[name]
    V = np.array([v_el, v_pl, v_pl])
    radii = np.array([R, R, 2 * R])
    found = kind.maxima(_model(name), V, radii, m)
    assert set(found) >= {"yielded", "status"} and found["status"].shape == V.shape
    for i in range(V.size):
        one = getattr(kind.solve(_model(name), V[i], radii[i], m, _options(name)), "normal",
                      None) or kind.solve(_model(name), V[i], radii[i], m, _options(name))
        assert found["status"][i] == OK and bool(found["yielded"][i]) == one.yielded
        for field in found:
            if field in kind.units and hasattr(one, field):
                assert found[field][i] == pytest.approx(getattr(one, field), rel=1e-12)
    assert found["yielded"][1]          # the plastic speed yields


@pytest.mark.parametrize("name", BUILTIN)
def test_the_history_reaches_the_maxima(name):
    kind = kind_named(name)
    _, m, R, _, V = CASES[name]
    fast = kind.maxima(_model(name), V, R, m)
    hist = kind.history(_model(name), V, R, m, _options(name))
    assert hist.result.delta_max == pytest.approx(float(fast["delta_max"]), rel=1e-6)
    assert hist.result.restitution == pytest.approx(float(fast["restitution"]), rel=1e-5)
    size = getattr(hist, kind.size)
    assert size.shape == hist.time.shape == hist.force.shape
    assert np.all(np.diff(hist.time) >= 0) and np.max(hist.force) > 0


@pytest.mark.parametrize("name", BUILTIN)
def test_the_map_equals_the_maxima_point_by_point_and_marks_its_range(name):
    kind = kind_named(name)
    _, m, R, v_el, v_pl = CASES[name]
    velocity = np.array([v_el, v_pl, 1e4])          # the last beyond any model's range
    rows = np.array([R, 2 * R]) if not kind.oblique else np.array([R, 2 * R])
    opts = _options(name)
    mp = kind.impact_map(_model(name), velocity, rows, m, opts)
    assert mp.kind == name and mp.shape == kind.shape
    assert set(mp.to_dict()) <= set(map_units()) | {"mass"}
    for i, r in enumerate(rows):
        found = kind.maxima(_model(name), velocity, np.full(3, r), m)
        for field in ("delta_max", "force_max", "restitution"):
            np.testing.assert_allclose(mp.field(field)[i], found[field], rtol=1e-12)
    assert mp.out_of_range[:, -1].all() and not mp.out_of_range[:, :2].any()
    assert np.isnan(mp.field("delta_max")[:, -1]).all()
    assert (found["status"][-1] == EXCEEDS_RADIUS)


@pytest.mark.parametrize("name", BUILTIN)
def test_a_map_reads_back_from_its_arrays(name):
    kind = kind_named(name)
    _, m, R, v_el, v_pl = CASES[name]
    mp = kind.impact_map(_model(name), np.array([v_el, v_pl]), np.array([R, 2 * R]), m,
                         _options(name))
    back = kind.map_from_arrays(mp.to_dict(), mp.regime_names, mp.attrs)
    assert back.kind == mp.kind and tuple(back.fields) == tuple(mp.fields)
    for field in kind.units:
        np.testing.assert_array_equal(back.field(field), mp.field(field))
    np.testing.assert_array_equal(back.yielded, mp.yielded)


def test_an_unknown_kind_or_shape_names_what_exists():
    from filmscale.continuum.contact.kinds import kind_for
    from filmscale.core.errors import InputError
    with pytest.raises(InputError, match="not one of: sphere, sphere-oblique, cylinder"):
        kind_named("wedge")
    with pytest.raises(InputError, match="has no oblique impact model"):
        kind_for("cylinder", oblique=True)
