"""Wilson's theta method (Wilson, Farhoomand & Bathe 1973), as in SAP2000 and Bathe's texts.

Equilibrium is imposed at ``t + theta dt`` of a motion whose acceleration varies linearly over
the extended step ``theta dt``, with the ground motion extrapolated linearly to that time; the
step end follows from ``a(n+1) = a(n) + (a(t + theta dt) - a(n)) / theta`` and the
linear-acceleration relations over ``dt`` (Newmark gamma = 1/2, beta = 1/6). ``theta = 1`` is
Newmark's linear-acceleration method (conditionally stable); the method is unconditionally
stable for ``theta >= (1 + sqrt 3) / 2 = 1.366`` (Hilber & Hughes 1978), which this module
requires, and ``theta = 1.4`` is the usual choice. It is second-order accurate, with numerical
damping of the high modes (spectral radius 0.68 at dt w -> inf for theta = 1.4) but also more
damping and period error of the low modes than HHT or generalised-alpha at the same step, and
overshoot in the first steps of a high mode (Hilber & Hughes 1978): it is here for comparison
with studies and programs that use it.
"""

import math
from typing import ClassVar, Literal

from pydantic import Field

from pframe.integrators._base import Facts, Implicit
from pframe.integrators.coefficients import Coefficients

#: the smallest theta of unconditional stability, (1 + sqrt 3) / 2
THETA_STABLE = (1.0 + math.sqrt(3.0)) / 2.0


class WilsonTheta(Implicit):
    """Wilson-theta with full Newton iterations."""

    type: Literal["wilson_theta"] = "wilson_theta"
    facts: ClassVar[Facts] = Facts(
        order=2, paths=frozenset({"events", "retry"}),
        examples={"wilson_theta": {"type": "wilson_theta", "theta": 1.4}},
        restitution_tolerance=3e-3, impact_balance_tolerance=1e-10,
        # its numerical damping of the storeys' modes (positive, growing with dt) against the
        # little that evaluating closing contacts past the step end creates
        balance={"wilson_theta": ({"type": "wilson_theta", "theta": 1.4}, (-1e-2, 5e-2))},
        balance_tolerance=1e-10,
        spectral_decay=({"type": "wilson_theta", "theta": 1.4},))
    theta: float = Field(1.4, ge=1.37, le=2.0,
                         description="theta in [1.37, 2] (unconditionally stable from "
                         "(1 + sqrt 3)/2 = 1.366; 1.4 is the usual choice).")

    def coefficients(self):
        return Coefficients(0.5, 1.0 / 6.0, 1.0 - self.theta, 0.0, scheme="wilson_theta",
                            theta=self.theta, opensees=("wilson_theta", self.theta),
                            **self.runs_on())

    def describe(self) -> str:
        return f"wilson_theta(theta={self.theta:.6g})"
