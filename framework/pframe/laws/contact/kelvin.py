"""Kelvin (linear spring-dashpot) contact, Anagnostopoulos (1988).

F = k delta + c delta_dot while delta > 0, with c = 2 zeta sqrt(k m1 m2 / (m1 + m2)) and
zeta = -ln e / sqrt(pi^2 + ln^2 e). With ``keep_tension: true`` the force may turn negative
during rebound (the drawback the paper shows in its Figure 6); by default the force is
clipped at zero, which makes the real restitution somewhat higher than e (0.47 for e = 0.4).

``calibration: exact``: with ``keep_tension`` the published zeta is already exact; clipped,
the floors separate where the force reaches zero and the restitution is
exp(-2 zeta arccos(zeta) / sqrt(1 - zeta^2)), which is inverted for zeta
(``pframe.laws.restitution.kelvin_clipped_zeta``).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.facts import Impact
from pframe.laws.params import (
    Calibration,
    ContactStiffness,
    DampedRestitution,
    kelvin_damping_ratio,
)
from pframe.laws.registry import SpringContact, contact_law
from pframe.laws.restitution import (
    kelvin_clipped_restitution,
    kelvin_clipped_zeta,
    kelvin_tension_restitution,
)


@contact_law("kelvin")
class Kelvin(SpringContact):
    class Params(ContactStiffness):
        law: Literal["kelvin"]
        restitution: DampedRestitution
        keep_tension: bool = Field(
            False, description="Keep the tensile force in rebound (no clipping at zero)."
        )
        calibration: Calibration = "published"

    free_when_open = True
    param_names = ("stiffness", "damping", "keep_tension")
    branches = "kelvin"
    examples = ({"stiffness": 2.0e7, "restitution": 0.6},
                {"stiffness": 2.0e6, "restitution": 0.6},
                {"stiffness": 2.0e6, "restitution": 0.6, "keep_tension": True})
    # With tension the force jumps by c v at onset and at separation, but the two O(dt)
    # impulse errors cancel to O(dt^2) (measured at 1000 .. 8000 steps per contact: 1.1e-6,
    # 2.8e-7, 6.9e-8, 1.7e-8); clipped, only the onset jump remains, an O(dt) impulse error
    # c v dt / 2 (4.3e-4, 2.1e-4, 1.1e-4, 5.4e-5).
    impacts = {
        "kelvin-tension": Impact(
            {"stiffness": 1.0e7, "keep_tension": True}, "`kelvin`, `keep_tension: true`",
            calibrations=("published",),
            descriptions={"published": "published (Anagnostopoulos 1988) = exact"}),
        "kelvin-clipped": Impact({"stiffness": 1.0e7}, "`kelvin` (clipped)", tolerance=3e-4),
    }

    @classmethod
    def reference_force(cls, params, context, v0):
        """Anagnostopoulos (1988): F = k delta + c delta', c = 2 zeta sqrt(k m_eff),
        zeta = -ln e / sqrt(pi^2 + ln^2 e) (``calibration: exact``: the law's zeta), clipped
        at zero unless ``keep_tension``."""
        k = params.resolve_stiffness(context)
        ln_e = math.log(params.restitution)
        zeta = (-ln_e / math.sqrt(math.pi**2 + ln_e**2) if params.calibration == "published"
                else cls.zeta(params))
        c = 2.0 * zeta * math.sqrt(k * context.effective_mass)
        if params.keep_tension:
            return lambda x, r: k * x + c * r
        return lambda x, r: max(k * x + c * r, 0.0)

    @classmethod
    def zeta(cls, params) -> float:
        e = params.restitution
        if params.calibration == "exact" and not params.keep_tension:
            return kelvin_clipped_zeta(e)
        return kelvin_damping_ratio(e)

    @classmethod
    def published_source(cls, params) -> str:
        return "Anagnostopoulos 1988"

    @classmethod
    def rebound(cls, params) -> float:
        """The restitution of a two-body impact with this damping (docs/restitution.md)."""
        zeta = cls.zeta(params)
        if params.keep_tension:
            return kelvin_tension_restitution(zeta)
        return kelvin_clipped_restitution(zeta)

    @classmethod
    def pack(cls, params, context=None):
        k = params.resolve_stiffness(context)
        zeta = cls.zeta(params)
        c = 2.0 * zeta * math.sqrt(k * context.effective_mass)
        return (k, c, 1.0 if params.keep_tension else 0.0)

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            return 0.0, 0.0, 0.0
        f = params[0] * deformation + params[1] * rate
        if f < 0.0 and params[2] == 0.0:
            return 0.0, 0.0, 0.0
        return f, params[0], params[1]
