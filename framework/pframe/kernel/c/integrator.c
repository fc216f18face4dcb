/* The implicit integrator: everything a scheme is, in one place.
 *
 * An implicit (sub-)step of length h advances the committed state (U, V, A) at its start
 * through the integrator's stages (pframe/integrators/tableau.py). Stage s ends at t + c_s h
 * with the state (u, v, a), a its unknown, and imposes equilibrium at its evaluation point,
 *        M ae + C ve + F(ue) = -M ag_e,
 * each of u, v, ue, ve, ae a linear combination of the points before it (the step start, the
 * ends of the earlier stages) and of its own a. With the slopes d ue/da = wf / c0,
 * d ve/da = wf c1 / c0 and d ae/da = wm (c0 = 1 / (c_u h^2), c_u the own coefficient of u),
 * Newton's effective stiffness is c0 wm M + c1 wf C + wf K_t (assembly.c, factor), and a
 * solve's solution x, the stage end's displacement increment, gives a += c0 x. The stage loop
 * (newton.c, solve_step) is the one implicit step of every path: whole steps (loop.c), the
 * sub-steps of a failed step (implicit.c) and located events (events.c). The step ends at the
 * last stage.
 *
 * A scheme (Settings.scheme) is how a stage's relations are computed:
 *
 * - TABLEAU: any stages, from the rows of Settings.tableau (STAGE_WIDTH numbers a stage: where
 *   it ends and is evaluated, its effective-stiffness class, then the coefficients
 *   [relation][point][value] of u, h v and h^2 a, a relation of order p divided by h^p).
 * - ALPHA_FAMILY and WILSON_THETA, the fast paths of one Newmark stage, written with gamma
 *   and beta (they give the same steps as their tableaux to round-off, tests/test_integrators.py;
 *   these are the bits pframe has always given):
 *   end relations u = U + h V + h^2 (1/2 - beta) A + beta h^2 a, v = V + h (1 - gamma) A +
 *   gamma h a, and c0 = 1 / (beta h^2);
 *   - ALPHA_FAMILY (Newmark, HHT, Chung-Hulbert generalised-alpha): x_e = (1 - alpha) x(n+1)
 *     + alpha x(n) with alpha_f for u, v and the ground, alpha_m for a; wf = 1 - alpha_f,
 *     wm = 1 - alpha_m, c1 = gamma / (beta h).
 *   - WILSON_THETA (Wilson, Farhoomand & Bathe 1973): equilibrium at t + theta h of the
 *     motion whose acceleration varies linearly over the extended step theta h (Newmark's
 *     relations over theta h, beta = 1/6 and gamma = 1/2 for Wilson's linear acceleration),
 *     the ground motion extrapolated linearly to t + theta h; the end state follows by the
 *     same relations over h from a = A + (a_theta - A) / theta. So
 *         ae = (1 - theta) A + theta a   (alpha_m = 1 - theta),
 *         ue = U + theta h V + theta^2 h^2 (1/2 - beta theta) A + beta theta^3 h^2 a,
 *         ve = V + theta h (1 - gamma theta) A + gamma theta^2 h a,
 *     wf = theta^3, wm = theta, c1 = gamma / (beta theta h). theta = 1 is Newmark's method.
 *
 * The energy form: the kinetic energy (1/2) v M v + kinetic_weight h^2 (1/2) a M a and the
 * work of the forces at each evaluation point, with which the step's energy balance closes
 * exactly (energy.c). A new integrator is a tableau (pframe.integrators): nothing here changes.
 */

/* the numbers of one stage's row of Settings.tableau */
#define STAGE_WIDTH (STAGE_HEAD + RELATIONS * STAGE_POINTS * VALUE_SLOTS)

