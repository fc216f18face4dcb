/* Recorders: gathering committed state into history rows and envelopes.
 *
 * Only what a scene's recorders ask for is gathered: a history of quantity q is written at the
 * steps that are multiples of its `every` (the loop asks next_due for the next such step once
 * per record, not every quantity every step), an envelope keeps the running peak of the
 * absolute value. Recorders see committed state only.
 */

/* a step no run reaches (no history is due) */
#define NEVER ((int64_t)1 << 62)

/* The committed values of quantity q of member b, and how many there are (NULL for the
 * ground acceleration, which is m->ground[b, c, k], a value per channel c). */
static PFRAME_INLINE const double *source(const Model *m, const State *st, int64_t q, int64_t b,
                            int64_t *width)
{
    const int64_t n = m->dofs, ns = m->stories, nc = m->contacts;
    switch (q) {
    case DISPLACEMENT: *width = n; return st->U + b * n;
    case VELOCITY: *width = n; return st->V + b * n;
    case ACCELERATION: *width = n; return st->A + b * n;
    case ABSOLUTE_ACCELERATION: *width = n; return st->A + b * n;
    case STORY_DRIFT: *width = ns; return st->drift + b * ns;
    case STORY_DRIFT_RATIO: *width = ns; return st->drift + b * ns;
    case STORY_FORCE: *width = ns; return st->story_force + b * ns;
    case CONTACT_FORCE: *width = nc; return st->contact_force + b * nc;
    case CONTACT_PENETRATION: *width = nc; return st->penetration + b * nc;
    /* the links are the last m->links spring elements, after the storeys */
    case LINK_DEFORMATION: *width = m->links; return st->drift + b * ns + (ns - m->links);
    case LINK_FORCE: *width = m->links; return st->story_force + b * ns + (ns - m->links);
    /* a foundation's sway and rocking DOFs (m->foundation_dofs) */
    case FOUNDATION_SWAY: *width = m->foundations; return st->U + b * n;
    case FOUNDATION_ROCKING: *width = m->foundations; return st->U + b * n;
    /* the named plan points: sums of the DOFs (m->gauge_*), along x and y of each point */
    case POINT_DISPLACEMENT: *width = 2 * m->points; return st->U + b * n;
    case POINT_DRIFT: *width = 2 * m->points; return st->U + b * n;
    /* the ground's displacements (series C + c) and each contact's part of them */
    case GROUND_DISPLACEMENT: *width = m->channels; return NULL;
    case CONTACT_GROUND_DISPLACEMENT: *width = nc; return NULL;
    default: *width = m->channels; return NULL;
    }
}

/* The ground acceleration of channel c of member b at the committed state: ag[c] at the end
 * of a sub-step, or (ag NULL) the sample of step k itself. */
static double ground_of(const Model *m, int64_t b, int64_t k, int64_t c, const double *ag)
{
    return ag != NULL ? ag[c] : m->ground[(b * m->ground_series + c) * m->ground_width + k];
}

/* The absolute acceleration of DOF i: its acceleration relative to the ground plus the
 * ground's as the ground load sees it (its channel's, m->dof_channel; none on a rotation or a
 * foundation's rocking), the one place the sum is made. */
static double absolute_acceleration(const Model *m, int64_t b, int64_t k, int64_t i,
                                    double relative, const double *ag)
{
    const int64_t c = m->dof_channel[i];
    return c >= 0 ? relative + ground_of(m, b, k, c, ag) : relative + 0.0;
}

/* Gauge g of member b at the displacements U: a named plan point's motion along an axis. */
static double gauge(const Model *m, int64_t b, int64_t g, const double *U)
{
    const double *coef = m->gauge_coef + b * m->gauge_terms;
    double sum = 0.0;
    int64_t t;
    for (t = m->gauge_start[g]; t < m->gauge_start[g + 1]; t++)
        sum += coef[t] * U[m->gauge_dof[t]];
    return sum;
}

