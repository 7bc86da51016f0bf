/* The Taylor engine: Taylor's method on a model's emitted series (<model>_taylor.c, the taylor target),
 * adaptive step as in Jorba & Zou (2005) and heyoka, the order fixed per build (ADB_TS_ORDER).
 *
 * One translation unit per (model, order): it #includes the model's series source with TS_MAXO =
 * ADB_TS_ORDER, so every order of a step is the always-inline series body with a constant K, every
 * convolution unrolled; compiled by adbgen.analysis.engines.taylor with
 *
 *     -DADB_TS_SOURCE='"<model>_taylor.c"' -DADB_TS_PREFIX=<model> -DADB_TS_ORDER=<p> -DADB_NY=<states>
 *     -DADB_NP=<parameters> -D'ADB_TS_ORDERS(FN)=FN(0) ... FN(<p - 1>)'   (gcc -O3 -march=native
 *     -ffp-contract=off)
 *
 * A step from (t, y): the coefficients y_0..y_p of the solution (y_{K+1} = f_K / (K + 1)); the step
 * h = fac * rho exp(-0.7 / (p - 1)) / e^2 (Jorba & Zou's rule, heyoka's with fac = 1) with rho taken per
 * component (`step_size`); clamped to t_end and to the first sign change of a Piecewise condition's
 * series (the ramp's t - t_ramp: the branch never changes inside a step); the new state by Horner.
 *
 * r_max and t_dec (thesis ch. 5) are located on each step's polynomial r^2(s) = x(s)^2 + y(s)^2 (exact
 * to the order of the method): a bound sum_k |x_k| h^k, sum_k |y_k| h^k screens the steps; r_max takes
 * the polynomial's largest value on [0, h] (its ends and the roots of d r^2/ds), t_dec the last root of
 * r^2 - H^2 in a step that ends below H.  Roots are isolated by Descartes' rule on the Bernstein
 * coefficients (subdivision by de Casteljau) and refined by bisection.  What they find goes to
 * event_measures.h with each step's end, which reports r_max and t_dec by the rule every engine shares.
 *
 * Exact symmetry: the series program evaluates every ball by the same lane operations, and the step
 * (norms, Horner) treats every component alike, so identical balls stay together bit for bit.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#ifndef ADB_TS_ORDER
#error "ADB_TS_ORDER (the Taylor order) must be defined"
#endif
#define TS_MAXO ADB_TS_ORDER
#if defined(TS_B) && TS_B > 1 && defined(TS_VECTOR_MATH) && TS_VECTOR_MATH
/* The ensemble build: sin, cos (the series' order 0) and pow (the step) have SIMD variants in glibc's
 * libmvec (within 4 ulp; the vector ABI GCC emits for `simd` functions), so the loops over a batch's
 * lanes call _ZGVeN8v_sin etc. once per vector instead of libm once per lane (link -lmvec; built with
 * -fno-builtin-sin etc., and `const` since errno is never read, else GCC merges sin and cos into a scalar
 * sincos per lane or keeps the calls for their errno).  Without TS_VECTOR_MATH every lane calls libm, bit
 * for bit the single stepper (tested). */
#include <math.h>
double sin(double) __attribute__((simd("notinbranch"), const));
double cos(double) __attribute__((simd("notinbranch"), const));
double pow(double, double) __attribute__((simd("notinbranch"), const));
#endif
#include ADB_TS_SOURCE
#include "driver_common.h"
#include "event_measures.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#define ADB_CAT2(a, b) a##b
#define ADB_CAT(a, b) ADB_CAT2(a, b)
#define TSF(x) ADB_CAT(ADB_TS_PREFIX, x)
typedef TSF(_ts) TsWork;

#define P ADB_TS_ORDER
#define NY ADB_NY
/* The norm of the step rule: 0, per component (each state's own weight |y_i| + atol / rtol, the default);
 * 1, the state's inf norm (weight max(|y|_inf, atol / rtol) for every component: Jorba & Zou's rule as
 * they and heyoka use it, longer steps where a small component (the rotor's x, y) has relatively large
 * coefficients, its error then held to the largest state's scale) */
#ifndef ADB_TS_NORM
#define ADB_TS_NORM 0
#endif
/* exp(-0.7 / (P - 1)) / e^2, Jorba & Zou's safety factor and scaling */
#define ADB_JZ_FACTOR (exp(-0.7 / (P - 1)) / (M_E * M_E))
#define DEG (2 * P) /* r^2's degree */

/* A stepper on a 64-byte boundary: every series row of an 8-lane batch (64 bytes) then starts a cache line, so
 * no vector load of a coefficient straddles two lines (malloc promises 16 bytes).  Not a measured speed-up on
 * its own: the runs that first suggested one (1.16-1.20x) turned out to vary with where the workspace lay,
 * aligned or not, and the cure was a smaller workspace (one row for a series without history, ccode.py). */
