/* adbgen's compiled integration path: a generated model's C library run by SUNDIALS, with no Python
 * call per step or per right-hand-side evaluation.
 *
 * One translation unit per model: it #includes the model's generated C source (ADB_MODEL_SOURCE), so
 * the compiler sees the right-hand side and may inline it.  Compiled by adbgen.analysis.engines.compiled
 * with
 *
 *     -DADB_MODEL_SOURCE='"<model>.c"' -DADB_RHS=<model>_rhs -DADB_JAC=<model>_jac
 *     -DADB_NY=<states> -DADB_NP=<parameters>
 *
 * Methods (adb_settings.method):
 *   0  ARKODE ERKStep, Fehlberg 13-stage 7(8)        explicit, order 8
 *   1  ARKODE ERKStep, Dormand-Prince 7-stage 4(5)   explicit, order 5
 *   2  ARKODE ERKStep, Verner 8-stage 5(6)           explicit, order 6
 *   10 CVODE BDF, Newton with a dense direct solver and the generated analytic Jacobian (stiff)
 *   11 CVODE Adams-Moulton with fixed-point iteration (non-stiff, no linear algebra)
 *
 * Per trajectory it reports what a rotordynamics user reads (thesis ch. 5): the rotor amplitude
 * r = sqrt(y[ix]^2 + y[iy]^2), its maximum r_max and the decay time t_dec = sup{t <= t_end : r >= H},
 * both located on the continuous (interpolated) solution by SUNDIALS' root finding: the extrema of r
 * are the roots of y[ix] y[ixd] + y[iy] y[iyd] (the rates of the rotor's coordinates), the threshold
 * crossings the roots of r^2 - H^2.  A maximum of r at or above H counts too (an excursion above H
 * that starts and ends inside one step changes no sign of r^2 - H^2 at step ends; SUNDIALS splits the
 * step at the maximum's root and then finds its end as a crossing).  The points and roots go to
 * event_measures.h, which reports r_max and t_dec by the rule every engine shares.
 *
 * Exact symmetry: the explicit (ERKStep) and Adams/fixed-point methods update every component by the
 * same sequence of floating-point operations (N_Vector operations are element-wise and reductions only
 * set the common step size), so balls with identical equations that start together stay together bit
 * for bit.  BDF's dense LU factorisation with partial pivoting treats the balls' rows differently, so
 * it does not promise that.
 */
#include <stdio.h>
#include <string.h>

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_types.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"
#include "event_measures.h"

typedef struct {
    /* inputs */
    const double *p;
    int ix, iy, ixd, iyd;
    double threshold;
    /* state of the run */
    int nonfinite;
    double t_nonfinite;
    char message[256];
} RunData;

static int rhs_fn(realtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    RunData *d = (RunData *)user_data;
    double *out = N_VGetArrayPointer(ydot);
    ADB_RHS(t, N_VGetArrayPointer(y), d->p, out);
    for (int i = 0; i < ADB_NY; ++i) {
        if (!isfinite(out[i])) {
            if (!d->nonfinite) {
                d->nonfinite = 1;
                d->t_nonfinite = t;
            }
            return -1; /* unrecoverable: a non-finite derivative is an error, never retried silently */
        }
    }
    return 0;
}

static int jac_fn(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *user_data, N_Vector t1, N_Vector t2,
                  N_Vector t3)
{
    (void)fy; (void)t1; (void)t2; (void)t3;
    RunData *d = (RunData *)user_data;
    double buf[ADB_NY * ADB_NY];
    ADB_JAC(t, N_VGetArrayPointer(y), d->p, buf);
    for (int i = 0; i < ADB_NY; ++i)
        for (int j = 0; j < ADB_NY; ++j) SM_ELEMENT_D(J, i, j) = buf[i * ADB_NY + j];
    return 0;
}

/* g0 = r^2 - H^2 (threshold crossings), g1 = d(r^2)/dt / 2 (extrema of r) */
static int root_fn(realtype t, N_Vector yv, realtype *g, void *user_data)
{
    (void)t;
    RunData *d = (RunData *)user_data;
    const double *y = N_VGetArrayPointer(yv);
    g[0] = y[d->ix] * y[d->ix] + y[d->iy] * y[d->iy] - d->threshold * d->threshold;
    g[1] = y[d->ix] * y[d->ixd] + y[d->iy] * y[d->iyd];
    return 0;
}

static void err_fn(int code, const char *module, const char *function, char *msg, void *user_data)
{
    (void)code;
    RunData *d = (RunData *)user_data;
    snprintf(d->message, sizeof d->message, "%s %s: %s", module, function, msg);
}

typedef struct {
    int method;
    void *mem;
    SUNMatrix A;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
} Solver;

