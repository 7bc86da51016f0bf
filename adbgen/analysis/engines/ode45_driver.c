/* `matlab-ode45`: an emulation of MATLAB's ode45 (the thesis' integrator, ch. 5) on a generated model's C
 * library, for explaining published numbers (docs/matlab-ode45.md).  Not a recommended integrator.
 *
 * What it reproduces of ode45 (MATLAB 7, default options, `[t, y] = ode45(f, [0 t_end], y0)`):
 *   - Dormand-Prince 5(4) with local extrapolation and FSAL; the stages as ode45 forms them, y + f*hB(:,i)
 *     with hB = h*B (the coefficient products rounded first, the stage sum over all seven columns in order);
 *   - the error estimate err = absh * || (f*E) ./ max(max(|y|, |ynew|), threshold) ||_inf with
 *     threshold = AbsTol/RelTol (no NormControl), accepted when err <= RelTol;
 *   - the initial step: absh = min(hmax, htspan), rh = ||f0 ./ max(|y0|, threshold)||_inf / (0.8 rtol^(1/5)),
 *     absh = 1/rh where absh*rh > 1; hmax = 0.1 |t_end - t0| (MaxStep), hmin = 16 eps(t);
 *   - the step control: after a failure absh = max(hmin, absh max(0.1, 0.8 (rtol/err)^(1/5))), after a second
 *     failure of the same step max(hmin, absh/2); after an accepted step with no failure
 *     absh = absh / max(0.2, 1.25 (err/rtol)^(1/5)); the last step stretched when 1.1 absh >= t_end - t;
 *   - the output: Refine = 4, each step's end and the three points at s = 1/4, 1/2, 3/4 of it from ntrp45
 *     (the interpolant y + f*(h*BI)*[s; s^2; s^3; s^4]).
 * r_max and t_dec are read off those output points, as a MATLAB user reads them off the returned [t, y]:
 * r_max = max r(t_i), t_dec = the last t_i with r(t_i) >= threshold (0 when none).
 *
 * Compiled by adbgen.analysis.engines.compiled like the other drivers (-DADB_MODEL_SOURCE, ADB_RHS,
 * ADB_NY, ADB_NP); the libm the model calls is the pinned one of fixed_libm.h.
 */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"

#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct {
    double *t, *y;
    long k;
} Ode45Trajectory;

/* MATLAB's eps(t): the distance from |t| to the next larger double (eps(0) = 2^-1074) */
static double matlab_eps(double t)
{
    double a = fabs(t);
    if (a == 0.0) return 4.9406564584124654e-324;
    return nextafter(a, INFINITY) - a;
}

static const double A[6] = {1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0};
/* B(j, i): row j (stage column f(:, j)), column i (which stage it forms) */
static const double B[7][6] = {
    {1.0 / 5.0, 3.0 / 40.0, 44.0 / 45.0, 19372.0 / 6561.0, 9017.0 / 3168.0, 35.0 / 384.0},
    {0.0, 9.0 / 40.0, -56.0 / 15.0, -25360.0 / 2187.0, -355.0 / 33.0, 0.0},
    {0.0, 0.0, 32.0 / 9.0, 64448.0 / 6561.0, 46732.0 / 5247.0, 500.0 / 1113.0},
    {0.0, 0.0, 0.0, -212.0 / 729.0, 49.0 / 176.0, 125.0 / 192.0},
    {0.0, 0.0, 0.0, 0.0, -5103.0 / 18656.0, -2187.0 / 6784.0},
    {0.0, 0.0, 0.0, 0.0, 0.0, 11.0 / 84.0},
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}};
static const double E[7] = {71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0,
                            22.0 / 525.0, -1.0 / 40.0};
/* ntrp45's BI (7 x 4) */
static const double BI[7][4] = {
    {1.0, -183.0 / 64.0, 37.0 / 12.0, -145.0 / 128.0},
    {0.0, 0.0, 0.0, 0.0},
    {0.0, 1500.0 / 371.0, -1000.0 / 159.0, 1000.0 / 371.0},
    {0.0, -125.0 / 32.0, 125.0 / 12.0, -375.0 / 64.0},
    {0.0, 9477.0 / 3392.0, -729.0 / 106.0, 25515.0 / 6784.0},
    {0.0, -11.0 / 7.0, 11.0 / 3.0, -55.0 / 28.0},
    {0.0, 3.0 / 2.0, -4.0, 5.0 / 2.0}};

