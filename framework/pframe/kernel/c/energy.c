/* Committing a step: energy increments, impact counts, the state copy, and a runaway check.
 *
 * The work of each force over the step is counted by the trapezoidal rule. With Newmark's
 * relations and equilibrium at t(n+1 - alpha) (forces weighted (1 - alpha_f) at the step end
 * and alpha_f at its start, inertia likewise with alpha_m), the step's works satisfy exactly
 *
 *     W_input = dE_kinetic + W_damping + W_storeys + W_links + W_contacts + D_algorithmic,
 *
 * with the kinetic energy (1/2) v M v + (beta - 1/4) (h^2 / 2) a M a (beta = 1/4: the plain
 * kinetic energy; central difference: beta = 0) and the integrator's own dissipation
 *
 *     D_algorithmic = (1/4 - gamma/2) h^2 [a M a / 2] - (gamma - 1/2) h v_mid M [a]
 *                     + (1/2 - alpha_m) du M [a] + (1/2 - alpha_f) du . [G],
 *
 * where [x] is the increment of x over the step, v_mid the mean velocity, du the displacement
 * increment and G = C v + F(u) + M a_g the non-inertial forces. D_algorithmic vanishes for
 * average acceleration (gamma = 1/2, alpha = 0) and is the numerical damping of HHT,
 * generalised alpha and Newmark with gamma > 1/2. It is counted on its own, so the balance
 * closes to round-off for every integrator of the family: its error measures the run's
 * arithmetic and the integrator's consistency (a pair that creates energy shows there), while
 * D_algorithmic says how much the integrator damped (pframe.verdict judges both).
 *
 * For a scheme whose evaluation point is not a weighted mean of the step's ends (Wilson-theta,
 * integrator.c) the last two terms are replaced by the work over the step of the forces at the
 * evaluation point, G_e . du, less the trapezoidal works: the identity behind the balance needs
 * only Newmark's end relations and ae = alpha_m A + (1 - alpha_m) a, so it holds there too (the
 * code below takes that form for every scheme off the step end).
 *
 * For the generic stage loop (TABLEAU: any stages, docs/theory.md) the step's stages s, with
 * increments du_s from the previous point and equilibrium M ae_s + G_e,s = 0 at their
 * evaluation points, give the same balance with
 *
 *     D_algorithmic = sum_s (M ae_s . du_s + G_e,s . du_s) - dE_kinetic - (trapezoidal works),
 *
 * the first sum the work of the inertia at the evaluation points (the inertial work) and the
 * second the evaluation work, both counted stage by stage as the stages converge (newton.c).
 * What the balance then leaves is sum_s R_s . du_s: the stages' residuals, Newton's tolerance.
 */

/* The sums of a committed step: the works of its forces (trapezoidal), the pieces of
 * D_algorithmic and the kinetic energies, each summed in the order of its DOFs, then of its
 * elements (the order that gives pframe's bits). */
typedef struct {
    double work_in, work_damp, work_story, work_link, work_contact;
    double du_dG, du_Mda, v_Mda, d_aMa; /* du . [G], du M [a], v_mid M [a], [a M a / 2] */
    double kinetic, raw;                /* modified and plain kinetic energies at the end */
} StepSums;

/* The DOFs' sums in one pass, which also commits U, V and A: the kinetic energies (the
 * modified one's shadow term only when shadowed: shadow is not zero), and with works (k > 0)
 * the works over the step and the pieces of D_algorithmic, [a M a / 2] and v_mid M [a] only
 * with mid (see commit_dofs); one: every DOF loaded by channel 0, whose mean and jump over the
 * step are then taken once. Inlined with the flags constant: one loop without branches for
 * each case. */
