/* Residual and tangent of the scene at an evaluation point, over its element groups.
 *
 * The residual is R = P - M (a_g + a) - C_m v - sum of element forces, at the point held in
 * w->ue, w->ve, w->ae (the step end for Newmark, the alpha point for HHT and
 * generalised-alpha). Storeys and contacts are visited in the plan's order, grouped by law;
 * a DOF of -1 is the ground (a storey's base, a wall's side of a contact). Each law group is
 * one loop that calls its law's function directly: a built-in law's group function
 * (spring_group_<id>, contact_group_<id>: the law inlined in it) is found by the law's id
 * once per group, or once per call when every element has one law (prepare_loops); a
 * plug-in law's group calls it through its function pointer. No element goes through a
 * switch on its law (laws.c's material_force and contact_force serve the tests of single
 * laws, pframe_law_force). A scene without contacts has no contact elements, so the contact
 * loop does not run.
 */

/* where a contact held closed is evaluated once its penetration is below it: the smallest
 * penetration a law sees as contact (any law's spring term vanishes there) */
#define HELD_DEPTH 1e-300

/* Record why member b stopped in step k; returns 0 (not ok). */
static int fail(State *st, int64_t b, int64_t code, int64_t k, int64_t kind, int64_t index)
{
    int64_t *status = st->status + b * STATUS_SLOTS;
    status[STATUS_CODE] = code;
    status[STATUS_STEP] = k;
    status[STATUS_KIND] = kind;
    status[STATUS_INDEX] = index;
    return 0;
}

/* kk g g^T into the band over element e's terms, g its first side's coefficients times
 * sign_first and its second side's times -sign_first (a spring: -1, its lower side first; a
 * contact: +1, left first); two terms on one DOF (cannot happen: sides of distinct nodes)
 * add twice their product to its diagonal. */
static void band_sides(double *band, int64_t bw, const int64_t *start, const int64_t *dof,
                       const double *coef, int64_t e, double sign_first, double kk)
{
    const int64_t lo = start[2 * e], mid = start[2 * e + 1], hi = start[2 * e + 2];
    int64_t x, y;
    for (x = lo; x < hi; x++) {
        const double gx = (x < mid ? sign_first : -sign_first) * coef[x];
        for (y = lo; y <= x; y++) {
            const double gy = (y < mid ? sign_first : -sign_first) * coef[y];
            const int64_t high = imax(dof[x], dof[y]), low = imin(dof[x], dof[y]);
            if (x == y)
                band[dof[x] * (bw + 1)] += kk * gx * gx;
            else if (high != low)
                band[high * (bw + 1) + (high - low)] += kk * gx * gy;
            else
                band[high * (bw + 1)] += 2.0 * kk * gx * gy;
        }
    }
}

/* Modal damping (docs/theory.md#damping): each block is a building's dense matrix C over its
 * DOFs (m->modal_dofs from m->modal_start[k]), row-major in that order. */

/* y += scale C x over every block of member b (x and y indexed by DOF). */
static void modal_add(const Model *m, int64_t b, const double *x, double scale, double *y)
{
    const double *C = m->modal_matrix + b * m->modal_width;
    int64_t k, i, j;
    for (k = 0; k < m->modal_blocks; k++) {
        const int64_t *dofs = m->modal_dofs + m->modal_start[k];
        const int64_t size = m->modal_start[k + 1] - m->modal_start[k];
        for (i = 0; i < size; i++) {
            double sum = 0.0;
            for (j = 0; j < size; j++)
                sum += C[i * size + j] * x[dofs[j]];
            y[dofs[i]] += scale * sum;
        }
        C += size * size;
    }
}

/* (p + sq q)^T C (u - U) summed over the blocks of member b: the work of the modal damping
 * forces C p (and C q) over a displacement increment. */
static double modal_work(const Model *m, int64_t b, const double *p, const double *q,
                         double sq, const double *u, const double *U)
{
    const double *C = m->modal_matrix + b * m->modal_width;
    double work = 0.0;
    int64_t k, i, j;
    for (k = 0; k < m->modal_blocks; k++) {
        const int64_t *dofs = m->modal_dofs + m->modal_start[k];
        const int64_t size = m->modal_start[k + 1] - m->modal_start[k];
        for (i = 0; i < size; i++) {
            double sum = 0.0;
            for (j = 0; j < size; j++)
                sum += C[i * size + j] * (p[dofs[j]] + sq * q[dofs[j]]);
            work += sum * (u[dofs[i]] - U[dofs[i]]);
        }
        C += size * size;
    }
    return work;
}

