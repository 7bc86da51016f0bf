"""The event searches of adbgen/analysis/engines/dense_search.h (r_max and t_dec on a step's continuous
solution, thesis ch. 5), each function on an interpolant whose answer is known: the header compiled with
a polynomial r^2(t) standing for a driver's dense output (the handle is its coefficients).

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
static inline double adb_r2(const double *y, int ix, int iy) { return y[ix] * y[ix] + y[iy] * y[iy]; }
#define ADB_DENSE const double *
/* r^2(t) = c0 + c1 t + c2 t^2 + c3 t^3: the interpolant */
static double dense_r2(const double *c, double t, int ix, int iy)
{
    (void)ix, (void)iy;
    return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}
#include "dense_search.h"
double bisect_down(const double *c, double a, double b, double H2) { return adb_bisect_down(c, a, b, 0, 1, H2); }
double peak_on(const double *c, double a, double b, int ns, double *tm) { return adb_peak_on(c, a, b, ns, 1, 0, 1, tm); }
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
"""

D = ctypes.POINTER(ctypes.c_double)


@pytest.fixture(scope="module")
def lib(tmp_path_factory):  # (gcc: the autouse _needs_gcc of analysis_fixtures)
    folder = tmp_path_factory.mktemp("dense_search")
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
