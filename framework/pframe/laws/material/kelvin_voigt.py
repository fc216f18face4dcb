"""Kelvin-Voigt viscoelastic link: a spring and a dashpot in parallel,
F = k u + c |v|^alpha sign(v).

A viscoelastic coupling or damping link (``links:``; elastomeric and viscoelastic dampers,
the spring-dashpot of a tuned mass damper), or a storey with its own dashpot. Tension and
compression alike; OpenSees models it as a ``Parallel`` of ``Elastic`` and ``Viscous``. Below
``linear_below`` the dashpot is linear, as for ``viscous``.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from pframe.laws.material.viscous import dashpot_states
from pframe.laws.params import (
    DASHPOT_UNDIMENSIONED,
    LawParams,
    Positive,
    dashpot_dimensions,
    dashpot_units,
)
from pframe.laws.registry import Law, material


@material("kelvin_voigt")
class KelvinVoigt(Law):
    class Params(LawParams):
        material: Literal["kelvin_voigt"]
        stiffness: Positive = Field(description="Spring stiffness k (N/m).")
        damping: float = Field(ge=0, allow_inf_nan=False,
                               description="Damping coefficient c (N (s/m)^alpha).")
        exponent: float = Field(1.0, gt=0, le=2.0, description="Velocity exponent alpha "
                                "(1: a linear dashpot).")
        linear_below: Positive = Field(
            1e-5, description="v_0 (m/s): below it the dashpot is linear, c v_0^(alpha - 1) v, "
            "continuous with the power law at v_0 (alpha < 1 only: Newton cycles around a root "
            "near v = 0 of a force with an infinite slope there; the force is below the power "
            "law's by at most c v_0^alpha, at velocities whose work is negligible).")

    param_names = ("stiffness", "damping", "exponent", "linear_below")
    dimensions = {"stiffness": "stiffness", "exponent": "dimensionless",
                  "linear_below": "velocity"}
    undimensioned = {"damping": DASHPOT_UNDIMENSIONED}
    dimensions_given = classmethod(dashpot_dimensions)
    branches = "smooth"
    opensees = "Parallel(Elastic, Viscous)"
    examples = ({"stiffness": 1.0e5, "damping": 1.0e3},
                {"stiffness": 1.0e5, "damping": 2.0e3, "exponent": 0.5})

    @classmethod
    def tangent_states(cls, packed):
        """Both branches of the dashpot, both ways; the spring's k."""
        return dashpot_states(*packed)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """The spring stiffness K, the dashpot's c (in N (s/m)^alpha) and its exponent,
        alpha_v (not a storey's post-yield ratio alpha). v_0 is the numerical bound of the
        linear branch, not a property of the dashpot."""
        return {"K": ("stiffness", packed[0]), "c": (dashpot_units(packed[2]), packed[1]),
                "alpha_v": ("dimensionless", packed[2])}

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.stiffness), float(params.damping), float(params.exponent),
                float(params.linear_below))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        c = params[1]
        alpha = params[2]
        v0 = params[3]
        speed = abs(rate)
        if speed < v0:  # the linear branch below v_0 (see linear_below)
            slope = c * v0 ** (alpha - 1.0)
            return params[0] * deformation + slope * rate, params[0], slope
        damper = c * speed ** alpha
        if rate < 0.0:
            damper = -damper
        return params[0] * deformation + damper, params[0], alpha * c * speed ** (alpha - 1.0)
