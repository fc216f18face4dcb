/* Newton iterations of one implicit (sub-)step of the generalised-alpha family.
 *
 * From the committed state (U, V, A) at the step start, find u at the step end such that
 *
 *     M a(n+1-alpha_m) + C v(n+1-alpha_f) + F(u(n+1-alpha_f)) = -M a_g(t(n+1-alpha_f)),
 *
 * with Newmark's relations a = c0 (u - U) - c2 V - c3 A and v = V + c4 A + c5 a. A linear scene
 * takes one solve with the factor made once before its first step. A nonlinear scene starts
 * from the constant-acceleration predictor and refactors the effective stiffness only when an
 * element tangent or the step length changed.
 */

/* Newmark's c0 ... c5 for a step of length h; 0 (and the work's ZERO_DIVISION flag set) when
 * one divides by zero (Python raised ZeroDivisionError there; the driver still does). */
static int coefficients(const Settings *s, Work *w, double h, double *c)
{
    if (s->beta * h * h == 0.0 || s->beta * h == 0.0 || s->beta == 0.0) {
        w->scalars[ZERO_DIVISION] = 1.0;
        return 0;
    }
    c[0] = 1.0 / (s->beta * h * h);
    c[1] = s->gamma / (s->beta * h);
    c[2] = 1.0 / (s->beta * h);
    c[3] = 0.5 / s->beta - 1.0;
    c[4] = h * (1.0 - s->gamma);
    c[5] = h * s->gamma;
    return 1;
}

/* Move the evaluation point to t(n+1-alpha); return the ground acceleration there. For
 * Newmark the evaluation arrays are the step-end arrays themselves. */
static double at_alpha_point(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                             double ag_old, double ag_new)
{
    const int64_t n = m->dofs;
    double wm, wf;
    const double *U, *V, *A;
    int64_t i;
    if (!s->alpha)
        return ag_new;
    wm = 1.0 - s->alpha_m;
    wf = 1.0 - s->alpha_f;
    U = st->U + b * n;
    V = st->V + b * n;
    A = st->A + b * n;
    for (i = 0; i < n; i++) {
        w->ue[i] = wf * w->u[i] + s->alpha_f * U[i];
        w->ve[i] = wf * w->v[i] + s->alpha_f * V[i];
        w->ae[i] = wm * w->a[i] + s->alpha_m * A[i];
    }
    return wf * ag_new + s->alpha_f * ag_old;
}

/* Move the evaluation point to the step end (a no-op for Newmark). */
static void at_end_point(const Model *m, const Settings *s, Work *w)
{
    int64_t i;
    if (s->alpha) {
        for (i = 0; i < m->dofs; i++) {
            w->ue[i] = w->u[i];
            w->ve[i] = w->v[i];
            w->ae[i] = w->a[i];
        }
    }
}

/* G(t(n+1-alpha)) . (u(n+1) - u(n)): the work over the whole step of the non-inertial forces
 * (damping, storeys, contacts, ground) as evaluated at the alpha point, where the step's
 * equilibrium holds (energy.c counts the integrator's dissipation with it). Element
 * deformations are linear in u, so their increment is (d_alpha - d_n) / wf. */
static double alpha_work(const Model *m, State *st, Work *w, int64_t b, double age, double wf)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *U = st->U + b * n, *u = w->u, *ve = w->ve;
    const double *drift_c = st->drift + b * ns, *pen_c = st->penetration + b * nc;
    double work = 0.0;
    int64_t i, e;
    for (i = 0; i < n; i++)
        work += (damping[i] * ve[i] + mass[i] * age) * (u[i] - U[i]);
    for (e = 0; e < ns; e++)
        work += (w->story_force[e] + w->story_damping_force[e]) * (w->drift[e] - drift_c[e]) / wf;
    for (e = 0; e < nc; e++)
        work += w->contact_force[e] * (w->penetration[e] - pen_c[e]) / wf;
    return work;
}

