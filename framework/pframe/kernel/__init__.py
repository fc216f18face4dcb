"""The time-stepping kernel (C, compiled when pframe is installed) and its driver.

The algorithm is C, one idea per file of ``c/``: ``loop.c`` (the time loop, the entry point
``pframe_run``), ``implicit.c`` (an implicit step in parts: retried sub-steps, events),
``integrator.c`` (a stage's relations), ``newton.c`` (the stage loop and Newton),
``explicit.c``, ``events.c``, ``assembly.c`` (residual, tangents, the band),
``energy.c`` (commit and energy bookkeeping), ``record.c``, ``banded.c`` and the generated
``laws.c`` (the built-in laws, translated from their Python ``force`` by
:mod:`pframe.kernel.translate`), over the structs of the generated ``state.h``
(:mod:`pframe.kernel.state`). ``pip install`` compiles them into the extension
``pframe.kernel._ckernel``; :mod:`pframe.kernel.ckernel` loads it with ctypes and
:func:`simulate` (:mod:`pframe.kernel.run`) drives it. Plug-in laws are numba ``cfunc``
function pointers (:mod:`pframe.kernel.plugins`); built-in scenes never import numba.
"""

from pframe.kernel.run import Result, simulate

__all__ = ["Result", "simulate"]
