"""Bouc-Wen-Baber-Noori storey: Bouc-Wen hysteresis with strength and stiffness degradation
and pinching (Baber & Noori 1986, in Foliente's 1995 form; OpenSees ``BWBN`` uniaxialMaterial).

The storey shear is F = alpha k0 u + (1 - alpha) k0 z; the hysteretic displacement z (m)
follows

    dz/du = h(z) [A - nu |z|^n (gamma + beta sign(du z))] / eta,

degraded by the hysteretic energy e = (1 - alpha) k0 int z du (J) as ``bouc_wen`` is:
A = A0 - deltaA e, nu = 1 + deltaNu e (strength), eta = 1 + deltaEta e (stiffness), and
pinched by

    h(z) = 1 - zeta1 exp(-(z sign(du) - q z_u)^2 / zeta2^2),
    zeta1 = zetas (1 - exp(-p e)),  zeta2 = (psi + deltaPsi e) (lamda + zeta1),
    z_u = (A / (nu (beta + gamma)))^(1/n)  (the largest z the loop reaches),

so the tangent drops near z = q z_u on each reloading branch, more as energy is dissipated
(zetas: how much, p: how fast, psi and deltaPsi: over what range of z, lamda: the coupling of
the range to zeta1). With zetas = 0 there is no pinching and the law is ``bouc_wen`` (the same
force and state bit for bit).

The algorithm is OpenSees' ``BWBN`` (SRC/material/uniaxial/BWBN.cpp): from the committed
(u, z, e), the trial z solves z - z_c - h Phi / eta (u - u_c) = 0 by Newton from z = 0.01
until two iterates differ by no more than ``tolerance`` or after ``max_iterations``, with
sign(du) = -1 for du = 0 as OpenSees' ``signum`` (the solve ``bouc_wen`` shares:
``_bouc_wen.trial_z``). OpenSees' BWBN has no A, nu or eta
degradation and takes z_u = (1 / (beta + gamma))^(1/n): it is this law with A0 = 1 and
deltaA = deltaNu = deltaEta = 0, which is what ``pframe opensees`` can write as ``BWBN``;
the forces then agree to round-off (tests/test_bwbn.py). The Newton derivative and the
tangent here include the degradation's terms (z_u's dependence on e among them); the tangent
is the consistent dF/du of the step's equation. OpenSees' BWBN tangent is not where the
pinching acts: its numerator, h Phi - Phi dh/du, should be h Phi + du Phi dh/du (the
tangent only steers the structure's Newton iterations, not the forces it converges to).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

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
from pframe.laws.params import Positive
from pframe.laws.registry import Law, material


@material("bwbn")
class Bwbn(Law):
    class Params(HystereticParams):
        material: Literal["bwbn"]
        q: float = Field(0.0, ge=0, le=1, description="Pinching: where on the loop it acts, "
                         "z = q z_u on the reloading branch (0: at zero hysteretic force).")
        zetas: float = Field(0.0, ge=0, lt=1, description="Pinching: its severity zeta_s, the "
                             "largest fraction of the tangent it removes (0: no pinching).")
        p: float = Field(0.0, ge=0, allow_inf_nan=False,
                         description="Pinching: the rate (1/J) at which it sets in with the "
                                     "hysteretic energy, zeta1 = zetas (1 - exp(-p e)).")
        psi: Positive | None = Field(None, description="Pinching: psi (m), the initial spread of "
                                     "the pinched range of z (OpenSees' Shi); needed when "
                                     "zetas > 0.")
        deltaPsi: float = Field(0.0, ge=0, allow_inf_nan=False,
                                description="Pinching: growth of the spread with the "
                                            "hysteretic energy (m/J; OpenSees' deltaShi).")
        lamda: Positive | None = Field(None, description="Pinching: lamda, the coupling of the "
                                       "spread to zeta1, zeta2 = (psi + deltaPsi e) (lamda + "
                                       "zeta1); needed when zetas > 0.")
        tolerance: float = Field(1e-8, gt=0, le=1e-3, description="Convergence tolerance (m) "
                                 "of the Newton solve for z (OpenSees' usual 1e-8).")
        max_iterations: int = Field(20, ge=1, le=MAX_ITERATIONS,
                                    description="Newton iterations for z at most (OpenSees' "
                                                "maxNumIter).")

        @model_validator(mode="after")
        def _pinching_complete(self):
            if self.zetas > 0.0:
                missing = [name for name in ("psi", "lamda") if getattr(self, name) is None]
                if missing:
                    raise ValueError(f"zetas > 0 (pinching) needs {' and '.join(missing)} "
                                     "(positive numbers: the spread psi in m, lamda "
                                     "dimensionless)")
                if self.beta + self.gamma <= 0.0:
                    raise ValueError("zetas > 0 (pinching) needs beta + gamma > 0: the pinching "
                                     "is placed by z_u = (A / (nu (beta + gamma)))^(1/n)")
            return self

    param_names = ("alpha", "ko", "n", "gamma", "beta", "Ao", "deltaA", "deltaNu", "deltaEta",
                   "q", "zetas", "p", "psi", "deltaPsi", "lamda", "tolerance", "max_iterations")
    state_names = ("drift", "z", "energy")
    dimensions = DIMENSIONS | {"q": "dimensionless", "zetas": "dimensionless", "p": "1/J",
                               "psi": "length", "deltaPsi": "m/J", "lamda": "dimensionless",
                               "tolerance": "length", "max_iterations": "dimensionless"}
    dimensions_given = classmethod(gamma_beta_dimensions)
    undimensioned = undimensioned("BWBN")
    #: no regime description for the reference solver (pframe accuracy): the law is its
    #: step's backward-Euler update, whose state the reference solver does not integrate
    branches = None
    opensees = "BWBN"
    examples = ({"alpha": 0.05, "ko": 1.0e5, "n": 1.5, "gamma": 300.0, "beta": 700.0,
                 "deltaA": 1e-4, "deltaNu": 2e-4, "deltaEta": 1e-4, "q": 0.2, "zetas": 0.8,
                 "p": 1e-2, "psi": 0.004, "deltaPsi": 1e-5, "lamda": 0.5},
                {"alpha": 0.1, "ko": 1.0e5, "n": 2.0, "gamma": 2500.0, "beta": 2500.0})
    tangent_states = classmethod(tangent_states)

    post_yield_stiffness = classmethod(post_yield_stiffness)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K = k0, z_u = (A0 / (beta + gamma))^(1/n), the shape numbers, the degradations and
        pinching rates per unit k0 z_u^2 and the pinching spread per unit z_u."""
        out, zu, energy = shape_numbers(packed, "z_u")
        q, zetas, p, psi, dpsi, lamda = packed[9:15]
        return out | {"q": ("dimensionless", q), "zetas": ("dimensionless", zetas),
                      "p_e": ("dimensionless", p * energy),
                      "psi_zu": ("dimensionless", psi / zu),
                      "deltaPsi_e": ("dimensionless", dpsi * energy / zu),
                      "lamda": ("dimensionless", lamda)}

    @classmethod
    def pack(cls, params, context=None):
        # without pinching (zetas = 0) psi and lamda are never read: 1 keeps them harmless
        psi = 1.0 if params.psi is None else float(params.psi)
        lamda = 1.0 if params.lamda is None else float(params.lamda)
        return (float(params.alpha), float(params.ko), float(params.n), float(params.gamma),
                float(params.beta), float(params.Ao), float(params.deltaA),
                float(params.deltaNu), float(params.deltaEta), float(params.q),
                float(params.zetas), float(params.p), psi, float(params.deltaPsi), lamda,
                float(params.tolerance), float(params.max_iterations))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        alpha = params[0]
        ko = params[1]
        n = params[2]
        strain = deformation - committed[0]
        sd = 1.0 if strain > 0.0 else -1.0
        z = trial_z(params, committed, strain, params[15], params[16], 1.0)
        stress = alpha * ko * deformation + (1.0 - alpha) * ko * z
        te, ta, tnu, teta, psi, phi = hysteretic(params, z, strain, committed[2])
        tangent = alpha * ko + (1.0 - alpha) * ko
        if z != 0.0:
            # F(z, du) = z - z_c - Phi h / eta du = 0: dz/du = -F_du / F_z, each through e too
            pow2 = abs(z) ** n
            e_du = (1.0 - alpha) * ko * z
            e_dz = (1.0 - alpha) * ko * strain
            phi_e = -params[6] - pow2 * psi * params[7]
            phi_z = -n * abs(z) ** (n - 1.0) * (1.0 if z > 0.0 else -1.0) * psi * tnu
            h, h_e, h_x = _pinching_at(params, z, sd, te, ta, tnu)
            # d(Phi h / eta)/de at fixed z
            w_e = (phi_e * h + phi * h_e) / teta - phi * h * params[8] / (teta * teta)
            numerator = phi * h / teta + strain * w_e * e_du
            denominator = 1.0 - strain * (w_e * e_dz + (phi_z * h + phi * h_x * sd) / teta)
            tangent = alpha * ko + (1.0 - alpha) * ko * (numerator / denominator)
        trial[0] = deformation
        trial[1] = z
        trial[2] = te
        return stress, tangent, 0.0


