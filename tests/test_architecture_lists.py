"""docs/architecture.md names every module of the package in its module tables, so that the
page a contributor reads first matches the tree."""

import re
from pathlib import Path

import filmscale

ROOT = Path(filmscale.__file__).resolve().parent


def test_every_module_is_named_in_the_architecture_page():
    page = (ROOT / "docs" / "architecture.md").read_text()
    tables = "\n".join(line for line in page.splitlines() if line.startswith("| "))
    named = set(re.findall(r"`([a-z_0-9]+)`", tables))
    modules = {p.stem for part in ("core", "continuum", "md", "potentials", "workflows")
               for p in (ROOT / part).rglob("*.py") if p.name != "__init__.py"}
    assert sorted(modules - named) == []
