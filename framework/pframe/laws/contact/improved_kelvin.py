"""Improved (modified) Kelvin contact, Ye, Li & Zhu (2009), as used by Wu et al. (2021).

F = k delta + xi delta delta_dot, xi = 3 k (1 - e) / (2 e v0)  (paper eqs. 1-3), i.e. the
Hunt-Crossley form with n = 1 and chi = 3 (1 - e) / (2 e). v0 is the approach velocity at
contact onset (never below the energy velocity of the contact: see docs/restitution.md). The
force never jumps at onset and does not pull in rebound.

``calibration: exact`` replaces the published chi, whose two-body impact rebounds with a
restitution somewhat below e (0.38 for e = 0.4), by the root of
chi (1 + e) = ln((1 + chi) / (1 - chi e)), with which it rebounds with e itself.
"""

from __future__ import annotations

from typing import Literal

from pframe.laws.contact._hunt_crossley import (
    PARAM_NAMES,
    STATE_NAMES,
    hunt_crossley_force,
    hunt_crossley_rebound,
    hunt_crossley_tangent_states,
)
from pframe.laws.facts import Impact
from pframe.laws.params import Calibration, ContactStiffness, DampedRestitution
from pframe.laws.registry import SpringContact, contact_law
from pframe.laws.restitution import hunt_crossley_chi


def ye_chi(e: float) -> float:
    """chi = 3 (1 - e) / (2 e), Ye, Li & Zhu (2009)."""
    return 1.5 * (1.0 - e) / e


@contact_law("improved_kelvin")
class ImprovedKelvin(SpringContact):
    class Params(ContactStiffness):
        law: Literal["improved_kelvin"]
        restitution: DampedRestitution
        calibration: Calibration = "published"

    free_when_open = True
    param_names = PARAM_NAMES
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)
    branches = "hunt_crossley"
    opensees = "Hertzdamp"  # n = 1, but in conditions (pframe.peers.twins)
    tangent_states = classmethod(hunt_crossley_tangent_states)
    examples = ({"stiffness": 2.0e7, "restitution": 0.6},
                {"frequency_ratio": 30.0, "restitution": 0.5})
    impacts = {"improved_kelvin": Impact({"stiffness": 1.0e7}, "`improved_kelvin`")}

    @classmethod
    def reference_force(cls, params, context, v0):
        """Ye, Li & Zhu (2009): F = k delta + xi delta delta', xi = 3 k (1 - e) / (2 e v0),
        never pulling (``calibration: exact``: xi = chi k / v0 with the law's chi)."""
        k = params.resolve_stiffness(context)
        e = params.restitution
        xi = (3.0 * k * (1.0 - e) / (2.0 * e * v0) if params.calibration == "published"
              else cls.chi(params) * k / v0)
        return lambda x, r: max(k * x + xi * x * r, 0.0)

    @classmethod
    def chi(cls, params) -> float:
        e = params.restitution
        return hunt_crossley_chi(e) if params.calibration == "exact" else ye_chi(e)

    @classmethod
    def published_source(cls, params) -> str:
        return "Ye, Li & Zhu 2009"

    rebound = classmethod(hunt_crossley_rebound)

    @classmethod
    def pack(cls, params, context=None):
        return (params.resolve_stiffness(context), 1.0, cls.chi(params),
                1.0 / context.effective_mass)
