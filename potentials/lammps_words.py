"""Strict grammars for the words filmscale writes into a LAMMPS input.

LAMMPS reads its input line by line and expands ``$`` variables, continues lines ending in
``&``, joins lines inside triple quotes and treats ``#`` as a comment, and an input can run
shell commands (``shell``), Python (``python``) or other files (``include``, ``jump``). A word
from a spec that carried a newline, a quote or one of those marks could therefore add commands.
Each function here accepts one kind of word (a name, an element, ``pair_style`` arguments, a
``pair_coeff`` template, a file path) in a form that cannot do that, or raises `InputError`
naming the field, its value (``repr``, shortened) and what is allowed. Numbers reach inputs
only as finite floats checked in range and written by Python. `md.lammps_input` checks the
whole input again before LAMMPS reads it.
"""

from __future__ import annotations

import re

from filmscale.core.errors import InputError

#: Names of runs and potentials: they become folder names and appear in input comments.
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
#: A keyword argument of a style (``shift``, ``nodensity``).
KEYWORD = re.compile(r"[a-z][a-z0-9_]*")
#: A chemical element symbol.
ELEMENT = re.compile(r"[A-Z][a-z]?")
#: A plain decimal number as Python or a person writes it.
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
#: An atom type or a range of them in ``pair_coeff`` (``*``, ``1``, ``1*2``, ``*3``).
TYPES = re.compile(r"\d+|\d*\*\d*")
#: Characters of a file path LAMMPS may be given: no quote, ``$``, ``#``, ``&``, ``;``,
#: ``|``, backtick, bracket or control character; blanks only as plain spaces (quoted).
PATH_CHARACTERS = re.compile(r"[A-Za-z0-9 ._+,=@%:~/-]+")
#: Endings for which some LAMMPS versions read a file through a shell decompressor (popen).
COMPRESSED = (".gz", ".bz2", ".zst", ".xz", ".lzma", ".lz4")
#: Words that run commands, code or other files in a LAMMPS input (as commands, styles or
#: keywords).
FORBIDDEN = frozenset({"shell", "python", "include", "jump", "label", "next", "plugin",
                       "getenv", "atomfile"})
MAX_SHOWN = 60       # characters of a refused value shown in the message


def shown(value) -> str:
    """``repr(value)`` cut to a readable length (a refused value may be megabytes)."""
    text = repr(value)
    return text if len(text) <= MAX_SHOWN else f"{text[:MAX_SHOWN - 3]}..."


def refuse(field: str, value, allowed: str, error: type[InputError] = InputError):
    """Raise ``error``: one line naming the field, its value and what is allowed."""
    raise error(f"{field} = {shown(value)} is refused: {allowed}")


def _string(field: str, value, error: type[InputError]) -> str:
    if not isinstance(value, str):
        refuse(field, value, "it must be a string", error)
    return value


def check_name(field: str, value, error: type[InputError] = InputError) -> str:
    """A run or potential name: letters, digits, ``.``, ``_`` and ``-``, starting with a
    letter or digit (so never ``.``, ``..`` or a path), at most 100 characters."""
    if not NAME.fullmatch(_string(field, value, error)):
        refuse(field, value, "a name is 1-100 letters, digits, '.', '_' or '-', starting "
                             "with a letter or digit", error)
    return value


def check_element(field: str, value, error: type[InputError] = InputError) -> str:
    """A chemical element symbol (``Cu``, ``C``)."""
    if not ELEMENT.fullmatch(_string(field, value, error)):
        refuse(field, value, "an element symbol is one capital letter and at most one small "
                             "letter", error)
    return value


def check_pair_style(field: str, value, styles, error: type[InputError] = InputError) -> str:
    """``pair_style`` arguments: one of ``styles`` followed by numbers and keywords."""
    text = _string(field, value, error)
    words = text.split(" ")
    allowed = (f"a style ({', '.join(sorted(styles))}) followed by numbers or keywords, "
               "separated by single spaces")
    if words[0] not in styles or not all(
            NUMBER.fullmatch(w) or (KEYWORD.fullmatch(w) and w not in FORBIDDEN)
            for w in words[1:]):
        refuse(field, value, allowed, error)
    return text


def check_pair_coeff(field: str, value, error: type[InputError] = InputError) -> str:
    """A ``pair_coeff`` template: two atom-type ranges, then ``{file}`` once, ``{types}`` at
    most once, element symbols and numbers, separated by single spaces."""
    words = _string(field, value, error).split(" ")
    ok = (len(words) >= 3 and all(TYPES.fullmatch(w) for w in words[:2])
          and words.count("{file}") == 1 and words.count("{types}") <= 1
          and all(w in ("{file}", "{types}") or ELEMENT.fullmatch(w) or NUMBER.fullmatch(w)
                  for w in words[2:]))
    if not ok:
        refuse(field, value, "two atom types ('*', '1', '1*2'), then {file} once, {types} at "
                             "most once, element symbols and numbers, separated by single "
                             "spaces", error)
    return value


def check_path_word(field: str, path, error: type[InputError] = InputError) -> str:
    """A file path as one LAMMPS word: only letters, digits, spaces and ``._+,=@%:~/-``,
    no compressed-file ending; quoted when it holds a space."""
    text = str(path)
    if not PATH_CHARACTERS.fullmatch(text) or len(text) > 4096:
        refuse(field, text, "a path of letters, digits, spaces and ._+,=@%:~/- only (move "
                            "the file to such a path)", error)
    if text.lower().endswith(COMPRESSED):
        refuse(field, text, f"an uncompressed file (not {', '.join(COMPRESSED)})", error)
    return f'"{text}"' if " " in text else text
