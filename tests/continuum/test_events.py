"""The piecewise event integrator shared by the impact histories, against closed forms written
here: a linear spring m x'' = -k x hit at speed V (x = V sqrt(m/k) sin(t sqrt(k/m))) and a
free flight at constant speed."""

import math

import numpy as np
import pytest

from filmscale.continuum.contact.events import (METHODS, Event, PiecewiseRun, check_history_options,
                                                integrate_until, sample_pieces, sampled_maximum)
from filmscale.core.errors import InputError, ModelRangeError

MASS, STIFFNESS, V = 2e-3, 5e4, 0.7          # kg, N/m, m/s
T_REF = math.sqrt(MASS / STIFFNESS)          # 1/omega, s
D_REF = V * T_REF                            # amplitude V/omega, m


def spring(_, y):
    """m x'' = -k x on the scaled state y = (x / D_REF, v / V) over t / T_REF."""
    return [y[1], -STIFFNESS * (y[0] * D_REF) * D_REF / (MASS * V * V)]


def loading_events(limit=10.0):
    return {"maximum approach": Event(lambda t, y: y[1], -1),
            "range limit": Event(lambda t, y: y[0] - limit, 1)}


def separation():
    return {"separation": Event(lambda t, y: y[0], -1)}


def impact(rtol=1e-10, samples=50):
    run = PiecewiseRun(0.0, np.array([0.0, 1.0]), check_history_options(rtol, samples, "DOP853"))
    turn = run.advance(spring, loading_events(), phase=1)
    sep = run.advance(spring, separation(), phase=2)
    return run, turn, sep


def test_spring_turns_and_separates_where_the_closed_form_says():
    _, turn, sep = impact()
    assert turn.event == "maximum approach" and sep.event == "separation"
    # quarter and half period of omega = sqrt(k/m); amplitude V/omega; rebound at V
    assert turn.t * T_REF == pytest.approx(math.pi / 2 * T_REF, rel=1e-9)
    assert turn.y[0] * D_REF == pytest.approx(V * math.sqrt(MASS / STIFFNESS), rel=1e-9)
    assert turn.y[1] == pytest.approx(0.0, abs=1e-12)
    assert sep.t * T_REF == pytest.approx(math.pi * T_REF, rel=1e-9)
    assert -sep.y[1] * V == pytest.approx(V, rel=1e-9)


def test_samples_follow_the_sine_and_keep_every_step():
    run, turn, sep = impact(samples=50)
    time, delta, velocity, phase, branch = run.sample(T_REF, D_REF, V)
    np.testing.assert_allclose(delta, D_REF * np.sin(time / T_REF), rtol=0, atol=1e-9 * D_REF)
    np.testing.assert_allclose(velocity, V * np.cos(time / T_REF), rtol=0, atol=1e-9 * V)
    assert time[0] == 0.0 and time[-1] == sep.t * T_REF and np.all(np.diff(time) >= 0)
    assert np.all(np.diff(phase) >= 0) and set(phase) == {1, 2} and not branch.any()
    assert np.all(time[phase == 1] <= turn.t * T_REF) and np.all(time[phase == 2] >= turn.t * T_REF)
    # each piece: its evenly spaced samples plus every solver step inside it
    for piece, label in zip(run.pieces, (1, 2)):
        steps = piece.sol.t[(piece.sol.t >= piece.t_start) & (piece.sol.t <= piece.t_end)]
        mine = time[phase == label] / T_REF
        expected = np.union1d(steps, np.linspace(piece.t_start, piece.t_end, 50))
        np.testing.assert_allclose(mine, expected, rtol=1e-15)
    assert [(p.phase, p.t_start, p.t_end) for p in run.pieces] == [
        (1, 0.0, turn.t), (2, turn.t, sep.t)]


def test_sample_pieces_labels_each_piece():
    run, _, _ = impact(samples=5)
    pieces = [type(p)(p.sol, p.phase, 7 * p.phase, p.t_start, p.t_end) for p in run.pieces]
    *_, phase, branch = sample_pieces(pieces, 5, T_REF, D_REF, V)
    assert np.array_equal(branch, 7 * phase)


