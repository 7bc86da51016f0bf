"""The event measures of adbgen/analysis/engines/event_measures.h (r_max and t_dec, thesis ch. 5; the one
implementation every compiled engine's driver reports them by), each function on an interpolant whose
answer is known: the header compiled with a polynomial r^2(t) per step standing for a driver's dense
output (the handle is its coefficients), then the whole search over stored steps and the report's rule.

The engines' end-to-end results (tests/analysis/test_c_interface.py's fingerprints, test_decay_time.py)
see a wrong search only where problem A happens to need it; here each bracket, comparison and margin is
met head on (found by `adbgen bench mutation --runtime`: the screen's factor-2 margin survived them).
"""

from __future__ import annotations

import ctypes
import subprocess

import numpy as np
import pytest

from adbgen.analysis.engines.compiled import HERE, compiler

HARNESS = r"""
#include <math.h>
#include <stddef.h>
#define ADB_NY 4
#include "driver_common.h"
/* step k's interpolant: r^2(t) = c0 + c1 t + c2 t^2 + c3 t^3 with c = C + 4 k; NaN c0: not to be had */
#define ADB_DENSE const double *
#define ADB_DENSE_SOURCE const double *
static const double *dense_open(const double *C, const double *T, const double *Y, size_t k)
{
    (void)T, (void)Y;
    return isnan(C[4 * k]) ? NULL : C + 4 * k;
}
static void dense_close(const double *c) { (void)c; }
static double dense_r2(const double *c, double t, int ix, int iy)
{
    (void)ix, (void)iy;
    return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}
#include "event_measures.h"
double bisect_down(const double *c, double a, double b, double H2) { return adb_bisect_down(c, a, b, 0, 1, H2); }
double peak_on(const double *c, double a, double b, int ns, double *tm) { return adb_peak_on(c, a, b, ns, 0, 1, tm); }
int may_exceed(const double *t, const double *Y, long k, const int *amp, double H2)
{
    return adb_may_exceed(t, Y, (size_t)k, amp, H2);
}
double scan_ends(const double *Y, long K, double H2, long *last)
{
    size_t l;
    double v = adb_scan_ends(Y, (size_t)K, 0, 1, H2, &l);
    *last = l == (size_t)-1 ? -1 : (long)l;
    return v;
}
long next_peak(const double *Y, long K, double floor_, double done_above, double *value)
{
    size_t k = adb_next_peak(Y, (size_t)K, 0, 1, floor_, done_above, value);
    return k == (size_t)-1 ? -1 : (long)k;
}
/* a run's report as a driver makes it: started at Y[0], the stored steps searched when it finished
 * (status 0), their ends as points when not; out = (r_max, t_dec) */
void measures(const double *C, const double *T, const double *Y, long K, double H, int status, int measured,
              double *out)
{
    static const int amp[4] = {0, 1, 2, 3};
    adb_events ev;
    adb_result r;
    adb_events_start(&ev, H, Y, amp);
    if (status == ADB_SUCCESS) adb_dense_measures(C, T, Y, (size_t)K, amp, 8, &ev);
    else adb_events_points(&ev, T, Y, (size_t)K, amp);
    adb_events_report(&ev, measured, status, adb_r2(Y + (K - 1) * ADB_NY, 0, 1), &r);
    out[0] = r.r_max, out[1] = r.t_dec;
}
"""

D = ctypes.POINTER(ctypes.c_double)


@pytest.fixture(scope="module")
def lib(tmp_path_factory):  # (gcc: the autouse _needs_gcc of analysis_fixtures)
    folder = tmp_path_factory.mktemp("event_measures")
    (folder / "harness.c").write_text(HARNESS)
    out = folder / "harness.so"
    subprocess.run([compiler(), "-std=gnu99", "-O2", "-fPIC", "-shared", f"-I{HERE}", str(folder / "harness.c"),
                    "-o", str(out), "-lm"], check=True)
    lib = ctypes.CDLL(str(out))
    lib.bisect_down.restype = lib.peak_on.restype = lib.scan_ends.restype = ctypes.c_double
    lib.bisect_down.argtypes = [D, ctypes.c_double, ctypes.c_double, ctypes.c_double]
    lib.peak_on.argtypes = [D, ctypes.c_double, ctypes.c_double, ctypes.c_int, D]
    lib.may_exceed.argtypes = [D, D, ctypes.c_long, ctypes.POINTER(ctypes.c_int), ctypes.c_double]
    lib.scan_ends.argtypes = [D, ctypes.c_long, ctypes.c_double, ctypes.POINTER(ctypes.c_long)]
    lib.next_peak.restype = ctypes.c_long
    lib.next_peak.argtypes = [D, ctypes.c_long, ctypes.c_double, ctypes.c_double, D]
    lib.measures.argtypes = [D, D, D, ctypes.c_long, ctypes.c_double, ctypes.c_int, ctypes.c_int, D]
    return lib


