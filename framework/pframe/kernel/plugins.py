"""Law ids for a plan, and plug-in laws compiled into C functions the kernel calls.

Built-in laws have the ids of their place in the one ordered registry
(:func:`pframe.laws.registry.builtin_laws`); their C is in the compiled kernel (``c/laws.c``,
generated from their Python ``force``). A plug-in law (an entry point in
``pframe.contact_laws`` or ``pframe.materials``) gets an id after the built-in ones of its
kind, and its Python ``force`` is compiled by numba's ``cfunc`` into a C function of the
kernel's ``LawFunction`` signature::

    void force(const double *params, const double *committed, double *trial,
               double deformation, double rate, double *out3)

whose address the kernel calls through a table in its Settings. The wrapper module is
generated into the plug-in cache folder (``$PFRAME_CACHE_DIR/plugins/<key>``, default
``~/.cache/pframe``; the key hashes the laws' sources and the versions), where numba caches
the compiled functions: a set of plug-in laws compiles once, in seconds. numba is imported
only here, only for a plan that names a plug-in law (``pip install "pframe[plugins]"``).
"""

from __future__ import annotations

import ctypes
import hashlib
import importlib.util
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from pframe.errors import InputError
from pframe.laws import compiled as compiled_force
from pframe.laws.registry import builtin_count, builtin_id

#: written into a plug-in folder once its laws have been compiled and cached
MARKER = "compiled"


# eq=False: nothing compares two (their dicts and ctypes tables would not hash); each
# generated function is compiled at every start
@dataclass(frozen=True, eq=False)
class LawIds:
    """The law ids of a plan and the plug-in laws' function pointers."""

    ids: dict  # law class -> id (materials and contact laws count separately)
    materials: int  # number of material ids
    contact_laws: int  # number of contact law ids
    material_table: object = None  # ctypes array of plug-in material function pointers
    contact_table: object = None  # ... of plug-in contact law function pointers
    module: object = None  # the compiled plug-in module (holds the functions' code)

    @staticmethod
    def address(table) -> int:
        return ctypes.addressof(table) if table is not None else 0


def _laws(plan):
    return (tuple(dict.fromkeys(g.law for g in plan.story_groups)),
            tuple(dict.fromkeys(g.law for g in plan.contact_groups)))


def law_ids(plan, announce=None) -> LawIds:
    """The ids of the plan's laws; plug-in laws compiled (or loaded from their cache) first,
    ``announce(message)`` before they are compiled."""
    # the built-in laws' ids without importing the laws the plan does not use
    materials, contacts = builtin_count("material"), builtin_count("contact")
    used_materials, used_contacts = _laws(plan)
    extra_materials = tuple(sorted((m for m in used_materials if builtin_id(m) is None),
                                   key=lambda law: law.name))
    extra_contacts = tuple(sorted((c for c in used_contacts if builtin_id(c) is None),
                                  key=lambda law: law.name))
    ids = {law: builtin_id(law) for law in used_materials + used_contacts
           if builtin_id(law) is not None}
    ids.update({law: materials + i for i, law in enumerate(extra_materials)})
    ids.update({law: contacts + i for i, law in enumerate(extra_contacts)})
    count_m, count_c = materials + len(extra_materials), contacts + len(extra_contacts)
    if not (extra_materials or extra_contacts):
        return LawIds(ids, count_m, count_c)
    module = compiled(extra_materials + extra_contacts, announce)
    functions = [getattr(module, f"law{i}").address
                 for i in range(len(extra_materials) + len(extra_contacts))]
    split = len(extra_materials)
    tables = [(ctypes.c_void_p * len(part))(*part) if part else None
              for part in (functions[:split], functions[split:])]
    return LawIds(ids, count_m, count_c, tables[0], tables[1], module)


# --- the cache folder ------------------------------------------------------------------------

def root() -> Path:
    return Path(os.environ.get("PFRAME_CACHE_DIR") or Path.home() / ".cache" / "pframe")


def folder(key: str) -> Path:
    """The cache folder for ``key``, created; a temporary one if it cannot be written (the
    plug-ins are then compiled again by the next process, which is slower but never wrong)."""
    import tempfile  # here and in compiled: a run of built-in laws makes no file

    path = root() / "plugins" / key
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
        return path
    except OSError:
        user = os.getuid() if hasattr(os, "getuid") else 0
        fallback = Path(tempfile.gettempdir()) / f"pframe-{user}" / key
        fallback.mkdir(parents=True, exist_ok=True)
        return fallback


_noted: set = set()


