"""The test suite's own layout: what several test modules share lives in tests/helpers (and
tests/conftest.py for fixtures), so no module under tests/ imports a test module (test_*.py),
and the helpers import none either: a test module imported by another is loaded twice (under
pytest's name and the importer's), and the helpers it lends out move whenever its tests do."""

import ast
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
HELPERS = TESTS / "helpers"
#: the test modules' own names, as pytest imports them (a folder without __init__.py)
TEST_MODULES = {p.stem for p in TESTS.rglob("test_*.py")}


def _is_test_module(dotted: str) -> bool:
    """Whether the dotted name (leading dots for a relative import) names a test module, or
    something inside one: a ``test_*`` part under the package ``tests``, a relative one, or a
    test module's own name imported as top-level."""
    parts = dotted.lstrip(".").split(".")
    if not any(p.startswith("test_") for p in parts):
        return False
    return dotted.startswith(".") or parts[0] == "tests" or parts[0] in TEST_MODULES


def imported_test_modules(source: str) -> list[tuple[int, str]]:
    """(line, dotted name) of every import of a test module in ``source``, at any depth
    (imports inside functions count too)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names if _is_test_module(a.name)]
        elif isinstance(node, ast.ImportFrom):
            base = "." * node.level + (node.module or "")
            if _is_test_module(base):                   # from <test module> import name
                found.append((node.lineno, base))
                continue
            sep = "." if node.module else ""             # from <package> import <module>
            found += [(node.lineno, base + sep + a.name) for a in node.names
                      if _is_test_module(base + sep + a.name)]
    return found


def _offenders(files) -> list[str]:
    return [f"{path.relative_to(TESTS.parent)}:{line} imports {name}"
            for path in files for line, name in imported_test_modules(path.read_text())]


#: (source, what the check reports); a made-up folder ``sub``, so that no grep for the real
#: cross-imports finds these lines
@pytest.mark.parametrize("source, name", [
    ("from tests.sub.test_mod import BASE", "tests.sub.test_mod"),
    ("from tests.sub import test_mod as tm", "tests.sub.test_mod"),
    ("import tests.sub.test_mod", "tests.sub.test_mod"),
    ("from .test_mod import MINIMAL", ".test_mod"),
    ("from . import test_mod", ".test_mod"),
    ("import test_test_layout", "test_test_layout"),         # as pytest names this module
    ("def f():\n    from tests.sub.test_mod import fill", "tests.sub.test_mod"),
], ids=["from-module-import-name", "from-package-import-module", "import-dotted",
        "relative-from-module", "relative-from-package", "top-level-basename", "in-a-function"])
def test_the_check_finds_each_form_of_a_test_module_import(source, name):
    assert name in [n for _, n in imported_test_modules(source)]


@pytest.mark.parametrize("source", [
    "from tests.helpers.scenes import BASE",
    "from tests.helpers import curves as tc",
    "import pytest",
    "from filmscale.workflows.cli import main",
])
def test_the_check_passes_helper_and_package_imports(source):
    assert imported_test_modules(source) == []


def test_no_module_under_tests_imports_a_test_module():
    offenders = _offenders(sorted(TESTS.rglob("*.py")))
    assert offenders == [], "shared helpers belong in tests/helpers:\n" + "\n".join(offenders)


def test_the_helpers_import_no_test_module_and_hold_none():
    modules = sorted(HELPERS.rglob("*.py"))
    assert HELPERS / "__init__.py" in modules
    assert [p.name for p in modules if p.name.startswith("test_")] == []
    offenders = _offenders(modules)
    assert offenders == [], "a helper imports a test module:\n" + "\n".join(offenders)
