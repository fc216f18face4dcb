"""Ground acceleration on the analysis time grid t_n = n dt."""

from __future__ import annotations

import numpy as np


def ground_acceleration(excitation, times: np.ndarray, record=None) -> np.ndarray:
    """a_g(t_n) (m/s^2) for a Sine definition, or for ``record = (t, a)`` (linear interpolation,
    zero after the record ends); zeros when ``excitation`` is None (free vibration)."""
    if excitation is None:
        return np.zeros_like(times)
    if excitation.kind == "sine":
        end = np.inf
        if excitation.cycles is not None:
            end = excitation.cycles * 2.0 * np.pi / excitation.frequency
        elif excitation.duration is not None:
            end = excitation.duration
        acc = excitation.amplitude * np.sin(excitation.frequency * times)
        return np.where(times <= end * (1.0 + 1e-12), acc, 0.0)
    t, a = record
    return excitation.scale * np.interp(times, t, a, left=0.0, right=0.0)