typedef struct {
    double *T, *Y;
    size_t k, cap;
    int keep;
    int ix, iy;
    double H2, r2max, t_dec;
} Output;

static void emit(Output *o, double t, const double *y)
{
    double r2 = adb_r2(y, o->ix, o->iy);
    if (r2 > o->r2max) o->r2max = r2;
    if (r2 >= o->H2) o->t_dec = t;
    if (!o->keep) return;
    if (o->k == o->cap) {
        o->cap *= 2;
        o->T = realloc(o->T, o->cap * sizeof(double));
        o->Y = realloc(o->Y, o->cap * ADB_NY * sizeof(double));
    }
    o->T[o->k] = t;
    memcpy(o->Y + o->k * ADB_NY, y, sizeof(double) * ADB_NY);
    ++o->k;
}

/* y + f*(hB(:, col)): the seven products in column order, summed from zero, then added to y */
static void stage_state(const double *y, double f[7][ADB_NY], const double *hB_col, double *out)
{
    for (int i = 0; i < ADB_NY; ++i) {
        double s = 0.0;
        for (int j = 0; j < 7; ++j) s += f[j][i] * hB_col[j];
        out[i] = y[i] + s;
    }
}

/* Returns a status code; out_stats: [r_max, t_dec, t_last, t_fail]; out_counts: [rhs evaluations, steps]. */
int adb_ode45_integrate(const double *y0, const double *p, double t_end, double rtol, double atol, long max_steps,
                        const int *amp_idx, double threshold, int keep, Ode45Trajectory *traj, double *y_end,
                        double *out_stats, long *out_counts)
{
    out_stats[0] = out_stats[1] = out_stats[2] = out_stats[3] = NAN;
    out_counts[0] = out_counts[1] = 0;
    if (traj) traj->t = traj->y = NULL, traj->k = 0;
    if (!(t_end > 0.0) || !(rtol > 0.0) || !(atol > 0.0) || !adb_all_finite(y0, ADB_NY)) return ADB_BAD_INPUT;
    if (rtol < 100.0 * DBL_EPSILON) rtol = 100.0 * DBL_EPSILON; /* as odearguments does (with a warning) */

    Output o = {NULL, NULL, 0, 1024, keep && traj, amp_idx[0], amp_idx[1], threshold * threshold, 0.0, 0.0};
    if (o.keep) {
        o.T = malloc(o.cap * sizeof(double));
        o.Y = malloc(o.cap * ADB_NY * sizeof(double));
    }
    const double pw = 1.0 / 5.0, t0 = 0.0, tfinal = t_end;
    const double threshold_w = atol / rtol;
    const double hmax = fmin(fabs(tfinal - t0), 0.1 * fabs(tfinal - t0));
    const double htspan = fabs(tfinal - t0);
    double t = t0, y[ADB_NY], ynew[ADB_NY], ys[ADB_NY], f[7][ADB_NY];
    memcpy(y, y0, sizeof y);
    memset(f, 0, sizeof f);
    long nfev = 0, nsteps = 0;
    int status = ADB_SUCCESS;
    ADB_RHS(t, y, p, f[0]);
    ++nfev;
    emit(&o, t, y);

    double hmin = 16.0 * matlab_eps(t);
    double absh = fmin(hmax, htspan);
    double rh = 0.0;
    for (int i = 0; i < ADB_NY; ++i) rh = fmax(rh, fabs(f[0][i] / fmax(fabs(y[i]), threshold_w)));
    rh = rh / (0.8 * pow(rtol, pw));
    if (absh * rh > 1.0) absh = 1.0 / rh;
    absh = fmax(absh, hmin);

    int done = 0;
    while (!done) {
        hmin = 16.0 * matlab_eps(t);
        absh = fmin(hmax, fmax(hmin, absh));
        double h = absh;
        if (1.1 * absh >= fabs(tfinal - t)) {
            h = tfinal - t;
            absh = fabs(h);
            done = 1;
        }
        int nofailed = 1;
        double err, tnew;
        for (;;) {
            double hA[6], hB[6][7];
            for (int i = 0; i < 6; ++i) {
                hA[i] = h * A[i];
                for (int j = 0; j < 7; ++j) hB[i][j] = h * B[j][i];
            }
            for (int i = 0; i < 5; ++i) {
                stage_state(y, f, hB[i], ys);
                ADB_RHS(t + hA[i], ys, p, f[i + 1]);
            }
            tnew = t + hA[5];
            if (done) tnew = tfinal;
            h = tnew - t; /* purify h */
            stage_state(y, f, hB[5], ynew);
            ADB_RHS(tnew, ynew, p, f[6]);
            nfev += 6;
            err = 0.0;
            for (int i = 0; i < ADB_NY; ++i) {
                double fe = 0.0;
                for (int j = 0; j < 7; ++j) fe += f[j][i] * E[j];
                err = fmax(err, fabs(fe / fmax(fmax(fabs(y[i]), fabs(ynew[i])), threshold_w)));
            }
            err = absh * err;
            if (!(err <= rtol)) {
                if (!isfinite(err) && !adb_all_finite(ynew, ADB_NY) && absh <= hmin) {
                    status = ADB_NONFINITE;
                    out_stats[3] = t;
                    goto finish;
                }
                if (absh <= hmin) {
                    status = ADB_STEP_UNDERFLOW;
                    out_stats[3] = t;
                    goto finish;
                }
                if (nofailed) {
                    nofailed = 0;
                    double q = isfinite(err) ? 0.8 * pow(rtol / err, pw) : 0.0;
                    absh = fmax(hmin, absh * fmax(0.1, q));
                } else
                    absh = fmax(hmin, 0.5 * absh);
                h = absh;
                done = 0;
            } else
                break;
        }
        ++nsteps;
        /* Refine = 4: ntrp45 at s = 1/4, 1/2, 3/4 of the step, then the step's end */
        for (int r = 1; r < 4; ++r) {
            double tref = t + (tnew - t) * (r / 4.0), s = (tref - t) / h, cs[4] = {s, s * s, s * s * s, s * s * s * s};
            double yi[ADB_NY];
            for (int i = 0; i < ADB_NY; ++i) {
                double acc = 0.0;
                for (int k = 0; k < 4; ++k) {
                    double fhbi = 0.0;
                    for (int j = 0; j < 7; ++j) fhbi += f[j][i] * (h * BI[j][k]);
                    acc += fhbi * cs[k];
                }
                yi[i] = y[i] + acc;
            }
            emit(&o, tref, yi);
        }
        emit(&o, tnew, ynew);
        t = tnew;
        memcpy(y, ynew, sizeof y);
        memcpy(f[0], f[6], sizeof f[0]);
        if (!adb_all_finite(y, ADB_NY)) {
            status = ADB_NONFINITE;
            out_stats[3] = t;
            break;
        }
        if (nofailed) {
            double temp = 1.25 * pow(err / rtol, pw);
            if (temp > 0.2)
                absh = absh / temp;
            else
                absh = 5.0 * absh;
        }
        if (max_steps > 0 && nsteps >= max_steps && !done) {
            status = ADB_MAX_STEPS;
            out_stats[3] = t;
            break;
        }
    }
finish:
    out_stats[0] = sqrt(o.r2max);
    out_stats[1] = o.t_dec;
    out_stats[2] = t;
    memcpy(y_end, y, sizeof y);
    out_counts[0] = nfev;
    out_counts[1] = nsteps;
    if (o.keep) {
        traj->t = o.T, traj->y = o.Y, traj->k = (long)o.k;
    }
    return status;
}

void adb_ode45_release(Ode45Trajectory *traj)
{
    free(traj->t);
    free(traj->y);
    traj->t = traj->y = NULL;
    traj->k = 0;
}

/* Many trajectories on `threads` OpenMP threads; row k of Y0 with row k of P; outputs in rows. */
void adb_ode45_integrate_many(int n, const double *Y0, const double *P, double t_end, double rtol, double atol,
                              long max_steps, const int *amp_idx, double threshold, int threads, int *status,
                              double *Y_end, double *stats, long *counts)
{
#ifdef _OPENMP
    if (threads < 1) threads = omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
    for (int k = 0; k < n; ++k)
        status[k] = adb_ode45_integrate(Y0 + (size_t)k * ADB_NY, P + (size_t)k * ADB_NP, t_end, rtol, atol, max_steps,
                                        amp_idx, threshold, 0, NULL, Y_end + (size_t)k * ADB_NY, stats + (size_t)k * 4,
                                        counts + (size_t)k * 2);
}
