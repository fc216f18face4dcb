"""Closed-form pulse ground motions: cycloidal pulses (Makris 1997; Makris & Black 2004) and
the Ricker wavelet, each given by its acceleration amplitude a_p and pulse period T_p
(w_p = 2 pi / T_p). The ground is at rest before t = 0 and the acceleration is zero after the
pulse; velocity and displacement are the exact integrals of the acceleration from t = 0.

Cycloidal pulses (Makris & Black 2004, eqs. 1-3, written with a_p instead of V_p):

- type A (forward):    a = a_p sin(w_p t),  0 <= t <= T_p;  a_p = w_p V_p / 2
                       v = a_p / w_p (1 - cos w_p t),  u = a_p / w_p (t - sin(w_p t) / w_p)
- type B (forward and back):  a = a_p cos(w_p t),  0 <= t <= T_p;  a_p = w_p V_p
                       v = a_p / w_p sin(w_p t),  u = a_p / w_p^2 (1 - cos w_p t)
- type C_n (n main cycles): a = a_p cos(w_p t + phi),  0 <= t <= (n + 1/2 - phi / pi) T_p
                       v = a_p / w_p (sin(w_p t + phi) - sin phi)
                       u = a_p / w_p^2 (cos phi - cos(w_p t + phi)) - a_p / w_p t sin phi
  with phi the phase that returns the ground to its starting place at the pulse's end:
  2 cos phi = ((2n + 1) pi - 2 phi) sin phi  (phi = 0.0697 pi for C_1, 0.0410 pi for C_2).

Ricker wavelet (the second derivative of a Gaussian, centred at t_0):

    a = a_p (1 - 2 pi^2 s^2 / T_p^2) exp(-pi^2 s^2 / T_p^2),   s = t - t_0
    v = a_p (s e^{-c s^2} - s_0 e^{-c s_0^2}),                 c = pi^2 / T_p^2, s_0 = -t_0
    u = a_p ((e^{-c s_0^2} - e^{-c s^2}) / (2 c) - s_0 e^{-c s_0^2} t)

(the terms in s_0 are the ground's velocity at t = 0 of the wavelet begun at -infinity,
about 1e-9 a_p T_p for the default t_0 = 1.5 T_p; they keep the integrals exact from t = 0).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

#: default centre of a Ricker wavelet, in pulse periods (|a| < 1e-8 a_p at t = 0)
RICKER_CENTER = 1.5


def cycloidal_phase(n: int) -> float:
    """The phase phi (rad) of a type-C_n pulse: zero ground displacement at its end."""
    k = (2 * n + 1) * math.pi
    return brentq(lambda p: 2.0 * math.cos(p) - (k - 2.0 * p) * math.sin(p), 0.0, math.pi / 2)


def pulse_end(excitation) -> float:
    """When the pulse's acceleration returns to zero for good (s)."""
    tp = excitation.period
    if excitation.kind == "ricker":
        return 2.0 * ricker_center(excitation)
    if excitation.type == "C":
        return (excitation.n + 0.5 - cycloidal_phase(excitation.n) / math.pi) * tp
    return tp


def ricker_center(excitation) -> float:
    return excitation.center if excitation.center is not None else RICKER_CENTER * excitation.period


def pulse_motion(excitation, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ground acceleration (m/s^2), velocity (m/s) and displacement (m) at times ``t`` (s)."""
    t = np.asarray(t, dtype=float)
    ap, wp = float(excitation.amplitude), 2.0 * math.pi / float(excitation.period)
    end = pulse_end(excitation)
    inside = (t >= 0.0) & (t <= end)
    s = np.clip(t, 0.0, end)  # the closed forms at the pulse's end hold afterwards
    if excitation.kind == "ricker":
        c = (math.pi / excitation.period) ** 2
        t0 = ricker_center(excitation)
        x, x0 = s - t0, -t0
        g, g0 = np.exp(-c * x * x), math.exp(-c * x0 * x0)
        acc = ap * (1.0 - 2.0 * c * x * x) * g
        vel = ap * (x * g - x0 * g0)
        disp = ap * ((g0 - g) / (2.0 * c) - x0 * g0 * s)
    elif excitation.type == "A":
        acc = ap * np.sin(wp * s)
        vel = ap / wp * (1.0 - np.cos(wp * s))
        disp = ap / wp * (s - np.sin(wp * s) / wp)
    elif excitation.type == "B":
        acc = ap * np.cos(wp * s)
        vel = ap / wp * np.sin(wp * s)
        disp = ap / wp**2 * (1.0 - np.cos(wp * s))
    else:
        phi = cycloidal_phase(excitation.n)
        acc = ap * np.cos(wp * s + phi)
        vel = ap / wp * (np.sin(wp * s + phi) - math.sin(phi))
        disp = ap / wp**2 * (math.cos(phi) - np.cos(wp * s + phi)) - ap / wp * s * math.sin(phi)
    after = t > end
    # after the pulse the ground keeps its final velocity (zero for every pulse but type A)
    disp = np.where(after, disp + vel * (t - end), disp)
    disp = np.where(t < 0.0, 0.0, disp)
    vel = np.where(t < 0.0, 0.0, vel)
    return np.where(inside, acc, 0.0), vel, disp
