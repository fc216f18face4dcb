"""A reference solution independent of the time-stepping kernel.

scipy's ODE solvers (DOP853 by default) at tight tolerances on the first-order equations of
motion, restarted at every regime change of a law (contact onset and separation, release of a
clipped contact force, yield and unloading of bilinear storeys) and at breakpoints of the
ground motion. The reference shares the constitutive laws with the kernel (it calls their
``force``) but not the time stepping. See ``docs/reference-solution.md``.
"""

from pframe.reference.ground import Ground, of_scene, sampled
from pframe.reference.result import Event, Impact, ReferenceResult
from pframe.reference.solver import METHODS, default_atol, solve

__all__ = ["METHODS", "Event", "Ground", "Impact", "ReferenceResult", "default_atol",
           "of_scene", "sampled", "solve"]
