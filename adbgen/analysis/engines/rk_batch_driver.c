/* The DOP853 ensemble engine (issue 22 item 4): ADB_LANES trajectories per vector, every operation of a
 * step (the stages, the model's rhs from generated/<model>/<model>_lanes.h, the error sums) one vector
 * operation over the lanes, compiled with
 *
 *     -DADB_LANES_SOURCE='"<model>_lanes.h"' -DADB_RHS_LANES=<model>_rhs_lanes -DADB_NY=.. -DADB_NP=..
 *     -DADB_LANES=8|4|1 [-DADB_EXACT_MATH=1]
 *
 * Per-lane steps: each lane has its own time, step size, accept/reject, segment ends and early stop; the
 * step arithmetic is element-wise, so lanes at different times and step sizes cost nothing extra (the rhs
 * takes a vector of times).  A shared step would have to be the smallest any lane accepts (the others
 * wasting accuracy, their error control reduced to bookkeeping) and would end at the slowest lane; per-lane
 * steps only mask what each lane does after the step (scalar code, once per step, not per stage).  A lane
 * whose trajectory ends takes the next one from a queue shared by the threads; with the queue empty it
 * computes a copy of a running lane (its results unused) until the group is done.
 *
 * Each lane's step is rk_driver.c's: the same tableau (rk_dop853.h), the same controller and statuses, the
 * same segments and target regions.  With ADB_EXACT_MATH=1 (glibc's scalar sin/cos, both libraries built
 * without merging sin and cos into sincos) every trajectory is bitwise the scalar engine's; with libmvec's
 * sin/cos (the default) they differ by the functions' last bits (4 ulp), i.e. within the tolerance's noise.  This engine reports no r_max/t_dec (sweeps' attractor
 * labels need neither): the Python side runs the scalar engine for those.
 */
#include <stdlib.h>
#include <string.h>

#include "lanes.h"
#include ADB_LANES_SOURCE
#include "driver_common.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#define RK_T adb_lanes
#define RK_NY ADB_NY
#define RK_ABS(x) adb_lanes_abs(x)
#define RK_MAX(a, b) adb_lanes_max(a, b)
#define RK_RHS(t, y, f) ADB_RHS_LANES((t), (y), ((const adb_lanes *)ctx), (f))
#include "rk_dop853.h"

const char adb_rk_batch_math[] = ADB_VECTOR_MATH;
const int adb_rk_batch_lanes = ADB_LANES;

typedef struct {
    long k;      /* trajectory (row), -1: idle */
    double t, h_abs, seg_end, min_step;
    long steps, evals;
    int rejected;
} Lane;

typedef struct {
    double t_end, rtol, atol, check_dt;
    long max_steps;
    int n_targets;
    const double *centres, *weights, *cubics, *levels;
    const unsigned char *periodic;
    double *Y_end;
    adb_result *res;
} Job;

static void get_lane(const adb_lanes *v, int b, double *out, int n)
{
    for (int i = 0; i < n; ++i) out[i] = v[i][b];
}

static void set_lane(adb_lanes *v, int b, const double *in, int n)
{
    for (int i = 0; i < n; ++i) v[i][b] = in[i];
}

static void finish(const Job *J, Lane *L, const adb_lanes *Y, int b, int status)
{
    long k = L->k;
    double y[ADB_NY];
    get_lane(Y, b, y, ADB_NY);
    adb_result *r = J->res + k;
    r->status = status;
    memcpy(J->Y_end + (size_t)k * ADB_NY, y, sizeof y);
    r->r_max = r->t_dec = NAN;
    r->t_last = L->t;
    r->t_fail = (status == ADB_SUCCESS || status == ADB_STOPPED) ? NAN : L->t;
    r->n_rhs = L->evals;
    r->n_steps = L->steps;
    L->k = -1;
}

