"""The hostile-input suite, round two (issue 31): unit strings that lie, special files as
inputs, archive bombs, codecs that are not text encodings, non-finite map axes. Each case
asserts the outcome written beside it: exit status 2, one line on stderr without a traceback
naming the field, option or file (and what was wrong), and no file of the work folder
changed. Never exit 0 with a wrong value. Cases run in-process under an alarm, so a reader
that waits on a pipe fails the case instead of hanging the suite."""

import hashlib
import os
import signal
import stat
import zipfile
from pathlib import Path

import numpy as np
import pytest

from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.tips import berkovich
from tests.helpers.cli import run_main
from tests.helpers.curves import sphere_curve_file
from tests.helpers.scenes import MINIMAL, SCENE

#: numbers that lie: a decimal comma, juxtaposed numbers, two decimal points, thousands
#: separators in three styles, a digit group mark, a number after the unit, broken exponents
LIES = ("10,5", "10 5", "1.6.1", "1,234.5", "1.234,5", "1_0", "1'000", "2.5e", "1e5.5")

#: quantity options of `impact` with a unit of their kind and a valid magnitude
OPTIONS = (("--radius", "um"), ("--velocity", "m/s"), ("--mass", "mg"))

#: scene keys (as written in MINIMAL) with a unit of their kind
KEYS = (("radius = 10e-6", "radius", "um", "impactor.radius"),
        ("mass = 1.6e-6", "mass", "mg", "impactor.mass"),
        ("velocity = 0.2", "velocity", "m/s", "impactor.velocity"),
        ("E = 90e9", "E", "GPa", "E"),
        ("sigma_y = 2.4e9", "sigma_y", "GPa", "sigma_y"))

NOT_TEXT = ("rot13", "zlib_codec", "base64_codec", "hex_codec", "bz2_codec", "uu_codec",
            "quopri_codec", "no-such-encoding")


def _cases():
    cases = []
    for flag, unit in OPTIONS:
        for lie in LIES:
            cases.append((f"option {flag} {lie}", ["impact", "scene.toml", flag,
                                                     f"{lie} {unit}"], flag))
        cases.append((f"option {flag} number after unit",
                      ["impact", "scene.toml", flag, f"10 {unit} 5"], flag))
    for i, (_, _, _, name) in enumerate(KEYS):
        for j, lie in enumerate(LIES[:6]):
            cases.append((f"scene {name} {lie}", f"plan lie_{i}_{j}.toml", name))
    for command in ("run", "plan", "impact", "impact-map"):
        cases.append((f"fifo scene {command}", f"{command} fifo.toml", "not a regular file"))
    cases += [
        ("fifo profile table", "impact fifo_profile.toml", "not a regular file"),
        ("fifo report", "report fifo.h5", "not a regular file"),
        ("fifo curve table analyze", "indent analyze fifo.csv --tip berkovich",
         "not a regular file"),
        ("fifo workbook analyze", "indent analyze fifo.xlsx --tip berkovich",
         "not a regular file"),
        ("fifo curve calibrate", "calibrate fifo.csv --tip sphere:5um", "not a regular file"),
        ("fifo hdf5 calibrate", "calibrate fifo.h5 --tip sphere:5um", "not a regular file"),
        ("fifo area file", "indent analyze curves --tip berkovich --area-file fifo.toml",
         "not a regular file"),
        ("fifo reader options", "indent analyze curves --tip berkovich --reader fifo.toml",
         "not a regular file"),
        ("fifo sweep", "sweep run fifo.toml --store s", "not a regular file"),
        ("fifo md spec", "md indent fifo.toml --out md_out", "not a regular file"),
        ("fifo particle spec", "particles indent fifo.toml --out p_out",
         "not a regular file"),
        ("folder as scene", "plan curves", "not a regular file"),
        ("zip bomb analyze", "indent analyze bomb.xlsx --tip berkovich", "bomb.xlsx"),
        ("zip bomb calibrate", "calibrate bomb.xlsx --tip sphere:5um", "bomb.xlsx"),
        ("sparse workbook analyze", "indent analyze sparse.xlsx --tip berkovich",
         "sparse.xlsx"),
        ("sparse workbook calibrate", "calibrate sparse.xlsx --tip sphere:5um",
         "sparse.xlsx"),
        ("thousands in a comma table", "calibrate thousands.csv --tip sphere:5um",
         "thousands separators"),
    ]
    for enc in NOT_TEXT:
        cases.append((f"encoding {enc}",
                      f"indent analyze curves --tip berkovich --reader enc_{enc}.toml", enc))
    for axis in ("velocity", "radius"):
        for k, special in enumerate(("nan", "inf", "-inf")):
            for command in ("plan", "impact-map"):
                cases.append((f"map {axis} {special} {command}",
                              f"{command} map_{axis}_{k}.toml", f"map.{axis}"))
    return cases


CASES = _cases()
#: cases of `indent analyze` on one bad file: the batch reports it and goes on
BATCH = ("zip bomb analyze", "sparse workbook analyze")