def _p(a):
    a = np.ascontiguousarray(a, dtype=float)
    return a, a.ctypes.data_as(D)


def test_bisection_brackets_the_last_time_above_the_threshold(lib):
    """r^2 = 1 - t falls through H^2 = 1/4 at t = 3/4: the search keeps r^2 >= H^2 at its left end."""
    c, cp = _p([1.0, -1.0, 0.0, 0.0])
    t = lib.bisect_down(cp, 0.0, 1.0, 0.25)
    assert t == pytest.approx(0.75, abs=1e-14) and 1.0 - t >= 0.25
    c2, cp2 = _p([0.25, 0.5, -1.0, 0.0])  # r^2 = 1/4 + t/2 - t^2: above 1/4 until t = 1/2
    assert lib.bisect_down(cp2, 0.1, 0.9, 0.25) == pytest.approx(0.5, abs=1e-14)


def test_the_peak_is_the_largest_value_not_the_smallest(lib):
    """r^2 = 1 - (t - 0.3)^2 on [0, 1]: its maximum 1 at t = 0.3 (scan, then golden section)."""
    c, cp = _p([1.0 - 0.09, 0.6, -1.0, 0.0])
    tm = ctypes.c_double()
    best = lib.peak_on(cp, 0.0, 1.0, 8, ctypes.byref(tm))
    assert best == pytest.approx(1.0, abs=1e-14) and tm.value == pytest.approx(0.3, abs=1e-6)
    # a peak at the interval's end: the scan's last point is b itself
    assert lib.peak_on(cp, 0.0, 0.2, 8, ctypes.byref(tm)) == pytest.approx(1.0 - 0.01, abs=1e-15)
    assert tm.value == 0.2


def _step(x0, xd0, x1, xd1):
    """Two step ends of (x, y, x', y') with y = y' = 0 and the step [0, 1]."""
    return _p([0.0, 1.0]), _p([[x0, 0.0, xd0, 0.0], [x1, 0.0, xd1, 0.0]])


def test_the_screen_passes_over_a_step_only_below_half_the_threshold(lib):
    """r^2 = x^2 at the ends 1/4, slopes +1/2 and -1/2: the Hermite estimate peaks at 3/8 mid-step.  It
    screens the step in for H^2 = 0.6 (3/8 >= H^2 / 2, the documented margin of 2) and out for 0.8; a step
    without an interior maximum (r^2 rising at both ends) never."""
    (t, tp), (Y, Yp) = _step(0.5, 0.5, 0.5, -0.5)
    amp = (ctypes.c_int * 4)(0, 1, 2, 3)
    assert lib.may_exceed(tp, Yp, 0, amp, 0.6) == 1
    assert lib.may_exceed(tp, Yp, 0, amp, 0.74) == 1
    assert lib.may_exceed(tp, Yp, 0, amp, 0.8) == 0
    (t2, tp2), (Y2, Yp2) = _step(0.5, 0.5, 0.5, 0.5)
    assert lib.may_exceed(tp2, Yp2, 0, amp, 0.6) == 0


def test_the_scan_of_the_step_ends_counts_a_value_at_the_threshold_as_above(lib):
    """r^2 at the ends (0.01, 0.25, 0.0625, 0.25, 0.0025): the largest 0.25, the last at or above
    H^2 = 0.25 the fourth (r^2 exactly H^2 counts: t_dec = sup{r >= H})."""
    x = np.array([0.1, 0.5, 0.25, 0.5, 0.05])
    Y, Yp = _p(np.column_stack([x, np.zeros(5), np.zeros(5), np.zeros(5)]))
    last = ctypes.c_long()
    assert lib.scan_ends(Yp, 5, 0.25, ctypes.byref(last)) == 0.25 and last.value == 3
    assert lib.scan_ends(Yp, 5, 0.3, ctypes.byref(last)) == 0.25 and last.value == -1


def test_the_peaks_come_in_turn_largest_first(lib):
    x = np.sqrt([0.1, 0.4, 0.2, 0.3, 0.1])
    Y, Yp = _p(np.column_stack([x, np.zeros(5), np.zeros(5), np.zeros(5)]))
    value = ctypes.c_double()
    assert lib.next_peak(Yp, 5, 0.0, np.inf, ctypes.byref(value)) == 1 and value.value == pytest.approx(0.4)
    assert lib.next_peak(Yp, 5, 0.0, value.value, ctypes.byref(value)) == 3 and value.value == pytest.approx(0.3)
    assert lib.next_peak(Yp, 5, 0.0, value.value, ctypes.byref(value)) == -1  # no peak below the last one
    assert lib.next_peak(Yp, 5, 0.35, np.inf, ctypes.byref(value)) == 1  # none under the floor