/* One lane group: trajectories from the shared counter *next until all n are taken and done. */
static void run_group(const Job *J, int n, const double *Y0, const double *P, long *next)
{
    adb_lanes Y[ADB_NY], Yn[ADB_NY], Pv[ADB_NP], K[DOP_EXTENDED][ADB_NY], tmp[ADB_NY], f1[ADB_NY];
    Lane L[ADB_LANES];
    const adb_lanes *ctx = Pv;
    memset(Y, 0, sizeof Y), memset(Pv, 0, sizeof Pv), memset(K, 0, sizeof K);
    for (int b = 0; b < ADB_LANES; ++b) L[b].k = -1;
    for (;;) {
        /* refill idle lanes from the queue; a bad initial state is reported at once */
        int fresh[ADB_LANES], n_fresh = 0;
        for (int b = 0; b < ADB_LANES; ++b) {
            while (L[b].k < 0) {
                long k;
#pragma omp atomic capture
                k = (*next)++;
                if (k >= n) break;
                const double *y0 = Y0 + (size_t)k * ADB_NY;
                L[b] = (Lane){k, 0.0, 0.0, J->check_dt > 0.0 ? fmin(J->t_end, J->check_dt) : J->t_end, 0.0, 0, 2, 0};
                J->res[k].target = -1;
                if (!adb_all_finite(y0, ADB_NY)) {
                    set_lane(Y, b, y0, ADB_NY);
                    for (int i = 0; i < ADB_NY; ++i) Y[i][b] = 0.0;
                    L[b].evals = 0;
                    finish(J, &L[b], Y, b, ADB_BAD_INPUT);
                    J->Y_end[(size_t)k * ADB_NY] = NAN;
                    memcpy(J->Y_end + (size_t)k * ADB_NY, y0, sizeof(double) * ADB_NY);
                    continue;
                }
                set_lane(Y, b, y0, ADB_NY);
                set_lane(Pv, b, P + (size_t)k * ADB_NP, ADB_NP);
                fresh[n_fresh++] = b;
            }
        }
        int running = -1;
        for (int b = 0; b < ADB_LANES; ++b)
            if (L[b].k >= 0) running = b;
        if (running < 0) return;
        /* idle lanes compute a copy of a running one (valid numbers, results unused) */
        for (int b = 0; b < ADB_LANES; ++b)
            if (L[b].k < 0) {
                for (int i = 0; i < ADB_NY; ++i) Y[i][b] = Y[i][running], K[0][i][b] = K[0][i][running];
                for (int i = 0; i < ADB_NP; ++i) Pv[i][b] = Pv[i][running];
                L[b].t = L[running].t, L[b].h_abs = L[running].h_abs;
            }
        if (n_fresh) {
            /* f(0, y0) and Hairer's first step for the new lanes (two vector rhs for all of them) */
            adb_lanes tv, h0v;
            for (int b = 0; b < ADB_LANES; ++b) tv[b] = L[b].t;
            RK_RHS(tv, Y, tmp);
            double h0[ADB_LANES], d1[ADB_LANES];
            for (int b = 0; b < ADB_LANES; ++b) h0[b] = 0.0, d1[b] = 0.0;
            for (int q = 0; q < n_fresh; ++q) {
                int b = fresh[q];
                double d0 = 0.0, dd = 0.0;
                for (int i = 0; i < ADB_NY; ++i) {
                    K[0][i][b] = tmp[i][b];
                    double sc = J->atol + fabs(Y[i][b]) * J->rtol;
                    d0 += (Y[i][b] / sc) * (Y[i][b] / sc), dd += (tmp[i][b] / sc) * (tmp[i][b] / sc);
                }
                d0 = sqrt(d0 / ADB_NY), dd = sqrt(dd / ADB_NY);
                double h = (d0 < 1e-5 || dd < 1e-5) ? 1e-6 : 0.01 * d0 / dd;
                h0[b] = fmin(h, L[b].seg_end - L[b].t), d1[b] = dd;
            }
            for (int b = 0; b < ADB_LANES; ++b) h0v[b] = h0[b];
            for (int i = 0; i < ADB_NY; ++i) tmp[i] = Y[i] + h0v * K[0][i];
            RK_RHS(tv + h0v, tmp, f1);
            for (int q = 0; q < n_fresh; ++q) {
                int b = fresh[q];
                double d2 = 0.0;
                for (int i = 0; i < ADB_NY; ++i) {
                    double sc = J->atol + fabs(Y[i][b]) * J->rtol, v = (f1[i][b] - K[0][i][b]) / sc;
                    d2 += v * v;
                }
                d2 = sqrt(d2 / ADB_NY) / h0[b];
                double h1 = (d1[b] <= 1e-15 && d2 <= 1e-15) ? fmax(1e-6, h0[b] * 1e-3)
                                                            : pow(0.01 / fmax(d1[b], d2), 1.0 / 8.0);
                L[b].h_abs = fmin(fmin(100.0 * h0[b], h1), L[b].seg_end - L[b].t);
            }
        }
        /* one step attempt of every lane, each with its own t and h */
        adb_lanes tv, hv, e5, e3;
        double t_new[ADB_LANES];
        for (int b = 0; b < ADB_LANES; ++b) {
            Lane *l = &L[b];
            double ms = 10.0 * (nextafter(l->t, INFINITY) - l->t);
            if (l->k >= 0 && !l->rejected && l->h_abs < ms) l->h_abs = ms;
            l->min_step = ms;
            double tn = l->t + l->h_abs;
            if (tn > l->seg_end) tn = l->seg_end;
            t_new[b] = tn;
            tv[b] = l->t, hv[b] = tn - l->t;
        }
        dop_step(tv, hv, Y, K, Yn, J->rtol, J->atol, &e5, &e3, ctx);
        for (int b = 0; b < ADB_LANES; ++b) {
            Lane *l = &L[b];
            if (l->k < 0) continue;
            l->evals += DOP_STAGES;
            double h = hv[b], err = dop_norm(h, e5[b], e3[b]), fin = 0.0;
            for (int i = 0; i < ADB_NY; ++i) fin += 0.0 * Yn[i][b] + 0.0 * K[DOP_STAGES][i][b];
            if (!(fin == 0.0)) { /* a non-finite state or derivative (rk_driver.c's rule) */
                finish(J, l, Y, b, ADB_NONFINITE);
                continue;
            }
            double f = dop_factor(err, l->rejected);
            l->h_abs = fabs(h) * f;
            if (!(err < 1.0)) {
                l->rejected = 1;
                if (l->h_abs < l->min_step) finish(J, l, Y, b, ADB_STEP_UNDERFLOW);
                continue;
            }
            l->rejected = 0;
            l->t = t_new[b];
            ++l->steps;
            for (int i = 0; i < ADB_NY; ++i) Y[i][b] = Yn[i][b], K[0][i][b] = K[DOP_STAGES][i][b];
            if (l->t >= J->t_end) {
                finish(J, l, Y, b, ADB_SUCCESS);
                continue;
            }
            if (l->t >= l->seg_end) {
                if (J->n_targets > 0) {
                    double y[ADB_NY];
                    get_lane(Y, b, y, ADB_NY);
                    int tk = adb_in_target(y, J->n_targets, J->centres, J->weights, J->cubics, J->levels, J->periodic);
                    if (tk >= 0) {
                        J->res[l->k].target = tk;
                        finish(J, l, Y, b, ADB_STOPPED);
                        continue;
                    }
                }
                l->seg_end = fmin(J->t_end, l->seg_end + J->check_dt);
            }
            if (J->max_steps > 0 && l->steps >= J->max_steps) finish(J, l, Y, b, ADB_MAX_STEPS);
        }
    }
}