def test_free_flight_reaches_the_surface_at_gap_over_v():
    gap = 3e-8                                   # m
    run = PiecewiseRun(0.0, np.array([-gap / D_REF, 1.0]),
                       check_history_options(1e-8, 2, "RK45"))
    stop = run.advance(lambda t, y: [y[1], 0.0], {"contact": Event(lambda t, y: y[0], 1)},
                       phase=0)
    assert stop.t * T_REF == pytest.approx(gap / V, rel=1e-12)
    assert run.t == stop.t and list(run.y) == pytest.approx([0.0, 1.0], abs=1e-12)


def test_the_first_terminal_event_ends_the_piece_and_others_are_dated():
    # a limit at half the amplitude comes first (sin t = 1/2 at t = pi/6); a non-terminal
    # event at a quarter of it is dated on the way and does not stop the piece
    events = loading_events(limit=0.5)
    events["quarter"] = Event(lambda t, y: y[0] - 0.25, 1, terminal=False)
    stop = integrate_until(spring, 0.0, [0.0, 1.0], events,
                           check_history_options(1e-10, 2, "DOP853"))
    assert stop.event == "range limit"
    assert stop.t == pytest.approx(math.pi / 6, rel=1e-9)
    assert stop.fired["quarter"] == pytest.approx([math.asin(0.25)], rel=1e-9)
    assert stop.fired["maximum approach"].size == 0


def test_adjust_moves_the_recorded_end():
    run = PiecewiseRun(0.0, np.array([0.0, 1.0]), check_history_options(1e-10, 2, "DOP853"))

    def back_off(stop):
        t = 0.5 * stop.t
        return stop._replace(event="moved", t=t, y=stop.sol.sol(t))
    stop = run.advance(spring, loading_events(), phase=1, adjust=back_off)
    assert stop.event == "moved" and run.t == run.pieces[0].t_end == stop.t
    assert stop.t == pytest.approx(math.pi / 4, rel=1e-9)
    assert run.y[0] == pytest.approx(math.sin(math.pi / 4), rel=1e-9)


def test_no_event_raises_a_model_range_error():
    options = check_history_options(1e-8, 2, "DOP853")
    # a body flying away from the surface never turns and never reaches the range limit
    with pytest.raises(ModelRangeError, match="time integration stopped without an event"):
        integrate_until(lambda t, y: [y[1], 0.0], 0.0, [0.0, -1.0], loading_events(), options)
    with pytest.raises(ModelRangeError, match="stopped before separation"):
        integrate_until(lambda t, y: [1.0, 0.0], 0.0, [0.0, 1.0], separation(), options,
                        stopped="before separation")
    # a failed integration (the step size collapses at a slope that is NaN past t = 1) is
    # no event either
    with pytest.raises(ModelRangeError, match="without an event"):
        integrate_until(lambda t, y: [math.nan if t > 1 else y[1], 0.0], 0.0, [0.0, 1.0],
                        loading_events(), options)


def test_sampled_maximum_refines_an_interior_peak_only():
    ts = np.linspace(0.0, 3.0, 7)
    # sin peaks at pi/2, between samples: refined to 1
    assert sampled_maximum(np.sin(ts), ts, math.sin) == pytest.approx(1.0, abs=1e-12)
    # a peak at an end is the largest sample; a larger ``best`` stays
    assert sampled_maximum(ts**2, ts, lambda t: t * t) == 9.0
    assert sampled_maximum(np.sin(ts), ts, math.sin, best=2.0) == 2.0


def test_options_are_checked_and_name_the_parameter():
    options = check_history_options(1e-9, 3, "Radau")
    assert (options.rtol, options.samples, options.method) == (1e-9, 3, "Radau")
    assert options.solver() == dict(method="Radau", rtol=1e-9, atol=1e-9 * 1e-3,
                                    dense_output=True)
    assert METHODS == ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
    for kwargs, match in [(dict(rtol=1e-14), r"rtol = 1e-14 is outside the valid range"),
                          (dict(rtol=0.1), r"rtol = 0.1 is outside"),
                          (dict(rtol=math.nan), "rtol"),
                          (dict(method="Euler"), r"method = 'Euler' is not one of: DOP853"),
                          (dict(samples=1), r"samples = 1 must be an integer >= 2"),
                          (dict(samples=True), r"samples = True must be an integer"),
                          (dict(samples=2.0), r"samples = 2.0 must be an integer")]:
        args = dict(rtol=1e-8, samples=2, method="DOP853") | kwargs
        with pytest.raises(InputError, match=match):
            check_history_options(**args)
