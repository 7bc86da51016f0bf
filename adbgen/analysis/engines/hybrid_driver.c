/* Stick and slip of balls on a race as an event-driven hybrid system (issue 37, item 2), on DOP853 (the
 * step and 7th-order interpolant of rk_dop853.h) compiled in one translation unit with the model's
 * generated C rhs and measures:
 *
 *     -DADB_MODEL_SOURCE='"<model>.c"' -DADB_RHS=<model>_rhs -DADB_MEASURE=<model>_measure
 *     -DADB_NY=<states> -DADB_NP=<parameters>
 *
 * The model carries each switching ball's mode in its parameters (stuck_b: 1 stuck, 0 slipping; slip_dir_b:
 * the direction of its slip, along which the model's friction acts while it slips) and emits the switching
 * functions as measures: the slip rate (slip -> stick when it reaches 0), the stick margin mu_s N - |F|
 * (stick -> slip when it turns negative) and the required tangential force F of a stuck ball (its sign:
 * which way a released ball slips).  The driver only reads them; no physics is written here.
 *
 * Per accepted step, every ball's switching function g is evaluated at the step's end (slipping: slip_dir
 * times the slip rate; stuck: the margin).  Where one is negative, its root is located on the step's
 * interpolant by bisection to the last representable time (so an event sits within the interpolant's
 * error, which the step's error control keeps at the engine's tolerance); the earliest root ends the step,
 * and every ball whose root lies within 64 ulp of it switches there (symmetric balls switch together).  A
 * ball that switches is decided at the event's state: held stuck (stuck = 1, phi' = 0) if the margin
 * computed in the stuck mode is >= 0, else slipping in the direction opposite to the force it would need
 * (slip_dir = -sign F; friction then acts with the kinetic coefficient).  The balls that switch together
 * (and, at the start, every ball at rest on the race) are decided together from one state (`decide_set`),
 * not one after another: the rotor's acceleration is in every ball's required force, so one ball's release
 * changes another's margin, and deciding ball 1 against ball 2's mode before ball 2 was decided made the
 * outcome depend on the order and on the mode the caller gave a ball at rest (a test shows it).  A slip so decided must not end
 * at once: where a ball's slip ends within 64 ulp of the time it was decided and the ball is decided into
 * slip again, no mode of that ball holds (mu_r > mu_s, the slip decelerating from its start: the scene
 * refuses it, a parameter set by hand does not) and the run stops with HY_NO_MODE at that time rather than
 * looping through events that do not advance it.  The run restarts from the event
 * (DOP853 is one-step: no history is lost).  An excursion of g below 0 and back within one step is not seen
 * (a slip reversing twice in one step); the step size keeps that to features shorter than a step.
 *
 * Within a mode the vector field is smooth: a slipping ball's friction acts along its mode (slip_dir), not
 * along the sign of its rate, so the field continues past phi_b' = 0 and the stop is located on it like any
 * root (the event-driven treatment of Coulomb friction: each of forward slip, backward slip and stick is
 * its own smooth system, the switch a state event; Otter, Elmqvist and Mattsson 1999, the Modelica
 * library's friction elements).  With sign(phi_b') in the field, as the models had before, the field
 * flipped inside a step near the stop, the solution chattered at phi_b' ~ 1e-11 without crossing 0 at a
 * step's end, and the step size shrank without end (tests/analysis/test_hybrid_stall.py).
 *
 * Why this and not CVODE's root finding: the events change the model's parameters (its mode), after which
 * CVODE restarts at order 1 with a tiny step (CVodeReInit loses its history) at every stick and release;
 * a one-step method restarts at full order.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef ADB_MODEL_INCLUDED /* a test that wraps the model's rhs includes it first */
#include ADB_MODEL_SOURCE
#endif

#define RK_T double
#define RK_NY ADB_NY
#define RK_ABS(x) fabs(x)
#define RK_MAX(a, b) fmax(a, b)
#define RK_RHS(t, y, f) ADB_RHS((t), (y), ((const double *)ctx), (f))
#include "rk_dop853.h"

#ifndef HY_LOCATE_ITERATIONS /* bisections of an event on the step (a test plants 0: the event at the step's end) */
#define HY_LOCATE_ITERATIONS 200
#endif

#ifndef HY_MODE_CHECK /* the consistency check of a decided slip (a test plants 0: the loop it stops) */
#define HY_MODE_CHECK 1
#endif

enum { HY_OK = 0, HY_MAX_STEPS = 1, HY_MAX_EVENTS = 2, HY_UNDERFLOW = 3, HY_NONFINITE = 4, HY_NO_MODE = 5 };

typedef struct {
    int nb;
    const int *stuck, *dir, *rate_state, *m_rate, *m_margin, *m_force;
    int na; /* acceleration inputs of the measures: p[acc_param[j]] = the rhs' f[acc_state[j]] */
    const int *acc_param, *acc_state;
} Balls;

/* A model whose switching functions hold accelerations it has no closed form for (a rotor core solved
 * numerically in its rhs) declares them as parameters accel_<coordinate>, which only its measures read: they
 * are filled here from the model's own rhs at the same (t, y, p, modes) before such a measure is evaluated. */