/* What the storey (spring) loop of evaluate reads and writes for member b: prepared once per
 * call (prepare_loops), but for what each evaluation sets (its point, its weights, where the
 * laws start from). */
typedef struct {
    const double *committed_step; /* the laws' state at the step start */
    int64_t *calls;
    int terms, grounded;
    int current; /* every spring's damping on its current tangent, none with P-delta */
    int in_order; /* the evaluation order is the elements' own (order[j] == j) */
    const int64_t *dofs, *order, *modes, *start, *side_dof, *g_start, *g_channel;
    const double *params, *committed, *k0, *beta, *kg, *side_coef, *tangent_c, *ue, *ve;
    const double *g_coef, *g_d, *g_v; /* across supports (docs/supports.md) */
    double *trial, *drift, *force, *damping_force, *tangent_t, *kks, *R;
    int64_t P, S;
    double c1, wf;
    int tangent;
} SpringLoop;

/* The springs order[from .. to - 1], all of law `force` (a law group: its function called
 * directly, inlined where it is a built-in law); `terms` 0 when no spring of the scene has
 * sides (a planar scene: each its two DOFs), `grounded` 0 when none spans supports, `current`
 * 1 when every spring's damping is on its current tangent and none has P-delta (the paper's
 * scenes, and the lines of a plan's storeys: neither is looked up per spring), `in_order` 1
 * when the evaluation order is the springs' own (element j is order[j] = j: every per-element
 * address then steps with the loop, which the compiler strength-reduces). Each flag is a
 * constant where spring_run is inlined: one loop without the branches of what the scene does
 * not use. Returns 1 when an effective tangent changed. */
static PFRAME_INLINE int spring_run(const SpringLoop *L, int64_t from, int64_t to,
                                    LawFunction force, int terms, int grounded, int current,
                                    int in_order)
{
    double out[3];
    int stale = 0;
    int64_t j;
    for (j = from; j < to; j++) {
        const int64_t e = in_order ? j : L->order[j];
        const int64_t lo = L->dofs[2 * e], up = L->dofs[2 * e + 1];
        const int64_t mode = current ? DAMPING_CURRENT : L->modes[e];
        const int sided = terms && general(L->start, e);
        double d, r, f, kt, kr, kd, fd;
        if (sided) { /* a line in plan, a storey on soil (less h theta): its sides */
            sides_sum2(L->start, L->side_dof, L->side_coef, e, 1, L->ue, L->ve, &d, &r);
        } else {
            d = L->ue[up];
            r = L->ve[up];
            if (lo >= 0) {
                d -= L->ue[lo];
                r -= L->ve[lo];
            }
        }
        if (grounded) { /* across supports: the ground displacements' part */
            d += ground_sum(L->g_start, L->g_channel, L->g_coef, e, L->g_d);
            r += ground_sum(L->g_start, L->g_channel, L->g_coef, e, L->g_v);
        }
        force(L->params + e * L->P, L->committed + e * L->S, L->trial + e * L->S, d, r, out);
        f = out[0];
        kt = out[1];
        kr = out[2];
        if (mode == DAMPING_INITIAL)
            kd = L->k0[e];
        else if (mode == DAMPING_CURRENT)
            kd = kt;
        else
            kd = L->tangent_c[e];
        fd = L->beta[e] * kd * r;
        L->drift[e] = d;
        L->tangent_t[e] = kt; /* the material's: Rayleigh damping on the current tangent */
        if (!current && L->kg[e] != 0.0) {
            /* P-delta: the gravity load P's overturning moment P d over the height h is a
             * shear P d / h the storey's columns must also resist: the storey resists
             * f - (P / h) d, with tangent k_t - P / h */
            f -= L->kg[e] * d;
            kt -= L->kg[e];
        }
        L->force[e] = f;
        L->damping_force[e] = fd;
        if (sided) {
            sides_add(L->R, L->start, L->side_dof, L->side_coef, e, 1, -(f + fd), f + fd);
        } else {
            L->R[up] -= f + fd;
            if (lo >= 0)
                L->R[lo] += f + fd;
        }
        if (L->tangent) {
            double kk = (kt + L->c1 * (kr + L->beta[e] * kd)) * L->wf;
            if (kk != L->kks[e]) {
                L->kks[e] = kk;
                stale = 1;
            }
        }
    }
    return stale;
}

