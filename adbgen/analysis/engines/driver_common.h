/* What the compiled engines' drivers share (and variational_driver.c, outside the interface): the C
 * interface (adb_engine.h), status codes, the rotor amplitude, early-stop target regions.  The event
 * measures r_max and t_dec are event_measures.h's, included after this by the drivers that report them.
 * Included after the model's generated C source, with ADB_NY defined. */
#ifndef ADB_DRIVER_COMMON_H
#define ADB_DRIVER_COMMON_H

#include <math.h>
#include <stddef.h>

#include "adb_engine.h"

/* status codes, mirrored in adbgen/analysis/engines/c_interface.py (STATUS) */
#define ADB_SUCCESS 0
#define ADB_MAX_STEPS 1
#define ADB_STEP_UNDERFLOW 2
#define ADB_NONFINITE 3
#define ADB_SOLVER_FAILURE 4
#define ADB_STOPPED 5 /* reached a target region (early stop), not a failure */
#define ADB_BAD_INPUT 6

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* squared rotor amplitude x^2 + y^2 of the first two core coordinates */
static inline double adb_r2(const double *y, int ix, int iy) { return y[ix] * y[ix] + y[iy] * y[iy]; }

static inline int adb_all_finite(const double *y, int n)
{
    for (int i = 0; i < n; ++i)
        if (!isfinite(y[i])) return 0;
    return 1;
}

/* Index of the first target region holding y, or -1.  Region k: e'W_k e <= 1 and e'W_k e + K_k(e, e, e)
 * <= level_k, e = y - c_k with the angles (periodic[i] != 0) wrapped to [-pi, pi]; W_k (ADB_NY x ADB_NY,
 * row-major) is weights + k ADB_NY^2, K_k (ADB_NY^3) cubics + k ADB_NY^3 (NULL: no cubic terms), level_k
 * levels[k] (NULL: 1).  Weights w_i give W = diag(w_i^2), the ball inscribed in the box |e_i| w_i <= 1.
 * The sweeps' stop regions of stable steady states (attractors.StopRegion.target). */
static int adb_in_target(const double *y, int n_targets, const double *centres, const double *weights,
                         const double *cubics, const double *levels, const unsigned char *periodic)
{
    for (int k = 0; k < n_targets; ++k) {
        const double *c = centres + (size_t)k * ADB_NY, *W = weights + (size_t)k * ADB_NY * ADB_NY;
        double e[ADB_NY], q = 0.0;
        for (int i = 0; i < ADB_NY; ++i) {
            e[i] = y[i] - c[i];
            if (periodic && periodic[i]) e[i] = remainder(e[i], 2.0 * M_PI);
        }
        for (int i = 0; i < ADB_NY; ++i) {
            double row = 0.0;
            for (int j = 0; j < ADB_NY; ++j) row += W[(size_t)i * ADB_NY + j] * e[j];
            q += e[i] * row;
        }
        if (q > 1.0) continue;
        double v = q;
        if (cubics) {
            const double *K = cubics + (size_t)k * ADB_NY * ADB_NY * ADB_NY;
            for (int i = 0; i < ADB_NY; ++i)
                for (int j = 0; j < ADB_NY; ++j) {
                    double inner = 0.0;
                    for (int l = 0; l < ADB_NY; ++l) inner += K[((size_t)i * ADB_NY + j) * ADB_NY + l] * e[l];
                    v += e[i] * e[j] * inner;
                }
        }
        if (v <= (levels ? levels[k] : 1.0)) return k;
    }
    return -1;
}

#endif
