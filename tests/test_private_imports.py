"""No module reaches into another module's private names.

A ``_name`` (one leading underscore) is private to the module that defines it. A second module
that imports it (``from filmscale.x import _name``, ``from .x import _name``) or reads it off
the module (``import filmscale.x as m; m._name``) has found a shared helper in disguise: give
it a public name that says what it does, or move it into a module of its own. Public here
means importable without an underscore, not part of a package's API table (`_WHERE`).

The scan covers the package (the repository root), not tests or benchmarks, which may reach
into internals to check them.
"""

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = "filmscale"
#: top-level folders that are not part of the package
EXCLUDED = {".venv", "tests", "benchmarks"}

def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _package_files() -> dict[str, Path]:
    """Module name -> file of every module of the package."""
    modules = {}
    for path in sorted(ROOT.rglob("*.py")):
        parts = path.relative_to(ROOT).parts
        if parts[0] in EXCLUDED or any(p.startswith(".") for p in parts):
            continue
        names = [PACKAGE, *parts[:-1]]
        if parts[-1] != "__init__.py":
            names.append(path.stem)
        modules[".".join(names)] = path
    return modules


def _absolute(module: str, path: Path, node: ast.ImportFrom) -> str:
    """The absolute name of the module ``node`` imports from, inside ``module`` (at ``path``)."""
    if not node.level:
        return node.module or ""
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    base = package[:len(package) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _private_uses(module: str, path: Path, modules) -> list[tuple[str, str, str, int]]:
    """(importer, defining module, name, line) of each private name of another module of the
    package that ``module`` imports or reads as a module attribute."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    importer = path.relative_to(ROOT).as_posix()
    found = []
    aliases = {}        # local name (dotted) -> the package module it is bound to
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            source = _absolute(module, path, node)
            if source.split(".")[0] != PACKAGE:
                continue
            for alias in node.names:
                if f"{source}.{alias.name}" in modules:
                    aliases[alias.asname or alias.name] = f"{source}.{alias.name}"
                if _is_private(alias.name) and source != module:
                    found.append((importer, source, alias.name, node.lineno))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in modules:
                    aliases[alias.asname or alias.name] = alias.name
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _is_private(node.attr):
            try:
                owner = aliases.get(ast.unparse(node.value))
            except (ValueError, TypeError):
                owner = None
            if owner is not None and owner != module:
                found.append((importer, owner, node.attr, node.lineno))
    return found


def _all_private_uses() -> list[tuple[str, str, str, int]]:
    modules = _package_files()
    return [use for module, path in modules.items()
            for use in _private_uses(module, path, modules)]


def test_no_module_imports_another_modules_private_names():
    uses = _all_private_uses()
    assert not uses, ("private names used outside the module that defines them (make each "
                      "public under a name that says what it does, or move it):\n"
                      + "\n".join(f"  {path}:{line}: {name} of {source}"
                                  for path, source, name, line in uses))


def test_the_scan_finds_each_kind_of_private_use(tmp_path, monkeypatch):
    # the scan itself: a relative and an absolute import, a module attribute, and the
    # module's own names (not counted)
    pkg = tmp_path / "sub"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("_x = 1\n_y = 2\nz = _x\n")
    (pkg / "b.py").write_text("from .a import _x\nfrom filmscale.sub.a import _y, z\n"
                              "from filmscale.sub import a\nimport filmscale.sub.a as m\n"
                              "w = a._x + m._y + a.z + a.__name__\n")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    uses = sorted(u[:3] for u in _all_private_uses())
    assert uses == [("sub/b.py", "filmscale.sub.a", "_x")] * 2 \
        + [("sub/b.py", "filmscale.sub.a", "_y")] * 2
