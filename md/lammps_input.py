"""The last check of every LAMMPS input filmscale writes, and safe run-directory names.

Specs are validated word by word when they are loaded (`potentials.lammps_words`); this is
the second line: `check_input` reads a complete input the way LAMMPS will and refuses it unless
every line is a command filmscale itself generates, in the form it generates it. No line may
run a shell command, Python or another file (``shell``, ``python``, ``include``, ``jump``,
``plugin``, ``variable ... python/getenv/file``), expand a variable the input did not define,
continue onto the next line (``&``, triple quotes), write outside the run directory, start a
program (``dump movie``) or read a file through a decompressor. Comments are free text, which
LAMMPS ignores once a line can no longer continue. `write_input` checks before it writes and
`engine.run_input` checks again before LAMMPS reads the file, so every MD, elastic-constant
and particle input, fresh or resumed, passes here.
"""

from __future__ import annotations

import re
from pathlib import Path

from filmscale.core.errors import InputError
from filmscale.potentials.lammps_words import COMPRESSED, FORBIDDEN, check_name, shown

#: The commands filmscale generates; any other first word is refused.
COMMANDS = frozenset({
    "atom_modify", "atom_style", "boundary", "change_box", "comm_modify", "compute",
    "create_atoms", "create_box", "dimension", "dump", "dump_modify", "fix", "group",
    "lattice", "minimize", "neigh_modify", "neighbor", "newton", "pair_coeff", "pair_style",
    "print", "processors", "read_data", "read_restart", "region", "reset_timestep", "restart",
    "run", "set", "thermo", "thermo_modify", "thermo_style", "timestep", "unfix", "units",
    "variable", "velocity", "write_dump", "write_restart"})
#: The fix styles filmscale generates (``fix ID group STYLE ...``).
FIX_STYLES = frozenset({
    "addforce", "box/relax", "halt", "indent", "langevin", "nve", "print", "setforce",
    "smd/adjust_dt", "smd/integrate_tlsph", "smd/integrate_ulsph", "smd/setvel",
    "wall/region"})
#: Dump styles that only write text (``dump movie`` and ``image`` start external programs).
DUMP_STYLES = frozenset({"custom"})
#: Positions of the file arguments of the commands that name them (read or written).
FILE_ARGUMENTS = {"read_data": (1,), "read_restart": (1,), "write_restart": (1,),
                  "restart": (2, 3), "write_dump": (3,), "dump": (5,)}
#: A file in the run directory: relative, no ``..``, ``*`` for LAMMPS's step number.
RUN_FILE = re.compile(r"(?!.*(?:^|/)\.\.(?:/|$))[A-Za-z0-9_.*-]+(?:/[A-Za-z0-9_.*-]+)*")
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: What an immediate formula ``$(...)`` may hold: names, numbers, operators, a format.
FORMULA = re.compile(r"[A-Za-z0-9_.,:%+*/()\[\] <>=!-]*")
#: Printable ASCII: no control characters (NUL, CR, tab) and nothing LAMMPS maps from UTF-8.
_PRINTABLE = re.compile(r"[\x20-\x7e]*")
_WORDS = re.compile(r'"[^"]*"|\S+')


def _split_comment(line: str) -> tuple[str, bool]:
    """The command part of a line (before a ``#`` outside double quotes) and whether its
    quotes are balanced."""
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == "#" and not quoted:
            return line[:i], True
    return line, not quoted


def _check_dollars(command: str, defined: set[str]) -> str | None:
    """Why the ``$`` expansions of ``command`` are refused, or None: ``${name}`` only for a
    variable defined above, ``$(formula)`` only with a plain formula."""
    at = command.find("$")
    while at >= 0:
        rest = command[at + 1:]
        braced = re.match(r"\{([^}]*)\}", rest)
        if braced:
            if braced.group(1) not in defined:
                return f"${{{braced.group(1)}}} expands a variable the input does not define"
            end = braced.end()
        elif rest.startswith("("):
            depth, end = 0, 0
            for end, ch in enumerate(rest, start=1):
                depth += {"(": 1, ")": -1}.get(ch, 0)
                if depth == 0:
                    break
            if depth or not FORMULA.fullmatch(rest[1:end - 1]):
                return "a $(...) formula holds something other than names, numbers and " \
                       "operators"
        else:
            return "a '$' is not followed by {name} or (formula)"
        at = command.find("$", at + 1 + end)
    return None


def _line_problem(line: str, defined: set[str]) -> str | None:
    """Why ``line`` is refused, or None; records a ``variable`` it defines in ``defined``."""
    if not _PRINTABLE.fullmatch(line):
        return "it holds a control or non-ASCII character"
    if "&" in line or '"""' in line:
        return "it holds '&' or '\"\"\"', which join it with the next line"
    # a comment is inert once it can neither continue (& and triple quotes, above) nor
    # hold a newline: what follows is the command part only
    command, balanced = _split_comment(line)
    if not balanced:
        return "its double quotes are not balanced"
    words = _WORDS.findall(command)
    if not words:
        return None
    # a word or a style's first part (python/invoke); path components are not words
    if any(w.lower().split("/")[0] in FORBIDDEN for w in words):
        return f"it names one of {', '.join(sorted(FORBIDDEN))}"
    name = words[0]
    if name not in COMMANDS:
        return f"{name!r} is not a command filmscale writes"
    if "'" in command:
        return "it holds a single quote"
    if any(w.lower().rstrip('"').endswith(COMPRESSED) for w in words):
        return "it names a compressed file, which LAMMPS may read through a shell"
    if name == "variable":
        if len(words) < 4 or not IDENTIFIER.fullmatch(words[1]) or \
                words[2] not in ("equal", "atom"):
            return "a variable must be 'variable NAME equal|atom FORMULA'"
    style_at = {"fix": 3, "dump": 3, "write_dump": 2}.get(name)
    if style_at is not None:
        style = words[style_at] if len(words) > style_at else None
        if style not in (FIX_STYLES if name == "fix" else DUMP_STYLES):
            return f"{name} style {style!r} is not one filmscale writes"
    files = [words[i + 1] for i, w in enumerate(words[:-1]) if w in ("file", "append")]
    files += [words[i] for i in FILE_ARGUMENTS.get(name, ()) if i < len(words)]
    for file in files:
        if not RUN_FILE.fullmatch(file):
            return f"file {file!r} is not a plain name inside the run directory"
    problem = _check_dollars(command, defined)
    if problem is None and name == "variable":
        defined.add(words[1])
    return problem


def check_input(text: str, source: str = "LAMMPS input") -> str:
    """Return ``text`` if every line is a command filmscale generates (see the module
    docstring), else raise `InputError` naming ``source``, the line and the reason."""
    defined: set[str] = set()
    for number, line in enumerate(text.split("\n"), start=1):
        problem = _line_problem(line, defined)
        if problem is not None:
            raise InputError(f"{source} line {number} = {shown(line)} is refused: {problem}")
    return text


def write_input(path: Path, text: str) -> None:
    """Write the input ``text`` to ``path`` after `check_input`: a refused input is never
    written."""
    path.write_text(check_input(text, path.name))


def run_dir_for(parent: Path | str, name: str) -> Path:
    """The run directory ``parent/name`` of a spec called ``name``: a plain name (no
    separator, never ``.`` or ``..``) whose resolved folder stays under ``parent``."""
    check_name("name", name)
    parent = Path(parent)
    folder = parent / name
    if not folder.resolve().is_relative_to(parent.resolve()):
        raise InputError(f"run directory {folder} resolves to {folder.resolve()}, outside "
                         f"{parent.resolve()}")
    return folder