/* What the contact loop of evaluate reads and writes for member b (see SpringLoop). */
typedef struct {
    const double *committed_step;
    int64_t *calls;
    int terms, grounded, in_order;
    const int64_t *dofs, *order, *start, *side_dof, *g_start, *g_channel;
    const double *params, *committed, *gap, *pen_c, *force_c, *side_coef, *ue, *ve;
    const double *g_coef, *g_d, *g_v; /* across supports (docs/supports.md) */
    double *trial, *force, *penetration, *kks, *R;
    int64_t Q, T, held;
    double c1, wf, held_closed;
    int tangent, hold_start;
} ContactLoop;

/* The contacts order[from .. to - 1], all of law `force` (see spring_run); `holding` 0 when
 * no contact is held on a branch (no located event, no hold at the start). */
static PFRAME_INLINE int contact_run(const ContactLoop *L, int64_t from, int64_t to,
                                     LawFunction force, int terms, int grounded, int in_order,
                                     int holding)
{
    double out[3];
    int stale = 0;
    int64_t j;
    for (j = from; j < to; j++) {
        const int64_t e = in_order ? j : L->order[j];
        const int64_t left = L->dofs[2 * e], right = L->dofs[2 * e + 1];
        const int plain = !(terms && general(L->start, e));
        double d, r, f, kd, kr, at;
        if (plain) { /* floor to floor or to a wall: its nodes' values */
            d = dof_value(L->ue, left) - dof_value(L->ue, right);
            r = dof_value(L->ve, left) - dof_value(L->ve, right);
        } else { /* points off the centre of mass, a struck column: its sides */
            sides_sum2(L->start, L->side_dof, L->side_coef, e, 0, L->ue, L->ve, &d, &r);
        }
        if (grounded) { /* across supports: the ground displacements' difference */
            d += ground_sum(L->g_start, L->g_channel, L->g_coef, e, L->g_d);
            r += ground_sum(L->g_start, L->g_channel, L->g_coef, e, L->g_v);
        }
        d -= L->gap[e];
        at = d;
        if (!holding) {
            /* evaluated where it is */
        } else if (e == L->held) {
            /* Located events (events.c) hold the contact on one branch, so that its
             * penetration is a continuous function of the sub-step length: held open, no
             * force on either side of delta = 0; held closed, the law's force at
             * delta = 0+ continued to delta < 0 (the jump of a dashpot, c delta', at
             * delta = 0 stays off the search). */
            at = L->held_closed != 0.0 ? py_max(d, HELD_DEPTH) : py_min(d, 0.0);
        } else if (L->hold_start) {
            /* closed: in contact, or touching with a force (restarted at its onset) */
            at = (L->pen_c[e] > 0.0 || L->force_c[e] > 0.0) ? py_max(d, HELD_DEPTH)
                                                             : py_min(d, 0.0);
        }
        force(L->params + e * L->Q, L->committed + e * L->T, L->trial + e * L->T, at, r, out);
        f = out[0];
        kd = out[1];
        kr = out[2];
        if (holding && at > d)
            kd = 0.0;
        L->force[e] = f;
        L->penetration[e] = d;
        if (plain) {
            if (left >= 0) /* -1: a wall, the ground's side */
                L->R[left] -= f;
            if (right >= 0)
                L->R[right] += f;
        } else { /* the force on each side's DOFs, as its point moves with them */
            sides_add(L->R, L->start, L->side_dof, L->side_coef, e, 0, -f, f);
        }
        if (L->tangent) {
            double kk = (kd + L->c1 * kr) * L->wf;
            if (kk != L->kks[e]) {
                L->kks[e] = kk;
                stale = 1;
            }
        }
    }
    return stale;
}

/* Each built-in law's group loops as functions of their own, spring_group_<id> and
 * contact_group_<id>, which evaluate calls (not copies into itself): with sixteen laws in a
 * few variants each, copies made evaluate one function of over 100 kB, through whose
 * scattered pieces a step jumped and whose hot loops spilled registers to the stack (the
 * paper's pair ran 7 % slower than with only its own two laws compiled). A variant is chosen
 * per call by the flags of spring_run and contact_run. */