static void *ts_alloc(size_t size)
{
    void *p = NULL;
    return posix_memalign(&p, 64, size) == 0 ? p : NULL;
}

#if TS_B == 1 /* the single trajectory (a batch build, TS_B > 1, has its own stepper below) */
typedef struct {
    double jet[P + 1][NY]; /* the solution's coefficients of the current step */
    double f[NY];
    TsWork w;
} Stepper;

/* Order K of the series program, K constant: one function per order (each compiled on its own, which
 * keeps gcc's time linear in the order's size), its convolutions unrolled.  The build's orders come from
 * ADB_TS_ORDERS(FN), FN(0) FN(1) ... FN(P - 1), rendered for the order by engines/taylor.py (build). */
#define ADB_ORDER_FN(K)                                                                                      \
    static __attribute__((noinline)) void order_##K(Stepper *S)                                              \
    {                                                                                                        \
        TSF(_ts_order)(&S->w, (K), S->f);                                                                    \
        for (int r = 0; r < NY; ++r) S->jet[(K) + 1][r] = S->f[r] * ts_rec[(K) + 1];                           \
        TSF(_ts_load)(&S->w, (K) + 1, S->jet[(K) + 1]);                                                      \
    }

/* The jet of the solution through (t, y): rows 0..P. */
static void jet_of(Stepper *S, double t, const double *y);

#if P > 40 || P < 2
#error "ADB_TS_ORDER must be in 2..40"
#endif
ADB_TS_ORDERS(ADB_ORDER_FN)
#define ADB_ORDER_PTR(K) order_##K,
static void (*const orders[P])(Stepper *) = {ADB_TS_ORDERS(ADB_ORDER_PTR)};

static void jet_of(Stepper *S, double t, const double *y)
{
    TSF(_ts_time)(&S->w, &t, 1.0);
    memcpy(S->jet[0], y, sizeof(double) * NY);
    TSF(_ts_load)(&S->w, 0, S->jet[0]);
    for (int K = 0; K < P; ++K) orders[K](S);
}
#endif

/* Jorba & Zou's step (see the header), per component: rho = min over k = P - 1, P and i of
 * (w_i / |y_k,i|)^(1/k) with w_i = |y_0,i| + atol / rtol, so |y_P,i| h^P ~ (atol + rtol |y_i|) e^(-2P) for
 * every state (a small rotor coordinate beside large spin angles keeps its own accuracy).  fac scales
 * the step (1: Jorba & Zou's). */
typedef double Jet[P + 1][NY];

static double step_size(const Jet jet, double rtol, double atol, double fac)
{
    const double a = atol / rtol;
    double qp = 0.0, qm = 0.0;
#if ADB_TS_NORM == 1
    double m0 = 0.0;
    for (int r = 0; r < NY; ++r) {
        const double v0 = fabs(jet[0][r]), vp = fabs(jet[P][r]), vm = fabs(jet[P - 1][r]);
        m0 = v0 > m0 ? v0 : m0;
        qp = vp > qp ? vp : qp;
        qm = vm > qm ? vm : qm;
    }
    const double inv = 1.0 / (m0 > a ? m0 : a);
    qp *= inv;
    qm *= inv;
#else
    for (int r = 0; r < NY; ++r) {
        const double inv = 1.0 / (fabs(jet[0][r]) + a);
        const double vp = fabs(jet[P][r]) * inv, vm = fabs(jet[P - 1][r]) * inv;
        qp = vp > qp ? vp : qp;
        qm = vm > qm ? vm : qm;
    }
#endif
    const double rp = pow(qp, -1.0 / P), rm = pow(qm, -1.0 / (P - 1));
    const double rho = rp < rm ? rp : rm;
    return fac * rho * ADB_JZ_FACTOR;
}

static void horner(const Jet jet, double h, double *y)
{
    for (int r = 0; r < NY; ++r) {
        double s = jet[P][r];
        for (int k = P - 1; k >= 0; --k) s = s * h + jet[k][r];
        y[r] = s;
    }
}

/* ------------------------------------------------------------------------------ polynomial roots */

static double poly_at(const double *c, int d, double s)
{
    double v = c[d];
    for (int k = d - 1; k >= 0; --k) v = v * s + c[k];
    return v;
}

static int variations(const double *b, int d)
{
    int n = 0, last = 0;
    for (int j = 0; j <= d; ++j) {
        int sg = b[j] > 0.0 ? 1 : (b[j] < 0.0 ? -1 : 0);
        if (sg && last && sg != last) ++n;
        if (sg) last = sg;
    }
    return n;
}

/* the root of c (degree d, in u on [0, 1] after scaling) in [lo, hi] with a sign change: bisection */
static double bisect(const double *c, int d, double lo, double hi)
{
    double flo = poly_at(c, d, lo);
    for (int it = 0; it < 200; ++it) {
        double m = 0.5 * (lo + hi);
        if (m <= lo || m >= hi) break;
        double fm = poly_at(c, d, m);
        if ((fm > 0.0) == (flo > 0.0) && fm != 0.0) lo = m, flo = fm;
        else hi = m;
    }
    return 0.5 * (lo + hi);
}

