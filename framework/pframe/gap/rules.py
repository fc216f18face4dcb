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
"""

from __future__ import annotations

import numpy as np

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
