"""Newton iterations of one implicit (sub-)step of the generalised-alpha family.

From the committed state (U, V, A) at the step start, find u at the step end such that

    M a(n+1-alpha_m) + C v(n+1-alpha_f) + F(u(n+1-alpha_f)) = -M a_g(t(n+1-alpha_f)),

with Newmark's relations a = c0 (u - U) - c2 V - c3 A and v = V + c4 A + c5 a. A linear scene
takes one solve with the factor made once before its first step. A nonlinear scene starts from
the constant-acceleration predictor and refactors the effective stiffness only when an element
tangent or the step length changed.
"""

from __future__ import annotations

import numpy as np

from pframe.kernel.banded import ldl_solve
from pframe.kernel.cache import compiled, inline
from pframe.kernel.state import (
    ALPHA_WORK,
    H_FACTORED,
    MASS_MIN,
    NODE,
    NOT_CONVERGED,
    SOLVES,
    STALE,
)

from .assembly import check_finite, evaluate, evaluate_call, factor, fail


@inline
def coefficients(s, h):
    """Newmark's c0 ... c5 for a step of length h."""
    c0 = 1.0 / (s.beta * h * h)
    c1 = s.gamma / (s.beta * h)
    c2 = 1.0 / (s.beta * h)
    c3 = 0.5 / s.beta - 1.0
    c4 = h * (1.0 - s.gamma)
    c5 = h * s.gamma
    return c0, c1, c2, c3, c4, c5


@inline
def at_alpha_point(m, s, st, w, b, ag_old, ag_new):
    """Move the evaluation point to t(n+1-alpha); return the ground acceleration there. For
    Newmark the evaluation arrays are the step-end arrays themselves."""
    if not s.alpha:
        return ag_new
    wm = 1.0 - s.alpha_m
    wf = 1.0 - s.alpha_f
    U, V, A = st.U[b], st.V[b], st.A[b]
    u, v, a, ue, ve, ae = w.u, w.v, w.a, w.ue, w.ve, w.ae
    for i in range(u.shape[0]):
        ue[i] = wf * u[i] + s.alpha_f * U[i]
        ve[i] = wf * v[i] + s.alpha_f * V[i]
        ae[i] = wm * a[i] + s.alpha_m * A[i]
    return wf * ag_new + s.alpha_f * ag_old


@inline
def at_end_point(s, w):
    """Move the evaluation point to the step end (a no-op for Newmark)."""
    if s.alpha:
        u, v, a, ue, ve, ae = w.u, w.v, w.a, w.ue, w.ve, w.ae
        for i in range(u.shape[0]):
            ue[i] = u[i]
            ve[i] = v[i]
            ae[i] = a[i]


@inline
def alpha_work(m, st, w, b, age, wf):
    """G(t(n+1-alpha)) . (u(n+1) - u(n)): the work over the whole step of the non-inertial
    forces (damping, storeys, contacts, ground) as evaluated at the alpha point, where the
    step's equilibrium holds (pframe.kernel.energy counts the integrator's dissipation with
    it). Element deformations are linear in u, so their increment is (d_alpha - d_n) / wf."""
    mass, damping, U, u, ve = m.mass[b], m.mass_damping[b], st.U[b], w.u, w.ve
    work = 0.0
    for i in range(mass.shape[0]):
        work += (damping[i] * ve[i] + mass[i] * age) * (u[i] - U[i])
    drift, force, damping_force, drift_c = (w.drift, w.story_force, w.story_damping_force,
                                            st.drift[b])
    for e in range(drift.shape[0]):
        work += (force[e] + damping_force[e]) * (drift[e] - drift_c[e]) / wf
    cforce, pen, pen_c = w.contact_force, w.penetration, st.penetration[b]
    for e in range(pen.shape[0]):
        work += cforce[e] * (pen[e] - pen_c[e]) / wf
    return work


@inline
def factor_linear(m, s, st, w, b, k, h):
    """Factor the constant effective stiffness of a linear scene (initial tangents)."""
    c0, c1, _, _, _, _ = coefficients(s, h)
    wf = 1.0 - s.alpha_f
    k0, beta, kks = m.story_k0[b], m.story_beta[b], w.story_kk
    for e in range(kks.shape[0]):
        kks[e] = k0[e] * (1.0 + c1 * beta[e]) * wf
    return factor(m, s, st, w, b, k, c0, c1, 1.0 - s.alpha_m, wf)


