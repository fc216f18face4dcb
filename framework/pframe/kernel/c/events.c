/* Event-aware stepping: contact onset and separation located inside a step.
 *
 * While a contact is closed, a step is taken in sub-steps of 1 / event_parts of it. After a
 * converged sub-step, a contact that opened or closed inside it shortens it (regula falsi on
 * the fraction of the sub-step) so that it ends just past the crossing, where a law's onset
 * velocity is taken; the rest of the step follows as further sub-steps.
 */

/* Shorten the converged sub-step from pos to *f_try (fractions of step k) to end just past the
 * first contact crossing in it; *f_try, *hs, *ag_old, *ag_new become the sub-step to commit.
 * 0 if a shortened sub-step failed. */
static int locate_event(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                        int64_t k, double h, double pos, double *f_try, double *hs,
                        double *ag_old, double *ag_new)
{
    const int64_t nc = m->contacts;
    const double *pen_c = st->penetration + b * nc;
    int64_t first = -1, e, iteration;
    double earliest = 2.0, d0, d1, target, lo_s, lo_d, hi_s, hi_d, span;
    for (e = 0; e < nc; e++) {
        d0 = pen_c[e];
        d1 = w->penetration[e];
        if (d0 != 0.0 && ((d0 < 0.0 && 0.0 < d1) || (d0 > 0.0 && 0.0 >= d1))) {
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
    d1 = w->penetration[first];
    target = 1e-7 * fabs(d1 - d0) * (d1 > 0.0 ? 1.0 : -1.0);
    lo_s = 0.0;
    lo_d = d0;
    hi_s = 1.0;
    hi_d = d1;
    span = *f_try - pos;
    for (iteration = 0; iteration < 8; iteration++) {
        double fraction = lo_s + (target - lo_d) * (hi_s - lo_s) / (hi_d - lo_d), d;
        fraction = py_min(py_max(fraction, lo_s + 1e-6 * (hi_s - lo_s)),
                          hi_s - 1e-6 * (hi_s - lo_s));
        *f_try = pos + fraction * span;
        *hs = (*f_try - pos) * h;
        ground_between(m, b, k, pos, *f_try, ag_old, ag_new);
        if (!solve_step(m, s, st, w, b, k, *hs, *ag_old, *ag_new))
            return 0;
        d = w->penetration[first];
        if ((target > 0.0 && 0.0 < d && d <= 2.0 * target)
            || (target < 0.0 && 2.0 * target <= d && d <= 0.0))
            break;
        if ((d - target) * (lo_d - target) > 0.0) {
            lo_s = fraction;
            lo_d = d;
        } else {
            hi_s = fraction;
            hi_d = d;
        }
    }
    return 1;
}

/* Take part `part` of `parts` of step k in sub-steps that end at contact events. */
static int event_substeps(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                          int64_t k, double h, int64_t part, int64_t parts)
{
    const int64_t nc = m->contacts;
    const double *pen_c = st->penetration + b * nc;
    double pos = (double)part / (double)parts;
    const double stop = (double)(part + 1) / (double)parts;
    while (pos < stop) {
        /* while a contact is closed, sub-steps of 1 / event_parts of the step (a sliver left
         * before the step end joins the last one) */
        double f_try = stop, hs, ag_old, ag_new;
        int64_t e;
        for (e = 0; e < nc; e++) {
            if (pen_c[e] > 0.0) {
                const double piece = 1.0 / (double)(parts * m->event_parts[b]);
                if (pos + 1.01 * piece < stop)
                    f_try = pos + piece;
                break;
            }
        }
        hs = (f_try - pos) * h;
        ground_between(m, b, k, pos, f_try, &ag_old, &ag_new);
        if (!solve_step(m, s, st, w, b, k, hs, ag_old, ag_new))
            return 0;
        if (!locate_event(m, s, st, w, b, k, h, pos, &f_try, &hs, &ag_old, &ag_new)
            || !commit(m, s, st, w, b, k, hs, ag_old, ag_new))
            return 0;
        pos = f_try;
    }
    return 1;
}
