"""Friction pendulum storey: a single concave sliding surface (or a flat slider).

The storey shear is the pendulum's restoring force plus friction,

    F = (W / R) u + q,    |q| <= mu(v) W,

with W the weight the bearing carries, R the radius of the surface (none: a flat slider) and
q the friction force, elastic-plastic with stiffness k0 = k_init - W / R before it slides
(the stick phase; ``k_init`` is the bearing's initial stiffness) and mu(v) W while it slides.
Friction is Coulomb (``mu``) or velocity dependent (Constantinou, Mokha & Reinhorn 1990),

    mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|),

v the drift rate. This is OpenSees' ``flatSliderBearing`` / ``singleFPBearing`` in one
horizontal direction with a constant axial load W (the same return mapping for q, the same
``Coulomb`` / ``VelDependent`` friction models); OpenSees' singleFP adds the second-order
terms of the vertical equilibrium (N = W + q u / R), which pframe leaves out.

W defaults to g times the masses the storey carries (its upper floor and every floor above).
A mass sliding freely (mu = 0) on the surface swings with the pendulum period
2 pi sqrt(R / g), whatever its mass; friction breaks away at mu W and dissipates
4 mu W (D - mu W / k0) per cycle of amplitude D.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from pframe.errors import InputError
from pframe.laws.facts import TangentState
from pframe.laws.params import LawParams, Positive
from pframe.laws.registry import Law, material


@material("friction_pendulum")
class FrictionPendulum(Law):
    class Params(LawParams):
        material: Literal["friction_pendulum"]
        radius: Positive | None = Field(
            None, description="Radius R of the concave surface (m): the pendulum period is "
                              "2 pi sqrt(R / g). Omit it for a flat slider (no restoring force).")
        mu: float | None = Field(None, ge=0, le=1, description="Coulomb friction coefficient "
                                 "(constant); or give mu_slow, mu_fast and rate_parameter.")
        mu_slow: float | None = Field(None, ge=0, le=1, description="Friction coefficient at "
                                      "vanishing sliding velocity (Constantinou et al. 1990).")
        mu_fast: float | None = Field(None, ge=0, le=1, description="Friction coefficient at "
                                      "high sliding velocity.")
        rate_parameter: float | None = Field(
            None, ge=0, allow_inf_nan=False,
            description="a (s/m) of mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|).")
        weight: Positive | None = Field(
            None, description="Weight W the bearing carries (N); default: g times the masses "
                              "of the storey's upper floor and of every floor above it.")
        k_init: Positive = Field(description="Initial (stick) stiffness of the bearing (N/m): "
                                             "friction slides at a drift near mu W / k_init.")

        @model_validator(mode="after")
        def _one_friction(self):
            coulomb = self.mu is not None
            velocity = [n for n in ("mu_slow", "mu_fast", "rate_parameter")
                        if getattr(self, n) is not None]
            if coulomb == bool(velocity) or (velocity and len(velocity) != 3):
                raise ValueError("give either mu (Coulomb friction) or all three of mu_slow, "
                                 "mu_fast and rate_parameter (velocity-dependent friction); got "
                                 f"{', '.join((['mu'] if coulomb else []) + velocity) or 'none'}")
            return self

    param_names = ("weight", "inverse_radius", "k_init", "mu_slow", "mu_fast", "rate_parameter")
    state_names = ("plastic_drift",)
    dimensions = {"radius": "length", "mu": "dimensionless", "mu_slow": "dimensionless",
                  "mu_fast": "dimensionless", "rate_parameter": "s/m", "weight": "force",
                  "k_init": "stiffness"}
    branches = "smooth"
    #: with Coulomb friction (pframe.peers.twins); velocity-dependent friction is an
    #: element's in OpenSees (flatSliderBearing / singleFPBearing), not a uniaxialMaterial's
    opensees = "Parallel(Steel01, Elastic)"
    #: the first without ``weight``: g times the masses above the storey (StoreyContext)
    examples = ({"radius": 1.0, "mu_slow": 0.05, "mu_fast": 0.1, "rate_parameter": 30.0,
                 "k_init": 2.0e6},
                {"radius": 2.0, "mu": 0.08, "weight": 5e4, "k_init": 1e6},
                {"mu_slow": 0.05, "mu_fast": 0.12, "rate_parameter": 20.0, "weight": 5e4,
                 "k_init": 1e6})

    @classmethod
    def tangent_states(cls, packed):
        """Sticking from rest, sliding both ways from rest and from a plastic drift, at two
        drift rates, away from the stick-slip limit."""
        rows = [((0.0,), 1e-4), ((0.0,), 0.02), ((0.0,), -0.02), ((0.015,), 0.0152),
                ((0.015,), 0.005)]
        return [TangentState(c, x, rate, (0.01, 0.3)) for rate in (0.3, -0.2) for c, x in rows]

    #: a sliding bearing: k_init only keeps the stick phase finite, it is no structural
    #: stiffness (a Rayleigh term on it damps the pendulum far above the ratio asked)
    isolator = True

    @classmethod
    def post_yield_stiffness(cls, packed):
        """W / R: the pendulum's restoring stiffness while it slides (0: a flat slider)."""
        return packed[0] * packed[1]

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K = k_init, the slip drift u_s = mu_fast W / k_init, the pendulum length R (omitted
        for a flat slider) and the friction numbers mu_slow, mu_fast, a g."""
        w, inverse_radius, k_init, slow, fast, a = packed
        out = {"K": ("stiffness", k_init), "W": ("force", w),
               "mu_slow": ("dimensionless", slow), "mu_fast": ("dimensionless", fast),
               "a": ("s/m", a)}
        if inverse_radius > 0.0:
            out["R"] = ("length", 1.0 / inverse_radius)
        return out

    @classmethod
    def pack(cls, params, context=None):
        if params.weight is not None:
            weight = float(params.weight)
        elif context is not None and context.mass_above > 0.0:
            weight = float(context.weight)
        else:
            raise InputError("friction_pendulum needs the weight it carries: give weight (N) "
                             "(the default, g times the masses above the storey, is unknown "
                             "here)")
        inverse_radius = 0.0 if params.radius is None else 1.0 / float(params.radius)
        if weight * inverse_radius >= float(params.k_init):
            raise InputError(
                f"friction_pendulum: k_init {params.k_init!r} N/m must exceed the pendulum "
                f"stiffness W / R = {weight * inverse_radius!r} N/m (the stick stiffness is "
                "k_init - W / R)")
        if params.mu is not None:
            slow = fast = float(params.mu)
            a = 0.0
        else:
            slow, fast, a = (float(params.mu_slow), float(params.mu_fast),
                             float(params.rate_parameter))
        return (weight, inverse_radius, float(params.k_init), slow, fast, a)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        weight = params[0]
        k2 = weight * params[1]
        k_init = params[2]
        k0 = k_init - k2
        decay = (params[4] - params[3]) * math.exp(-params[5] * abs(rate))
        q_yield = (params[4] - decay) * weight
        q_trial = k0 * (deformation - committed[0])
        size = abs(q_trial)
        if size - q_yield <= 0.0:  # sticking: elastic
            trial[0] = committed[0]
            return q_trial + k2 * deformation, k_init, 0.0
        direction = q_trial / size
        # OpenSees' return mapping, in its order of operations
        trial[0] = committed[0] + (size - q_yield) / k0 * q_trial / size
        slope = 0.0  # d mu / d rate
        if rate > 0.0:
            slope = params[5] * decay
        elif rate < 0.0:
            slope = -params[5] * decay
        return q_yield * q_trial / size + k2 * deformation, k2, slope * weight * direction
