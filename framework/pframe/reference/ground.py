"""Ground acceleration a_g(t) as a function of continuous time, with its breakpoints.

The integrator restarts at every breakpoint (a kink or jump of a_g), so that no step straddles
one: a Runge-Kutta step across a kink of the forcing loses its order and its error estimate.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Ground:
    """a_g(t) (m/s^2) for scalar or array t, smooth between ``breakpoints`` (s)."""

    function: object
    breakpoints: np.ndarray = field(default_factory=lambda: np.empty(0))
    description: str = "user function"

    def __call__(self, t):
        return self.function(t)


def sampled(times: np.ndarray, values: np.ndarray) -> Ground:
    """Linear interpolation of samples (what the kernel's sub-steps use); a breakpoint at
    every sample, zero outside the samples."""
    times = np.asarray(times, dtype=float)
    values = np.asarray(values, dtype=float)
    if not np.any(values):
        return Ground(lambda t: np.zeros(np.shape(t)), np.empty(0), "none")

    def function(t):
        return np.interp(t, times, values, left=0.0, right=0.0)

    return Ground(function, times, "samples, interpolated linearly")


def of_scene(loaded) -> Ground:
    """The ground motion a scene applies, in continuous time: the very function whose samples
    the scene's plan holds (:func:`pframe.excitation.sample.motion`), for every kind of
    excitation: the exact sine with its cut-off, each pulse in closed form, the record as
    applied (``scale``, ``pga``, ``frequency``: the scene's resolved record, not the file read
    again) interpolated linearly between its samples, zero without excitation. Breakpoints at
    every kink or jump. This is what the kernel converges to as dt -> 0, whereas the plan's
    samples change with dt."""
    from pframe.excitation.sample import motion

    excitation = loaded.scene.excitation
    if excitation is None:
        return Ground(lambda t: np.zeros(np.shape(t)), np.empty(0), "none")
    applied = motion(excitation, getattr(loaded.expanded, "record", None))
    return Ground(applied.function, applied.breakpoints, applied.description)
