"""No import cycle between the package's modules.

The graph is that of the imports a module runs when it is loaded (its top-level statements,
`if TYPE_CHECKING:` blocks left out); an import inside a function runs on first use, where it
is the package's deliberate way to defer heavy modules (docs/architecture.md), and is not an
edge. The package's `__init__` modules resolve names lazily (`core.lazy`) and import nothing
of their sub-modules at load time. The layer contracts (`tests/test_layering.py`) hold the
direction between packages; this test holds it between any two modules.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXCLUDED = {".venv", "tests", "benchmarks", "examples", "docs"}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(["filmscale", *parts])


def _load_time_imports(tree: ast.Module, name: str, is_package: bool) -> set[str]:
    """The modules imported by the top-level statements of a module."""
    package = name if is_package else name.rsplit(".", 1)[0]
    found = set()

    def visit(statements):
        for node in statements:
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
                continue
            if isinstance(node, (ast.If, ast.Try, ast.With)):
                visit(node.body)
                for extra in (getattr(node, "orelse", []), getattr(node, "finalbody", [])):
                    visit(extra)
                for handler in getattr(node, "handlers", []):
                    visit(handler.body)
            elif isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(anchor + ([base] if base else []))
                found.add(base)
                found.update(f"{base}.{alias.name}" for alias in node.names)
    visit(tree.body)
    return found


def _graph() -> dict[str, set[str]]:
    files = {}
    for path in ROOT.rglob("*.py"):
        parts = path.relative_to(ROOT).parts
        if parts[0] in EXCLUDED or any(p.startswith(".") for p in parts):
            continue
        files[_module_name(path)] = path
    graph = {}
    for name, path in files.items():
        imports = _load_time_imports(ast.parse(path.read_text()), name,
                                     path.name == "__init__.py")
        graph[name] = {m for m in imports if m in files and m != name}
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the graph, or None (iterative depth-first search)."""
    state = {}
    for start in sorted(graph):
        if state.get(start):
            continue
        stack = [(start, iter(sorted(graph[start])))]
        path = [start]
        state[start] = 1
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                state[node] = 2
                stack.pop()
                path.pop()
            elif state.get(child) == 1:
                return path[path.index(child):] + [child]
            elif not state.get(child):
                state[child] = 1
                path.append(child)
                stack.append((child, iter(sorted(graph[child]))))
    return None


def test_no_module_imports_itself_back_at_load_time():
    cycle = _cycle(_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_the_cycle_finder_finds_one():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None