def _bomb(path: Path, megabytes: int = 300) -> None:
    """A small .xlsx whose one sheet inflates to ``megabytes`` MB of repeated rows."""
    row = b'<row><c t="n"><v>1</v></c></row>' * 1024
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr("xl/workbook.xml", "<workbook/>")
        with z.open("xl/worksheets/sheet1.xml", "w", force_zip64=True) as sheet:
            sheet.write(b"<worksheet><sheetData>")
            for _ in range(megabytes * 2**20 // len(row)):
                sheet.write(row)
            sheet.write(b"</sheetData></worksheet>")


def _sparse(path: Path) -> None:
    """A 2-cell .xlsx whose cells span the whole sheet (A1 and XFD1048576)."""
    sheet = ('<worksheet><sheetData><row r="1"><c r="A1"><v>1</v></c></row>'
             '<row r="1048576"><c r="XFD1048576"><v>2</v></c></row></sheetData></worksheet>')
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr("xl/workbook.xml", '<workbook><sheets><sheet name="S" sheetId="1" '
                   'r:id="rId1"/></sheets></workbook>')
        z.writestr("xl/worksheets/sheet1.xml", sheet)


@pytest.fixture(scope="module")
def bomb_bytes(tmp_path_factory) -> bytes:
    path = tmp_path_factory.mktemp("bomb") / "bomb.xlsx"
    _bomb(path)
    return path.read_bytes()


@pytest.fixture
def work(tmp_path, monkeypatch, bomb_bytes, capsys) -> Path:
    d = tmp_path
    (d / "scene.toml").write_text(SCENE)
    for i, (written, key, unit, _) in enumerate(KEYS):
        for j, lie in enumerate(LIES[:6]):
            (d / f"lie_{i}_{j}.toml").write_text(
                MINIMAL.replace(written, f'{key} = "{lie} {unit}"'))
    for axis in ("velocity", "radius"):
        for k, special in enumerate(("nan", "inf", "-inf")):
            axes = {"velocity": "[0.01, 1.0, 3]", "radius": "[1e-6, 1e-5, 3]"}
            axes[axis] = axes[axis].replace("1.0" if axis == "velocity" else "1e-5", special)
            (d / f"map_{axis}_{k}.toml").write_text(
                MINIMAL + f"\n[map]\nvelocity = {axes['velocity']}\n"
                          f"radius = {axes['radius']}\n")
    (d / "fifo_profile.toml").write_text(MINIMAL + '\n[target.profile]\nfile = "fifo.csv"\n')
    for name in ("fifo.toml", "fifo.csv", "fifo.xlsx", "fifo.h5"):
        os.mkfifo(d / name)
    sphere_curve_file(d)                                   # film.csv
    (d / "curves").mkdir()
    curve = synthetic_curve(140e9, 12e9, berkovich(), h_c=40e-9, m=1.4, noise=0.001, seed=1)
    np.savetxt(d / "curves" / "i.csv", np.column_stack([curve.h * 1e9, curve.P * 1e6]),
               delimiter=", ", header="h [nm], P [uN]", comments="")
    P = curve.P * 1e9                                       # nN: values above 1,000
    (d / "thousands.csv").write_text("h [nm], P [nN]\n" + "".join(
        f"{a * 1e9:.3f}, {b:,.3f}\n" for a, b in zip(curve.h, P)))
    for enc in NOT_TEXT:
        (d / f"enc_{enc}.toml").write_text(f'encoding = "{enc}"\n')
    (d / "bomb.xlsx").write_bytes(bomb_bytes)
    _sparse(d / "sparse.xlsx")
    monkeypatch.chdir(d)
    capsys.readouterr()
    return d


def _snapshot(folder: Path) -> dict[str, str]:
    """Hashes of the regular files (a pipe is not read: it would wait for a writer)."""
    out = {}
    for p in sorted(folder.rglob("*")):
        mode = p.lstat().st_mode
        out[p.relative_to(folder).as_posix()] = (
            hashlib.sha256(p.read_bytes()).hexdigest() if stat.S_ISREG(mode)
            else stat.filemode(mode))
    return out


class _Blocked(Exception):
    pass


def _alarm(signum, frame):
    raise _Blocked


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_hostile_input_round_two(case, work, capsys):
    name, argv, message = case
    before = _snapshot(work)
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(20)
    try:
        status, _, err = run_main(argv if isinstance(argv, list) else argv.split(), capsys)
    except _Blocked:
        pytest.fail(f"{name}: blocked for 20 s")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert status == 2, err
    assert "Traceback" not in err and "internal error" not in err
    lines = err.splitlines()
    if name in BATCH:
        # a batch command reads on past a bad file: its progress and summary lines stay,
        # the bad file gets one error line
        lines = [line for line in lines if line.startswith("filmscale: error")]
    assert len(lines) == 1, err
    assert message in lines[0], err
    assert _snapshot(work) == before


def test_the_suite_is_large_enough():
    assert len(CASES) >= 100
