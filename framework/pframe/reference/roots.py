"""Locating zeros of event functions along a step, to a few ulps of the time."""

from __future__ import annotations

import numpy as np
from scipy import optimize

EPS = np.finfo(float).eps


def root(g, a: float, b: float) -> float:
    """A zero of g in [a, b] where g(a) >= 0 >= g(b) (Brent's method, to a few ulps of t)."""
    ga, gb = g(a), g(b)
    if ga <= 0.0:
        return a
    if gb >= 0.0:
        return b
    xtol = 4.0 * EPS * max(abs(a), abs(b))
    return optimize.brentq(g, a, b, xtol=xtol, rtol=4.0 * EPS, maxiter=200)


def crossing(g, a: float, b: float) -> float:
    """The first time in (a, b] at which g, positive (or zero) at a, has become negative or
    zero: Brent's root, then moved forward by a few ulps until g is strictly negative (so
    that the new regime starts strictly on its side), or b."""
    x = root(g, a, b)
    if x == a:
        x = min(b, a + 4.0 * EPS * max(abs(a), abs(b)))
    step = 4.0 * EPS * max(abs(x), abs(b - a))
    start = x
    for _ in range(60):
        if g(x) < 0.0:
            return x
        x = min(b, start + step)
        if x == b:
            break
        step *= 2.0
    return b
