"""Residual and tangent of the scene at an evaluation point, over its element groups.

The residual is R = P - M (a_g + a) - C_m v - sum of element forces, at the point held in
``w.ue, w.ve, w.ae`` (the step end for Newmark, the alpha point for HHT and generalised-alpha).
Storeys and contacts are visited in the plan's order (grouped by law); each calls its law
through the law-id switch. A scene without contacts has empty contact arrays, so the contact
loop does not run.
"""

from __future__ import annotations

import numpy as np

from pframe.kernel.banded import ldl_factor
from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import (
    CONTACT,
    EVALUATIONS,
    FACTORISATIONS,
    HELD,
    HELD_CLOSED,
    NODE,
    NOT_DEFINITE,
    NOT_FINITE,
    STATUS_CODE,
    STATUS_INDEX,
    STATUS_KIND,
    STATUS_STEP,
    STORY,
)
from pframe.kernel.views import row

from .dispatch import contact_force, material_force

#: where a contact held closed is evaluated once its penetration is below it: the smallest
#: penetration a law sees as contact (any law's spring term vanishes there)
HELD_DEPTH = 1e-300


@inline
def fail(st, b, code, k, kind, index):
    """Record why member ``b`` stopped in step ``k``; returns False (not ok)."""
    st.status[b, STATUS_CODE] = code
    st.status[b, STATUS_STEP] = k
    st.status[b, STATUS_KIND] = kind
    st.status[b, STATUS_INDEX] = index
    return False


@inline
def copy2(dst, src):
    """dst[...] = src for 2-D arrays, without numba's overlap check and temporary."""
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


def evaluate(m, st, w, b, age, c1, wf, tangent):
    """Element forces and the residual at the evaluation point, ground acceleration ``age``.

    With ``tangent``, each element's effective tangent (k_t + c1 (k_r + beta k_d)) wf is
    compared with the one in the current factorisation; returns True when one changed (the
    factorisation is then stale).
    """
    # Arrays are taken out of the named tuples once, before the loops: each access makes a
    # reference, and reference counting in a loop would cost more than the physics.
    mass, damping = m.mass[b], m.mass_damping[b]
    ue, ve, ae, R = w.ue, w.ve, w.ae, w.R
    for i in range(mass.shape[0]):
        R[i] = -mass[i] * (age + ae[i]) - damping[i] * ve[i]
    st.counters[b, EVALUATIONS] += 1
    stale = False

    dofs, order, laws, modes = m.story_dofs, m.story_order, m.story_law, m.story_damping
    params, committed, trial = m.story_params[b], st.story_committed[b], st.story_trial[b]
    k0, beta, tangent_c = m.story_k0[b], m.story_beta[b], st.story_tangent[b]
    calls = st.material_calls[b]
    drift, force, damping_force, tangent_t, kks = (w.drift, w.story_force,
                                                  w.story_damping_force, w.story_tangent,
                                                  w.story_kk)
    for j in range(order.shape[0]):
        e = order[j]
        lo = dofs[e, 0]
        up = dofs[e, 1]
        d = ue[up]
        r = ve[up]
        if lo >= 0:
            d -= ue[lo]
            r -= ve[lo]
        law = laws[e]
        f, kt, kr = material_force(law, row(params, e), row(committed, e), row(trial, e), d, r)
        calls[law] += 1
        mode = modes[e]
        if mode == 0:
            kd = k0[e]
        elif mode == 1:
            kd = kt
        else:
            kd = tangent_c[e]
        fd = beta[e] * kd * r
        drift[e] = d
        force[e] = f
        damping_force[e] = fd
        tangent_t[e] = kt
        R[up] -= f + fd
        if lo >= 0:
            R[lo] += f + fd
        if tangent:
            kk = (kt + c1 * (kr + beta[e] * kd)) * wf
            if kk != kks[e]:
                kks[e] = kk
                stale = True

    dofs, order, laws = m.contact_dofs, m.contact_order, m.contact_law
    params, committed, trial = m.contact_params[b], st.contact_committed[b], st.contact_trial[b]
    gap, calls = m.gap[b], st.contact_calls[b]
    force, penetration, kks = w.contact_force, w.penetration, w.contact_kk
    held = int(w.scalars[HELD])
    for j in range(order.shape[0]):
        e = order[j]
        left = dofs[e, 0]
        right = dofs[e, 1]
        d = ue[left] - ue[right] - gap[e]
        r = ve[left] - ve[right]
        law = laws[e]
        at = d
        if e == held:
            # Located events (kernel/events.py) hold the contact on one branch, so that its
            # penetration is a continuous function of the sub-step length: held open, no
            # force on either side of delta = 0; held closed, the law's force at delta = 0+
            # continued to delta < 0 (the jump of a dashpot, c delta', at delta = 0 stays off
            # the search).
            at = max(d, HELD_DEPTH) if w.scalars[HELD_CLOSED] != 0.0 else min(d, 0.0)
        f, kd, kr = contact_force(law, row(params, e), row(committed, e), row(trial, e), at, r)
        if at > d:
            kd = 0.0
        calls[law] += 1
        force[e] = f
        penetration[e] = d
        R[left] -= f
        R[right] += f
        if tangent:
            kk = (kd + c1 * kr) * wf
            if kk != kks[e]:
                kks[e] = kk
                stale = True
    return stale



