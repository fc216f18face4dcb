"""Ground acceleration on the analysis time grid t_n = n dt."""

from __future__ import annotations

import numpy as np


def sine_end(excitation) -> float:
    """When a sine excitation stops (s): after its cycles or duration, else never."""
    if excitation.cycles is not None:
        return excitation.cycles * 2.0 * np.pi / excitation.frequency
    if excitation.duration is not None:
        return excitation.duration
    return np.inf


def ground_acceleration(excitation, times: np.ndarray, record=None) -> np.ndarray:
    """a_g(t_n) (m/s^2) for a Sine or pulse definition, or for ``record = (t, a)`` (linear
    interpolation, zero after the record ends); zeros when ``excitation`` is None (free
    vibration)."""
    if excitation is None:
        return np.zeros_like(times)
    if excitation.kind in ("cycloidal", "ricker"):
        from pframe.excitation.pulses import pulse_motion

        return pulse_motion(excitation, times)[0]
    if excitation.kind == "sine":
        acc = excitation.amplitude * np.sin(excitation.frequency * times)
        return np.where(times <= sine_end(excitation) * (1.0 + 1e-12), acc, 0.0)
    t, a = record
    return excitation.scale * np.interp(times, t, a, left=0.0, right=0.0)
