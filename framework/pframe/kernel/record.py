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
    GROUND_ACCELERATION,
    STORY_DRIFT,
    STORY_FORCE,
    VELOCITY,
)

#: a step no run reaches (no history is due)
NEVER = 1 << 62


@inline
def source(m, st, q):
    """The (B, width) array holding quantity ``q``'s committed values: a row per member."""
    if q == DISPLACEMENT:
        return st.U
    if q == VELOCITY:
        return st.V
    if q == ACCELERATION:
        return st.A
    if q == STORY_DRIFT:
        return st.drift
    if q == STORY_FORCE:
        return st.story_force
    if q == CONTACT_FORCE:
        return st.contact_force
    return st.penetration  # contact penetration, clipped at 0 by value()


@inline
def value(m, st, q, values, b, k, i):
    """Committed value i of quantity ``q`` (its array ``values`` from :func:`source`)."""
    if q == GROUND_ACCELERATION:
        return m.ground[b, k]
    if q == CONTACT_PENETRATION:
        return max(values[b, i], 0.0)
    return values[b, i]


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
            values = source(m, st, q)  # chosen once per quantity, not once per value
            for i in range(history.shape[2]):
                history[b, row, i] = value(m, st, q, values, b, k, i)
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
            values = source(m, st, q)
            for i in range(peak.shape[1]):
                peak[b, i] = max(peak[b, i], abs(value(m, st, q, values, b, k, i)))
            gathered += peak.shape[1]
    st.counters[b, GATHERS] += gathered


@inline
def record_substep(m, st, rec, b, k):
    """Envelopes see the state committed at the end of every sub-step of step ``k`` (central
    difference's ``substeps``, event location, split steps), not only at the step end: a
    contact that opens and closes inside one step has its peak force recorded."""
    if rec.enveloped.sum() > 0:
        record_envelopes(m, st, rec, b, k)
