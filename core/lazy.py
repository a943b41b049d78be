"""Public names of a package imported on first use (PEP 562), so that importing the package
(and starting the command line) does not load LAMMPS, MDAnalysis or matplotlib."""

from __future__ import annotations

import sys
from importlib import import_module


def lazy_exports(package: str, where: dict[str, str]):
    """``(__getattr__, __dir__)`` for ``package`` whose public name ``n`` is defined in its
    submodule ``where[n]``; a name, once resolved, is kept in the package."""
    def __getattr__(name: str):
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(f"{package}.{where[name]}"), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__():
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__
