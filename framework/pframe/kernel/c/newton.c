/* Newton iterations of one implicit (sub-)step.
 *
 * From the committed state (U, V, A) at the step start, find the end acceleration a such that
 * equilibrium holds at the scheme's evaluation point,
 *
 *     M ae + C ve + F(ue) = -M a_g(t_e),
 *
 * with the scheme's relations (integrator.c: the end relations, the evaluation point and the
 * effective-stiffness weights). A linear scene takes one solve with the factor made once
 * before its first step. A nonlinear scene starts from the scheme's predictor and refactors
 * the effective stiffness only when an element tangent or the step length changed.
 */

/* Factor the constant effective stiffness of a linear scene (initial tangents). */
static int factor_linear(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                         int64_t k, double h)
{
    Weights c;
    const double *k0 = m->story_k0 + b * m->stories, *beta = m->story_beta + b * m->stories;
    int64_t e;
    if (!step_weights(s, w, h, &c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    for (e = 0; e < m->stories; e++) {
        const double kg = m->story_kg[b * m->stories + e]; /* P-delta, P / h */
        w->story_kk[e] = kg == 0.0 ? k0[e] * (1.0 + c.c1 * beta[e]) * c.wf
                                   : ((k0[e] - kg) + c.c1 * beta[e] * k0[e]) * c.wf;
    }
    return factor(m, s, st, w, b, k, c.c0, c.c1, c.wm, c.wf);
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
    Weights c;
    double inv_c0_mmin, norm_u = 0.0, age = ag_new;
    int converged = 0;
    int64_t i, it;
    if (!step_weights(s, w, h, &c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    inv_c0_mmin = 1.0 / (c.c0 * c.wm * scalars[MASS_MIN]);
    predict(n, A, a);
    for (it = 0; it < s->max_iterations + 1; it++) {
        end_point(n, &c, U, V, A, a, u, v);
        age = evaluation_point(m, s, st, w, &c, b, ag_old, ag_new);
        if (evaluate(m, s, st, w, b, age, c.c1, c.wf, !s->linear))
            scalars[STALE] = 1.0;
        if (!check_finite(m, st, w, b, k))
            return 0;
        if (!s->linear && it > 0 && !converged) {
            /* The next increment x = K^-1 R is bounded by |R| / (c0 wm min m) while the
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
            if (!factor(m, s, st, w, b, k, c.c0, c.c1, c.wm, c.wf))
                return 0;
        }
        ldl_solve(w->band, n, s->bandwidth, R);
        counters[SOLVES] += 1;
        if (s->linear) {
            for (i = 0; i < n; i++)
                a[i] += c.c0 * R[i];
            converged = 1;
        } else {
            double norm_du = 0.0;
            norm_u = 0.0;
            for (i = 0; i < n; i++) {
                a[i] += c.c0 * R[i];
                norm_du += R[i] * R[i];
                norm_u += (u[i] + R[i]) * (u[i] + R[i]);
            }
            converged = sqrt(norm_du) <= s->tolerance * sqrt(norm_u) + s->absolute_tolerance;
        }
    }
    if (s->alpha) {
        scalars[ALPHA_WORK] = evaluation_work(m, st, w, b, age);
        /* commit the laws' state and forces at the step end, not at the evaluation point */
        at_end_point(m, s, w);
        evaluate(m, s, st, w, b, ag_new, c.c1, c.wf, 0);
    }
    return 1;
}
