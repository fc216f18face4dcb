"""Newmark's method (1959): average acceleration (gamma 1/2, beta 1/4, the default,
unconditionally stable, second order, no numerical damping) or linear acceleration
(gamma 1/2, beta 1/6, stable for dt <= sqrt(12) / w_max)."""

from typing import ClassVar, Literal

from pydantic import Field, model_validator

from pframe.integrators._base import Facts, Implicit
from pframe.integrators.coefficients import Coefficients


class Newmark(Implicit):
    """Newmark's method with full Newton iterations."""

    type: Literal["newmark"] = "newmark"
    facts: ClassVar[Facts] = Facts(
        order=2, paths=frozenset({"events", "retry"}),
        examples={"average_acceleration": {"type": "newmark"},
                  "linear_acceleration": {"type": "newmark", "variant": "linear_acceleration"}},
        restitution_tolerance=2e-3, impact_balance_tolerance=1e-10,
        balance={"newmark": ({"type": "newmark"}, (-1e-6, 1e-6)),
                 "newmark-gamma-0.6": ({"type": "newmark", "gamma": 0.6, "beta": 0.3025},
                                       (1e-4, float("inf"))),
                 "newmark-events": ({"type": "newmark", "events": True}, (-1e-6, 1e-6))},
        balance_tolerance=1e-10,
        spectral_decay=({"type": "newmark", "gamma": 0.6, "beta": 0.3025},))
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
        if self.variant == "linear_acceleration":
            gamma, beta = 0.5, 1.0 / 6.0
        else:
            gamma = 0.5 if self.gamma is None else self.gamma
            beta = 0.25 if self.beta is None else self.beta
        return Coefficients(gamma, beta, opensees=("newmark", gamma, beta), **self.runs_on())

    def describe(self) -> str:
        c = self.coefficients()
        return f"newmark(gamma={c.gamma:.6g}, beta={c.beta:.6g})"
