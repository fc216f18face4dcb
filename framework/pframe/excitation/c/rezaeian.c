/* The time-varying filter of the Rezaeian & Der Kiureghian (2008) stochastic ground motion
 * model, compiled (pframe.excitation.stochastic calls it through ctypes, which releases the
 * GIL, so that motions are generated on a thread beside the kernel's).
 *
 *   total[k] = sum_{i<k} h(k - i, omega_i) u_i,   norm[k] = sum_{i<k} h(k - i, omega_i)^2,
 *   h(m, w) = w / r exp(-zeta w m dt) sin(w r m dt),   r = sqrt(1 - zeta^2),
 *
 * pulse by pulse as s_m = (w / r) z^m, z = exp((-zeta + i r) w dt), h = Im s_m: one complex
 * multiplication a lag instead of an exp and a sin. s is set again from exp, cos and sin every
 * RESEED lags, so that its roundoff stays that of a few multiplications. A pulse's lags end
 * where zeta w m dt exceeds `cutoff` (its terms are then below e^-cutoff of its first).
 * omega must be monotonic (it is: a linear function held at a floor), so that the pulses still
 * running at lag m are a contiguous range; the loop over them vectorises. */

#ifndef Py_LIMITED_API
#define Py_LIMITED_API 0x030A0000
#endif
#include <Python.h>
#include <math.h>
#include <stdint.h>

#define RESEED 64

#if defined(_WIN32)
#define EXPORT __declspec(dllexport)
#else
#define EXPORT __attribute__((visibility("default")))
#endif

/* the loops over pulses in 4-wide vectors where the CPU has AVX2 (chosen at load time; the
 * same arithmetic, so the same results, as the 2-wide baseline) */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define VECTOR_CLONES
#endif

/* work: 4 n doubles (the pulses' states and multipliers). Returns the number of lags. */
VECTOR_CLONES EXPORT int64_t pframe_rezaeian_filter(int64_t n, double dt, double zeta, double cutoff,
                                      const double *restrict omega, const double *restrict u,
                                      double *restrict total,
                                      double *restrict norm, double *restrict work) {
    double root = sqrt(1.0 - zeta * zeta);
    double *restrict sr = work, *restrict si = work + n, *restrict zr = work + 2 * n,
           *restrict zi = work + 3 * n;
    int64_t lo = 0, hi = n, m, i;
    for (i = 0; i < n; i++) {
        double w = omega[i], d = exp(-zeta * w * dt);
        zr[i] = d * cos(w * root * dt);
        zi[i] = d * sin(w * root * dt);
        sr[i] = w / root;
        si[i] = 0.0;
        total[i] = 0.0;
        norm[i] = 0.0;
    }
    for (m = 1; m < n; m++) {
        if (hi > n - m) hi = n - m;
        while (lo < hi && zeta * omega[lo] * dt * (double)m > cutoff) lo++;
        while (hi > lo && zeta * omega[hi - 1] * dt * (double)m > cutoff) hi--;
        if (lo >= hi) break;
        {
            double *restrict t = total + m, *restrict q = norm + m;
            if (m % RESEED == 0) {
                for (i = lo; i < hi; i++) {
                    double w = omega[i], a = w / root * exp(-zeta * w * dt * (double)m);
                    sr[i] = a * cos(w * root * dt * (double)m);
                    si[i] = a * sin(w * root * dt * (double)m);
                    t[i] += si[i] * u[i];
                    q[i] += si[i] * si[i];
                }
            } else {
                for (i = lo; i < hi; i++) {
                    double re = sr[i] * zr[i] - si[i] * zi[i];
                    double im = sr[i] * zi[i] + si[i] * zr[i];
                    sr[i] = re;
                    si[i] = im;
                    t[i] += im * u[i];
                    q[i] += im * im;
                }
            }
        }
    }
    return m;
}

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cstochastic",
    "the compiled filter of pframe's stochastic ground motions (called through ctypes: "
    "pframe.excitation.stochastic)",
    -1, NULL, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__cstochastic(void) { return PyModule_Create(&module); }