/* A step's weights: see the file's head. */
typedef struct {
    double h;
    double c0;  /* da per unit end displacement (1 / (beta h^2)); a += c0 x after a solve */
    double c1;  /* the damping weight: d ve/da = wf c1 / c0 */
    double inv_c0_mmin; /* 1 / (c0 wm min m): Newton's bound on an increment per residual */
    double wm;  /* d ae/da */
    double wf;  /* d ue/da = wf / c0: the stiffness weight of the effective stiffness */
    double u_A, u_a; /* the fast paths: u = U + (h V + u_A A + u_a a) */
    double v_A, v_a; /* v = V + v_A A + v_a a */
    int64_t stage;   /* the stage (0 ... stages - 1) */
    double at;       /* its evaluation point, a fraction of the step (TABLEAU) */
    double stiffness; /* its effective-stiffness class: a factorisation serves one */
    /* TABLEAU: the coefficients scaled by the powers of h, and the points' values they weigh
     * (the step start, the earlier stages' ends, the stage's own a) */
    double coef[RELATIONS][STAGE_POINTS][VALUE_SLOTS];
    const double *point[STAGE_POINTS][VALUE_SLOTS];
} Weights;

/* The weights of a step of length h; 0 (and the work's ZERO_DIVISION flag set) when one divides
 * by zero (Python raised ZeroDivisionError there; the driver still does). */
static PFRAME_INLINE int step_weights(const Settings *s, Work *w, double h, Weights *c)
{
    Loops *kept = (Loops *)w->loops; /* the divisions of the last step length */
    const double bh2 = s->beta * h * h;
    c->wm = 1.0 - s->alpha_m;
    if (h != kept->weights_h) {
        if (bh2 == 0.0 || s->beta * h == 0.0 || s->beta == 0.0) {
            w->scalars[ZERO_DIVISION] = 1.0;
            return 0;
        }
        kept->c0 = 1.0 / bh2;
        kept->c1 = s->gamma / (s->beta * h);
        if (s->scheme == WILSON_THETA)
            kept->c1 = kept->c1 / s->theta;
        kept->inv_c0_mmin = 1.0 / (kept->c0 * c->wm * w->scalars[MASS_MIN]);
        kept->weights_h = h;
    }
    c->h = h;
    c->c0 = kept->c0;
    c->c1 = kept->c1;
    c->inv_c0_mmin = kept->inv_c0_mmin;
    c->wf = s->scheme == WILSON_THETA ? s->theta * s->theta * s->theta : 1.0 - s->alpha_f;
    c->u_A = 0.5 * h * h - bh2;
    c->u_a = bh2;
    c->v_A = h * (1.0 - s->gamma);
    c->v_a = h * s->gamma;
    c->stage = 0;
    c->stiffness = 0.0;
    return 1;
}

/* Settings.tableau's number of stage `stage`, column `column` (StageColumn) */
static double stage_column(const Settings *s, int64_t stage, int64_t column)
{
    return s->tableau[stage * STAGE_WIDTH + column];
}

/* Settings.tableau's coefficient of stage `stage`: relation r, point j, value q (unscaled) */
static double tableau_entry(const Settings *s, int64_t stage, int64_t r, int64_t j, int64_t q)
{
    return s->tableau[stage * STAGE_WIDTH + STAGE_HEAD + (r * STAGE_POINTS + j) * VALUE_SLOTS + q];
}

/* The weights of TABLEAU's stage `stage` of a step of length h, and the points its
 * relations weigh (member b's committed state, the stored ends of the earlier stages, w->a);
 * 0 (and the work's ZERO_DIVISION flag set) when one divides by zero. */