#define SPRING_GROUP_FUNCTION(id, function) \
    static PFRAME_NOINLINE int spring_group_##id(const SpringLoop *L, int64_t from, int64_t to) \
    { \
        const int terms = L->terms; \
        return L->grounded ? spring_run(L, from, to, function, terms, 1, 0, 0) \
               : terms ? (L->current ? spring_run(L, from, to, function, 1, 0, 1, 0) \
                                     : spring_run(L, from, to, function, 1, 0, 0, 0)) \
               : !L->current ? spring_run(L, from, to, function, 0, 0, 0, 0) \
               : L->in_order ? spring_run(L, from, to, function, 0, 0, 1, 1) \
                             : spring_run(L, from, to, function, 0, 0, 1, 0); \
    }
MATERIAL_LAWS(SPRING_GROUP_FUNCTION)
#undef SPRING_GROUP_FUNCTION

/* the group functions by law id */
typedef int (*SpringGroup)(const SpringLoop *, int64_t, int64_t);
#define SPRING_GROUP_ENTRY(id, function) [id] = spring_group_##id,
static const SpringGroup SPRING_GROUPS[BUILTIN_MATERIALS] = {MATERIAL_LAWS(SPRING_GROUP_ENTRY)};
#undef SPRING_GROUP_ENTRY

/* in_order: the contacts in their own order, none held (see evaluate_contacts) */
#define CONTACT_GROUP_FUNCTION(id, function) \
    static PFRAME_NOINLINE int contact_group_##id(const ContactLoop *L, int64_t from, \
                                                  int64_t to, int in_order) \
    { \
        return L->terms || L->grounded \
                   ? contact_run(L, from, to, function, L->terms, L->grounded, 0, 1) \
               : in_order ? contact_run(L, from, to, function, 0, 0, 1, 0) \
                          : contact_run(L, from, to, function, 0, 0, 0, 1); \
    }
CONTACT_LAWS(CONTACT_GROUP_FUNCTION)
#undef CONTACT_GROUP_FUNCTION

typedef int (*ContactGroup)(const ContactLoop *, int64_t, int64_t, int);
#define CONTACT_GROUP_ENTRY(id, function) [id] = contact_group_##id,
static const ContactGroup CONTACT_GROUPS[BUILTIN_CONTACT_LAWS] = {CONTACT_LAWS(CONTACT_GROUP_ENTRY)};
#undef CONTACT_GROUP_ENTRY

/* The end of the law group that starts at order[from] (elements of one law are consecutive
 * in the plan's order). */
static PFRAME_INLINE int64_t group_end(const int64_t *order, const int64_t *laws, int64_t from,
                                      int64_t count)
{
    int64_t to = from + 1;
    if (laws[order[count - 1]] == laws[order[from]]) /* the last group: no search */
        return count;
    while (to < count && laws[order[to]] == laws[order[from]])
        to++;
    return to;
}

/* What evaluate runs for member b: its element loops. */
typedef struct {
    SpringLoop springs;
    ContactLoop contacts;
    /* every DOF loaded by the ground's channel 0 (one component, no rotation or rocking DOF):
     * the loops over the DOFs read its value once */
    int one_channel;
    /* the fast paths' weights of the step length weights_h (integrator.c, step_weights): the
     * divisions once per step length, not once per step */
    double weights_h, c0, c1, inv_c0_mmin;
    /* every spring (contact) of one built-in law, whose group function is then found once per
     * call: evaluate calls it without the law groups' loop and switch (about 3 % of a step
     * of the paper's pair); NULL otherwise */
    SpringGroup spring_group;
    ContactGroup contact_group;
    int64_t spring_law, contact_law;
} Loops;

/* Member b's loops, what of them holds for a whole call (evaluate sets the rest), in loops,
 * which w then points to. */
