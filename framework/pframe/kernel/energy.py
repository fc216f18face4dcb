"""Committing a step: energy increments, impact counts, the state copy, and a runaway check.

The work of each force over the step is counted by the trapezoidal rule. With Newmark's
relations and equilibrium at t(n+1 - alpha) (forces weighted (1 - alpha_f) at the step end and
alpha_f at its start, inertia likewise with alpha_m), the step's works satisfy exactly

    W_input = dE_kinetic + W_damping + W_storeys + W_contacts + D_algorithmic,

with the kinetic energy (1/2) v M v + (beta - 1/4) (h^2 / 2) a M a (beta = 1/4: the plain
kinetic energy; central difference: beta = 0) and the integrator's own dissipation

    D_algorithmic = (1/4 - gamma/2) h^2 [a M a / 2] - (gamma - 1/2) h v_mid M [a]
                    + (1/2 - alpha_m) du M [a] + (1/2 - alpha_f) du . [G],

where [x] is the increment of x over the step, v_mid the mean velocity, du the displacement
increment and G = C v + F(u) + M a_g the non-inertial forces. D_algorithmic vanishes for
average acceleration (gamma = 1/2, alpha = 0) and is the numerical damping of HHT,
generalised alpha and Newmark with gamma > 1/2. It is counted on its own, so the balance
closes to round-off for every integrator of the family: its error measures the run's
arithmetic and the integrator's consistency (a pair that creates energy shows there), while
D_algorithmic says how much the integrator damped (``pframe.verdict`` judges both).
"""

from __future__ import annotations

from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import (
    ALGORITHMIC,
    ALPHA_WORK,
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
        # the pieces of D_algorithmic (module docstring): du . [G], du M [a], v_mid M [a],
        # [a M a / 2]
        du_dG = 0.0
        du_Mda = 0.0
        v_Mda = 0.0
        d_aMa = 0.0
        for i in range(n):
            du = u[i] - U[i]
            da = a[i] - A[i]
            work_in -= 0.5 * (ag_old + ag_new) * mass[i] * du
            work_damp += 0.5 * damping[i] * (V[i] + v[i]) * du
            du_dG += (damping[i] * (v[i] - V[i]) + mass[i] * (ag_new - ag_old)) * du
            du_Mda += mass[i] * da * du
            v_Mda += 0.5 * (V[i] + v[i]) * mass[i] * da
            d_aMa += 0.5 * mass[i] * (a[i] * a[i] - A[i] * A[i])
        work_story = 0.0
        for e in range(ns):
            dd = drift_t[e] - drift_c[e]
            work_story += 0.5 * (force_c[e] + force_t[e]) * dd
            work_damp += 0.5 * (damping_c[e] + damping_t[e]) * dd
            du_dG += (force_t[e] - force_c[e] + damping_t[e] - damping_c[e]) * dd
        energy[INPUT] += work_in
        energy[DAMPING] += work_damp
        energy[STOREYS] += work_story
        work_contact = 0.0
        if nc:
            for e in range(nc):
                dp = pen_t[e] - pen_c[e]
                work_contact += 0.5 * (cforce_c[e] + cforce_t[e]) * dp
                du_dG += (cforce_t[e] - cforce_c[e]) * dp
                if pen_c[e] <= 0.0 and pen_t[e] > 0.0:
                    impacts[e] += 1
            energy[CONTACTS] += work_contact
        inertial = ((0.25 - 0.5 * s.gamma) * h * h * d_aMa - (s.gamma - 0.5) * h * v_Mda
                    + (0.5 - s.alpha_m) * du_Mda)
        if s.alpha:
            # equilibrium holds at the alpha point, with the forces evaluated there (not the
            # weighted end forces: the two differ where a law is nonlinear)
            trapezoid = work_damp + work_story + work_contact - work_in
            energy[ALGORITHMIC] += inertial + w.scalars[ALPHA_WORK] - trapezoid
        else:
            energy[ALGORITHMIC] += inertial + 0.5 * du_dG

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
