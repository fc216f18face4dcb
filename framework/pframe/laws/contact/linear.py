"""Linear compression-only spring: F = k delta for delta > 0 (no damping).

The same law as OpenSees ``ElasticPPGap`` with an unreachable yield force; it conserves energy
(restitution 1).
"""

from __future__ import annotations

import math
from typing import Literal

from pframe.laws.params import ContactStiffness
from pframe.laws.registry import Law, contact_law


@contact_law("linear")
class Linear(Law):
    class Params(ContactStiffness):
        law: Literal["linear"]

    param_names = ("stiffness",)
    branches = "gap"
    opensees = "ElasticPPGap"
    dimensions = {"stiffness": "stiffness", "frequency": "frequency",
                  "frequency_ratio": "dimensionless", "restitution": "dimensionless"}

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """The contact frequency w_bar = sqrt(k / m_eff) (Wu et al. 2021)."""
        return {"w_bar": ("frequency", math.sqrt(packed[0] / effective_mass))}


    @classmethod
    def pack(cls, params, context=None):
        return (params.resolve_stiffness(context),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        return params[0] * deformation, params[0], 0.0
