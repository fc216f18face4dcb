/* The implicit integrator: everything a scheme is, in one place.
 *
 * An implicit (sub-)step of length h finds the acceleration a at its end from the committed
 * state (U, V, A) at its start. A scheme is three things, all of them here:
 *
 * 1. Its end relations, Newmark's with gamma and beta:
 *        u = U + h V + h^2 (1/2 - beta) A + beta h^2 a,   v = V + h (1 - gamma) A + gamma h a.
 * 2. Its evaluation point, where equilibrium is imposed,
 *        M ae + C ve + F(ue) = -M ag_e,
 *    an affine function of a with slopes d ue/da = wf / c0, d ve/da = wf c1 / c0 and
 *    d ae/da = wm (c0 = 1 / (beta h^2)). Newton's effective stiffness is then
 *    c0 wm M + c1 wf C + wf K_t (assembly.c, factor), and a solve's solution x gives a += c0 x.
 * 3. Its energy form: the modified kinetic energy (1/2) v M v + (beta - 1/4) (h^2 / 2) a M a
 *    and the work of the forces at the evaluation point, with which the step's energy balance
 *    closes exactly (energy.c; the identity depends only on the end relations and on ae being
 *    alpha_m A + (1 - alpha_m) a, so both schemes share it).
 *
 * The schemes (Settings.scheme):
 *
 * - ALPHA_FAMILY (Newmark, HHT, Chung-Hulbert generalised-alpha): x_e = (1 - alpha) x(n+1) +
 *   alpha x(n) with alpha_f for u, v and the ground, alpha_m for a; wf = 1 - alpha_f,
 *   wm = 1 - alpha_m, c1 = gamma / (beta h).
 * - WILSON_THETA (Wilson, Farhoomand & Bathe 1973): equilibrium at t + theta h of the motion
 *   whose acceleration varies linearly over the extended step theta h (Newmark's relations over
 *   theta h, beta = 1/6 and gamma = 1/2 for Wilson's linear acceleration), the ground motion
 *   extrapolated linearly to t + theta h; the end state follows by the same relations over h
 *   from a = A + (a_theta - A) / theta. So
 *       ae = (1 - theta) A + theta a   (alpha_m = 1 - theta),
 *       ue = U + theta h V + theta^2 h^2 (1/2 - beta theta) A + beta theta^3 h^2 a,
 *       ve = V + theta h (1 - gamma theta) A + gamma theta^2 h a,
 *   wf = theta^3, wm = theta, c1 = gamma / (beta theta h). theta = 1 is Newmark's method.
 *
 * An integrator outside these two is a new scheme id and a case in each function below (the
 * predictor, the end relations, the evaluation point and the weights), plus its Python side
 * (pframe.integrators: parameters, Coefficients, amplification matrix).
 */

/* A step's weights: see the file's head. */
typedef struct {
    double h;
    double c0;  /* 1 / (beta h^2): da per unit end displacement; a += c0 x after a solve */
    double c1;  /* the damping weight: d ve/da = wf c1 / c0 */
    double wm;  /* d ae/da */
    double wf;  /* d ue/da = wf / c0: the stiffness weight of the effective stiffness */
    double u_A, u_a; /* u = U + (h V + u_A A + u_a a) */
    double v_A, v_a; /* v = V + v_A A + v_a a */
} Weights;

/* The weights of a step of length h; 0 (and the work's ZERO_DIVISION flag set) when one divides
 * by zero (Python raised ZeroDivisionError there; the driver still does). */