def solve_step(m, s, st, w, b, k, h, ag_old, ag_new):
    """Iterate a step of length h from the committed state to equilibrium at ag_new.

    Leaves u, v, a at the step end and the element forces and law states evaluated there;
    returns False (after recording why in st.status) if it failed.
    """
    U, V, A = st.U[b], st.V[b], st.A[b]
    u, v, a, R, band, scalars = w.u, w.v, w.a, w.R, w.band, w.scalars
    counters = st.counters[b]
    n = u.shape[0]
    c0, c1, c2, c3, c4, c5 = coefficients(s, h)
    wm = 1.0 - s.alpha_m
    wf = 1.0 - s.alpha_f
    inv_c0_mmin = 1.0 / (c0 * wm * scalars[MASS_MIN])
    # Predictor: constant acceleration (a = A, v = V + h A). A storey that
    # keeps yielding or a contact that stays closed is then met on its current branch with
    # the tangent of the direction it moves in, and one solve ends the step. u = U would
    # evaluate every law at its committed point, where a yielding storey reports its elastic
    # slope (four steps in five of the paper's example took a second solve). A linear scene's
    # single solve is exact from any predictor.
    #
    # The unknown iterated is the acceleration a, from which u and v follow forward,
    # u = U + h V + h^2 (1/2 - beta) A + beta h^2 a and v = V + h (1 - gamma) A + gamma h a.
    # Iterating on u and taking a = c0 (u - U) - c2 V - c3 A would lose every bit of a in a
    # short (sub-)step: u - U cancels to eps |u| and c0 ~ 1/h^2 amplifies it (a sub-step of
    # 1e-12 s that an event ends gave accelerations of 1e5 m/s^2 from round-off, which the next
    # step turned into kinetic energy). The effective stiffness and the solves are the same;
    # a solve's displacement increment du gives a += c0 du.
    bh2 = s.beta * h * h
    for i in range(n):
        a[i] = A[i]
    converged = False
    norm_u = 0.0
    age = ag_new
    for it in range(s.max_iterations + 1):
        for i in range(n):
            u[i] = U[i] + (h * V[i] + (0.5 * h * h - bh2) * A[i] + bh2 * a[i])
            v[i] = V[i] + c4 * A[i] + c5 * a[i]
        age = at_alpha_point(m, s, st, w, b, ag_old, ag_new)
        if evaluate(m, st, w, b, age, c1, wf, not s.linear):
            scalars[STALE] = 1.0
        if not check_finite(m, st, w, b, k):
            return False
        if not s.linear and it > 0 and not converged:
            # The next increment du = K^-1 R is bounded by |R| / (c0 wm min m) while the
            # tangents are not negative. When that bound is a thousandth of the tolerance the
            # correction is negligible (a step whose laws stayed on one branch: R is
            # round-off), so skip it; otherwise iterate, so that results do not depend on the
            # tolerance.
            norm_r = 0.0
            for i in range(n):
                norm_r += R[i] * R[i]
            converged = (np.sqrt(norm_r) * inv_c0_mmin
                         <= 1e-3 * (s.tolerance * np.sqrt(norm_u) + s.absolute_tolerance))
        if converged:
            break
        if it == s.max_iterations:
            worst = 0
            for i in range(n):
                if abs(R[i]) > abs(R[worst]):
                    worst = i
            return fail(st, b, NOT_CONVERGED, k, NODE, worst)
        # Refactor only when a tangent or the step changed: a storey that stays elastic or
        # keeps yielding and an open contact keep theirs, so most steps reuse the factor (bit
        # for bit what refactoring would give).
        if not s.linear and (scalars[STALE] != 0.0 or h != scalars[H_FACTORED]):
            scalars[STALE] = 0.0
            scalars[H_FACTORED] = h
            if not factor(m, s, st, w, b, k, c0, c1, wm, wf):
                return False
        ldl_solve(band, s.bandwidth, R)
        counters[SOLVES] += 1
        if s.linear:
            for i in range(n):
                a[i] += c0 * R[i]
            converged = True
        else:
            norm_du = 0.0
            norm_u = 0.0
            for i in range(n):
                a[i] += c0 * R[i]
                norm_du += R[i] * R[i]
                norm_u += (u[i] + R[i]) * (u[i] + R[i])
            converged = np.sqrt(norm_du) <= s.tolerance * np.sqrt(norm_u) + s.absolute_tolerance
    if s.alpha:
        scalars[ALPHA_WORK] = alpha_work(m, st, w, b, age, wf)
        # commit the laws' state and forces at the step end, not at the alpha point
        at_end_point(s, w)
        evaluate_call(m, st, w, b, ag_new, c1, wf, False)
    return True


#: solve_step as a call: for sub-steps and event location (Newton compiled into few places)
solve_step_call = compiled(solve_step)
#: inlined where the common case runs (no call)
solve_step = inline(solve_step)
