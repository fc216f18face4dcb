/* The limit pframe's kernel is measured against: a hand-written C program of the same
 * algorithm on the same scene (benchmarks/kernel_limit.py writes the numbers, compiles this
 * file with the flags setup.py gives the kernel, runs both and compares).
 *
 * The scene is a set of floors (masses, mass-proportional damping a0 m) joined by bilinear
 * storeys (Rayleigh's stiffness-proportional damping on the current tangent, a1 k_t) and
 * compression-only improved Kelvin contacts (Hunt-Crossley with n = 1: k delta (1 + chi
 * delta' / v0), v0 the approach velocity at onset), under one ground acceleration. Newmark's
 * average acceleration (gamma = 1/2, beta = 1/4), unknown the end acceleration, Newton from
 * the predictor a = A until |du| <= tol |u| + abs_tol, the factor of the effective stiffness
 * c0 M + c1 C + K_t (banded LDL^T) kept while no element's tangent changed; a Newton step
 * whose residual bound is a thousandth of the tolerance is skipped (pframe's rule, so that
 * the iterations, and so the numbers, are the same). What it keeps: the peak absolute floor
 * displacement, storey drift and contact force. Nothing else: no energy, no history, no
 * checks of finiteness or stability, no batch, no sub-steps.
 *
 *     kernel_limit INPUT [REPEATS]
 *
 * INPUT: int64 n, storeys, contacts, steps, bandwidth, max_iterations; then doubles: dt,
 * gamma, beta, tol, abs_tol; mass[n], mass_damping[n]; per storey: lower, upper (int64, -1
 * the ground), k, yield force, alpha, a1 (doubles); per contact: left, right (int64), gap, k,
 * chi, 1 / m_eff; ground[steps + 1]. Prints the best time per step (ns) over REPEATS runs,
 * then the peaks, one number a line.
 */

#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c99 */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    int64_t n, ns, nc, steps, bw, max_iter;
    double dt, gamma, beta, tol, abs_tol;
    double *mass, *damp;
    int64_t *s_lo, *s_up;
    double *s_k, *s_fy, *s_alpha, *s_a1;
    int64_t *c_l, *c_r;
    double *c_gap, *c_k, *c_chi, *c_invm;
    double *ground;
} Scene;

static double *doubles(FILE *f, int64_t count)
{
    double *out = malloc(sizeof(double) * (size_t)(count > 0 ? count : 1));
    if (count > 0 && fread(out, sizeof(double), (size_t)count, f) != (size_t)count)
        exit(2);
    return out;
}

static int64_t *ints(FILE *f, int64_t count)
{
    int64_t *out = malloc(sizeof(int64_t) * (size_t)(count > 0 ? count : 1));
    if (count > 0 && fread(out, sizeof(int64_t), (size_t)count, f) != (size_t)count)
        exit(2);
    return out;
}

static Scene read_scene(const char *path)
{
    Scene s;
    int64_t head[6];
    double numbers[5];
    FILE *f = fopen(path, "rb");
    if (!f || fread(head, sizeof(int64_t), 6, f) != 6 || fread(numbers, sizeof(double), 5, f) != 5)
        exit(2);
    s.n = head[0]; s.ns = head[1]; s.nc = head[2]; s.steps = head[3]; s.bw = head[4];
    s.max_iter = head[5];
    s.dt = numbers[0]; s.gamma = numbers[1]; s.beta = numbers[2]; s.tol = numbers[3];
    s.abs_tol = numbers[4];
    s.mass = doubles(f, s.n);
    s.damp = doubles(f, s.n);
    s.s_lo = ints(f, s.ns); s.s_up = ints(f, s.ns);
    s.s_k = doubles(f, s.ns); s.s_fy = doubles(f, s.ns); s.s_alpha = doubles(f, s.ns);
    s.s_a1 = doubles(f, s.ns);
    s.c_l = ints(f, s.nc); s.c_r = ints(f, s.nc);
    s.c_gap = doubles(f, s.nc); s.c_k = doubles(f, s.nc); s.c_chi = doubles(f, s.nc);
    s.c_invm = doubles(f, s.nc);
    s.ground = doubles(f, s.steps + 1);
    fclose(f);
    return s;
}

/* the peaks and the run's state */
typedef struct {
    double *U, *V, *A, *u, *v, *a, *R, *band;
    double *s_d, *s_f, *s_kk, *s_def_c, *s_force_c, *s_def_t, *s_force_t; /* bilinear states */
    double *c_f, *c_kk, *c_v0_c, *c_on_c, *c_v0_t, *c_on_t;             /* contact states */
    double *peak_u, *peak_d, *peak_f;
    int stale; /* an element's tangent changed since the factor was made */
} Run;

