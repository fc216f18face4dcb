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
state, as OpenSees' ``revertToLastCommit``. Its two envelope routines are evaluated at one
place (every path of ``setTrialStrain`` calls exactly one of them once). Two guards where
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
        ke = params[0]
        my_pos = params[3]
        my_neg = params[4]
        ls = params[5]
        ld = params[6]
        la = params[7]
        lk = params[8]
        cs = params[9]
        cd = params[10]
        ca = params[11]
        ck = params[12]
        theta_p_pos = params[13]
        theta_p_neg = params[14]
        frac_pos = params[19]
        frac_neg = -params[20]
        d_pos = params[21]
        d_neg = params[22]
        enrgts = ls * my_pos
        enrgtk = 2.0 * lk * my_pos
        enrgta = la * my_pos
        enrgtd = ld * my_pos
        ekhard_pos0 = ke * params[1]
        ekhard_neg0 = ke * params[2]
        fpeak_pos = my_pos + ekhard_pos0 * theta_p_pos
        fpeak_neg = my_neg + ekhard_neg0 * (-theta_p_neg)
        cap_slope_pos = -fpeak_pos / (params[15] * ke)
        cap_slope_neg = fpeak_neg / (params[16] * ke)

        dp = committed[0]
        fp = committed[1]
        ek = committed[2]
        unl = committed[3]
        kon = committed[4]
        flag_stop = committed[5]
        dmax = committed[6]
        dmin = committed[7]
        fmax = committed[8]
        fmin = committed[9]
        fy_pos = committed[10]
        fy_neg = committed[11]
        dlst_pos = committed[12]
        dlst_neg = committed[13]
        flst_pos = committed[14]
        flst_neg = committed[15]
        sn = committed[16]
        sp = committed[17]
        enrgc = committed[18]
        enrgtot = committed[19]
        fcapref_pos = committed[20]
        fcapref_neg = committed[21]
        ekunload = committed[22]
        cp_pos = committed[23]
        cp_neg = committed[24]
        ekhard_pos = committed[25]
        ekhard_neg = committed[26]
        alfa_pos = committed[27]
        alfa_neg = committed[28]
        prod_beta = committed[29]
        ekp = ek

        d = deformation
        delta_d = d - dp
        f = fp
        if not (abs(delta_d) < 1.0e-18 and d != 0.0 and kon != 0.0):
            if kon == 0.0:
                alfa_neg = params[2]
                alfa_pos = params[1]
                ekhard_pos = ekhard_pos0
                ekhard_neg = ekhard_neg0
                enrgtot = 0.0
                enrgc = 0.0
                dmax = my_pos / ke
                dmin = my_neg / ke
                ekp = ke
                ekunload = ke
                fy_pos = my_pos
                fy_neg = my_neg
                cp_pos = my_pos / ke + theta_p_pos
                cp_neg = my_neg / ke + (-theta_p_neg)
                fcapref_pos = -cap_slope_pos * ke * (theta_p_pos + my_pos / ke) + fpeak_pos
                fcapref_neg = -cap_slope_neg * ke * (-theta_p_neg + my_neg / ke) + fpeak_neg
                fmin = my_neg
                fmax = my_pos
                flag_stop = 0.0
                dlst_neg = my_neg / ke
                dlst_pos = my_pos / ke
                flst_neg = my_neg
                flst_pos = my_pos
                ek = 0.0
                sp = 0.0
                fp = 0.0
                sn = 0.0
                f = 0.0
                unl = 1.0
                prod_beta = 1.0
                if delta_d >= 0.0:
                    kon = 1.0
                else:
                    kon = 2.0
            if flag_stop == 0.0:
                # which branch, and where its one envelope evaluation is
                mode = 0.0
                if delta_d >= 0.0:
                    if kon == 2.0:
                        kon = 1.0
                        unl = 0.0
                        rse = 0.5 * fp * fp / ekunload
                        a2 = enrgtk - (enrgtot - rse)
                        if a2 < 0.0 and enrgtk != 0.0:
                            flag_stop = 1.0
                        if lk != 0.0:
                            if (enrgtot - rse) >= enrgtk:
                                betak = 1.0
                            else:
                                base = (enrgc - rse) / (enrgtk - (enrgtot - rse))
                                if base < 0.0 and ck != math.floor(ck):
                                    base = 0.0
                                betak = base ** ck
                            ekunload = ke * (prod_beta * (1.0 - betak))
                            prod_beta = prod_beta * (1.0 - betak)
                            if ekunload <= ekhard_neg:
                                flag_stop = 1.0
                        if fp < 0.0:
                            tst = dp - fp / ekunload
                            if abs(dmax - my_pos / ke) >= 1.0e-10 and abs(tst) <= 1.0e-10:
                                sn = 1.0e-9
                            else:
                                sn = dp - fp / ekunload
                        if abs(dmin - dp) <= 1.0e-10:
                            sp = sn + 1.0e-10
                    if d >= dmax:
                        mode = 1.0
                        x = d
                        positive = 1.0
                    elif abs(sn) > 1.0e-10:
                        mode = 2.0
                        x = dmax
                        positive = 1.0
                    else:
                        mode = 3.0
                        x = d
                        positive = 1.0 if d > 0.0 else 0.0
                else:
                    if kon == 1.0:
                        kon = 2.0
                        unl = 0.0
                        rse = 0.5 * fp * fp / ekunload
                        if lk != 0.0:
                            if (enrgtot - rse) >= enrgtk:
                                betak = 1.0
                            else:
                                base = (enrgc - rse) / (enrgtk - (enrgtot - rse))
                                if base < 0.0 and ck != math.floor(ck):
                                    base = 0.0
                                betak = base ** ck
                            ekunload = ke * (prod_beta * (1.0 - betak))
                            prod_beta = prod_beta * (1.0 - betak)
                            if ekunload <= ekhard_pos:
                                flag_stop = 1.0
                        if fp > 0.0:
                            tst = dp - fp / ekunload
                            if abs(dmin - my_neg / ke) >= 1.0e-10 and abs(tst) <= 1.0e-10:
                                sp = 1.0e-9
                            else:
                                sp = dp - fp / ekunload
                        if abs(dmax - dp) <= 1.0e-10:
                            sn = sp - 1.0e-10
                    if d <= dmin:
                        mode = 4.0
                        x = d
                        positive = 0.0
                    elif abs(sp) > 1.0e-10:
                        mode = 5.0
                        x = dmin
                        positive = 0.0
                    else:
                        mode = 6.0
                        x = d
                        positive = 1.0 if d > 0.0 else 0.0

                # OpenSees' envelPosCap2 / envelNegCap2 at x: fe, eke (x moves to the
                # fracture drift, and flagStop is set, past theta_u)
                if positive == 1.0:
                    dy = fy_pos / ke
                    if dy <= cp_pos:
                        res = params[17] * my_pos
                        rcap = fy_pos + alfa_pos * ke * (cp_pos - dy)
                        dres = cp_pos + (res - rcap) / (cap_slope_pos * ke)
                        if x < 0.0:
                            fe = 0.0
                            eke = 1.0e-7
                        elif x <= dy:
                            eke = ke
                            fe = eke * x
                        elif x <= cp_pos:
                            eke = ke * alfa_pos
                            fe = fy_pos + eke * (x - dy)
                        elif x <= dres:
                            eke = cap_slope_pos * ke
                            fe = rcap + eke * (x - cp_pos)
                        else:
                            eke = 1.0e-7
                            fe = res + x * eke
                    else:
                        rcap = ke * cp_pos
                        res = params[17] * rcap
                        dres = cp_pos + (res - rcap) / (cap_slope_pos * ke)
                        if x < 0.0:
                            fe = 0.0
                            eke = 1.0e-7
                        elif x <= cp_pos:
                            eke = ke
                            fe = eke * x
                        elif x <= dres:
                            eke = cap_slope_pos * ke
                            fe = rcap + eke * (x - cp_pos)
                        else:
                            eke = 1.0e-7
                            fe = res + x * eke
                    if x >= frac_pos:
                        eke = 1.0e-7
                        fe = 1.0e-10
                        x = frac_pos
                        flag_stop = 1.0
                else:
                    dy = fy_neg / ke
                    if dy >= cp_neg:
                        res = params[18] * my_neg
                        rcap = fy_neg + alfa_neg * ke * (cp_neg - dy)
                        dres = cp_neg + (res - rcap) / (cap_slope_neg * ke)
                        if x > 0.0:
                            fe = 0.0
                            eke = 1.0e-7
                        elif x >= dy:
                            eke = ke
                            fe = eke * x
                        elif x >= cp_neg:
                            eke = ke * alfa_neg
                            fe = fy_neg + eke * (x - dy)
                        elif x >= dres:
                            eke = ke * cap_slope_neg
                            fe = rcap + eke * (x - cp_neg)
                        else:
                            eke = 1.0e-7
                            fe = res + eke * x
                    else:
                        rcap = ke * cp_neg
                        res = params[18] * rcap
                        dres = cp_neg + (res - rcap) / (cap_slope_neg * ke)
                        if x > 0.0:
                            fe = 0.0
                            eke = 1.0e-7
                        elif x >= cp_neg:
                            eke = ke
                            fe = eke * x
                        elif x >= dres:
                            eke = ke * cap_slope_neg
                            fe = rcap + eke * (x - cp_neg)
                        else:
                            eke = 1.0e-7
                            fe = res + eke * x
                    if x <= frac_neg:
                        eke = 1.0e-7
                        fe = 1.0e-10
                        x = frac_neg
                        flag_stop = 1.0

                if mode == 1.0:
                    d = x
                    f = fe
                    ek = eke
                    dmax = d
                    fmax = f
                    dlst_pos = dmax + 1.0e-10
                    flst_pos = f
                elif mode == 2.0:
                    dmax = x
                    fmax = fe
                    ek = eke
                    if d <= sn:
                        ek = ekunload
                        f = fp + ek * delta_d
                        if unl == 0.0 and abs(ek - ekp) > 1.0e-10 and dp != dmin:
                            dlst_neg = dp
                            flst_neg = fp
                    else:
                        ek = fmax / (dmax - sn)
                        f2 = ek * (d - sn)
                        if dlst_pos > sn and dlst_pos < dmax:
                            ekc = flst_pos / (dlst_pos - sn)
                            if ekc > ek and flst_pos < fmax:
                                if d < dlst_pos:
                                    ek = flst_pos / (dlst_pos - sn)
                                    f2 = ek * (d - sn)
                                else:
                                    ek = (fmax - flst_pos) / (dmax - dlst_pos)
                                    f2 = flst_pos + ek * (d - dlst_pos)
                        f1 = fp + ekunload * delta_d
                        if f1 < f2:
                            f = f1
                        else:
                            f = f2
                        if abs(f - f1) < 1.0e-10:
                            ek = ekunload
                elif mode == 4.0:
                    d = x
                    f = fe
                    ek = eke
                    dmin = d
                    fmin = f
                    dlst_neg = dmin - 1.0e-10
                    flst_neg = f
                elif mode == 5.0:
                    dmin = x
                    fmin = fe
                    ek = eke
                    if d >= sp:
                        ek = ekunload
                        f = fp + ek * delta_d
                        if unl == 0.0 and abs(ek - ekp) > 1.0e-10 and dp != dmax:
                            dlst_pos = dp
                            flst_pos = fp
                    else:
                        ek = fmin / (dmin - sp)
                        f2 = ek * (d - sp)
                        if dlst_neg < sp and dlst_neg > dmin:
                            ekc = flst_neg / (dlst_neg - sp)
                            if ekc > ek and flst_neg > fmin:
                                if d > dlst_neg:
                                    ek = flst_neg / (dlst_neg - sp)
                                    f2 = ek * (d - sp)
                                else:
                                    ek = (fmin - flst_neg) / (dmin - dlst_neg)
                                    f2 = flst_neg + ek * (d - dlst_neg)
                        f1 = fp + ekunload * delta_d
                        if f1 > f2:
                            f = f1
                        else:
                            f = f2
                        if abs(f - f1) < 1.0e-10:
                            ek = ekunload
                else:
                    d = x
                    f = fe
                    ek = eke

                enrgi = 0.5 * (f + fp) * delta_d
                enrgc = enrgc + enrgi
                enrgtot = enrgtot + enrgi
                flagdeg = 0.0
                if f * fp < 0.0:
                    if (fp > 0.0 and dmax > fy_pos / ke) or (fp < 0.0 and dmin < fy_neg / ke):
                        flagdeg = 1.0
                if flagdeg == 1.0:
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
                            base = enrgc / (enrgts - enrgtot)
                            if base < 0.0 and cs != math.floor(cs):
                                base = 0.0
                            betas = base ** cs
                        if la != 0.0:
                            base = enrgc / (enrgta - enrgtot)
                            if base < 0.0 and ca != math.floor(ca):
                                base = 0.0
                            betaa = base ** ca
                        if ld != 0.0:
                            if enrgtd - enrgtot == 0.0:
                                betac = 1.0
                            else:
                                base = enrgc / (enrgtd - enrgtot)
                                if base < 0.0 and cd != math.floor(cd):
                                    base = 0.0
                                betac = base ** cd
                        if abs(betas) >= 1.0:
                            betas = 1.0
                        if abs(betaa) >= 1.0:
                            betaa = 1.0
                        if abs(betac) >= 1.0:
                            betac = 1.0
                    enrgc = 0.0
                    if delta_d < 0.0:
                        fy_neg = fy_neg * (1.0 - betas * d_neg)
                        alfa_neg = alfa_neg * (1.0 - betas * d_neg)
                        fcapref_neg = fcapref_neg * (1.0 - betac * d_neg)
                        dmin = dmin * (1.0 + betaa)
                        dy_neg = fy_neg / ke
                        ekhard_neg = alfa_neg * ke
                        dcap1 = fcapref_neg / (ke - cap_slope_neg * ke)
                        dcap2 = (fcapref_neg + ekhard_neg * dy_neg - fy_neg) / (
                            ekhard_neg - cap_slope_neg * ke)
                        if dcap1 < dcap2:
                            cp_neg = dcap1
                        else:
                            cp_neg = dcap2
                    else:
                        fy_pos = fy_pos * (1.0 - betas * d_pos)
                        alfa_pos = alfa_pos * (1.0 - betas * d_pos)
                        fcapref_pos = fcapref_pos * (1.0 - betac * d_pos)
                        dmax = dmax * (1.0 + betaa)
                        dy_pos = fy_pos / ke
                        ekhard_pos = alfa_pos * ke
                        dcap1 = fcapref_pos / (ke - cap_slope_pos * ke)
                        dcap2 = (fcapref_pos + ekhard_pos * dy_pos - fy_pos) / (
                            ekhard_pos - cap_slope_pos * ke)
                        if dcap1 > dcap2:
                            cp_pos = dcap1
                        else:
                            cp_pos = dcap2
            else:
                f = 0.0
                ek = 0.0
            dp = d
            fp = f

        trial[0] = dp
        trial[1] = fp
        trial[2] = ek
        trial[3] = unl
        trial[4] = kon
        trial[5] = flag_stop
        trial[6] = dmax
        trial[7] = dmin
        trial[8] = fmax
        trial[9] = fmin
        trial[10] = fy_pos
        trial[11] = fy_neg
        trial[12] = dlst_pos
        trial[13] = dlst_neg
        trial[14] = flst_pos
        trial[15] = flst_neg
        trial[16] = sn
        trial[17] = sp
        trial[18] = enrgc
        trial[19] = enrgtot
        trial[20] = fcapref_pos
        trial[21] = fcapref_neg
        trial[22] = ekunload
        trial[23] = cp_pos
        trial[24] = cp_neg
        trial[25] = ekhard_pos
        trial[26] = ekhard_neg
        trial[27] = alfa_pos
        trial[28] = alfa_neg
        trial[29] = prod_beta
        return fp, ek, 0.0