static void prepare_loops(const Model *m, State *st, Work *w, int64_t b, Loops *loops)
{
    const int64_t ns = m->stories, nc = m->contacts;
    SpringLoop *sl = &loops->springs;
    ContactLoop *cl = &loops->contacts;
    int64_t e;
    sl->committed_step = st->story_committed + b * ns * m->story_states;
    sl->calls = st->material_calls + b * m->materials;
    sl->terms = m->story_terms > 0;
    sl->grounded = m->story_ground_terms > 0;
    sl->current = 1;
    sl->in_order = 1;
    for (e = 0; e < ns; e++) {
        sl->current &= m->story_damping[e] == DAMPING_CURRENT && m->story_kg[b * ns + e] == 0.0;
        sl->in_order &= m->story_order[e] == e;
    }
    sl->dofs = m->story_dofs;
    sl->order = m->story_order;
    sl->modes = m->story_damping;
    sl->start = m->story_side_start;
    sl->side_dof = m->story_side_dof;
    sl->params = m->story_params + b * ns * m->story_width;
    sl->k0 = m->story_k0 + b * ns;
    sl->beta = m->story_beta + b * ns;
    sl->kg = m->story_kg + b * ns;
    sl->side_coef = m->story_side_coef + b * m->story_terms;
    sl->g_start = m->story_ground_start;
    sl->g_channel = m->story_ground_channel;
    sl->g_coef = m->story_ground_coef + b * m->story_ground_terms;
    sl->tangent_c = st->story_tangent + b * ns;
    sl->ue = w->ue;
    sl->ve = w->ve;
    sl->trial = st->story_trial + b * ns * m->story_states;
    sl->drift = w->drift;
    sl->force = w->story_force;
    sl->damping_force = w->story_damping_force;
    sl->tangent_t = w->story_tangent;
    sl->kks = w->story_kk;
    sl->R = w->R;
    sl->P = m->story_width;
    sl->S = m->story_states;
    cl->committed_step = st->contact_committed + b * nc * m->contact_states;
    cl->calls = st->contact_calls + b * m->contact_laws;
    cl->terms = m->contact_terms > 0;
    cl->grounded = m->contact_ground_terms > 0;
    cl->in_order = 1;
    for (e = 0; e < nc; e++)
        cl->in_order &= m->contact_order[e] == e;
    cl->dofs = m->contact_dofs;
    cl->order = m->contact_order;
    cl->start = m->contact_side_start;
    cl->side_dof = m->contact_side_dof;
    cl->params = m->contact_params + b * nc * m->contact_width;
    cl->gap = m->gap + b * nc;
    cl->pen_c = st->penetration + b * nc;
    cl->force_c = st->contact_force + b * nc;
    cl->side_coef = m->contact_side_coef + b * m->contact_terms;
    cl->g_start = m->contact_ground_start;
    cl->g_channel = m->contact_ground_channel;
    cl->g_coef = m->contact_ground_coef + b * m->contact_ground_terms;
    cl->ue = w->ue;
    cl->ve = w->ve;
    cl->trial = st->contact_trial + b * nc * m->contact_states;
    cl->force = w->contact_force;
    cl->penetration = w->penetration;
    cl->kks = w->contact_kk;
    cl->R = w->R;
    cl->Q = m->contact_width;
    cl->T = m->contact_states;
    loops->spring_group = NULL;
    loops->spring_law = ns ? m->story_law[m->story_order[0]] : -1;
    if (ns && loops->spring_law < BUILTIN_MATERIALS
        && group_end(m->story_order, m->story_law, 0, ns) == ns)
        loops->spring_group = SPRING_GROUPS[loops->spring_law];
    loops->contact_group = NULL;
    loops->contact_law = nc ? m->contact_law[m->contact_order[0]] : -1;
    if (nc && loops->contact_law < BUILTIN_CONTACT_LAWS
        && group_end(m->contact_order, m->contact_law, 0, nc) == nc)
        loops->contact_group = CONTACT_GROUPS[loops->contact_law];
    loops->weights_h = NAN; /* none yet: reset_work took this member's smallest mass */
    loops->one_channel = m->dofs > 0; /* channel 0 then exists */
    for (e = 0; e < m->dofs; e++)
        loops->one_channel &= m->dof_channel[e] == 0;
    w->loops = loops;
}

/* The storeys' and links' forces (the material's, Rayleigh damping's, P-delta's) at the
 * evaluation point, subtracted from the residual, law group by law group; returns 1 when an
 * effective tangent changed (see evaluate). */
