"""The public API: each package's __all__ (the names of its lazy table, where it has one)
resolves, and docs/api.md documents exactly those names."""

import importlib
import re
from pathlib import Path

import pytest

import filmscale

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("filmscale.core", "filmscale.continuum", "filmscale.continuum.indentation",
            "filmscale.continuum.indentation.reverse", "filmscale.continuum.calibration",
            "filmscale.continuum.contact", "filmscale.md", "filmscale.potentials",
            "filmscale.workflows")


def _documented() -> dict[str, list[str]]:
    sections = re.split(r"^## `([\w.]+)`$", (ROOT / "docs" / "api.md").read_text(), flags=re.M)
    return {name: re.findall(r"^\| `(\w+)` \|", body, flags=re.M)
            for name, body in zip(sections[1::2], sections[2::2])}


@pytest.mark.parametrize("package", PACKAGES)
def test_public_names_resolve_and_are_documented(package):
    module = importlib.import_module(package)
    names = module.__all__
    assert len(names) >= 8, f"{package} exports {len(names)} names"
    assert len(set(names)) == len(names)
    # every name the package resolves lazily is public, and nothing else
    assert set(names) == set(getattr(module, "_WHERE", names))
    missing = [n for n in names if getattr(module, n, None) is None]
    assert not missing
    assert sorted(_documented()[package]) == sorted(names)


def test_the_api_page_documents_no_other_package():
    assert set(_documented()) == set(PACKAGES)


def test_version_is_the_installed_distribution_version():
    from importlib import metadata
    assert filmscale.__version__ == metadata.version("filmscale")
