"""Bilinear storey with kinematic hardening (OpenSees Steel01 without isotropic hardening).

Elastic stiffness k, yield force f_y = k u_y, post-yield stiffness alpha k. The force stays
between the two bounding lines alpha k u +/- (1 - alpha) f_y and moves with slope k inside
them (Penzien 1962; the paper's bilinear inter-storey model). alpha = 0 is elastic-perfectly
plastic.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from pframe.laws.facts import TangentState
from pframe.laws.params import LawParams, Positive
from pframe.laws.registry import Law, material


@material("bilinear")
class Bilinear(Law):
    class Params(LawParams):
        material: Literal["bilinear"]
        stiffness: Positive = Field(description="Initial storey stiffness k (N/m).")
        yield_drift: Positive | None = Field(None, description="Yield drift u_y (m).")
        yield_force: Positive | None = Field(None, description="Yield force f_y = k u_y (N).")
        alpha: float = Field(ge=0, le=1, description="Post-yield stiffness ratio.")

        @model_validator(mode="after")
        def _one_yield(self):
            if (self.yield_drift is None) == (self.yield_force is None):
                raise ValueError("give exactly one of yield_drift (m) or yield_force (N)")
            return self

    param_names = ("stiffness", "yield_force", "alpha")
    state_names = ("drift", "force")
    dimensions = {"stiffness": "stiffness", "yield_drift": "length", "yield_force": "force",
                  "alpha": "dimensionless"}
    branches = "bilinear"
    opensees = "Steel01"
    examples = ({"stiffness": 2.0e6, "yield_drift": 0.005, "alpha": 0.1},
                {"stiffness": 1.0e5, "yield_drift": 0.01, "alpha": 0.1},
                {"stiffness": 1.0e5, "yield_force": 1000.0, "alpha": 0.0})

    @classmethod
    def tangent_states(cls, packed):
        """Elastic from the origin both ways (k), yielding both ways (alpha k), unloading from
        the upper bound (k) and reverse yielding after it (alpha k)."""
        k, fy, alpha = packed
        uy = fy / k

        def upper(u):
            return alpha * k * u + (1 - alpha) * fy

        rows = [((0.0, 0.0), 0.5 * uy, k), ((0.0, 0.0), -0.5 * uy, k),
                ((uy, fy), 2.0 * uy, alpha * k), ((-uy, -fy), -2.0 * uy, alpha * k),
                ((3.0 * uy, upper(3.0 * uy)), 2.5 * uy, k),
                ((3.0 * uy, upper(3.0 * uy)), 0.3 * uy, alpha * k)]
        return [TangentState(c, x, 0.1, (uy, 0.1), tangent=t, rate_tangent=0.0)
                for c, x, t in rows]

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K, the yield drift u_y = f_y / K and the post-yield ratio alpha."""
        k, fy, alpha = packed
        return {"K": ("stiffness", k), "u_y": ("length", fy / k),
                "alpha": ("dimensionless", alpha)}


    @classmethod
    def post_yield_stiffness(cls, packed):
        """alpha k: the slope of the bounding lines."""
        return packed[2] * packed[0]

    @classmethod
    def pack(cls, params, context=None):
        k = float(params.stiffness)
        fy = params.yield_force if params.yield_force is not None else k * params.yield_drift
        return (k, float(fy), float(params.alpha))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        k = params[0]
        alpha = params[2]
        reach = (1.0 - alpha) * params[1]
        f = committed[1] + k * (deformation - committed[0])
        tangent = k
        centre = alpha * k * deformation
        if f > centre + reach:
            f = centre + reach
            tangent = alpha * k
        elif f < centre - reach:
            f = centre - reach
            tangent = alpha * k
        trial[0] = deformation
        trial[1] = f
        return f, tangent, 0.0
