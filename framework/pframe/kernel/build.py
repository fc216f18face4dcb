"""Which compiled kernel runs a plan: the built-in one, or one wired with plug-in laws.

Every built-in law, material, integrator, recorder and scene size runs in the one kernel of
:mod:`pframe.kernel.loop`, compiled the first time any scene runs after installing pframe and
cached on disk (:mod:`pframe.kernel.cache`). A scene naming plug-in laws (entry points) runs
in a second copy of the same modules whose law switch is generated to include them
(:mod:`pframe.kernel.plugins`), compiled once per set of plug-in laws and cached likewise.
"""

from __future__ import annotations

from pframe.errors import InputError, PframeError
from pframe.kernel import cache
from pframe.kernel.dispatch import CONTACT_LAWS, MATERIALS

#: the line shown before the first compilation (seconds measured on a 2-core machine)
COMPILING = ("compiling pframe's kernel once for this installation (about {seconds} s; later "
             "runs of any scene start at once)")


def _laws(plan):
    return (tuple(dict.fromkeys(g.law for g in plan.story_groups)),
            tuple(dict.fromkeys(g.law for g in plan.contact_groups)))


def kernel_for(plan, announce=None):
    """(kernel, law ids, material id count, contact law id count, ready) for this plan;
    ``ready()`` is to be called once the kernel has run (it marks the cache as compiled)."""
    from pframe.kernel import FOLDER, loop

    materials, contacts = _laws(plan)
    extra_materials = tuple(sorted((m for m in materials if m not in MATERIALS),
                                   key=lambda law: law.name))
    extra_contacts = tuple(sorted((c for c in contacts if c not in CONTACT_LAWS),
                                  key=lambda law: law.name))
    ids = {law: i for i, law in enumerate(MATERIALS + extra_materials)}
    ids.update({law: i for i, law in enumerate(CONTACT_LAWS + extra_contacts)})
    counts = (len(MATERIALS) + len(extra_materials), len(CONTACT_LAWS) + len(extra_contacts))
    if extra_materials or extra_contacts:
        from pframe.kernel.plugins import plugin_kernel

        kernel, folder = plugin_kernel(extra_materials, extra_contacts)
        message = ("compiling pframe's kernel with the plug-in laws "
                   + ", ".join(law.name for law in extra_materials + extra_contacts)
                   + " (once for this set of plug-ins; about {seconds} s)")
    else:
        kernel, folder, message = loop.run, FOLDER, COMPILING
    if announce is not None and not cache.is_compiled(folder):
        announce(message.format(seconds=30))
    return kernel, ids, *counts, lambda: cache.mark_compiled(folder)


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