#define MAXR 64
/* Roots of the polynomial c (degree d <= DEG, in u on [0, 1]) with Bernstein coefficients b on
 * [lo, hi]: Descartes' rule (0 variations: none; 1: one, refined by bisection), else halves by
 * de Casteljau.  Appends to roots (ascending), at most MAXR. */
static void isolate(const double *c, int d, const double *b, double lo, double hi, int depth, double *roots, int *n)
{
    int v = variations(b, d);
    if (v == 0 || *n >= MAXR) return;
    if (v == 1 && (poly_at(c, d, lo) > 0.0) != (poly_at(c, d, hi) > 0.0)) {
        roots[(*n)++] = bisect(c, d, lo, hi);
        return;
    }
    if (depth > 48 || hi - lo < 1e-15) {
        if ((poly_at(c, d, lo) > 0.0) != (poly_at(c, d, hi) > 0.0)) roots[(*n)++] = 0.5 * (lo + hi);
        return;
    }
    double left[DEG + 1], right[DEG + 1], tmp[DEG + 1];
    memcpy(tmp, b, sizeof(double) * (d + 1));
    for (int k = 0; k <= d; ++k) {
        left[k] = tmp[0];
        right[d - k] = tmp[d - k];
        for (int j = 0; j < d - k; ++j) tmp[j] = 0.5 * (tmp[j] + tmp[j + 1]);
    }
    double mid = 0.5 * (lo + hi);
    isolate(c, d, left, lo, mid, depth + 1, roots, n);
    isolate(c, d, right, mid, hi, depth + 1, roots, n);
}

static double binom_tab[DEG + 1][DEG + 1];
static int binom_ready = 0;

static void binoms(void)
{
    if (binom_ready) return;
    for (int n = 0; n <= DEG; ++n) {
        binom_tab[n][0] = binom_tab[n][n] = 1.0;
        for (int k = 1; k < n; ++k) binom_tab[n][k] = binom_tab[n - 1][k - 1] + binom_tab[n - 1][k];
    }
    binom_ready = 1;
}

/* Roots in [0, h] of the polynomial sum_k c_k s^k (degree d), ascending, in s; returns their number */
static int roots_on(const double *c, int d, double h, double *roots)
{
    double a[DEG + 1], b[DEG + 1];
    double hk = 1.0;
    for (int k = 0; k <= d; ++k) a[k] = c[k] * hk, hk *= h;
    while (d > 0 && a[d] == 0.0) --d;
    if (d == 0) return 0;
    for (int j = 0; j <= d; ++j) {
        double s = 0.0;
        for (int k = 0; k <= j; ++k) s += binom_tab[j][k] / binom_tab[d][k] * a[k];
        b[j] = s;
    }
    int n = 0;
    isolate(a, d, b, 0.0, 1.0, 0, roots, &n);
    for (int k = 0; k < n; ++k) roots[k] *= h;
    return n;
}

/* r^2(s) of the step from the amplitude's series x, y: coefficients 0..DEG */
static void r2_poly(const double *x, const double *y, double *q)
{
    for (int k = 0; k <= DEG; ++k) {
        /* the products j, k - j and k - j, j are one: twice the sum below the middle, plus the middle */
        double s = 0.0;
        const int lo = k > P ? k - P : 0;
        for (int j = lo; 2 * j < k; ++j) s += x[j] * x[k - j] + y[j] * y[k - j];
        s += s;
        if (!(k & 1)) s += x[k / 2] * x[k / 2] + y[k / 2] * y[k / 2];
        q[k] = s;
    }
}

/* sum_k |x_k| h^k and |y_k|'s: |r(s)| <= hypot of both on [0, h] */
static double r2_bound(const Jet jet, const int *amp, double h)
{
    double bx = 0.0, by = 0.0, hk = 1.0;
    for (int k = 0; k <= P; ++k) {
        bx += fabs(jet[k][amp[0]]) * hk;
        by += fabs(jet[k][amp[1]]) * hk;
        hk *= h;
    }
    return bx * bx + by * by;
}

/* largest r^2 on [0, h]: the ends and the roots of d r^2 / ds */
static double r2_max(const double *q, double h)
{
    double dq[DEG], roots[MAXR];
    for (int k = 1; k <= DEG; ++k) dq[k - 1] = k * q[k];
    double best = fmax(poly_at(q, DEG, 0.0), poly_at(q, DEG, h));
    int n = roots_on(dq, DEG - 1, h, roots);
    for (int k = 0; k < n; ++k) best = fmax(best, poly_at(q, DEG, roots[k]));
    return best;
}

