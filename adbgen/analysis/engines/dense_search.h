/* The event measures r_max and t_dec of the drivers that keep their accepted steps (cyrk_driver.c on
 * CyRK's dense output, rk_driver.c on DOP853's own interpolant): the scan of the step ends, the choice of
 * the peaks to refine, and the searches of r = |(x, y)| on a step's continuous solution (the last crossing
 * of a threshold, the largest value on an interval, the screen for an excursion above the threshold
 * inside one step).  (sundials_driver.c finds both by SUNDIALS' root finding, taylor_driver.c on each
 * step's polynomial, ode45_driver.c on its output points, as MATLAB's users read them.)
 *
 * The includer defines ADB_DENSE, the type of its handle on an interpolant, and before the #include
 *     static double dense_r2(ADB_DENSE h, double t, int ix, int iy);     r^2 at time t
 * Included after driver_common.h (adb_r2) with ADB_NY defined.  Each function is its drivers' former
 * copy, operation for operation (the engines' results are unchanged bit for bit). */
#ifndef ADB_DENSE_SEARCH_H
#define ADB_DENSE_SEARCH_H

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
 * its time in *tm.  exact_end: the scan's last point is b0 itself (not a0 + (b0 - a0), which may round
 * off b0: rk_driver.c's interpolant is only defined up to its step's end). */
static double adb_peak_on(ADB_DENSE h, double a0, double b0, int ns, int exact_end, int ix, int iy, double *tm)
{
    double span = b0 - a0, tb = a0, best = -1.0;
    for (int j = 0; j <= ns; ++j) {
        double tt = exact_end && j == ns ? b0 : a0 + span * j / ns, v = dense_r2(h, tt, ix, iy);
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

#endif
