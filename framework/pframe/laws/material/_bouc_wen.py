"""The Bouc-Wen family's step: the trial hysteretic displacement z of ``bouc_wen`` and ``bwbn``.

Both laws share their first nine packed numbers (alpha, k0, n, gamma, beta, A0, deltaA,
deltaNu, deltaEta) and their committed state (u, z, e). Over a drift increment du = u - u_c
the trial z solves the backward-Euler step of the evolution equation,

    z - z_c - h(z, e) Phi(z, e) / eta(e) du = 0,    Phi = A - |z|^n (gamma + beta sign(du z)) nu,

with e = e_c + (1 - alpha) k0 du z moving with z, A = A0 - deltaA e, nu = 1 + deltaNu e,
eta = 1 + deltaEta e (Baber & Noori 1985) and h the pinching of ``bwbn`` (h = 1 for
``bouc_wen``), by Newton from z = 0.01 as OpenSees' ``BoucWen`` and ``BWBN`` do (Tz, Tzold =
0.01, Tznew = 1), until two iterates differ by no more than the tolerance or after the
iteration limit. The pieces are helper functions of the laws' ``force`` (translated to C with
it, ``pframe.kernel.translate``); each keeps OpenSees' order of operations.
"""

from __future__ import annotations

import math
from fractions import Fraction

from pydantic import Field

from pframe.laws.facts import TangentState
from pframe.laws.params import LawParams, Positive

#: upper bound of the local Newton loop (``max_iterations`` is at most this)
MAX_ITERATIONS = 100


class HystereticParams(LawParams):
    """The parameters both laws share: the first nine they pack, in this order."""

    material: str
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
                        "displacement (m; bwbn's z_u). Usual: beta = gamma = 0.5 / z_y^n.")
    Ao: Positive = Field(1.0, description="A0, the initial value of A (1 unless the "
                                          "hysteretic part starts softer).")
    deltaA: float = Field(0.0, ge=0, allow_inf_nan=False,
                          description="Degradation of A with the hysteretic energy e (1/J).")
    deltaNu: float = Field(0.0, ge=0, allow_inf_nan=False,
                           description="Strength degradation nu = 1 + deltaNu e (1/J).")
    deltaEta: float = Field(0.0, ge=0, allow_inf_nan=False,
                            description="Stiffness degradation eta = 1 + deltaEta e (1/J).")


#: the dimensions of the shared parameters (gamma and beta have none a declaration can say)
DIMENSIONS = {"alpha": "dimensionless", "ko": "stiffness", "n": "dimensionless",
              "Ao": "dimensionless", "deltaA": "1/J", "deltaNu": "1/J", "deltaEta": "1/J"}


def undimensioned(law: str) -> dict:
    """Why ``pframe scale`` refuses gamma and beta of ``law`` (a law's ``undimensioned``):
    they are in m^-n, whose dimension depends on n; ``pframe pi`` names the law by its yield
    displacement instead (``governing``)."""
    why = (f"gamma and beta of the {law} material are in m^-n, a dimension that depends on n; "
           "scale them by hand (by S_L^-n)")
    return {"gamma": why, "beta": why}


def gamma_beta_dimensions(cls, given: dict) -> dict[str, str]:
    """The Bouc-Wen family's ``dimensions_given``: gamma and beta in m^-n for n as written."""
    n = given.get("n")
    if isinstance(n, bool) or not isinstance(n, (int, float)) or not n > 0:
        return {}  # validation names n
    units = f"m^({-Fraction(n).limit_denominator(1000)})"
    return {"gamma": units, "beta": units}


def shape_numbers(packed, yield_name: str) -> tuple[dict, float, float]:
    """The governing numbers both laws share (a law's ``governing``): K = k0, the yield
    displacement z_y = (A0 / (beta + gamma))^(1/n) (named ``yield_name``), the shape numbers
    alpha, n, beta / (beta + gamma), A0 and the degradations per unit k0 z_y^2; with z_y
    and k0 z_y^2 (J)."""
    alpha, k0, n, gamma, beta, a0, da, dnu, deta = packed[:9]
    zy = (a0 / (beta + gamma)) ** (1.0 / n) if beta + gamma > 0 else math.inf
    energy = k0 * zy * zy
    return ({"K": ("stiffness", k0), yield_name: ("length", zy),
             "alpha": ("dimensionless", alpha), "n": ("dimensionless", n),
             "beta_ratio": ("dimensionless", beta / (beta + gamma)),
             "A0": ("dimensionless", a0),
             "deltaA_e": ("dimensionless", da * energy),
             "deltaNu_e": ("dimensionless", dnu * energy),
             "deltaEta_e": ("dimensionless", deta * energy)}, zy, energy)


def post_yield_stiffness(cls, packed):
    """alpha k0: the elastic part's slope, which the tangent tends to once z saturates (a
    law's ``post_yield_stiffness``)."""
    return packed[0] * packed[1]


