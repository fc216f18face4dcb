"""Generalised-alpha method of Chung & Hulbert (1993), set by the spectral radius at infinite
frequency rho_inf in [0, 1]:

    alpha_m = (2 rho - 1) / (rho + 1),  alpha_f = rho / (rho + 1),
    gamma = 1/2 - alpha_m + alpha_f,    beta = (1 - alpha_m + alpha_f)^2 / 4.

Second order and unconditionally stable; rho_inf = 1 is average acceleration, smaller values
damp the high modes (contact chatter) with the least low-mode damping of the family.
"""

from typing import Literal

from pydantic import Field

from pframe.integrators._base import Implicit


class GeneralizedAlpha(Implicit):
    """Chung-Hulbert generalised-alpha with full Newton iterations."""

    type: Literal["generalized_alpha"] = "generalized_alpha"
    rho_infinity: float = Field(0.8, ge=0, le=1, description="Spectral radius at dt w -> inf.")

    def coefficients(self):
        from pframe.integrators import Coefficients

        rho = self.rho_infinity
        am = (2.0 * rho - 1.0) / (rho + 1.0)
        af = rho / (rho + 1.0)
        return Coefficients(0.5 - am + af, 0.25 * (1.0 - am + af) ** 2, am, af,
                            events=self.events)

    def describe(self) -> str:
        return f"generalized_alpha(rho_infinity={self.rho_infinity:.6g})"