#define BAND(i, d) band[(i) * (bw + 1) + (d)]

static int ldl_factor(double *band, int64_t n, int64_t bw)
{
    int64_t i, j, k;
    for (j = 0; j < n; j++) {
        double d = BAND(j, 0);
        for (k = (j - bw > 0 ? j - bw : 0); k < j; k++)
            d -= BAND(j, j - k) * BAND(j, j - k) * BAND(k, 0);
        if (!(d > 0.0))
            return 0;
        BAND(j, 0) = d;
        for (i = j + 1; i < (n < j + bw + 1 ? n : j + bw + 1); i++) {
            double s = BAND(i, i - j);
            for (k = (i - bw > 0 ? i - bw : 0); k < j; k++)
                s -= BAND(i, i - k) * BAND(j, j - k) * BAND(k, 0);
            BAND(i, i - j) = s / d;
        }
    }
    return 1;
}

static void ldl_solve(const double *band, int64_t n, int64_t bw, double *x)
{
    int64_t i, k;
    for (i = 0; i < n; i++) {
        double s = x[i];
        for (k = (i - bw > 0 ? i - bw : 0); k < i; k++)
            s -= BAND(i, i - k) * x[k];
        x[i] = s;
    }
    for (i = 0; i < n; i++)
        x[i] /= BAND(i, 0);
    for (i = n - 1; i >= 0; i--) {
        double s = x[i];
        for (k = i + 1; k < (n < i + bw + 1 ? n : i + bw + 1); k++)
            s -= BAND(k, k - i) * x[k];
        x[i] = s;
    }
}

/* R = -M (a_g + a) - C_m v - forces at (u, v); each element's effective tangent into kk;
 * returns whether one changed */
static int residual(const Scene *s, Run *r, double ag, double c1)
{
    double *R = r->R;
    const double *u = r->u, *v = r->v;
    int stale = 0;
    int64_t i, e;
    for (i = 0; i < s->n; i++)
        R[i] = -s->mass[i] * (ag + r->a[i]) - s->damp[i] * v[i];
    for (e = 0; e < s->ns; e++) {
        const int64_t lo = s->s_lo[e], up = s->s_up[e];
        double d = u[up], rate = v[up], k = s->s_k[e], alpha = s->s_alpha[e];
        double reach, f, kt, centre, fd, kk;
        if (lo >= 0) {
            d -= u[lo];
            rate -= v[lo];
        }
        reach = (1.0 - alpha) * s->s_fy[e];
        f = r->s_force_c[e] + k * (d - r->s_def_c[e]);
        kt = k;
        centre = alpha * k * d;
        if (f > centre + reach) {
            f = centre + reach;
            kt = alpha * k;
        } else if (f < centre - reach) {
            f = centre - reach;
            kt = alpha * k;
        }
        r->s_def_t[e] = d;
        r->s_force_t[e] = f;
        r->s_d[e] = d;
        fd = s->s_a1[e] * kt * rate;
        r->s_f[e] = f;
        R[up] -= f + fd;
        if (lo >= 0)
            R[lo] += f + fd;
        kk = (kt + c1 * (0.0 + s->s_a1[e] * kt)) * 1.0;
        if (kk != r->s_kk[e]) {
            r->s_kk[e] = kk;
            stale = 1;
        }
    }
    for (e = 0; e < s->nc; e++) {
        const int64_t l = s->c_l[e], rr = s->c_r[e];
        const double d = (l >= 0 ? u[l] : 0.0) - (rr >= 0 ? u[rr] : 0.0) - s->c_gap[e];
        const double rate = (l >= 0 ? v[l] : 0.0) - (rr >= 0 ? v[rr] : 0.0);
        double f = 0.0, kd = 0.0, kr = 0.0, kk;
        if (d <= 0.0) {
            r->c_v0_t[e] = 0.0;
            r->c_on_t[e] = 0.0;
        } else {
            const double k = s->c_k[e], chi = s->c_chi[e];
            const double onset = r->c_on_c[e] == 0.0;
            const double v0 = onset ? rate : r->c_v0_c[e];
            const double spring = k * d, dspring = 1.0 * spring / d;
            r->c_v0_t[e] = v0;
            r->c_on_t[e] = 1.0;
            if (v0 <= 0.0 || chi == 0.0) {
                f = spring;
                kd = dspring;
            } else {
                const double ve2 = 2.0 * spring * d * s->c_invm[e] / 2.0;
                if (v0 * v0 >= ve2) {
                    if (onset) {
                        f = spring * (1.0 + chi);
                        kd = dspring * (1.0 + chi);
                    } else {
                        const double factor = 1.0 + chi * rate / v0;
                        if (factor > 0.0) {
                            f = spring * factor;
                            kd = dspring * factor;
                            kr = spring * chi / v0;
                        }
                    }
                } else {
                    const double damping = chi * spring / sqrt(ve2);
                    const double total = spring + damping * rate;
                    if (total > 0.0) {
                        f = total;
                        kd = dspring + 0.5 * 0.0 * damping * rate / d;
                        kr = damping;
                    }
                }
            }
        }
        r->c_f[e] = f;
        if (l >= 0)
            R[l] -= f;
        if (rr >= 0)
            R[rr] += f;
        kk = (kd + c1 * kr) * 1.0;
        if (kk != r->c_kk[e]) {
            r->c_kk[e] = kk;
            stale = 1;
        }
    }
    return stale;
}

