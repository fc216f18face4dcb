"""Newmark's method (1959): average acceleration (gamma 1/2, beta 1/4, the default,
unconditionally stable, second order, no numerical damping) or linear acceleration
(gamma 1/2, beta 1/6, stable for dt <= sqrt(12) / w_max)."""

from typing import Literal

from pydantic import Field, model_validator

from pframe.integrators._base import Implicit


class Newmark(Implicit):
    """Newmark's method with full Newton iterations."""

    type: Literal["newmark"] = "newmark"
    variant: Literal["average_acceleration", "linear_acceleration"] | None = Field(
        None, description="A named member; sets gamma and beta (do not give them too)."
    )
    gamma: float | None = Field(None, ge=0.5, le=1.0, description="Newmark gamma (default 1/2).")
    beta: float | None = Field(None, gt=0, le=0.5, description="Newmark beta (default 1/4).")

    @model_validator(mode="after")
    def _variant_or_coefficients(self):
        if self.variant is not None and (self.gamma is not None or self.beta is not None):
            raise ValueError("give variant or gamma/beta, not both")
        return self

    def coefficients(self):
        from pframe.integrators import Coefficients

        if self.variant == "linear_acceleration":
            return Coefficients(0.5, 1.0 / 6.0, events=self.events)
        gamma = 0.5 if self.gamma is None else self.gamma
        beta = 0.25 if self.beta is None else self.beta
        return Coefficients(gamma, beta, events=self.events)

    def describe(self) -> str:
        c = self.coefficients()
        return f"newmark(gamma={c.gamma:.6g}, beta={c.beta:.6g})"
