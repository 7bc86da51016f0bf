/* The cyrk-* engines: a generated model's C library run by CyRK's C++ Runge-Kutta solvers (DOP853,
 * Vern7, Vern8, RK45, RK23), with no Python per step or per evaluation.
 *
 * One translation unit per model: it #includes the model's generated C source (ADB_MODEL_SOURCE) so
 * the compiler may inline the right-hand side into the callback.  CyRK's solver is reached through
 * the C function pointers its numba bridge exports (CyRK.nb.numba_c_api), handed over once by
 * adb_cyrk_init; compiled by adbgen.analysis.engines.compiled with
 *
 *     -DADB_MODEL_SOURCE='"<model>.c"' -DADB_RHS=<model>_rhs -DADB_NY=<states> -DADB_NP=<parameters>
 *
 * r_max and t_dec (thesis ch. 5) are located on the continuous solution by event_measures.h
 * (adb_dense_measures: the last crossing of r = threshold, an excursion above it inside one step, the
 * largest peaks of r): each step it searches is integrated again from its accepted state with CyRK's dense
 * output (the method's own continuous extension).
 *
 * Exact symmetry: the RK stages update every component by the same element-wise operations and the
 * generated code evaluates every ball in the same order, so identical balls stay together bit for bit.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"
#include "cyrk_bridge.h"

/* CyRK's function pointers, once per library (cyrk_bridge.h) */
int adb_cyrk_init(void *const *ptrs)
{
    adb_cyrk_bind(ptrs);
    return ADB_NY;
}

/* CyRK copies the argument bytes; the counter pointer survives the copy */
typedef struct {
    double p[ADB_NP];
    long *count;
} Args;

static void diffeq(double *dy, double t, double *y, char *args, PreEvalFn pre)
{
    (void)pre;
    Args *a = (Args *)args;
    ADB_RHS(t, y, a->p, dy);
    ++*a->count;
}

typedef struct {
    int method;
    double rtol, atol;
    size_t max_steps;
} Settings;

static void *solve(const Settings *s, double t0, double t1, double *y0, Args *args, bool dense, double first_step)
{
    /* CyRK refuses a first step longer than half the interval */
    if (first_step > 0.49 * (t1 - t0)) first_step = 0.49 * (t1 - t0);
    return cy.solve(diffeq, t0, t1, y0, ADB_NY, s->method, 0, 0, (char *)args, sizeof(Args), s->max_steps, 2000,
                    dense, NULL, 0, NULL, NULL, 0, (double *)&s->rtol, 1, (double *)&s->atol, 1, INFINITY, first_step, true);
}

/* r^2 at time t on the dense output of `res` */
static double dense_r2(void *res, double t, int ix, int iy)
{
    double y[ADB_NY];
    cy.call(res, t, y);
    return adb_r2(y, ix, iy);
}

/* step t[k] -> t[k+1] integrated again from its accepted state with dense output; the window runs on
 * past t[k+1] (CyRK's first step may be at most half of it: 2.05 h leaves room for h and one more
 * step), and its first step is the accepted step again.  NULL on failure. */
static void *redo_step(const Settings *s, Args *args, const double *t, const double *Y, size_t k)
{
    double y0[ADB_NY];
    memcpy(y0, Y + k * ADB_NY, sizeof y0);
    double h = t[k + 1] - t[k];
    void *res = solve(s, t[k], t[k] + 2.05 * h, y0, args, true, h);
    if (res && !cy.success(res)) {
        cy.free(res);
        res = NULL;
    }
    return res;
}

/* event_measures.h's hooks: a step's interpolant is the step integrated again with dense output */
typedef struct {
    const Settings *s;
    Args *args;
} DenseSource;

static void *dense_open(const DenseSource *src, const double *T, const double *Y, size_t k)
{
    return redo_step(src->s, src->args, T, Y, k);
}

static void dense_close(void *res) { cy.free(res); }

#define ADB_DENSE void *
#define ADB_DENSE_SOURCE const DenseSource *
#include "event_measures.h"

/* One trajectory from t = 0 to s->t_end.
 *
 * Segments: with check_dt > 0 the run goes in segments of check_dt (each a fresh solve from the previous
 * end, first step = the last accepted step), with or without targets, so a run with early stop and one
 * without see bit-identical trajectories until the stop; it stops in the first target region holding
 * the state at a segment's end (early stop).
 * keep: 1 returns every accepted step in *traj (free with adb_release), 0 only counts them.
 * measures: 0 skips r_max and t_dec (NaN; sweeps' attractor labels need neither), and with keep = 0
 * only the last state is kept instead of every accepted step.
 * The settings and the report: adb_engine.h. */
