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

from typing import Literal

from pydantic import Field

from pframe.laws.material._bouc_wen import (
    DIMENSIONS,
    MAX_ITERATIONS,
    HystereticParams,
    gamma_beta_dimensions,
    hysteretic,
    post_yield_stiffness,
    shape_numbers,
    tangent_states,
    trial_z,
    undimensioned,
)
from pframe.laws.registry import Law, material


@material("bouc_wen")
class BoucWen(Law):
    class Params(HystereticParams):
        material: Literal["bouc_wen"]
        tolerance: float = Field(1e-8, gt=0, le=1e-3, description="Convergence tolerance (m) of the Newton "
                                    "solve for z (OpenSees' default 1e-8).")
        max_iterations: int = Field(20, ge=1, le=MAX_ITERATIONS,
                                    description="Newton iterations for z at most (OpenSees' "
                                                "default 20).")

    param_names = ("alpha", "ko", "n", "gamma", "beta", "Ao", "deltaA", "deltaNu", "deltaEta",
                   "tolerance", "max_iterations")
    state_names = ("drift", "z", "energy")
    dimensions = DIMENSIONS | {"tolerance": "length", "max_iterations": "dimensionless"}
    dimensions_given = classmethod(gamma_beta_dimensions)
    undimensioned = undimensioned("Bouc-Wen")
    branches = "smooth"
    opensees = "BoucWen"
    examples = ({"alpha": 0.1, "ko": 1.0e5, "n": 2.0, "gamma": 2500.0, "beta": 2500.0},
                {"alpha": 0.0, "ko": 1.0e5, "n": 1.0, "gamma": 30.0, "beta": 70.0,
                 "deltaA": 1e-4, "deltaNu": 2e-4, "deltaEta": 1e-4})
    tangent_states = classmethod(tangent_states)

    post_yield_stiffness = classmethod(post_yield_stiffness)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K = k0, the yield displacement z_y = (A0 / (beta + gamma))^(1/n), the shape numbers
        alpha, n, beta / (beta + gamma), A0 and the degradations per unit k0 z_y^2."""
        return shape_numbers(packed, "z_y")[0]

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
