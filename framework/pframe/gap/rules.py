"""Code and research rules for the minimum separation of two buildings from their peak
displacements u_A, u_B (relative to the ground, at one level, each building run alone).

- ABS: u_A + u_B, the absolute sum (the two peaks in opposite directions at once).
- SRSS: sqrt(u_A^2 + u_B^2), the form of ASCE 7 section 12.12.3 (delta_M) and of EN 1998-1
  section 4.4.2.7(2); EN 1998-1 section 4.4.2.7(3) allows 0.7 of it where the floor levels of
  the two buildings coincide (``SRSS_EN_0.7``, an option).
- DDC: the double-difference combination (Penzien 1997; Lopez Garcia 2004)
  sqrt(u_A^2 + u_B^2 - 2 rho u_A u_B), rho the CQC correlation coefficient of the two
  buildings' first modes (Der Kiureghian 1981):

      rho = 8 sqrt(xi_i xi_j) (xi_i + r xi_j) r^{3/2}
            / [(1 - r^2)^2 + 4 xi_i xi_j r (1 + r^2) + 4 (xi_i^2 + xi_j^2) r^2],

  r = T_short / T_long <= 1, building i the short-period one.

Code rules (ASCE 7, IS 1893, EN 1998-1, NBC, TBDY 2018, NTC-DS, GB 50011 and rules of the
user's own) are a table in :mod:`pframe.gap.codes`; :mod:`pframe.gap.selection` chooses them
for an audit or a study. The functions below ``CODE_RULES`` are the earlier interface to two
of them, kept: they evaluate the table.
"""

from __future__ import annotations

import numpy as np

from pframe.gap.codes import CODES, separation, separation_from_peaks

#: the rules every audit reports, in order; "simulated" is the no-contact run's g_req
RULES = ("ABS", "SRSS", "DDC", "simulated")
EN_RULE = "SRSS_EN_0.7"
EN_FACTOR = 0.7


def cqc_correlation(period_a, period_b, damping_a, damping_b):
    """rho of two modes of periods T_a, T_b (s) and damping ratios xi_a, xi_b (arrays
    broadcast); symmetric in the two buildings, 1 for equal periods and dampings."""
    ta, tb = np.asarray(period_a, float), np.asarray(period_b, float)
    xa, xb = np.asarray(damping_a, float), np.asarray(damping_b, float)
    short_is_a = ta <= tb
    r = np.where(short_is_a, ta / tb, tb / ta)
    xi_i = np.where(short_is_a, xa, xb)  # the short-period building's damping
    xi_j = np.where(short_is_a, xb, xa)
    num = 8.0 * np.sqrt(xi_i * xi_j) * (xi_i + r * xi_j) * r**1.5
    den = (1.0 - r * r) ** 2 + 4.0 * xi_i * xi_j * r * (1.0 + r * r) + 4.0 * (xi_i**2 + xi_j**2) * r * r
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(den > 0, num / np.where(den > 0, den, 1.0), 1.0)
    return rho


#: the earlier code-rule names and their factors' defaults, from the table
#: (:data:`pframe.gap.codes.CODES`)
CODE_RULES = {code: (tuple(r.name for r in CODES[code]),
                     {k: f.default for k, f in CODES[code][0].factors})
              for code in ("asce7", "is1893")}


def design_displacement(u, r_factor, importance):
    """The elastic displacement under a code's design forces (the motion's elastic forces
    divided by R / I) of a building whose simulated elastic peak displacement is ``u``."""
    return np.abs(np.asarray(u, float)) * importance / r_factor


def asce7_separation(delta_max_a, delta_max_b, cd_a, cd_b, ie_a, ie_b) -> dict[str, np.ndarray]:
    """ASCE/SEI 7-16 12.12.3 from the two maximum elastic displacements delta_max (m, under the
    design forces): delta_M = C_d delta_max / I_e; the SRSS of the two on one property, their
    sum across a property line (each building set back by its own delta_M)."""
    fa, fb = {"Cd": cd_a, "Ie": ie_a}, {"Cd": cd_b, "Ie": ie_b}
    return {name: separation(name, delta_max_a, delta_max_b, factors_a=fa, factors_b=fb)
            for name in CODE_RULES["asce7"][0]}


def is1893_separation(delta_a, delta_b, r_a, r_b) -> dict[str, np.ndarray]:
    """IS 1893 (Part 1):2016 7.11.3 from the two storey displacements under the design lateral
    forces (m, 7.11.1): R times their sum, R / 2 where the floor levels coincide."""
    fa, fb = {"R": r_a}, {"R": r_b}
    return {"IS1893": separation("IS1893", delta_a, delta_b, factors_a=fa, factors_b=fb),
            "IS1893_same_levels": separation("IS1893", delta_a, delta_b, aligned=True,
                                             factors_a=fa, factors_b=fb)}


def code_separations(u_a, u_b, codes, factors_a=None, factors_b=None) -> dict[str, np.ndarray]:
    """The rules of ``codes`` (names of :data:`CODE_RULES`) from the simulated elastic peak
    displacements u_a, u_b (m) of each building, floors not aligned (IS 1893 also gives
    ``IS1893_same_levels``, aligned); ``factors_a``/``factors_b`` update the defaults."""
    out = {}
    for code in codes:
        for rule in CODES[code]:
            out[rule.name] = separation_from_peaks(rule, u_a, u_b, factors_a=factors_a,
                                                   factors_b=factors_b)
        if code == "is1893":
            out["IS1893_same_levels"] = separation_from_peaks(
                "IS1893", u_a, u_b, factors_a=factors_a, factors_b=factors_b, aligned=True)
    return out


def separations(u_a, u_b, rho, en_coincident: bool = False) -> dict[str, np.ndarray]:
    """ABS, SRSS, DDC (and SRSS_EN_0.7) separations (m) from peak displacements (m)."""
    u_a, u_b = np.abs(np.asarray(u_a, float)), np.abs(np.asarray(u_b, float))
    out = {
        "ABS": u_a + u_b,
        "SRSS": np.sqrt(u_a**2 + u_b**2),
        "DDC": np.sqrt(np.maximum(u_a**2 + u_b**2 - 2.0 * rho * u_a * u_b, 0.0)),
    }
    if en_coincident:
        out[EN_RULE] = EN_FACTOR * out["SRSS"]
    return out
