"""Hertzdamp contact: Hertz spring with delta^1.5-proportional damping.

F = k delta^1.5 + xi delta^1.5 delta_dot with xi = chi k / v0, i.e. the Hunt-Crossley form with
n = 3/2. Two published damping formulas are offered:

- ``muthukumar`` (Muthukumar & DesRoches 2006): xi = 3 k (1 - e^2) / (4 v0), chi = 3 (1 - e^2) / 4;
- ``ye`` (Ye, Li & Zhu 2009): xi = 8 k (1 - e) / (5 e v0), chi = 8 (1 - e) / (5 e).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws.contact._hunt_crossley import STATE_NAMES, hunt_crossley_force
from pframe.laws.params import LawParams, Positive, Restitution
from pframe.laws.registry import Law, contact_law

CHI_FORMULAS = {
    "muthukumar": lambda e: 0.75 * (1.0 - e * e),
    "ye": lambda e: 1.6 * (1.0 - e) / e,
}


@contact_law("hertzdamp")
class Hertzdamp(Law):
    class Params(LawParams):
        law: Literal["hertzdamp"]
        stiffness: Positive = Field(description="Hertz stiffness k (N/m^1.5).")
        restitution: Restitution
        formula: Literal["muthukumar", "ye"] = Field(
            "muthukumar", description="Damping formula: Muthukumar & DesRoches 2006 or Ye 2009."
        )

    param_names = ("stiffness", "exponent", "chi")
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness), 1.5, CHI_FORMULAS[params.formula](params.restitution))