static int tableau_weights(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                           double h, int64_t stage, Weights *c)
{
    /* the power of h each relation is divided by, in Relation's order
     * (pframe.integrators.tableau.RELATIONS; tests/test_integrators.py holds the two together) */
    static const int order[RELATIONS] = {0, 1, 0, 1, 2};
    const int64_t n = m->dofs;
    double power[5], u_own, ue_own;
    int64_t r, j, q;
    u_own = tableau_entry(s, stage, U_END, stage + 1, VALUE_A);
    ue_own = tableau_entry(s, stage, U_EVAL, stage + 1, VALUE_A);
    if (u_own * h * h == 0.0 || ue_own * h == 0.0) {
        w->scalars[ZERO_DIVISION] = 1.0;
        return 0;
    }
    c->h = h;
    c->c0 = 1.0 / (u_own * h * h);
    c->wf = ue_own / u_own;
    c->c1 = tableau_entry(s, stage, V_EVAL, stage + 1, VALUE_A) / (ue_own * h);
    c->wm = tableau_entry(s, stage, A_EVAL, stage + 1, VALUE_A);
    c->inv_c0_mmin = 1.0 / (c->c0 * c->wm * w->scalars[MASS_MIN]);
    c->stage = stage;
    c->at = stage_column(s, stage, STAGE_AT);
    c->stiffness = stage_column(s, stage, STAGE_STIFFNESS);
    power[0] = 1.0 / (h * h);
    power[1] = 1.0 / h;
    power[2] = 1.0;
    power[3] = h;
    power[4] = h * h;
    for (r = 0; r < RELATIONS; r++)
        for (j = 0; j < STAGE_POINTS; j++)
            for (q = 0; q < VALUE_SLOTS; q++)
                c->coef[r][j][q] = j <= stage + 1
                    ? tableau_entry(s, stage, r, j, q) * power[q - order[r] + 2] : 0.0;
    for (j = 0; j < STAGE_POINTS; j++)
        for (q = 0; q < VALUE_SLOTS; q++)
            c->point[j][q] = NULL;
    c->point[0][VALUE_U] = st->U + b * n;
    c->point[0][VALUE_V] = st->V + b * n;
    c->point[0][VALUE_A] = st->A + b * n;
    for (j = 1; j <= stage; j++)
        for (q = 0; q < VALUE_SLOTS; q++)
            c->point[j][q] = w->stage_values + ((j - 1) * VALUE_SLOTS + q) * n;
    c->point[stage + 1][VALUE_A] = w->a;
    return 1;
}

/* The weights of stage `stage` of a step of length h (a fast path's, or the tableau's, with
 * the points its relations weigh); 0 (and the work's ZERO_DIVISION flag set) when one divides
 * by zero. Inlined: a fast path's step takes no call for them. */
static PFRAME_INLINE int stage_weights(const Model *m, const Settings *s, State *st, Work *w,
                                       int64_t b, double h, int64_t stage, Weights *c)
{
    if (s->scheme != TABLEAU)
        return step_weights(s, w, h, c);
    return tableau_weights(m, s, st, w, b, h, stage, c);
}

/* x = relation r of the stage: its coefficients times the points' values (zero terms left
 * out: a stage's own u and v are not among them). */
static void combine(int64_t n, const Weights *c, int64_t r, double *x)
{
    int first = 1;
    int64_t i, j, q;
    for (j = 0; j <= c->stage + 1; j++) {
        for (q = 0; q < VALUE_SLOTS; q++) {
            const double k = c->coef[r][j][q];
            const double *value = c->point[j][q];
            if (k == 0.0)
                continue;
            if (first) {
                for (i = 0; i < n; i++)
                    x[i] = k * value[i];
            } else {
                for (i = 0; i < n; i++)
                    x[i] += k * value[i];
            }
            first = 0;
        }
    }
    if (first)
        for (i = 0; i < n; i++)
            x[i] = 0.0;
}

/* The predictor: constant acceleration, a = A. A storey that keeps yielding or a contact that
 * stays closed is then met on its current branch with the tangent of the direction it moves
 * in, and one solve ends the step (u = U would evaluate every law at its committed point,
 * where a yielding storey reports its elastic slope). A linear scene's single solve is exact
 * from any predictor. */
static void predict(int64_t n, const double *A, double *a)
{
    int64_t i;
    for (i = 0; i < n; i++)
        a[i] = A[i];
}

/* u and v at the stage's end from the points before it (for the fast paths the step start)
 * and its acceleration a. The unknown iterated is a, from which u and v follow forward: iterating on u and taking a = c0 (u - U) - ... would
 * lose every bit of a in a short (sub-)step (u - U cancels to eps |u| and c0 ~ 1/h^2 amplifies
 * it: a sub-step of 1e-12 s that an event ends gave accelerations of 1e5 m/s^2 from
 * round-off, which the next step turned into kinetic energy). */
