/* The event measures of the compiled engines, one implementation for every driver that reports them
 * (thesis ch. 5; docs/simulation.md): the peak amplitude r_max = max r(t) and the decay time
 * t_dec = sup{t <= t_end : r(t) >= H} of the rotor amplitude r = |(x, y)|.
 *
 * adb_events, for every driver: the running maximum of r^2 and the last time known with r >= H, fed the
 * points of the solution the driver has (step ends, output points, located extrema and crossings), and
 * the one rule turning them into adb_result's r_max and t_dec (adb_events_report: t_dec NaN when r(t_end)
 * >= H or the run did not finish, 0 when r never reached H; both NaN when not asked for).  Who feeds what:
 *   cyrk_driver.c, rk_driver.c  their stored steps, searched on the step's continuous solution by
 *                               adb_dense_measures below (CyRK's dense output, DOP853's own interpolant);
 *   taylor_driver.c             each step's end, and the extrema and last crossing located on the step's
 *                               polynomial (its Bernstein root isolation, exact to the method's order);
 *   sundials_driver.c           each return and SUNDIALS' roots of r^2 - H^2 and of d(r^2)/dt;
 *   ode45_driver.c              its output points (Refine = 4), as a MATLAB user reads them.
 * rk_batch_driver.c reports neither (its ensembles never ask).
 *
 * The dense search (#ifdef ADB_DENSE): a driver with a continuous solution over stored steps defines,
 * before the #include,
 *     ADB_DENSE           its handle on one step's interpolant (a type)
 *     ADB_DENSE_SOURCE    what it opens them from (a type: settings, parameters, scratch)
 *     static ADB_DENSE dense_open(ADB_DENSE_SOURCE src, const double *T, const double *Y, size_t k);
 *                         step k's interpolant, valid on [T[k], T[k+1]] (NULL: it failed)
 *     static void dense_close(ADB_DENSE h);
 *     static double dense_r2(ADB_DENSE h, double t, int ix, int iy);     r^2 at time t
 * and gets the searches (the last crossing of a threshold, the largest value on an interval, the screen
 * for an excursion above the threshold inside one step) and adb_dense_measures, which runs them.
 * Included after driver_common.h (adb_r2, adb_result, the status codes) with ADB_NY defined. */
#ifndef ADB_EVENT_MEASURES_H
#define ADB_EVENT_MEASURES_H

/* r^2's running maximum and t_above, the last time known with r^2 >= H2 (-1: none yet) */
typedef struct {
    double H2, r2max, t_above;
} adb_events;

/* the measures at the start (t = 0, state y0), for threshold H and the amplitude's indices amp */
static inline void adb_events_start(adb_events *ev, double H, const double *y0, const int *amp)
{
    ev->H2 = H * H;
    ev->r2max = adb_r2(y0, amp[0], amp[1]);
    ev->t_above = ev->r2max >= ev->H2 ? 0.0 : -1.0;
}

/* r^2 = r2 at time t (t never earlier than a point before it).  r^2 exactly H^2 counts as above:
 * t_dec = sup{r >= H}.  A NaN r2 raises nothing (the run reports non-finite itself). */
static inline void adb_events_point(adb_events *ev, double t, double r2)
{
    if (r2 > ev->r2max) ev->r2max = r2;
    if (r2 >= ev->H2) ev->t_above = t;
}

/* r = H located at time t (a crossing found by a root finder, SUNDIALS' or Taylor's on its polynomial,
 * whose r^2 there may round either way) */
static inline void adb_events_crossing(adb_events *ev, double t) { ev->t_above = fmax(ev->t_above, t); }

/* The report (thesis ch. 5): r_max = sqrt(max r^2); t_dec for a finished run (ADB_SUCCESS) only: NaN when
 * r(t_end) >= H (r^2 = r2_end: not settled), 0 when r never reached H, else the last time above.  measured
 * 0: neither asked for, both NaN. */
static inline void adb_events_report(const adb_events *ev, int measured, int status, double r2_end, adb_result *r)
{
    r->r_max = r->t_dec = NAN;
    if (!measured) return;
    r->r_max = sqrt(ev->r2max);
    if (status == ADB_SUCCESS) r->t_dec = r2_end >= ev->H2 ? NAN : (ev->t_above < 0.0 ? 0.0 : ev->t_above);
}

