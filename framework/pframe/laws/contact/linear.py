"""Linear compression-only spring: F = k delta for delta > 0 (no damping).

The same law as OpenSees ``ElasticPPGap`` with an unreachable yield force; it conserves energy
(restitution 1).
"""

from __future__ import annotations

from typing import Literal

from pframe.laws.params import ContactStiffness
from pframe.laws.registry import SpringContact, contact_law


@contact_law("linear")
class Linear(SpringContact):
    class Params(ContactStiffness):
        law: Literal["linear"]

    param_names = ("stiffness",)
    branches = "gap"
    opensees = "ElasticPPGap"

    @classmethod
    def pack(cls, params, context=None):
        return (params.resolve_stiffness(context),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        return params[0] * deformation, params[0], 0.0