static void end_point(const Settings *s, int64_t n, const Weights *c, const double *U,
                      const double *V, const double *A, const double *a, double *u, double *v)
{
    const double h = c->h;
    int64_t i;
    if (s->scheme == TABLEAU) {
        combine(n, c, U_END, u);
        combine(n, c, V_END, v);
        return;
    }
    for (i = 0; i < n; i++) {
        u[i] = U[i] + (h * V[i] + c->u_A * A[i] + c->u_a * a[i]);
        v[i] = V[i] + c->v_A * A[i] + c->v_a * a[i];
    }
}

/* A fast path's end_point without s->alpha, where the stage is evaluated (w->ue, ve, ae are
 * w->u, v, a; the ground's accelerations are ag_new's), and the DOFs' part of the residual
 * there (evaluate's, assembly.c) in the same pass: the same numbers as end_point, then
 * evaluate's loop over the DOFs, without a second pass over them. */
static void end_point_residual(const Model *m, int64_t b, const Weights *c, const double *U,
                               const double *V, const double *A, Work *w,
                               const double *ag_new)
{
    const int64_t n = m->dofs;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *a = w->a, h = c->h;
    double *u = w->u, *v = w->v, *R = w->R;
    int64_t i;
    if (((const Loops *)w->loops)->one_channel) {
        const double g = ag_new[0];
        for (i = 0; i < n; i++) {
            u[i] = U[i] + (h * V[i] + c->u_A * A[i] + c->u_a * a[i]);
            v[i] = V[i] + c->v_A * A[i] + c->v_a * a[i];
            R[i] = dof_residual(mass[i], damping[i], g, a[i], v[i]);
        }
    } else {
        for (i = 0; i < n; i++) {
            u[i] = U[i] + (h * V[i] + c->u_A * A[i] + c->u_a * a[i]);
            v[i] = V[i] + c->v_A * A[i] + c->v_a * a[i];
            R[i] = dof_residual(mass[i], damping[i], dof_ground(m, i, ag_new), a[i], v[i]);
        }
    }
    if (m->modal_blocks)
        modal_add(m, b, v, -1.0, R);
}

/* Move the evaluation point (w->ue, ve, ae) to where the stage imposes equilibrium, from the
 * points before it and the stage's end in w->u, v, a; return the ground accelerations there
 * (linear in the step's samples, extrapolated past its end: w->age, or ag_new itself). Without
 * s->alpha (every stage evaluated at its end) the evaluation arrays are the end arrays
 * themselves. */
static const double *evaluation_point(const Model *m, const Settings *s, State *st, Work *w,
                                      const Weights *c, int64_t b, const double *ag_old,
                                      const double *ag_new)
{
    const int64_t n = m->dofs;
    const double *U, *V, *A;
    int64_t i;
    if (s->scheme == TABLEAU) {
        if (s->alpha) {
            combine(n, c, U_EVAL, w->ue);
            combine(n, c, V_EVAL, w->ve);
            combine(n, c, A_EVAL, w->ae);
        }
        ground_mix(m, w->age, 1.0 - c->at, ag_old, c->at, ag_new);
        return w->age;
    }
    if (!s->alpha)
        return ag_new;
    U = st->U + b * n;
    V = st->V + b * n;
    A = st->A + b * n;
    if (s->scheme == WILSON_THETA) {
        const double th = s->theta, h = c->h;
        const double e_V = th * h, e_A = th * th * h * h * (0.5 - s->beta * th);
        const double e_a = s->beta * th * th * th * h * h;
        const double f_A = th * h * (1.0 - s->gamma * th), f_a = s->gamma * th * th * h;
        for (i = 0; i < n; i++) {
            w->ue[i] = U[i] + (e_V * V[i] + e_A * A[i] + e_a * w->a[i]);
            w->ve[i] = V[i] + f_A * A[i] + f_a * w->a[i];
            w->ae[i] = c->wm * w->a[i] + s->alpha_m * A[i];
        }
        ground_mix(m, w->age, th, ag_new, 1.0 - th, ag_old);
        return w->age;
    }
    for (i = 0; i < n; i++) {
        w->ue[i] = c->wf * w->u[i] + s->alpha_f * U[i];
        w->ve[i] = c->wf * w->v[i] + s->alpha_f * V[i];
        w->ae[i] = c->wm * w->a[i] + s->alpha_m * A[i];
    }
    ground_mix(m, w->age, c->wf, ag_new, s->alpha_f, ag_old);
    return w->age;
}