static PFRAME_INLINE void dof_sums(const Model *m, State *st, const Work *w, int64_t b,
                                   double shadow, const double *ag_old, const double *ag_new,
                                   int works, int mid, int shadowed, int one, StepSums *x)
{
    const int64_t n = m->dofs;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const int64_t *channel = m->dof_channel;
    double *U = st->U + b * n, *V = st->V + b * n, *A = st->A + b * n;
    const double *u = w->u, *v = w->v, *a = w->a;
    /* the sums in locals, not through x: stores into U, V, A may not change them */
    double kinetic = 0.0, plain = 0.0, work_in = 0.0, work_damp = 0.0, du_dG = 0.0;
    double du_Mda = 0.0, v_Mda = 0.0, d_aMa = 0.0;
    /* channel 0's mean and jump, as the loop below takes them for each DOF */
    const double mean_0 = one ? 0.5 * (ag_old[0] + ag_new[0]) : 0.0;
    const double jump_0 = one ? ag_new[0] - ag_old[0] : 0.0;
    int64_t i;
    for (i = 0; i < n; i++) {
        plain += 0.5 * mass[i] * (v[i] * v[i]);
        if (shadowed)
            kinetic += 0.5 * mass[i] * (v[i] * v[i] + shadow * a[i] * a[i]);
        if (works) {
            const double du = u[i] - U[i];
            const double da = a[i] - A[i];
            const int64_t c = one ? 0 : channel[i]; /* -1: a rotation, not loaded */
            work_damp += 0.5 * damping[i] * (V[i] + v[i]) * du;
            if (one) {
                work_in -= mean_0 * mass[i] * du;
                du_dG += (damping[i] * (v[i] - V[i]) + mass[i] * jump_0) * du;
            } else if (c >= 0) {
                work_in -= 0.5 * (ag_old[c] + ag_new[c]) * mass[i] * du;
                du_dG += (damping[i] * (v[i] - V[i]) + mass[i] * (ag_new[c] - ag_old[c])) * du;
            } else {
                du_dG += damping[i] * (v[i] - V[i]) * du;
            }
            du_Mda += mass[i] * da * du;
            if (mid) {
                v_Mda += 0.5 * (V[i] + v[i]) * mass[i] * da;
                d_aMa += 0.5 * mass[i] * (a[i] * a[i] - A[i] * A[i]);
            }
        }
        U[i] = u[i];
        V[i] = v[i];
        A[i] = a[i];
    }
    /* without the shadow term the modified kinetic energy is the plain one, the same sum */
    x->kinetic = shadowed ? kinetic : plain;
    x->raw = plain;
    x->work_in = work_in;
    x->work_damp = work_damp;
    x->du_dG = du_dG;
    x->du_Mda = du_Mda;
    x->v_Mda = v_Mda;
    x->d_aMa = d_aMa;
}

/* The DOFs' sums (with k > 0 the works over the step) in one pass, which also commits U, V
 * and A. The fast paths' inertial dissipation (integrator.c, inertial_dissipation) weighs
 * [a M a / 2] and v_mid M [a] by (1/4 - gamma/2) h^2 and -(gamma - 1/2) h: with gamma = 1/2
 * (Newmark's average acceleration, the paper's) both weights are zero and the two sums are
 * not taken; the generic stage loop (TABLEAU) counts its inertia's work itself and takes
 * none of the three. */