static void accelerations(const Balls *B, double t, const double *y, double *p)
{
    if (!B->na) return;
    double f[ADB_NY];
    ADB_RHS(t, y, p, f);
    for (int j = 0; j < B->na; ++j) p[B->acc_param[j]] = f[B->acc_state[j]];
}

typedef struct {
    double t0, h, y[ADB_NY], F[7][ADB_NY];
} Step;

static void step_at(const Step *s, double t, double *out)
{
    double x = (t - s->t0) / s->h, w = 1.0 - x;
    for (int i = 0; i < ADB_NY; ++i) {
        double v = s->F[6][i];
        v = v * x + s->F[5][i], v = v * w + s->F[4][i], v = v * x + s->F[3][i];
        v = v * w + s->F[2][i], v = v * x + s->F[1][i], v = v * w + s->F[0][i];
        out[i] = s->y[i] + v * x;
    }
}

/* ball b's switching function in its present mode: >= 0 while the mode holds */
static double switching(const Balls *B, int b, double t, const double *y, double *p)
{
    if (p[B->stuck[b]] > 0.5) {
        accelerations(B, t, y, p);
        return ADB_MEASURE(B->m_margin[b], t, y, p);
    }
    return p[B->dir[b]] * ADB_MEASURE(B->m_rate[b], t, y, p);
}

/* ball b held at rest on the race (phi_b' = 0 in y) and stuck: the ball's rate state moved by its slip rate until
 * that is exactly 0 (one pass where the slip rate is the state itself; two where it is relative to the race's
 * rate, the second removing the first's rounding) */
static void hold(const Balls *B, int b, double t, double *y, double *p)
{
    for (int it = 0; it < 4; ++it) {
        double g = ADB_MEASURE(B->m_rate[b], t, y, p);
        if (g == 0.0) break;
        y[B->rate_state[b]] -= g;
    }
    p[B->stuck[b]] = 1.0;
    p[B->dir[b]] = 0.0;
}

/* The modes of the n balls set[k], each at rest on the race, decided together: all held stuck, then every one
 * whose margin is negative released, slipping away from the force it would need (slip_dir = -sign F), the
 * margins and forces of all of them computed from the same state and modes; repeated with those released until
 * no held ball's margin is negative (at most n rounds: a ball once released stays so).  The result depends
 * neither on the balls' order nor on the modes p held for them before (stick wherever it can hold, given the
 * others).  mode[k]: +1 / -1 (slip direction) or 0 (stuck). */
static void decide_set(const Balls *B, const int *set, int n, double t, double *y, double *p, int *mode)
{
    for (int k = 0; k < n; ++k) hold(B, set[k], t, y, p), mode[k] = 0;
    for (int round = 0; round < n; ++round) {
        double F[n];
        int release[n], any = 0;
        accelerations(B, t, y, p);
        for (int k = 0; k < n; ++k) {
            release[k] = mode[k] == 0 && ADB_MEASURE(B->m_margin[set[k]], t, y, p) < 0.0;
            if (release[k]) F[k] = ADB_MEASURE(B->m_force[set[k]], t, y, p), any = 1;
        }
        if (!any) break;
        for (int k = 0; k < n; ++k) {
            if (!release[k]) continue;
            mode[k] = F[k] > 0.0 ? -1 : 1;
            p[B->stuck[set[k]]] = 0.0;
            p[B->dir[set[k]]] = (double)mode[k];
        }
    }
}

/* the first t in (a, b] of the step where ball's g < 0, given g(a) >= 0 > g(b): bisection to adjacent doubles */
static double locate(const Balls *B, int ball, const Step *s, double a, double b, double *p)
{
    double y[ADB_NY];
    for (int it = 0; it < HY_LOCATE_ITERATIONS; ++it) {
        double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;
        step_at(s, m, y);
        if (switching(B, ball, m, y, p) >= 0.0) a = m;
        else b = m;
    }
    return b;
}

/* Integrates from (t0, y0) to t1 with the modes in p (updated in place, and set at t0 for every ball at rest
 * on the race); y_eval[k] = the solution at t_eval[k] (increasing, within [t0, t1]); events: ev_t, ev_ball,
 * ev_mode (0 stuck, +1 / -1 slipping that way) up to max_events; *t_reached and y_end the last state. */
