"""Bathe's composite method (Bathe & Baig 2005; Bathe 2007; any splitting ratio: Bathe & Noh
2012), a step of length h in two implicit sub-steps:

1. the trapezoidal rule (Newmark's average acceleration) from t to t + gamma h;
2. the three-point backward difference over the whole step,

       v(t+h) = c1 u(t) + c2 u(t+gamma h) + c3 u(t+h),
       a(t+h) = c1 v(t) + c2 v(t+gamma h) + c3 v(t+h),

       c1 = (1 - gamma) / (gamma h),  c2 = -1 / ((1 - gamma) gamma h),
       c3 = (2 - gamma) / ((1 - gamma) h),

with equilibrium at the end of each. It is the TR-BDF2 method of Bank et al. (1985) applied to
the first-order form (u, v)' = (v, a): on a linear system one step multiplies each mode by
R(h lambda), R(z) = (w0 + w1 (1 + gamma z / 2) / (1 - gamma z / 2)) / (1 - k z) with
w1 = 1 / (gamma (2 - gamma)), w0 = 1 - w1, k = (1 - gamma) / (2 - gamma) (Hosea & Shampine
1996). Second order, unconditionally stable, and its spectral radius goes to 0 as w h grows
(rho_inf = 0, Bathe 2007): it removes the high modes (contact chatter) in a few steps while
the low ones keep their amplitude to O((w h)^3) a step. Its numerical dissipation is counted
as the integrator's own (energy_algorithmic).

gamma = 1/2 is Bathe's original (and OpenSees' TRBDF2). gamma = 2 - sqrt 2 (the default, the
usual choice for TR-BDF2) makes both sub-steps' effective stiffness K + (2 / (gamma h)) C +
(4 / (gamma h)^2) M, so the kernel factors it once for both (then k = gamma / 2, taken so
exactly: the rounded weights are made equal for the factor to be shared).

In the kernel it is data: its :class:`~pframe.integrators.tableau.Tableau`, run by the generic
stage loop on every stepping path (whole steps, retried sub-steps, located events).
"""

import math
from typing import ClassVar, Literal

from pydantic import Field

from pframe.integrators._base import Facts, Implicit
from pframe.integrators.coefficients import Coefficients
from pframe.integrators.tableau import Stage, Tableau

#: the splitting ratio for which both sub-steps share their effective stiffness
GAMMA_SHARED = 2.0 - math.sqrt(2.0)


class Bathe(Implicit):
    """Bathe's composite method (trapezoidal rule, then three-point backward difference)."""

    type: Literal["bathe"] = "bathe"
    gamma: float = Field(GAMMA_SHARED, gt=0.0, lt=1.0,
                         description="The first sub-step's share of the step, in (0, 1): "
                         "2 - sqrt 2 (default: one factorisation for both sub-steps) or 0.5 "
                         "(Bathe's original).")
    facts: ClassVar[Facts] = Facts(
        order=2, paths=frozenset({"events", "retry"}),
        examples={"bathe": {"type": "bathe"}, "bathe-0.5": {"type": "bathe", "gamma": 0.5}},
        # the free impact: worst the Kelvin jump inside a step without events (measured 9.5e-4);
        # the balance closes to round-off (measured 3.3e-12)
        restitution_tolerance=2e-3, impact_balance_tolerance=1e-10,
        # positive numerical damping, small at the paper's steps (measured 3.0e-5 and 8.4e-5
        # of the largest energy term at 1 and 4 times its step)
        balance={"bathe": ({"type": "bathe"}, (0.0, 1e-3))},
        balance_tolerance=1e-10,
        spectral_decay=({"type": "bathe"}, {"type": "bathe", "gamma": 0.5}))

    def tableau(self) -> Tableau:
        g = self.gamma
        half = g / 2.0  # the trapezoidal sub-step's weights: u, v own (g h / 2)^2 a, (g h / 2) a
        k = (1.0 - g) / (2.0 - g)
        if abs(k - half) <= 4.0 * math.ulp(half):
            k = half
        w1 = 1.0 / (g * (2.0 - g))
        w0 = 1.0 - w1
        trapezoid = Stage(g, u=((1.0, g, half * half), (0.0, 0.0, half * half)),
                          v=((0.0, 1.0, half), (0.0, 0.0, half)))
        # v = w0 v0 + w1 v1 + k h a,  u = w0 u0 + w1 u1 + k h v
        backward = Stage(1.0, u=((w0, k * w0, 0.0), (w1, k * w1, 0.0), (0.0, 0.0, k * k)),
                         v=((0.0, w0, 0.0), (0.0, w1, 0.0), (0.0, 0.0, k)))
        return Tableau((trapezoid, backward))

    def coefficients(self):
        opensees = ("trbdf2",) if self.gamma == 0.5 else (
            f"OpenSees' TRBDF2 is Bathe's method with gamma = 0.5, not {self.gamma:.6g}: set "
            "gamma: 0.5 to compare with it")
        return Coefficients(scheme="tableau", tableau=self.tableau(), opensees=opensees,
                            **self.runs_on())

    def describe(self) -> str:
        return f"bathe(gamma={self.gamma:.6g})"
