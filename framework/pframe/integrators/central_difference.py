"""Explicit central difference (Newmark gamma = 1/2, beta = 0) with a diagonal mass matrix.

u(n+1) = u + dt v + dt^2 a / 2; the forces at t(n+1) depend on the velocity too (damping,
contact dashpots), so a(n+1) is found from a predicted velocity v + dt a and corrected once
with v(n+1) = v + dt (a + a(n+1)) / 2, which keeps second order with damping. No equation is
solved. Stable only for dt < 2 / w_max, w_max being the highest frequency of the scene with
its contacts closed: pframe refuses a larger step with the limit in the message, or, with
``substeps: auto``, integrates each recorded step in as many sub-steps as the limit needs.
"""

from typing import ClassVar, Literal

from pydantic import Field

from pframe.integrators._base import Facts, IntegratorParams
from pframe.integrators.coefficients import Coefficients


class CentralDifference(IntegratorParams):
    """Explicit central difference."""

    type: Literal["central_difference"] = "central_difference"
    # no Newton iteration to fail nor events to locate: its own path (kernel/c/explicit.c)
    facts: ClassVar[Facts] = Facts(
        order=2, paths=frozenset(),
        examples={"central_difference": {"type": "central_difference"}},
        restitution_tolerance=2e-3, impact_balance_tolerance=1e-10,
        balance={"central_difference": ({"type": "central_difference", "substeps": "auto"},
                                        (-1e-6, 1e-6))},
        # its velocity corrector's O(h^2): about 2e-6 at 4 times the paper's step
        balance_tolerance=1e-5,
        spectral_decay=())
    substeps: Literal["none", "auto"] = Field(
        "none", description="auto: split each step to stay below the stability limit."
    )
    safety: float = Field(0.9, gt=0, le=1, description="Fraction of the stability limit used.")

    def coefficients(self):
        # OpenSees' NewmarkExplicit with gamma = 1/2 (pframe.peers.from_plan says where the
        # two part: forces that depend on velocity)
        return Coefficients(0.5, 0.0, explicit=True, retry=False,
                            opensees=("central_difference",))

    def describe(self) -> str:
        return "central_difference"