/* The running peaks of gauges first .. first + count - 1 at the displacements U: gauge()
 * in one loop over their terms (the point drifts' envelope, kept for every scene in plan,
 * is most of the recording's work there). */
static void gauge_peaks(const Model *m, int64_t b, int64_t first, int64_t count,
                        const double *U, double *peak)
{
    const double *coef = m->gauge_coef + b * m->gauge_terms;
    const int64_t *start = m->gauge_start + first, *dof = m->gauge_dof;
    int64_t g, t = start[0];
    for (g = 0; g < count; g++) {
        double sum = 0.0;
        for (; t < start[g + 1]; t++)
            sum += coef[t] * U[dof[t]];
        peak[g] = py_max(peak[g], fabs(sum));
    }
}

/* Committed value i of quantity q (its values from source); ag holds the ground accelerations
 * at the committed state (a sub-step's end; NULL: the samples of step k). */
static double value(const Model *m, int64_t q, const double *values, int64_t b, int64_t k,
                    int64_t i, const double *ag)
{
    if (q == GROUND_ACCELERATION)
        return ground_of(m, b, k, i, ag);
    if (q == ABSOLUTE_ACCELERATION)
        return absolute_acceleration(m, b, k, i, values[i], ag);
    if (q == CONTACT_PENETRATION)
        return py_max(values[i], 0.0);
    if (q == STORY_DRIFT_RATIO)
        return values[i] / m->story_height[b * m->stories + i];
    if (q == FOUNDATION_SWAY)
        return values[m->foundation_dofs[2 * i]];
    if (q == FOUNDATION_ROCKING)
        return values[m->foundation_dofs[2 * i + 1]];
    if (q == POINT_DISPLACEMENT)
        return gauge(m, b, i, values);
    if (q == POINT_DRIFT)
        return gauge(m, b, 2 * m->points + i, values);
    if (q == GROUND_DISPLACEMENT)
        return ground_of(m, b, k, m->channels + i, ag);
    if (q == CONTACT_GROUND_DISPLACEMENT) {
        const double *coef = m->contact_ground_coef + b * m->contact_ground_terms;
        double sum = 0.0;
        int64_t t;
        for (t = m->contact_ground_start[i]; t < m->contact_ground_start[i + 1]; t++)
            sum += coef[t] * ground_of(m, b, k, m->channels + m->contact_ground_channel[t], ag);
        return sum;
    }
    return values[i];
}

/* Quantity q's values are its source's as they are (value() returns values[i]). */
static int as_stored(int64_t q)
{
    return q != GROUND_ACCELERATION && q != ABSOLUTE_ACCELERATION && q != CONTACT_PENETRATION
           && q != STORY_DRIFT_RATIO && q != FOUNDATION_SWAY && q != FOUNDATION_ROCKING
           && q != POINT_DISPLACEMENT && q != POINT_DRIFT && q != GROUND_DISPLACEMENT
           && q != CONTACT_GROUND_DISPLACEMENT;
}

/* The recorded histories of a call: the quantities with an `every`, listed once per call
 * (the loop's test each step was a pass over every recordable quantity, twice). */
typedef struct {
    int64_t count;
    int every_step; /* every history is due at every step */
    int64_t quantity[RECORDABLE_COUNT];
    int64_t every[RECORDABLE_COUNT];
} Histories;

static void prepare_histories(const Recording *rec, Histories *hist)
{
    int64_t q;
    hist->count = 0;
    hist->every_step = 1;
    for (q = 0; q < RECORDABLE_COUNT; q++) {
        if (rec->every[q] > 0) {
            hist->quantity[hist->count] = q;
            hist->every[hist->count] = rec->every[q];
            hist->every_step &= rec->every[q] == 1;
            hist->count += 1;
        }
    }
}

