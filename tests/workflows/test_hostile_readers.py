"""Bounded readers (issue 31, parts 3 and 6): special files, archives, and no echo of foreign
files.

- A named pipe (FIFO) given as a scene, as a scene's profile table, as a curve file or as a
  workbook is refused before it is opened: the command exits 2 at once with one line naming
  the file and "not a regular file" (opening a FIFO for reading waits for a writer for ever).
  The commands run as subprocesses with a timeout, so a reader that blocks fails the test
  instead of hanging it.
- An .xlsx whose members inflate far beyond any real export (a zip bomb) or whose cell
  references span an absurd rectangle (two cells, A1 and XFD1048576, make calamine allocate
  1.7e10 cells and abort the process) is refused from the archive before calamine parses it.
- A potential "file" pointed at a file that is not a potential file is refused without
  quoting any of it; a bad curve table is quoted only in a bounded, escaped excerpt.
"""

import os
import re
import socket
import subprocess
import sys
import threading
import time
import zipfile
from pathlib import Path

import pytest

from filmscale.continuum.indentation import workbooks
from filmscale.continuum.indentation.io import read_curves, read_table
from filmscale.core import files
from filmscale.core.errors import InputError
from filmscale.core.files import MAX_EXCERPT, check_regular_file, open_regular, read_text
from filmscale.potentials import PotentialError, user_potential
from filmscale.workflows.scene import load_scene
from tests.helpers.scenes import MINIMAL

PROFILE_SCENE = MINIMAL + '\n[target.profile]\nfile = "profile.csv"\n'
PROFILE = "h_c [nm], E_r [GPa], H [GPa]\n20, 150, 12\n80, 120, 9\n"
TABLE = "h [nm], P [uN]\n" + "".join(f"{k}, {k * k}\n" for k in range(1, 20))
#: seconds a refusal may take beyond the start of the command line (its imports)
PROMPT = 2.0


def _cli(args, cwd: Path, timeout: float) -> tuple[int, str, float]:
    """(exit status, stderr, seconds) of the real entry point."""
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "filmscale", *map(str, args)], cwd=cwd,
                              capture_output=True, text=True, stdin=subprocess.DEVNULL,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"filmscale {' '.join(map(str, args))} still runs after {timeout:.0f} s "
                    "(blocked on a named pipe?)")
    return done.returncode, done.stderr, time.perf_counter() - start


@pytest.fixture(scope="module")
def startup(tmp_path_factory) -> float:
    """Seconds the command line takes to start and refuse a missing scene (the imports)."""
    d = tmp_path_factory.mktemp("startup")
    times = []
    for _ in range(2):
        code, err, seconds = _cli(["plan", "absent.toml"], d, timeout=120)
        assert code == 2 and "does not exist" in err
        times.append(seconds)
    return min(times)


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# --- named pipes: refused before they are opened -------------------------------------------

def _work(d: Path) -> Path:
    (d / "profile_scene.toml").write_text(PROFILE_SCENE)
    for name in ("scene.toml", "profile.csv", "curve.csv", "curves.xlsx"):
        os.mkfifo(d / name)
    return d


#: (command line, the file the message names)
FIFO_CASES = [
    (["run", "scene.toml"], "scene.toml"),
    (["plan", "scene.toml"], "scene.toml"),
    (["impact", "scene.toml"], "scene.toml"),
    (["impact", "profile_scene.toml"], "profile.csv"),
    (["run", "profile_scene.toml"], "profile.csv"),
    (["indent", "analyze", "curve.csv", "--tip", "berkovich"], "curve.csv"),
    (["calibrate", "curve.csv", "--tip", "sphere:5um"], "curve.csv"),
    (["indent", "analyze", "curves.xlsx", "--tip", "berkovich"], "curves.xlsx"),
    (["calibrate", "curves.xlsx", "--tip", "berkovich"], "curves.xlsx"),
]


@pytest.mark.parametrize("args, named", FIFO_CASES, ids=[" ".join(a[:2]) + " " + n
                                                         for a, n in FIFO_CASES])
def test_a_named_pipe_is_refused_at_once_in_one_line(tmp_path, startup, args, named):
    d = _work(tmp_path)
    code, err, seconds = _cli(args, d, timeout=startup + 30)
    line = _one_line(err)
    assert code == 2
    assert named in line and "not a regular file" in line, line
    assert seconds < startup + PROMPT, f"{seconds:.1f} s (start-up {startup:.1f} s)"


