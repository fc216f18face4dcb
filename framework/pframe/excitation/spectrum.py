"""Elastic response spectra of ground accelerations: the exact piecewise-linear recurrence.

The ground acceleration is taken as linear between its samples (as a record is meant), and
the linear SDOF oscillator u'' + 2 xi w u' + w^2 u = -a_g(t) is integrated exactly over each
interval (Nigam & Jennings 1969; the coefficients as tabulated in Chopra, *Dynamics of
Structures*, section 5.2):

    u_{i+1}  = A u_i  + B u'_i  + C p_i  + D p_{i+1}
    u'_{i+1} = A' u_i + B' u'_i + C' p_i + D' p_{i+1},        p = -a_g,  k = w^2

with no time-step error: the result is exact for the piecewise-linear ground motion, so the
record's own step serves for every period (no sub-stepping of short periods is needed). The
pseudo-spectral acceleration is Sa = w^2 max |u|.
"""

from __future__ import annotations

import math

import numpy as np

try:
    from numba import njit
except ImportError:  # numba is the optional 'plugins' extra: the same recurrences in Python

    def njit(*args, **kwargs):
        return args[0] if args and callable(args[0]) else (lambda function: function)

G = 9.80665


def _coefficients(period: float, damping: float, dt: float) -> np.ndarray:
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"damping ratio {damping} must be in [0, 1)")
    w = 2.0 * math.pi / period
    root = math.sqrt(1.0 - damping * damping)
    wd = w * root
    e = math.exp(-damping * w * dt)
    s, c = math.sin(wd * dt), math.cos(wd * dt)
    k = w * w
    r = damping / root
    a = e * (r * s + c)
    b = e * s / wd
    cc = (2.0 * damping / (w * dt)
          + e * (((1.0 - 2.0 * damping**2) / (wd * dt) - r) * s
                 - (1.0 + 2.0 * damping / (w * dt)) * c)) / k
    d = (1.0 - 2.0 * damping / (w * dt)
         + e * ((2.0 * damping**2 - 1.0) / (wd * dt) * s + 2.0 * damping / (w * dt) * c)) / k
    a1 = -e * w / root * s
    b1 = e * (c - r * s)
    c1 = (-1.0 / dt + e * ((w / root + damping / (dt * root)) * s + c / dt)) / k
    d1 = (1.0 - e * (r * s + c)) / (k * dt)
    return np.array([a, b, cc, d, a1, b1, c1, d1])


@njit(cache=True, nogil=True)
def _peaks(acc, coef, u0, v0):  # pragma: no cover - compiled
    n = coef.shape[0]
    out = np.zeros(n)
    for j in range(n):
        a, b, c, d, a1, b1, c1, d1 = coef[j]
        u, v = u0, v0
        peak = abs(u)
        for i in range(acc.shape[0] - 1):
            p0, p1 = -acc[i], -acc[i + 1]
            u, v = a * u + b * v + c * p0 + d * p1, a1 * u + b1 * v + c1 * p0 + d1 * p1
            if abs(u) > peak:
                peak = abs(u)
        out[j] = peak
    return out


@njit(cache=True, nogil=True)
def _history(acc, coef, u0, v0):  # pragma: no cover - compiled
    a, b, c, d, a1, b1, c1, d1 = coef
    u = np.empty(acc.shape[0])
    v = np.empty(acc.shape[0])
    u[0], v[0] = u0, v0
    for i in range(acc.shape[0] - 1):
        p0, p1 = -acc[i], -acc[i + 1]
        u[i + 1] = a * u[i] + b * v[i] + c * p0 + d * p1
        v[i + 1] = a1 * u[i] + b1 * v[i] + c1 * p0 + d1 * p1
    return u, v


def sdof_response(acc, dt: float, period: float, damping: float = 0.05,
                  u0: float = 0.0, v0: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Displacement (m) and velocity (m/s) relative to the ground of a linear SDOF of natural
    ``period`` (s) and ``damping`` ratio under the ground acceleration ``acc`` (m/s^2, samples
    every ``dt`` s, linear between them), from ``u0``, ``v0`` at t = 0."""
    acc = np.ascontiguousarray(acc, dtype=float)
    return _history(acc, _coefficients(period, damping, dt), float(u0), float(v0))


def response_spectrum(acc, dt: float, periods, damping: float = 0.05) -> dict[str, np.ndarray]:
    """Peak responses of linear SDOFs from rest: ``Sd`` (m), pseudo-velocity ``PSv`` (m/s) and
    pseudo-acceleration ``PSa`` (m/s^2) at each of ``periods`` (s); a period of 0 gives the
    peak ground acceleration (the infinitely stiff oscillator)."""
    acc = np.ascontiguousarray(acc, dtype=float)
    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    if np.any(periods < 0) or not np.all(np.isfinite(periods)):
        raise ValueError(f"periods must be finite and >= 0, got {periods}")
    positive = periods > 0
    sd = np.zeros(periods.shape)
    if np.any(positive):
        coef = np.array([_coefficients(t, damping, dt) for t in periods[positive]])
        sd[positive] = _peaks(acc, coef, 0.0, 0.0)
    w = np.where(positive, 2.0 * np.pi / np.where(positive, periods, 1.0), 0.0)
    psa = np.where(positive, w * w * sd, np.max(np.abs(acc)) if acc.size else 0.0)
    return {"Sd": sd, "PSv": w * sd, "PSa": psa}


def spectral_acceleration(acc, dt: float, period: float, damping: float = 0.05) -> float:
    """Sa(T, xi) (m/s^2): the pseudo-spectral acceleration at one period."""
    return float(response_spectrum(acc, dt, [period], damping)["PSa"][0])