static PFRAME_INLINE int evaluate_springs(const Model *m, const Settings *s, Work *w, const double *age,
                            int from_stage, double c1, double wf, int tangent)
{
    const int64_t ns = m->stories;
    const Loops *loops = (const Loops *)w->loops;
    SpringLoop *L = &((Loops *)w->loops)->springs;
    const int terms = L->terms, grounded = L->grounded;
    int stale = 0;
    int64_t j, to;
    L->committed = from_stage ? w->story_stage : L->committed_step;
    if (grounded) {
        L->g_d = ground_block(m, age, 1);
        L->g_v = ground_block(m, age, 2);
    }
    L->c1 = c1;
    L->wf = wf;
    L->tangent = tangent;
    if (loops->spring_group != NULL) { /* one group */
        L->calls[loops->spring_law] += ns;
        return loops->spring_group(L, 0, ns);
    }
    for (j = 0; j < ns; j = to) {
        const int64_t law = m->story_law[m->story_order[j]];
        to = group_end(m->story_order, m->story_law, j, ns);
        L->calls[law] += to - j;
        switch (law) {
#define SPRING_GROUP(id, function) \
        case id: \
            stale |= spring_group_##id(L, j, to); \
            break;
            MATERIAL_LAWS(SPRING_GROUP)
#undef SPRING_GROUP
        default:
            stale |= spring_run(L, j, to, s->material_plugins[law - BUILTIN_MATERIALS],
                                terms, grounded, 0, 0);
        }
    }
    return stale;
}

/* The contacts' forces at the evaluation point, added to the residual, law group by law
 * group; returns 1 when an effective tangent changed (see evaluate). */
static PFRAME_INLINE int evaluate_contacts(const Model *m, const Settings *s, Work *w, const double *age,
                             int from_stage, double c1, double wf, int tangent)
{
    const int64_t nc = m->contacts;
    const Loops *loops = (const Loops *)w->loops;
    ContactLoop *L = &((Loops *)w->loops)->contacts;
    const int terms = L->terms, grounded = L->grounded;
    int stale = 0, in_order;
    int64_t j, to;
    L->committed = from_stage ? w->contact_stage : L->committed_step;
    if (grounded) {
        L->g_d = ground_block(m, age, 1);
        L->g_v = ground_block(m, age, 2);
    }
    L->held = (int64_t)w->scalars[HELD];
    L->held_closed = w->scalars[HELD_CLOSED];
    L->c1 = c1;
    L->wf = wf;
    L->tangent = tangent;
    /* With located events, an evaluation point past the sub-step's end (Wilson-theta's
     * t + theta h: s->beyond) holds every contact on the branch it has at the sub-step
     * start: a contact that closes or opens beyond the sub-step's end must not act inside
     * it (a dashpot's jump there changed the sub-step before an impact by O(h)); one that
     * crosses inside it is located (events.c) and the sub-step cut there. The step end
     * (tangent off: the commit's evaluation) sees the real law. */
    L->hold_start = tangent && s->events && s->beyond;
    /* the elements in their own order, none held: the plain loop */
    in_order = L->in_order && L->held < 0 && !L->hold_start;
    if (loops->contact_group != NULL) { /* one group */
        L->calls[loops->contact_law] += nc;
        return loops->contact_group(L, 0, nc, in_order);
    }
    for (j = 0; j < nc; j = to) {
        const int64_t law = m->contact_law[m->contact_order[j]];
        to = group_end(m->contact_order, m->contact_law, j, nc);
        L->calls[law] += to - j;
        switch (law) {
#define CONTACT_GROUP(id, function) \
        case id: \
            stale |= contact_group_##id(L, j, to, in_order); \
            break;
            CONTACT_LAWS(CONTACT_GROUP)
#undef CONTACT_GROUP
        default:
            stale |= contact_run(L, j, to, s->contact_plugins[law - BUILTIN_CONTACT_LAWS],
                                 terms, grounded, 0, 1);
        }
    }
    return stale;
}

/* The residual's part of DOF i at the evaluation point, -m_i (a_g + ae_i) - c_i ve_i, with a_g
 * the ground acceleration that loads it (dof_ground; evaluate and end_point_residual, which
 * takes it with the stage's end point); modal damping's -C ve is added after. */
static PFRAME_INLINE double dof_residual(double mass, double damping, double ag, double ae,
                                         double ve)
{
    return -mass * (ag + ae) - damping * ve;
}

/* The element forces at the evaluation point subtracted from the residual, whose DOF part
 * (dof_residual, modal damping's) is in w->R. With tangent, each element's effective tangent
 * (k_t + c1 (k_r + beta k_d)) wf is compared with the one in the current factorisation;
 * returns 1 when one changed (the factorisation is then stale). Each law group runs as one
 * loop calling its law's function (spring_run, contact_run). */