/* the last s in [0, h] with r^2(s) >= H2, given r^2(h) < H2; -1 if r^2 < H2 on [0, h] */
static double r2_last_above(const double *q, double h, double H2)
{
    double c[DEG + 1], roots[MAXR];
    memcpy(c, q, sizeof c);
    c[0] -= H2;
    int n = roots_on(c, DEG, h, roots);
    return n ? roots[n - 1] : -1.0;
}

/* the first sign change in (0, h] of the Piecewise conditions' series (lane b): h itself if none */
static double switch_limit(const TsWork *w, int b, double t, double h)
{
#if TS_N_SWITCH > 0
    double c[P + 1], roots[MAXR];
    for (int which = 0; which < TS_N_SWITCH; ++which) {
        for (int k = 0; k < P; ++k) c[k] = TSF(_ts_switch)(w, which, k, b);
        c[P] = 0.0; /* (the body computes a switch's coefficients to order P - 1) */
        int n = roots_on(c, P - 1, h, roots);
        for (int k = 0; k < n; ++k)
            if (roots[k] > 0.0) {
                /* a change within an ulp of t: step one ulp, past it (the next step takes the other branch) */
                h = fmin(h, t + roots[k] > t ? roots[k] : nextafter(t, INFINITY) - t);
                break;
            }
    }
#else
    (void)w;
    (void)b;
    (void)t;
#endif
    return h;
}

/* ------------------------------------------------------------------------------ integration */

/* What a run is asked (shared by the trajectories of a batch): adb_settings with the threshold H and H^2 */
typedef struct {
    double t_end, rtol, atol, fac, H, H2, check_dt;
    long max_steps;
    const int *amp;
    int measures, n_targets;
    const double *centres, *weights, *cubics, *levels;
    const unsigned char *periodic;
} Settings;

/* A step kept for r_max or t_dec (its start, length, screen bound and the amplitude's two series): the
 * root finding on r^2 is deferred, as most such steps are superseded (a later step reaches higher, or
 * crosses the threshold later) and never need it */
#define PEND 16
typedef struct {
    double t, h, bound, x[P + 1], y[P + 1];
} Pending;

/* One trajectory's state between steps (a lane of a batch, or the single run) */
typedef struct {
    double t, y[NY], next_check;
    adb_events ev; /* r_max and t_dec (event_measures.h), fed each step's end and what the pending steps give */
    Pending pmax[PEND], pdec[PEND];
    int n_max, n_dec;
    long steps;
    int status, target, running;
    int keep; /* the single run: every step end into T, Y */
    size_t cap, K;
    double *T, *Y;
    double t_fail;
} Lane;

static void lane_start(Lane *L, const Settings *st, const double *y0, int keep)
{
    memset(L, 0, sizeof *L);
    memcpy(L->y, y0, sizeof L->y);
    adb_events_start(&L->ev, st->H, y0, st->amp);
    L->next_check = st->check_dt > 0.0 ? st->check_dt : INFINITY;
    L->status = ADB_SUCCESS;
    L->target = -1;
    L->running = 1;
    L->t_fail = NAN;
    L->keep = keep;
    if (keep) {
        L->cap = 1024;
        L->T = malloc(L->cap * sizeof(double));
        L->Y = malloc(L->cap * NY * sizeof(double));
        L->T[0] = 0.0;
        memcpy(L->Y, y0, sizeof(double) * NY);
        L->K = 1;
    }
}

static void lane_store(Lane *L)
{
    if (!L->keep) return;
    if (L->K + 1 > L->cap) {
        L->cap *= 2;
        L->T = realloc(L->T, L->cap * sizeof(double));
        L->Y = realloc(L->Y, L->cap * NY * sizeof(double));
    }
    L->T[L->K] = L->t;
    memcpy(L->Y + L->K * NY, L->y, sizeof L->y);
    ++L->K;
}

static void pend(Pending *c, const Jet jet, const int *amp, double t, double h, double bound)
{
    c->t = t;
    c->h = h;
    c->bound = bound;
    for (int k = 0; k <= P; ++k) {
        c->x[k] = jet[k][amp[0]];
        c->y[k] = jet[k][amp[1]];
    }
}

/* r^2's own screen, r^2_0 + sum_k |r^2_k| h^k (tight where x, y turn while r changes slowly) */
static double q_bound(const double *q, double h)
{
    double tail = 0.0, hk = h;
    for (int k = 1; k <= DEG; ++k, hk *= h) tail += fabs(q[k]) * hk;
    return q[0] + tail;
}

/* r_max over the pending steps, highest screen bound first, until the bound is below r_max */
static void resolve_max(Lane *L)
{
    double q[DEG + 1];
    for (;;) {
        int best = -1;
        for (int i = 0; i < L->n_max; ++i)
            if (L->pmax[i].bound > L->ev.r2max && (best < 0 || L->pmax[i].bound > L->pmax[best].bound)) best = i;
        if (best < 0) break;
        Pending *c = &L->pmax[best];
        r2_poly(c->x, c->y, q);
        if (q_bound(q, c->h) > L->ev.r2max) L->ev.r2max = fmax(L->ev.r2max, r2_max(q, c->h));
        c->bound = -INFINITY;
    }
    L->n_max = 0;
}

