"""Time integrators, one small module each.

An integrator module holds the YAML parameters (a pydantic model tagged by ``type``) and turns
them into the coefficients the kernel uses. The implicit ones are members of the
generalised-alpha family (Newmark: alpha_m = alpha_f = 0; HHT: alpha_m = 0): equilibrium

    M a(n+1-alpha_m) + C v(n+1-alpha_f) + F(u(n+1-alpha_f)) = P(t(n+1-alpha_f)),
    x(n+1-alpha) = (1 - alpha) x(n+1) + alpha x(n),

with Newmark's relations for u, v, a and full Newton iterations. Central difference is
explicit (no solve: the mass matrix is diagonal).
"""

from dataclasses import dataclass

from pframe.integrators.central_difference import CentralDifference
from pframe.integrators.generalized_alpha import GeneralizedAlpha
from pframe.integrators.hht import HHT
from pframe.integrators.newmark import Newmark


@dataclass(frozen=True)
class Coefficients:
    """What the kernel needs: Newmark gamma and beta, the alpha weights, explicit or not."""

    gamma: float
    beta: float
    alpha_m: float = 0.0
    alpha_f: float = 0.0
    explicit: bool = False
    events: bool = False

    @property
    def alpha(self) -> bool:
        """Equilibrium off the step end (HHT, generalised-alpha)."""
        return self.alpha_m != 0.0 or self.alpha_f != 0.0


ALL_INTEGRATORS = (Newmark, HHT, GeneralizedAlpha, CentralDifference)

__all__ = ["ALL_INTEGRATORS", "CentralDifference", "Coefficients", "GeneralizedAlpha", "HHT",
           "Newmark"]