static int solver_create(Solver *s, int method, SUNContext ctx, N_Vector y, RunData *d, double rtol, double atol,
                         long max_steps)
{
    memset(s, 0, sizeof *s);
    s->method = method;
    int flag = 0;
    if (method < 10) {
        static const ARKODE_ERKTableID tables[] = {ARKODE_FEHLBERG_13_7_8, ARKODE_DORMAND_PRINCE_7_4_5,
                                                   ARKODE_VERNER_8_5_6};
        if (method < 0 || method > 2) return -1;
        s->mem = ERKStepCreate(rhs_fn, 0.0, y, ctx);
        if (!s->mem) return -1;
        flag |= ERKStepSetErrHandlerFn(s->mem, err_fn, d);
        flag |= ERKStepSetTableNum(s->mem, tables[method]);
        flag |= ERKStepSStolerances(s->mem, rtol, atol);
        flag |= ERKStepSetUserData(s->mem, d);
        flag |= ERKStepSetMaxNumSteps(s->mem, max_steps);
        flag |= ERKStepSetMaxHnilWarns(s->mem, -1);
        flag |= ERKStepRootInit(s->mem, 2, root_fn);
        flag |= ERKStepSetNoInactiveRootWarn(s->mem);
    } else if (method == 10 || method == 11) {
        s->mem = CVodeCreate(method == 10 ? CV_BDF : CV_ADAMS, ctx);
        if (!s->mem) return -1;
        flag |= CVodeSetErrHandlerFn(s->mem, err_fn, d);
        flag |= CVodeInit(s->mem, rhs_fn, 0.0, y);
        flag |= CVodeSStolerances(s->mem, rtol, atol);
        flag |= CVodeSetUserData(s->mem, d);
        flag |= CVodeSetMaxNumSteps(s->mem, max_steps);
        flag |= CVodeSetMaxHnilWarns(s->mem, -1);
        flag |= CVodeRootInit(s->mem, 2, root_fn);
        flag |= CVodeSetNoInactiveRootWarn(s->mem);
        if (method == 10) {
            s->A = SUNDenseMatrix(ADB_NY, ADB_NY, ctx);
            s->LS = SUNLinSol_Dense(y, s->A, ctx);
            flag |= CVodeSetLinearSolver(s->mem, s->LS, s->A);
            flag |= CVodeSetJacFn(s->mem, jac_fn);
        } else {
            s->NLS = SUNNonlinSol_FixedPoint(y, 0, ctx);
            flag |= CVodeSetNonlinearSolver(s->mem, s->NLS);
        }
    } else {
        return -1;
    }
    return flag ? -1 : 0;
}

static void solver_free(Solver *s)
{
    if (s->method < 10) ERKStepFree(&s->mem);
    else CVodeFree(&s->mem);
    if (s->LS) SUNLinSolFree(s->LS);
    if (s->A) SUNMatDestroy(s->A);
    if (s->NLS) SUNNonlinSolFree(s->NLS);
}

static int solver_evolve(Solver *s, double tout, N_Vector y, double *t)
{
    int flag = s->method < 10 ? ERKStepEvolve(s->mem, tout, y, t, ARK_NORMAL) : CVode(s->mem, tout, y, t, CV_NORMAL);
    if (flag == ARK_ROOT_RETURN) return 2; /* CV_ROOT_RETURN has the same value */
    return flag < 0 ? flag : 0;
}

/* SUNDIALS' step limit is per call (steps before the next return: a root, a sample, a check): the steps left
 * of the run's max_steps (> 0), so that it bounds the whole run as the other engines' does */
static void solver_steps_left(Solver *s, long left)
{
    if (s->method < 10) ERKStepSetMaxNumSteps(s->mem, left);
    else CVodeSetMaxNumSteps(s->mem, left);
}

static void solver_root_info(Solver *s, int *found)
{
    if (s->method < 10) ERKStepGetRootInfo(s->mem, found);
    else CVodeGetRootInfo(s->mem, found);
}

static void solver_stats(Solver *s, long *nfe, long *nsteps, double *hcur)
{
    long e = 0, st = 0, dummy = 0;
    double h = 0.0;
    if (s->method < 10) {
        ERKStepGetNumRhsEvals(s->mem, &e);
        ERKStepGetNumSteps(s->mem, &st);
        ERKStepGetCurrentStep(s->mem, &h);
    } else {
        CVodeGetNumRhsEvals(s->mem, &e);
        CVodeGetNumSteps(s->mem, &st);
        CVodeGetCurrentStep(s->mem, &h);
        if (s->method == 10) { /* finite-difference rhs calls of the linear solver: none (analytic J) */
            CVodeGetNumLinRhsEvals(s->mem, &dummy);
            e += dummy;
        }
    }
    *nfe = e;
    *nsteps = st;
    *hcur = h;
}

/* Integrate one trajectory from t = 0 to t_end.
 *
 * set->sample_times (set->n_samples, increasing, in (0, t_end]) and set->samples (n_samples x ADB_NY) may be
 * NULL/0.  Early stop: every check_dt (> 0) time units, if the state lies in one of the n_targets target
 * regions (adb_in_target), the run stops with ADB_STOPPED and out->target = its index (else -1).
 * out->t_dec is NaN when r(t_end) >= threshold.  y_end: the state at out->t_last.  set->message: 256 bytes
 * or NULL.  No steps are kept (traj unused): samples instead.
 */