static void commit_dofs(const Model *m, const Settings *s, State *st, const Work *w, int64_t b,
                        int64_t k, double shadow, const double *ag_old, const double *ag_new,
                        StepSums *x)
{
    const int64_t n = m->dofs;
    const double *u = w->u, *v = w->v;
    const double *U = st->U + b * n, *V = st->V + b * n;
    double modal_damp = 0.0, modal_dG = 0.0;
    if (k > 0 && m->modal_blocks) { /* modal damping: (C (V + v) / 2) du and C [v] du */
        modal_damp = modal_work(m, b, V, v, 1.0, u, U);
        modal_dG = modal_work(m, b, v, V, -1.0, u, U);
    }
    const int works = k > 0, mid = works && s->scheme != TABLEAU && s->gamma != 0.5;
    const int one = ((const Loops *)w->loops)->one_channel;
#define DOF_SUMS(works, mid, shadowed) \
    do { \
        if (one) \
            dof_sums(m, st, w, b, shadow, ag_old, ag_new, works, mid, shadowed, 1, x); \
        else \
            dof_sums(m, st, w, b, shadow, ag_old, ag_new, works, mid, shadowed, 0, x); \
    } while (0)
    if (shadow != 0.0) {
        if (!works)
            DOF_SUMS(0, 0, 1);
        else if (mid)
            DOF_SUMS(1, 1, 1);
        else
            DOF_SUMS(1, 0, 1);
    } else {
        if (!works)
            DOF_SUMS(0, 0, 0);
        else if (mid)
            DOF_SUMS(1, 1, 0);
        else
            DOF_SUMS(1, 0, 0);
    }
#undef DOF_SUMS
    if (k > 0 && m->modal_blocks) {
        x->work_damp += 0.5 * modal_damp;
        x->du_dG += modal_dG;
    }
}

/* The springs e = from .. to - 1 (storeys, or links): their material forces' work over the
 * step (returned), their damping's added to *work_damp and their part of du . [G] to *du_dG,
 * each in the springs' order; their committed deformation and forces become the trial ones. */
static PFRAME_INLINE double spring_works(int64_t from, int64_t to, double *drift_c,
                                         double *force_c, double *damping_c, double *tangent_c,
                                         const Work *w, double *work_damp, double *du_dG)
{
    const double *drift_t = w->drift, *force_t = w->story_force;
    const double *damping_t = w->story_damping_force, *tangent_t = w->story_tangent;
    double work = 0.0, damp = *work_damp, dG = *du_dG;
    int64_t e;
    for (e = from; e < to; e++) {
        const double dd = drift_t[e] - drift_c[e];
        work += 0.5 * (force_c[e] + force_t[e]) * dd;
        damp += 0.5 * (damping_c[e] + damping_t[e]) * dd;
        dG += (force_t[e] - force_c[e] + damping_t[e] - damping_c[e]) * dd;
        drift_c[e] = drift_t[e];
        force_c[e] = force_t[e];
        damping_c[e] = damping_t[e];
        tangent_c[e] = tangent_t[e];
    }
    *work_damp = damp;
    *du_dG = dG;
    return work;
}

/* The storeys' and links' works over the step (k > 0), then the contacts': works and impacts
 * (a contact open at the start and closed at the end); then every element's committed state
 * and force, and its law's. */
static void commit_elements(const Model *m, State *st, const Work *w, int64_t b, int64_t k,
                            StepSums *x)
{
    const int64_t ns = m->stories, nc = m->contacts, storeys = m->stories - m->links;
    double *drift_c = st->drift + b * ns, *force_c = st->story_force + b * ns;
    double *damping_c = st->story_damping_force + b * ns, *tangent_c = st->story_tangent + b * ns;
    const double *drift_t = w->drift, *force_t = w->story_force;
    const double *damping_t = w->story_damping_force, *tangent_t = w->story_tangent;
    double *cforce_c = st->contact_force + b * nc, *pen_c = st->penetration + b * nc;
    int64_t *impacts = st->impacts + b * nc;
    const double *cforce_t = w->contact_force, *pen_t = w->penetration;
    double work_story = 0.0, work_link = 0.0, work_damp = x->work_damp, work_contact = 0.0;
    double du_dG = x->du_dG;
    int64_t e;
    if (k > 0) {
        work_story = spring_works(0, storeys, drift_c, force_c, damping_c, tangent_c, w,
                                  &work_damp, &du_dG);
        /* the links (no Rayleigh damping: a link's dashpot is in its force) */
        work_link = spring_works(storeys, ns, drift_c, force_c, damping_c, tangent_c, w,
                                 &work_damp, &du_dG);
        for (e = 0; e < nc; e++) {
            const double dp = pen_t[e] - pen_c[e];
            work_contact += 0.5 * (cforce_c[e] + cforce_t[e]) * dp;
            du_dG += (cforce_t[e] - cforce_c[e]) * dp;
            if (pen_c[e] <= 0.0 && pen_t[e] > 0.0)
                impacts[e] += 1;
            cforce_c[e] = cforce_t[e];
            pen_c[e] = pen_t[e];
        }
    } else {
        for (e = 0; e < ns; e++) {
            drift_c[e] = drift_t[e];
            force_c[e] = force_t[e];
            damping_c[e] = damping_t[e];
            tangent_c[e] = tangent_t[e];
        }
        for (e = 0; e < nc; e++) {
            cforce_c[e] = cforce_t[e];
            pen_c[e] = pen_t[e];
        }
    }
    x->work_story = work_story;
    x->work_link = work_link;
    x->work_damp = work_damp;
    x->work_contact = work_contact;
    x->du_dG = du_dG;
    {
        const int64_t story_values = ns * m->story_states, contact_values = nc * m->contact_states;
        memcpy(st->story_committed + b * story_values, st->story_trial + b * story_values,
               sizeof(double) * (size_t)story_values);
        memcpy(st->contact_committed + b * contact_values, st->contact_trial + b * contact_values,
               sizeof(double) * (size_t)contact_values);
    }
}

