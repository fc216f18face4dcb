"""Improved (modified) Kelvin contact, Ye, Li & Zhu (2009), as used by Wu et al. (2021).

F = k delta + xi delta delta_dot, xi = 3 k (1 - e) / (2 e v0)  (paper eqs. 1-3), i.e. the
Hunt-Crossley form with n = 1 and chi = 3 (1 - e) / (2 e). v0 is the approach velocity at
contact onset. The force never jumps at onset and does not pull in rebound.
"""

from __future__ import annotations

from typing import Literal

from pframe.laws.contact._hunt_crossley import STATE_NAMES, hunt_crossley_force
from pframe.laws.params import ContactStiffness, Restitution
from pframe.laws.registry import Law, contact_law


def ye_chi(e: float) -> float:
    """chi = 3 (1 - e) / (2 e), Ye, Li & Zhu (2009)."""
    return 1.5 * (1.0 - e) / e


@contact_law("improved_kelvin")
class ImprovedKelvin(Law):
    class Params(ContactStiffness):
        law: Literal["improved_kelvin"]
        restitution: Restitution

    param_names = ("stiffness", "exponent", "chi")
    state_names = STATE_NAMES
    force = staticmethod(hunt_crossley_force)

    @classmethod
    def pack(cls, params, context=None):
        return (params.resolve_stiffness(context), 1.0, ye_chi(params.restitution))