/* The first step at or after k at which a history is due (NEVER if none is). */
static int64_t next_due(const Histories *hist, int64_t k)
{
    int64_t due = NEVER, j;
    if (hist->count && hist->every_step)
        return k;
    for (j = 0; j < hist->count; j++) {
        const int64_t every = hist->every[j];
        const int64_t step = (k + every - 1) / every * every;
        if (step < due)
            due = step;
    }
    return due;
}

/* Gather the histories due at step k; returns the next step one is due. */
static int64_t record_histories(const Model *m, State *st, Recording *rec,
                                const Histories *hist, int64_t b, int64_t k)
{
    int64_t gathered = 0, j, i, width;
    for (j = 0; j < hist->count; j++) {
        const int64_t q = hist->quantity[j], every = hist->every[j];
        if (k % every == 0) {
            const int64_t columns = rec->history_width[q];
            const int64_t row = k / every - rec->first_row[q];
            double *history = rec->history[q] + (b * rec->history_rows[q] + row) * columns;
            const double *values = source(m, st, q, b, &width); /* once per quantity */
            if (as_stored(q)) /* most quantities: a copy, without value()'s tests per value */
                for (i = 0; i < columns; i++)
                    history[i] = values[i];
            else
                for (i = 0; i < columns; i++)
                    history[i] = value(m, q, values, b, k, i, NULL);
            gathered += columns;
        }
    }
    st->counters[b * COUNTER_SLOTS + GATHERS] += gathered;
    return next_due(hist, k + 1);
}

/* The running maximum of each pair's closing U[i] - U[j] (rec->closing_dofs) at committed step
 * k, as the gap's sink finds it from the displacements' history (pframe.gap.runs.GapSink: the
 * same subtraction of the same doubles, and max keeps the larger, as numpy's): the study's
 * runs need no history streamed for it. */
static void record_closings(const State *st, const Recording *rec, int64_t n, int64_t b)
{
    const double *U = st->U + b * n;
    const int64_t *dofs = rec->closing_dofs;
    double *peak = rec->closing + b * rec->closings;
    int64_t p;
    for (p = 0; p < rec->closings; p++)
        peak[p] = py_max(peak[p], U[dofs[2 * p]] - U[dofs[2 * p + 1]]);
}

/* The running peaks of enveloped quantity q (rec->envelope_list) with the committed state
 * (values: its source; ag as in record_envelopes). */
static void quantity_peaks(const Model *m, const Recording *rec, int64_t b, int64_t k,
                           int64_t q, const double *values, const double *ag)
{
    const int64_t columns = rec->envelope_width[q];
    double *peak = rec->envelope[q] + b * columns;
    int64_t i;
    if (as_stored(q)) /* most quantities: their committed values */
        for (i = 0; i < columns; i++)
            peak[i] = py_max(peak[i], fabs(values[i]));
    else if (q == POINT_DISPLACEMENT || q == POINT_DRIFT) /* kept for every plan */
        gauge_peaks(m, b, q == POINT_DRIFT ? 2 * m->points : 0, columns, values, peak);
    else
        for (i = 0; i < columns; i++)
            peak[i] = py_max(peak[i], fabs(value(m, q, values, b, k, i, ag)));
}

/* Update the running peaks of the enveloped quantities (rec->envelope_list) with step k (or a
 * sub-step of it, at whose end the ground accelerations are ag; NULL: step k's samples). */
static void record_envelopes(const Model *m, State *st, Recording *rec, int64_t b, int64_t k,
                             const double *ag)
{
    int64_t gathered = 0, j, width;
    for (j = 0; j < rec->envelope_count; j++) {
        const int64_t q = rec->envelope_list[j];
        quantity_peaks(m, rec, b, k, q, source(m, st, q, b, &width), ag);
        gathered += rec->envelope_width[q];
    }
    st->counters[b * COUNTER_SLOTS + GATHERS] += gathered;
}

/* How step_envelopes takes an enveloped quantity's values: as they are stored; the absolute
 * acceleration of a scene whose every DOF the ground's channel 0 loads (A[i] plus the
 * step's sample, added once per step); the storey drift ratio (drift over height); or by
 * quantity_peaks (value() per value: the rest). The same sums as value() gives: the same
 * bits. */