/* t_dec over the pending steps (all after the last step ending at or above the threshold), latest
 * first: the first with r^2 reaching H2 gives the last time above it */
static void resolve_dec(Lane *L, double H2)
{
    double q[DEG + 1];
    for (int i = L->n_dec - 1; i >= 0; --i) {
        const Pending *c = &L->pdec[i];
        r2_poly(c->x, c->y, q);
        if (q_bound(q, c->h) < H2) continue;
        const double sl = r2_last_above(q, c->h, H2);
        if (sl >= 0.0) {
            adb_events_crossing(&L->ev, c->t + sl);
            break;
        }
    }
    L->n_dec = 0;
}

static void lane_fail(Lane *L, int status)
{
    L->status = status;
    L->t_fail = L->t;
    L->running = 0;
}

/* The step a lane may take from the rule's size h: clamped to t_end and to the first Piecewise switch
 * (lane b of the workspace w); 0 with the lane failed at the step limit, on non-finite last coefficients
 * (cp, cm: rows P and P - 1, NY values `stride` apart) or when the step underflows.  The single stepper
 * and the batch's whole-step path both admit their steps here. */
static double lane_admit(Lane *L, const Settings *st, const TsWork *w, int b, double h, const double *cp,
                         const double *cm, int stride)
{
    const double t = L->t;
    if (st->max_steps > 0 && L->steps >= st->max_steps) {
        lane_fail(L, ADB_MAX_STEPS);
        return 0.0;
    }
    if (!(h > 0.0) || !isfinite(h)) {
        /* a zero or non-finite coefficient norm: a non-finite state, or an exactly polynomial solution */
        for (int r = 0; r < NY; ++r)
            if (!isfinite(cp[r * stride]) || !isfinite(cm[r * stride])) {
                lane_fail(L, ADB_NONFINITE);
                return 0.0;
            }
        h = st->t_end - t;
    }
    if (t + h > st->t_end) h = st->t_end - t;
    h = switch_limit(w, b, t, h);
    if (!(t + h > t)) {
        lane_fail(L, ADB_STEP_UNDERFLOW);
        return 0.0;
    }
    return h;
}

/* One step of a lane from the jet of its state (lane b of the workspace w for the Piecewise switches):
 * the step size, the new state, r_max and t_dec on the step's polynomial, early stop. */
static void lane_step(Lane *L, const Settings *st, const Jet jet, const TsWork *w, int b)
{
    const double t = L->t;
    double ynew[NY];
    const double h = lane_admit(L, st, w, b, step_size(jet, st->rtol, st->atol, st->fac), jet[P], jet[P - 1], 1);
    if (!L->running) return;
    horner(jet, h, ynew);
    if (!adb_all_finite(ynew, NY)) {
        lane_fail(L, ADB_NONFINITE);
        return;
    }
    const double t1 = (t + h >= st->t_end) ? st->t_end : t + h;
    ++L->steps;
    if (st->measures) {
        /* a screen, (sum |x_k| h^k)^2 + (sum |y_k| h^k)^2 >= r^2 on the step, keeps the steps that may
         * raise r_max or hold t_dec (pending, resolved when full and at the end); r_max meanwhile is the
         * largest r^2 at a step end */
        const double end2 = adb_r2(ynew, st->amp[0], st->amp[1]), H2 = st->H2;
        const double bound = r2_bound(jet, st->amp, h);
        if (bound > L->ev.r2max) {
            if (L->n_max == PEND) resolve_max(L);
            pend(&L->pmax[L->n_max++], jet, st->amp, t, h, bound);
        }
        if (end2 < H2 && bound >= H2) {
            if (L->n_dec == PEND) resolve_dec(L, H2);
            pend(&L->pdec[L->n_dec++], jet, st->amp, t, h, bound);
        }
        adb_events_point(&L->ev, t1, end2);
        if (end2 >= H2) L->n_dec = 0; /* every pending step is earlier */
    }
    /* early stop: the state at each multiple of check_dt inside this step, on its polynomial (the steps
     * are the same with or without targets) */
    while (st->n_targets > 0 && L->next_check <= t1 && L->next_check < st->t_end) {
        double yc[NY];
        horner(jet, L->next_check - t, yc);
        int k = adb_in_target(yc, st->n_targets, st->centres, st->weights, st->cubics, st->levels, st->periodic);
        if (k >= 0) {
            L->target = k;
            L->status = ADB_STOPPED;
            L->t = L->next_check;
            memcpy(L->y, yc, sizeof yc);
            lane_store(L);
            L->running = 0;
            return;
        }
        L->next_check += st->check_dt;
    }
    L->t = t1;
    memcpy(L->y, ynew, sizeof ynew);
    lane_store(L);
    if (L->t >= st->t_end) L->running = 0;
}

