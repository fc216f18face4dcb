"""Explicit central difference (Newmark gamma = 1/2, beta = 0) with the diagonal mass.

u(n+1) = u + h v + h^2 a / 2; the forces at t(n+1) also depend on the velocity (damping,
contact dashpots), so a(n+1) is found from the predicted velocity v + h a and corrected once
with the trapezoidal velocity. A step longer than the stability limit allows is split into
``cd_parts`` equal sub-steps (``substeps: auto``), with the ground motion interpolated; every
sub-step counts its impacts and updates the envelopes (a contact can open and close between
two recorded steps).
"""

from __future__ import annotations

from pframe.kernel.cache import compiled
from pframe.kernel.state import SOLVES

from .assembly import check_finite, evaluate_call, ground_between
from .energy import commit_call
from .record import record_substep


@compiled
def explicit_step(m, s, st, w, b, k, h, rec):
    """Advance member ``b`` from step k - 1 to step k; False (after recording why) on failure."""
    U, V, A = st.U[b], st.V[b], st.A[b]
    u, v, a, R = w.u, w.v, w.a, w.R
    mass = m.mass[b]
    parts = m.cd_parts[b]
    hs = h / parts
    for part in range(parts):
        ag_old, ag_new = ground_between(m, b, k, part / parts, (part + 1) / parts)
        for i in range(mass.shape[0]):
            u[i] = U[i] + hs * V[i] + 0.5 * hs * hs * A[i]
            v[i] = V[i] + hs * A[i]
        for _ in range(2):  # predictor, then one corrector of the velocity-dependent forces
            evaluate_call(m, st, w, b, ag_new, 0.0, 1.0, False)
            if not check_finite(m, st, w, b, k):
                return False
            for i in range(mass.shape[0]):
                a[i] = R[i] / mass[i]
                v[i] = V[i] + 0.5 * hs * (A[i] + a[i])
        st.counters[b, SOLVES] += 1  # the diagonal mass 'solve' of central difference
        if not commit_call(m, s, st, w, b, k, hs, ag_old, ag_new):
            return False
        if parts > 1:
            record_substep(m, st, rec, b, k)
    return True
