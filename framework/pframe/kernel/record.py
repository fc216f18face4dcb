"""Recorders: gathering committed state into history rows and envelopes.

Only what a scene's recorders ask for is gathered: a history of quantity q is written at the
steps that are multiples of its ``every`` (the loop asks :func:`next_due` for the next such
step once per record, not every quantity every step), an envelope keeps the running peak of
the absolute value. Recorders see committed state only.
"""

from __future__ import annotations

from pframe.kernel.cache import inline
from pframe.kernel.state import (
    ACCELERATION,
    CONTACT_FORCE,
    CONTACT_PENETRATION,
    DISPLACEMENT,
    GATHERS,
    STORY_DRIFT,
    STORY_FORCE,
    VELOCITY,
)

#: a step no run reaches (no history is due)
NEVER = 1 << 62


@inline
def value(m, st, q, b, k, i):
    """Committed value i of quantity ``q`` of member ``b`` at step ``k``."""
    if q == DISPLACEMENT:
        return st.U[b, i]
    if q == VELOCITY:
        return st.V[b, i]
    if q == ACCELERATION:
        return st.A[b, i]
    if q == STORY_DRIFT:
        return st.drift[b, i]
    if q == STORY_FORCE:
        return st.story_force[b, i]
    if q == CONTACT_FORCE:
        return st.contact_force[b, i]
    if q == CONTACT_PENETRATION:
        return max(st.penetration[b, i], 0.0)
    return m.ground[b, k]  # ground acceleration: one value


@inline
def next_due(rec, k):
    """The first step at or after ``k`` at which a history is due (NEVER if none is)."""
    due = NEVER
    every = rec.every
    for q in range(every.shape[0]):
        if every[q] > 0:
            step = (k + every[q] - 1) // every[q] * every[q]
            if step < due:
                due = step
    return due


@inline
def record_histories(m, st, rec, b, k):
    """Gather the histories due at step ``k``; returns the next step one is due."""
    every, first = rec.every, rec.first_row
    gathered = 0
    for q in range(every.shape[0]):
        if every[q] > 0 and k % every[q] == 0:
            history = rec.history[q]
            row = k // every[q] - first[q]
            for i in range(history.shape[2]):
                history[b, row, i] = value(m, st, q, b, k, i)
            gathered += history.shape[2]
    st.counters[b, GATHERS] += gathered
    return next_due(rec, k + 1)


@inline
def record_envelopes(m, st, rec, b, k):
    """Update the running peaks of the enveloped quantities with step ``k``."""
    gathered = 0
    for q in range(rec.enveloped.shape[0]):
        if rec.enveloped[q]:
            peak = rec.envelope[q]
            for i in range(peak.shape[1]):
                peak[b, i] = max(peak[b, i], abs(value(m, st, q, b, k, i)))
            gathered += peak.shape[1]
    st.counters[b, GATHERS] += gathered