static int evaluate_elements(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                             const double *age, double c1, double wf, int tangent)
{
    /* the laws' committed state: the step start's, or in a stage after the first the end of
     * the stage before (newton.c, keep_stage) */
    const int from_stage = w->scalars[LAWS_FROM_STAGE] != 0.0;
    int stale;
    st->counters[b * COUNTER_SLOTS + EVALUATIONS] += 1;
    stale = m->stories ? evaluate_springs(m, s, w, age, from_stage, c1, wf, tangent) : 0;
    if (m->contacts && evaluate_contacts(m, s, w, age, from_stage, c1, wf, tangent))
        stale = 1;
    return stale;
}

/* Element forces and the residual at the evaluation point, ground accelerations age (one per
 * channel); returns 1 when an effective tangent changed (evaluate_elements). */
static int evaluate(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                    const double *age, double c1, double wf, int tangent)
{
    const int64_t n = m->dofs;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *ve = w->ve, *ae = w->ae;
    double *R = w->R;
    int64_t i;
    if (((const Loops *)w->loops)->one_channel) {
        const double g = age[0];
        for (i = 0; i < n; i++)
            R[i] = dof_residual(mass[i], damping[i], g, ae[i], ve[i]);
    } else {
        for (i = 0; i < n; i++) /* influence: 1, or 0 on a foundation's rocking DOF */
            R[i] = dof_residual(mass[i], damping[i], dof_ground(m, i, age), ae[i], ve[i]);
    }
    if (m->modal_blocks)
        modal_add(m, b, ve, -1.0, R);
    return evaluate_elements(m, s, st, w, b, age, c1, wf, tangent);
}

/* The driver asked the kernel to stop (Ctrl-C, SIGTERM): another thread sets m->stop[0]
 * while this call runs, hence the volatile read. */
static int stop_asked(const Model *m) { return *(volatile const int64_t *)m->stop != 0; }

/* 0 after recording the element whose force is not finite, if any, or STOPPED when the driver
 * asked the kernel to stop. Every evaluation of the residual is followed by this check, so a
 * stop is seen within one Newton iteration or sub-step in every mode, however many of them
 * a step takes (the failed step unwinds as any failure does; the driver then discards the
 * call). */
static PFRAME_INLINE int check_finite(const Model *m, State *st, Work *w, int64_t b, int64_t k)
{
    const double *R = w->R;
    double total = 0.0;
    int64_t i, e, kind = NODE, where = 0;
    if (stop_asked(m))
        return fail(st, b, STOPPED, k, NODE, 0);
    for (i = 0; i < m->dofs; i++)
        total += R[i];
    if (isfinite(total))
        return 1;
    for (e = 0; e < m->stories; e++) {
        if (!isfinite(w->story_force[e] + w->story_damping_force[e])) {
            kind = STORY;
            where = e;
            break;
        }
    }
    for (e = 0; e < m->contacts; e++) {
        if (!isfinite(w->contact_force[e])) {
            kind = CONTACT;
            where = e;
            break;
        }
    }
    return fail(st, b, NOT_FINITE, k, kind, where);
}

/* check_finite for Newton's iterations, which also takes the residual's squared norm R . R
 * into *norm_r (summed in the DOFs' order, as the convergence test reads it): one pass over R
 * for both. A finite R . R means every R[i] is finite and below 1.4e154, so that their sum is
 * finite too; otherwise (an R[i] not finite, or one whose square overflows) check_finite
 * decides, so the same failure is reported, and a stop asked for is seen as there. */
static PFRAME_INLINE int check_finite_norm(const Model *m, State *st, Work *w, int64_t b,
                                           int64_t k, double *norm_r)
{
    const double *R = w->R;
    double norm = 0.0;
    int64_t i;
    for (i = 0; i < m->dofs; i++)
        norm += R[i] * R[i];
    *norm_r = norm;
    if (!isfinite(norm))
        return check_finite(m, st, w, b, k);
    if (stop_asked(m))
        return fail(st, b, STOPPED, k, NODE, 0);
    return 1;
}

/* Why the effective stiffness is not definite: the element (storey, link or contact) whose
 * effective tangent is the most negative, which a positive mass term could not outweigh;
 * without one (every tangent non-negative), the DOF of the first pivot that is not positive. */
static int not_definite(const Model *m, State *st, const Work *w, int64_t b, int64_t k,
                        int64_t pivot)
{
    int64_t e, kind = NODE, index = pivot;
    double worst = 0.0;
    for (e = 0; e < m->stories; e++) {
        if (w->story_kk[e] < worst) {
            worst = w->story_kk[e];
            kind = STORY;
            index = e;
        }
    }
    for (e = 0; e < m->contacts; e++) {
        if (w->contact_kk[e] < worst) {
            worst = w->contact_kk[e];
            kind = CONTACT;
            index = e;
        }
    }
    return fail(st, b, NOT_DEFINITE, k, kind, index);
}

