"""Linear elastic storey: V = k drift."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws.facts import TangentState
from pframe.laws.params import LawParams, Positive
from pframe.laws.registry import Law, material


@material("elastic")
class Elastic(Law):
    class Params(LawParams):
        material: Literal["elastic"]
        stiffness: Positive = Field(description="Storey stiffness k (N/m).")

    param_names = ("stiffness",)
    dimensions = {"stiffness": "stiffness"}
    branches = "smooth"
    opensees = "Elastic"
    examples = ({"stiffness": 2.0e6}, {"stiffness": 1.0e5})

    @classmethod
    def tangent_states(cls, packed):
        """Drifts both ways: the tangent is k, rate independent."""
        return [TangentState((), x, 0.1, tangent=packed[0], rate_tangent=0.0)
                for x in (-0.02, 0.003, 0.05)]

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """The storey stiffness K."""
        return {"K": ("stiffness", packed[0])}

    linear = True

    @classmethod
    def post_yield_stiffness(cls, packed):
        """k: it never yields."""
        return packed[0]

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness),)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        return params[0] * deformation, params[0], 0.0
