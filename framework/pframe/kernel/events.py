"""Event-aware stepping: contact onset and separation located inside a step.

While a contact is closed, a step is taken in sub-steps of 1 / ``event_parts`` of it. After a
converged sub-step in which a contact opened or closed, the sub-step is shortened so that it
ends just past the crossing of delta = 0, and the rest of the step follows as further
sub-steps. Three things make that exact for every law, whatever its force does at delta = 0:

- The search holds the crossing contact on the branch it had at the sub-step start
  (``w.scalars[HELD]``, see :func:`pframe.kernel.assembly.evaluate`): open, no force; closed,
  the law's force at delta = 0+ continued below 0. A dashpot's force ``c delta'`` jumps at
  delta = 0 (Kelvin at onset, and at separation with ``keep_tension``); on the real law the
  end penetration of a sub-step then jumps across the window the search aims at as the
  sub-step grows (the contact's force switches on or off inside it), and the search stalled
  on the wrong side. On the held branch it is continuous, and the crossing is where the
  trajectory of the branch the contact is on reaches delta = 0 -- the event itself. If the
  held trajectory does not cross in the sub-step at all, the sub-step is that trajectory (a
  root of the real law, which had two).
- The search is regula falsi with the Illinois modification (no end of the bracket sticks).
- After the event sub-step is committed, the laws are evaluated at its end on their new
  branches and the acceleration is taken from equilibrium there, as at t = 0: the force jump
  is a jump of the acceleration at the event, which the next sub-step starts from instead of
  averaging it over its length. The jump happens at a fixed penetration and does no work.
  A contact that starts touching (delta = 0 exactly, as two bodies placed against each
  other) with a closing velocity is at its onset: it is restarted closed before its first
  sub-step. (The modified kinetic energy of HHT and generalised-alpha, whose term
  (beta - 1/4) h^2 a M a / 2 depends on the acceleration, is re-taken with the new one.)
"""

from __future__ import annotations

from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import HELD, HELD_CLOSED, KINETIC

from .assembly import check_finite, copy2, evaluate_call, ground_between
from .energy import commit_call
from .newton import at_end_point, solve_step_call
from .record import record_substep

#: regula falsi iterations of one event location (Illinois: a few suffice)
LOCATE_ITERATIONS = 40


@inline
def crossed(d0, d1):
    """A contact whose penetration went from d0 to d1 opened or closed (d0 = 0 exactly is the
    touching start of a contact, not a crossing)."""
    return (d0 < 0.0 < d1) or (d0 > 0.0 >= d1)


@inline
def locate_event(m, s, st, w, b, k, h, pos, f_try, hs, ag_old, ag_new):
    """Shorten the converged sub-step from ``pos`` to ``f_try`` (fractions of step k) to end
    just past the first contact crossing in it. Returns (ok, f_try, hs, ag_old, ag_new,
    located) of the sub-step to commit; ``located``: it ends at an event."""
    first = -1
    earliest = 2.0
    for e in range(w.penetration.shape[0]):
        d0 = st.penetration[b, e]
        d1 = w.penetration[e]
        if crossed(d0, d1):
            fraction = d0 / (d0 - d1)
            if fraction < earliest:
                earliest = fraction
                first = e
    if first < 0:
        return True, f_try, hs, ag_old, ag_new, False
    d0 = st.penetration[b, first]
    w.scalars[HELD] = first
    w.scalars[HELD_CLOSED] = 1.0 if d0 > 0.0 else 0.0
    # the sub-step again with the contact on its branch: does it cross there?
    if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
        w.scalars[HELD] = -1.0
        return False, f_try, hs, ag_old, ag_new, False
    d1 = w.penetration[first]
    if not crossed(d0, d1):
        w.scalars[HELD] = -1.0
        return True, f_try, hs, ag_old, ag_new, False
    # end within (0, 2 target] of delta = 0, past it (onset: delta > 0; separation: <= 0)
    target = 1e-7 * abs(d1 - d0) * (1.0 if d1 > 0.0 else -1.0)
    lo_s, lo_g, hi_s, hi_g = 0.0, d0 - target, 1.0, d1 - target
    span = f_try - pos
    at = 1.0  # where the solution in w was computed (fraction of the span)
    found = False
    side = 0
    for _ in range(LOCATE_ITERATIONS):
        fraction = (lo_s * hi_g - hi_s * lo_g) / (hi_g - lo_g)
        width = hi_s - lo_s
        fraction = min(max(fraction, lo_s + 1e-9 * width), hi_s - 1e-9 * width)
        f_try = pos + fraction * span
        hs = (f_try - pos) * h
        ag_old, ag_new = ground_between(m, b, k, pos, f_try)
        if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            w.scalars[HELD] = -1.0
            return False, f_try, hs, ag_old, ag_new, False
        at = fraction
        d = w.penetration[first]
        if (target > 0.0 and 0.0 < d <= 2.0 * target) or (target < 0.0 and 2.0 * target <= d <= 0.0):
            found = True
            break
        g = d - target
        if g * lo_g > 0.0:  # still before the crossing
            lo_s, lo_g = fraction, g
            if side == -1:
                hi_g *= 0.5
            side = -1
        else:
            hi_s, hi_g = fraction, g
            if side == 1:
                lo_g *= 0.5
            side = 1
        if hi_s - lo_s <= 1e-15:
            break
    if not found and at != hi_s:
        # not in the window in LOCATE_ITERATIONS: end at the nearest point known past it
        f_try = pos + hi_s * span
        hs = (f_try - pos) * h
        ag_old, ag_new = ground_between(m, b, k, pos, f_try)
        if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            w.scalars[HELD] = -1.0
            return False, f_try, hs, ag_old, ag_new, False
    w.scalars[HELD] = -1.0
    return True, f_try, hs, ag_old, ag_new, True


