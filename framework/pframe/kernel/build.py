"""Compiling and caching generated kernels.

The generated module is written once to ``$PFRAME_CACHE_DIR`` (default ``~/.cache/pframe``)
under a name that hashes the scene structure and the source of every law it calls; numba's
on-disk cache beside it makes later runs of the same structure skip compilation entirely.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile
from pathlib import Path

from pframe.errors import InputError, PframeError
from pframe.kernel.codegen import Structure, generate

_loaded: dict[str, object] = {}


def cache_dir() -> Path:
    root = os.environ.get("PFRAME_CACHE_DIR") or Path.home() / ".cache" / "pframe"
    path = Path(root) / "kernels"
    path.mkdir(parents=True, exist_ok=True)
    return path


def kernel_for(structure: Structure):
    """The compiled (lazily, on first call) kernel function for this structure."""
    key = structure.key()
    if key in _loaded:
        return _loaded[key]
    path = cache_dir() / f"pframe_kernel_{key}.py"
    if not path.exists():
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        with os.fdopen(fd, "w") as handle:
            handle.write(generate(structure))
        os.replace(tmp, path)
    name = f"pframe_kernel_{key}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    _loaded[key] = module.kernel
    return module.kernel


def diagnose(structure: Structure, error: Exception) -> PframeError:
    """Name the law that numba cannot compile (called when compiling a kernel failed)."""
    import numba
    from numba import types

    arr = types.Array(types.float64, 1, "C")
    signature = types.UniTuple(types.float64, 3)(arr, arr, arr, types.float64, types.float64)
    for kind, laws in (("material", structure.story_laws), ("contact law", structure.contact_laws)):
        for law in laws:
            try:
                numba.njit(signature)(law.force)
            except Exception as exc:  # numba raises many types; any of them means 'cannot'
                first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                return InputError(
                    f"{kind} {law.name!r} ({law.__module__}.{law.__qualname__}) cannot be "
                    f"compiled by numba: {first}. A law's force() must use only float "
                    "arithmetic, math functions and its 1-D float arrays (see docs/contact-laws.md)."
                )
    return PframeError(f"the kernel failed to compile: {error}")