static int step_weights(const Settings *s, Work *w, double h, Weights *c)
{
    double bh2;
    if (s->beta * h * h == 0.0 || s->beta * h == 0.0 || s->beta == 0.0) {
        w->scalars[ZERO_DIVISION] = 1.0;
        return 0;
    }
    bh2 = s->beta * h * h;
    c->h = h;
    c->c0 = 1.0 / bh2;
    c->c1 = s->gamma / (s->beta * h);
    c->wm = 1.0 - s->alpha_m;
    c->wf = 1.0 - s->alpha_f;
    if (s->scheme == WILSON_THETA) {
        c->c1 = c->c1 / s->theta;
        c->wf = s->theta * s->theta * s->theta;
    }
    c->u_A = 0.5 * h * h - bh2;
    c->u_a = bh2;
    c->v_A = h * (1.0 - s->gamma);
    c->v_a = h * s->gamma;
    return 1;
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

/* u and v at the step end from its start and the end acceleration a. The unknown iterated is
 * a, from which u and v follow forward: iterating on u and taking a = c0 (u - U) - ... would
 * lose every bit of a in a short (sub-)step (u - U cancels to eps |u| and c0 ~ 1/h^2 amplifies
 * it: a sub-step of 1e-12 s that an event ends gave accelerations of 1e5 m/s^2 from
 * round-off, which the next step turned into kinetic energy). */
static void end_point(int64_t n, const Weights *c, const double *U, const double *V,
                      const double *A, const double *a, double *u, double *v)
{
    const double h = c->h;
    int64_t i;
    for (i = 0; i < n; i++) {
        u[i] = U[i] + (h * V[i] + c->u_A * A[i] + c->u_a * a[i]);
        v[i] = V[i] + c->v_A * A[i] + c->v_a * a[i];
    }
}

/* Move the evaluation point (w->ue, ve, ae) to where the scheme imposes equilibrium, from the
 * end state in w->u, v, a; return the ground acceleration there. For Newmark (s->alpha off)
 * the evaluation arrays are the step-end arrays themselves. */
static double evaluation_point(const Model *m, const Settings *s, State *st, Work *w,
                               const Weights *c, int64_t b, double ag_old, double ag_new)
{
    const int64_t n = m->dofs;
    const double *U, *V, *A;
    int64_t i;
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
        return th * ag_new + (1.0 - th) * ag_old;
    }
    for (i = 0; i < n; i++) {
        w->ue[i] = c->wf * w->u[i] + s->alpha_f * U[i];
        w->ve[i] = c->wf * w->v[i] + s->alpha_f * V[i];
        w->ae[i] = c->wm * w->a[i] + s->alpha_m * A[i];
    }
    return c->wf * ag_new + s->alpha_f * ag_old;
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

/* G_e . (u(n+1) - u(n)): the work over the whole step of the non-inertial forces (damping,
 * storeys, contacts, ground) as evaluated at the evaluation point, where the step's
 * equilibrium holds (energy.c counts the integrator's dissipation with it). The element
 * deformation increments are those of the step end (the evaluation point is not on the
 * straight line from U to u for every scheme). Called with the forces of the evaluation point
 * in w and the end state in w->u. */
static double evaluation_work(const Model *m, State *st, Work *w, int64_t b, double age)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *U = st->U + b * n, *u = w->u, *ve = w->ve;
    const double *drift_c = st->drift + b * ns, *pen_c = st->penetration + b * nc;
    const double *gap = m->gap + b * nc;
    double work = 0.0;
    int64_t i, e;
    for (i = 0; i < n; i++)
        work += (damping[i] * ve[i] + m->ground_influence[i] * mass[i] * age) * (u[i] - U[i]);
    if (m->modal_blocks)
        work += modal_work(m, b, ve, ve, 0.0, u, U);
    for (e = 0; e < ns; e++) {
        const int64_t lo = m->story_dofs[2 * e], up = m->story_dofs[2 * e + 1];
        const int64_t th = m->story_theta[e];
        double d = u[up] - dof_value(u, lo);
        if (th >= 0)
            d -= m->story_height[b * ns + e] * u[th];
        work += (w->story_force[e] + w->story_damping_force[e]) * (d - drift_c[e]);
    }
    for (e = 0; e < nc; e++) {
        work += w->contact_force[e]
                * ((contact_side(m, u, b, e, 0) - contact_side(m, u, b, e, 1) - gap[e]) - pen_c[e]);
    }
    return work;
}

/* (beta - 1/4) h^2: the weight of (1/2) a M a in the modified kinetic energy */
static double kinetic_shadow(const Settings *s, double h)
{
    return (s->beta - 0.25) * h * h;
}

/* The inertial part of the step's algorithmic dissipation (energy.c), from the increments
 * d_aMa = [a M a / 2], v_Mda = v_mid M [a] and du_Mda = du M [a]:
 *     (1/4 - gamma/2) h^2 [a M a / 2] - (gamma - 1/2) h v_mid M [a] + (1/2 - alpha_m) du M [a]. */
static double inertial_dissipation(const Settings *s, double h, double d_aMa, double v_Mda,
                                   double du_Mda)
{
    return ((0.25 - 0.5 * s->gamma) * h * h * d_aMa - (s->gamma - 0.5) * h * v_Mda
            + (0.5 - s->alpha_m) * du_Mda);
}
