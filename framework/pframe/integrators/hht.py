"""Hilber-Hughes-Taylor alpha method (1977).

``alpha`` in [0, 1/3] is the weight of the previous step in the force terms (OpenSees writes
the same method with its alpha = 1 - ours): alpha_f = alpha, alpha_m = 0,
gamma = 1/2 + alpha, beta = (1 + alpha)^2 / 4. Second order, unconditionally stable, with
numerical damping of the high modes growing with alpha (alpha = 0 is average acceleration).
"""

from typing import Literal

from pydantic import Field

from pframe.integrators._base import Implicit


class HHT(Implicit):
    """HHT-alpha with full Newton iterations."""

    type: Literal["hht"] = "hht"
    alpha: float = Field(0.05, ge=0, le=1.0 / 3.0, description="alpha in [0, 1/3].")

    def coefficients(self):
        from pframe.integrators import Coefficients

        a = self.alpha
        return Coefficients(0.5 + a, 0.25 * (1.0 + a) ** 2, 0.0, a, events=self.events)

    def describe(self) -> str:
        return f"hht(alpha={self.alpha:.6g})"