def test_open_regular_refuses_a_name_swapped_for_a_pipe_after_the_check(tmp_path,
                                                                           monkeypatch):
    """The race: the name passed `check_regular_file`, then became a FIFO. The open does not
    wait (O_NONBLOCK) and fstat refuses it."""
    path = tmp_path / "scene.toml"
    os.mkfifo(path)
    monkeypatch.setattr(files, "check_regular_file", lambda *args: None)
    outcome = []

    def read():
        try:
            read_text(path, "scene")
        except InputError as err:
            outcome.append(str(err))

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(timeout=5)
    if reader.is_alive():           # release it before failing
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
        pytest.fail("read_text blocked on a FIFO that appeared after the check")
    assert outcome and "named pipe (FIFO), not a regular file" in outcome[0]


def _socket(path: Path):
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(path))
    return s


@pytest.mark.parametrize("make, kind", [
    (lambda p: p.mkdir(), "a folder"),
    (lambda p: os.mkfifo(p), "a named pipe (FIFO)"),
    (lambda p: p.symlink_to("/dev/null"), "a character device"),
    (_socket, "a socket"),
])
def test_check_regular_file_names_what_the_path_is(tmp_path, make, kind):
    path = tmp_path / "in\nput.toml"           # a line break in the name is escaped
    held = make(path)
    try:
        with pytest.raises(InputError) as err:
            check_regular_file(path, "scene")
        message = str(err.value)
        assert "\n" not in message and repr(str(path))[1:-1] in message
        assert message.endswith(f"{kind}, not a regular file") and "scene" in message
    finally:
        if held is not None:
            held.close()


def test_a_symbolic_link_to_a_regular_file_is_read(tmp_path):
    (tmp_path / "scene.toml").write_text(MINIMAL)
    (tmp_path / "link.toml").symlink_to("scene.toml")
    assert check_regular_file(tmp_path / "link.toml", "scene").st_size == len(MINIMAL)
    assert load_scene(tmp_path / "link.toml").impactor.radius == 10e-6
    with open_regular(tmp_path / "link.toml", "scene") as f:
        assert f.read() == MINIMAL.encode()


# --- workbooks: bounded before calamine parses them ----------------------------------------

CONTENT_TYPES = ('<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.'
                 'openxmlformats.org/package/2006/content-types"><Default Extension="rels" '
                 'ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                 '<Default Extension="xml" ContentType="application/xml"/><Override '
                 'PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-'
                 'officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/'
                 'worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-'
                 'officedocument.spreadsheetml.worksheet+xml"/></Types>')
RELS = ('<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.'
        'openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://'
        'schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" '
        'Target="xl/workbook.xml"/></Relationships>')
WORKBOOK = ('<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.'
            'openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats'
            '.org/officeDocument/2006/relationships"><sheets><sheet name="Test 001" sheetId="1" '
            'r:id="rId1"/></sheets></workbook>')
WORKBOOK_RELS = ('<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.'
                 'openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" '
                 'Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/'
                 'worksheet" Target="worksheets/sheet1.xml"/></Relationships>')
SHEET_HEAD = (b'<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.'
              b'openxmlformats.org/spreadsheetml/2006/main"><sheetData>')
SHEET_TAIL = b"</sheetData></worksheet>"


