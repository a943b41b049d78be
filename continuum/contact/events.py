"""Piecewise time integration with terminal, directional events: the integrator that the
sphere (`impact`) and cylinder (`cylinder`) impact histories share.

An impact history is integrated in pieces, each one `scipy.integrate.solve_ivp` run from
where the last one stopped until the first of its terminal events fires: a free flight that
ends at contact, loading pieces that end at the maximum approach (the velocity crossing zero
downwards), at a regime threshold (a new force branch) or at the range limit, and an
unloading piece that ends at separation. A piece ends exactly on its event, so that no solver
step straddles a kink of the force law; non-terminal events only date something (first
yield of the cylinder). Every piece keeps its dense output, which `sample_pieces` turns into
sampled histories.

The state is scaled by the caller, y = (approach / d_ref, velocity / V) over the time
t / t_ref; the integration runs at most _T_BOUND time units (its events end it far earlier)
with the absolute tolerance 1e-3 rtol. SI units outside the scaled state.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np

from filmscale.core.checks import check_choice, check_real
from filmscale.core.errors import InputError, ModelRangeError

#: the `solve_ivp` methods a history may use
METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
_T_BOUND = 1e6    # integration limit in scaled time units (events end it earlier)


@dataclass(frozen=True)
class HistoryOptions:
    """Checked options of a time-integrated history (`check_history_options`)."""

    rtol: float     #: relative tolerance; the absolute one is 1e-3 rtol on the scaled state
    samples: int    #: evenly spaced dense-output points per piece, besides the solver's steps
    method: str     #: one of METHODS

    def solver(self) -> dict:
        """Keyword arguments of `solve_ivp`: method, tolerances and dense output."""
        return dict(method=self.method, rtol=self.rtol, atol=self.rtol * 1e-3,
                    dense_output=True)


def check_history_options(rtol, samples, method) -> HistoryOptions:
    """rtol in [1e-13, 1e-2], samples an integer >= 2 and method one of METHODS; InputError
    naming the parameter otherwise."""
    rtol = check_real("rtol", rtol, low=1e-13, high=1e-2)
    check_choice("method", method, METHODS)
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InputError(f"samples = {samples!r} must be an integer >= 2")
    return HistoryOptions(rtol, samples, method)


class Event(NamedTuple):
    """An event g(t, y) = 0 crossed in ``direction`` (+1 upwards, -1 downwards, 0 either);
    a terminal event ends the piece."""

    fun: Callable
    direction: int
    terminal: bool = True


class _EventFunction:
    """An event as `solve_ivp` takes it: a callable with ``terminal`` and ``direction``."""

    def __init__(self, event: Event):
        self.fun, self.direction, self.terminal = event.fun, event.direction, event.terminal

    def __call__(self, t, y):
        return self.fun(t, y)


class Stop(NamedTuple):
    """Where a piece stopped: the `solve_ivp` solution, the name of the terminal event that
    ended it, its time and state, and the times at which each event fired (non-terminal
    events included)."""

    sol: object
    event: str
    t: float
    y: np.ndarray
    fired: dict


@dataclass(frozen=True)
class Piece:
    """One integrated piece: its dense solution, phase (0 free flight, 1 loading,
    2 unloading), the force branch it used (0 where the model has one per phase) and the
    scaled times it covers."""

    sol: object
    phase: int
    branch: int
    t_start: float
    t_end: float


def integrate_until(rhs, t0, y0, events: dict[str, Event], options: HistoryOptions,
                    stopped="without an event") -> Stop:
    """Integrate y' = rhs(t, y) from (t0, y0) until the first terminal event of ``events``
    (name -> Event); ModelRangeError "time integration stopped <stopped>: ..." when the
    integration ends, or fails, before one fires."""
    from scipy.integrate import solve_ivp
    names = list(events)
    funs = [_EventFunction(events[name]) for name in names]
    sol = solve_ivp(rhs, (t0, t0 + _T_BOUND), y0, events=funs, **options.solver())
    hit = [k for k, fun in enumerate(funs) if fun.terminal and sol.t_events[k].size]
    if not hit or sol.status < 0:
        raise ModelRangeError(f"time integration stopped {stopped}: {sol.message}")
    k = min(hit, key=lambda j: sol.t_events[j][0])
    return Stop(sol, names[k], sol.t_events[k][0], sol.y_events[k][0].copy(),
                dict(zip(names, sol.t_events)))


class PiecewiseRun:
    """The pieces of one integration so far and the scaled state (t, y) where the last one
    stopped, from which the next one starts."""

    def __init__(self, t, y, options: HistoryOptions):
        self.t, self.y, self.options = t, y, options
        self.pieces: list[Piece] = []

    def advance(self, rhs, events: dict[str, Event], phase: int, branch: int = 0, *,
                stopped="without an event", adjust=None) -> Stop:
        """Integrate one piece with `integrate_until`, record it and move the state to its
        end; ``adjust(stop) -> stop``, if given, may move the end before it is recorded."""
        stop = integrate_until(rhs, self.t, self.y, events, self.options, stopped)
        if adjust is not None:
            stop = adjust(stop)
        self.pieces.append(Piece(stop.sol, phase, branch, self.t, stop.t))
        self.t, self.y = stop.t, stop.y
        return stop

    def sample(self, t_ref: float, d_ref: float, v_ref: float):
        """`sample_pieces` of the pieces so far at the options' samples per piece."""
        return sample_pieces(self.pieces, self.options.samples, t_ref, d_ref, v_ref)


def sample_pieces(pieces, samples: int, t_ref: float, d_ref: float, v_ref: float):
    """Samples of a time integration in `Piece` s (dense-output `solve_ivp` solutions of the
    scaled approach and velocity): every solver step within [t_start, t_end] plus
    ``samples`` evenly spaced points. Returns time (s), approach (m), velocity (m/s), phase
    and branch, one array each."""
    rows = []
    for piece in pieces:
        sol, t_a, t_b = piece.sol, piece.t_start, piece.t_end
        steps = sol.t[(sol.t >= t_a) & (sol.t <= t_b)]
        ts = np.unique(np.concatenate([steps, np.linspace(t_a, t_b, samples)]))
        ys = sol.sol(ts)
        rows.append([ts * t_ref, ys[0] * d_ref, ys[1] * v_ref,
                     np.full(ts.size, piece.phase), np.full(ts.size, piece.branch)])
    return tuple(np.concatenate(column) for column in zip(*rows))


def sampled_maximum(q, ts, fun, best=-np.inf):
    """``best`` raised to the largest sample q of fun at the increasing times ts, then, where
    that sample is an interior local maximum, to the maximum of fun(t) found between its
    neighbours by a bounded scalar search (to 1e-14 ts[-1])."""
    k = int(np.argmax(q))
    best = max(best, float(q[k]))
    if 0 < k < ts.size - 1 and q[k] > q[k - 1] and q[k] > q[k + 1]:
        from scipy.optimize import minimize_scalar
        res = minimize_scalar(lambda t: -fun(t), bounds=(ts[k - 1], ts[k + 1]),
                              method="bounded", options={"xatol": 1e-14 * ts[-1]})
        best = max(best, -res.fun)
    return best
