"""Ground acceleration: the one definition of the motion a scene applies, in continuous time
(:func:`motion`), and its samples on the analysis time grid t_n = n dt
(:func:`ground_acceleration`, what the kernel is given).

The reference solution of ``pframe accuracy`` (:func:`pframe.reference.of_scene`) integrates
the same :func:`motion`, so that a run and its reference cannot apply different motions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


def sine_end(excitation) -> float:
    """When a sine excitation stops (s): after its cycles or duration, else never."""
    if excitation.cycles is not None:
        return excitation.cycles * 2.0 * np.pi / excitation.frequency
    if excitation.duration is not None:
        return excitation.duration
    return np.inf


# eq=False: it holds numpy arrays (== elementwise): a generated __eq__ and __hash__
# could only raise, and would be compiled at every start
@dataclass(frozen=True, eq=False)
class Motion:
    """a_g(t) (m/s^2) for a scalar or an array t (s), smooth between ``breakpoints`` (s),
    zero after ``end`` (s; inf for a sine without end)."""

    function: object
    breakpoints: np.ndarray = field(default_factory=lambda: np.empty(0))
    end: float = 0.0
    description: str = "none"

    def __call__(self, t):
        return self.function(t)


def _zero(t):
    return 0.0 if np.ndim(t) == 0 else np.zeros(np.shape(t))


def _record_arrays(record):
    """(times, accelerations) of an AppliedRecord or of a (times, accelerations) pair."""
    if hasattr(record, "acceleration"):
        return np.asarray(record.times, float), np.asarray(record.acceleration, float)
    t, a = record
    return np.asarray(t, float), np.asarray(a, float)


def motion(excitation, record=None) -> Motion:
    """The ground acceleration a scene applies, in continuous time.

    Parameters
    ----------
    excitation : Sine, Record, a pulse (Cycloidal, Ricker), Stochastic or None
        The scene's excitation definition (None: the ground is at rest).
    record : AppliedRecord or (times, accelerations), optional
        For a record: the record as applied (``pga`` and ``frequency`` done,
        :func:`pframe.excitation.characteristic.apply_record`); for a stochastic motion, its
        realisation (:func:`pframe.excitation.stochastic.stochastic_record`). ``excitation.scale`` is
        applied here. Linear between its samples, zero outside them.
    """
    if excitation is None:
        return Motion(_zero, np.empty(0), 0.0, "none")
    if excitation.kind in ("cycloidal", "ricker"):
        return _pulse(excitation)
    if excitation.kind == "sine":
        amplitude, frequency = float(excitation.amplitude), float(excitation.frequency)
        end = sine_end(excitation)
        limit = end * (1.0 + 1e-12)

        def sine(t):
            if np.ndim(t) == 0:  # the reference's calls: keep them cheap
                return amplitude * math.sin(frequency * t) if t <= limit else 0.0
            t = np.asarray(t, dtype=float)
            return np.where(t <= limit, amplitude * np.sin(frequency * t), 0.0)

        breaks = np.array([limit]) if np.isfinite(limit) else np.empty(0)
        return Motion(sine, breaks, float(end), f"{amplitude:g} sin({frequency:g} t)")
    t, a = _record_arrays(record)
    scale = float(excitation.scale)

    def interpolated(x):
        return scale * np.interp(x, t, a, left=0.0, right=0.0)

    if excitation.kind == "stochastic":
        from pframe.excitation.stochastic import generate

        return Motion(interpolated, t, float(t[-1]), generate(excitation).description())
    return Motion(interpolated, t, float(t[-1]), f"record {excitation.file}")


def _pulse(excitation) -> Motion:
    """A pulse's acceleration (the formulas of :func:`pframe.excitation.pulses.pulse_motion`)."""
    from pframe.excitation.pulses import cycloidal_phase, pulse_end, ricker_center

    tp = float(excitation.period)
    ap, wp = float(excitation.amplitude), 2.0 * math.pi / tp
    end = pulse_end(excitation)
    if excitation.kind == "ricker":
        c = (math.pi / tp) ** 2
        t0 = ricker_center(excitation)

        def shape(s, sin, cos, exp):
            x = s - t0
            return ap * (1.0 - 2.0 * c * x * x) * exp(-c * x * x)
    elif excitation.type == "A":
        def shape(s, sin, cos, exp):
            return ap * sin(wp * s)
    elif excitation.type == "B":
        def shape(s, sin, cos, exp):
            return ap * cos(wp * s)
    else:
        phi = cycloidal_phase(excitation.n)

        def shape(s, sin, cos, exp):
            return ap * cos(wp * s + phi)

    def function(t):
        if np.ndim(t) == 0:
            return shape(float(t), math.sin, math.cos, math.exp) if 0.0 <= t <= end else 0.0
        t = np.asarray(t, dtype=float)
        s = np.clip(t, 0.0, end)
        return np.where((t >= 0.0) & (t <= end), shape(s, np.sin, np.cos, np.exp), 0.0)

    name = "ricker" if excitation.kind == "ricker" else f"cycloidal {excitation.type}"
    return Motion(function, np.array([0.0, end]), float(end),
                  f"{name} pulse a_p = {ap:g} m/s^2, T_p = {tp:g} s")


def ground_acceleration(excitation, times: np.ndarray, record=None) -> np.ndarray:
    """a_g(t_n) (m/s^2) for a Sine or pulse definition, or for ``record`` (an AppliedRecord or
    ``(t, a)``: linear interpolation, zero after the record ends); zeros when ``excitation`` is
    None (free vibration). The samples of :func:`motion`."""
    times = np.asarray(times, dtype=float)
    return np.asarray(motion(excitation, record)(times), dtype=float) * np.ones_like(times)
