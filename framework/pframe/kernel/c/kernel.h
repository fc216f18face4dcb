/* pframe's time-stepping kernel: what every file of it shares.
 *
 * The kernel is compiled as one unit (kernel.c includes each file in turn), so that every
 * function is static and the compiler inlines across files as numba did. C99, no VLAs, no
 * compiler extensions: gcc, clang and MSVC compile it alike. IEEE arithmetic (no fast-math, no
 * contraction into fused multiply-adds), in the order the Python reference wrote it, so that
 * results agree with the laws' Python definitions to the last bit where the operations are
 * the same.
 *
 * Names follow pframe/kernel/state.py (m: Model, s: Settings, st: State, rec: Recording,
 * w: Work, sv: Saved, b: batch member, k: step, h: step length); the structs and slot names
 * are generated from it into state.h.
 */

#ifndef PFRAME_KERNEL_H
#define PFRAME_KERNEL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "state.h"

#if defined(_WIN32)
#define PFRAME_EXPORT __declspec(dllexport)
#elif defined(__GNUC__)
#define PFRAME_EXPORT __attribute__((visibility("default")))
#else
#define PFRAME_EXPORT
#endif

/* a function the compiler copies into its callers (the law dispatch of the element loops) */
#if defined(_MSC_VER)
#define PFRAME_INLINE __forceinline
#elif defined(__GNUC__)
#define PFRAME_INLINE inline __attribute__((always_inline))
#else
#define PFRAME_INLINE inline
#endif

/* a function kept out of its callers (a law group's loop: assembly.c) */
#if defined(_MSC_VER)
#define PFRAME_NOINLINE __declspec(noinline)
#elif defined(__GNUC__)
#define PFRAME_NOINLINE __attribute__((noinline))
#else
#define PFRAME_NOINLINE
#endif

/* the version of the interface between the driver (pframe/kernel/ckernel.py) and the kernel */
#define PFRAME_KERNEL_INTERFACE 1

/* Python's max(a, b) and min(a, b) of floats (the first unless the second is larger/smaller) */
static double py_max(double a, double b) { return b > a ? b : a; }
static double py_min(double a, double b) { return b < a ? b : a; }
static int64_t imax(int64_t a, int64_t b) { return a > b ? a : b; }
static int64_t imin(int64_t a, int64_t b) { return a < b ? a : b; }
static int64_t iabs(int64_t a) { return a < 0 ? -a : a; }
/* x[i] of a DOF, or 0 for the ground (-1): a storey's lower end, a wall's side */
static double dof_value(const double *x, int64_t i) { return i >= 0 ? x[i] : 0.0; }

/* Elements act along a direction at a point of each side (pframe/assemble/incidence.py). A
 * plain element (no terms) joins its two DOFs of *_dofs with coefficient 1; any other has its
 * sides as terms: side s of element e is sum coef[t] x[dof[t]], t = start[2e+s] ..
 * start[2e+s+1] (coef offset to the member: coef + b * terms). */
static int general(const int64_t *start, int64_t e) { return start[2 * e + 2] > start[2 * e]; }

/* first side's terms times sign_first plus the second side's times sign_second, summed term
 * by term in that order (a storey on soil: (u_upper - u_lower) - h theta, as written) */
static PFRAME_INLINE double sides_sum(const int64_t *start, const int64_t *dof,
                                      const double *coef, int64_t e, int first, const double *x)
{
    double sum = 0.0;
    int64_t t;
    for (t = start[2 * e + first]; t < start[2 * e + first + 1]; t++)
        sum += coef[t] * x[dof[t]];
    for (t = start[2 * e + 1 - first]; t < start[2 * e + 2 - first]; t++)
        sum -= coef[t] * x[dof[t]];
    return sum;
}

/* sides_sum of x and of y in one pass over the terms (an element's deformation and its rate:
 * each sum in the same order as sides_sum's, so the same bits) */
static PFRAME_INLINE void sides_sum2(const int64_t *start, const int64_t *dof,
                                     const double *coef, int64_t e, int first, const double *x,
                                     const double *y, double *sx, double *sy)
{
    const int64_t add_from = start[2 * e + first], add_to = start[2 * e + first + 1];
    const int64_t sub_from = start[2 * e + 1 - first], sub_to = start[2 * e + 2 - first];
    double a = 0.0, c = 0.0;
    int64_t t;
    for (t = add_from; t < add_to; t++) {
        const double k = coef[t];
        const int64_t i = dof[t];
        a += k * x[i];
        c += k * y[i];
    }
    for (t = sub_from; t < sub_to; t++) {
        const double k = coef[t];
        const int64_t i = dof[t];
        a -= k * x[i];
        c -= k * y[i];
    }
    *sx = a;
    *sy = c;
}

