"""Load-displacement curves: segments, data checks, corrections and file round trips."""

import dataclasses

import h5py
import numpy as np
import pytest

from filmscale.continuum.indentation.curves import (HOLD, LOAD, UNLOAD, LoadDisplacementCurve, check_curve, drift_rate)
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.io import read_curves, write_curve_group
from filmscale.continuum.indentation.tips import berkovich
from filmscale.core.errors import InputError

TIP = berkovich()


def clean(**kw):
    return synthetic_curve(100e9, 10e9, TIP, h_c=100e-9, **kw)


def codes(curve):
    return {f.code for f in check_curve(curve)}


def test_segments_detected_from_the_load_rate():
    truth = clean(noise=0.002, seed=3)
    detected = LoadDisplacementCurve(truth.h, truth.P, truth.t)
    # labels may differ only where the smoothing window (9 points: 2 % of 450, not widened
    # at 0.2 % noise) straddles one of the two transitions
    assert np.sum(detected.segment != truth.segment) <= 2 * 9
    assert [r[0] for r in detected.runs()] == [LOAD, HOLD, UNLOAD]
    no_time = LoadDisplacementCurve(truth.h, truth.P)
    assert [r[0] for r in no_time.runs()] == [LOAD, HOLD, UNLOAD]


def test_clean_curve_raises_no_flag():
    assert codes(clean()) == set()
    assert codes(clean(noise=0.002, seed=1)) == set()


def test_nan_rows_flagged_and_dropped():
    c = clean()
    h = c.h.copy()
    h[[10, 300]] = np.nan
    bad = LoadDisplacementCurve(h, c.P, c.t)
    assert codes(bad) == {"nan_data"}
    assert len(bad.finite()) == len(c) - 2


def test_no_unloading_and_few_points():
    c = clean()
    load_only = LoadDisplacementCurve(c.h[:250], c.P[:250], c.t[:250])
    assert "no_unloading" in codes(load_only)
    sparse = clean(n_unload=8)
    assert "few_unloading_points" in codes(sparse)


def test_non_monotonic_depth_and_time():
    c = clean()
    h = c.h.copy()
    h[100:110] -= 0.1 * c.h.max()          # a 10 % fall-back during loading
    assert "non_monotonic" in codes(dataclasses.replace(c, h=h))
    t = c.t.copy()
    t[50] = t[49]
    assert "non_monotonic" in codes(dataclasses.replace(c, t=t))


def test_offsets_flagged():
    c = clean()
    assert "zero_load_offset" in codes(dataclasses.replace(c, P=c.P - 0.05 * c.P_max))
    assert "displacement_offset" in codes(dataclasses.replace(c, h=c.h + 0.1 * c.h_max))
    # a small shift stays under the 3 % threshold
    assert "displacement_offset" not in codes(dataclasses.replace(c, h=c.h + 0.005 * c.h_max))


def drifting(rate):
    """Unload to 10 % of P_max, hold 20 s there, unload to zero; h drifts at `rate`."""
    c = clean()
    unl = c.segment == UNLOAD
    P_unl, h_unl = c.P[unl], c.h[unl]
    k = int(np.argmin(np.abs(P_unl - 0.1 * c.P_max)))
    t_hold = c.t[unl][k] + np.linspace(0.1, 20.0, 100)
    t_rest = t_hold[-1] + (c.t[unl][k + 1:] - c.t[unl][k])
    t = np.concatenate([c.t[~unl], c.t[unl][:k + 1], t_hold, t_rest])
    h = np.concatenate([c.h[~unl], h_unl[:k + 1], np.full(100, h_unl[k]), h_unl[k + 1:]])
    P = np.concatenate([c.P[~unl], P_unl[:k + 1], np.full(100, P_unl[k]), P_unl[k + 1:]])
    return LoadDisplacementCurve(h + rate * t, P, t)


