"""The time loop: every member of a batch, over the steps of one call.

This is the kernel's entry point, :func:`run`. It is compiled once for every scene: what a
scene does not use costs nothing here (a linear scene factors once and takes one solve a step;
a scene without contacts has empty contact arrays; an unrecorded quantity is never gathered;
an unused law is never branched to). Calls over consecutive step ranges continue one another,
bit for bit, so a run can be cut into chunks for progress reports and streamed output.
"""

from __future__ import annotations

import numpy as np

from pframe.kernel.cache import inline, jit
from pframe.kernel.state import HELD, MASS_MIN, OK, STATUS_CODE
from pframe.kernel.views import borrowed

from .assembly import check_finite, evaluate_call, ground_between
from .energy import commit, commit_call
from .explicit import explicit_step
from .implicit import step_in_parts
from .newton import at_end_point, factor_linear, solve_step
from .record import next_due, record_envelopes, record_histories


@inline
def reset_work(m, w, b):
    """A member's first step in a call refactors and takes its own smallest mass."""
    w.story_kk[:] = np.nan
    w.contact_kk[:] = np.nan
    w.scalars[:] = 0.0
    w.scalars[HELD] = -1.0
    mass = m.mass[b]
    smallest = mass[0]
    for i in range(mass.shape[0]):
        smallest = min(smallest, mass[i])
    w.scalars[MASS_MIN] = smallest


@inline
def initial_state(m, s, st, w, b, k, h):
    """State 0: accelerations from equilibrium with the initial displacements and velocities."""
    U, V = st.U[b], st.V[b]
    mass = m.mass[b]
    for i in range(mass.shape[0]):
        w.u[i] = U[i]
        w.v[i] = V[i]
        w.a[i] = 0.0
    at_end_point(s, w)
    ag = m.ground[b, 0]
    evaluate_call(m, st, w, b, ag, 0.0, 1.0, False)
    if not check_finite(m, st, w, b, k):
        return False
    for i in range(mass.shape[0]):
        w.a[i] = w.R[i] / mass[i]
    return commit_call(m, s, st, w, b, k, h, 0.0, ag)


@jit
def run(m, s, st, rec, w, sv, begin, end):
    """Advance every member that has not stopped from state ``begin`` to state ``end``
    (state 0 is t = 0, computed from the initial conditions). ``w`` and ``sv`` are scratch
    arrays (pframe.kernel.run.work_arrays), used by the members in turn.

    The whole step of the implicit family, the common case, is solved and committed here
    (inlined: no call per step); a step that fails, or one with event location, is taken in
    parts by :func:`pframe.kernel.implicit.step_in_parts`.
    """
    m, st, rec, w, sv = borrowed(m), borrowed(st), borrowed(rec), borrowed(w), borrowed(sv)
    envelopes = rec.enveloped.sum() > 0
    for b in range(m.mass.shape[0]):
        if st.status[b, STATUS_CODE] != OK:
            continue
        reset_work(m, w, b)
        h = m.dt[b]
        first_step = max(begin, 1)
        if s.linear and not s.explicit and end > first_step:  # factored once per call
            if not factor_linear(m, s, st, w, b, first_step, h):
                continue
        due = next_due(rec, begin)
        for k in range(begin, end):
            if k == 0:
                ok = initial_state(m, s, st, w, b, k, h / m.cd_parts[b] if s.explicit else h)
            elif s.explicit:
                ok = explicit_step(m, s, st, w, b, k, h, rec)
            elif s.events:
                ok = step_in_parts(m, s, st, w, sv, b, k, h, rec)
            else:
                ag_old, ag_new = ground_between(m, b, k, 0.0, 1.0)
                if solve_step(m, s, st, w, b, k, h, ag_old, ag_new):
                    ok = commit(m, s, st, w, b, k, h, ag_old, ag_new)
                else:
                    ok = step_in_parts(m, s, st, w, sv, b, k, h, rec)
            if not ok:
                break
            if k == due:
                due = record_histories(m, st, rec, b, k)
            if envelopes:
                record_envelopes(m, st, rec, b, k)
