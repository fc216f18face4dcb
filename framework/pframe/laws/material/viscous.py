"""Viscous damper: F = c |v|^alpha sign(v) of the deformation rate v (OpenSees ``Viscous``).

Linear (alpha = 1) or nonlinear (fluid viscous dampers: alpha 0.2 to 1) dashpot, the
element of a link (``links:``) between buildings, between a floor and the ground, or across
a storey; it acts in tension and compression and has no stiffness. For alpha < 1 the force has
an infinite slope at v = 0, where Newton cycles (x -> -x on sign(x) |x|^(1/2)) when the step's
root is near v = 0, as it is from rest: below ``linear_below`` = v_0 (1e-5 m/s by default)
the dashpot is linear, c v_0^(alpha - 1) v, continuous with the power law at v_0 (OpenSees'
``Viscous`` keeps the power law and caps only the tangent, and fails from rest there without an
absolute Newton tolerance).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws.facts import TangentState
from pframe.laws.params import (
    DASHPOT_UNDIMENSIONED,
    LawParams,
    Positive,
    dashpot_dimensions,
    dashpot_units,
)
from pframe.laws.registry import Law, material


def dashpot_states(k, c, alpha, v0):
    """The tangent states of a spring k in parallel with the dashpot c |v|^alpha (linear
    below v0): above v0 both ways (d f / dv = alpha c |v|^(alpha - 1)) and below it
    (c v0^(alpha - 1)); d f / du = k, to the bit."""
    rows = []
    for rate in (0.3, -0.2, 0.3 * v0, -0.5 * v0):
        slope = alpha * c * abs(rate) ** (alpha - 1) if abs(rate) >= v0 else \
            c * v0 ** (alpha - 1)
        rows.append(TangentState((), 0.004, rate, (0.01, abs(rate)), tangent=k,
                                 rate_tangent=slope, tolerance=(0.0, 1e-12)))
    return rows


@material("viscous")
class Viscous(Law):
    class Params(LawParams):
        material: Literal["viscous"]
        damping: Positive = Field(description="Damping coefficient c (N (s/m)^alpha).")
        exponent: float = Field(1.0, gt=0, le=2.0, description="Velocity exponent alpha "
                                "(1: linear; fluid viscous dampers 0.2 to 1).")
        linear_below: Positive = Field(
            1e-5, description="v_0 (m/s): below it the dashpot is linear, c v_0^(alpha - 1) v, "
            "continuous with the power law at v_0 (alpha < 1 only: Newton cycles around a root "
            "near v = 0 of a force with an infinite slope there; the force is below the power "
            "law's by at most c v_0^alpha, at velocities whose work is negligible).")

    param_names = ("damping", "exponent", "linear_below")
    dimensions = {"exponent": "dimensionless", "linear_below": "velocity"}
    undimensioned = {"damping": DASHPOT_UNDIMENSIONED}
    dimensions_given = classmethod(dashpot_dimensions)
    branches = "smooth"
    opensees = "Viscous"
    stiffness_free = True  # no initial stiffness: a link, not a storey
    examples = ({"damping": 2.0e3, "exponent": 0.5}, {"damping": 2.0e3},
                {"damping": 2.0e3, "exponent": 0.4})

    @classmethod
    def tangent_states(cls, packed):
        """Both branches of the dashpot, both ways."""
        return dashpot_states(0.0, *packed)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """c (in N (s/m)^alpha) and its exponent, alpha_v. v_0 is the numerical bound of the
        linear branch, not a property of the dashpot."""
        return {"c": (dashpot_units(packed[1]), packed[0]),
                "alpha_v": ("dimensionless", packed[1])}

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.damping), float(params.exponent), float(params.linear_below))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        c = params[0]
        alpha = params[1]
        v0 = params[2]
        speed = abs(rate)
        if speed < v0:  # the linear branch below v_0 (see linear_below)
            slope = c * v0 ** (alpha - 1.0)
            return slope * rate, 0.0, slope
        f = c * speed ** alpha
        if rate < 0.0:
            f = -f
        return f, 0.0, alpha * c * speed ** (alpha - 1.0)
