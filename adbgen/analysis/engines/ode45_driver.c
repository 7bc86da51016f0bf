/* `matlab-ode45`: an emulation of MATLAB's ode45 (the thesis' integrator, ch. 5) on a generated model's C
 * library, for explaining published numbers (docs/reproduction-method.md, `matlab-ode45`).  Not a recommended integrator.
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
 * r_max = max r(t_i), t_dec = the last t_i with r(t_i) >= threshold (event_measures.h's points and report:
 * 0 when none, NaN when r(t_end) >= threshold or the run failed).
 *
 * Compiled by adbgen.analysis.engines.compiled like the other drivers (-DADB_MODEL_SOURCE, ADB_RHS,
 * ADB_NY, ADB_NP); the libm the model calls is the pinned one of fixed_libm.h.
 */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"
#include "event_measures.h"


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

/* the output points: the measures' points (event_measures.h), and with keep the returned [t, y] */
typedef struct {
    double *T, *Y;
    size_t k, cap;
    int keep;
    const int *amp;
    adb_events ev;
} Output;

static void emit(Output *o, double t, const double *y)
{
    adb_events_point(&o->ev, t, adb_r2(y, o->amp[0], o->amp[1]));
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

/* One trajectory (adb_engine.h; no targets, no segments: s->check_dt and the regions are ignored, the
 * Python side refuses them); returns a status code. */
static int adb_run(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj, double *y_end,
                   adb_result *r)
{
    double rtol = s->rtol; /* raised below as MATLAB does */
    if (!(s->t_end > 0.0) || !(rtol > 0.0) || !(s->atol > 0.0) || !adb_all_finite(y0, ADB_NY)) return ADB_BAD_INPUT;
    if (rtol < 100.0 * DBL_EPSILON) rtol = 100.0 * DBL_EPSILON; /* as odearguments does (with a warning) */

    Output o = {NULL, NULL, 0, 1024, s->keep && traj, s->amp, {0.0, 0.0, 0.0}};
    adb_events_start(&o.ev, s->threshold, y0, s->amp);
    if (o.keep) {
        o.T = malloc(o.cap * sizeof(double));
        o.Y = malloc(o.cap * ADB_NY * sizeof(double));
    }
    const double pw = 1.0 / 5.0, t0 = 0.0, tfinal = s->t_end;
    const double threshold_w = s->atol / rtol;
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
                    r->t_fail = t;
                    goto finish;
                }
                if (absh <= hmin) {
                    status = ADB_STEP_UNDERFLOW;
                    r->t_fail = t;
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
            r->t_fail = t;
            break;
        }
        if (nofailed) {
            double temp = 1.25 * pow(err / rtol, pw);
            if (temp > 0.2)
                absh = absh / temp;
            else
                absh = 5.0 * absh;
        }
        if (s->max_steps > 0 && nsteps >= s->max_steps && !done) {
            status = ADB_MAX_STEPS;
            r->t_fail = t;
            break;
        }
    }
finish:
    adb_events_report(&o.ev, s->measures, status, adb_r2(y, s->amp[0], s->amp[1]), r);
    r->t_last = t;
    memcpy(y_end, y, sizeof y);
    r->n_rhs = nfev;
    r->n_steps = nsteps;
    if (o.keep) {
        traj->t = o.T, traj->y = o.Y, traj->k = (long)o.k;
    }
    return status;
}

#include "adb_entries.h"
