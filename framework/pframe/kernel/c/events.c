/* Event-aware stepping: contact onset and separation located inside a step.
 *
 * While a contact is closed, a step is taken in sub-steps of 1 / event_parts of it. After a
 * converged sub-step in which a contact opened or closed, the sub-step is shortened so that it
 * ends just past the crossing of delta = 0, and the rest of the step follows as further
 * sub-steps. Three things make that exact for every law, whatever its force does at delta = 0:
 *
 * - The search holds the crossing contact on the branch it had at the sub-step start
 *   (w->scalars[HELD], see evaluate in assembly.c): open, no force; closed, the law's force at
 *   delta = 0+ continued below 0. A dashpot's force c delta' jumps at delta = 0 (Kelvin at
 *   onset, and at separation with keep_tension); on the real law the end penetration of a
 *   sub-step then jumps across the window the search aims at as the sub-step grows (the
 *   contact's force switches on or off inside it), and the search stalled on the wrong side.
 *   On the held branch it is continuous, and the crossing is where the trajectory of the
 *   branch the contact is on reaches delta = 0 -- the event itself. If the held trajectory
 *   does not cross in the sub-step at all, the sub-step is that trajectory (a root of the real
 *   law, which had two).
 * - The search is regula falsi with the Illinois modification (no end of the bracket sticks).
 * - After the event sub-step is committed, the laws are evaluated at its end on their new
 *   branches and the acceleration is taken from equilibrium there, as at t = 0: the force jump
 *   is a jump of the acceleration at the event, which the next sub-step starts from instead of
 *   averaging it over its length. The jump happens at a fixed penetration and does no work.
 *   A contact that starts touching (delta = 0 exactly, as two bodies placed against each
 *   other) with a closing velocity is at its onset: it is restarted closed before its first
 *   sub-step. (The modified kinetic energy of HHT and generalised-alpha, whose term
 *   (beta - 1/4) h^2 a M a / 2 depends on the acceleration, is re-taken with the new one.)
 */

/* regula falsi iterations of one event location (Illinois: a few suffice) */
#define LOCATE_ITERATIONS 40

/* A contact whose penetration went from d0 to d1 opened or closed (d0 = 0 exactly is the
 * touching start of a contact, not a crossing). */
static int crossed(double d0, double d1)
{
    return (d0 < 0.0 && 0.0 < d1) || (d0 > 0.0 && 0.0 >= d1);
}

/* Shorten the converged sub-step from pos to *f_try (fractions of step k) to end just past the
 * first contact crossing in it; *f_try, *hs, ag_old[], ag_new[] become the sub-step to commit and
 * *located says whether it ends at an event. 0 if a sub-step of the search failed. */
static int locate_event(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                        int64_t k, double h, double pos, double *f_try, double *hs,
                        double *ag_old, double *ag_new, int *located)
{
    const int64_t nc = m->contacts;
    const double *pen_c = st->penetration + b * nc;
    int64_t first = -1, e, iteration, side = 0;
    double earliest = 2.0, d0, d1, target, lo_s, lo_g, hi_s, hi_g, span, at = 1.0;
    int found = 0;
    *located = 0;
    for (e = 0; e < nc; e++) {
        d0 = pen_c[e];
        d1 = w->penetration[e];
        if (crossed(d0, d1)) {
            const double fraction = d0 / (d0 - d1);
            if (fraction < earliest) {
                earliest = fraction;
                first = e;
            }
        }
    }
    if (first < 0)
        return 1;
    d0 = pen_c[first];
    w->scalars[HELD] = (double)first;
    w->scalars[HELD_CLOSED] = d0 > 0.0 ? 1.0 : 0.0;
    /* the sub-step again with the contact on its branch: does it cross there? */
    if (!solve_step(m, s, st, w, b, k, *hs, ag_old, ag_new)) {
        w->scalars[HELD] = -1.0;
        return 0;
    }
    d1 = w->penetration[first];
    if (!crossed(d0, d1)) {
        w->scalars[HELD] = -1.0;
        return 1;
    }
    /* end within (0, 2 target] of delta = 0, past it (onset: delta > 0; separation: <= 0) */
    target = 1e-7 * fabs(d1 - d0) * (d1 > 0.0 ? 1.0 : -1.0);
    lo_s = 0.0;
    lo_g = d0 - target;
    hi_s = 1.0;
    hi_g = d1 - target;
    span = *f_try - pos;
    for (iteration = 0; iteration < LOCATE_ITERATIONS; iteration++) {
        double fraction = (lo_s * hi_g - hi_s * lo_g) / (hi_g - lo_g);
        const double width = hi_s - lo_s;
        double d, g;
        fraction = py_min(py_max(fraction, lo_s + 1e-9 * width), hi_s - 1e-9 * width);
        *f_try = pos + fraction * span;
        *hs = (*f_try - pos) * h;
        ground_between(m, b, k, pos, *f_try, ag_old, ag_new);
        if (!solve_step(m, s, st, w, b, k, *hs, ag_old, ag_new)) {
            w->scalars[HELD] = -1.0;
            return 0;
        }
        at = fraction;
        d = w->penetration[first];
        if ((target > 0.0 && 0.0 < d && d <= 2.0 * target)
            || (target < 0.0 && 2.0 * target <= d && d <= 0.0)) {
            found = 1;
            break;
        }
        g = d - target;
        if (g * lo_g > 0.0) { /* still before the crossing */
            lo_s = fraction;
            lo_g = g;
            if (side == -1)
                hi_g *= 0.5;
            side = -1;
        } else {
            hi_s = fraction;
            hi_g = g;
            if (side == 1)
                lo_g *= 0.5;
            side = 1;
        }
        if (hi_s - lo_s <= 1e-15)
            break;
    }
    if (!found && at != hi_s) {
        /* not in the window in LOCATE_ITERATIONS: end at the nearest point known past it */
        *f_try = pos + hi_s * span;
        *hs = (*f_try - pos) * h;
        ground_between(m, b, k, pos, *f_try, ag_old, ag_new);
        if (!solve_step(m, s, st, w, b, k, *hs, ag_old, ag_new)) {
            w->scalars[HELD] = -1.0;
            return 0;
        }
    }
    w->scalars[HELD] = -1.0;
    *located = 1;
    return 1;
}

