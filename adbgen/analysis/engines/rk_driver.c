/* The DOP853 engine at its floor (issue 22 item 3): Hairer's 8(5,3) Runge-Kutta pair (rk_dop853.h)
 * compiled in one translation unit with the model's generated C rhs, which every stage calls directly
 * (no function pointer, no solver object, no copy of the arguments), compiled by
 * adbgen.analysis.engines.rk with
 *
 *     -DADB_MODEL_SOURCE='"<model>.c"' -DADB_RHS=<model>_rhs -DADB_NY=<states> -DADB_NP=<parameters>
 *
 * It reports what cyrk_driver.c reports, through the same entry points (adb_engine.h: adb_integrate,
 * adb_integrate_many, adb_release; adb_dense): status codes, early stop in target regions at segment ends,
 * r_max and t_dec on the continuous solution.  The continuous solution is the method's own 7th-order
 * interpolant of each accepted step, rebuilt when needed from the stored step (t_k, y_k, t_{k+1}): the
 * same arithmetic as the step itself, so the rebuilt step ends bitwise at y_{k+1}.  t_dec = sup{t : r(t)
 * >= H} sees an excursion above H inside one step (both ends below H) as cyrk_driver.c does: steps with
 * an interior maximum of r (x x' + y y' from + to -) whose Hermite estimate comes near H are searched on
 * their interpolant, latest first.
 *
 * Step control is scipy's (CyRK's): first step by Hairer's estimate, safety 0.9, factor in [0.2, 10],
 * no growth right after a rejection, a step below 10 ulp of t is an underflow.  Segments (check_dt): a
 * step never crosses a segment's end (the run continues from it with the controller's next step), so
 * runs with and without early stop see the same steps until a stop.
 *
 * Exact symmetry: every stage updates each component by the same element-wise operations and the
 * generated rhs evaluates every ball in the same order, so identical balls stay together bit for bit.
 */
#include <stdlib.h>
#include <time.h>
#include <string.h>

#include ADB_MODEL_SOURCE
#include "driver_common.h"

#define RK_T double
#define RK_NY ADB_NY
#define RK_ABS(x) fabs(x)
#define RK_MAX(a, b) fmax(a, b)
#define RK_RHS(t, y, f) ADB_RHS((t), (y), ((const double *)ctx), (f))
#include "rk_dop853.h"

typedef struct {
    double t[2], y[ADB_NY], F[7][ADB_NY];
} Dense;

/* the interpolant of stored step k (T[k] -> T[k+1], from Y[k]) */
static void dense_of(Dense *d, const double *p, const double *T, const double *Y, size_t k)
{
    double K[DOP_EXTENDED][ADB_NY], ynew[ADB_NY], e5, e3;
    const double *y = Y + k * ADB_NY, *ctx = p;
    double t = T[k], h = T[k + 1] - T[k];
    RK_RHS(t, y, K[0]);
    dop_step(t, h, y, K, ynew, 1.0, 1.0, &e5, &e3, ctx);
    dop_dense(t, h, y, ynew, K, d->F, ctx);
    d->t[0] = t, d->t[1] = T[k + 1];
    memcpy(d->y, y, sizeof d->y);
}

static void dense_at(const Dense *d, double t, double *out)
{
    double x = (t - d->t[0]) / (d->t[1] - d->t[0]), w = 1.0 - x;
    for (int i = 0; i < ADB_NY; ++i) {
        double v = d->F[6][i];
        v = v * x + d->F[5][i], v = v * w + d->F[4][i], v = v * x + d->F[3][i];
        v = v * w + d->F[2][i], v = v * x + d->F[1][i], v = v * w + d->F[0][i];
        out[i] = d->y[i] + v * x;
    }
}

static double dense_r2(const Dense *d, double t, int ix, int iy)
{
    double y[ADB_NY];
    dense_at(d, t, y);
    return adb_r2(y, ix, iy);
}

/* event_measures.h's hooks: a step's interpolant is rebuilt into the source's scratch (never fails) */
typedef struct {
    const double *p;
    Dense d;
} DenseSource;

static const Dense *dense_open(DenseSource *src, const double *T, const double *Y, size_t k)
{
    dense_of(&src->d, src->p, T, Y, k);
    return &src->d;
}