static int adb_run(const double *y0, const double *p, const adb_settings *set, adb_trajectory *traj, double *y_end,
                   adb_result *out)
{
    (void)traj;
    RunData d;
    memset(&d, 0, sizeof d);
    d.p = p;
    d.ix = set->amp[0];
    d.iy = set->amp[1];
    d.ixd = set->amp[2];
    d.iyd = set->amp[3];
    d.threshold = set->threshold;
    if (!(set->t_end > 0.0) || !(set->rtol > 0.0) || !(set->atol > 0.0)) return ADB_BAD_INPUT;

    SUNContext ctx;
    if (SUNContext_Create(NULL, &ctx)) return ADB_SOLVER_FAILURE;
    N_Vector y = N_VNew_Serial(ADB_NY, ctx);
    double *yd = N_VGetArrayPointer(y);
    memcpy(yd, y0, sizeof(double) * ADB_NY);

    Solver s;
    int status = ADB_SUCCESS;
    if (solver_create(&s, set->method, ctx, y, &d, set->rtol, set->atol, set->max_steps)) {
        N_VDestroy(y);
        SUNContext_Free(&ctx);
        return ADB_BAD_INPUT;
    }
    if (s.method < 10) ERKStepSetStopTime(s.mem, set->t_end);
    else CVodeSetStopTime(s.mem, set->t_end);

    adb_events ev;
    adb_events_start(&ev, set->threshold, y0, set->amp);
    double t = 0.0;
    int sample = 0;
    double next_check = set->check_dt > 0.0 && set->n_targets > 0 ? set->check_dt : INFINITY;
    while (t < set->t_end) {
        double tout = set->t_end;
        if (sample < set->n_samples && set->sample_times[sample] < tout) tout = set->sample_times[sample];
        if (next_check < tout) tout = next_check;
        if (set->max_steps > 0) {
            double h;
            long nfe, nst;
            solver_stats(&s, &nfe, &nst, &h);
            if (nst >= set->max_steps) { /* the run's limit reached at a return: as the solver's own failure */
                status = ADB_MAX_STEPS;
                out->t_fail = t;
                break;
            }
            solver_steps_left(&s, set->max_steps - nst);
        }
        int flag = solver_evolve(&s, tout, y, &t);
        if (flag < 0) {
            double h;
            long nfe, nst;
            solver_stats(&s, &nfe, &nst, &h);
            if (d.nonfinite) {
                status = ADB_NONFINITE;
                out->t_fail = d.t_nonfinite;
            } else if (flag == ARK_TOO_MUCH_WORK) {
                status = ADB_MAX_STEPS;
                out->t_fail = t;
            } else if (fabs(h) <= 16.0 * 2.220446049250313e-16 * fmax(fabs(t), 1.0)) {
                status = ADB_STEP_UNDERFLOW;
                out->t_fail = t;
            } else {
                status = ADB_SOLVER_FAILURE;
                out->t_fail = t;
            }
            /* the state it reached is a point too: r rose or fell monotonically since the last return (every
             * maximum of r is a root, so a return), so r_max is the larger of the two (a NaN r^2 counts nothing) */
            adb_events_point(&ev, t, adb_r2(yd, d.ix, d.iy));
            break;
        }
        const double r2 = adb_r2(yd, d.ix, d.iy);
        /* every return is a point (a maximum of r above H between crossings counts: sup{t : r >= H}; after
         * such a root SUNDIALS checks r^2 - H^2 again from it to the step's end, so the excursion's end is
         * the next crossing root even when both step ends are below H) */
        adb_events_point(&ev, t, r2);
        if (flag == 2) {
            int found[2] = {0, 0};
            solver_root_info(&s, found);
            if (found[0]) adb_events_crossing(&ev, t);
            continue;
        }
        if (!isfinite(r2)) {
            status = ADB_NONFINITE;
            out->t_fail = t;
            break;
        }
        while (sample < set->n_samples && set->sample_times[sample] <= t) {
            memcpy(set->samples + (size_t)sample * ADB_NY, yd, sizeof(double) * ADB_NY);
            ++sample;
        }
        if (t >= next_check) {
            int k = adb_in_target(yd, set->n_targets, set->centres, set->weights, set->cubics, set->levels,
                                  set->periodic);
            if (k >= 0) {
                out->target = k;
                status = ADB_STOPPED;
                break;
            }
            next_check += set->check_dt;
        }
    }
    double h;
    long nfe, nst;
    solver_stats(&s, &nfe, &nst, &h);
    memcpy(y_end, yd, sizeof(double) * ADB_NY);
    adb_events_report(&ev, set->measures, status, adb_r2(yd, d.ix, d.iy), out);
    out->t_last = t;
    out->n_rhs = nfe;
    out->n_steps = nst;
    if (set->message) memcpy(set->message, d.message, sizeof d.message);
    solver_free(&s);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return status;
}

/* r_max and t_dec come from the root finding along the way: set->measures 0 saves nothing but reports NaN */
#include "adb_entries.h"
