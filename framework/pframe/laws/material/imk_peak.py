"""Modified Ibarra-Medina-Krawinkler storey with peak-oriented hysteresis and cyclic
deterioration: OpenSees' ``ModIMKPeakOriented`` uniaxial material, in storey terms.

The backbone (each direction apart): elastic with stiffness K0 up to the yield force My,
hardening with slope as K0 up to the capping drift (yield drift + theta_p), softening with the
cap slope -F_peak / theta_pc (a negative tangent) down to the residual force Res My, then flat
(a tangent of 1e-7 N/m, as OpenSees) until the ultimate drift theta_u, where the storey
fractures: its force and tangent are zero from then on. Reloading aims at the largest drift
reached so far in that direction (peak-oriented; Clough's rule with the Ibarra-Krawinkler
refinement of the last unloading point). Cyclic deterioration follows Rahnama and
Krawinkler's energy rule: after each half cycle past yield, beta = (E_i / (E_t - sum E))^c
with the hysteretic capacities E_t = Lamda My (Lamda in metres in storey terms, so E_t in
joules): basic strength and post-yield slope (Lamda_S, c_S), the cap's reference force
(Lamda_C, c_C), accelerated reloading (Lamda_A, c_A: the target drift grows by 1 + beta) and
unloading stiffness (Lamda_K, c_K, at every reversal). D scales the deterioration of a
direction.

``force`` is OpenSees' ``setTrialStrain`` (SRC/material/uniaxial/ModIMKPeakOriented.cpp, with
nFactor = 0: the 23-argument form) statement by statement; each call starts from the committed
state, as OpenSees' ``revertToLastCommit``, and works on ``trial`` (a copy of it) in named
pieces, each a helper function translated to C with ``force``: the first loading, the
step's direction and reversal (``_direction``, the unloading stiffness's deterioration), the
two envelope routines (evaluated at one place: every path of ``setTrialStrain`` calls
exactly one of them once), reloading inside the loop each way, and the cyclic deterioration
at the end of a half cycle (``_deteriorate``). Two guards where
OpenSees' C gives NaN: a negative energy ratio raised to a non-integer exponent (round-off at
an elastic reversal; C's pow is NaN there, Python's ``**`` complex) counts as 0, and a cap
capacity used up exactly (sum E = E_t,C, a division by zero) gives beta_C = 1. Elsewhere,
integer exponents included, the port agrees with OpenSeesPy to the bit
(tests/test_imk_peak.py).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.facts import TangentState
from pframe.laws.params import LawParams, Positive
from pframe.laws.registry import Law, material

_NonNegative = Field(ge=0, allow_inf_nan=False)


def _field(description: str, **bounds):
    return Field(description=description, allow_inf_nan=False, **bounds)


@material("imk_peak")
class ImkPeak(Law):
    class Params(LawParams):
        material: Literal["imk_peak"]
        k0: Positive = Field(description="K0: elastic storey stiffness (N/m).")
        as_plus: float = _field("as_Plus: strain-hardening ratio (post-yield slope / K0), "
                                "positive drift.", ge=0, lt=1)
        as_neg: float = _field("as_Neg: strain-hardening ratio, negative drift.", ge=0, lt=1)
        my_plus: Positive = Field(description="My_Plus: yield force (storey shear, N), "
                                              "positive drift.")
        my_neg: Positive = Field(description="My_Neg: yield force magnitude (N), negative drift "
                                             "(OpenSees takes it negative).")
        lamda_s: float = _field("Lamda_S: basic strength deterioration, E_t = Lamda_S My_Plus "
                                "(m; 0: none).", ge=0)
        lamda_c: float = _field("Lamda_C: post-capping strength deterioration (m; 0: OpenSees "
                                "then drops the cap's reference force at the first half cycle "
                                "past yield, by D).", ge=0)
        lamda_a: float = _field("Lamda_A: accelerated reloading stiffness deterioration (m; 0: "
                                "none).", ge=0)
        lamda_k: float = _field("Lamda_K: unloading stiffness deterioration, E_t = 2 Lamda_K "
                                "My_Plus (m; 0: none).", ge=0)
        c_s: float = _field("c_S: exponent of basic strength deterioration.", ge=0)
        c_c: float = _field("c_C: exponent of post-capping strength deterioration.", ge=0)
        c_a: float = _field("c_A: exponent of accelerated reloading deterioration.", ge=0)
        c_k: float = _field("c_K: exponent of unloading stiffness deterioration.", ge=0)
        theta_p_plus: float = _field("theta_p_Plus: pre-capping plastic drift (m), positive "
                                     "drift.", ge=0)
        theta_p_neg: float = _field("theta_p_Neg: pre-capping plastic drift (m), negative "
                                    "drift.", ge=0)
        theta_pc_plus: Positive = Field(description="theta_pc_Plus: post-capping drift (m) from "
                                                    "the cap to zero force.")
        theta_pc_neg: Positive = Field(description="theta_pc_Neg: post-capping drift (m), "
                                                   "negative drift.")
        res_plus: float = _field("Res_Pos: residual force / My_Plus.", ge=0, le=1)
        res_neg: float = _field("Res_Neg: residual force / My_Neg.", ge=0, le=1)
        theta_u_plus: Positive = Field(description="theta_u_Plus: ultimate drift (m): the "
                                                   "storey fractures beyond it.")
        theta_u_neg: Positive = Field(description="theta_u_Neg: ultimate drift magnitude (m), "
                                                  "negative drift.")
        d_plus: float = _field("D_Plus: rate of cyclic deterioration, positive drift (1: "
                               "full).", ge=0, le=1)
        d_neg: float = _field("D_Neg: rate of cyclic deterioration, negative drift.", ge=0, le=1)

    param_names = ("k0", "as_plus", "as_neg", "my_plus", "my_neg", "lamda_s", "lamda_c",
                   "lamda_a", "lamda_k", "c_s", "c_c", "c_a", "c_k", "theta_p_plus",
                   "theta_p_neg", "theta_pc_plus", "theta_pc_neg", "res_plus", "res_neg",
                   "theta_u_plus", "theta_u_neg", "d_plus", "d_neg")
    #: OpenSees' committed variables (kon = 0: not yet loaded; Unl, kon, flagStop as numbers)
    state_names = ("dP", "fP", "ek", "Unl", "kon", "flagStop", "dmax", "dmin", "fmax", "fmin",
                   "fyPos", "fyNeg", "dlstPos", "dlstNeg", "flstPos", "flstNeg", "sn", "sp",
                   "Enrgc", "Enrgtot", "fCapRefPos", "fCapRefNeg", "ekunload", "cpPos", "cpNeg",
                   "ekhardPos", "ekhardNeg", "AlfaPos", "AlfaNeg", "prodBeta")
    dimensions = {"k0": "stiffness", "as_plus": "dimensionless", "as_neg": "dimensionless",
                  "my_plus": "force", "my_neg": "force", "lamda_s": "length",
                  "lamda_c": "length", "lamda_a": "length", "lamda_k": "length",
                  "c_s": "dimensionless", "c_c": "dimensionless", "c_a": "dimensionless",
                  "c_k": "dimensionless", "theta_p_plus": "length", "theta_p_neg": "length",
                  "theta_pc_plus": "length", "theta_pc_neg": "length",
                  "res_plus": "dimensionless", "res_neg": "dimensionless",
                  "theta_u_plus": "length", "theta_u_neg": "length",
                  "d_plus": "dimensionless", "d_neg": "dimensionless"}
    #: no regime description for the reference solver (pframe accuracy): where this law's
    #: state changes is not described in pframe.reference.branches, so it refuses the law
    #: rather than integrate across unlocated kinks
    branches = None
    opensees = "ModIMKPeakOriented"
    examples = (dict(k0=2.0e6, as_plus=0.03, as_neg=0.03, my_plus=1.0e4, my_neg=1.0e4,
                     lamda_s=0.05, lamda_c=0.05, lamda_a=0.05, lamda_k=0.05, c_s=1.0, c_c=1.0,
                     c_a=1.0, c_k=1.0, theta_p_plus=0.01, theta_p_neg=0.01, theta_pc_plus=0.05,
                     theta_pc_neg=0.05, res_plus=0.3, res_neg=0.3, theta_u_plus=0.2,
                     theta_u_neg=0.2, d_plus=1.0, d_neg=1.0),
                dict(k0=4.0e7, as_plus=0.03, as_neg=0.04, my_plus=1.0e5, my_neg=1.2e5,
                     lamda_s=0.6, lamda_c=0.6, lamda_a=0.6, lamda_k=0.6, c_s=1.0, c_c=1.0,
                     c_a=1.0, c_k=1.0, theta_p_plus=0.02, theta_p_neg=0.025,
                     theta_pc_plus=0.06, theta_pc_neg=0.08, res_plus=0.3, res_neg=0.25,
                     theta_u_plus=0.15, theta_u_neg=0.17, d_plus=1.0, d_neg=0.9))

    @classmethod
    def tangent_states(cls, packed):
        """From rest onto each branch of the backbone both ways (elastic, hardening, capping,
        residual: their slopes), and unloading after a first excursion past yield (its
        unloading stiffness, deteriorated at the reversal, is in the state)."""
        k, as_pos, as_neg = packed[0], packed[1], packed[2]
        rest = (0.0,) * len(cls.state_names)
        cap_pos = -(packed[3] + as_pos * k * packed[13]) / packed[15]
        cap_neg = (packed[4] - as_neg * k * packed[14]) / packed[16]
        loaded = list(rest)
        for d in (0.004, 0.008, 0.01):
            trial = list(rest)
            cls.force(packed, loaded, trial, d, 0.0)
            loaded = trial
        rows = [(rest, 0.001, k), (rest, -0.001, k), (rest, 0.01, as_pos * k),
                (rest, -0.01, as_neg * k), (rest, 0.04, cap_pos), (rest, -0.05, cap_neg),
                (rest, 0.1, 1e-7), (rest, -0.15, 1e-7), (tuple(loaded), 0.009, None)]
        return [TangentState(c, x, 0.1, (1e-3, 0.1), tangent=t, rate_tangent=0.0)
                for c, x, t in rows]

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """K, the yield drift u_y = My_Plus / K and the hardening ratio as_Plus, then every
        other parameter under its own name."""
        out = {"K": ("stiffness", packed[0]), "u_y": ("length", packed[3] / packed[0]),
               "alpha": ("dimensionless", packed[1]), "as_neg": ("dimensionless", packed[2])}
        for name, value in zip(cls.param_names[4:], packed[4:]):
            out[name] = (cls.dimensions[name], abs(value) if name == "my_neg" else value)
        return out

    @classmethod
    def parameter_warnings(cls, packed):
        """Lamda_C = 0 does not switch cap deterioration off in OpenSees' algorithm (which
        pframe follows): at the first half cycle past yield the cap's reference force is
        scaled by 1 - D, and with it the strength beyond the cap."""
        out = []
        for side, d in (("d_plus", packed[21]), ("d_neg", packed[22])):
            if packed[6] == 0.0 and d > 0.0:
                out.append(f"imk_peak with lamda_c = 0 and {side} = {d:g}: as OpenSees' "
                           f"ModIMKPeakOriented, the cap's reference force drops by {d:.0%} at "
                           "the first half cycle past yield (lamda_c = 0 does not mean no "
                           "post-capping deterioration; for that give a large lamda_c)")
        return tuple(out)

    @classmethod
    def post_yield_stiffness(cls, packed):
        """The hardening slope as K0 of the weaker side (the cap's negative slope is the
        model's own softening, not a P-delta effect)."""
        return min(packed[1], packed[2]) * packed[0]

    @classmethod
    def pack(cls, params, context=None):
        p = params
        return (float(p.k0), float(p.as_plus), float(p.as_neg), float(p.my_plus),
                -float(p.my_neg), float(p.lamda_s), float(p.lamda_c), float(p.lamda_a),
                float(p.lamda_k), float(p.c_s), float(p.c_c), float(p.c_a), float(p.c_k),
                float(p.theta_p_plus), float(p.theta_p_neg), float(p.theta_pc_plus),
                float(p.theta_pc_neg), float(p.res_plus), float(p.res_neg),
                float(p.theta_u_plus), float(p.theta_u_neg), float(p.d_plus), float(p.d_neg))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        # trial holds the state as it changes; committed is read once, here
        _copy_state(committed, trial)
        d = deformation
        delta_d = d - trial[DP]
        if not (abs(delta_d) < 1.0e-18 and d != 0.0 and trial[KON] != 0.0):
            ekp = trial[EK]
            if trial[KON] == 0.0:
                _first_loading(params, trial, delta_d)
                ekp = params[0]
            if trial[STOP] == 0.0:
                d, f = _step(params, trial, d, delta_d, ekp)
            else:
                f = 0.0
                trial[EK] = 0.0
            trial[DP] = d
            trial[FP] = f
        return trial[FP], trial[EK], 0.0


# the state's slots, in the order of ImkPeak.state_names
(DP, FP, EK, UNL, KON, STOP, DMAX, DMIN, FMAX, FMIN, FY_POS, FY_NEG, DLST_POS, DLST_NEG,
 FLST_POS, FLST_NEG, SN, SP, ENRGC, ENRGTOT, FCAP_POS, FCAP_NEG, EKUNLOAD, CP_POS, CP_NEG,
 EKHARD_POS, EKHARD_NEG, ALFA_POS, ALFA_NEG, PROD_BETA) = range(30)


def _copy_state(committed, trial):
    """trial = committed, slot by slot."""
    trial[0] = committed[0]
    trial[1] = committed[1]
    trial[2] = committed[2]
    trial[3] = committed[3]
    trial[4] = committed[4]
    trial[5] = committed[5]
    trial[6] = committed[6]
    trial[7] = committed[7]
    trial[8] = committed[8]
    trial[9] = committed[9]
    trial[10] = committed[10]
    trial[11] = committed[11]
    trial[12] = committed[12]
    trial[13] = committed[13]
    trial[14] = committed[14]
    trial[15] = committed[15]
    trial[16] = committed[16]
    trial[17] = committed[17]
    trial[18] = committed[18]
    trial[19] = committed[19]
    trial[20] = committed[20]
    trial[21] = committed[21]
    trial[22] = committed[22]
    trial[23] = committed[23]
    trial[24] = committed[24]
    trial[25] = committed[25]
    trial[26] = committed[26]
    trial[27] = committed[27]
    trial[28] = committed[28]
    trial[29] = committed[29]


def _backbone(params):
    """The peak forces and the cap slopes (per K0) of the two directions, as (fpeak_pos,
    fpeak_neg, cap_slope_pos, cap_slope_neg)."""
    ke = params[0]
    ekhard_pos0 = ke * params[1]
    ekhard_neg0 = ke * params[2]
    fpeak_pos = params[3] + ekhard_pos0 * params[13]
    fpeak_neg = params[4] + ekhard_neg0 * (-params[14])
    return (fpeak_pos, fpeak_neg, -fpeak_pos / (params[15] * ke),
            fpeak_neg / (params[16] * ke))


def _first_loading(params, s, delta_d):
    """The state OpenSees sets up at the first call (kon = 0)."""
    ke = params[0]
    my_pos = params[3]
    my_neg = params[4]
    theta_p_pos = params[13]
    theta_p_neg = params[14]
    fpeak_pos, fpeak_neg, cap_slope_pos, cap_slope_neg = _backbone(params)
    s[ALFA_NEG] = params[2]
    s[ALFA_POS] = params[1]
    s[EKHARD_POS] = ke * params[1]
    s[EKHARD_NEG] = ke * params[2]
    s[ENRGTOT] = 0.0
    s[ENRGC] = 0.0
    s[DMAX] = my_pos / ke
    s[DMIN] = my_neg / ke
    s[EKUNLOAD] = ke
    s[FY_POS] = my_pos
    s[FY_NEG] = my_neg
    s[CP_POS] = my_pos / ke + theta_p_pos
    s[CP_NEG] = my_neg / ke + (-theta_p_neg)
    s[FCAP_POS] = -cap_slope_pos * ke * (theta_p_pos + my_pos / ke) + fpeak_pos
    s[FCAP_NEG] = -cap_slope_neg * ke * (-theta_p_neg + my_neg / ke) + fpeak_neg
    s[FMIN] = my_neg
    s[FMAX] = my_pos
    s[STOP] = 0.0
    s[DLST_NEG] = my_neg / ke
    s[DLST_POS] = my_pos / ke
    s[FLST_NEG] = my_neg
    s[FLST_POS] = my_pos
    s[EK] = 0.0
    s[SP] = 0.0
    s[FP] = 0.0
    s[SN] = 0.0
    s[UNL] = 1.0
    s[PROD_BETA] = 1.0
    if delta_d >= 0.0:
        s[KON] = 1.0
    else:
        s[KON] = 2.0


def _step(params, s, d, delta_d, ekp):
    """setTrialStrain past the first call, while the storey stands (flagStop = 0): the
    (drift, force) of the step, the state in ``s``."""
    mode, x, positive = _direction(params, s, d, delta_d)
    # OpenSees' envelPosCap2 / envelNegCap2 at x, evaluated once on every path
    if positive == 1.0:
        fe, eke, x = _envelope_pos(params, s, x)
    else:
        fe, eke, x = _envelope_neg(params, s, x)
    if mode == 1.0:  # beyond the largest positive drift: on the envelope
        d = x
        f = fe
        s[EK] = eke
        s[DMAX] = d
        s[FMAX] = f
        s[DLST_POS] = s[DMAX] + 1.0e-10
        s[FLST_POS] = f
    elif mode == 2.0:
        f = _reload_pos(s, d, x, fe, eke, delta_d, ekp)
    elif mode == 4.0:  # beyond the largest negative drift
        d = x
        f = fe
        s[EK] = eke
        s[DMIN] = d
        s[FMIN] = f
        s[DLST_NEG] = s[DMIN] - 1.0e-10
        s[FLST_NEG] = f
    elif mode == 5.0:
        f = _reload_neg(s, d, x, fe, eke, delta_d, ekp)
    else:
        d = x
        f = fe
        s[EK] = eke
    _deteriorate(params, s, f, delta_d)
    return d, f


def _power(base, exponent):
    """base ** exponent, 0 for a negative base and a non-integer exponent (round-off at an
    elastic reversal, where C's pow is NaN)."""
    if base < 0.0 and exponent != math.floor(exponent):
        base = 0.0
    return base ** exponent


def _unloading(params, s, rse, ekhard):
    """At a reversal: the unloading stiffness deteriorates (Lamda_K, c_K); the storey stops
    where it falls to the hardening slope ``ekhard``."""
    lk = params[8]
    if lk != 0.0:
        enrgtk = 2.0 * lk * params[3]
        if (s[ENRGTOT] - rse) >= enrgtk:
            betak = 1.0
        else:
            betak = _power((s[ENRGC] - rse) / (enrgtk - (s[ENRGTOT] - rse)), params[12])
        s[EKUNLOAD] = params[0] * (s[PROD_BETA] * (1.0 - betak))
        s[PROD_BETA] = s[PROD_BETA] * (1.0 - betak)
        if s[EKUNLOAD] <= ekhard:
            s[STOP] = 1.0


def _direction(params, s, d, delta_d):
    """The reversal bookkeeping of the step's direction, and which branch the step is on:
    (mode, where the envelope is evaluated, 1 for the positive envelope else 0)."""
    ke = params[0]
    if delta_d >= 0.0:
        if s[KON] == 2.0:
            s[KON] = 1.0
            s[UNL] = 0.0
            fp = s[FP]
            rse = 0.5 * fp * fp / s[EKUNLOAD]
            enrgtk = 2.0 * params[8] * params[3]
            a2 = enrgtk - (s[ENRGTOT] - rse)
            if a2 < 0.0 and enrgtk != 0.0:
                s[STOP] = 1.0
            _unloading(params, s, rse, s[EKHARD_NEG])
            if fp < 0.0:
                tst = s[DP] - fp / s[EKUNLOAD]
                if abs(s[DMAX] - params[3] / ke) >= 1.0e-10 and abs(tst) <= 1.0e-10:
                    s[SN] = 1.0e-9
                else:
                    s[SN] = s[DP] - fp / s[EKUNLOAD]
            if abs(s[DMIN] - s[DP]) <= 1.0e-10:
                s[SP] = s[SN] + 1.0e-10
        if d >= s[DMAX]:
            return 1.0, d, 1.0
        if abs(s[SN]) > 1.0e-10:
            return 2.0, s[DMAX], 1.0
        return 3.0, d, 1.0 if d > 0.0 else 0.0
    if s[KON] == 1.0:
        s[KON] = 2.0
        s[UNL] = 0.0
        fp = s[FP]
        rse = 0.5 * fp * fp / s[EKUNLOAD]
        _unloading(params, s, rse, s[EKHARD_POS])
        if fp > 0.0:
            tst = s[DP] - fp / s[EKUNLOAD]
            if abs(s[DMIN] - params[4] / ke) >= 1.0e-10 and abs(tst) <= 1.0e-10:
                s[SP] = 1.0e-9
            else:
                s[SP] = s[DP] - fp / s[EKUNLOAD]
        if abs(s[DMAX] - s[DP]) <= 1.0e-10:
            s[SN] = s[SP] - 1.0e-10
    if d <= s[DMIN]:
        return 4.0, d, 0.0
    if abs(s[SP]) > 1.0e-10:
        return 5.0, s[DMIN], 0.0
    return 6.0, d, 1.0 if d > 0.0 else 0.0


def _envelope_pos(params, s, x):
    """OpenSees' envelPosCap2 at x: (force, tangent, x); past theta_u x moves to the fracture
    drift and flagStop is set."""
    ke = params[0]
    fy = s[FY_POS]
    cp = s[CP_POS]
    fpeak_pos, fpeak_neg, cap_slope, cap_slope_neg = _backbone(params)
    dy = fy / ke
    if dy <= cp:
        res = params[17] * params[3]
        rcap = fy + s[ALFA_POS] * ke * (cp - dy)
        dres = cp + (res - rcap) / (cap_slope * ke)
        if x < 0.0:
            fe = 0.0
            eke = 1.0e-7
        elif x <= dy:
            eke = ke
            fe = eke * x
        elif x <= cp:
            eke = ke * s[ALFA_POS]
            fe = fy + eke * (x - dy)
        elif x <= dres:
            eke = cap_slope * ke
            fe = rcap + eke * (x - cp)
        else:
            eke = 1.0e-7
            fe = res + x * eke
    else:
        rcap = ke * cp
        res = params[17] * rcap
        dres = cp + (res - rcap) / (cap_slope * ke)
        if x < 0.0:
            fe = 0.0
            eke = 1.0e-7
        elif x <= cp:
            eke = ke
            fe = eke * x
        elif x <= dres:
            eke = cap_slope * ke
            fe = rcap + eke * (x - cp)
        else:
            eke = 1.0e-7
            fe = res + x * eke
    if x >= params[19]:
        eke = 1.0e-7
        fe = 1.0e-10
        x = params[19]
        s[STOP] = 1.0
    return fe, eke, x


def _envelope_neg(params, s, x):
    """OpenSees' envelNegCap2 at x (the mirror of :func:`_envelope_pos`, in its own order of
    operations)."""
    ke = params[0]
    fy = s[FY_NEG]
    cp = s[CP_NEG]
    fpeak_pos, fpeak_neg, cap_slope_pos, cap_slope = _backbone(params)
    dy = fy / ke
    if dy >= cp:
        res = params[18] * params[4]
        rcap = fy + s[ALFA_NEG] * ke * (cp - dy)
        dres = cp + (res - rcap) / (cap_slope * ke)
        if x > 0.0:
            fe = 0.0
            eke = 1.0e-7
        elif x >= dy:
            eke = ke
            fe = eke * x
        elif x >= cp:
            eke = ke * s[ALFA_NEG]
            fe = fy + eke * (x - dy)
        elif x >= dres:
            eke = ke * cap_slope
            fe = rcap + eke * (x - cp)
        else:
            eke = 1.0e-7
            fe = res + eke * x
    else:
        rcap = ke * cp
        res = params[18] * rcap
        dres = cp + (res - rcap) / (cap_slope * ke)
        if x > 0.0:
            fe = 0.0
            eke = 1.0e-7
        elif x >= cp:
            eke = ke
            fe = eke * x
        elif x >= dres:
            eke = ke * cap_slope
            fe = rcap + eke * (x - cp)
        else:
            eke = 1.0e-7
            fe = res + eke * x
    if x <= -params[20]:
        eke = 1.0e-7
        fe = 1.0e-10
        x = -params[20]
        s[STOP] = 1.0
    return fe, eke, x


def _reload_pos(s, d, x, fe, eke, delta_d, ekp):
    """Moving positive inside the loop: unloading, then reloading toward the largest
    positive drift (peak-oriented, Ibarra-Krawinkler's last unloading point); the force."""
    s[DMAX] = x
    s[FMAX] = fe
    s[EK] = eke
    sn = s[SN]
    if d <= sn:
        s[EK] = s[EKUNLOAD]
        f = s[FP] + s[EK] * delta_d
        if s[UNL] == 0.0 and abs(s[EK] - ekp) > 1.0e-10 and s[DP] != s[DMIN]:
            s[DLST_NEG] = s[DP]
            s[FLST_NEG] = s[FP]
        return f
    dmax = s[DMAX]
    fmax = s[FMAX]
    dlst = s[DLST_POS]
    flst = s[FLST_POS]
    ek = fmax / (dmax - sn)
    f2 = ek * (d - sn)
    if dlst > sn and dlst < dmax:
        ekc = flst / (dlst - sn)
        if ekc > ek and flst < fmax:
            if d < dlst:
                ek = flst / (dlst - sn)
                f2 = ek * (d - sn)
            else:
                ek = (fmax - flst) / (dmax - dlst)
                f2 = flst + ek * (d - dlst)
    f1 = s[FP] + s[EKUNLOAD] * delta_d
    if f1 < f2:
        f = f1
    else:
        f = f2
    if abs(f - f1) < 1.0e-10:
        ek = s[EKUNLOAD]
    s[EK] = ek
    return f


def _reload_neg(s, d, x, fe, eke, delta_d, ekp):
    """Moving negative inside the loop (the mirror of :func:`_reload_pos`); the force."""
    s[DMIN] = x
    s[FMIN] = fe
    s[EK] = eke
    sp = s[SP]
    if d >= sp:
        s[EK] = s[EKUNLOAD]
        f = s[FP] + s[EK] * delta_d
        if s[UNL] == 0.0 and abs(s[EK] - ekp) > 1.0e-10 and s[DP] != s[DMAX]:
            s[DLST_POS] = s[DP]
            s[FLST_POS] = s[FP]
        return f
    dmin = s[DMIN]
    fmin = s[FMIN]
    dlst = s[DLST_NEG]
    flst = s[FLST_NEG]
    ek = fmin / (dmin - sp)
    f2 = ek * (d - sp)
    if dlst < sp and dlst > dmin:
        ekc = flst / (dlst - sp)
        if ekc > ek and flst > fmin:
            if d > dlst:
                ek = flst / (dlst - sp)
                f2 = ek * (d - sp)
            else:
                ek = (fmin - flst) / (dmin - dlst)
                f2 = flst + ek * (d - dlst)
    f1 = s[FP] + s[EKUNLOAD] * delta_d
    if f1 > f2:
        f = f1
    else:
        f = f2
    if abs(f - f1) < 1.0e-10:
        ek = s[EKUNLOAD]
    s[EK] = ek
    return f


def _betas(params, s):
    """Rahnama & Krawinkler's beta of basic strength, accelerated reloading and the cap, as
    (beta_S, beta_A, beta_C), from the energies of the half cycle and in all."""
    my_pos = params[3]
    ls = params[5]
    ld = params[6]
    la = params[7]
    enrgts = ls * my_pos
    enrgta = la * my_pos
    enrgtd = ld * my_pos
    enrgtot = s[ENRGTOT]
    enrgc = s[ENRGC]
    betas = 0.0
    betaa = 0.0
    betac = 0.0
    if enrgtot >= enrgts and enrgts != 0.0:
        betas = 1.0
    elif enrgtot >= enrgta and enrgta != 0.0:
        betaa = 1.0
    elif enrgtot >= enrgtd and enrgtd == 0.0:
        betac = 1.0
    else:
        if ls != 0.0:
            betas = _power(enrgc / (enrgts - enrgtot), params[9])
        if la != 0.0:
            betaa = _power(enrgc / (enrgta - enrgtot), params[11])
        if ld != 0.0:
            if enrgtd - enrgtot == 0.0:
                betac = 1.0
            else:
                betac = _power(enrgc / (enrgtd - enrgtot), params[10])
        if abs(betas) >= 1.0:
            betas = 1.0
        if abs(betaa) >= 1.0:
            betaa = 1.0
        if abs(betac) >= 1.0:
            betac = 1.0
    return betas, betaa, betac


def _deteriorated(ke, cap_slope, fy, alfa, fcapref, extreme, betas, betaa, betac, rate):
    """One direction's backbone after a half cycle past yield: (yield force, hardening ratio,
    cap reference force, target drift, hardening slope, the two candidate capping drifts)."""
    fy = fy * (1.0 - betas * rate)
    alfa = alfa * (1.0 - betas * rate)
    fcapref = fcapref * (1.0 - betac * rate)
    extreme = extreme * (1.0 + betaa)
    dy = fy / ke
    ekhard = alfa * ke
    dcap1 = fcapref / (ke - cap_slope * ke)
    dcap2 = (fcapref + ekhard * dy - fy) / (ekhard - cap_slope * ke)
    return fy, alfa, fcapref, extreme, ekhard, dcap1, dcap2


def _deteriorate(params, s, f, delta_d):
    """The energy of the step; at a reversal of force past yield, the cyclic deterioration
    of the direction the step moves in."""
    ke = params[0]
    fp = s[FP]
    enrgi = 0.5 * (f + fp) * delta_d
    s[ENRGC] = s[ENRGC] + enrgi
    s[ENRGTOT] = s[ENRGTOT] + enrgi
    flagdeg = 0.0
    if f * fp < 0.0:
        if (fp > 0.0 and s[DMAX] > s[FY_POS] / ke) or (fp < 0.0 and s[DMIN] < s[FY_NEG] / ke):
            flagdeg = 1.0
    if flagdeg == 1.0:
        betas, betaa, betac = _betas(params, s)
        s[ENRGC] = 0.0
        fpeak_pos, fpeak_neg, cap_slope_pos, cap_slope_neg = _backbone(params)
        if delta_d < 0.0:
            fy, alfa, fcapref, dmin, ekhard, dcap1, dcap2 = _deteriorated(
                ke, cap_slope_neg, s[FY_NEG], s[ALFA_NEG], s[FCAP_NEG], s[DMIN], betas, betaa,
                betac, params[22])
            s[FY_NEG] = fy
            s[ALFA_NEG] = alfa
            s[FCAP_NEG] = fcapref
            s[DMIN] = dmin
            s[EKHARD_NEG] = ekhard
            if dcap1 < dcap2:
                s[CP_NEG] = dcap1
            else:
                s[CP_NEG] = dcap2
        else:
            fy, alfa, fcapref, dmax, ekhard, dcap1, dcap2 = _deteriorated(
                ke, cap_slope_pos, s[FY_POS], s[ALFA_POS], s[FCAP_POS], s[DMAX], betas, betaa,
                betac, params[21])
            s[FY_POS] = fy
            s[ALFA_POS] = alfa
            s[FCAP_POS] = fcapref
            s[DMAX] = dmax
            s[EKHARD_POS] = ekhard
            if dcap1 > dcap2:
                s[CP_POS] = dcap1
            else:
                s[CP_POS] = dcap2