int adb_hybrid_run(const double *y0, double t0, double t1, double *p, int nb, const int *stuck, const int *dir,
                   const int *rate_state, const int *m_rate, const int *m_margin, const int *m_force, double rtol,
                   double atol, long max_steps, const double *t_eval, long n_eval, double *y_eval, double *ev_t,
                   int *ev_ball, int *ev_mode, long max_events, long *n_events, double *t_reached, double *y_end,
                   long *n_steps, int na, const int *acc_param, const int *acc_state)
{
    Balls B = {nb, stuck, dir, rate_state, m_rate, m_margin, m_force, na, acc_param, acc_state};
    const double *ctx = p;
    double y[ADB_NY], ynew[ADB_NY], K[DOP_EXTENDED][ADB_NY], e5, e3;
    memcpy(y, y0, sizeof y);
    double t = t0;
    long ne = 0, k_eval = 0, steps = 0;
    int status = HY_OK;
    double slipped[64]; /* per ball: the time of its last decision into slip (none since, or stuck: -inf) */
    for (int b = 0; b < 64; ++b) slipped[b] = -INFINITY;
    int at_rest[nb > 0 ? nb : 1], start_mode[nb > 0 ? nb : 1], n_rest = 0;
    for (int b = 0; b < nb; ++b) { /* the modes at the start: the balls at rest decided together */
        double rate = ADB_MEASURE(m_rate[b], t, y, p); /* relative to the race */
        if (rate == 0.0) {
            at_rest[n_rest++] = b;
        } else {
            p[stuck[b]] = 0.0;
            p[dir[b]] = rate > 0.0 ? 1.0 : -1.0;
        }
    }
    decide_set(&B, at_rest, n_rest, t, y, p, start_mode);
    for (int k = 0; k < n_rest; ++k) {
        int b = at_rest[k], mode = start_mode[k];
        if (ne < max_events) ev_t[ne] = t, ev_ball[ne] = b, ev_mode[ne] = mode;
        ++ne;
        if (b < 64 && mode != 0) slipped[b] = t;
    }
    while (k_eval < n_eval && t_eval[k_eval] <= t) memcpy(y_eval + ADB_NY * k_eval++, y, sizeof y);
    double h = fmin(1e-4 * (t1 - t0), t1 - t0);
    RK_RHS(t, y, K[0]);
    int rejected = 0;
    while (t < t1) {
        if (steps >= max_steps) { status = HY_MAX_STEPS; break; }
        if (h < 10.0 * fabs(nextafter(t, INFINITY) - t)) { status = HY_UNDERFLOW; break; }
        double hs = fmin(h, t1 - t);
        dop_step(t, hs, y, K, ynew, rtol, atol, &e5, &e3, ctx);
        ++steps;
        double err = dop_norm(hs, e5, e3);
        if (!isfinite(err)) { status = HY_NONFINITE; break; }
        if (err > 1.0) {
            h = hs * dop_factor(err, rejected);
            rejected = 1;
            continue;
        }
        Step s;
        s.t0 = t, s.h = hs;
        memcpy(s.y, y, sizeof y);
        dop_dense(t, hs, y, ynew, K, s.F, ctx);
        double tn = t + hs, first = INFINITY, roots[64];
        int nroots = nb < 64 ? nb : 64;
        for (int b = 0; b < nroots; ++b) {
            roots[b] = INFINITY;
            if (switching(&B, b, tn, ynew, p) < 0.0) {
                double y0s[ADB_NY];
                step_at(&s, t, y0s);
                roots[b] = switching(&B, b, t, y0s, p) < 0.0 ? t : locate(&B, b, &s, t, tn, p);
                if (roots[b] < first) first = roots[b];
            }
        }
        double tend = isfinite(first) ? fmax(first, t) : tn, yend[ADB_NY];
        if (isfinite(first)) step_at(&s, tend, yend);
        else memcpy(yend, ynew, sizeof yend);
        while (k_eval < n_eval && t_eval[k_eval] <= tend) {
            double te = t_eval[k_eval];
            if (te == tend) memcpy(y_eval + ADB_NY * k_eval, yend, sizeof yend);
            else step_at(&s, te, y_eval + ADB_NY * k_eval);
            ++k_eval;
        }
        h = hs * dop_factor(err, rejected);
        rejected = 0;
        t = tend;
        memcpy(y, yend, sizeof y);
        if (isfinite(first)) {
            double close = 64.0 * fabs(nextafter(first, INFINITY) - first);
            int set[64], modes[64], n_set = 0;
            for (int b = 0; b < nroots; ++b)
                if (roots[b] <= first + close) set[n_set++] = b;
            decide_set(&B, set, n_set, t, y, p, modes);
            for (int k = 0; k < n_set; ++k) {
                int b = set[k], mode = modes[k];
                if (ne < max_events) ev_t[ne] = t, ev_ball[ne] = b, ev_mode[ne] = mode;
                ++ne;
                /* a slip decided that ended within 64 ulp of its start and is decided again: the ball can
                 * neither stick nor slip; stop, not loop through events that do not advance time */
                if (mode != 0 && HY_MODE_CHECK && t - slipped[b] <= close) status = HY_NO_MODE;
                slipped[b] = mode != 0 ? t : -INFINITY;
            }
            if (status == HY_NO_MODE) break;
            if (ne >= max_events) { status = HY_MAX_EVENTS; RK_RHS(t, y, K[0]); break; }
            RK_RHS(t, y, K[0]);
            h = fmax(h, hs);
        } else {
            memcpy(K[0], K[DOP_STAGES], sizeof K[0]);
        }
    }
    *n_events = ne < max_events ? ne : max_events;
    *t_reached = t;
    *n_steps = steps;
    memcpy(y_end, y, sizeof y);
    return status;
}