static void dense_close(const Dense *d) { (void)d; }

#define ADB_DENSE const Dense *
#define ADB_DENSE_SOURCE DenseSource *
#include "event_measures.h"

/* Hairer's initial step (scipy's select_initial_step; order 7 of the error estimator) */
static double first_step(double t, const double *y, const double *f0, double t_bound, double rtol, double atol,
                         const double *ctx)
{
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, y1[ADB_NY], f1[ADB_NY], span = t_bound - t;
    for (int i = 0; i < ADB_NY; ++i) {
        double sc = atol + fabs(y[i]) * rtol;
        d0 += (y[i] / sc) * (y[i] / sc), d1 += (f0[i] / sc) * (f0[i] / sc);
    }
    d0 = sqrt(d0 / ADB_NY), d1 = sqrt(d1 / ADB_NY);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = fmin(h0, span);
    for (int i = 0; i < ADB_NY; ++i) y1[i] = y[i] + h0 * f0[i];
    RK_RHS(t + h0, y1, f1);
    for (int i = 0; i < ADB_NY; ++i) {
        double sc = atol + fabs(y[i]) * rtol, v = (f1[i] - f0[i]) / sc;
        d2 += v * v;
    }
    d2 = sqrt(d2 / ADB_NY) / h0;
    double h1 = (d1 <= 1e-15 && d2 <= 1e-15) ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    return fmin(fmin(100.0 * h0, h1), span);
}

/* One trajectory from t = 0 to s->t_end (adb_engine.h; s->method is unused: DOP853), segments and early stop
 * as cyrk_driver.c's. */
