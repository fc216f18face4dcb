"""Generalised-alpha method of Chung & Hulbert (1993), set by the spectral radius at infinite
frequency rho_inf in [0, 1]:

    alpha_m = (2 rho - 1) / (rho + 1),  alpha_f = rho / (rho + 1),
    gamma = 1/2 - alpha_m + alpha_f,    beta = (1 - alpha_m + alpha_f)^2 / 4.

Second order and unconditionally stable; rho_inf = 1 is average acceleration, smaller values
damp the high modes (contact chatter) with the least low-mode damping of the family.
"""

from typing import ClassVar, Literal

from pydantic import Field

from pframe.integrators._base import Facts, Implicit
from pframe.integrators.coefficients import Coefficients


class GeneralizedAlpha(Implicit):
    """Chung-Hulbert generalised-alpha with full Newton iterations."""

    type: Literal["generalized_alpha"] = "generalized_alpha"
    facts: ClassVar[Facts] = Facts(
        order=2, paths=frozenset({"events", "retry"}),
        examples={"generalized_alpha": {"type": "generalized_alpha", "rho_infinity": 0.6}},
        restitution_tolerance=2e-3, impact_balance_tolerance=1e-10,
        balance={"generalized_alpha": ({"type": "generalized_alpha", "rho_infinity": 0.8},
                                       (-1e-2, 0.0)),
                 "generalized_alpha-0": ({"type": "generalized_alpha", "rho_infinity": 0.0},
                                         (1e-4, float("inf")))},
        balance_tolerance=1e-10,
        spectral_decay=({"type": "generalized_alpha", "rho_infinity": 0.5},))
    rho_infinity: float = Field(0.8, ge=0, le=1, description="Spectral radius at dt w -> inf.")

    def coefficients(self):
        rho = self.rho_infinity
        am = (2.0 * rho - 1.0) / (rho + 1.0)
        af = rho / (rho + 1.0)
        gamma, beta = 0.5 - am + af, 0.25 * (1.0 - am + af) ** 2
        # OpenSees' HHTGeneralized is the method (its GeneralizedAlpha is not:
        # pframe.peers.opensees)
        return Coefficients(gamma, beta, am, af,
                            opensees=("generalized_alpha", am, af, gamma, beta),
                            **self.runs_on())

    def describe(self) -> str:
        return f"generalized_alpha(rho_infinity={self.rho_infinity:.6g})"
