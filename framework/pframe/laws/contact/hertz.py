"""Hertz contact: F = k delta^1.5 for delta > 0, elastic (restitution 1).

``stiffness`` is k in N/m^1.5.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.facts import Impact
from pframe.laws.params import HERTZ_STIFFNESS, LawParams, Positive
from pframe.laws.registry import HertzContact, contact_law


@contact_law("hertz")
class Hertz(HertzContact):
    class Params(LawParams):
        law: Literal["hertz"]
        stiffness: Positive = Field(description=HERTZ_STIFFNESS)

    free_when_open = True
    param_names = ("stiffness",)
    branches = "gap"
    opensees = "Hertzdamp"  # without damping (pframe.peers.twins)
    examples = ({"stiffness": 1.0e9},)
    impacts = {"hertz": Impact({"stiffness": 1.0e9}, "`hertz`")}

    @classmethod
    def reference_force(cls, params, context, v0):
        """F = k delta^1.5 (Hertz)."""
        k = params.stiffness
        return lambda x, r: k * x**1.5

    @classmethod
    def rebound(cls, params) -> float:
        """Elastic: 1."""
        return 1.0

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        root = math.sqrt(deformation)
        return params[0] * deformation * root, 1.5 * params[0] * root, 0.0
