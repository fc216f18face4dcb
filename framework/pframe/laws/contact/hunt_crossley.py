"""Hunt-Crossley contact with a general exponent (Hunt & Crossley 1975).

    F = k delta^n (1 + chi delta' / v0),    chi = 3 (1 - e) / 2,

never pulling. Hunt & Crossley (1975, "Coefficient of restitution interpreted as damping in
vibroimpact", J. Appl. Mech. 42(2), 440-445) write the force k delta^n + lambda delta^n delta'
with lambda = 3 alpha k / 2 and e = 1 - alpha v0, a restitution that falls linearly with the
approach velocity v0: lambda = 3 k (1 - e) / (2 v0), the form above. n is the contact's own:
1 a linear spring (``improved_kelvin``'s force with another chi), 3/2 Hertz (``hertzdamp``'s),
other values for measured force-indentation curves. v0 is the approach velocity at onset, never
below the energy velocity of the contact (docs/restitution.md): the force of
``_hunt_crossley.py``.

A two-body impact rebounds with the root e' of chi (1 + e') = ln((1 + chi) / (1 - chi e')),
whatever n (docs/restitution.md): Hunt and Crossley's chi, from the linear e(v0) of slow
impacts, rebounds with more than e (0.62 for e = 0.4; pframe warns of it), and is exact only
as e -> 1. ``calibration: exact`` packs the chi whose impact rebounds with e itself.
``stiffness`` is k in N/m^n, a unit that depends on n: ``pframe scale`` refuses it.
"""

from __future__ import annotations

from fractions import Fraction
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
from pframe.laws.params import Calibration, DampedRestitution, LawParams, Positive
from pframe.laws.registry import Law, contact_law
from pframe.laws.restitution import hunt_crossley_chi


@contact_law("hunt_crossley")
class HuntCrossley(Law):
    class Params(LawParams):
        law: Literal["hunt_crossley"]
        stiffness: Positive = Field(description="k of F = k delta^n (N/m^n).")
        exponent: float = Field(gt=0, le=3, description="n of F = k delta^n (1: linear, "
                                                        "1.5: Hertz).")
        restitution: DampedRestitution
        calibration: Calibration = "published"

    free_when_open = True
    param_names = PARAM_NAMES
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)
    branches = "hunt_crossley"
    opensees = "Hertzdamp"  # but in conditions (pframe.peers.twins)
    dimensions = {"exponent": "dimensionless", "restitution": "dimensionless"}
    undimensioned = {"stiffness": "the stiffness of hunt_crossley is in N/m^n, a dimension that "
                                  "depends on n; scale it by hand (by S_F S_L^-n)"}
    tangent_states = classmethod(hunt_crossley_tangent_states)

    @classmethod
    def dimensions_given(cls, given: dict) -> dict[str, str]:
        """k in N/m^n for the exponent n as written (docs/units.md)."""
        n = given.get("exponent")
        if isinstance(n, bool) or not isinstance(n, (int, float)) or not n > 0:
            return {}  # validation names the exponent
        return {"stiffness": f"N/m^({Fraction(n).limit_denominator(1000)})"}

    examples = ({"stiffness": 1.0e9, "exponent": 1.5, "restitution": 0.6},
                {"stiffness": 3.0e7, "exponent": 1.2, "restitution": 0.5},
                {"stiffness": 1.0e12, "exponent": 2.0, "restitution": 0.5, "calibration": "exact"})
    impacts = {"hunt_crossley": Impact({"stiffness": 3.0e8, "exponent": 1.3},
                                       "`hunt_crossley`, `exponent: 1.3`")}

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """k_n (N/m^n, the dimension its exponent n gives it) and n (the restitution e, which
        fixes chi, is the scene's own variable)."""
        k, n = packed[0], packed[1]
        return {"k_n": (f"N/m^{n!r}", k), "n": ("dimensionless", n)}

    @classmethod
    def chi(cls, params) -> float:
        e = params.restitution
        return hunt_crossley_chi(e) if params.calibration == "exact" else 1.5 * (1.0 - e)

    @classmethod
    def published_source(cls, params) -> str:
        return "Hunt & Crossley 1975"

    rebound = classmethod(hunt_crossley_rebound)

    @classmethod
    def pack(cls, params, context=None):
        inverse_mass = impact_inverse_mass(context)
        return (float(params.stiffness), float(params.exponent), cls.chi(params), inverse_mass)

    @classmethod
    def reference_force(cls, params, context, v0):
        """Hunt & Crossley (1975): F = k delta^n + lambda delta^n delta', never pulling, with
        lambda = 3 k (1 - e) / (2 v0) (``calibration: exact``: lambda = chi k / v0 with the
        law's chi)."""
        k, n, e = params.stiffness, params.exponent, params.restitution
        lam = (3.0 * k * (1.0 - e) / (2.0 * v0) if params.calibration == "published"
               else cls.chi(params) * k / v0)
        return lambda x, r: max(k * x**n + lam * x**n * r, 0.0)