/* A finished lane's outputs (adb_result; n_rhs: order passes, steps x P, the analogue of rhs evaluations) */
static void lane_finish(Lane *L, const Settings *st, double *y_end, adb_result *r)
{
    if (st->measures) {
        resolve_max(L);
        resolve_dec(L, st->H2);
    }
    adb_events_report(&L->ev, st->measures, L->status, adb_r2(L->y, st->amp[0], st->amp[1]), r);
    r->t_last = L->t;
    r->t_fail = L->t_fail;
    memcpy(y_end, L->y, sizeof L->y);
    r->n_rhs = L->steps * P;
    r->n_steps = L->steps;
    r->target = L->target;
    r->status = L->status;
}

static int bad_settings(const adb_settings *s)
{
    return !(s->t_end > 0.0) || !(s->rtol > 0.0) || !(s->atol > 0.0) || !(s->step_factor > 0.0);
}

/* the run's Settings from the interface's */
static Settings settings_of(const adb_settings *s)
{
    const Settings st = {s->t_end, s->rtol, s->atol, s->step_factor, s->threshold, s->threshold * s->threshold,
                         s->check_dt, s->max_steps, s->amp, s->measures, s->n_targets, s->centres, s->weights, s->cubics,
                         s->levels, s->periodic};
    return st;
}

#if TS_B == 1
/* One trajectory from t = 0 to s->t_end (adb_engine.h, with s->step_factor, the step factor; s->method
 * unused).  With check_dt > 0 the state is tested at every multiple of check_dt (on the step's polynomial:
 * the steps are the same with or without targets) and the run stops in the first target region holding
 * it. */
static int adb_run(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj, double *y_end,
                   adb_result *r)
{
    if (bad_settings(s) || !adb_all_finite(y0, NY)) return ADB_BAD_INPUT;
    binoms();
    Stepper *S = ts_alloc(sizeof(Stepper));
    if (!S) return ADB_SOLVER_FAILURE;
    const Settings st = settings_of(s);
    TSF(_ts_setup)(&S->w, p);
    Lane L;
    lane_start(&L, &st, y0, s->keep && traj != NULL);
    while (L.running) {
        jet_of(S, L.t, L.y);
        lane_step(&L, &st, (const double(*)[NY])S->jet, &S->w, 0);
    }
    lane_finish(&L, &st, y_end, r);
    free(S);
    if (traj && L.keep) {
        traj->t = L.T, traj->y = L.Y, traj->k = (long)L.K;
    } else {
        free(L.T);
        free(L.Y);
    }
    return L.status;
}

#define ADB_MANY_SETUP() binoms() /* the binomial table once, before the threads */
#include "adb_entries.h"

#endif

#if TS_B > 1
/* ---------------------------------------------------------------------- the batch variant (TS_B > 1)
 * TS_B trajectories at once, one per lane of every series (the series program's batch dimension): every
 * operation of a step runs on the TS_B lanes together (SIMD), then each lane takes its own step (its own
 * time, step size, events, switches, early stop).  A finished trajectory's lane takes the next one from
 * the queue; a lane with nothing left to run copies a running lane (its results are not used). */
typedef struct {
    double jet[P + 1][NY * TS_B]; /* row k: state r of lane b at r * TS_B + b (the series' load layout) */
    double f[NY * TS_B];
    TsWork w;
} BStepper;

#define ADB_BORDER_FN(K)                                                                                     \
    static __attribute__((noinline)) void border_##K(BStepper *S)                                            \
    {                                                                                                        \
        TSF(_ts_order)(&S->w, (K), S->f);                                                                    \
        for (int i = 0; i < NY * TS_B; ++i) S->jet[(K) + 1][i] = S->f[i] * ts_rec[(K) + 1];                   \
        TSF(_ts_load)(&S->w, (K) + 1, S->jet[(K) + 1]);                                                      \
    }
ADB_TS_ORDERS(ADB_BORDER_FN)
#define ADB_BORDER_PTR(K) border_##K,
static void (*const borders[P])(BStepper *) = {ADB_TS_ORDERS(ADB_BORDER_PTR)};

static int take_next(int *next, int n)
{
    int k;
#ifdef _OPENMP
#pragma omp atomic capture
#endif
    k = (*next)++;
    return k < n ? k : -1;
}

/* r[b] = x[b]^e over the lanes: libmvec's vector pow in the ensemble build (GCC does not vectorise the
 * loop over a `simd` pow by itself), else libm lane by lane */
