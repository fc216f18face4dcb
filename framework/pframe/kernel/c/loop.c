/* The time loop: every member of a batch, over the steps of one call.
 *
 * This is the kernel's entry point, pframe_run. It serves every scene: what a scene does not
 * use costs nothing here (a linear scene factors once and takes one solve a step; a scene
 * without contacts has no contact elements; an unrecorded quantity is never gathered; an
 * unused law is never branched to). Calls over consecutive step ranges continue one another,
 * bit for bit, so a run can be cut into chunks for progress reports, Ctrl-C and streamed
 * output. The kernel uses no Python API: the driver calls it through ctypes, which releases
 * the GIL, so members of a batch run in threads.
 */

/* A member's first step in a call refactors and takes its own smallest mass. */
static void reset_work(const Model *m, Work *w, int64_t b)
{
    const double *mass = m->mass + b * m->dofs;
    double smallest = mass[0];
    int64_t i;
    for (i = 0; i < m->stories; i++)
        w->story_kk[i] = NAN;
    for (i = 0; i < m->contacts; i++)
        w->contact_kk[i] = NAN;
    for (i = 0; i < SCALAR_SLOTS; i++)
        w->scalars[i] = 0.0;
    w->scalars[HELD] = -1.0;
    for (i = 0; i < m->dofs; i++)
        smallest = py_min(smallest, mass[i]);
    w->scalars[MASS_MIN] = smallest;
}

/* State 0: accelerations from equilibrium with the initial displacements and velocities. */
static int initial_state(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                         int64_t k, double h)
{
    const int64_t n = m->dofs;
    const double *U = st->U + b * n, *V = st->V + b * n, *mass = m->mass + b * n;
    int64_t i;
    ground_at(m, b, 0, w->ag_new); /* the ground's acceleration at t = 0, each channel */
    for (i = 0; i < m->ground_series; i++)
        w->ag_old[i] = 0.0;
    for (i = 0; i < n; i++) {
        w->u[i] = U[i];
        w->v[i] = V[i];
        w->a[i] = 0.0;
    }
    at_end_point(m, s, w);
    evaluate(m, s, st, w, b, w->ag_new, 0.0, 1.0, 0);
    if (!check_finite(m, st, w, b, k))
        return 0;
    for (i = 0; i < n; i++)
        w->a[i] = w->R[i] / mass[i];
    return commit(m, s, st, w, b, k, h, w->ag_old, w->ag_new);
}

/* Advance every member that has not stopped from state begin to state end (state 0 is t = 0,
 * computed from the initial conditions). w and sv are scratch arrays used by the members in
 * turn. Returns RUN_OK, RUN_ZERO_DIVISION when a step's coefficients divided by zero, or
 * RUN_STOPPED when the driver asked to stop (m->stop, seen at every evaluation): the members'
 * states are then mid-call, and the driver discards the run. */
PFRAME_EXPORT int64_t pframe_run(const Model *m, const Settings *s, State *st, Recording *rec,
                                 Work *w, Saved *sv, int64_t begin, int64_t end)
{
    Histories histories; /* the same for every member */
    int64_t b, k;
    prepare_histories(rec, &histories);
    for (b = 0; b < m->batch; b++) {
        const double h = m->dt[b];
        const int64_t first_step = imax(begin, 1);
        Loops loops;
        Envelopes envelopes;
        int64_t due;
        if (stop_asked(m))
            return RUN_STOPPED;
        if (st->status[b * STATUS_SLOTS + STATUS_CODE] != OK)
            continue;
        reset_work(m, w, b);
        prepare_loops(m, st, w, b, &loops);
        prepare_envelopes(m, st, rec, w, b, &envelopes);
        if (s->linear && !s->explicit && end > first_step) { /* factored once per call */
            if (!factor_linear(m, s, st, w, b, first_step, h, 0)) {
                if (w->scalars[ZERO_DIVISION] != 0.0)
                    return RUN_ZERO_DIVISION;
                continue;
            }
        }
        due = next_due(&histories, begin);
        for (k = begin; k < end; k++) {
            int ok;
            if (k == 0) {
                ok = initial_state(m, s, st, w, b, k,
                                   s->explicit ? h / (double)m->cd_parts[b] : h);
            } else if (s->explicit) {
                ok = explicit_step(m, s, st, w, rec, b, k, h);
            } else if (s->events) {
                ok = step_in_parts(m, s, st, w, sv, rec, b, k, h);
            } else {
                ground_between(m, b, k, 0.0, 1.0, w->ag_old, w->ag_new);
                if ((s->linear || !s->force_split)
                    && solve_step(m, s, st, w, b, k, h, w->ag_old, w->ag_new))
                    ok = commit(m, s, st, w, b, k, h, w->ag_old, w->ag_new);
                else
                    ok = step_in_parts(m, s, st, w, sv, rec, b, k, h);
            }
            if (!ok) {
                if (w->scalars[ZERO_DIVISION] != 0.0)
                    return RUN_ZERO_DIVISION;
                if (st->status[b * STATUS_SLOTS + STATUS_CODE] == STOPPED)
                    return RUN_STOPPED;
                break;
            }
            if (k == due)
                due = record_histories(m, st, rec, &histories, b, k);
            if (rec->closings)
                record_closings(st, rec, m->dofs, b);
            if (envelopes.count)
                step_envelopes(m, st, rec, b, k, &envelopes); /* the ground at step k itself */
        }
    }
    return RUN_OK;
}

/* The interface version and a hash of the sources this kernel was compiled from (the driver
 * refuses a kernel built from other sources than those beside it: a stale build). */
#ifndef PFRAME_SOURCE_HASH
#define PFRAME_SOURCE_HASH unknown
#endif
#define PFRAME_STRING(x) #x
#define PFRAME_EXPAND(x) PFRAME_STRING(x)

PFRAME_EXPORT int64_t pframe_interface(void) { return PFRAME_KERNEL_INTERFACE; }

/* setup.py defines PFRAME_SOURCE_HASH as a bare name (h + hex digits), quoted here: a quoted
 * string on a compiler's command line is not portable */
PFRAME_EXPORT const char *pframe_source_hash(void) { return PFRAME_EXPAND(PFRAME_SOURCE_HASH); }

/* sizeof of each struct, for the driver to check its ctypes mirror against */
PFRAME_EXPORT void pframe_layout(int64_t *sizes)
{
    sizes[0] = (int64_t)sizeof(Model);
    sizes[1] = (int64_t)sizeof(Settings);
    sizes[2] = (int64_t)sizeof(State);
    sizes[3] = (int64_t)sizeof(Recording);
    sizes[4] = (int64_t)sizeof(Work);
    sizes[5] = (int64_t)sizeof(Saved);
}

/* One built-in law's force, for the tests that compare the C translation of every law with
 * its Python definition (pframe.kernel.translate): kind 0 a material, 1 a contact law. */
PFRAME_EXPORT void pframe_law_force(int64_t kind, int64_t law, const double *params,
                                    const double *committed, double *trial,
                                    double deformation, double rate, double *out)
{
    Settings s = {0};
    const int64_t builtin = kind == 0 ? BUILTIN_MATERIALS : BUILTIN_CONTACT_LAWS;
    if (law < 0 || law >= builtin) { /* plug-ins are not in the compiled kernel */
        out[0] = out[1] = out[2] = NAN;
        return;
    }
    if (kind == 0)
        material_force(&s, law, params, committed, trial, deformation, rate, out);
    else
        contact_force(&s, law, params, committed, trial, deformation, rate, out);
}