@inline
def check_finite(m, st, w, b, k):
    """False after recording the element whose force is not finite, if any."""
    R = w.R
    total = 0.0
    for i in range(R.shape[0]):
        total += R[i]
    if np.isfinite(total):
        return True
    kind = NODE
    where = 0
    force, damping_force = w.story_force, w.story_damping_force
    for e in range(force.shape[0]):
        if not np.isfinite(force[e] + damping_force[e]):
            kind = STORY
            where = e
            break
    force = w.contact_force
    for e in range(force.shape[0]):
        if not np.isfinite(force[e]):
            kind = CONTACT
            where = e
            break
    return fail(st, b, NOT_FINITE, k, kind, where)


@compiled
def factor(m, s, st, w, b, k, c0, c1, wm, wf):
    """Assemble the effective stiffness band from the element tangents in ``w.story_kk`` and
    ``w.contact_kk`` and factor it; False (after recording why) if it is not definite."""
    band, bw = w.band, s.bandwidth
    mass, damping = m.mass[b], m.mass_damping[b]
    for i in range(mass.shape[0]):
        for d in range(1, bw + 1):
            band[i, d] = 0.0
        band[i, 0] = mass[i] * c0 * wm + damping[i] * c1 * wf
    dofs, kks = m.story_dofs, w.story_kk
    for e in range(dofs.shape[0]):
        kk = kks[e]
        lo = dofs[e, 0]
        up = dofs[e, 1]
        band[up, 0] += kk
        if lo >= 0:
            band[lo, 0] += kk
            band[max(lo, up), abs(lo - up)] -= kk
    dofs, kks = m.contact_dofs, w.contact_kk
    for e in range(dofs.shape[0]):
        kk = kks[e]
        left = dofs[e, 0]
        right = dofs[e, 1]
        band[left, 0] += kk
        band[right, 0] += kk
        band[max(left, right), abs(left - right)] -= kk
    st.counters[b, FACTORISATIONS] += 1
    if ldl_factor(band, bw):
        return True
    return fail(st, b, NOT_DEFINITE, k, NODE, 0)


@inline
def ground_between(m, b, k, start, stop):
    """Ground accelerations at fractions ``start`` and ``stop`` of step k (linear between the
    samples k - 1 and k)."""
    ag = m.ground[b]
    slope = ag[k] - ag[k - 1]
    return ag[k - 1] + slope * start, ag[k - 1] + slope * stop


#: evaluate as a call: for the state at t = 0, the step end of HHT and generalised-alpha,
#: and central difference
evaluate_call = compiled(evaluate)
#: inlined where the common case runs (no call)
evaluate = inline(evaluate)