/* Every stored step end (T, Y: K of them) as a point: the measures of a run that kept its steps but is not
 * searched on a continuous solution (it did not finish) */
static inline void adb_events_points(adb_events *ev, const double *T, const double *Y, size_t K, const int *amp)
{
    for (size_t k = 0; k < K; ++k) adb_events_point(ev, T[k], adb_r2(Y + k * ADB_NY, amp[0], amp[1]));
}

/* Can r exceed H inside step k although r(t[k]), r(t[k+1]) < H?  Only at an interior maximum: r^2' =
 * 2 (x x' + y y') (the rates are states) goes from + to -.  A cubic Hermite estimate of r^2 from the
 * step's ends and slopes screens the candidates: it is within 15 % of the interpolant's maximum on
 * problem A at rtol 1e-3 (measured), and a step is only passed over when the estimate stays below
 * H^2 / 2 (a factor 2 of margin; H^2 / 4 re-integrated twice as many steps, 8 % more time at rtol 1e-8). */
static int adb_may_exceed(const double *t, const double *Y, size_t k, const int *amp, double H2)
{
    const double *u = Y + k * ADB_NY, *v = Y + (k + 1) * ADB_NY;
    int ix = amp[0], iy = amp[1], ixd = amp[2], iyd = amp[3];
    double g0 = u[ix] * u[ixd] + u[iy] * u[iyd], g1 = v[ix] * v[ixd] + v[iy] * v[iyd];
    if (!(g0 > 0.0 && g1 < 0.0)) return 0;
    double h = t[k + 1] - t[k], f0 = adb_r2(u, ix, iy), f1 = adb_r2(v, ix, iy), d0 = 2.0 * h * g0, d1 = 2.0 * h * g1;
    for (int j = 1; j < 16; ++j) {
        double x = j / 16.0, x2 = x * x, x3 = x2 * x;
        double p = (2 * x3 - 3 * x2 + 1) * f0 + (x3 - 2 * x2 + x) * d0 + (3 * x2 - 2 * x3) * f1 + (x3 - x2) * d1;
        if (p >= 0.5 * H2) return 1;
    }
    return 0;
}

/* The largest r^2 at the K step ends of Y; *last: the last step k with r^2 >= H2 ((size_t)-1: none) */
static double adb_scan_ends(const double *Y, size_t K, int ix, int iy, double H2, size_t *last)
{
    double best = 0.0;
    *last = (size_t)-1;
    for (size_t k = 0; k < K; ++k) {
        double v = adb_r2(Y + k * ADB_NY, ix, iy);
        if (v >= H2) *last = k;
        if (v > best) best = v;
    }
    return best;
}

/* The step end of the largest local maximum of r^2 at step ends in [floor_, done_above), or (size_t)-1;
 * its r^2 in *value.  Called with done_above = the previous one's value, it gives the peaks in turn. */
static size_t adb_next_peak(const double *Y, size_t K, int ix, int iy, double floor_, double done_above,
                            double *value)
{
    size_t kb = (size_t)-1;
    double vb = -1.0;
    for (size_t k = 0; k < K; ++k) {
        double v = adb_r2(Y + k * ADB_NY, ix, iy);
        if (v < floor_ || v >= done_above || v <= vb) continue;
        if (k > 0 && adb_r2(Y + (k - 1) * ADB_NY, ix, iy) > v) continue;
        if (k + 1 < K && adb_r2(Y + (k + 1) * ADB_NY, ix, iy) > v) continue;
        kb = k, vb = v;
    }
    *value = vb;
    return kb;
}

#ifdef ADB_DENSE
/* the last t in [a, b] with r^2 >= H2 on the interpolant, given r^2(a) >= H2 > r^2(b): bisection */
static double adb_bisect_down(ADB_DENSE h, double a, double b, int ix, int iy, double H2)
{
    for (int it = 0; it < 200; ++it) {
        double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;
        if (dense_r2(h, m, ix, iy) >= H2) a = m;
        else b = m;
    }
    return a;
}

