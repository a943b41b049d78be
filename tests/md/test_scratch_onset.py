"""The onset of a residual groove in the particle scratch against the sliding model's first
yield (issue 35's cross-scale check, `filmscale.md.scratch_onset`).

The closed form, derived here from Hertz (Johnson 1985, 3.4): a = (3 P R / (4 E*))^(1/3) and
p0 = 3 P / (2 pi a^2), so p0^3 = 6 P E*^2 / (pi^3 R^2) and P = pi^3 R^2 p0^3 / (6 E*^2); a
frictionless sphere first yields (von Mises, nu = 0.3) where the largest von Mises stress,
0.62 p0 at 0.48 a below the surface, reaches sigma_y: p0 = 1.6 sigma_y.

The material: E = 70 GPa, nu = 0.3, perfectly plastic with sigma_y chosen so that the Hertz
contact radius at first yield spans 4 spacings of the slow sequence (a_y = 0.4 um on a 0.1 um
lattice) under an 8 um sphere: a_y / R = 0.05, sigma_y = 1.53 GPa, E / sigma_y = 45.7 (a 2 um
sphere, a_y / R = 0.2 and E / sigma_y = 11.4, puts TLSPH's elastic peak von Mises stress 9-11 %
above Hertz's at the same load, and yield at 0.66 of the model's load: finite strains and
a finite a / R).
"""

import math

import pytest

from filmscale.core.errors import InputError
from filmscale.md.particle_scratch import spec_from_mapping
from filmscale.md.scratch_onset import (ONSET_THRESHOLD, groove_onset, hertz_first_yield,
                                        model_first_yield_load)

R, E, NU = 8e-6, 70e9, 0.3
E_STAR = E / (1 - NU**2)
SPACING = 1e-7                    # the slow sequence's lattice
A_Y = 4 * SPACING                 # the Hertz contact radius at first yield
P0_Y = 2 * E_STAR * A_Y / (math.pi * R)        # Hertz: a = pi p0 R / (2 E*)
SIGMA_Y = P0_Y / 1.6


def closed_form_first_yield_load(sigma_y: float) -> float:
    """P_y = pi^3 R^2 (1.6 sigma_y)^3 / (6 E*^2) (module docstring)."""
    return math.pi**3 * R**2 * (1.6 * sigma_y)**3 / (6 * E_STAR**2)


def onset_spec(spacing: float, width: float, length: float, depth: float):
    """The check's scratch: the material above, 250 m/s along x (4.2 % of the P-wave speed),
    20 m/s down and up (100 m/s reaches the first-yield depth, 20 nm, in 0.2 ns, three wave
    transits of the contact: an impact, which yields at x = 0 at 0.54 of the load), 0.5 ns
    relaxation."""
    return spec_from_mapping({
        "name": "onset", "tip": "sphere:8um",
        "target": {"substrate": {"E": E, "nu": NU, "sigma_y": SIGMA_Y, "density": 2700.0}},
        "grid": {"spacing": spacing, "width": width, "depth": width},
        "scratch": {"depth": depth, "length": length, "speed": 250.0, "load_speed": 20.0,
                    "relax_time": 0.5e-9, "frames": 0}})


def test_first_yield_load_of_the_model_and_the_closed_form():
    spec = onset_spec(SPACING, 12 * SPACING, 8 * SPACING, 2e-8)
    P_y, a_y, delta_y = hertz_first_yield(spec)
    P_closed = closed_form_first_yield_load(SIGMA_Y)
    assert P_y == pytest.approx(P_closed, rel=1e-12)
    assert a_y == pytest.approx(A_Y, rel=1e-12)
    assert delta_y == pytest.approx(A_Y**2 / R, rel=1e-12)
    # the sliding model (friction 0, the particle contact's): its largest von Mises stress is
    # 0.620 p0, so p0 = 1.613 sigma_y at first yield, 2.4 % above the rounded 1.6's load
    P_model = model_first_yield_load(spec, 0.0)
    assert P_model == pytest.approx(P_closed, rel=0.03)
    assert model_first_yield_load(spec, 0.3) < P_model      # friction brings yield earlier


