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

from pframe.laws.contact._hunt_crossley import (
    PARAM_NAMES,
    STATE_NAMES,
    hunt_crossley_force,
    hunt_crossley_rebound,
    hunt_crossley_tangent_states,
    impact_inverse_mass,
)
from pframe.laws.facts import Impact
from pframe.laws.params import (
    HERTZ_STIFFNESS,
    Calibration,
    DampedRestitution,
    LawParams,
    Positive,
)
from pframe.laws.registry import HertzContact, contact_law
from pframe.laws.restitution import hunt_crossley_chi

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

    free_when_open = True
    param_names = PARAM_NAMES
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)
    branches = "hunt_crossley"
    opensees = "Hertzdamp"  # but in conditions (pframe.peers.twins)
    tangent_states = classmethod(hunt_crossley_tangent_states)
    examples = ({"stiffness": 1.0e9, "restitution": 0.6},
                {"stiffness": 1.0e9, "restitution": 0.5, "formula": "muthukumar"},
                {"stiffness": 1.0e9, "restitution": 0.5, "formula": "ye"})
    impacts = {
        "hertzdamp-muthukumar": Impact({"stiffness": 1.0e9, "formula": "muthukumar"},
                                       "`hertzdamp`, `formula: muthukumar`",
                                       calibrations=("published",)),
        "hertzdamp-ye": Impact({"stiffness": 1.0e9, "formula": "ye"}, "`hertzdamp`, `formula: ye`",
                               descriptions={"exact": "exact (either formula)"},
                               exact_label="`hertzdamp`"),
    }

    @classmethod
    def reference_force(cls, params, context, v0):
        """F = k delta^1.5 + xi delta^1.5 delta', never pulling, with Muthukumar & DesRoches'
        xi = 3 k (1 - e^2) / (4 v0) or Ye, Li & Zhu's xi = 8 k (1 - e) / (5 e v0)
        (``calibration: exact``: xi = chi k / v0 with the law's chi)."""
        k = params.stiffness
        e = params.restitution
        if params.calibration == "exact":
            xi = cls.chi(params) * k / v0
        elif params.formula == "muthukumar":
            xi = 3.0 * k * (1.0 - e * e) / (4.0 * v0)
        else:
            xi = 8.0 * k * (1.0 - e) / (5.0 * e * v0)
        return lambda x, r: max(k * x**1.5 + xi * x**1.5 * r, 0.0)

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

    rebound = classmethod(hunt_crossley_rebound)

    @classmethod
    def pack(cls, params, context=None):
        inverse_mass = impact_inverse_mass(context)
        return (float(params.stiffness), 1.5, cls.chi(params), inverse_mass)