#if TS_VECTOR_MATH && TS_B == 8 && defined(__AVX512F__)
typedef double ts_vec __attribute__((vector_size(8 * sizeof(double))));
ts_vec _ZGVeN8vv_pow(ts_vec, ts_vec);
#define TS_VPOW _ZGVeN8vv_pow
#elif TS_VECTOR_MATH && TS_B == 4 && defined(__AVX2__)
typedef double ts_vec __attribute__((vector_size(4 * sizeof(double))));
ts_vec _ZGVdN4vv_pow(ts_vec, ts_vec);
#define TS_VPOW _ZGVdN4vv_pow
#endif
static inline void batch_pow(const double *x, double e, double *r)
{
#ifdef TS_VPOW
    ts_vec xv, ev;
    memcpy(&xv, x, sizeof xv);
    for (int b = 0; b < TS_B; ++b) ev[b] = e;
    const ts_vec rv = TS_VPOW(xv, ev);
    memcpy(r, &rv, sizeof rv);
#else
    for (int b = 0; b < TS_B; ++b) r[b] = pow(x[b], e);
#endif
}

/* Every lane's step at once, where no lane asks for more than its end state (no r_max/t_dec, early stop,
 * Piecewise switches or kept steps): step_size and horner's operations in their order over the lanes
 * (SIMD), so each lane's step is bit for bit the single stepper's when pow is libm's (tested). */
static void batch_step_sizes(const BStepper *S, const Settings *st, double *h)
{
    const double a = st->atol / st->rtol;
    double qp[TS_B], qm[TS_B];
    for (int b = 0; b < TS_B; ++b) qp[b] = qm[b] = 0.0;
#if ADB_TS_NORM == 1
    double m0[TS_B];
    for (int b = 0; b < TS_B; ++b) m0[b] = 0.0;
    for (int r = 0; r < NY; ++r)
        for (int b = 0; b < TS_B; ++b) {
            const double v0 = fabs(S->jet[0][r * TS_B + b]), vp = fabs(S->jet[P][r * TS_B + b]),
                         vm = fabs(S->jet[P - 1][r * TS_B + b]);
            m0[b] = v0 > m0[b] ? v0 : m0[b];
            qp[b] = vp > qp[b] ? vp : qp[b];
            qm[b] = vm > qm[b] ? vm : qm[b];
        }
    for (int b = 0; b < TS_B; ++b) {
        const double inv = 1.0 / (m0[b] > a ? m0[b] : a);
        qp[b] *= inv;
        qm[b] *= inv;
    }
#else
    for (int r = 0; r < NY; ++r)
        for (int b = 0; b < TS_B; ++b) {
            const double inv = 1.0 / (fabs(S->jet[0][r * TS_B + b]) + a);
            const double vp = fabs(S->jet[P][r * TS_B + b]) * inv, vm = fabs(S->jet[P - 1][r * TS_B + b]) * inv;
            qp[b] = vp > qp[b] ? vp : qp[b];
            qm[b] = vm > qm[b] ? vm : qm[b];
        }
#endif
    double rp[TS_B], rm[TS_B];
    batch_pow(qp, -1.0 / P, rp);
    batch_pow(qm, -1.0 / (P - 1), rm);
    for (int b = 0; b < TS_B; ++b) {
        const double rho = rp[b] < rm[b] ? rp[b] : rm[b];
        h[b] = st->fac * rho * ADB_JZ_FACTOR;
    }
}

static void batch_horner(const BStepper *S, const double *h, double *y)
{
    for (int r = 0; r < NY; ++r) {
        double s[TS_B];
        for (int b = 0; b < TS_B; ++b) s[b] = S->jet[P][r * TS_B + b];
        for (int k = P - 1; k >= 0; --k)
            for (int b = 0; b < TS_B; ++b) s[b] = s[b] * h[b] + S->jet[k][r * TS_B + b];
        for (int b = 0; b < TS_B; ++b) y[r * TS_B + b] = s[b];
    }
}

