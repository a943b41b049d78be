"""The package's errors: one base class, each kind with its fixed command-line exit code.

=====================  =========  ==========================================================
class                  exit code  meaning
=====================  =========  ==========================================================
`InputError`           2          a value outside its valid range, a bad file, a bad option;
                                  raised before any expensive work starts
`ModelRangeError`      1          valid inputs that take a model outside the range where its
                                  equations hold (an approach deeper than the sphere radius)
`EngineError`          1          an engine (LAMMPS) that failed or cannot be loaded
=====================  =========  ==========================================================

The command line prints the message on one line, without a traceback, and exits with
`FilmscaleError.exit_code`. Subclasses keep the built-in base each had (`ValueError` for bad
input, `RuntimeError` for the others) so ``except ValueError`` in user code still works.
"""

from __future__ import annotations

from pathlib import Path


class FilmscaleError(Exception):
    """Base of every error the package raises on purpose."""

    exit_code = 1


class InputError(FilmscaleError, ValueError):
    """A parameter value outside its valid range; the message names the parameter."""

    exit_code = 2


class ModelRangeError(FilmscaleError, RuntimeError):
    """Valid inputs that take a model outside the range where its equations hold."""

    exit_code = 1


class EngineError(FilmscaleError, RuntimeError):
    """An engine run that failed; ``run_dir`` is where it ran (None: not started)."""

    exit_code = 1

    def __init__(self, message: str, run_dir: Path | str | None = None):
        self.message = message.strip()
        self.run_dir = Path(run_dir) if run_dir is not None else None
        where = f" (run directory {self.run_dir})" if self.run_dir else ""
        super().__init__(f"{self.message}{where}")