static void factor(const Scene *s, Run *r, double c0, double c1)
{
    const int64_t n = s->n, bw = s->bw;
    double *band = r->band;
    int64_t i, e;
    memset(band, 0, sizeof(double) * (size_t)(n * (bw + 1)));
    for (i = 0; i < n; i++)
        BAND(i, 0) = s->mass[i] * c0 * 1.0 + s->damp[i] * c1 * 1.0;
    for (e = 0; e < s->ns; e++) {
        const int64_t lo = s->s_lo[e], up = s->s_up[e];
        const double kk = r->s_kk[e];
        BAND(up, 0) += kk;
        if (lo >= 0) {
            BAND(lo, 0) += kk;
            BAND(lo > up ? lo : up, lo > up ? lo - up : up - lo) -= kk;
        }
    }
    for (e = 0; e < s->nc; e++) {
        const int64_t l = s->c_l[e], rr = s->c_r[e];
        const double kk = r->c_kk[e];
        if (l >= 0)
            BAND(l, 0) += kk;
        if (rr >= 0)
            BAND(rr, 0) += kk;
        if (l >= 0 && rr >= 0)
            BAND(l > rr ? l : rr, l > rr ? l - rr : rr - l) -= kk;
    }
    if (!ldl_factor(band, n, bw)) {
        fprintf(stderr, "not definite\n");
        exit(1);
    }
}

static double *zeros(int64_t count) { return calloc((size_t)(count > 0 ? count : 1), sizeof(double)); }

/* Running peaks by an inline comparison, as a hand-written loop keeps them: libm's fmax is a
   call per value at -O2 without -ffast-math (its NaN rule keeps gcc from inlining it), which
   would slow this reference by about a tenth. The values here are finite (the run stops on
   a non-definite factor), so the comparison keeps the same peaks. */
static void keep_max(double *peak, const double *values, int64_t count)
{
    int64_t i;
    for (i = 0; i < count; i++) {
        const double v = fabs(values[i]);
        if (v > peak[i])
            peak[i] = v;
    }
}

static void keep_peaks(const Scene *s, Run *r)
{
    keep_max(r->peak_u, r->U, s->n);
    keep_max(r->peak_d, r->s_def_c, s->ns);
    keep_max(r->peak_f, r->c_f, s->nc);
}

