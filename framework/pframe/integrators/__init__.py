"""Time integrators, one small module each.

An integrator module holds the YAML parameters (a pydantic model tagged by ``type``) and turns
them into the coefficients the kernel uses. The implicit ones are members of the
generalised-alpha family (Newmark: alpha_m = alpha_f = 0; HHT: alpha_m = 0): equilibrium

    M a(n+1-alpha_m) + C v(n+1-alpha_f) + F(u(n+1-alpha_f)) = P(t(n+1-alpha_f)),
    x(n+1-alpha) = (1 - alpha) x(n+1) + alpha x(n),

with Newmark's relations for u, v, a and full Newton iterations. Wilson-theta imposes
equilibrium at t + theta dt, outside the step (its own scheme in the kernel). Central
difference is explicit (no solve: the mass matrix is diagonal).

An integrator is one unit: its parameters and :class:`Coefficients` here, its amplification
matrix (:meth:`Coefficients.amplification`, from which the dt checks take its period error),
and in the C kernel one scheme of ``kernel/c/integrator.c`` (end relations, evaluation point,
effective-stiffness weights; the energy form follows from them).
"""

from dataclasses import dataclass

import numpy as np

from pframe.integrators.central_difference import CentralDifference
from pframe.integrators.generalized_alpha import GeneralizedAlpha
from pframe.integrators.hht import HHT
from pframe.integrators.newmark import Newmark
from pframe.integrators.wilson_theta import WilsonTheta

#: the kernel's implicit schemes (pframe.kernel.state.ALPHA_FAMILY, WILSON_THETA)
SCHEMES = ("alpha_family", "wilson_theta")


@dataclass(frozen=True)
class Coefficients:
    """What the kernel needs: Newmark gamma and beta (the end relations), the alpha weights,
    the scheme and its theta, explicit or not."""

    gamma: float
    beta: float
    alpha_m: float = 0.0
    alpha_f: float = 0.0
    explicit: bool = False
    events: bool = False
    scheme: str = "alpha_family"
    theta: float = 1.0

    @property
    def alpha(self) -> bool:
        """Equilibrium off the step end (HHT, generalised-alpha, Wilson-theta)."""
        return self.alpha_m != 0.0 or self.alpha_f != 0.0 or self.scheme != "alpha_family"

    def amplification(self, w_h: float) -> np.ndarray:
        """The amplification matrix of an undamped vibration of circular frequency w integrated
        with step h (``w_h`` = w h): ``x(n+1) = A x(n)`` for ``x = (u, h v, h^2 a)``."""
        g, b, am, af = self.gamma, self.beta, self.alpha_m, self.alpha_f
        W = w_h * w_h
        # Newmark's end relations (the first two rows), then equilibrium where the scheme
        # imposes it
        lhs = np.array([[1.0, 0.0, -b], [0.0, 1.0, -g], [0.0, 0.0, 0.0]])
        rhs = np.array([[1.0, 1.0, 0.5 - b], [0.0, 1.0, 1.0 - g], [0.0, 0.0, 0.0]])
        if self.scheme == "wilson_theta":
            th = self.theta
            # (1 - th) a + th a' + w^2 [u + th h v + th^2 (1/2 - b th) h^2 a + b th^3 h^2 a'] = 0
            lhs[2] = [0.0, 0.0, th + W * b * th ** 3]
            rhs[2] = [-W, -W * th, -(1.0 - th) - W * th * th * (0.5 - b * th)]
        else:
            lhs[2] = [W * (1.0 - af), 0.0, 1.0 - am]
            rhs[2] = [-W * af, 0.0, -am]
        return np.linalg.solve(lhs, rhs)

    def spectral_radius(self, w_h: float) -> float:
        """The largest modulus of the amplification matrix's eigenvalues at ``w_h`` = w h."""
        return float(np.max(np.abs(np.linalg.eigvals(self.amplification(w_h)))))


ALL_INTEGRATORS = (Newmark, HHT, GeneralizedAlpha, WilsonTheta, CentralDifference)

__all__ = ["ALL_INTEGRATORS", "SCHEMES", "CentralDifference", "Coefficients",
           "GeneralizedAlpha", "HHT", "Newmark", "WilsonTheta"]