def test_hold_drift_measured_flagged_and_removed():
    rate = 0.05e-9                          # 0.05 nm/s over ~45 s: 2 % of h_max
    c = drifting(rate)
    assert "hold_drift" in codes(c)
    assert drift_rate(c) == pytest.approx(rate, rel=1e-9)   # exact linear drift
    assert "hold_drift" not in codes(c.drift_corrected(drift_rate(c)))
    assert "hold_drift" not in codes(drifting(0.0))


def test_frame_correction_subtracts_compliance_times_load():
    c = clean()
    corrected = dataclasses.replace(c, h=c.h + 2e-10 * c.P).frame_corrected(2e-10)
    np.testing.assert_allclose(corrected.h, c.h, atol=1e-20)
    with pytest.raises(InputError, match="frame compliance C_f"):
        c.frame_corrected(-1.0)


def test_bad_curves_rejected():
    with pytest.raises(InputError, match="differ in length"):
        LoadDisplacementCurve([0, 1, 2], [0, 1])
    with pytest.raises(InputError, match="segment labels"):
        LoadDisplacementCurve([0, 1], [0, 1], segment=["load", "pause"])


def test_text_reader_converts_units(tmp_path):
    f = tmp_path / "indent.csv"
    f.write_text("h [nm], P [uN], t [s]\n0, 0, 0\n10, 50, 1\n20, 200, 2\n15, 80, 3\n")
    (c,) = read_curves(f).values()
    np.testing.assert_allclose(c.h, [0, 10e-9, 20e-9, 15e-9])
    np.testing.assert_allclose(c.P, [0, 50e-6, 200e-6, 80e-6])
    np.testing.assert_allclose(c.t, [0, 1, 2, 3])
    g = tmp_path / "si.txt"
    g.write_text("depth load\n0 0\n1e-8 1e-4\n")       # no units: SI
    assert read_curves(g)["si"].P[1] == 1e-4
    bad = tmp_path / "bad.csv"
    bad.write_text("x [nm], P [uN]\n0, 0\n1, 1\n")
    with pytest.raises(InputError, match="no h column"):
        read_curves(bad)


def test_hdf5_round_trip(tmp_path):
    c = clean(noise=0.001, seed=2)
    path = tmp_path / "curves.h5"
    with h5py.File(path, "w") as f:
        write_curve_group(f.create_group("run/a"), c)
        write_curve_group(f.create_group("b"), c.frame_corrected(1e-10))
    curves = read_curves(path)
    assert set(curves) == {"run/a", "b"}
    back = curves["run/a"]
    np.testing.assert_array_equal(back.h, c.h)
    np.testing.assert_array_equal(back.segment, c.segment)
    assert str(back.indenter) == "berkovich" and back.meta["seed"] == 2
    assert curves["b"].meta["frame_compliance"] == 1e-10


def test_loading_curvature_is_the_kick_fit_of_the_loading_only():
    """Oracle: the synthetic loading is P = P_max (h/h_max)^2 exactly, so C = P_max/h_max^2
    (1e-12); the hold and unloading must not enter. With load noise, C against numpy's
    least squares on the same points (a second method) to 1e-12, and within 4 standard
    errors of the true C."""
    curve = clean()
    C_true = curve.P_max / curve.h_max**2
    assert curve.loading_curvature() == pytest.approx(C_true, rel=1e-12)
    assert curve.loading_curvature(from_fraction=0.5) == pytest.approx(C_true, rel=1e-12)
    noisy = clean(noise=0.01, seed=5)
    sel = noisy.segment == LOAD
    h, P = noisy.h[sel], noisy.P[sel]
    (C_lstsq,), *_ = np.linalg.lstsq((h**2)[:, None], P, rcond=None)
    assert noisy.loading_curvature() == pytest.approx(C_lstsq, rel=1e-12)
    stderr = 0.01 * noisy.P_max / np.sqrt(np.sum(h**4))
    assert abs(noisy.loading_curvature() - C_true) < 4 * stderr
    with pytest.raises(InputError, match="from_fraction"):
        curve.loading_curvature(from_fraction=1.0)