/* Assemble the effective stiffness band from the element tangents in w->story_kk and
 * w->contact_kk and factor it; 0 (after recording why) if it is not definite. */
static int factor(const Model *m, const Settings *s, State *st, Work *w, int64_t b, int64_t k,
                  double c0, double c1, double wm, double wf)
{
    const int64_t n = m->dofs, bw = s->bandwidth;
    double *band = w->band;
    const double *mass = m->mass + b * n, *damping = m->mass_damping + b * n;
    const double *kks;
    const int64_t *dofs;
    int64_t i, d, e, pivot;
    for (i = 0; i < n; i++) {
        for (d = 1; d < bw + 1; d++)
            band[i * (bw + 1) + d] = 0.0;
        band[i * (bw + 1)] = mass[i] * c0 * wm + damping[i] * c1 * wf;
    }
    { /* modal damping: its blocks' lower triangles (the bandwidth spans every block) */
        const double *C = m->modal_matrix + b * m->modal_width;
        int64_t k, x, y;
        for (k = 0; k < m->modal_blocks; k++) {
            const int64_t *at = m->modal_dofs + m->modal_start[k];
            const int64_t size = m->modal_start[k + 1] - m->modal_start[k];
            for (x = 0; x < size; x++)
                for (y = 0; y < size; y++)
                    if (at[y] <= at[x])
                        band[at[x] * (bw + 1) + (at[x] - at[y])] += C[x * size + y] * c1 * wf;
            C += size * size;
        }
    }
    dofs = m->story_dofs;
    kks = w->story_kk;
    for (e = 0; e < m->stories; e++) {
        const double kk = kks[e];
        const int64_t lo = dofs[2 * e], up = dofs[2 * e + 1];
        if (general(m->story_side_start, e)) { /* kk g g^T, g = upper side - lower side */
            band_sides(band, bw, m->story_side_start, m->story_side_dof,
                       m->story_side_coef + b * m->story_terms, e, -1.0, kk);
            continue;
        }
        band[up * (bw + 1)] += kk;
        if (lo >= 0) {
            band[lo * (bw + 1)] += kk;
            band[imax(lo, up) * (bw + 1) + iabs(lo - up)] -= kk;
        }
    }
    dofs = m->contact_dofs;
    kks = w->contact_kk;
    for (e = 0; e < m->contacts; e++) {
        const double kk = kks[e];
        const int64_t left = dofs[2 * e], right = dofs[2 * e + 1];
        if (general(m->contact_side_start, e)) { /* kk g g^T, g = left side - right side */
            band_sides(band, bw, m->contact_side_start, m->contact_side_dof,
                       m->contact_side_coef + b * m->contact_terms, e, 1.0, kk);
            continue;
        }
        if (left >= 0)
            band[left * (bw + 1)] += kk;
        if (right >= 0)
            band[right * (bw + 1)] += kk;
        if (left >= 0 && right >= 0)
            band[imax(left, right) * (bw + 1) + iabs(left - right)] -= kk;
    }
    st->counters[b * COUNTER_SLOTS + FACTORISATIONS] += 1;
    pivot = ldl_factor(band, n, bw);
    if (pivot < 0)
        return 1;
    return not_definite(m, st, w, b, k, pivot);
}

/* The ground's series (each channel's acceleration, then with supports their displacements
 * and velocities) at fractions start and stop of step k (linear between the samples k - 1
 * and k). */
static void ground_between(const Model *m, int64_t b, int64_t k, double start, double stop,
                           double *ag_old, double *ag_new)
{
    int64_t c;
    for (c = 0; c < m->ground_series; c++) {
        const double *ag = m->ground + (b * m->ground_series + c) * m->ground_width;
        const double slope = ag[k] - ag[k - 1];
        ag_old[c] = ag[k - 1] + slope * start;
        ag_new[c] = ag[k - 1] + slope * stop;
    }
}

/* The ground's series at sample k. */
static void ground_at(const Model *m, int64_t b, int64_t k, double *ag)
{
    int64_t c;
    for (c = 0; c < m->ground_series; c++)
        ag[c] = m->ground[(b * m->ground_series + c) * m->ground_width + k];
}