/* R[dof] += w_s coef over both sides of element e, side s_first first (an element's force on
 * its sides' DOFs; the bounds read once, as the stores into R cannot change them) */
static PFRAME_INLINE void sides_add(double *R, const int64_t *start, const int64_t *dof,
                                    const double *coef, int64_t e, int s_first, double w_first,
                                    double w_second)
{
    const int64_t a_from = start[2 * e + s_first], a_to = start[2 * e + s_first + 1];
    const int64_t b_from = start[2 * e + 1 - s_first], b_to = start[2 * e + 2 - s_first];
    int64_t t;
    for (t = a_from; t < a_to; t++)
        R[dof[t]] += coef[t] * w_first;
    for (t = b_from; t < b_to; t++)
        R[dof[t]] += coef[t] * w_second;
}

/* The ground displacements' part of element e's deformation (docs/supports.md): sum of
 * coef[t] g[channel[t]] over its ground terms, with g a block of the ground's series (the
 * displacements, or the velocities for its rate); 0 for an element on one support. */
static PFRAME_INLINE double ground_sum(const int64_t *start, const int64_t *channel,
                                       const double *coef, int64_t e, const double *g)
{
    double sum = 0.0;
    int64_t t;
    for (t = start[e]; t < start[e + 1]; t++)
        sum += coef[t] * g[channel[t]];
    return sum;
}

/* The deformation of spring e at x: upper (second) side less lower (first), plus across
 * supports the ground displacements' part from g (the ground's displacements at x's time;
 * NULL: none, the element on one support). */
static double spring_deformation(const Model *m, int64_t b, int64_t e, const double *x,
                                 const double *g)
{
    double d;
    if (general(m->story_side_start, e))
        d = sides_sum(m->story_side_start, m->story_side_dof,
                      m->story_side_coef + b * m->story_terms, e, 1, x);
    else
        d = x[m->story_dofs[2 * e + 1]] - dof_value(x, m->story_dofs[2 * e]);
    if (g != NULL && m->story_ground_terms)
        d += ground_sum(m->story_ground_start, m->story_ground_channel,
                        m->story_ground_coef + b * m->story_ground_terms, e, g);
    return d;
}

/* How far contact e's sides have closed at x: left less right (before the gap), plus
 * across supports the ground displacements' part from g (as spring_deformation). */
static double contact_closing(const Model *m, int64_t b, int64_t e, const double *x,
                              const double *g)
{
    double d;
    if (general(m->contact_side_start, e))
        d = sides_sum(m->contact_side_start, m->contact_side_dof,
                      m->contact_side_coef + b * m->contact_terms, e, 0, x);
    else
        d = dof_value(x, m->contact_dofs[2 * e]) - dof_value(x, m->contact_dofs[2 * e + 1]);
    if (g != NULL && m->contact_ground_terms)
        d += ground_sum(m->contact_ground_start, m->contact_ground_channel,
                        m->contact_ground_coef + b * m->contact_ground_terms, e, g);
    return d;
}

/* The ground's displacements (block 1) and velocities (block 2) within its series g, or NULL
 * without elements across supports. */
static const double *ground_block(const Model *m, const double *g, int64_t block)
{
    return m->ground_series > m->channels ? g + block * m->channels : NULL;
}

/* The ground acceleration that loads DOF i, from the channels' values g: that of its channel
 * (m->dof_channel), 0 for a rotation or a foundation's rocking (-1). */
static double dof_ground(const Model *m, int64_t i, const double *g)
{
    const int64_t c = m->dof_channel[i];
    return c >= 0 ? g[c] : 0.0;
}

/* out = wa a + wb b, series by series: the ground between two times */
static void ground_mix(const Model *m, double *out, double wa, const double *a, double wb,
                       const double *b)
{
    int64_t c;
    for (c = 0; c < m->ground_series; c++)
        out[c] = wa * a[c] + wb * b[c];
}

/* functions used before the file that defines them */
static int solve_step(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                      int64_t k, double h, const double *ag_old, const double *ag_new);
static int commit(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                  int64_t k, double h, const double *ag_old, const double *ag_new);

#endif