@inline
def restart(m, s, st, w, b, k, hs, ag, held):
    """At an event (the end of a committed sub-step, or a contact touching with a closing
    velocity): every law evaluated at the committed state on its new branch (contact ``held``
    closed, if >= 0), and the acceleration from equilibrium there, as at t = 0."""
    U, V, A = st.U[b], st.V[b], st.A[b]
    mass = m.mass[b]
    u, v, a, R = w.u, w.v, w.a, w.R
    for i in range(mass.shape[0]):
        u[i] = U[i]
        v[i] = V[i]
        a[i] = 0.0
    at_end_point(s, w)
    w.scalars[HELD] = held
    w.scalars[HELD_CLOSED] = 1.0
    evaluate_call(m, st, w, b, ag, 0.0, 1.0, False)
    w.scalars[HELD] = -1.0
    if not check_finite(m, st, w, b, k):
        return False
    shadow = (s.beta - 0.25) * hs * hs
    kinetic = 0.0
    for i in range(mass.shape[0]):
        A[i] = R[i] / mass[i]
        kinetic += 0.5 * mass[i] * (V[i] * V[i] + shadow * A[i] * A[i])
    st.energy[b, KINETIC] = kinetic
    force, damping, tangent = st.story_force[b], st.story_damping_force[b], st.story_tangent[b]
    for e in range(force.shape[0]):
        force[e] = w.story_force[e]
        damping[e] = w.story_damping_force[e]
        tangent[e] = w.story_tangent[e]
    force = st.contact_force[b]
    for e in range(force.shape[0]):
        force[e] = w.contact_force[e]
    copy2(st.story_committed[b], st.story_trial[b])
    copy2(st.contact_committed[b], st.contact_trial[b])
    return True


@inline
def touching(m, st, b):
    """A contact whose committed penetration is exactly 0 (touching, as two bodies placed
    against each other at t = 0) with a closing velocity and no force yet: it is at its onset,
    which no crossing inside a sub-step will show. -1 if none."""
    dofs, V = m.contact_dofs, st.V[b]
    for e in range(dofs.shape[0]):
        if (st.penetration[b, e] == 0.0 and st.contact_force[b, e] == 0.0
                and V[dofs[e, 0]] - V[dofs[e, 1]] > 0.0):
            return e
    return -1


@compiled
def event_substeps(m, s, st, w, b, k, h, part, parts, rec):
    """Take part ``part`` of ``parts`` of step k in sub-steps that end at contact events."""
    pos = part / parts
    stop = (part + 1) / parts
    while pos < stop:
        # while a contact is closed, sub-steps of 1 / event_parts of the step (a sliver left
        # before the step end joins the last one)
        f_try = stop
        for e in range(st.penetration.shape[1]):
            if st.penetration[b, e] > 0.0:
                piece = 1.0 / (parts * m.event_parts[b])
                if pos + 1.01 * piece < stop:
                    f_try = pos + piece
                break
        hs = (f_try - pos) * h
        ag_old, ag_new = ground_between(m, b, k, pos, f_try)
        onset = touching(m, st, b)
        if onset >= 0 and not restart(m, s, st, w, b, k, hs, ag_old, onset):
            return False
        if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False
        ok, f_try, hs, ag_old, ag_new, located = locate_event(m, s, st, w, b, k, h, pos, f_try,
                                                              hs, ag_old, ag_new)
        if not ok or not commit_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False
        if located and not restart(m, s, st, w, b, k, hs, ag_new, -1):
            return False
        record_substep(m, st, rec, b, k)
        pos = f_try
    return True