/* The batch build's adb_integrate_many (adb_engine.h): TS_B trajectories per lane group, a group per thread */
void adb_integrate_many(int n, const double *Y0, const double *Pm, const adb_settings *s, int threads,
                        double *Y_end, adb_result *res)
{
    binoms();
    const Settings st = settings_of(s);
    for (int k = 0; k < n; ++k) {
        adb_result_clear(res + k);
        res[k].status = ADB_BAD_INPUT;
    }
    if (bad_settings(s)) return;
    /* nothing asked of a lane but its end state: every step over the lanes at once */
    const int whole = !s->measures && s->n_targets == 0 && TS_N_SWITCH == 0;
    int next = 0;
#ifdef _OPENMP
    if (threads < 1) threads = omp_get_max_threads();
#pragma omp parallel num_threads(threads)
#else
    (void)threads;
#endif
    {
        BStepper *S = ts_alloc(sizeof(BStepper));
        Lane L[TS_B];
        int traj[TS_B];
        double params[TS_B * ADB_NP], tl[TS_B];
        double lj[P + 1][NY];
        int dirty = 1;
        for (int b = 0; b < TS_B; ++b) {
            traj[b] = -1;
            L[b].running = 0;
        }
        for (;;) {
            /* fill idle lanes from the queue (a bad initial state is reported and skipped) */
            for (int b = 0; b < TS_B; ++b) {
                while (!L[b].running) {
                    int k = take_next(&next, n);
                    traj[b] = k;
                    if (k < 0) break;
                    if (!adb_all_finite(Y0 + (size_t)k * NY, NY)) continue;
                    lane_start(&L[b], &st, Y0 + (size_t)k * NY, 0);
                    memcpy(params + b * ADB_NP, Pm + (size_t)k * ADB_NP, sizeof(double) * ADB_NP);
                    dirty = 1;
                }
            }
            int live = -1;
            for (int b = 0; b < TS_B; ++b)
                if (L[b].running) live = b;
            if (live < 0 || !S) break;
            for (int b = 0; b < TS_B; ++b)
                if (!L[b].running) { /* an idle lane computes a copy of a running one */
                    memcpy(params + b * ADB_NP, params + live * ADB_NP, sizeof(double) * ADB_NP);
                    L[b].t = L[live].t;
                    memcpy(L[b].y, L[live].y, sizeof L[b].y);
                    dirty = 1;
                }
            if (dirty) TSF(_ts_setup)(&S->w, params);
            dirty = 0;
            for (int b = 0; b < TS_B; ++b) {
                tl[b] = L[b].t;
                for (int r = 0; r < NY; ++r) S->jet[0][r * TS_B + b] = L[b].y[r];
            }
            TSF(_ts_time)(&S->w, tl, 1.0);
            TSF(_ts_load)(&S->w, 0, S->jet[0]);
            for (int K = 0; K < P; ++K) borders[K](S);
            if (whole) {
                double h[TS_B], ynew[NY * TS_B];
                batch_step_sizes(S, &st, h);
                for (int b = 0; b < TS_B; ++b)
                    h[b] = L[b].running && traj[b] >= 0
                           ? lane_admit(&L[b], &st, &S->w, b, h[b], &S->jet[P][b], &S->jet[P - 1][b], TS_B) : 0.0;
                batch_horner(S, h, ynew);
                for (int b = 0; b < TS_B; ++b) {
                    if (traj[b] < 0) continue;
                    Lane *Lb = &L[b];
                    if (Lb->running) {
                        for (int r = 0; r < NY; ++r) lj[0][r] = ynew[r * TS_B + b];
                        if (!adb_all_finite(lj[0], NY)) {
                            lane_fail(Lb, ADB_NONFINITE);
                        } else {
                            const double t1 = (Lb->t + h[b] >= st.t_end) ? st.t_end : Lb->t + h[b];
                            ++Lb->steps;
                            Lb->t = t1;
                            memcpy(Lb->y, lj[0], sizeof Lb->y);
                            if (Lb->t >= st.t_end) Lb->running = 0;
                        }
                    }
                    if (!Lb->running) {
                        const int k = traj[b];
                        lane_finish(Lb, &st, Y_end + (size_t)k * NY, res + k);
                    }
                }
                continue;
            }
            for (int b = 0; b < TS_B; ++b) {
                if (!L[b].running || traj[b] < 0) continue;
                for (int k = 0; k <= P; ++k)
                    for (int r = 0; r < NY; ++r) lj[k][r] = S->jet[k][r * TS_B + b];
                lane_step(&L[b], &st, (const double(*)[NY])lj, &S->w, b);
                if (!L[b].running) {
                    const int k = traj[b];
                    lane_finish(&L[b], &st, Y_end + (size_t)k * NY, res + k);
                }
            }
        }
        free(S);
    }
}
#endif

#if TS_B == 1
/* The continuous solution of a run at `times` (n, increasing, within [T[0], T[K-1]]) into out (n x NY):
 * each step's polynomial, computed again from its start (the same coefficients as in the run). */
int adb_dense(const double *T, const double *Y, long K, const double *p, const adb_settings *s, int n,
              const double *times, double *out)
{
    (void)s; /* each step's polynomial: no tolerance needed */
    Stepper *S = ts_alloc(sizeof(Stepper));
    if (!S) return ADB_SOLVER_FAILURE;
    TSF(_ts_setup)(&S->w, p);
    long k = 0, held = -1;
    for (int j = 0; j < n; ++j) {
        while (k + 2 < K && T[k + 1] <= times[j]) ++k; /* a step end belongs to the next step: y itself */
        if (held != k) {
            jet_of(S, T[k], Y + k * NY);
            held = k;
        }
        horner((const double(*)[NY])S->jet, times[j] - T[k], out + (size_t)j * NY);
    }
    free(S);
    return 0;
}

/* The jet (P + 1 rows of NY) of the solution through (t, y): for tests and the orbits' users */
int adb_taylor_jet(double t, const double *y, const double *p, double *jet)
{
    Stepper *S = ts_alloc(sizeof(Stepper));
    if (!S) return ADB_SOLVER_FAILURE;
    TSF(_ts_setup)(&S->w, p);
    jet_of(S, t, y);
    memcpy(jet, S->jet, sizeof(S->jet));
    free(S);
    return P;
}
#endif
