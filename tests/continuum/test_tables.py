"""Curves and impact histories as pandas and xarray objects for notebooks: the same numbers,
point by point, with their units and segment names (oracle: the objects' own arrays)."""

import numpy as np
import pytest

from filmscale.continuum.contact.impact import ImpactModel
from filmscale.continuum.contact.laws import contact_law
from filmscale.continuum.indentation import parse_tip, synthetic_curve
from filmscale.continuum.materials import ElasticPlastic

pytest.importorskip("xarray")


def test_a_curve_as_a_table_and_a_dataset():
    curve = synthetic_curve(150e9, 10e9, parse_tip("berkovich"), h_c=200e-9, n_load=20,
                            n_hold=5, n_unload=20)
    df = curve.to_dataframe()
    assert list(df.columns) == ["h", "P", "t", "segment"] and len(df) == len(curve)
    np.testing.assert_array_equal(df["h"], curve.h)
    np.testing.assert_array_equal(df["t"], curve.t)
    assert df["segment"].value_counts().to_dict() == {"load": 20, "hold": 5, "unload": 20}
    assert df.attrs["units"]["P"] == "N" and df.attrs["indenter"] == "berkovich"
    np.testing.assert_array_equal(df[df["segment"] == "unload"]["P"], curve.P[curve.segment == 2])
    ds = curve.to_xarray()
    assert ds["h"].attrs["units"] == "m" and ds["t"].attrs["units"] == "s"
    np.testing.assert_array_equal(ds["P"].where(ds["segment"] == "hold", drop=True),
                                  curve.P[curve.segment == 1])


def test_an_impact_history_as_a_table_indexed_by_time():
    model = ImpactModel(ElasticPlastic(E=200e9, nu=0.3, sigma_y=1.5e9), contact_law("hertz"))
    hist = model.history(0.05, 1e-3, 3.27e-5)
    df = hist.to_dataframe()
    assert df.index.name == "time" and len(df) == hist.time.size
    np.testing.assert_array_equal(df["force"], hist.force)
    np.testing.assert_array_equal(df.index, hist.time)
    assert df["delta"].max() == pytest.approx(hist.result.delta_max, rel=1e-3)
    assert df.attrs["units"]["force"] == "N"
