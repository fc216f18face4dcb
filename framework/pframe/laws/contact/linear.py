"""Linear compression-only spring: F = k delta for delta > 0 (no damping).

The same law as OpenSees ``ElasticPPGap`` with an unreachable yield force; it conserves energy
(restitution 1).
"""

from __future__ import annotations

from typing import Literal

from pframe.laws.facts import Impact
from pframe.laws.params import ContactStiffness
from pframe.laws.registry import SpringContact, contact_law


@contact_law("linear")
class Linear(SpringContact):
    class Params(ContactStiffness):
        law: Literal["linear"]

    free_when_open = True
    param_names = ("stiffness",)
    branches = "gap"
    opensees = "ElasticPPGap"
    examples = ({"stiffness": 2.0e7}, {"stiffness": 2.0e6})
    impacts = {"linear": Impact({"stiffness": 1.0e7}, "`linear`")}

    @classmethod
    def reference_force(cls, params, context, v0):
        """F = k delta."""
        k = params.resolve_stiffness(context)
        return lambda x, r: k * x

    @classmethod
    def rebound(cls, params) -> float:
        """Elastic: 1."""
        return 1.0

    @classmethod
    def pack(cls, params, context=None):
        return (params.resolve_stiffness(context),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        return params[0] * deformation, params[0], 0.0