def _note_fallback(path: Path) -> None:
    """Say once when the plug-in cache lives in a temporary folder because the configured one
    (``PFRAME_CACHE_DIR``, default ``~/.cache/pframe``) cannot be written."""
    base = root()
    if path in _noted or Path(path).is_relative_to(base):
        return
    _noted.add(path)
    print(f"pframe: note: the cache folder {base} cannot be written; the compiled plug-in laws "
          f"are kept in {path} instead (set PFRAME_CACHE_DIR to a writable folder to choose "
          "where)", file=sys.stderr)


# --- compiling -------------------------------------------------------------------------------

def _numba():
    try:
        import numba
    except ImportError:
        raise InputError(
            "the scene uses a plug-in law, which numba compiles for the kernel, and numba is "
            "not installed: pip install \"pframe[plugins]\" (or pip install numba)") from None
    return numba


def _key(laws) -> str:
    from pframe import __version__

    numba = _numba()
    digest = hashlib.sha256()
    digest.update(f"{__version__} numba {numba.__version__} {sys.version_info[:2]}".encode())
    digest.update(_source(laws).encode())
    for law in laws:
        digest.update(f"{law.kind} {law.name} {law.__module__}.{law.__qualname__}\n".encode())
        digest.update(compiled_force.source(law.force).encode())  # and its helpers
    return digest.hexdigest()[:16]


def _source(laws) -> str:
    """The generated module: each law's force wrapped into a C-callable cfunc ``lawN``."""
    lines = ['"""Generated by pframe.kernel.plugins: plug-in laws as C functions."""',
             "import numba", "from numba import types", "",
             "from pframe.laws.compiled import njit", "",
             "_p = types.CPointer(types.float64)",
             "SIGNATURE = types.void(_p, _p, _p, types.float64, types.float64, _p)", ""]
    for i, law in enumerate(laws):
        top = law.__qualname__.split(".")[0]
        rest = law.__qualname__[len(top):]
        params, states = max(1, len(law.param_names)), max(1, len(law.state_names))
        # error_model 'numpy': a division by zero gives inf or nan, as in the C kernel (which
        # then stops the member and says where), without a check at every division
        lines += [f"from {law.__module__} import {top} as _law{i}",
                  f"_force{i} = njit(_law{i}{rest}.force, inline='always', "
                  "error_model='numpy')", "", "",
                  "@numba.cfunc(SIGNATURE, cache=True, nopython=True, error_model='numpy')",
                  f"def law{i}(params, committed, trial, deformation, rate, out):",
                  f"    f, kd, kr = _force{i}(numba.carray(params, ({params},)),",
                  f"                        numba.carray(committed, ({states},)),",
                  f"                        numba.carray(trial, ({states},)), deformation, rate)",
                  "    out[0] = f", "    out[1] = kd", "    out[2] = kr", "", ""]
    return "\n".join(lines)


_loaded: dict[str, object] = {}


def _check(law) -> None:
    """Compile one law's force alone, to name the law that numba cannot compile."""
    _numba()  # a clear message when numba is missing
    from numba import types

    array = types.Array(types.float64, 1, "C")
    signature = types.UniTuple(types.float64, 3)(array, array, array, types.float64,
                                                  types.float64)
    try:
        compiled_force.njit(law.force).compile(signature)
    except Exception as exc:  # numba raises many types; any of them means 'cannot'
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(
            f"{law.kind} law {law.name!r} ({law.__module__}.{law.__qualname__}) cannot be "
            f"compiled by numba: {first}. A law's force() must use only float arithmetic, math "
            "functions, its 1-D float arrays and module-level helper functions written alike "
            "(see docs/contact-laws.md).") from None


def compiled(laws, announce=None):
    """The generated module of these plug-in laws, compiled (or loaded from numba's cache)."""
    import tempfile

    key = _key(laws)
    if key in _loaded:
        return _loaded[key]
    path = folder(key)
    _note_fallback(path)
    fresh = not (path / MARKER).exists()
    if fresh and announce is not None:
        announce("compiling the plug-in laws " + ", ".join(law.name for law in laws)
                 + " with numba (once for this set of plug-ins; a few seconds)")
    source = path / f"pframe_plugins_{key}.py"
    text = _source(laws)
    if not source.exists() or source.read_text(encoding="utf-8") != text:
        fd, tmp = tempfile.mkstemp(dir=path, suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.replace(tmp, source)
    name = f"pframe_plugins_{key}"
    spec = importlib.util.spec_from_file_location(name, source)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except Exception:
        del sys.modules[name]
        for law in laws:
            _check(law)
        raise
    if fresh:
        try:
            (path / MARKER).write_text("compiled\n", encoding="utf-8")
        except OSError:
            pass
    _loaded[key] = module
    return module