/* The whole run; returns the Newton solves. */
static int64_t run(const Scene *s, Run *r)
{
    const int64_t n = s->n;
    const double h = s->dt, c0 = 1.0 / (s->beta * h * h), c1 = s->gamma / (s->beta * h);
    const double u_A = 0.5 * h * h - s->beta * h * h, u_a = s->beta * h * h;
    const double v_A = h * (1.0 - s->gamma), v_a = h * s->gamma;
    double mass_min = s->mass[0], inv_c0_mmin;
    double *U = r->U, *V = r->V, *A = r->A, *u = r->u, *v = r->v, *a = r->a, *R = r->R;
    int64_t i, k, it, solves = 0;
    for (i = 0; i < n; i++)
        mass_min = fmin(mass_min, s->mass[i]);
    inv_c0_mmin = 1.0 / (c0 * 1.0 * mass_min);
    for (i = 0; i < s->ns; i++)
        r->s_kk[i] = NAN;
    for (i = 0; i < s->nc; i++)
        r->c_kk[i] = NAN;
    /* t = 0: at rest, the acceleration from equilibrium */
    r->stale = 1;
    residual(s, r, s->ground[0], c1);
    for (i = 0; i < n; i++)
        r->A[i] = r->a[i] = r->R[i] / s->mass[i];
    memcpy(r->s_def_c, r->s_def_t, sizeof(double) * (size_t)s->ns);
    memcpy(r->s_force_c, r->s_force_t, sizeof(double) * (size_t)s->ns);
    memcpy(r->c_v0_c, r->c_v0_t, sizeof(double) * (size_t)s->nc);
    memcpy(r->c_on_c, r->c_on_t, sizeof(double) * (size_t)s->nc);
    keep_peaks(s, r);
    for (k = 1; k <= s->steps; k++) {
        /* the ground at the step's end as pframe interpolates it between the samples */
        const double ag = s->ground[k - 1] + (s->ground[k] - s->ground[k - 1]) * 1.0;
        int converged = 0;
        double norm_u = 0.0;
        memcpy(a, A, sizeof(double) * (size_t)n);
        for (it = 0; it < s->max_iter + 1; it++) {
            for (i = 0; i < n; i++) {
                u[i] = U[i] + (h * V[i] + u_A * A[i] + u_a * a[i]);
                v[i] = V[i] + v_A * A[i] + v_a * a[i];
            }
            r->stale |= residual(s, r, ag, c1);
            if (it > 0 && !converged) {
                double norm_r = 0.0;
                for (i = 0; i < n; i++)
                    norm_r += R[i] * R[i];
                converged = sqrt(norm_r) * inv_c0_mmin <= 1e-3 * (s->tol * sqrt(norm_u) + s->abs_tol);
            }
            if (converged)
                break;
            if (it == s->max_iter) {
                fprintf(stderr, "not converged at step %ld\n", (long)k);
                exit(1);
            }
            if (r->stale) {
                r->stale = 0;
                factor(s, r, c0, c1);
            }
            ldl_solve(r->band, n, s->bw, R);
            solves++;
            {
                double norm_du = 0.0;
                norm_u = 0.0;
                for (i = 0; i < n; i++) {
                    a[i] += c0 * R[i];
                    norm_du += R[i] * R[i];
                    norm_u += (u[i] + R[i]) * (u[i] + R[i]);
                }
                converged = sqrt(norm_du) <= s->tol * sqrt(norm_u) + s->abs_tol;
            }
        }
        memcpy(U, u, sizeof(double) * (size_t)n);
        memcpy(V, v, sizeof(double) * (size_t)n);
        memcpy(A, a, sizeof(double) * (size_t)n);
        memcpy(r->s_def_c, r->s_def_t, sizeof(double) * (size_t)s->ns);
        memcpy(r->s_force_c, r->s_force_t, sizeof(double) * (size_t)s->ns);
        memcpy(r->c_v0_c, r->c_v0_t, sizeof(double) * (size_t)s->nc);
        memcpy(r->c_on_c, r->c_on_t, sizeof(double) * (size_t)s->nc);
        keep_peaks(s, r);
    }
    return solves;
}

static Run fresh(const Scene *s)
{
    Run r;
    r.U = zeros(s->n); r.V = zeros(s->n); r.A = zeros(s->n);
    r.u = zeros(s->n); r.v = zeros(s->n); r.a = zeros(s->n); r.R = zeros(s->n);
    r.band = zeros(s->n * (s->bw + 1));
    r.s_d = zeros(s->ns); r.s_f = zeros(s->ns); r.s_kk = zeros(s->ns);
    r.s_def_c = zeros(s->ns); r.s_force_c = zeros(s->ns);
    r.s_def_t = zeros(s->ns); r.s_force_t = zeros(s->ns);
    r.c_f = zeros(s->nc); r.c_kk = zeros(s->nc);
    r.c_v0_c = zeros(s->nc); r.c_on_c = zeros(s->nc);
    r.c_v0_t = zeros(s->nc); r.c_on_t = zeros(s->nc);
    r.peak_u = zeros(s->n); r.peak_d = zeros(s->ns); r.peak_f = zeros(s->nc);
    return r;
}

int main(int argc, char **argv)
{
    Scene s;
    Run r;
    int repeats = argc > 2 ? atoi(argv[2]) : 5, k;
    double best = INFINITY;
    int64_t i, solves = 0;
    if (argc < 2) {
        fprintf(stderr, "usage: kernel_limit INPUT [REPEATS]\n");
        return 2;
    }
    s = read_scene(argv[1]);
    for (k = 0; k < repeats; k++) {
        struct timespec t0, t1;
        r = fresh(&s);
        clock_gettime(CLOCK_MONOTONIC, &t0);
        solves = run(&s, &r);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        best = fmin(best, (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    }
    printf("%.3f\n%ld\n", best / (double)s.steps * 1e9, (long)solves);
    for (i = 0; i < s.n; i++)
        printf("%.17g\n", r.peak_u[i]);
    for (i = 0; i < s.ns; i++)
        printf("%.17g\n", r.peak_d[i]);
    for (i = 0; i < s.nc; i++)
        printf("%.17g\n", r.peak_f[i]);
    return 0;
}
