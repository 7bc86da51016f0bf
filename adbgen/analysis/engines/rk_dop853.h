/* One DOP853 step and its dense output, written once over an element type so the scalar driver
 * (rk_driver.c: RK_T double) and the ensemble driver (rk_batch_driver.c: RK_T adb_lanes, a vector of
 * trajectories) run the same arithmetic.  Hairer, Norsett & Wanner, Solving ODEs I, sec. II.10 (the
 * 8(5,3) pair and its 7th-order continuous extension), with scipy's/CyRK's error norm (the 5th- and
 * 3rd-order estimates combined as err5^2 / sqrt(err5^2 + 0.01 err3^2), root mean square over states).
 *
 * The includer defines RK_T, RK_NY, RK_ABS(x), RK_MAX(a, b) and RK_RHS(t, y, f) (a statement evaluating
 * the model's rhs: compiled in this translation unit, no call through a pointer).  Zero tableau entries
 * are skipped (the rest is summed in increasing stage order).
 */
#ifndef ADB_RK_DOP853_H
#define ADB_RK_DOP853_H

#include "dop853_tableau.h"

/* Stages of a step of size h from (t, y), K[0] = f(t, y) on entry: K[1..11], ynew (8th order), K[12] =
 * f(t + h, ynew) (the next step's K[0]); e5, e3: the sums over states of the squared scaled error
 * estimates (scale atol + max(|y|, |ynew|) rtol), from which the caller forms the norm per trajectory. */
static inline void dop_step(RK_T t, RK_T h, const RK_T *y, RK_T (*K)[RK_NY], RK_T *ynew, double rtol, double atol,
                            RK_T *e5, RK_T *e3, const void *ctx)
{
    (void)ctx;
    RK_T z[RK_NY], acc[RK_NY];
    /* unrolled: the tableau's entries become constants and its zeros vanish at compile time */
#pragma GCC unroll 16
    for (int s = 1; s < DOP_STAGES; ++s) {
        for (int i = 0; i < RK_NY; ++i) acc[i] = dop_a[s][0] * K[0][i];
#pragma GCC unroll 16
        for (int j = 1; j < s; ++j) {
            if (dop_a[s][j] == 0.0) continue;
            for (int i = 0; i < RK_NY; ++i) acc[i] += dop_a[s][j] * K[j][i];
        }
        for (int i = 0; i < RK_NY; ++i) z[i] = y[i] + acc[i] * h;
        RK_RHS(t + dop_c[s] * h, z, K[s]);
    }
    for (int i = 0; i < RK_NY; ++i) acc[i] = dop_b[0] * K[0][i];
#pragma GCC unroll 16
    for (int j = 1; j < DOP_STAGES; ++j) {
        if (dop_b[j] == 0.0) continue;
        for (int i = 0; i < RK_NY; ++i) acc[i] += dop_b[j] * K[j][i];
    }
    for (int i = 0; i < RK_NY; ++i) ynew[i] = y[i] + h * acc[i];
    RK_RHS(t + h, ynew, K[DOP_STAGES]);
    RK_T s5 = 0.0 * h, s3 = 0.0 * h;
    for (int i = 0; i < RK_NY; ++i) {
        RK_T a5 = 0.0 * h, a3 = 0.0 * h;
#pragma GCC unroll 16
        for (int j = 0; j <= DOP_STAGES; ++j) {
            if (dop_e5[j] != 0.0) a5 += dop_e5[j] * K[j][i];
            if (dop_e3[j] != 0.0) a3 += dop_e3[j] * K[j][i];
        }
        RK_T sc = atol + RK_MAX(RK_ABS(y[i]), RK_ABS(ynew[i])) * rtol;
        a5 = a5 / sc, a3 = a3 / sc;
        s5 += a5 * a5, s3 += a3 * a3;
    }
    *e5 = s5, *e3 = s3;
}

/* The 7th-order interpolant of the step (t, y) -> (t + h, ynew) whose stages are K[0..12]: the three extra
 * stages into K[13..15], then F[0..6] (scipy's Dop853DenseOutput form): y(t + x h) = y + x(F0 + (1-x)(F1 +
 * x(F2 + (1-x)(F3 + x(F4 + (1-x)(F5 + x F6)))))). */
static inline void dop_dense(RK_T t, RK_T h, const RK_T *y, const RK_T *ynew, RK_T (*K)[RK_NY], RK_T (*F)[RK_NY],
                             const void *ctx)
{
    (void)ctx;
    RK_T z[RK_NY];
    for (int s = DOP_STAGES + 1; s < DOP_EXTENDED; ++s) {
        for (int i = 0; i < RK_NY; ++i) {
            RK_T acc = dop_a[s][0] * K[0][i];
            for (int j = 1; j < s; ++j)
                if (dop_a[s][j] != 0.0) acc += dop_a[s][j] * K[j][i];
            z[i] = y[i] + acc * h;
        }
        RK_RHS(t + dop_c[s] * h, z, K[s]);
    }
    for (int i = 0; i < RK_NY; ++i) {
        RK_T dy = ynew[i] - y[i];
        F[0][i] = dy;
        F[1][i] = h * K[0][i] - dy;
        F[2][i] = 2.0 * dy - h * (K[DOP_STAGES][i] + K[0][i]);
        for (int r = 0; r < 4; ++r) {
            RK_T acc = dop_d[r][0] * K[0][i];
            for (int j = 1; j < DOP_EXTENDED; ++j)
                if (dop_d[r][j] != 0.0) acc += dop_d[r][j] * K[j][i];
            F[3 + r][i] = h * acc;
        }
    }
}

/* scipy's step-size controller (safety 0.9, factors in [0.2, 10], exponent -1/8): the factor for the next
 * step from the error norm, and the norm from dop_step's sums.  err^(-1/8) as 1 / sqrt(sqrt(sqrt(err)))
 * (three correctly rounded square roots instead of pow: a few ulp apart, a tenth of the time). */
static inline double dop_root8(double err) { return 1.0 / sqrt(sqrt(sqrt(err))); }
#define DOP_SAFETY 0.9
#define DOP_MIN_FACTOR 0.2
#define DOP_MAX_FACTOR 10.0

static inline double dop_norm(double h, double e5, double e3)
{
    if (e5 == 0.0 && e3 == 0.0) return 0.0;
    return fabs(h) * e5 / sqrt((e5 + 0.01 * e3) * RK_NY);
}

static inline double dop_factor(double err, int rejected)
{
    double f;
    if (err < 1.0) {
        f = err == 0.0 ? DOP_MAX_FACTOR : fmin(DOP_MAX_FACTOR, DOP_SAFETY * dop_root8(err));
        if (rejected) f = fmin(1.0, f);
    } else
        f = fmax(DOP_MIN_FACTOR, DOP_SAFETY * dop_root8(err));
    return f;
}

#endif
