"""The README's code cannot rot: every ```python block runs as written, each on its own in a
fresh namespace and an empty folder (a reader pastes one block, not the page), and every
command the README and docs/*.md name exists: each ``filmscale`` subcommand and each
``--option`` of their shell blocks and of their inline code (`filmscale report --figure`) in
the command-line parser, each ``make`` target in the Makefile."""

import argparse
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```(\w*)\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
PYTHON = [code for lang, code in BLOCKS if lang == "python"]
SHELL = [code for lang, code in BLOCKS if lang in ("", "bash", "sh", "console")]


def test_the_readme_has_the_blocks_this_test_reads():
    assert len(PYTHON) >= 3 and any("filmscale impact-map" in code for code in SHELL)


@pytest.mark.parametrize("code", PYTHON, ids=[f"python-{i}" for i in range(len(PYTHON))])
def test_python_block_runs_as_written(code, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {"__name__": "__readme__"})
    assert capsys.readouterr().out or any(tmp_path.iterdir())    # it showed or wrote something


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    return next((a.choices for a in parser._actions
                 if isinstance(a, argparse._SubParsersAction)), {})


PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _shell_commands(text: str) -> list[tuple[list[str], set[str]]]:
    """(subcommand words, options) of each filmscale command line in the shell blocks; an
    option on a continuation line belongs to the command above it."""
    found = []
    for lang, code in re.findall(r"```(\w*)\n(.*?)```", text, re.S):
        if lang not in ("", "bash", "sh", "console"):
            continue
        current = None                      # a block's continuation lines are its own
        for line in code.splitlines():
            words = line.split()
            if words[:1] == ["filmscale"]:
                current = (words[1:], set())
                found.append(current)
            elif current is None or not line.startswith(" "):
                continue
            # a quoted value is another program's (--sbatch='--mail-type=END')
            current[1].update(re.findall(r"(--[\w-]+)", re.sub(r"'[^']*'", "", line)))
    return found


def _inline_commands(text: str) -> list[tuple[list[str], set[str]]]:
    """(subcommand words, options) of each inline code span that starts with filmscale."""
    prose = re.sub(r"```.*?```", "", text, flags=re.S).replace("\\|", "|")  # table pipes
    return [(span.split()[1:], set(re.findall(r"(--[\w-]+)", span)))
            for span in re.findall(r"`(filmscale [^`]+)`", prose)]


def _commands():
    return [(page.name, words, options) for page in PAGES
            for words, options in (_shell_commands(page.read_text())
                                   + _inline_commands(page.read_text()))]


COMMANDS = _commands()


@pytest.mark.parametrize("page, words, options", COMMANDS,
                         ids=[f"{p}: {' '.join(w[:2])}" for p, w, _ in COMMANDS])
def test_filmscale_command_and_options_exist(page, words, options):
    from filmscale.workflows.cli import build_parser
    parsers = [build_parser()]
    # `filmscale --version`: options of the top level
    rest = [] if words and words[0].startswith("--") else list(words)
    while (sub := _subparsers(parsers[0])) and rest:
        names = rest.pop(0).split("|")              # "plan|run": each must exist
        for name in names:
            assert name in sub, f"filmscale {name}: no such command ({page})"
        parsers = [sub[name] for name in names]
    choices = next((a.choices for a in parsers[0]._actions
                    if not a.option_strings and a.choices), None)
    if choices and rest:                            # "potentials list | show NAME | verify"
        named = [w for w in " ".join(rest).replace("|", " ").split() if w.islower()]
        assert set(named) <= set(choices), f"{page} names {named}, the parser {choices}"
    # options of alternatives ("sweep plan|run [--jobs N]") belong to one of them
    known = {s for parser in parsers for a in parser._actions for s in a.option_strings}
    assert options <= known, (f"{page}: filmscale {' '.join(words[:2])}: "
                              f"{options - known} unknown")


def test_make_targets_exist():
    makefile = (ROOT / "Makefile").read_text()
    targets = set(re.findall(r"^([\w-]+):", makefile, re.M))
    wanted = {line.split()[1] for code in SHELL for line in code.splitlines()
              if line.startswith("make ")}
    assert wanted and wanted <= targets