def _xlsx(path: Path, sheet_parts, level: int = 6, head: bytes = SHEET_HEAD,
          tail: bytes = SHEET_TAIL) -> Path:
    """A one-sheet .xlsx whose sheet XML is the concatenation of ``sheet_parts`` (bytes),
    streamed into the archive (deflate, ``level``)."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=level) as z:
        z.writestr("[Content_Types].xml", CONTENT_TYPES)
        z.writestr("_rels/.rels", RELS)
        z.writestr("xl/workbook.xml", WORKBOOK)
        z.writestr("xl/_rels/workbook.xml.rels", WORKBOOK_RELS)
        with z.open("xl/worksheets/sheet1.xml", "w", force_zip64=True) as f:
            f.write(head)
            for part in sheet_parts:
                f.write(part)
            f.write(tail)
    return path


def _header(prefix: str = "") -> bytes:
    p = f"{prefix}:" if prefix else ""
    return (f'<{p}row r="1"><{p}c r="A1" t="inlineStr"><{p}is><{p}t>h [nm]</{p}t></{p}is>'
            f'</{p}c><{p}c r="B1" t="inlineStr"><{p}is><{p}t>P [uN]</{p}t></{p}is></{p}c>'
            f'</{p}row>').encode()


#: MiB of sheet XML in the bomb: past the 256 MiB bound (16 x the 16 MiB input limit)
BOMB_MIB = 300


@pytest.fixture(scope="module")
def bomb(tmp_path_factory) -> Path:
    """A 2 MB .xlsx holding 300 MiB of sheet XML (1 MiB of repeated rows, 300 times)."""
    row = b"<row><c><v>1</v></c><c><v>2</v></c></row>"
    block = row * (2**20 // len(row))
    return _xlsx(tmp_path_factory.mktemp("bomb") / "bomb.xlsx",
                 (block for _ in range(BOMB_MIB)), level=1)


@pytest.fixture
def no_calamine(monkeypatch):
    """calamine fails the test if it is reached: the checks must refuse the file first."""
    import python_calamine

    class Reached(BaseException):       # not an Exception: no reader may catch it
        pass

    class Workbook:
        def __init__(self, *args, **kwargs):
            raise Reached("calamine was given the file")
        from_path = from_filelike = from_object = classmethod(__init__)

    monkeypatch.setattr(python_calamine, "CalamineWorkbook", Workbook)


def test_a_zip_bomb_is_refused_from_its_directory_in_under_a_second(bomb, no_calamine,
                                                                       monkeypatch):
    monkeypatch.delenv("FILMSCALE_MAX_INPUT_BYTES", raising=False)
    assert bomb.stat().st_size < 4 * 2**20
    start = time.perf_counter()
    with pytest.raises(InputError) as err:
        read_curves(bomb)
    seconds = time.perf_counter() - start
    message = str(err.value)
    assert seconds < 1.0, f"{seconds:.2f} s"
    assert "\n" not in message and str(bomb) in message
    assert re.search(r"holds \d+\.\d MiB uncompressed", message), message


def test_a_zip_bomb_on_the_command_line(bomb, startup):
    code, err, seconds = _cli(["calibrate", bomb, "--tip", "berkovich"], bomb.parent,
                              timeout=startup + 30)
    line = _one_line(err)
    assert code == 2 and str(bomb) in line and "MiB uncompressed" in line, line
    assert seconds < startup + PROMPT


@pytest.mark.parametrize("far", ["XFD1048576", "ZZZZZZZZ5", "B99999999999999999999"])
def test_cells_far_apart_are_refused_before_calamine(tmp_path, no_calamine, far):
    """Two cells make calamine allocate every cell of the rectangle between them (A1 and
    XFD1048576: 550 GB, which aborts the process)."""
    path = _xlsx(tmp_path / "sparse.xlsx",
                 [_header(), f'<row r="2"><c r="{far}"><v>2</v></c></row>'.encode()])
    with pytest.raises(InputError) as err:
        read_curves(path)
    message = str(err.value)
    assert str(path) in message and "the limits are 1000000 rows and 10000000 cells" in message


def test_cells_without_references_are_counted_per_row(tmp_path, no_calamine):
    """Cells without an r attribute follow the one before: one row of 11 million of them is
    refused (`test_a_real_sized_sheet_passes_the_checks`: a real one without them is not)."""
    path = _xlsx(tmp_path / "wide.xlsx", [_header(), b"<row>" + b"<c/>" * 11_000_000
                                          + b"</row>"], level=1)
    with pytest.raises(InputError, match="spans up to 2 rows x \\d+ columns"):
        read_curves(path)


@pytest.mark.parametrize("prefix, referenced", [("", True), ("", False), ("x", True)])
def test_a_real_sized_sheet_passes_the_checks(tmp_path, prefix, referenced):
    p = f"{prefix}:" if prefix else ""
    rows = [_header(prefix)] + [
        (f'<{p}row r="{i}"><{p}c r="A{i}"><{p}v>{i}</{p}v></{p}c><{p}c r="B{i}"><{p}v>'
         f'{i * i}</{p}v></{p}c></{p}row>' if referenced else
         f'<{p}row><{p}c><{p}v>{i}</{p}v></{p}c><{p}c><{p}v>{i * i}</{p}v></{p}c></{p}row>'
         ).encode() for i in range(2, 3000)]
    head, tail = SHEET_HEAD, SHEET_TAIL
    if prefix:          # as the .NET Open XML SDK writes: x:worksheet, x:row, x:c
        head = head.replace(b"<worksheet xmlns=", b"<x:worksheet xmlns:x=").replace(
            b"<sheetData>", b"<x:sheetData>")
        tail = b"</x:sheetData></x:worksheet>"
    curve = read_curves(_xlsx(tmp_path / "real.xlsx", rows, head=head, tail=tail))["Test 001"]
    assert curve.h.size == 2998


def test_a_sheet_over_the_row_limit_is_refused_before_it_is_converted(monkeypatch):
    """The .xls (OLE2) path: calamine's own extent of each sheet is checked before its
    cells become Python lists."""
    monkeypatch.setattr(workbooks, "MAX_SHEET_ROWS", 100)
    path = Path(__file__).resolve().parents[1] / "data" / "instruments" / "Popin.xls"
    with pytest.raises(InputError, match="Popin.xls: sheet '.*' spans up to \\d+ rows"):
        read_curves(path)


# --- no echo of foreign files ---------------------------------------------------------------

MARK = "SECRET-TOKEN-123"
GRID = "1 0.1 1 0.1 5.0"
TERSOFF_NUMBERS = "3.0 1.0 0.0 100390 16.217 -0.59825 0.78734 1.1e-6 1.7322 471.18 " \
                  "2.85 0.15 2.4799 1830.8"

#: (case, pair_style, elements, file text): each puts the marker where the check fails
SECRETS = [
    ("tersoff number", "tersoff", ["Si"], f"Si Si Si {TERSOFF_NUMBERS.replace('1.0', MARK)}"),
    ("tersoff element", "tersoff", ["Si"], f"{MARK} Si Si {TERSOFF_NUMBERS}"),
    ("setfl count", "eam/alloy", ["Cu"], f"a\nb\nc\n{MARK}\n{GRID}\n"),
    ("setfl element list", "eam/alloy", ["Fe"], f"a\nb\nc\n2 Cu {MARK}\n{GRID}\n"),
    ("setfl element label", "eam/alloy", ["Cu"],
     f"a\nb\nc\n2 Cu {MARK}\n{GRID}\n29 63.5 3.6 fcc\n0.0\n0.0\n"),
    ("setfl grid", "eam/alloy", ["Cu"], f"a\nb\nc\n1 Cu\n1 {MARK} 1 0.1 5.0\n"),
    ("funcfl mass", "eam", ["Cu"], f"comment\n29 {MARK} 3.6 fcc\n{GRID}\n"),
    ("airebo", "airebo", ["C"], f"{MARK} 1 2\n" * 150),
    ("passwd as tersoff/mod", "tersoff/mod", ["Si"],
     f"root:x:0:0:{MARK}:/root:/bin/bash\n" * 20),
]


@pytest.mark.parametrize("case, style, elements, text", SECRETS, ids=[s[0] for s in SECRETS])
def test_a_potential_file_that_fails_its_check_is_not_quoted(tmp_path, case, style, elements,
                                                              text):
    path = tmp_path / "secrets.txt"
    path.write_text(text)
    with pytest.raises(PotentialError) as err:
        user_potential(path, name="x", elements=elements, pair_style=style, citation="x")
    message = str(err.value)
    assert str(path.resolve()) in message and "\n" not in message
    assert MARK not in message and "SECRET" not in message, message


def test_a_bad_curve_table_is_quoted_only_in_a_short_escaped_excerpt(tmp_path):
    path = tmp_path / "curve.csv"
    path.write_text(TABLE + "20, " + "\x1b[31m" + "x" * 10_000 + "\n")
    with pytest.raises(InputError) as err:
        read_table(path)
    message = str(err.value)
    assert str(path) in message and "\x1b" not in message and "\\x1b" in message
    assert "x" * (MAX_EXCERPT + 1) not in message and len(message) < 300, message


def test_an_unknown_unit_is_quoted_only_in_a_short_excerpt(tmp_path):
    path = tmp_path / "curve.csv"
    path.write_text("h [" + "u" * 5000 + "], P [uN]\n1, 2\n2, 5\n")
    with pytest.raises(InputError) as err:
        read_table(path)
    message = str(err.value)
    assert str(path) in message and "u" * (MAX_EXCERPT + 1) not in message, message
