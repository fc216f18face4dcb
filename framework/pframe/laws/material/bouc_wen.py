"""Bouc-Wen storey: smooth hysteresis with degradation (OpenSees ``BoucWen`` uniaxialMaterial).

The storey shear is F = alpha k0 u + (1 - alpha) k0 z, where the hysteretic displacement z
(m) follows

    dz/du = [A - |z|^n (gamma + beta sign(du z)) nu] / eta,

with the hysteretic energy e = (1 - alpha) k0 int z du degrading the law:
A = A0 - delta_A e, nu = 1 + delta_nu e, eta = 1 + delta_eta e (Baber & Noori 1985, as in
OpenSees' BoucWenMaterial). Without degradation z is bounded by
z_y = (A0 / (beta + gamma))^(1/n), so the storey "yields" near F = alpha k0 u + (1 - alpha) k0 z_y:
elastomeric and lead-rubber isolators. n large gives a sharp (bilinear-like) knee, n = 1 a
smooth one.

The algorithm is OpenSees' operation for operation: from the committed (u, z, e), the trial z
solves z - z_c - Phi(z) / eta(z) (u - u_c) = 0 (backward Euler over the drift increment) by
Newton from z = 0.01, until two iterates differ by no more than ``tolerance`` (m) or after
``max_iterations`` (the solve ``bwbn`` shares: ``_bouc_wen.trial_z``); the tangent is
OpenSees' consistent dF/du. The trial z (so the loop) is
first-order accurate in the drift increment of a step: the loop under a record converges to the
evolution equation's as dt -> 0 (tests/test_isolators.py measures it).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.material._bouc_wen import MAX_ITERATIONS, hysteretic, tangent_states, trial_z
from pframe.laws.params import LawParams, Positive
from pframe.laws.registry import Law, material


@material("bouc_wen")
class BoucWen(Law):
    class Params(LawParams):
        material: Literal["bouc_wen"]
        alpha: float = Field(ge=0, le=1, description="Post-yield stiffness ratio alpha: "
                             "F = alpha k0 u + (1 - alpha) k0 z.")
        ko: Positive = Field(description="Initial storey stiffness k0 (N/m): the tangent at the "
                                         "origin is k0 (alpha + (1 - alpha) A0).")
        n: Positive = Field(description="Exponent n of the evolution equation: the sharpness of "
                                        "the knee (1: smooth; 10 or more: nearly bilinear).")
        gamma: float = Field(allow_inf_nan=False, description="gamma (m^-n): with beta the "
                             "shape of the loop; beta + gamma > 0 bounds z.")
        beta: float = Field(allow_inf_nan=False, description="beta (m^-n): with gamma the shape "
                            "of the loop; z_y = (A0 / (beta + gamma))^(1/n) is the yield "
                            "displacement (m). Usual: beta = gamma = 0.5 / z_y^n.")
        Ao: Positive = Field(1.0, description="A0, the initial value of A (1 unless the "
                                              "hysteretic part starts softer).")
        deltaA: float = Field(0.0, ge=0, allow_inf_nan=False,
                              description="Degradation of A with the hysteretic energy e (1/J).")
        deltaNu: float = Field(0.0, ge=0, allow_inf_nan=False,
                               description="Strength degradation nu = 1 + deltaNu e (1/J).")
        deltaEta: float = Field(0.0, ge=0, allow_inf_nan=False,
                                description="Stiffness degradation eta = 1 + deltaEta e (1/J).")
        tolerance: float = Field(1e-8, gt=0, le=1e-3, description="Convergence tolerance (m) of the Newton "
                                    "solve for z (OpenSees' default 1e-8).")
        max_iterations: int = Field(20, ge=1, le=MAX_ITERATIONS,
                                    description="Newton iterations for z at most (OpenSees' "
                                                "default 20).")

    param_names = ("alpha", "ko", "n", "gamma", "beta", "Ao", "deltaA", "deltaNu", "deltaEta",
                   "tolerance", "max_iterations")
    state_names = ("drift", "z", "energy")
    #: gamma and beta are in m^-n: their dimension depends on n, which a field's declaration
    #: cannot say; ``pframe scale`` refuses them with this reason, ``pframe pi`` names the law
    #: by its yield displacement instead (``governing``)
    dimensions = {"alpha": "dimensionless", "ko": "stiffness", "n": "dimensionless",
                  "Ao": "dimensionless", "deltaA": "1/J", "deltaNu": "1/J", "deltaEta": "1/J",
                  "tolerance": "length", "max_iterations": "dimensionless"}
    undimensioned = {
        "gamma": "gamma and beta of the Bouc-Wen material are in m^-n, a dimension that depends "
                 "on n; scale them by hand (by S_L^-n)",
        "beta": "gamma and beta of the Bouc-Wen material are in m^-n, a dimension that depends "
                "on n; scale them by hand (by S_L^-n)"}
    branches = "smooth"
    opensees = "BoucWen"
    examples = ({"alpha": 0.1, "ko": 1.0e5, "n": 2.0, "gamma": 2500.0, "beta": 2500.0},
                {"alpha": 0.0, "ko": 1.0e5, "n": 1.0, "gamma": 30.0, "beta": 70.0,
                 "deltaA": 1e-4, "deltaNu": 2e-4, "deltaEta": 1e-4})
    tangent_states = classmethod(tangent_states)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K = k0, the yield displacement z_y = (A0 / (beta + gamma))^(1/n), the shape numbers
        alpha, n, beta / (beta + gamma), A0 and the degradations per unit k0 z_y^2."""
        alpha, k0, n, gamma, beta, a0, da, dnu, deta = packed[:9]
        zy = (a0 / (beta + gamma)) ** (1.0 / n) if beta + gamma > 0 else math.inf
        energy = k0 * zy * zy
        return {"K": ("stiffness", k0), "z_y": ("length", zy),
                "alpha": ("dimensionless", alpha), "n": ("dimensionless", n),
                "beta_ratio": ("dimensionless", beta / (beta + gamma)),
                "A0": ("dimensionless", a0),
                "deltaA_e": ("dimensionless", da * energy),
                "deltaNu_e": ("dimensionless", dnu * energy),
                "deltaEta_e": ("dimensionless", deta * energy)}

    @classmethod
    def post_yield_stiffness(cls, packed):
        """alpha k0: the elastic part's slope, which the tangent tends to once z saturates."""
        return packed[0] * packed[1]

    @classmethod
    def pack(cls, params, context=None):
        return (float(params.alpha), float(params.ko), float(params.n), float(params.gamma),
                float(params.beta), float(params.Ao), float(params.deltaA),
                float(params.deltaNu), float(params.deltaEta), float(params.tolerance),
                float(params.max_iterations))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        alpha = params[0]
        ko = params[1]
        n = params[2]
        strain = deformation - committed[0]
        z = trial_z(params, committed, strain, params[9], params[10], 0.0)
        stress = alpha * ko * deformation + (1.0 - alpha) * ko * z
        te, ta, tnu, teta, psi, phi = hysteretic(params, z, strain, committed[2])
        tangent = alpha * ko + (1.0 - alpha) * ko
        if z != 0.0:  # OpenSees' consistent tangent, in its order of operations
            delta_a = params[6]
            delta_nu = params[7]
            delta_eta = params[8]
            b1 = (1.0 - alpha) * ko * z
            b2 = (1.0 - alpha) * ko * strain
            b3 = strain / teta
            b4 = (-b3 * delta_a * b1 - b3 * abs(z) ** n * psi * delta_nu * b1
                  - phi / (teta * teta) * strain * delta_eta * b1 + phi / teta)
            b5 = (1.0 + b3 * delta_a * b2
                  + b3 * n * abs(z) ** (n - 1.0) * (1.0 if z > 0.0 else -1.0) * psi * tnu
                  + b3 * abs(z) ** n * psi * delta_nu * b2
                  + phi / (teta * teta) * strain * delta_eta * b2)
            tangent = alpha * ko + (1.0 - alpha) * ko * (b4 / b5)
        trial[0] = deformation
        trial[1] = z
        trial[2] = te
        return stress, tangent, 0.0
