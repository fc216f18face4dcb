"""Nonlinear viscoelastic contact, Jankowski (2005).

F = beta delta^1.5 + c delta_dot during approach (delta_dot > 0), F = beta delta^1.5 in
restitution, with c = 2 zeta sqrt(beta sqrt(delta) m1 m2 / (m1 + m2)) and
zeta = 9 sqrt(5) / 2 * (1 - e^2) / (e (e (9 pi - 16) + 16)).

Scaling delta by (v0^2 m_eff / beta)^(2/5) and time by that length over v0 turns the impact
into x'' = -x^1.5 - 2 zeta x^(1/4) x' (approach), x'' = -x^1.5 (restitution): its restitution
depends on zeta alone, not on beta, the masses or v0. The published zeta is an approximation
(it rebounds with 0.393 for e = 0.4); ``calibration: exact`` finds the zeta of e by
integrating that impact (``pframe.laws.restitution.jankowski_zeta_exact``, once per e).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.facts import Impact
from pframe.laws.params import (
    HERTZ_STIFFNESS,
    Calibration,
    DampedRestitution,
    LawParams,
    Positive,
)
from pframe.laws.registry import HertzContact, contact_law
from pframe.laws.restitution import jankowski_restitution, jankowski_zeta_exact


def jankowski_zeta(e: float) -> float:
    """Damping ratio of Jankowski's law for restitution e."""
    return 4.5 * math.sqrt(5.0) * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0) + 16.0))


@contact_law("jankowski")
class Jankowski(HertzContact):
    class Params(LawParams):
        law: Literal["jankowski"]
        stiffness: Positive = Field(description="Impact stiffness beta: " + HERTZ_STIFFNESS)
        restitution: DampedRestitution
        calibration: Calibration = "published"

    free_when_open = True
    param_names = ("stiffness", "zeta", "effective_mass")
    branches = "jankowski"
    opensees = "JankowskiImpact"
    examples = ({"stiffness": 1.0e9, "restitution": 0.6}, {"stiffness": 1.0e9, "restitution": 0.5})
    # the damping c ~ delta^(1/4) makes the onset force non-smooth: the kernel's e converges
    # as about dt^1.25 (measured at 1000 .. 8000 steps per contact: 1.9e-4, 8.1e-5, 3.4e-5,
    # 1.4e-5)
    impacts = {"jankowski": Impact({"stiffness": 1.0e9}, "`jankowski`", tolerance=1e-4)}

    @classmethod
    def reference_force(cls, params, context, v0):
        """Jankowski (2005): F = beta delta^1.5 + c delta' while approaching, beta delta^1.5
        in restitution, c = 2 zeta sqrt(beta sqrt(delta) m_eff),
        zeta = 9 sqrt(5) / 2 (1 - e^2) / (e (e (9 pi - 16) + 16)) (``calibration: exact``:
        the law's zeta)."""
        beta = params.stiffness
        e = params.restitution
        zeta = (9.0 * math.sqrt(5.0) / 2.0 * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0)
                                                                  + 16.0))
                if params.calibration == "published" else cls.zeta(params))
        m_eff = context.effective_mass

        def force(x, r):
            c = 2.0 * zeta * math.sqrt(beta * math.sqrt(x) * m_eff)
            return beta * x**1.5 + (c * r if r > 0.0 else 0.0)

        return force

    @classmethod
    def zeta(cls, params) -> float:
        e = params.restitution
        return jankowski_zeta_exact(e) if params.calibration == "exact" else jankowski_zeta(e)

    @classmethod
    def published_source(cls, params) -> str:
        return "Jankowski 2005"

    @classmethod
    def rebound(cls, params) -> float:
        """The restitution of a two-body impact with this damping (docs/restitution.md)."""
        return jankowski_restitution(cls.zeta(params))

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness), cls.zeta(params), context.effective_mass)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        beta = params[0]
        root = math.sqrt(deformation)
        spring = beta * deformation * root
        dspring = 1.5 * beta * root
        if rate <= 0.0:
            return spring, dspring, 0.0
        c = 2.0 * params[1] * math.sqrt(beta * root * params[2])
        return spring + c * rate, dspring + 0.25 * c * rate / deformation, c
