"""Packages that are also the public function of the same name.

``pframe.plot`` and ``pframe.sweep`` are functions of the API (docs/python.md) and packages.
Once a package is imported, Python sets it as the attribute of its parent, so the name would
mean the function or the package depending on what was imported first. The package is made
callable instead: ``pframe.sweep(...)`` calls the function, ``pframe.sweep.run_sweep`` is
still the package's.
"""

from __future__ import annotations

import importlib
import sys
import types


def make_callable(package: str, module: str, function: str) -> None:
    """Calling ``package`` calls ``module.function``."""

    class CallableModule(types.ModuleType):
        __doc__ = sys.modules[package].__doc__

        def __call__(self, *args, **kwargs):
            return getattr(importlib.import_module(module), function)(*args, **kwargs)

    sys.modules[package].__class__ = CallableModule
