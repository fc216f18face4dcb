/* Newton iterations of one implicit (sub-)step: the integrator's stages in turn.
 *
 * From the committed state (U, V, A) at the step start, each stage finds the acceleration a
 * at its end such that equilibrium holds at its evaluation point,
 *
 *     M ae + C ve + F(ue) = -M a_g(t_e),
 *
 * with the scheme's relations (integrator.c: the end relations, the evaluation point and the
 * effective-stiffness weights). solve_step runs the stages: it is the implicit step of every
 * path (loop.c, implicit.c, events.c), so that no path steps with another integrator than
 * the scene's. A linear scene takes one solve a stage with a factor made once per effective
 * stiffness. A nonlinear scene starts from a predictor and refactors the effective stiffness
 * only when an element tangent, the step length or the stage's stiffness class changed.
 */

/* Factor the constant effective stiffness of a linear scene (initial tangents) for stage
 * `stage`. */
static int factor_linear(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                         int64_t k, double h, int64_t stage)
{
    Weights c;
    const double *k0 = m->story_k0 + b * m->stories, *beta = m->story_beta + b * m->stories;
    int64_t e;
    if (!stage_weights(m, s, st, w, b, h, stage, &c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    for (e = 0; e < m->stories; e++) {
        const double kg = m->story_kg[b * m->stories + e]; /* P-delta, P / h */
        w->story_kk[e] = kg == 0.0 ? k0[e] * (1.0 + c.c1 * beta[e]) * c.wf
                                   : ((k0[e] - kg) + c.c1 * beta[e] * k0[e]) * c.wf;
    }
    w->scalars[STIFFNESS_FACTORED] = c.stiffness;
    return factor(m, s, st, w, b, k, c.c0, c.c1, c.wm, c.wf);
}

/* Iterate stage `stage` of a step of length h to equilibrium (ground acceleration ag_old at
 * the step start, ag_new at its end).
 *
 * Leaves u, v, a at the stage end and the element forces and law states evaluated there, and
 * adds the stage's works at its evaluation point to the work scalars (energy.c); returns 0
 * (after recording why in st->status) if it failed. */
static int solve_stage(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                       int64_t k, double h, int64_t stage, const double *ag_old,
                       const double *ag_new)
{
    const int64_t n = m->dofs;
    const double *U = st->U + b * n, *V = st->V + b * n, *A = st->A + b * n;
    double *u = w->u, *v = w->v, *a = w->a, *R = w->R, *scalars = w->scalars;
    int64_t *counters = st->counters + b * COUNTER_SLOTS;
    Weights c;
    const double *age = ag_new;
    double norm_u = 0.0, norm_r;
    int converged = 0;
    int64_t i, it;
    if (!stage_weights(m, s, st, w, b, h, stage, &c))
        return fail(st, b, NOT_FINITE, k, NODE, 0);
    if (s->linear && c.stiffness != scalars[STIFFNESS_FACTORED]
        && !factor_linear(m, s, st, w, b, k, h, stage))
        return 0;
    if (stage == 0) /* a later stage starts from the acceleration of the one before */
        predict(n, A, a);
    for (it = 0; it < s->max_iterations + 1; it++) {
        int stale;
        if (s->scheme != TABLEAU && !s->alpha) { /* evaluated at the end: one pass for both */
            end_point_residual(m, b, &c, U, V, A, w, ag_new);
            age = ag_new;
            stale = evaluate_elements(m, s, st, w, b, age, c.c1, c.wf, !s->linear);
        } else {
            end_point(s, n, &c, U, V, A, a, u, v);
            age = evaluation_point(m, s, st, w, &c, b, ag_old, ag_new);
            stale = evaluate(m, s, st, w, b, age, c.c1, c.wf, !s->linear);
        }
        if (stale)
            scalars[STALE] = 1.0;
        if (!check_finite_norm(m, st, w, b, k, &norm_r))
            return 0;
        if (!s->linear && it > 0 && !converged) {
            /* The next increment x = K^-1 R is bounded by |R| / (c0 wm min m) while the
             * tangents are not negative. When that bound is a thousandth of the tolerance the
             * correction is negligible (a step whose laws stayed on one branch: R is
             * round-off), so skip it; otherwise iterate, so that results do not depend on the
             * tolerance. */
            converged = (sqrt(norm_r) * c.inv_c0_mmin
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
        /* Refactor only when a tangent, the step or the stage's stiffness changed: a storey
         * that stays elastic or keeps yielding and an open contact keep theirs, so most steps
         * reuse the factor (bit for bit what refactoring would give). */
        if (!s->linear
            && (s->always_refactor || scalars[STALE] != 0.0 || h != scalars[H_FACTORED]
                || c.stiffness != scalars[STIFFNESS_FACTORED])) {
            scalars[STALE] = 0.0;
            scalars[H_FACTORED] = h;
            scalars[STIFFNESS_FACTORED] = c.stiffness;
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
    if (s->scheme == TABLEAU || s->alpha) {
        const int later = stage > 0;
        const double *from = later ? w->stage_values + (stage - 1) * VALUE_SLOTS * n : U;
        /* the ground at the stage's end: the step's end, or a stage of a tableau evaluated
         * at its end */
        scalars[ALPHA_WORK] += evaluation_work(
            m, w, b, age, later ? w->ag_stage : ag_old, s->scheme == TABLEAU ? age : ag_new,
            from,
            later ? w->stage_drift : st->drift + b * m->stories,
            later ? w->stage_penetration : st->penetration + b * m->contacts);
        if (s->scheme == TABLEAU)
            scalars[INERTIAL_WORK] += inertial_work(m, w, b, from);
    }
    if (s->alpha) {
        /* the laws' state and forces at the stage end, not at the evaluation point */
        at_end_point(m, s, w);
        evaluate(m, s, st, w, b, ag_new, c.c1, c.wf, 0);
    }
    return 1;
}

/* The end of stage `stage` becomes a point of the stages after it, and their laws' start. */
static void keep_stage(const Model *m, State *st, Work *w, int64_t b, int64_t stage)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const int64_t S = ns * m->story_states, T = nc * m->contact_states;
    double *kept = w->stage_values + stage * VALUE_SLOTS * n;
    int64_t i;
    for (i = 0; i < n; i++) {
        kept[VALUE_U * n + i] = w->u[i];
        kept[VALUE_V * n + i] = w->v[i];
        kept[VALUE_A * n + i] = w->a[i];
    }
    for (i = 0; i < ns; i++)
        w->stage_drift[i] = w->drift[i];
    for (i = 0; i < nc; i++)
        w->stage_penetration[i] = w->penetration[i];
    for (i = 0; i < S; i++)
        w->story_stage[i] = st->story_trial[b * S + i];
    for (i = 0; i < T; i++)
        w->contact_stage[i] = st->contact_trial[b * T + i];
    for (i = 0; i < m->ground_series; i++) /* a tableau's stage ends at its evaluation */
        w->ag_stage[i] = w->age[i];
    w->scalars[LAWS_FROM_STAGE] = 1.0;
}

/* One implicit step of length h from the committed state of member b: its stages in turn.
 *
 * Leaves u, v, a at the step end and the element forces and law states evaluated there (the
 * committed state untouched); returns 0 (after recording why in st->status) if a stage
 * failed. */
static int solve_step(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                      int64_t k, double h, const double *ag_old, const double *ag_new)
{
    int64_t stage;
    int ok = 1;
    w->scalars[ALPHA_WORK] = 0.0;
    w->scalars[INERTIAL_WORK] = 0.0;
    for (stage = 0; stage < s->stages && ok; stage++) {
        ok = solve_stage(m, s, st, w, b, k, h, stage, ag_old, ag_new);
        if (ok && stage + 1 < s->stages)
            keep_stage(m, st, w, b, stage);
    }
    w->scalars[LAWS_FROM_STAGE] = 0.0;
    return ok;
}