/* Factor the constant effective stiffness of a linear scene (initial tangents). */
static int factor_linear(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                         int64_t k, double h)
{
    double c[6], wf;
    const double *k0 = m->story_k0 + b * m->stories, *beta = m->story_beta + b * m->stories;
    int64_t e;
    if (!coefficients(s, w, h, c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    wf = 1.0 - s->alpha_f;
    for (e = 0; e < m->stories; e++)
        w->story_kk[e] = k0[e] * (1.0 + c[1] * beta[e]) * wf;
    return factor(m, s, st, w, b, k, c[0], c[1], 1.0 - s->alpha_m, wf);
}

/* Iterate a step of length h from the committed state to equilibrium at ag_new.
 *
 * Leaves u, v, a at the step end and the element forces and law states evaluated there;
 * returns 0 (after recording why in st->status) if it failed. */
static int solve_step(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                      int64_t k, double h, double ag_old, double ag_new)
{
    const int64_t n = m->dofs;
    const double *U = st->U + b * n, *V = st->V + b * n, *A = st->A + b * n;
    double *u = w->u, *v = w->v, *a = w->a, *R = w->R, *scalars = w->scalars;
    int64_t *counters = st->counters + b * COUNTER_SLOTS;
    double c[6], c0, c1, c2, c3, c4, c5, wm, wf, inv_c0_mmin, bh2, norm_u = 0.0, age = ag_new;
    int converged = 0;
    int64_t i, it;
    if (!coefficients(s, w, h, c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    c0 = c[0];
    c1 = c[1];
    c2 = c[2];
    c3 = c[3];
    c4 = c[4];
    c5 = c[5];
    wm = 1.0 - s->alpha_m;
    wf = 1.0 - s->alpha_f;
    inv_c0_mmin = 1.0 / (c0 * wm * scalars[MASS_MIN]);
    /* Predictor: constant acceleration (a = A, v = V + h A). A storey that keeps yielding or a
     * contact that stays closed is then met on its current branch with the tangent of the
     * direction it moves in, and one solve ends the step. u = U would evaluate every law at
     * its committed point, where a yielding storey reports its elastic slope (four steps in
     * five of the paper's example took a second solve). A linear scene's single solve is exact
     * from any predictor.
     *
     * The unknown iterated is the acceleration a, from which u and v follow forward,
     * u = U + h V + h^2 (1/2 - beta) A + beta h^2 a and v = V + h (1 - gamma) A + gamma h a.
     * Iterating on u and taking a = c0 (u - U) - c2 V - c3 A would lose every bit of a in a
     * short (sub-)step: u - U cancels to eps |u| and c0 ~ 1/h^2 amplifies it (a sub-step of
     * 1e-12 s that an event ends gave accelerations of 1e5 m/s^2 from round-off, which the
     * next step turned into kinetic energy). The effective stiffness and the solves are the
     * same; a solve's displacement increment du gives a += c0 du. (c2 and c3 are not needed.) */
    (void)c2;
    (void)c3;
    bh2 = s->beta * h * h;
    for (i = 0; i < n; i++)
        a[i] = A[i];
    for (it = 0; it < s->max_iterations + 1; it++) {
        for (i = 0; i < n; i++) {
            u[i] = U[i] + (h * V[i] + (0.5 * h * h - bh2) * A[i] + bh2 * a[i]);
            v[i] = V[i] + c4 * A[i] + c5 * a[i];
        }
        age = at_alpha_point(m, s, st, w, b, ag_old, ag_new);
        if (evaluate(m, s, st, w, b, age, c1, wf, !s->linear))
            scalars[STALE] = 1.0;
        if (!check_finite(m, st, w, b, k))
            return 0;
        if (!s->linear && it > 0 && !converged) {
            /* The next increment du = K^-1 R is bounded by |R| / (c0 wm min m) while the
             * tangents are not negative. When that bound is a thousandth of the tolerance the
             * correction is negligible (a step whose laws stayed on one branch: R is
             * round-off), so skip it; otherwise iterate, so that results do not depend on the
             * tolerance. */
            double norm_r = 0.0;
            for (i = 0; i < n; i++)
                norm_r += R[i] * R[i];
            converged = (sqrt(norm_r) * inv_c0_mmin
                         <= 1e-3 * (s->tolerance * sqrt(norm_u) + s->absolute_tolerance));
        }
        if (converged)
            break;
        if (it == s->max_iterations) {
            int64_t worst = 0;
            for (i = 0; i < n; i++)
                if (fabs(R[i]) > fabs(R[worst]))
                    worst = i;
            return fail(st, b, NOT_CONVERGED, k, NODE, worst);
        }
        /* Refactor only when a tangent or the step changed: a storey that stays elastic or
         * keeps yielding and an open contact keep theirs, so most steps reuse the factor (bit
         * for bit what refactoring would give). */
        if (!s->linear
            && (s->always_refactor || scalars[STALE] != 0.0 || h != scalars[H_FACTORED])) {
            scalars[STALE] = 0.0;
            scalars[H_FACTORED] = h;
            if (!factor(m, s, st, w, b, k, c0, c1, wm, wf))
                return 0;
        }
        ldl_solve(w->band, n, s->bandwidth, R);
        counters[SOLVES] += 1;
        if (s->linear) {
            for (i = 0; i < n; i++)
                a[i] += c0 * R[i];
            converged = 1;
        } else {
            double norm_du = 0.0;
            norm_u = 0.0;
            for (i = 0; i < n; i++) {
                a[i] += c0 * R[i];
                norm_du += R[i] * R[i];
                norm_u += (u[i] + R[i]) * (u[i] + R[i]);
            }
            converged = sqrt(norm_du) <= s->tolerance * sqrt(norm_u) + s->absolute_tolerance;
        }
    }
    if (s->alpha) {
        scalars[ALPHA_WORK] = alpha_work(m, st, w, b, age, wf);
        /* commit the laws' state and forces at the step end, not at the alpha point */
        at_end_point(m, s, w);
        evaluate(m, s, st, w, b, ag_new, c1, wf, 0);
    }
    return 1;
}
