"""What an integrator gives the kernel: its step as data, and the fast path's coefficients."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pframe.integrators.tableau import Tableau, newmark, wilson


@dataclass(frozen=True)
class Coefficients:
    """An integrator's step for the kernel.

    ``tableau`` is the method as data (:mod:`pframe.integrators.tableau`); the kernel runs it
    with one generic stage loop (``scheme="tableau"``). The schemes of one Newmark stage
    (``"alpha_family"``: Newmark, HHT, generalised-alpha; ``"wilson_theta"``) have a fast
    path in the kernel, written with Newmark's ``gamma`` and ``beta``, the alpha weights and
    Wilson's ``theta``; their tableau (built from those when not given) is the same method,
    which the tests hold the fast path to (to round-off). ``retry``: a step whose Newton
    iteration fails is retried in sub-steps (else the run stops there); ``events``: contact
    events are located inside steps. ``opensees``: the method as the OpenSees peer writes it
    (:class:`pframe.peers.scene.PeerScene`'s ``integrator``), or why it cannot.
    """

    gamma: float = math.nan
    beta: float = math.nan
    alpha_m: float = 0.0
    alpha_f: float = 0.0
    explicit: bool = False
    events: bool = False
    scheme: str = "alpha_family"
    theta: float = 1.0
    tableau: Tableau | None = None
    retry: bool = True
    opensees: tuple | str = "OpenSees has no counterpart of this integrator"

    def __post_init__(self):
        if self.tableau is None:
            if self.scheme == "alpha_family":
                own = newmark(self.gamma, self.beta, self.alpha_m, self.alpha_f)
            elif self.scheme == "wilson_theta":
                own = wilson(self.theta, self.gamma, self.beta)
            else:
                raise ValueError(f"the scheme {self.scheme!r} needs its tableau")
            object.__setattr__(self, "tableau", own)
        if not self.explicit and not all(stage.implicit for stage in self.tableau.stages):
            raise ValueError("an implicit integrator's stages must each solve for their own "
                             "acceleration (end and evaluated displacement depend on it)")

    @property
    def alpha(self) -> bool:
        """Equilibrium off the end of some stage (HHT, generalised-alpha, Wilson-theta)."""
        if self.scheme == "tableau":
            return self.tableau.off_end
        return self.alpha_m != 0.0 or self.alpha_f != 0.0 or self.scheme != "alpha_family"

    @property
    def stages(self) -> int:
        return len(self.tableau.stages)

    def amplification(self, w_h: float) -> np.ndarray:
        """The amplification matrix of an undamped vibration of circular frequency w integrated
        with step h (``w_h`` = w h): ``x(n+1) = A x(n)`` for ``x = (u, h v, h^2 a)``."""
        return self.tableau.amplification(w_h)

    def spectral_radius(self, w_h: float) -> float:
        """The largest modulus of the amplification matrix's eigenvalues at ``w_h`` = w h."""
        return self.tableau.spectral_radius(w_h)

    def describe_scheme(self) -> str:
        """How the kernel steps, in words (the result file's ``integrator_scheme``)."""
        if self.explicit:
            return "explicit (central difference, diagonal mass)"
        stages = self.stages
        ends = ", ".join(f"{stage.end:.6g}" for stage in self.tableau.stages)
        return f"{self.scheme}: {stages} implicit stage{'s' if stages > 1 else ''} ending at " \
               f"t + ({ends}) h"
