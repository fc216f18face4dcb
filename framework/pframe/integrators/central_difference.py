"""Explicit central difference (Newmark gamma = 1/2, beta = 0) with a diagonal mass matrix.

u(n+1) = u + dt v + dt^2 a / 2; the forces at t(n+1) depend on the velocity too (damping,
contact dashpots), so a(n+1) is found from a predicted velocity v + dt a and corrected once
with v(n+1) = v + dt (a + a(n+1)) / 2, which keeps second order with damping. No equation is
solved. Stable only for dt < 2 / w_max, w_max being the highest frequency of the scene with
its contacts closed: pframe refuses a larger step with the limit in the message, or, with
``substeps: auto``, integrates each recorded step in as many sub-steps as the limit needs.
"""

from typing import Literal

from pydantic import Field

from pframe.integrators._base import IntegratorParams


class CentralDifference(IntegratorParams):
    """Explicit central difference."""

    type: Literal["central_difference"] = "central_difference"
    substeps: Literal["none", "auto"] = Field(
        "none", description="auto: split each step to stay below the stability limit."
    )
    safety: float = Field(0.9, gt=0, le=1, description="Fraction of the stability limit used.")

    def coefficients(self):
        from pframe.integrators import Coefficients

        return Coefficients(0.5, 0.0, explicit=True)

    def describe(self) -> str:
        return "central_difference"