static int adb_run(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj, double *y_end,
                   adb_result *r)
{
    Settings cs = {s->method, s->rtol, s->atol, s->max_steps > 0 ? (size_t)s->max_steps : 0};
    long count = 0;
    Args args;
    memcpy(args.p, p, sizeof args.p);
    args.count = &count;
    int ix = s->amp[0], iy = s->amp[1];
    if (!(s->t_end > 0.0) || !(s->rtol > 0.0) || !(s->atol > 0.0) || !adb_all_finite(y0, ADB_NY)) return ADB_BAD_INPUT;

    size_t cap = 1024, K = 0;
    double *T = malloc(cap * sizeof(double)), *Y = malloc(cap * ADB_NY * sizeof(double));
    T[0] = 0.0;
    memcpy(Y, y0, sizeof(double) * ADB_NY);
    K = 1;
    int status = ADB_SUCCESS;
    long steps = 0;
    double t = 0.0, h = 0.0;
    int segmented = s->check_dt > 0.0, store = s->keep || s->measures;
    while (t < s->t_end) {
        double t1 = segmented ? fmin(s->t_end, t + s->check_dt) : s->t_end;
        double ystart[ADB_NY];
        memcpy(ystart, Y + (K - 1) * ADB_NY, sizeof ystart);
        void *res = solve(&cs, t, t1, ystart, &args, false, h);
        if (!res) {
            status = ADB_SOLVER_FAILURE;
            r->t_fail = t;
            break;
        }
        size_t n = cy.size(res);
        const double *rt = cy.t(res), *ry = cy.y(res);
        steps += (long)cy.steps(res);
        if (!store && n >= 3) {
            /* only the last two points (the state and the last step size): rows K-2, K-1 */
            K = 1;
            memcpy(Y, ry + (n - 3) * ADB_NY, sizeof(double) * ADB_NY);
            T[0] = rt[n - 3];
            for (size_t j = 1; j < n - 2; ++j)
                if (!adb_all_finite(ry + j * ADB_NY, ADB_NY)) {
                    status = ADB_NONFINITE;
                    r->t_fail = rt[j];
                    break;
                }
            rt += n - 3, ry += (n - 3) * ADB_NY, n = 3;
        }
        if (K + n > cap) {
            while (K + n > cap) cap *= 2;
            T = realloc(T, cap * sizeof(double));
            Y = realloc(Y, cap * ADB_NY * sizeof(double));
        }
        /* the solver's first stored point is its start: skip it */
        for (size_t j = 1; j < n && status == ADB_SUCCESS; ++j) {
            if (!adb_all_finite(ry + j * ADB_NY, ADB_NY)) {
                status = ADB_NONFINITE;
                r->t_fail = rt[j];
                break;
            }
            T[K] = rt[j];
            memcpy(Y + K * ADB_NY, ry + j * ADB_NY, sizeof(double) * ADB_NY);
            ++K;
        }
        int ok = cy.success(res);
        int code = cy.status(res);
        cy.free(res);
        if (status != ADB_SUCCESS) break;
        if (!ok) {
            status = adb_cyrk_decode(code);
            r->t_fail = T[K - 1];
            break;
        }
        if (K >= 2) h = T[K - 1] - T[K - 2];
        t = T[K - 1];
        if (s->max_steps > 0 && steps >= s->max_steps && t < s->t_end) {
            status = ADB_MAX_STEPS;
            r->t_fail = t;
            break;
        }
        if (segmented && t < s->t_end) {
            int k = adb_in_target(Y + (K - 1) * ADB_NY, s->n_targets, s->centres, s->weights, s->cubics, s->levels,
                                  s->periodic);
            if (k >= 0) {
                r->target = k;
                status = ADB_STOPPED;
                break;
            }
        }
    }
    long evals = count;
    if (s->measures) {
        /* the steps are stored (store): searched on their continuous solution when the run finished */
        adb_events ev;
        adb_events_start(&ev, s->threshold, y0, s->amp);
        if (status == ADB_SUCCESS) {
            const DenseSource src = {&cs, &args};
            adb_dense_measures(&src, T, Y, K, s->amp, 8, &ev); /* (its re-integrations not counted in n_rhs) */
        } else
            adb_events_points(&ev, T, Y, K, s->amp);
        adb_events_report(&ev, 1, status, adb_r2(Y + (K - 1) * ADB_NY, ix, iy), r);
    }
    r->t_last = T[K - 1];
    memcpy(y_end, Y + (K - 1) * ADB_NY, sizeof(double) * ADB_NY);
    r->n_rhs = evals;
    r->n_steps = steps;
    if (traj && s->keep) {
        traj->t = T, traj->y = Y, traj->k = (long)K;
    } else {
        free(T);
        free(Y);
    }
    return status;
}

#include "adb_entries.h"

/* The continuous solution of a run at `times` (n, increasing, within [T[0], T[K-1]]) into out (n x ADB_NY):
 * each step holding a time is integrated again with dense output, as adb_dense_measures does, so this is the
 * interpolant r_max and t_dec are located on.  Returns 0, or ADB_SOLVER_FAILURE. */
int adb_dense(const double *T, const double *Y, long K, const double *p, const adb_settings *set, int n,
              const double *times, double *out)
{
    Settings s = {set->method, set->rtol, set->atol, 0};
    long count = 0;
    Args args;
    memcpy(args.p, p, sizeof args.p);
    args.count = &count;
    size_t k = 0;
    void *res = NULL;
    size_t held = (size_t)-1;
    for (int j = 0; j < n; ++j) {
        while (k + 2 < (size_t)K && T[k + 1] < times[j]) ++k;
        if (held != k) {
            if (res) cy.free(res);
            res = redo_step(&s, &args, T, Y, k);
            held = k;
            if (!res) return ADB_SOLVER_FAILURE;
        }
        cy.call(res, times[j], out + (size_t)j * ADB_NY);
    }
    if (res) cy.free(res);
    return 0;
}
