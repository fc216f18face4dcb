"""The Hunt-Crossley family: F = k delta^n (1 + chi delta_dot / v0), compression only.

v0 is the approach velocity at contact onset, held for the whole contact. The improved Kelvin
law is n = 1, Hertzdamp n = 3/2. Written as ``xi delta^n delta_dot`` the damping coefficient is
xi = chi k / v0, and it vanishes with delta, so the force starts from zero at onset.

v0 is taken at the end of the step in which contact begins (the trial rate), so within that
step F = k delta^n (1 + chi) and the tangent holds no rate term. When the approach velocity is
not positive (a contact that closes by drift, not impact) there is no velocity to scale the
damping by, and the law acts as its spring alone.
"""

from __future__ import annotations

STATE_NAMES = ("onset_velocity", "in_contact")


def hunt_crossley_force(params, committed, trial, deformation, rate):
    """params = (k, n, chi); state = (v0, in_contact)."""
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
    if v0 <= 0.0 or chi == 0.0:
        return spring, dspring, 0.0
    if onset:
        return spring * (1.0 + chi), dspring * (1.0 + chi), 0.0
    factor = 1.0 + chi * rate / v0
    if factor <= 0.0:
        return 0.0, 0.0, 0.0
    return spring * factor, dspring * factor, spring * chi / v0
