/* Explicit central difference (Newmark gamma = 1/2, beta = 0) with the diagonal mass.
 *
 * u(n+1) = u + h v + h^2 a / 2; the forces at t(n+1) also depend on the velocity (damping,
 * contact dashpots), so a(n+1) is found from the predicted velocity v + h a and corrected
 * once with the trapezoidal velocity. A step longer than the stability limit allows is split
 * into cd_parts equal sub-steps (substeps: auto), with the ground motion interpolated; every
 * sub-step counts its impacts and updates the envelopes (a contact can open and close between
 * two recorded steps).
 */

/* Advance member b from step k - 1 to step k; 0 (after recording why) on failure. */
static int explicit_step(const Model *m, const Settings *s, State *st, Work *w,
                         Recording *rec, int64_t b, int64_t k, double h)
{
    const int64_t n = m->dofs;
    const double *U = st->U + b * n, *V = st->V + b * n, *A = st->A + b * n;
    double *u = w->u, *v = w->v, *a = w->a;
    const double *R = w->R, *mass = m->mass + b * n;
    const int64_t parts = m->cd_parts[b];
    const double hs = h / (double)parts;
    int64_t part, i, pass;
    for (part = 0; part < parts; part++) {
        const double *ag_old = w->ag_old, *ag_new = w->ag_new;
        ground_between(m, b, k, (double)part / (double)parts, (double)(part + 1) / (double)parts,
                       w->ag_old, w->ag_new);
        for (i = 0; i < n; i++) {
            u[i] = U[i] + hs * V[i] + 0.5 * hs * hs * A[i];
            v[i] = V[i] + hs * A[i];
        }
        for (pass = 0; pass < 2; pass++) { /* predictor, then one corrector of the
                                              velocity-dependent forces */
            evaluate(m, s, st, w, b, ag_new, 0.0, 1.0, 0);
            if (!check_finite(m, st, w, b, k))
                return 0;
            for (i = 0; i < n; i++) {
                a[i] = R[i] / mass[i];
                v[i] = V[i] + 0.5 * hs * (A[i] + a[i]);
            }
        }
        st->counters[b * COUNTER_SLOTS + SOLVES] += 1; /* the diagonal mass 'solve' */
        if (!commit(m, s, st, w, b, k, hs, ag_old, ag_new))
            return 0;
        if (parts > 1)
            record_substep(m, st, rec, b, k, ag_new);
    }
    return 1;
}