static int adb_run(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj, double *y_end,
                   adb_result *r)
{
    const double *ctx = p;
    if (!(s->t_end > 0.0) || !(s->rtol > 0.0) || !(s->atol > 0.0) || !adb_all_finite(y0, ADB_NY)) return ADB_BAD_INPUT;
    long evals = 2; /* f(0, y0) and the first step's estimate, then DOP_STAGES per step attempt */
    int store = s->keep || s->measures, segmented = s->check_dt > 0.0, status = ADB_SUCCESS;
    size_t cap = store ? 1024 : 1, K = 1;
    double *T = malloc(cap * sizeof(double)), *Y = malloc(cap * ADB_NY * sizeof(double));
    double y[ADB_NY], ynew[ADB_NY], Kst[DOP_EXTENDED][ADB_NY], t = 0.0;
    memcpy(y, y0, sizeof y);
    T[0] = 0.0;
    memcpy(Y, y0, sizeof y);
    RK_RHS(t, y, Kst[0]);
    double seg_end = segmented ? fmin(s->t_end, s->check_dt) : s->t_end;
    double h_abs = first_step(t, y, Kst[0], seg_end, s->rtol, s->atol, ctx);
    long steps = 0;
    while (t < s->t_end) {
        if (s->max_steps > 0 && steps >= s->max_steps) {
            status = ADB_MAX_STEPS;
            break;
        }
        double min_step = 10.0 * (nextafter(t, INFINITY) - t), t_new, h;
        int rejected = 0;
        if (h_abs < min_step) h_abs = min_step;
        for (;;) {
            if (h_abs < min_step) {
                status = ADB_STEP_UNDERFLOW;
                break;
            }
            t_new = t + h_abs;
            if (t_new > seg_end) t_new = seg_end;
            h = t_new - t;
            double e5, e3;
            dop_step(t, h, y, Kst, ynew, s->rtol, s->atol, &e5, &e3, ctx);
            evals += DOP_STAGES;
            double err = dop_norm(h, e5, e3);
            if (!adb_all_finite(ynew, ADB_NY) || !adb_all_finite(Kst[DOP_STAGES], ADB_NY)) {
                /* a non-finite state or derivative (an infinite error norm alone is a rejection) */
                status = ADB_NONFINITE;
                break;
            }
            double f = dop_factor(err, rejected);
            h_abs = fabs(h) * f;
            if (err < 1.0) break;
            rejected = 1;
        }
        if (status != ADB_SUCCESS) break;
        ++steps;
        t = t_new;
        memcpy(y, ynew, sizeof y);
        memcpy(Kst[0], Kst[DOP_STAGES], sizeof Kst[0]); /* FSAL */
        if (store) {
            if (K == cap) {
                cap *= 2;
                T = realloc(T, cap * sizeof(double));
                Y = realloc(Y, cap * ADB_NY * sizeof(double));
            }
            T[K] = t;
            memcpy(Y + K * ADB_NY, y, sizeof y);
            ++K;
        } else {
            T[0] = t;
            memcpy(Y, y, sizeof y);
        }
        if (t >= seg_end && t < s->t_end) {
            if (s->n_targets > 0) {
                int k = adb_in_target(y, s->n_targets, s->centres, s->weights, s->cubics, s->levels, s->periodic);
                if (k >= 0) {
                    r->target = k;
                    status = ADB_STOPPED;
                    break;
                }
            }
            seg_end = fmin(s->t_end, seg_end + s->check_dt);
        }
    }
    if (status != ADB_SUCCESS && status != ADB_STOPPED) r->t_fail = t;
    if (s->measures) {
        /* the steps are stored (store): searched on their interpolants when the run finished */
        adb_events ev;
        adb_events_start(&ev, s->threshold, y0, s->amp);
        if (status == ADB_SUCCESS) {
            DenseSource src;
            src.p = p;
            adb_dense_measures(&src, T, Y, K, s->amp, 8, &ev);
        } else
            adb_events_points(&ev, T, Y, K, s->amp);
        adb_events_report(&ev, 1, status, adb_r2(y, s->amp[0], s->amp[1]), r);
    }
    r->t_last = t;
    memcpy(y_end, y, sizeof y);
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

/* The continuous solution of a run (its stored steps T, Y) at `times` (increasing, in [T[0], T[K-1]])
 * into out (n x ADB_NY): each step's interpolant, the one r_max and t_dec are located on.  Returns 0. */
int adb_dense(const double *T, const double *Y, long K, const double *p, const adb_settings *s, int n,
              const double *times, double *out)
{
    (void)s;
    Dense d;
    size_t k = 0, held = (size_t)-1;
    for (int j = 0; j < n; ++j) {
        while (k + 2 < (size_t)K && T[k + 1] < times[j]) ++k;
        if (held != k) {
            dense_of(&d, p, T, Y, k);
            held = k;
        }
        dense_at(&d, times[j], out + (size_t)j * ADB_NY);
    }
    return 0;
}

/* CPU ns (this thread's clock: on a shared machine the wall clock counts other processes' time) per
 * rhs evaluation of this library's rhs: `calls` evaluations along a moving state (each feeds the next,
 * so none can be skipped), the floor the engine's time is compared against (bench rk) */
static double thread_ns(void)
{
    struct timespec a;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
    return a.tv_sec * 1e9 + a.tv_nsec;
}

double adb_rk_time_rhs(const double *y0, const double *p, long calls)
{
    double y[ADB_NY], f[ADB_NY];
    memcpy(y, y0, sizeof y);
    double start = thread_ns();
    for (long c = 0; c < calls; ++c) {
        ADB_RHS(0.0, y, p, f);
        for (int i = 0; i < ADB_NY; ++i) y[i] += 1e-9 * f[i];
    }
    double ns = thread_ns() - start;
    volatile double sink = y[0];
    (void)sink;
    return ns / (double)calls;
}

/* CPU ns per rhs evaluation at the run's own states: one evaluation at each of the K states of Y (K x
 * ADB_NY, a run's accepted steps in order), each input chained to the previous output by an addition that
 * leaves it unchanged (1e-300 f: the evaluations cannot overlap, as a run's stages cannot).  The floor of
 * bench rk: the rhs's cost depends on the state (libm's sin and cos take longer paths for larger angles),
 * so the states a run visits are the ones its evaluations are timed at. */
double adb_rk_time_rhs_along(const double *Y, long K, const double *p)
{
    double y[ADB_NY], f[ADB_NY] = {0.0};
    double start = thread_ns();
    for (long k = 0; k < K; ++k) {
        for (int i = 0; i < ADB_NY; ++i) y[i] = Y[k * ADB_NY + i] + 1e-300 * f[i];
        ADB_RHS(0.0, y, p, f);
    }
    double ns = thread_ns() - start;
    volatile double sink = f[0];
    (void)sink;
    return ns / (double)K;
}