enum { PEAKS_STORED, PEAKS_ABSOLUTE, PEAKS_RATIO, PEAKS_OTHER };

/* The envelopes of member b as the time loop keeps them at each step: each quantity's source
 * and peaks found once per call (the arrays stay in place through it), its values compared
 * in one loop of their own kind (the paper's pair's study runs envelope the absolute
 * accelerations and drift ratios, which value()'s tests per value made about a fifth of
 * the kernel's time there). */
typedef struct {
    int64_t count, gathered;
    int64_t quantity[RECORDABLE_COUNT];
    int64_t kind[RECORDABLE_COUNT];
    int64_t columns[RECORDABLE_COUNT];
    const double *values[RECORDABLE_COUNT];
    const double *height; /* member b's storey heights (PEAKS_RATIO) */
    const double *ground; /* member b's channel 0 samples (PEAKS_ABSOLUTE) */
    double *peak[RECORDABLE_COUNT];
} Envelopes;

/* Member b's Envelopes, once its loops are prepared (prepare_loops: their one_channel). */
static void prepare_envelopes(const Model *m, State *st, const Recording *rec, const Work *w,
                              int64_t b, Envelopes *env)
{
    const int one_channel = ((const Loops *)w->loops)->one_channel;
    int64_t j, width;
    env->count = rec->envelope_count;
    env->gathered = 0;
    env->height = m->story_height + b * m->stories;
    env->ground = one_channel ? m->ground + b * m->ground_series * m->ground_width : NULL;
    for (j = 0; j < rec->envelope_count; j++) {
        const int64_t q = rec->envelope_list[j];
        env->quantity[j] = q;
        env->values[j] = source(m, st, q, b, &width);
        env->columns[j] = rec->envelope_width[q];
        env->kind[j] = as_stored(q)                                 ? PEAKS_STORED
                       : q == ABSOLUTE_ACCELERATION && one_channel ? PEAKS_ABSOLUTE
                       : q == STORY_DRIFT_RATIO                    ? PEAKS_RATIO
                                                                   : PEAKS_OTHER;
        env->peak[j] = rec->envelope[q] + b * rec->envelope_width[q];
        env->gathered += rec->envelope_width[q];
    }
}

/* record_envelopes at step k's end (the ground's samples of step k), from what
 * prepare_envelopes found. */
static void step_envelopes(const Model *m, State *st, const Recording *rec, int64_t b,
                           int64_t k, const Envelopes *env)
{
    int64_t j, i;
    for (j = 0; j < env->count; j++) {
        const int64_t columns = env->columns[j];
        const double *values = env->values[j];
        double *peak = env->peak[j];
        switch (env->kind[j]) {
        case PEAKS_STORED:
            for (i = 0; i < columns; i++)
                peak[i] = py_max(peak[i], fabs(values[i]));
            break;
        case PEAKS_ABSOLUTE: {
            const double g = env->ground[k]; /* absolute_acceleration's, channel 0 */
            for (i = 0; i < columns; i++)
                peak[i] = py_max(peak[i], fabs(values[i] + g));
            break;
        }
        case PEAKS_RATIO:
            for (i = 0; i < columns; i++)
                peak[i] = py_max(peak[i], fabs(values[i] / env->height[i]));
            break;
        default:
            quantity_peaks(m, rec, b, k, env->quantity[j], values, NULL);
        }
    }
    st->counters[b * COUNTER_SLOTS + GATHERS] += env->gathered;
}

/* Envelopes see the state committed at the end of every sub-step of step k (central
 * difference's substeps, event location, split steps), not only at the step end: a contact
 * that opens and closes inside one step has its peak force recorded. */
static void record_substep(const Model *m, State *st, Recording *rec, int64_t b, int64_t k,
                           const double *ag)
{
    if (rec->envelope_count)
        record_envelopes(m, st, rec, b, k, ag);
}
