"""`matlab-ode45`: an emulation of MATLAB's ode45 at its defaults, for explaining published numbers.

The thesis integrated its transients with MATLAB's ode45 (ch. 5: "we use the Matlab routine ode45") and
states neither its tolerances nor how it read t_dec off the result.  This engine repeats what ode45 does
step by step (ode45_driver.c: Dormand-Prince 5(4), MATLAB's mixed error norm with threshold
AbsTol/RelTol, its initial step and step-size control, Refine = 4 output through ntrp45) on the generated
model's C library, and reads r_max and t_dec off the output points as a MATLAB user would (r_max the
largest r(t_i), t_dec the last output time with r(t_i) >= threshold).  With RelTol = 1e-3 and
AbsTol = 1e-6 (ode45's defaults) it reproduces the thesis' printed t_dec where the converged solution
does not (docs/reproduction.md), which shows those numbers are ode45's loose-tolerance values.

It is an emulation for that purpose, not an integrator to choose: its r_max and t_dec are read off
samples (not the continuous solution), its default tolerances are loose, and it keeps no exactness a
sweep relies on beyond the element-wise stage updates (identical balls stay together).
"""

from __future__ import annotations

import ctypes
import time

import numpy as np

from ..loading import AnalysisError
from .compiled import STATUS, D, I, L, _Compiled, _load_cached, _ptr, _single, build

DEFAULT_RTOL = 1e-3  # MATLAB's RelTol default
DEFAULT_ATOL = 1e-6  # MATLAB's AbsTol default


class _Trajectory(ctypes.Structure):
    _fields_ = [("t", D), ("y", D), ("k", ctypes.c_long)]


class MatlabOde45Engine(_Compiled):
    """MATLAB's ode45 emulated (ode45_driver.c); r_max and t_dec on its Refine = 4 output points."""

    name = "matlab-ode45"
    description = ("emulation of MATLAB's ode45 (Dormand-Prince 5(4), MATLAB's error norm, initial step and "
                   "Refine = 4 output; t_dec read from the output points): for explaining published numbers")
    driver = "ode45_driver.c"
    libs: list[str] = []
    prefix = "adb_ode45"
    symmetric = True
    native_events = False

    def library(self, model):
        return _load_cached(str(build(model, self.driver, self.libs, self.extra(model), self.tag)), self.prefix)

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=0):
        lib = self.library(model)
        y0 = np.ascontiguousarray(y0, dtype=float)
        p = np.ascontiguousarray(p, dtype=float)
        amp = self._common(model, threshold)
        traj = _Trajectory()
        y_end = np.zeros(model.n_states)
        stats = np.zeros(4)
        counts = np.zeros(2, np.int64)
        start = time.perf_counter()
        code = lib.adb_ode45_integrate(
            _ptr(y0), _ptr(p), ctypes.c_double(t_end), ctypes.c_double(rtol), ctypes.c_double(atol),
            ctypes.c_long(int(max_steps)), _ptr(amp, I), ctypes.c_double(threshold), 1 if keep_trajectory else 0,
            ctypes.byref(traj), _ptr(y_end), _ptr(stats), _ptr(counts, L))
        wall = time.perf_counter() - start
        try:
            k = traj.k
            t = np.ctypeslib.as_array(traj.t, (k,)).copy() if k else np.zeros(0)
            y = np.ctypeslib.as_array(traj.y, (k, model.n_states)).T.copy() if k else np.zeros((model.n_states, 0))
        finally:
            if traj.k:
                lib.adb_ode45_release(ctypes.byref(traj))
        return _single(code, t, y, y_end, stats, counts, wall, "")

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        if targets:
            raise AnalysisError("matlab-ode45 has no early stop (a sweep's --measure attractor needs another engine)")
        lib = self.library(model)
        n = len(Y0)
        Y0 = np.ascontiguousarray(Y0, dtype=float)
        P = np.ascontiguousarray(P, dtype=float)
        amp = self._common(model, threshold)
        status = np.zeros(n, np.int32)
        y_end = np.zeros((n, model.n_states))
        stats = np.zeros((n, 4))
        counts = np.zeros((n, 2), np.int64)
        start = time.perf_counter()
        lib.adb_ode45_integrate_many(
            n, _ptr(Y0), _ptr(P), ctypes.c_double(t_end), ctypes.c_double(rtol), ctypes.c_double(atol),
            ctypes.c_long(int(max_steps)), _ptr(amp, I), ctypes.c_double(threshold), int(threads or 0),
            _ptr(status, I), _ptr(y_end), _ptr(stats), _ptr(counts, L))
        wall = time.perf_counter() - start
        codes = np.array([STATUS[int(c)] for c in status])
        nan = np.full(n, np.nan)
        return {"status": codes, "r_max": stats[:, 0] if measures else nan, "t_dec": stats[:, 1] if measures else nan,
                "t_last": stats[:, 2], "t_fail": stats[:, 3], "y_end": y_end, "target": np.full(n, -1, np.int32),
                "n_rhs": counts[:, 0], "n_steps": counts[:, 1], "wall_s": wall}


ENGINE = MatlabOde45Engine()