/* Move the evaluation point to the stage's end (a no-op without s->alpha). */
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

/* G_e . (u - U): the work over the stage of the non-inertial forces (damping, storeys,
 * contacts, ground) as evaluated at its evaluation point, where its equilibrium holds
 * (energy.c counts the integrator's dissipation with it), from the point U (with element
 * deformations drift_c and pen_c) where the stage starts: the step start, or the previous
 * stage's end. The element deformation increments are those of the stage end (the evaluation
 * point is not on the straight line from U to u for every scheme). Called with the forces of
 * the evaluation point in w and the stage's end in w->u. */
static double evaluation_work(const Model *m, Work *w, int64_t b, const double *age,
                              const double *start_ground, const double *end_ground,
                              const double *U, const double *drift_c, const double *pen_c)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *u = w->u, *ve = w->ve;
    const double *gap = m->gap + b * nc;
    double work = 0.0;
    int64_t i, e;
    for (i = 0; i < n; i++)
        work += (damping[i] * ve[i] + mass[i] * dof_ground(m, i, age)) * (u[i] - U[i]);
    if (m->modal_blocks)
        work += modal_work(m, b, ve, ve, 0.0, u, U);
    /* the elements' work on the DOFs' increments: their deformation's change less the ground
     * displacements' (the supports' work is the input's, energy.c) */
    for (e = 0; e < ns; e++) {
        double d = spring_deformation(m, b, e, u, NULL) - drift_c[e];
        if (m->story_ground_terms)
            d += ground_sum(m->story_ground_start, m->story_ground_channel,
                            m->story_ground_coef + b * m->story_ground_terms, e,
                            ground_block(m, start_ground, 1));
        work += (w->story_force[e] + w->story_damping_force[e]) * d;
    }
    for (e = 0; e < nc; e++) {
        double d = (contact_closing(m, b, e, u, NULL) - gap[e]) - pen_c[e];
        if (m->contact_ground_terms)
            d += ground_sum(m->contact_ground_start, m->contact_ground_channel,
                            m->contact_ground_coef + b * m->contact_ground_terms, e,
                            ground_block(m, start_ground, 1));
        work += w->contact_force[e] * d;
    }
    return work;
}

/* M ae . (u - U): the work over the stage of the inertia at its evaluation point, from U
 * where it starts (the generic stage loop's energy form, energy.c). */
static double inertial_work(const Model *m, Work *w, int64_t b, const double *U)
{
    const int64_t n = m->dofs;
    const double *mass = m->mass + b * n;
    double work = 0.0;
    int64_t i;
    for (i = 0; i < n; i++)
        work += mass[i] * w->ae[i] * (w->u[i] - U[i]);
    return work;
}

/* kinetic_weight h^2 (Newmark's (beta - 1/4) h^2): the weight of (1/2) a M a in the modified
 * kinetic energy */
static double kinetic_shadow(const Settings *s, double h)
{
    return s->kinetic_weight * h * h;
}

/* The fast paths: the inertial part of the step's algorithmic dissipation (energy.c), from the
 * increments d_aMa = [a M a / 2], v_Mda = v_mid M [a] and du_Mda = du M [a]:
 *     (1/4 - gamma/2) h^2 [a M a / 2] - (gamma - 1/2) h v_mid M [a] + (1/2 - alpha_m) du M [a]. */
static double inertial_dissipation(const Settings *s, double h, double d_aMa, double v_Mda,
                                   double du_Mda)
{
    return ((0.25 - 0.5 * s->gamma) * h * h * d_aMa - (s->gamma - 0.5) * h * v_Mda
            + (0.5 - s->alpha_m) * du_Mda);
}
