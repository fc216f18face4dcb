"""Event-aware stepping: contact onset and separation located inside a step.

While a contact is closed, a step is taken in sub-steps of 1 / ``event_parts`` of it. After a
converged sub-step, a contact that opened or closed inside it shortens it (regula falsi on the
fraction of the sub-step) so that it ends just past the crossing, where a law's onset velocity
is taken; the rest of the step follows as further sub-steps.
"""

from __future__ import annotations

from pframe.kernel.cache import compiled, inline

from .assembly import ground_between
from .energy import commit_call
from .newton import solve_step_call


@inline
def locate_event(m, s, st, w, b, k, h, pos, f_try, hs, ag_old, ag_new):
    """Shorten the converged sub-step from ``pos`` to ``f_try`` (fractions of step k) to end
    just past the first contact crossing in it. Returns (ok, f_try, hs, ag_old, ag_new) of the
    sub-step to commit."""
    first = -1
    earliest = 2.0
    for e in range(w.penetration.shape[0]):
        d0 = st.penetration[b, e]
        d1 = w.penetration[e]
        if d0 != 0.0 and ((d0 < 0.0 < d1) or (d0 > 0.0 >= d1)):
            fraction = d0 / (d0 - d1)
            if fraction < earliest:
                earliest = fraction
                first = e
    if first < 0:
        return True, f_try, hs, ag_old, ag_new
    d0 = st.penetration[b, first]
    d1 = w.penetration[first]
    target = 1e-7 * abs(d1 - d0) * (1.0 if d1 > 0.0 else -1.0)
    lo_s, lo_d, hi_s, hi_d = 0.0, d0, 1.0, d1
    span = f_try - pos
    for _ in range(8):
        fraction = lo_s + (target - lo_d) * (hi_s - lo_s) / (hi_d - lo_d)
        fraction = min(max(fraction, lo_s + 1e-6 * (hi_s - lo_s)), hi_s - 1e-6 * (hi_s - lo_s))
        f_try = pos + fraction * span
        hs = (f_try - pos) * h
        ag_old, ag_new = ground_between(m, b, k, pos, f_try)
        if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False, f_try, hs, ag_old, ag_new
        d = w.penetration[first]
        if (target > 0.0 and 0.0 < d <= 2.0 * target) or (target < 0.0 and 2.0 * target <= d <= 0.0):
            break
        if (d - target) * (lo_d - target) > 0.0:
            lo_s, lo_d = fraction, d
        else:
            hi_s, hi_d = fraction, d
    return True, f_try, hs, ag_old, ag_new


@compiled
def event_substeps(m, s, st, w, b, k, h, part, parts):
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
        if not solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False
        ok, f_try, hs, ag_old, ag_new = locate_event(m, s, st, w, b, k, h, pos, f_try, hs,
                                                     ag_old, ag_new)
        if not ok or not commit_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False
        pos = f_try
    return True
