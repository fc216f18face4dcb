"""Hertzdamp contact: Hertz spring with delta^1.5-proportional damping.

F = k delta^1.5 + xi delta^1.5 delta_dot with xi = chi k / v0, i.e. the Hunt-Crossley form with
n = 3/2 (v0 never below the energy velocity of the contact: see docs/restitution.md). Two
published damping formulas are offered:

- ``muthukumar`` (Muthukumar & DesRoches 2006): xi = 3 k (1 - e^2) / (4 v0), chi = 3 (1 - e^2) / 4;
- ``ye`` (Ye, Li & Zhu 2009): xi = 8 k (1 - e) / (5 e v0), chi = 8 (1 - e) / (5 e).

``calibration: exact`` uses neither: chi is the root of chi (1 + e) = ln((1 + chi) / (1 - chi e)),
with which a two-body impact rebounds with e itself (``formula`` is then irrelevant).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws.contact._hunt_crossley import PARAM_NAMES, STATE_NAMES, hunt_crossley_force
from pframe.laws.params import (
    HERTZ_STIFFNESS,
    Calibration,
    DampedRestitution,
    LawParams,
    Positive,
)
from pframe.laws.registry import HertzContact, contact_law
from pframe.laws.restitution import hunt_crossley_chi, hunt_crossley_restitution

CHI_FORMULAS = {
    "muthukumar": lambda e: 0.75 * (1.0 - e * e),
    "ye": lambda e: 1.6 * (1.0 - e) / e,
}


@contact_law("hertzdamp")
class Hertzdamp(HertzContact):
    class Params(LawParams):
        law: Literal["hertzdamp"]
        stiffness: Positive = Field(description=HERTZ_STIFFNESS)
        restitution: DampedRestitution
        formula: Literal["muthukumar", "ye"] = Field(
            "muthukumar", description="Published damping formula: Muthukumar & DesRoches 2006 "
                                      "or Ye 2009 (used with calibration: published)."
        )
        calibration: Calibration = "published"

    param_names = PARAM_NAMES
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)
    branches = "hunt_crossley"

    @classmethod
    def chi(cls, params) -> float:
        e = params.restitution
        if params.calibration == "exact":
            return hunt_crossley_chi(e)
        return CHI_FORMULAS[params.formula](e)

    @classmethod
    def published_source(cls, params) -> str:
        return {"muthukumar": "Muthukumar & DesRoches 2006", "ye": "Ye, Li & Zhu 2009"}[
            params.formula]

    @classmethod
    def rebound(cls, params) -> float:
        """The restitution of a two-body impact with this damping (docs/restitution.md)."""
        return hunt_crossley_restitution(cls.chi(params))

    @classmethod
    def pack(cls, params, context=None):
        inverse_mass = 0.0 if context is None else 1.0 / context.effective_mass
        return (float(params.stiffness), 1.5, cls.chi(params), inverse_mass)
