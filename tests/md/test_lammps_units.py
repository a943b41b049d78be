"""Metal-unit conversions against the SI definitions (exact or CODATA 2018)."""

import numpy as np
import pytest

from filmscale.md.lammps_units import METAL, si_to_lammps, lammps_to_si


def test_force_and_pressure_factors_match_definitions():
    # 1 eV/A = 1.602176634e-19 J / 1e-10 m, exact since the 2019 SI redefinition
    assert lammps_to_si(1.0, "force") == pytest.approx(1.602176634e-9, rel=1e-15)
    assert lammps_to_si(1.0, "pressure") == 1e5                       # 1 bar
    assert lammps_to_si(10.0, "indent_constant") == pytest.approx(1.602176634e12, rel=1e-15)
    assert lammps_to_si(1.0, "velocity") == pytest.approx(100.0)      # 1 A/ps = 100 m/s


@pytest.mark.parametrize("dimension", sorted(METAL))
def test_round_trip(dimension):
    values = np.array([0.0, 1.5e-3, 2.0, 7.25e4])
    np.testing.assert_allclose(si_to_lammps(lammps_to_si(values, dimension), dimension), values,
                               rtol=1e-15, atol=0)
    assert si_to_lammps(lammps_to_si(3.0, dimension), dimension) == pytest.approx(3.0, rel=1e-15)


def test_unknown_dimension_is_named():
    with pytest.raises(KeyError, match="furlong"):
        lammps_to_si(1.0, "furlong")