/* The work of the supports' displacements on the elements across them over a sub-step
 * (docs/supports.md): an element's deformation includes the ground displacements' part g_e,
 * on which the supports do f dg_e (input, the trapezoid of the committed and trial forces,
 * damping's included); and what du . [G] must leave out of the force jumps times the
 * deformation's change (its dg_e part is not the DOFs'), taken off *du_dG. */
static double support_work(const Model *m, const State *st, const Work *w, int64_t b,
                           const double *ag_old, const double *ag_new, double *du_dG)
{
    const int64_t ns = m->stories, nc = m->contacts;
    const double *g_old = ground_block(m, ag_old, 1), *g_new = ground_block(m, ag_new, 1);
    const double *gs_coef = m->story_ground_coef + b * m->story_ground_terms;
    const double *gc_coef = m->contact_ground_coef + b * m->contact_ground_terms;
    const double *force_c = st->story_force + b * ns, *force_t = w->story_force;
    const double *damping_c = st->story_damping_force + b * ns;
    const double *damping_t = w->story_damping_force;
    const double *cforce_c = st->contact_force + b * nc, *cforce_t = w->contact_force;
    double work = 0.0;
    int64_t e;
    for (e = 0; m->story_ground_terms && e < ns; e++) {
        const double dg = ground_sum(m->story_ground_start, m->story_ground_channel, gs_coef,
                                     e, g_new)
                          - ground_sum(m->story_ground_start, m->story_ground_channel, gs_coef,
                                       e, g_old);
        work += 0.5 * (force_c[e] + force_t[e] + damping_c[e] + damping_t[e]) * dg;
        *du_dG -= (force_t[e] - force_c[e] + damping_t[e] - damping_c[e]) * dg;
    }
    for (e = 0; m->contact_ground_terms && e < nc; e++) {
        const double dg = ground_sum(m->contact_ground_start, m->contact_ground_channel,
                                     gc_coef, e, g_new)
                          - ground_sum(m->contact_ground_start, m->contact_ground_channel,
                                       gc_coef, e, g_old);
        work += 0.5 * (cforce_c[e] + cforce_t[e]) * dg;
        *du_dG -= (cforce_t[e] - cforce_c[e]) * dg;
    }
    return work;
}

/* Accept the step from t_k - h to t_k whose end state is in w; 0 (after recording why) if the
 * kinetic energy ran away from what the ground motion put in. The state is committed in the
 * same passes that sum the step's works. */
