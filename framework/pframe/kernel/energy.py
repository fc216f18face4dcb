"""Committing a step: energy increments, impact counts, the state copy, and a runaway check.

The work of each force over the step is counted by the trapezoidal rule; with Newmark's
relations the inertia work then equals the increment of the kinetic energy

    (1/2) v M v + (beta - 1/4) (h^2 / 2) a M a

exactly (beta = 1/4: the plain kinetic energy; central difference: beta = 0), so the balance
W_input = dE_kinetic + W_damping + W_storeys + W_contacts closes to round-off for every
integrator of the family, and its error measures the run's arithmetic, not its step.
"""

from __future__ import annotations

from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import (
    CONTACTS,
    DAMPING,
    INPUT,
    INPUT_ABS,
    KINETIC,
    KINETIC_0,
    MASS_MIN,
    NODE,
    NOT_STABLE,
    START,
    STOREYS,
)

from .assembly import copy2, fail


def commit(m, s, st, w, b, k, h, ag_old, ag_new):
    """Accept the step from t_k - h to t_k whose end state is in ``w``; False (after recording
    why) if the kinetic energy ran away from what the ground motion put in."""
    mass = m.mass[b]
    n = mass.shape[0]
    U, V, A = st.U[b], st.V[b], st.A[b]
    u, v, a = w.u, w.v, w.a
    drift_c, force_c, damping_c, tangent_c = (st.drift[b], st.story_force[b],
                                              st.story_damping_force[b], st.story_tangent[b])
    drift_t, force_t, damping_t, tangent_t = (w.drift, w.story_force, w.story_damping_force,
                                              w.story_tangent)
    cforce_c, pen_c, impacts = st.contact_force[b], st.penetration[b], st.impacts[b]
    cforce_t, pen_t = w.contact_force, w.penetration
    ns = drift_t.shape[0]
    nc = pen_t.shape[0]
    energy = st.energy[b]
    work_in = 0.0
    if k > 0:
        work_damp = 0.0
        damping = m.mass_damping[b]
        for i in range(n):
            du = u[i] - U[i]
            work_in -= 0.5 * (ag_old + ag_new) * mass[i] * du
            work_damp += 0.5 * damping[i] * (V[i] + v[i]) * du
        work_story = 0.0
        for e in range(ns):
            dd = drift_t[e] - drift_c[e]
            work_story += 0.5 * (force_c[e] + force_t[e]) * dd
            work_damp += 0.5 * (damping_c[e] + damping_t[e]) * dd
        energy[INPUT] += work_in
        energy[DAMPING] += work_damp
        energy[STOREYS] += work_story
        if nc:
            work_contact = 0.0
            for e in range(nc):
                work_contact += 0.5 * (cforce_c[e] + cforce_t[e]) * (pen_t[e] - pen_c[e])
                if pen_c[e] <= 0.0 and pen_t[e] > 0.0:
                    impacts[e] += 1
            energy[CONTACTS] += work_contact

    shadow = (s.beta - 0.25) * h * h
    kinetic = 0.0
    raw = 0.0
    for i in range(n):
        U[i] = u[i]
        V[i] = v[i]
        A[i] = a[i]
        raw += 0.5 * mass[i] * v[i] * v[i]
        kinetic += 0.5 * mass[i] * (v[i] * v[i] + shadow * a[i] * a[i])
    energy[KINETIC] = kinetic
    if k == 0:
        energy[KINETIC_0] = kinetic
    for e in range(ns):
        drift_c[e] = drift_t[e]
        force_c[e] = force_t[e]
        damping_c[e] = damping_t[e]
        tangent_c[e] = tangent_t[e]
    for e in range(nc):
        cforce_c[e] = cforce_t[e]
        pen_c[e] = pen_t[e]
    copy2(st.story_committed[b], st.story_trial[b])
    copy2(st.contact_committed[b], st.contact_trial[b])

    # Divergence: the kinetic energy cannot exceed what came in (initial energy plus the input
    # work, counted in absolute value) but by the integrator's own small excess; ten times
    # that means the numbers are running away (a test on the balance would not do: Newmark
    # with gamma = 1/2 conserves its modified energy even when unstable).
    if k == 0:
        start = raw
        for e in range(ns):
            start += 0.5 * force_t[e] * drift_t[e]
        for e in range(nc):
            start += 0.5 * cforce_t[e] * max(pen_t[e], 0.0)
        energy[START] = abs(start)
        return True
    energy[INPUT_ABS] += abs(work_in)
    budget = energy[INPUT_ABS] + energy[START] + (h * (abs(ag_old) + abs(ag_new))) ** 2 * w.scalars[MASS_MIN]
    if raw <= 10.0 * budget:
        return True
    worst = 0
    for i in range(n):
        if abs(U[i]) > abs(U[worst]):
            worst = i
    return fail(st, b, NOT_STABLE, k, NODE, worst)


#: commit as a call: for sub-steps, explicit steps and the state at t = 0
commit_call = compiled(commit)
#: inlined where the common case runs (no call)
commit = inline(commit)
