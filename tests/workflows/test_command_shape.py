"""The shape of the command line's code (docs/architecture.md, "a command"): each command
family is a module that adds its own sub-parsers (``add_arguments``) and that the parser
assembles from one table (`cli.COMMANDS`); no function of workflows/ grows past 80 lines, and
no command body (``cmd_*``) past a cyclomatic complexity of 15, so that each reads as the
steps it takes (read its inputs, choose its options, run, print)."""

import ast
from pathlib import Path

import pytest

import filmscale

WORKFLOWS = Path(filmscale.__file__).resolve().parent / "workflows"
MAX_LINES = 80
MAX_COMPLEXITY = 15
#: what adds one to the cyclomatic complexity (a BoolOp adds one per operand beyond the first)
BRANCHES = (ast.If, ast.For, ast.AsyncFor, ast.While, ast.IfExp, ast.ExceptHandler, ast.With,
            ast.AsyncWith, ast.Assert, ast.comprehension, ast.match_case)


def complexity(function: ast.AST) -> int:
    """1 + each branch, loop, conditional expression, handler, with, assert, comprehension
    and match case in ``function`` (the functions and lambdas inside it included) + each
    ``and``/``or`` beyond the first operand."""
    count = 1
    for node in ast.walk(function):
        if isinstance(node, BRANCHES):
            count += 1
        elif isinstance(node, ast.BoolOp):
            count += len(node.values) - 1
    return count


def _functions():
    """(module, name, node) of every function in workflows/, methods and nested ones too."""
    for path in sorted(WORKFLOWS.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield path.name, node.name, node


FUNCTIONS = list(_functions())


def test_the_tree_has_the_functions_this_test_reads():
    names = {(module, name) for module, name, _ in FUNCTIONS}
    assert {("cli.py", "build_parser"), ("cli.py", "main"),
            ("indent_cli.py", "cmd_indent_analyze")} <= names
    assert sum(name.startswith("cmd_") for _, name, _ in FUNCTIONS) >= 10


def test_the_complexity_count():
    code = ("def f(a, b):\n"
            "    if a and b or a:\n"                      # if 1, and/or 2
            "        return [x for x in a if x]\n"        # comprehension 1
            "    with open(b) as f:\n"                    # with 1
            "        return 1 if f else 2\n")             # ifexp 1
    assert complexity(ast.parse(code).body[0]) == 7


def test_no_function_in_workflows_is_longer_than_80_lines():
    long = {f"{module}:{name}": node.end_lineno - node.lineno + 1
            for module, name, node in FUNCTIONS
            if node.end_lineno - node.lineno + 1 > MAX_LINES}
    assert long == {}


def test_no_command_body_is_more_complex_than_15():
    complex_ = {f"{module}:{name}": complexity(node) for module, name, node in FUNCTIONS
                if name.startswith("cmd_") and complexity(node) > MAX_COMPLEXITY}
    assert complex_ == {}


def _command_families() -> list[str]:
    """The module names of `cli.COMMANDS`, read from cli.py."""
    tree = ast.parse((WORKFLOWS / "cli.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "COMMANDS" for t in node.targets):
            assert isinstance(node.value, ast.Tuple)
            return [element.id for element in node.value.elts]
    raise AssertionError("cli.py has no COMMANDS table")


@pytest.mark.parametrize("family", _command_families())
def test_each_command_family_adds_its_own_arguments(family):
    tree = ast.parse((WORKFLOWS / f"{family}.py").read_text(encoding="utf-8"))
    top = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
    assert "add_arguments" in top, f"workflows/{family}.py has no add_arguments(subparsers)"


def test_the_parser_is_assembled_from_the_table_in_its_order():
    """Every family of COMMANDS is what build_parser adds, in the order of --help."""
    from filmscale.workflows import cli

    assert [m.__name__.rsplit(".", 1)[1] for m in cli.COMMANDS] == _command_families()
    sub = next(a for a in cli.build_parser()._actions if a.dest == "command")
    assert list(sub.choices) == ["impact", "impact-map", "slide", "slide-map", "indent",
                                 "calibrate", "md",
                                 "potentials", "particles", "plan", "run", "sweep", "cancel",
                                 "status", "report"]