static int commit(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                  int64_t k, double h, const double *ag_old, const double *ag_new)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const double *mass = m->mass + b * n;
    double *U = st->U + b * n, *V = st->V + b * n, *A = st->A + b * n;
    double *energy = st->energy + b * ENERGY_SLOTS;
    StepSums x = {0.0};
    double shadow, budget, t, work_supports = 0.0;
    int64_t i, e;
    shadow = kinetic_shadow(s, h);
    if (k > 0 && shadow != 0.0) {
        /* The modified kinetic energy depends on the step length: after a (sub-)step of
         * another length (events, retries) the start's is re-taken with this one, as at an
         * event's restart (events.c), and the change booked to the integrator's own account
         * (nothing changes when the length is the same: the same numbers give the same sum). */
        double start = 0.0;
        for (i = 0; i < n; i++)
            start += 0.5 * mass[i] * (V[i] * V[i] + shadow * A[i] * A[i]);
        energy[ALGORITHMIC] -= start - energy[KINETIC];
        energy[KINETIC] = start;
    }
    commit_dofs(m, s, st, w, b, k, shadow, ag_old, ag_new, &x);
    if (k > 0 && (m->story_ground_terms || m->contact_ground_terms)) /* before the commit */
        work_supports = support_work(m, st, w, b, ag_old, ag_new, &x.du_dG);
    commit_elements(m, st, w, b, k, &x);
    if (k > 0) {
        double inertial;
        energy[INPUT] += x.work_in;
        energy[DAMPING] += x.work_damp;
        energy[STOREYS] += x.work_story;
        energy[LINKS] += x.work_link;
        if (nc)
            energy[CONTACTS] += x.work_contact;
        x.work_in += work_supports;
        energy[INPUT] += work_supports;
        if (s->scheme == TABLEAU)
            inertial = w->scalars[INERTIAL_WORK] - (x.kinetic - energy[KINETIC]);
        else
            inertial = inertial_dissipation(s, h, x.d_aMa, x.v_Mda, x.du_Mda);
        if (s->alpha || s->scheme == TABLEAU) {
            /* equilibrium holds at the evaluation point, with the forces evaluated there (not
             * the weighted end forces: the two differ where a law is nonlinear) */
            const double trapezoid = x.work_damp + x.work_story + x.work_link + x.work_contact
                                     - x.work_in;
            energy[ALGORITHMIC] += inertial + w->scalars[ALPHA_WORK] - trapezoid;
        } else {
            energy[ALGORITHMIC] += inertial + 0.5 * x.du_dG;
        }
    }
    energy[KINETIC] = x.kinetic;
    if (k == 0)
        energy[KINETIC_0] = x.kinetic;

    /* Divergence: the kinetic energy cannot exceed what came in (initial energy plus the input
     * work, counted in absolute value) but by the integrator's own small excess; ten times
     * that means the numbers are running away (a test on the balance would not do: Newmark
     * with gamma = 1/2 conserves its modified energy even when unstable). */
    if (k == 0) {
        const double *drift_t = w->drift, *force_t = w->story_force;
        const double *cforce_t = w->contact_force, *pen_t = w->penetration;
        double start = x.raw;
        for (e = 0; e < ns; e++)
            start += 0.5 * force_t[e] * drift_t[e];
        for (e = 0; e < nc; e++)
            start += 0.5 * cforce_t[e] * py_max(pen_t[e], 0.0);
        energy[START] = fabs(start);
        return 1;
    }
    energy[INPUT_ABS] += fabs(x.work_in);
    t = 0.0; /* how much velocity the ground's steps may give: h |a_g| summed over channels */
    for (i = 0; i < m->channels; i++)
        t += h * (fabs(ag_old[i]) + fabs(ag_new[i]));
    budget = energy[INPUT_ABS] + energy[START] + t * t * w->scalars[MASS_MIN];
    if (x.raw <= 10.0 * budget)
        return 1;
    {
        int64_t worst = 0;
        for (i = 0; i < n; i++)
            if (fabs(U[i]) > fabs(U[worst]))
                worst = i;
        return fail(st, b, NOT_STABLE, k, NODE, worst);
    }
}
