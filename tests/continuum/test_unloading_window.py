"""What lies outside the unloading fit window (20-98 % of P_max) does not change Oliver-Pharr.

The issue's curve: its last unloading points drift on to -0.2 % of P_max (the tip leaving the
surface, the load zero a little off) and it was refused, "the unloading power-law fit did not
converge". The fit itself only sees the window; the cause was the drift correction of the
analysis (`filmscale indent analyze`, on by default), which took the slow tail at the zero of
load for a thermal-drift hold, measured the retreat of the actuator there as drift and
removed it from the whole curve (up to tens of percent of h_max). A drift hold now needs
contact: a mean load above 1 % of P_max (`curves.DRIFT_HOLD_MIN_LOAD`).

Oracle: the same synthetic curve (`synthetic_curve`, whose E_r is known exactly) without the
tail, analysed the same way: E_r equal to 1e-6.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from filmscale.continuum.indentation.curves import (DRIFT_HOLD_MIN_LOAD, HOLD, LoadDisplacementCurve, check_curve, drift_rate)
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.oliver_pharr import oliver_pharr
from filmscale.continuum.indentation.tips import berkovich
from filmscale.core.errors import InputError
from filmscale.workflows.indent import AnalysisOptions, analyze_curve

TIP = berkovich()
E_R = 100e9


def curves(m=1.5, n_unload=200, h_c=100e-9, tail=20, labels=False):
    """(clean, with tail): the tail continues the unloading at the same time step, its load
    falling linearly from 0 to -0.2 % of P_max while the depth recedes by 1 % of its last
    value. ``labels``: segment labels given (an instrument's markers) or inferred (a text
    table)."""
    c = synthetic_curve(E_R, 5e9, TIP, h_c=h_c, m=m, n_unload=n_unload)
    P_max = float(c.P.max())
    dt = c.t[-1] - c.t[-2]
    h = np.concatenate([c.h, c.h[-1] * (1.0 - np.linspace(0.0, 0.01, tail + 1)[1:])])
    P = np.concatenate([c.P, np.linspace(0.0, -0.002 * P_max, tail + 1)[1:]])
    t = np.concatenate([c.t, c.t[-1] + dt * np.arange(1, tail + 1)])
    seg = np.concatenate([c.segment, np.full(tail, c.segment[-1])])
    clean = LoadDisplacementCurve(c.h, c.P, c.t, c.segment if labels else None, indenter=TIP)
    drifted = LoadDisplacementCurve(h, P, t, seg if labels else None, indenter=TIP)
    assert drifted.P.min() == pytest.approx(-0.002 * P_max)
    return clean, drifted


def analysed(curve):
    record = analyze_curve(curve, {"name": "c", "file": "c.csv"},
                           AnalysisOptions(tip="berkovich"))[0]
    assert record["status"] == 0, record["message"]
    return record


CASES = [
    dict(m=1.3, n_unload=1000, h_c=20e-9, tail=20),    # was refused: "did not converge"
    dict(m=1.3, n_unload=30, h_c=20e-9, tail=6),       # was E_r = 115 GPa
    dict(),
    dict(m=1.8, n_unload=200, h_c=1e-6, tail=40),
]


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("labels", [False, True])
def test_oliver_pharr_ignores_the_tail_below_zero_load(case, labels):
    clean, drifted = curves(labels=labels, **case)
    ref, result = oliver_pharr(clean, TIP), oliver_pharr(drifted, TIP)
    assert ref.ok and result.ok, result.message
    assert result.E_r == pytest.approx(ref.E_r, rel=1e-6)
    assert result.E_r == pytest.approx(E_R, rel=1e-6)
    assert (result.h_c, result.S) == pytest.approx((ref.h_c, ref.S), rel=1e-6)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("labels", [False, True])
def test_the_analysis_ignores_the_tail_below_zero_load(case, labels):
    """`analyze_curve` with its defaults (drift correction on), as `indent analyze` runs."""
    clean, drifted = curves(labels=labels, **case)
    ref, record = analysed(clean), analysed(drifted)
    assert record["E_r"] == pytest.approx(ref["E_r"], rel=1e-6)
    assert record["E_r"] == pytest.approx(E_R, rel=1e-6)
    assert record["drift_rate"] is None and "hold_drift" not in record["flags"]


def test_the_tail_is_no_drift_hold():
    _, drifted = curves(**CASES[0])
    hold = [(start, stop) for label, start, stop in drifted.runs() if label == HOLD
            and start > drifted.peak]
    assert hold, "the slow tail reads as a hold: the case the fix is about"
    with pytest.raises(InputError, match="no hold below half the peak load"):
        drift_rate(drifted)
    assert "hold_drift" not in [f.code for f in check_curve(drifted)]


def test_a_drift_hold_in_contact_is_still_measured():
    """Unload to 10 % of P_max, hold 20 s there while the depth drifts, unload to zero: the
    drift rate is measured as before; the same hold at 0.5 % of P_max is not one."""
    c = synthetic_curve(E_R, 5e9, TIP, h_c=100e-9)
    rate = 0.05e-9

    def with_hold(fraction):
        unl = np.flatnonzero(np.arange(c.h.size) > c.peak)
        k = unl[np.argmin(np.abs(c.P[unl] - fraction * c.P_max))]
        t_hold = c.t[k] + np.linspace(0.0, 20.0, 101)[1:]
        h = np.concatenate([c.h[:k + 1], c.h[k] + rate * (t_hold - c.t[k]), c.h[k + 1:]
                            + rate * 20.0])
        P = np.concatenate([c.P[:k + 1], np.full(100, c.P[k]), c.P[k + 1:]])
        t = np.concatenate([c.t[:k + 1], t_hold, c.t[k + 1:] + 20.0])
        return LoadDisplacementCurve(h, P, t, indenter=TIP)

    assert drift_rate(with_hold(0.1)) == pytest.approx(rate, rel=1e-6)
    assert DRIFT_HOLD_MIN_LOAD == 0.01
    with pytest.raises(InputError, match="no hold below half the peak load"):
        drift_rate(with_hold(0.005))


def test_indent_analyze_reads_and_analyses_the_curve(tmp_path):
    """The command line on a text table (no segment column), as the outside check ran it."""
    for name, curve in zip(("clean", "drifted"), curves(**CASES[0])):
        rows = "".join(f"{h * 1e9:.12g}, {P * 1e6:.12g}, {t:.12g}\n"
                       for h, P, t in zip(curve.h, curve.P, curve.t))
        (tmp_path / f"{name}.csv").write_text("h [nm], P [uN], t [s]\n" + rows)
    run = subprocess.run([sys.executable, "-m", "filmscale", "indent", "analyze", "clean.csv",
                          "drifted.csv", "--tip", "berkovich", "--json"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300,
                         stdin=subprocess.DEVNULL)
    assert run.returncode == 0, run.stderr
    records = {r["name"]: r for r in map(json.loads, run.stdout.splitlines())}
    assert records["drifted"]["status"] == 0, records["drifted"]["message"]
    assert records["drifted"]["E_r"] == pytest.approx(records["clean"]["E_r"], rel=1e-6)
