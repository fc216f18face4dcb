"""Which compiled kernel runs a plan: the built-in one, or one wired with plug-in laws.

Every built-in law, material, integrator, recorder and scene size runs in the one kernel of
:mod:`pframe.kernel.loop`, compiled the first time any scene runs after installing pframe and
cached on disk (:mod:`pframe.kernel.cache`). A scene naming plug-in laws (entry points) runs
in a second copy of the same modules whose law switch is generated to include them
(:mod:`pframe.kernel.plugins`), compiled once per set of plug-in laws and cached likewise.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pframe.errors import InputError, PframeError
from pframe.kernel import cache
from pframe.kernel.dispatch import CONTACT_LAWS, MATERIALS

#: the line shown before the first compilation (about 25-30 s on a 2-core machine)
COMPILING = ("compiling pframe's kernel once for this installation (about 30 s; later runs of "
             "any scene start at once)")


@dataclass(frozen=True)
class Kernel:
    """The compiled entry point for a plan, and the law ids it knows."""

    run: object  # pframe.kernel.loop.run, or its copy wired with plug-in laws
    ids: dict  # law class -> id (materials and contact laws count separately)
    materials: int  # number of material ids
    contact_laws: int  # number of contact law ids
    folder: Path  # its cache folder

    def ready(self) -> None:
        """Mark the cache as compiled (after the kernel has run once)."""
        cache.mark_compiled(self.folder)


def _laws(plan):
    return (tuple(dict.fromkeys(g.law for g in plan.story_groups)),
            tuple(dict.fromkeys(g.law for g in plan.contact_groups)))


def kernel_for(plan, announce=None) -> Kernel:
    """The kernel that runs this plan; ``announce(message)`` first if it is to be compiled."""
    from pframe.kernel import FOLDER, loop

    materials, contacts = _laws(plan)
    extra_materials = tuple(sorted((m for m in materials if m not in MATERIALS),
                                   key=lambda law: law.name))
    extra_contacts = tuple(sorted((c for c in contacts if c not in CONTACT_LAWS),
                                  key=lambda law: law.name))
    ids = {law: i for i, law in enumerate(MATERIALS + extra_materials)}
    ids.update({law: i for i, law in enumerate(CONTACT_LAWS + extra_contacts)})
    if extra_materials or extra_contacts:
        from pframe.kernel.plugins import plugin_kernel

        run, folder = plugin_kernel(extra_materials, extra_contacts)
        message = ("compiling pframe's kernel with the plug-in laws "
                   + ", ".join(law.name for law in extra_materials + extra_contacts)
                   + " (once for this set of plug-ins; about 30 s)")
    else:
        run, folder, message = loop.run, FOLDER, COMPILING
    _note_fallback(folder)
    if announce is not None and not cache.is_compiled(folder):
        announce(message)
    return Kernel(run, ids, len(MATERIALS) + len(extra_materials),
                  len(CONTACT_LAWS) + len(extra_contacts), folder)


_noted: set = set()


def _note_fallback(folder: Path) -> None:
    """Say once when the kernel cache lives in a temporary folder because the configured one
    (``PFRAME_CACHE_DIR``, default ``~/.cache/pframe``) cannot be written."""
    import sys

    root = cache.root()
    if folder in _noted or Path(folder).is_relative_to(root):
        return
    _noted.add(folder)
    print(f"pframe: note: the kernel cache folder {root} cannot be written; the compiled kernel "
          f"is kept in {folder} instead (set PFRAME_CACHE_DIR to a writable folder to choose "
          "where)", file=sys.stderr)


def diagnose(plan, error: Exception) -> PframeError:
    """Name the law that numba cannot compile (called when compiling a kernel failed)."""
    import numba
    from numba import types

    arr = types.Array(types.float64, 1, "C")
    signature = types.UniTuple(types.float64, 3)(arr, arr, arr, types.float64, types.float64)
    materials, contacts = _laws(plan)
    for kind, laws in (("material", materials), ("contact law", contacts)):
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