def test_onset_needs_increasing_depths_and_the_model_a_plastic_target(tmp_path):
    spec = onset_spec(SPACING, 12 * SPACING, 8 * SPACING, 2e-8)
    with pytest.raises(InputError, match="increasing"):
        groove_onset(spec, [2e-8, 1.5e-8], tmp_path)
    data = spec.to_dict()
    grid = {k: data["grid"][k] for k in ("spacing", "width", "depth", "half")}
    elastic = spec_from_mapping({"tip": data["tip"], "grid": grid,
                                 "scratch": data["scratch"],
                                 "target": {"substrate": {"E": E, "nu": NU}}})
    with pytest.raises(InputError, match="elastic"):
        model_first_yield_load(elastic)


# ---- the default suite: two depths either side of the onset on a coarse lattice (LAMMPS) -----

def test_coarse_bracket_elastic_below_plastic_above(tmp_path):
    """0.2 um lattice (a_y = 2 spacings), 1863 particles: at 0.55 delta_y no particle yields
    and no groove is left; at 2 delta_y particles yield and a groove is left; the model's
    first-yield load lies between the two normal forces."""
    spec = onset_spec(2 * SPACING, 16 * SPACING, 12 * SPACING, 2e-8)
    _, _, delta_y = hertz_first_yield(spec)
    r = groove_onset(spec, [0.55 * delta_y, 2.0 * delta_y], tmp_path)
    clean, plastic = r.points
    assert not clean.yielded and clean.plastic_max <= ONSET_THRESHOLD
    assert plastic.yielded and plastic.plastic_particles > 10
    assert abs(clean.groove_depth) < 0.01 * spec.grid.spacing
    assert plastic.groove_depth > 10 * max(abs(clean.groove_depth), 1e-3 * spec.grid.spacing)
    P_model = model_first_yield_load(spec)
    assert clean.normal_force < P_model < plastic.normal_force
    assert r.onset_load == pytest.approx(0.5 * (clean.normal_force + plastic.normal_force))


# ---- the cross-scale check: the whole sequence on the 0.1 um lattice (LAMMPS, ~10 min) -------

#: depths of the sequence, fractions of the Hertz first-yield depth delta_y = a_y^2 / R (20 nm)
FRACTIONS = (0.7, 0.765, 0.8, 0.85, 0.9)


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    """16 245 particles (a_y = 4 spacings; 18 spacings wide and deep, a 0.8 um stroke), five
    depths two at a time: about 10 min on this 2-core machine (each run 110-220 s). The block
    is 1.8 um (4.5 a_y): on 1.2 um (3 a_y) its rigid base stiffened the contact against the
    half-space the model solves (4 % more peak stress per load, an onset 11 % lower;
    docs/particles.md, "Is the gap numerical?")."""
    spec = onset_spec(SPACING, 18 * SPACING, 8 * SPACING, 2e-8)
    _, _, delta_y = hertz_first_yield(spec)
    return spec, groove_onset(spec, [f * delta_y for f in FRACTIONS],
                              tmp_path_factory.mktemp("onset"), jobs=2)


@pytest.mark.slow
def test_onset_load_measured(sequence):
    """The measured onset (docs/particles.md, "Groove onset"): 0.8 delta_y clean (0.789 of
    the model's load), 0.85 delta_y yielded (0.873, 5 particles, eps_p 6.7e-4): onset
    0.831 +- 0.042 of the model's load (-17 %), 0.851 of the closed form's (-15 %)."""
    spec, r = sequence
    P_model = model_first_yield_load(spec)
    assert [p.yielded for p in r.points] == [False, False, False, True, True]
    assert all(a.normal_force < b.normal_force for a, b in zip(r.points, r.points[1:]))
    assert 0.78 < r.onset_load / P_model < 0.88
    assert r.onset_error < 0.06 * r.onset_load
    # the residual groove stays under 2 nm (2 % of a spacing) at every depth, clean or
    # yielded: the plastic strain marks the onset, the groove does not
    assert all(abs(p.groove_depth) < 0.05 * SPACING for p in r.points)


@pytest.mark.slow
def test_onset_load_within_20_percent_of_the_sliding_model(sequence):
    """Issue 35's cross-scale check: the onset (the midpoint of its bracket) within 20 % of
    the sliding model's first-yield load and of the closed form's. The bracket's clean end
    alone is 21 % under the model's: the check passes on the midpoint, not on the bracket."""
    spec, r = sequence
    assert r.onset_load == pytest.approx(model_first_yield_load(spec, 0.0), rel=0.20)
    assert r.onset_load == pytest.approx(closed_form_first_yield_load(SIGMA_Y), rel=0.20)