def _pinching_at(params, z, sd, te, ta, tnu):
    """The pinching h at the trial (z, e) and its partial derivatives dh/de (at fixed z) and
    dh/dx (x = z sign(du) - q z_u), for the tangent; (1, 0, 0) without pinching."""
    zetas = params[10]
    if not zetas > 0.0:
        return 1.0, 0.0, 0.0
    n = params[2]
    p = params[11]
    psi0 = params[12]
    delta_psi = params[13]
    lamda = params[14]
    q = params[9]
    delta_a = params[6]
    delta_nu = params[7]
    zeta1 = zetas * (1.0 - math.exp(min(-p * te, 700.0)))
    zeta2 = (psi0 + delta_psi * te) * (lamda + zeta1)
    zu = (max(ta, 0.0) / (tnu * (params[4] + params[3]))) ** (1.0 / n)
    zu_e = 0.0
    if ta > 0.0:
        zu_e = zu / n * (-delta_a / ta - delta_nu / tnu)
    x = z * sd - q * zu
    g = math.exp(-(x * x) / (zeta2 * zeta2))
    h = 1.0 - zeta1 * g
    zeta1_e = zetas * p * math.exp(min(-p * te, 700.0))
    zeta2_e = (psi0 * zeta1_e + lamda * delta_psi + delta_psi * te * zeta1_e
               + delta_psi * zeta1)
    h_x = zeta1 * g * 2.0 * x / (zeta2 * zeta2)
    h_e = (-g * (zeta1_e + zeta1 * 2.0 * (x * x) * zeta2_e
                 / (zeta2 * zeta2 * zeta2)) - h_x * q * zu_e)
    return h, h_e, h_x