def _run(lib, pieces, T, x, xd, H, status=0, measured=1):
    """(r_max, t_dec) of a run with steps T, step ends (x, 0, xd, 0) and step k's r^2 the polynomial
    pieces[k] in s = t - T[k] (coefficients lowest first; None: the interpolant cannot be had)."""
    C = []
    for k, c in enumerate(pieces):
        if c is None:
            C.append([np.nan] * 4)
            continue
        shifted = np.polynomial.Polynomial(c)(np.polynomial.Polynomial([-T[k], 1.0]))  # in t
        C.append(list(shifted.coef) + [0.0] * (4 - len(shifted.coef)))
    Y = np.column_stack([x, np.zeros(len(x)), xd, np.zeros(len(x))])
    out = np.zeros(2)
    (C, Cp), (T, Tp), (Y, Yp) = _p(C), _p(T), _p(Y)
    lib.measures(Cp, Tp, Yp, len(T), H, status, measured, out.ctypes.data_as(D))
    return out


def test_t_dec_is_the_crossing_on_the_interpolant_and_r_max_its_peak(lib):
    """Ends r^2 = (0.01, 0.5, 0.01), H^2 = 0.25: step 1's r^2 = 0.5 + 0.4 s - 0.89 s^2 peaks at
    0.5 + 0.04/0.89 inside the step (above every end) and falls through H^2 at s = (0.4 + sqrt(1.05))/1.78.
    Without the interpolant of the crossing's step, t_dec is that step's start (the last end above)."""
    T, x = np.array([0.0, 1.0, 2.0]), np.sqrt([0.01, 0.5, 0.01])
    pieces = [[0.01, 0.49], [0.5, 0.4, -0.89]]
    r_max, t_dec = _run(lib, pieces, T, x, np.array([1.0, -1.0, -1.0]), 0.5)
    assert r_max == pytest.approx(np.sqrt(0.5 + 0.04 / 0.89), rel=1e-12)
    assert t_dec == pytest.approx(1.0 + (0.4 + np.sqrt(1.05)) / 1.78, abs=1e-12)
    assert _run(lib, [pieces[0], None], T, x, np.array([1.0, -1.0, -1.0]), 0.5)[1] == 1.0


def test_an_excursion_inside_a_later_step_is_the_decay_time(lib):
    """Ends r^2 = (0.5, 0.1, 0.1, 0.1), H^2 = 0.25: the last end above H is t = 0 (crossing at 0.625 in
    step 0), but step 2's r^2 = 0.1 + 0.8 s (1 - s) rises to 0.3 inside it and falls back through H^2 at
    s = 3/4: t_dec = 2.75, the sup of r >= H."""
    T, x = np.array([0.0, 1.0, 2.0, 3.0]), np.sqrt([0.5, 0.1, 0.1, 0.1])
    g = np.array([-0.2, -0.1, 0.4, -0.4])  # x x': r^2' / 2 at the ends (step 2 from + to -)
    r_max, t_dec = _run(lib, [[0.5, -0.4], [0.1], [0.1, 0.8, -0.8]], T, x, g / x, 0.5)
    assert t_dec == pytest.approx(2.75, abs=1e-12) and r_max == pytest.approx(np.sqrt(0.5), rel=1e-14)


def test_the_report_rule(lib):
    """t_dec NaN when r(t_end) >= H (not settled) or the run did not finish (r_max then the largest end),
    0 when r never reached H; both NaN when not asked for."""
    T, xd = np.array([0.0, 1.0]), np.array([1.0, 1.0])
    rising = [[0.01, 0.49]]  # r^2 from 0.01 to 0.5
    r_max, t_dec = _run(lib, rising, T, np.sqrt([0.01, 0.5]), xd, 0.5)
    assert np.isnan(t_dec) and r_max == pytest.approx(np.sqrt(0.5), rel=1e-14)
    r_max, t_dec = _run(lib, rising, T, np.sqrt([0.01, 0.5]), xd, 0.8)
    assert t_dec == 0.0 and r_max == pytest.approx(np.sqrt(0.5), rel=1e-14)
    falling = [[0.5, -0.49]]
    r_max, t_dec = _run(lib, falling, T, np.sqrt([0.5, 0.01]), -xd, 0.5, status=1)  # ADB_MAX_STEPS
    assert np.isnan(t_dec) and r_max == np.sqrt(0.5)
    assert np.isnan(_run(lib, falling, T, np.sqrt([0.5, 0.01]), -xd, 0.5, measured=0)).all()
    assert _run(lib, falling, T, np.sqrt([0.5, 0.01]), -xd, 0.5)[1] == pytest.approx(0.25 / 0.49, abs=1e-12)
