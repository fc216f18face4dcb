"""The Hunt-Crossley family: F = k delta^n (1 + chi delta_dot / v_ref), compression only.

v_ref is the approach velocity v0 at contact onset, held for the whole contact, or the energy
velocity of the contact if that is larger (see below). The improved Kelvin law is n = 1,
Hertzdamp n = 3/2. Written as ``xi delta^n delta_dot`` the damping coefficient is
xi = chi k / v_ref, and it vanishes with delta, so the force starts from zero at onset.

v0 is taken at the end of the step in which contact begins (the trial rate), so within that
step F = k delta^n (1 + chi) and the tangent holds no rate term. When v0 is not positive (a
contact that closes by drift, not impact) there is no velocity to scale the damping by, and
the law acts as its spring alone.

Grazing and persistent contact. xi = chi k / v0 grows without bound as v0 -> 0+: a contact
that begins with a tiny approach velocity (grazing) and is then pushed by the buildings, or
one that stays closed, would be as good as rigid. The reference velocity is therefore never
less than the *energy velocity* of the contact,

    v_e = sqrt(2 k delta^(n+1) / ((n + 1) m_eff)),

the approach velocity whose kinetic energy (1/2 m_eff v_e^2) equals the elastic energy the
contact holds now: v_ref = max(v0, v_e). In a free two-body impact the stored energy never
exceeds the kinetic energy at onset, so v_e <= v0 throughout and the law is the published one,
bit for bit. Where v_e wins the law is the speed-independent viscoelastic contact
k delta^n + (chi k / a) delta^((n-1)/2) delta_dot (a = sqrt(2 k / ((n + 1) m_eff))): for n = 1
a Kelvin dashpot of damping ratio chi / 2, for n = 3/2 Jankowski's form. The floor is
dimensionless (no parameter, no scene-dependent scale), so it keeps similitude, and the force
stays bounded as v0 -> 0+. ``inverse_effective_mass`` = 0 turns the floor off.
"""

from __future__ import annotations

import math

from pframe.laws.facts import V0, contact_states
from pframe.laws.restitution import hunt_crossley_restitution

STATE_NAMES = ("onset_velocity", "in_contact")
PARAM_NAMES = ("stiffness", "exponent", "chi", "inverse_effective_mass")


def hunt_crossley_tangent_states(cls, packed):
    """The contact tests' states: the onset step (no contact committed), then a running
    contact that began at V0 (a law's ``tangent_states``)."""
    return contact_states((0.0, 0.0), (V0, 1.0))


def hunt_crossley_rebound(cls, params) -> float:
    """The restitution of a two-body impact with the law's damping ``cls.chi(params)``, in
    closed form (docs/restitution.md; a law's ``rebound``)."""
    return hunt_crossley_restitution(cls.chi(params))


def impact_inverse_mass(context) -> float:
    """1 / m_eff of the contact's two sides, which a law packs to find its impact's onset
    velocity (0 without a context: a law packed outside a scene)."""
    return 0.0 if context is None else 1.0 / context.effective_mass


def impact_damping(spring, dspring, chi, rate, v0, onset):
    """(force, d/d delta, d/d delta') of spring (1 + chi delta' / v0) in an impact
    (v_ref = v0), never pulling; at onset delta' / v0 = 1 and no rate term (the law and
    ``bumper`` share it)."""
    if onset:
        return spring * (1.0 + chi), dspring * (1.0 + chi), 0.0
    factor = 1.0 + chi * rate / v0
    if factor <= 0.0:
        return 0.0, 0.0, 0.0
    return spring * factor, dspring * factor, spring * chi / v0


def hunt_crossley_force(params, committed, trial, deformation, rate):
    """params = (k, n, chi, 1 / m_eff); state = (v0, in_contact)."""
    if deformation <= 0.0:
        trial[0] = 0.0
        trial[1] = 0.0
        return 0.0, 0.0, 0.0
    k = params[0]
    n = params[1]
    chi = params[2]
    onset = committed[1] == 0.0
    v0 = rate if onset else committed[0]
    trial[0] = v0
    trial[1] = 1.0
    power = deformation if n == 1.0 else deformation**n
    spring = k * power
    dspring = n * spring / deformation
    if v0 <= 0.0 or chi == 0.0:  # no approach velocity (or no damping): the spring alone
        return spring, dspring, 0.0
    # energy velocity squared: 2 k delta^(n+1) / ((n + 1) m_eff)
    ve2 = 2.0 * spring * deformation * params[3] / (n + 1.0)
    if v0 * v0 >= ve2:  # an impact: v_ref = v0
        return impact_damping(spring, dspring, chi, rate, v0, onset)
    # v_ref = v_e ~ delta^((n+1)/2): damping force (chi spring / v_e) rate ~ delta^((n-1)/2)
    damping = chi * spring / math.sqrt(ve2)
    f = spring + damping * rate
    if f <= 0.0:
        return 0.0, 0.0, 0.0
    return f, dspring + 0.5 * (n - 1.0) * damping * rate / deformation, damping