/* adb_integrate_many (adb_engine.h; s->measures ignored: r_max, t_dec NaN) on lane groups: one group per
 * OpenMP thread, all taking trajectories from one queue. */
void adb_integrate_many(int n, const double *Y0, const double *P, const adb_settings *s, int threads,
                        double *Y_end, adb_result *res)
{
    Job J = {s->t_end, s->rtol, s->atol, s->check_dt, s->max_steps, s->n_targets, s->centres, s->weights,
             s->cubics, s->levels, s->periodic, Y_end, res};
    long next = 0;
    if (!(s->t_end > 0.0) || !(s->rtol > 0.0) || !(s->atol > 0.0)) {
        for (int k = 0; k < n; ++k) {
            adb_result_clear(res + k);
            res[k].status = ADB_BAD_INPUT;
            memcpy(Y_end + (size_t)k * ADB_NY, Y0 + (size_t)k * ADB_NY, sizeof(double) * ADB_NY);
        }
        return;
    }
#ifdef _OPENMP
    if (threads < 1) threads = omp_get_max_threads();
    int groups = (n + ADB_LANES - 1) / ADB_LANES;
    if (threads > groups) threads = groups > 0 ? groups : 1;
#pragma omp parallel num_threads(threads)
#endif
    run_group(&J, n, Y0, P, &next);
}
