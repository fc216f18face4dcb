"""One step of the implicit generalised-alpha family (Newmark, HHT, Chung-Hulbert).

The coefficient sets (gamma, beta, alpha_m, alpha_f) come from :mod:`pframe.integrators`;
:func:`pframe.kernel.newton.solve_step` iterates a (sub-)step to equilibrium. A step that has
no Newton root (a law with a jump or an infinite slope at contact onset) is retried from its
start as 2, 4, ... 2^max_split sub-steps with the ground motion interpolated; recording stays
on the step grid. With event-aware stepping each part is further cut at contact events.
"""

from __future__ import annotations

from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import NOT_FINITE, NOT_STABLE, SPLIT_STEPS, STATUS_CODE

from .assembly import ground_between
from .energy import commit_call
from .events import event_substeps
from .newton import solve_step_call
from .record import record_substep


@inline
def copy1(saved, live, to_saved):
    """Copy a 1-D array one way or the other (loops: no overlap check, no temporary)."""
    for i in range(live.shape[0]):
        if to_saved:
            saved[i] = live[i]
        else:
            live[i] = saved[i]


@inline
def copy2(saved, live, to_saved):
    for i in range(live.shape[0]):
        copy1(saved[i], live[i], to_saved)


@inline
def exchange(st, sv, b, to_saved):
    """Copy member b's committed arrays into ``sv`` (``to_saved``) or back from it."""
    copy1(sv.U, st.U[b], to_saved)
    copy1(sv.V, st.V[b], to_saved)
    copy1(sv.A, st.A[b], to_saved)
    copy1(sv.drift, st.drift[b], to_saved)
    copy1(sv.story_force, st.story_force[b], to_saved)
    copy1(sv.story_damping_force, st.story_damping_force[b], to_saved)
    copy1(sv.story_tangent, st.story_tangent[b], to_saved)
    copy2(sv.story_committed, st.story_committed[b], to_saved)
    copy1(sv.contact_force, st.contact_force[b], to_saved)
    copy1(sv.penetration, st.penetration[b], to_saved)
    copy2(sv.contact_committed, st.contact_committed[b], to_saved)
    copy1(sv.impacts, st.impacts[b], to_saved)
    copy1(sv.energy, st.energy[b], to_saved)


@inline
def save(st, sv, b):
    exchange(st, sv, b, True)


@inline
def restore(st, sv, b):
    exchange(st, sv, b, False)


@inline
def split_step(m, s, st, w, sv, b, k, h, split, rec):
    """Take step k (of length h) as 2^split parts, and in twice as many from its start (saved
    in ``sv``) while one fails, up to 2^max_split; False (after recording why in st.status,
    and restoring the step's start) if it failed even then. With events, each part is further
    cut at contact events."""
    while True:
        parts = 1 << split
        ok = True
        for part in range(parts):
            if s.events:
                ok = event_substeps(m, s, st, w, b, k, h, part, parts, rec)
            else:
                pos = part / parts
                stop = (part + 1) / parts
                hs = (stop - pos) * h
                ag_old, ag_new = ground_between(m, b, k, pos, stop)
                ok = (solve_step_call(m, s, st, w, b, k, hs, ag_old, ag_new)
                      and commit_call(m, s, st, w, b, k, hs, ag_old, ag_new))
                if ok:
                    record_substep(m, st, rec, b, k)
            if not ok:
                break
        if ok:
            return True
        restore(st, sv, b)
        code = st.status[b, STATUS_CODE]
        if code == NOT_FINITE or code == NOT_STABLE or split == s.max_split:
            return False
        if split == 0:
            st.counters[b, SPLIT_STEPS] += 1
        st.status[b, :] = 0
        split += 1


@compiled
def step_in_parts(m, s, st, w, sv, b, k, h, rec):
    """Step k (of length h) in sub-steps, after the whole step failed in the time loop or,
    with event location, from the start; False (after recording why in st.status) if it
    failed even in 2^max_split sub-steps. The whole step is the common case, and the time
    loop (:mod:`pframe.kernel.loop`) takes it itself, without a call."""
    split = 0
    if not s.events:
        code = st.status[b, STATUS_CODE]
        if s.linear or code == NOT_FINITE or code == NOT_STABLE:
            return False
        st.counters[b, SPLIT_STEPS] += 1
        st.status[b, :] = 0
        split = 1
    # nothing was committed yet: this is the step's start (with events, several sub-steps
    # may be committed before a failure)
    save(st, sv, b)
    return split_step(m, s, st, w, sv, b, k, h, split, rec)
