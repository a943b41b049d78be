"""docs/architecture.md: "No module is longer than 700 lines; a module that grows past that is
split along a seam of the physics". Counted over the package's own modules."""

from pathlib import Path

import filmscale

LIMIT = 700


def test_no_module_is_longer_than_700_lines():
    root = Path(filmscale.__file__).resolve().parent
    parts = ("core", "continuum", "md", "potentials", "workflows")
    long = {str(p.relative_to(root)): n for part in parts for p in (root / part).rglob("*.py")
            if (n := len(p.read_text().splitlines())) > LIMIT}
    assert long == {}
