"""Calling a law's own ``force`` over many elements (and many time samples) at once.

The reference shares the constitutive laws with the kernel but not the time stepping, so the
force of every storey and contact comes from the law's ``force`` function (the one the kernel's
C is translated from): by default compiled by numba into one loop per law when numba is
installed (about 1 us per call for a whole group), or, with ``jit=False`` or without numba,
called from Python element by element.
"""

from __future__ import annotations

import numpy as np

_COMPILED: dict = {}


def _compiled_loop(force):
    """A numba loop over rows of ``deformation``; row ``j`` is element ``j % g``."""
    if force in _COMPILED:
        return _COMPILED[force]
    try:
        import numba
    except ImportError:  # numba is the optional 'plugins' extra: the same force, in Python
        return _python_loop(force)

    from pframe.laws.compiled import njit

    law_force = njit(force)  # and the helper functions it calls

    @numba.njit
    def loop(params, committed, deformation, rate, out):
        g = params.shape[0]
        trial = np.empty(committed.shape[1])
        for j in range(deformation.shape[0]):
            e = j % g
            f, dfd, dfr = law_force(params[e], committed[e], trial, deformation[j], rate[j])
            out[0, j] = f
            out[1, j] = dfd
            out[2, j] = dfr

    _COMPILED[force] = loop
    return loop


def _python_loop(force):
    def loop(params, committed, deformation, rate, out):
        g = params.shape[0]
        trial = np.empty(committed.shape[1])
        for j in range(deformation.shape[0]):
            e = j % g
            out[:, j] = force(params[e], committed[e], trial, float(deformation[j]),
                              float(rate[j]))

    return loop


class LawElements:
    """The elements of one law: parameters, committed states and the compiled force loop.

    Parameters
    ----------
    law : type
        The registered law class.
    index : (g,) int array
        Element indices (storeys or contacts, declaration order).
    params : (g, p) array
        Packed parameters of one batch member.
    state : (g, m) array
        Initial state; becomes the committed state, updated only at events.
    jit : bool
        Compile the law's ``force`` with numba (default) or call it from Python.
    """

    def __init__(self, law, index, params, state, jit: bool = True):
        self.law = law
        self.index = np.asarray(index, dtype=np.int64)
        self.params = np.ascontiguousarray(params, dtype=float)
        self.committed = np.array(state, dtype=float).reshape(len(self.index), -1)
        self._loop = _compiled_loop(law.force) if jit else _python_loop(law.force)

    def __len__(self) -> int:
        return len(self.index)

    def forces(self, deformation: np.ndarray, rate: np.ndarray) -> np.ndarray:
        """(3, ...) force, d force / d deformation, d force / d rate at the committed state.

        ``deformation`` and ``rate`` have shape (..., g): the last axis runs over the group's
        elements, any leading axes over time samples.
        """
        shape = deformation.shape
        d = np.ascontiguousarray(deformation, dtype=float).reshape(-1)
        r = np.ascontiguousarray(rate, dtype=float).reshape(-1)
        out = np.empty((3, d.size))
        self._loop(self.params, self.committed, d, r, out)
        return out.reshape((3,) + shape)

    def force_only(self, deformation: np.ndarray, rate: np.ndarray) -> np.ndarray:
        """(g,) forces for one state (contiguous 1-D inputs): the right-hand side's call."""
        out = np.empty((3, len(self.index)))
        self._loop(self.params, self.committed, deformation, rate, out)
        return out[0]

    def commit(self, j: int, deformation: float, rate: float) -> float:
        """Call the law for element ``j`` at (deformation, rate) and commit its trial state,
        as the kernel commits an accepted step. Returns the force."""
        trial = self.committed[j].copy()
        f, _, _ = self.law.force(self.params[j], self.committed[j].copy(), trial,
                                 float(deformation), float(rate))
        self.committed[j] = trial
        return float(f)