def tangent_states(cls, packed):
    """Loading from rest, loading and unloading on a loop, both ways (committed (u, z, e)),
    at two drift rates: the tangent is rate independent (a law's ``tangent_states``)."""
    rows = [((0.0, 0.0, 0.0), 0.003), ((0.01, 0.008, 50.0), 0.013),
            ((0.01, 0.008, 50.0), 0.004), ((-0.02, -0.009, 400.0), -0.03),
            ((-0.02, -0.009, 400.0), -0.011)]
    return [TangentState(c, x, rate, (0.01, 0.3), rate_tangent=0.0)
            for rate in (0.3, -0.2) for c, x in rows]


def hysteretic(params, z, strain, committed_energy):
    """At z: the hysteretic energy e, A, nu, eta, gamma + beta sign(du z) and Phi (the
    bracket of the evolution equation), as (te, ta, tnu, teta, psi, phi)."""
    alpha = params[0]
    ko = params[1]
    te = committed_energy + (1.0 - alpha) * ko * strain * z
    ta = params[5] - params[6] * te
    tnu = 1.0 + params[7] * te
    teta = 1.0 + params[8] * te
    psi = params[3] + params[4] * (1.0 if strain * z > 0.0 else -1.0)
    phi = ta - abs(z) ** params[2] * psi * tnu
    return te, ta, tnu, teta, psi, phi


def hysteretic_slope(params, z, strain, psi, tnu):
    """d Phi / dz and d eta / dz along the step (e moves with z: de/dz = (1 - alpha) k0 du)."""
    n = params[2]
    te_ = (1.0 - params[0]) * params[1] * strain
    ta_ = -params[6] * te_
    tnu_ = params[7] * te_
    teta_ = params[8] * te_
    sign = 1.0 if z > 0.0 else -1.0
    pow1 = 0.0
    pow2 = 0.0
    if z != 0.0:
        pow1 = abs(z) ** (n - 1.0)
        pow2 = abs(z) ** n
    phi_ = ta_ - n * pow1 * sign * psi * tnu - pow2 * psi * tnu_
    return phi_, teta_


def pinching(params, z, strain, te, ta, tnu):
    """``bwbn``'s pinching h(z, e) and dh/dz along the step (1 and 0 without pinching,
    zetas = 0): h = 1 - zeta1 exp(-(z sign(du) - q z_u)^2 / zeta2^2) (Foliente 1995)."""
    zetas = params[10]
    if not zetas > 0.0:
        return 1.0, 0.0
    n = params[2]
    p = params[11]
    psi0 = params[12]
    delta_psi = params[13]
    lamda = params[14]
    q = params[9]
    sd = 1.0 if strain > 0.0 else -1.0
    te_ = (1.0 - params[0]) * params[1] * strain
    ta_ = -params[6] * te_
    tnu_ = params[7] * te_
    zeta1 = zetas * (1.0 - math.exp(min(-p * te, 700.0)))
    zeta2 = (psi0 + delta_psi * te) * (lamda + zeta1)
    zu = (max(ta, 0.0) / (tnu * (params[4] + params[3]))) ** (1.0 / n)
    zu_ = 0.0
    if ta > 0.0:
        zu_ = zu / n * (ta_ / ta - tnu_ / tnu)
    x = z * sd - q * zu
    x_ = sd - q * zu_
    g = math.exp(-(x * x) / (zeta2 * zeta2))
    h = 1.0 - zeta1 * g
    zeta1_ = zetas * p * math.exp(min(-p * te, 700.0)) * te_
    zeta2_ = (psi0 * zeta1_ + lamda * delta_psi * te_ + delta_psi * te * zeta1_
              + delta_psi * te_ * zeta1)
    h_ = -g * (zeta1_ - zeta1 * 2.0 * x * x_ / (zeta2 * zeta2)
               + zeta2_ * zeta1 * 2.0 * (x * x) / (zeta2 * zeta2 * zeta2))
    return h, h_


def trial_z(params, committed, strain, tolerance, most, pinched):
    """The trial z of the step by Newton from 0.01. ``pinched`` = 0: ``bouc_wen``'s residual
    z - z_c - Phi / eta du (OpenSees' BoucWen); 1: ``bwbn``'s z - z_c - Phi h / eta du
    (OpenSees' BWBN)."""
    cz = committed[1]
    z = 0.01
    z_old = 0.01
    z_new = 1.0
    count = 0.0
    for _ in range(MAX_ITERATIONS):
        if not (abs(z_old - z_new) > tolerance and count < most):
            break
        te, ta, tnu, teta, psi, phi = hysteretic(params, z, strain, committed[2])
        phi_, teta_ = hysteretic_slope(params, z, strain, psi, tnu)
        if pinched == 0.0:
            f = z - cz - phi / teta * strain
            f_ = 1.0 - (phi_ * teta - phi * teta_) / (teta * teta) * strain
        else:
            h, h_ = pinching(params, z, strain, te, ta, tnu)
            f = z - cz - phi * h / teta * strain
            f_ = 1.0 - ((phi_ * h + phi * h_) * teta - phi * h * teta_) / (teta * teta) * strain
        z_new = z - f / f_
        z_old = z
        z = z_new
        count = count + 1.0
    return z