/* largest r^2 on [a0, b0] of the interpolant: a scan of ns intervals, then golden section around its best;
 * its time in *tm.  The scan's last point is b0 itself (not a0 + (b0 - a0), which may round off b0: a step's
 * interpolant is only defined up to its step's end). */
static double adb_peak_on(ADB_DENSE h, double a0, double b0, int ns, int ix, int iy, double *tm)
{
    double span = b0 - a0, tb = a0, best = -1.0;
    for (int j = 0; j <= ns; ++j) {
        double tt = j == ns ? b0 : a0 + span * j / ns, v = dense_r2(h, tt, ix, iy);
        if (v > best) best = v, tb = tt;
    }
    double a = fmax(a0, tb - span / ns), b = fmin(b0, tb + span / ns), g = 0.5 * (sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a), fc = dense_r2(h, c, ix, iy), fd = dense_r2(h, d, ix, iy);
    for (int it = 0; it < 80; ++it) {
        if (fc > fd) {
            b = d, d = c, fd = fc;
            c = b - g * (b - a);
            fc = dense_r2(h, c, ix, iy);
        } else {
            a = c, c = d, fc = fd;
            d = a + g * (b - a);
            fd = dense_r2(h, d, ix, iy);
        }
    }
    if (fc > best) best = fc, tb = c;
    if (fd > best) best = fd, tb = d;
    *tm = tb;
    return best;
}

/* r_max and t_dec on the continuous solution of a finished run's K stored steps (T, Y), into ev (started at
 * Y[0]).  t_dec = sup{t : r(t) >= H}: when r(T[K-1]) < H, the latest excursion above H inside a step after
 * the last step end at or above H (both its ends below H: screened by adb_may_exceed, latest first, its
 * end bisected from the interpolant's peak), else the last crossing, bisected on the step holding it (its
 * step end T[k] when the interpolant cannot be had).  r_max: the largest r^2 at step ends, raised by the
 * interpolants of the two steps around each of the n_peaks largest local maxima at step ends (at least a
 * quarter of the largest).  Scans of 16 points for an excursion, 32 for a peak. */
static void adb_dense_measures(ADB_DENSE_SOURCE src, const double *T, const double *Y, size_t K, const int *amp,
                               int n_peaks, adb_events *ev)
{
    const int ix = amp[0], iy = amp[1];
    const double H2 = ev->H2;
    size_t last;
    const double best = adb_scan_ends(Y, K, ix, iy, H2, &last);
    ev->r2max = fmax(ev->r2max, best);
    if (last != (size_t)-1) ev->t_above = fmax(ev->t_above, T[last]);
    if (adb_r2(Y + (K - 1) * ADB_NY, ix, iy) < H2) {
        double found = -1.0;
        const size_t first = last == (size_t)-1 ? 0 : last + 1;
        for (size_t k = K - 1; found < 0.0 && k-- > first;) {
            if (!adb_may_exceed(T, Y, k, amp, H2)) continue;
            ADB_DENSE h = dense_open(src, T, Y, k);
            if (!h) continue;
            double tm;
            if (adb_peak_on(h, T[k], T[k + 1], 16, ix, iy, &tm) >= H2) found = adb_bisect_down(h, tm, T[k + 1], ix, iy, H2);
            dense_close(h);
        }
        if (found >= 0.0) ev->t_above = found;
        else if (last != (size_t)-1) {
            ADB_DENSE h = dense_open(src, T, Y, last);
            if (h) {
                ev->t_above = adb_bisect_down(h, T[last], T[last + 1], ix, iy, H2);
                dense_close(h);
            }
        }
    }
    double floor_ = 0.25 * best, done_above = INFINITY;
    for (int q = 0; q < n_peaks; ++q) {
        double vb;
        const size_t kb = adb_next_peak(Y, K, ix, iy, floor_, done_above, &vb);
        if (kb == (size_t)-1) break;
        done_above = vb;
        for (size_t k = kb > 0 ? kb - 1 : 0; k <= kb && k + 1 < K; ++k) {
            ADB_DENSE h = dense_open(src, T, Y, k);
            if (!h) continue;
            double tm;
            ev->r2max = fmax(ev->r2max, adb_peak_on(h, T[k], T[k + 1], 32, ix, iy, &tm));
            dense_close(h);
        }
    }
}

#endif /* ADB_DENSE */

#endif
