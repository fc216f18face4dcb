"""Bumper contact: an elastomeric bumper of finite thickness on one side of the gap.

After the model of Polycarpou, Komodromos & Polycarpou (2013, EESD 42): while the rubber
compresses the contact is a soft Hertz-damp law; once the rubber is crushed to a given ratio of
its thickness the floors meet through it and a hard Hertz contact adds to the rubber's force:

    F = [k_r delta^1.5 + k_h <delta - delta_c>^1.5] (1 + chi delta' / v_ref),
    delta_c = crush_ratio * thickness,

with <x> = max(x, 0). The gap is measured to the bumper's face (the rubber's thickness is
inside the gap: a contact's ``gap`` is the clear distance to the bumper). Damping is the
Hunt-Crossley form shared by both stages, one chi from the restitution e (``calibration``:
``exact`` by default, or ``published``, the Muthukumar & DesRoches formula
chi = 3 (1 - e^2) / 4); v_ref is the approach
velocity v0 at onset, never less than the energy velocity of the contact (as
``improved_kelvin`` / ``hertzdamp``, docs/restitution.md). With one chi for both stages a
two-body impact rebounds with the Hunt-Crossley restitution of chi whatever the spring (the
restitution of m x'' = -P(x) (1 + chi x' / v0) does not depend on P): e itself with
``calibration: exact``, whether the impact crushes the bumper or not. Crushing raises the peak
force and shortens the contact (tests/test_bumper.py checks both against an ODE solution).

The force is C1 at delta_c (the hard term starts with zero force and zero slope), so the
stage change needs no event.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field

from pframe.laws.contact._hunt_crossley import (
    hunt_crossley_rebound,
    hunt_crossley_tangent_states,
    impact_damping,
    impact_inverse_mass,
)
from pframe.laws.contact.hertzdamp import CHI_FORMULAS
from pframe.laws.facts import Impact
from pframe.laws.params import HERTZ_STIFFNESS, Calibration, DampedRestitution, LawParams, Positive
from pframe.laws.registry import HertzContact, contact_law
from pframe.laws.restitution import hunt_crossley_chi


@contact_law("bumper")
class Bumper(HertzContact):
    class Params(LawParams):
        law: Literal["bumper"]
        stiffness: Positive = Field(
            description="Hertz stiffness k_r of the rubber stage (N/m^1.5), F = k_r delta^1.5 "
                        "while the bumper compresses; much softer than the hard contact.")
        hard_stiffness: Positive = Field(description="Hertz stiffness k_h added once the "
                                                     "bumper is crushed: " + HERTZ_STIFFNESS)
        thickness: Positive = Field(description="Thickness of the rubber bumper (m).")
        crush_ratio: float = Field(0.9, gt=0, le=1, description="Share of the thickness at "
                                   "which the rubber is crushed and the hard contact begins.")
        restitution: DampedRestitution
        calibration: Calibration = Field(
            "exact", description="exact (the default here): the damping with which an impact "
                                 "rebounds with e, crushed or not; published: the Muthukumar & "
                                 "DesRoches 2006 formula chi = 3 (1 - e^2) / 4 (no damping "
                                 "formula was published for this composed law).")

    free_when_open = True
    param_names = ("stiffness", "exponent", "chi", "inverse_effective_mass", "hard_stiffness",
                   "crush_depth")
    state_names = ("onset_velocity", "in_contact")
    dimensions = {"stiffness": "hertz_stiffness", "hard_stiffness": "hertz_stiffness",
                  "thickness": "length", "crush_ratio": "dimensionless",
                  "restitution": "dimensionless"}
    branches = "bumper"
    opensees = "Parallel(Hertzdamp, Hertzdamp)"  # but in conditions (pframe.peers.twins)
    tangent_states = classmethod(hunt_crossley_tangent_states)
    examples = ({"stiffness": 1.0e8, "hard_stiffness": 1.0e9, "thickness": 0.001,
                 "restitution": 0.6},
                {"stiffness": 1.0e8, "hard_stiffness": 1.0e9, "thickness": 0.1,
                 "restitution": 0.5},  # never crushed in the tangent states
                {"stiffness": 1.0e8, "hard_stiffness": 1.0e9, "thickness": 0.0015,
                 "crush_ratio": 1.0, "restitution": 0.5, "calibration": "exact"})
    # a rubber bumper 10x softer than the hard contact, crushed by the impact at 0.5 m/s
    # (alone the rubber would penetrate 5.6 mm; it is crushed at 0.9 x 5 mm)
    impacts = {"bumper": Impact({"stiffness": 1.0e8, "hard_stiffness": 1.0e9,
                                 "thickness": 0.005}, "`bumper`")}

    @classmethod
    def reference_force(cls, params, context, v0):
        """Polycarpou et al. (2013): F = [k_r delta^1.5 + k_h <delta - delta_c>^1.5]
        (1 + chi delta' / v0), never pulling, delta_c = crush_ratio * thickness, with
        Muthukumar & DesRoches' chi = 3 (1 - e^2) / 4 (``calibration: exact``: the law's
        chi)."""
        k, hard = params.stiffness, params.hard_stiffness
        depth = params.crush_ratio * params.thickness
        e = params.restitution
        chi = 0.75 * (1.0 - e * e) if params.calibration == "published" else cls.chi(params)
        return lambda x, r: max((k * x**1.5 + hard * max(x - depth, 0.0)**1.5)
                                * (1.0 + chi * r / v0), 0.0)

    @classmethod
    def governing(cls, packed, effective_mass=None):
        """k_h (the rubber's Hertz stiffness, as the other Hertz laws name it), the hard
        stiffness ratio k_hard / k_h and the crush depth delta_c (the restitution e, which
        fixes chi, is the scene's own variable)."""
        k, _, _, _, hard, depth = packed
        return {"k_h": ("hertz_stiffness", k), "hard_ratio": ("dimensionless", hard / k),
                "delta_c": ("length", depth)}

    @classmethod
    def chi(cls, params) -> float:
        e = params.restitution
        if params.calibration == "exact":
            return hunt_crossley_chi(e)
        return CHI_FORMULAS["muthukumar"](e)

    @classmethod
    def published_source(cls, params) -> str:
        return "Muthukumar & DesRoches 2006"

    rebound = classmethod(hunt_crossley_rebound)

    @classmethod
    def pack(cls, params, context=None):
        inverse_mass = impact_inverse_mass(context)
        return (float(params.stiffness), 1.5, cls.chi(params), inverse_mass,
                float(params.hard_stiffness), float(params.crush_ratio * params.thickness))

    @staticmethod
    def force(params, committed, trial, deformation, rate):
        if deformation <= 0.0:
            trial[0] = 0.0
            trial[1] = 0.0
            return 0.0, 0.0, 0.0
        chi = params[2]
        onset = committed[1] == 0.0
        v0 = rate if onset else committed[0]
        trial[0] = v0
        trial[1] = 1.0
        root = math.sqrt(deformation)
        spring = params[0] * deformation * root
        dspring = 1.5 * params[0] * root
        stored = 0.4 * spring * deformation  # elastic energy int F d delta
        crushed = deformation - params[5]
        if crushed > 0.0:
            hard_root = math.sqrt(crushed)
            spring = spring + params[4] * crushed * hard_root
            dspring = dspring + 1.5 * params[4] * hard_root
            stored = stored + 0.4 * params[4] * crushed * crushed * hard_root
        if v0 <= 0.0 or chi == 0.0:  # no approach velocity (or no damping): the springs alone
            return spring, dspring, 0.0
        ve2 = 2.0 * stored * params[3]  # energy velocity squared, 2 E / m_eff
        if v0 * v0 >= ve2:  # an impact: v_ref = v0
            return impact_damping(spring, dspring, chi, rate, v0, onset)
        # v_ref = v_e = sqrt(2 E / m_eff), which grows with delta: d v_e / d delta = F_s / (m v_e)
        ve = math.sqrt(ve2)
        damping = chi * spring / ve
        f = spring + damping * rate
        if f <= 0.0:
            return 0.0, 0.0, 0.0
        dve = spring * params[3] / ve
        return f, dspring + chi * rate * (dspring - spring * dve / ve) / ve, damping