/* At an event (the end of a committed sub-step, or a contact touching with a closing
 * velocity): every law evaluated at the committed state on its new branch (contact `held`
 * closed, if >= 0), and the acceleration from equilibrium there, as at t = 0. */
static int restart(const Model *m, const Settings *s, State *st, Work *w, int64_t b, int64_t k,
                   double hs, const double *ag, int64_t held)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const double *U = st->U + b * n, *V = st->V + b * n, *mass = m->mass + b * n;
    double *A = st->A + b * n;
    double shadow, kinetic = 0.0;
    int64_t i, e;
    for (i = 0; i < n; i++) {
        w->u[i] = U[i];
        w->v[i] = V[i];
        w->a[i] = 0.0;
    }
    at_end_point(m, s, w);
    w->scalars[HELD] = (double)held;
    w->scalars[HELD_CLOSED] = 1.0;
    evaluate(m, s, st, w, b, ag, 0.0, 1.0, 0);
    w->scalars[HELD] = -1.0;
    if (!check_finite(m, st, w, b, k))
        return 0;
    shadow = kinetic_shadow(s, hs);
    for (i = 0; i < n; i++) {
        A[i] = w->R[i] / mass[i];
        kinetic += 0.5 * mass[i] * (V[i] * V[i] + shadow * A[i] * A[i]);
    }
    /* The jump of the acceleration does no work (u and v do not move), but the modified
     * kinetic energy's term (beta - 1/4) h^2 a M a / 2 of the integrator's energy form
     * (integrator.c) jumps with it: that change belongs to the integrator's own account, so
     * the balance stays closed. */
    st->energy[b * ENERGY_SLOTS + ALGORITHMIC] -= kinetic - st->energy[b * ENERGY_SLOTS + KINETIC];
    st->energy[b * ENERGY_SLOTS + KINETIC] = kinetic;
    for (e = 0; e < ns; e++) {
        st->story_force[b * ns + e] = w->story_force[e];
        st->story_damping_force[b * ns + e] = w->story_damping_force[e];
        st->story_tangent[b * ns + e] = w->story_tangent[e];
    }
    for (e = 0; e < nc; e++)
        st->contact_force[b * nc + e] = w->contact_force[e];
    {
        const int64_t story_values = ns * m->story_states, contact_values = nc * m->contact_states;
        for (i = 0; i < story_values; i++)
            st->story_committed[b * story_values + i] = st->story_trial[b * story_values + i];
        for (i = 0; i < contact_values; i++)
            st->contact_committed[b * contact_values + i] =
                st->contact_trial[b * contact_values + i];
    }
    return 1;
}

/* A contact whose committed penetration is exactly 0 (touching, as two bodies placed against
 * each other at t = 0) with a closing velocity and no force yet: it is at its onset, which no
 * crossing inside a sub-step will show. -1 if none. */
static int64_t touching(const Model *m, const State *st, int64_t b, const double *ag)
{
    const int64_t n = m->dofs, nc = m->contacts;
    const double *V = st->V + b * n;
    int64_t e;
    for (e = 0; e < nc; e++) {
        if (st->penetration[b * nc + e] == 0.0 && st->contact_force[b * nc + e] == 0.0
            && contact_closing(m, b, e, V, ground_block(m, ag, 2)) > 0.0)
            return e;
    }
    return -1;
}

/* Take part `part` of `parts` of step k in sub-steps that end at contact events. */
static int event_substeps(const Model *m, const Settings *s, State *st, Work *w,
                          Recording *rec, int64_t b, int64_t k, double h, int64_t part,
                          int64_t parts)
{
    const int64_t nc = m->contacts;
    const double *pen_c = st->penetration + b * nc;
    double pos = (double)part / (double)parts;
    const double stop = (double)(part + 1) / (double)parts;
    while (pos < stop) {
        /* while a contact is closed, sub-steps of 1 / event_parts of the step (a sliver left
         * before the step end joins the last one) */
        double f_try = stop, hs, *ag_old = w->ag_old, *ag_new = w->ag_new;
        int64_t e, onset;
        int located;
        for (e = 0; e < nc; e++) {
            if (pen_c[e] > 0.0) {
                const double piece = 1.0 / (double)(parts * m->event_parts[b]);
                if (pos + 1.01 * piece < stop)
                    f_try = pos + piece;
                break;
            }
        }
        hs = (f_try - pos) * h;
        ground_between(m, b, k, pos, f_try, ag_old, ag_new);
        onset = touching(m, st, b, ag_old);
        if (onset >= 0 && !restart(m, s, st, w, b, k, hs, ag_old, onset))
            return 0;
        if (!solve_step(m, s, st, w, b, k, hs, ag_old, ag_new))
            return 0;
        if (!locate_event(m, s, st, w, b, k, h, pos, &f_try, &hs, ag_old, ag_new, &located)
            || !commit(m, s, st, w, b, k, hs, ag_old, ag_new))
            return 0;
        if (located) {
            st->counters[b * COUNTER_SLOTS + EVENTS] += 1;
            if (!restart(m, s, st, w, b, k, hs, ag_new, -1))
                return 0;
        }
        record_substep(m, st, rec, b, k, ag_new);
        pos = f_try;
    }
    return 1;
}
