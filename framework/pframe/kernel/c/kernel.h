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

/* The displacement (or velocity) of one side of contact e: its node's, or for a floor-to-column
 * contact the point of the struck column, psi x_upper + (1 - psi) x_lower (assembly.c). */
static int plain_side(const Model *m, int64_t b, int64_t e, int side)
{
    return m->contact_lower[2 * e + side] < 0
           && m->contact_share[(b * m->contacts + e) * 2 + side] == 1.0;
}

/* A contact between two floors (or a floor and a wall): no column on either side. */
static int plain_contact(const Model *m, int64_t b, int64_t e)
{
    return plain_side(m, b, e, 0) && plain_side(m, b, e, 1);
}

static double contact_side(const Model *m, const double *x, int64_t b, int64_t e, int side)
{
    const int64_t node = m->contact_dofs[2 * e + side], lower = m->contact_lower[2 * e + side];
    if (plain_side(m, b, e, side))
        return dof_value(x, node);
    {
        const double psi = m->contact_share[(b * m->contacts + e) * 2 + side];
        return psi * dof_value(x, node) + (1.0 - psi) * dof_value(x, lower);
    }
}

/* functions used before the file that defines them */
static int solve_step(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                      int64_t k, double h, double ag_old, double ag_new);
static int commit(const Model *m, const Settings *s, State *st, Work *w, int64_t b,
                  int64_t k, double h, double ag_old, double ag_new);

#endif
