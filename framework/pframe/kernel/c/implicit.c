/* An implicit step in parts: the retry of a failed step, and event-aware stepping.
 *
 * solve_step (newton.c) runs the integrator's stages over a (sub-)step, here as in the time
 * loop: every part is a step of the scene's integrator. A step that has no Newton root (a law
 * with a jump or an infinite slope at contact onset) is retried from its start as 2, 4, ...
 * 2^max_split sub-steps with the ground motion interpolated (max_split = 0: the integrator
 * does not retry, and the run stops there); recording stays on the step grid. With
 * event-aware stepping each part is further cut at contact events.
 */

static void copy_values(double *saved, double *live, int64_t count, int to_saved)
{
    int64_t i;
    for (i = 0; i < count; i++) {
        if (to_saved)
            saved[i] = live[i];
        else
            live[i] = saved[i];
    }
}

/* Copy member b's committed arrays into sv (to_saved) or back from it. */
static void exchange(const Model *m, State *st, Saved *sv, int64_t b, int to_saved)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const int64_t S = ns * m->story_states, T = nc * m->contact_states;
    int64_t i;
    copy_values(sv->U, st->U + b * n, n, to_saved);
    copy_values(sv->V, st->V + b * n, n, to_saved);
    copy_values(sv->A, st->A + b * n, n, to_saved);
    copy_values(sv->drift, st->drift + b * ns, ns, to_saved);
    copy_values(sv->story_force, st->story_force + b * ns, ns, to_saved);
    copy_values(sv->story_damping_force, st->story_damping_force + b * ns, ns, to_saved);
    copy_values(sv->story_tangent, st->story_tangent + b * ns, ns, to_saved);
    copy_values(sv->story_committed, st->story_committed + b * S, S, to_saved);
    copy_values(sv->contact_force, st->contact_force + b * nc, nc, to_saved);
    copy_values(sv->penetration, st->penetration + b * nc, nc, to_saved);
    copy_values(sv->contact_committed, st->contact_committed + b * T, T, to_saved);
    for (i = 0; i < nc; i++) {
        if (to_saved)
            sv->impacts[i] = st->impacts[b * nc + i];
        else
            st->impacts[b * nc + i] = sv->impacts[i];
    }
    copy_values(sv->energy, st->energy + b * ENERGY_SLOTS, ENERGY_SLOTS, to_saved);
}

static void clear_status(State *st, int64_t b)
{
    int64_t i;
    for (i = 0; i < STATUS_SLOTS; i++)
        st->status[b * STATUS_SLOTS + i] = 0;
}

/* Take step k (of length h) as 2^split parts, and in twice as many from its start (saved in
 * sv) while one fails, up to 2^max_split; 0 (after recording why in st->status, and restoring
 * the step's start) if it failed even then. With events, each part is further cut at contact
 * events. */
static int split_step(const Model *m, const Settings *s, State *st, Work *w, Saved *sv,
                      Recording *rec, int64_t b, int64_t k, double h, int64_t split)
{
    for (;;) {
        const int64_t parts = (int64_t)1 << split;
        int64_t part, code;
        int ok = 1;
        for (part = 0; part < parts; part++) {
            if (s->events) {
                ok = event_substeps(m, s, st, w, rec, b, k, h, part, parts);
            } else {
                const double pos = (double)part / (double)parts;
                const double stop = (double)(part + 1) / (double)parts;
                const double hs = (stop - pos) * h;
                ground_between(m, b, k, pos, stop, w->ag_old, w->ag_new);
                ok = (solve_step(m, s, st, w, b, k, hs, w->ag_old, w->ag_new)
                      && commit(m, s, st, w, b, k, hs, w->ag_old, w->ag_new));
                if (ok)
                    record_substep(m, st, rec, b, k, w->ag_new);
            }
            if (!ok)
                break;
        }
        if (ok)
            return 1;
        exchange(m, st, sv, b, 0);
        code = st->status[b * STATUS_SLOTS + STATUS_CODE];
        if (code == NOT_FINITE || code == NOT_STABLE || split == s->max_split)
            return 0;
        if (split == 0)
            st->counters[b * COUNTER_SLOTS + SPLIT_STEPS] += 1;
        clear_status(st, b);
        split += 1;
    }
}

/* Step k (of length h) in sub-steps, after the whole step failed in the time loop or, with
 * event location, from the start; 0 (after recording why in st->status) if it failed even in
 * 2^max_split sub-steps. The whole step is the common case, and the time loop (loop.c) takes
 * it itself. */
static int step_in_parts(const Model *m, const Settings *s, State *st, Work *w, Saved *sv,
                         Recording *rec, int64_t b, int64_t k, double h)
{
    int64_t split = 0;
    if (!s->events) {
        const int64_t code = st->status[b * STATUS_SLOTS + STATUS_CODE];
        if (s->linear || s->max_split == 0 || code == NOT_FINITE || code == NOT_STABLE)
            return 0;
        st->counters[b * COUNTER_SLOTS + SPLIT_STEPS] += 1;
        clear_status(st, b);
        split = 1;
    }
    /* nothing was committed yet: this is the step's start (with events, several sub-steps may
     * be committed before a failure) */
    exchange(m, st, sv, b, 1);
    return split_step(m, s, st, w, sv, rec, b, k, h, split);
}
