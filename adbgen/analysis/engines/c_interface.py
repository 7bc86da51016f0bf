"""The compiled engines' one C interface (adb_engine.h), mirrored for ctypes and checked at load.

Every driver (cyrk_driver.c, rk_driver.c, rk_batch_driver.c, sundials_driver.c, taylor_driver.c,
ode45_driver.c) exports the same entry points on the same structs:

    int  adb_integrate(const double *y0, const double *p, const adb_settings *s, adb_trajectory *traj,
                       double *y_end, adb_result *r)
    void adb_integrate_many(int n, const double *Y0, const double *P, const adb_settings *s, int threads,
                            double *Y_end, adb_result *res)
    void adb_release(adb_trajectory *traj)
    int  adb_dense(const double *T, const double *Y, long K, const double *p, const adb_settings *s, int n,
                   const double *times, double *out)
    long adb_abi_layout(long *out, long n)

`open_library` loads a driver's library, compares the sizes and field offsets of the structs the library
was compiled with (adb_abi_layout) with this module's `Settings`, `Result` and `Trajectory`, refuses a
library that differs in one line, and declares every entry point's argument types, so a wrong argument is
a ctypes.ArgumentError instead of a wrong number.
"""

from __future__ import annotations

import ctypes
import time
from pathlib import Path

import numpy as np

from ..loading import AnalysisError
from ..results import STOPPED, SUCCESS

# status codes (driver_common.h ADB_SUCCESS ...)
STATUS = {0: SUCCESS, 1: "max_steps", 2: "step_underflow", 3: "nonfinite", 4: "solver_failure", 5: STOPPED,
          6: "bad_input"}

D = ctypes.POINTER(ctypes.c_double)
I = ctypes.POINTER(ctypes.c_int)
U8 = ctypes.POINTER(ctypes.c_uint8)


class Settings(ctypes.Structure):
    """adb_settings (adb_engine.h): one run's settings, shared by the trajectories of a batch."""

    _fields_ = [("t_end", ctypes.c_double), ("rtol", ctypes.c_double), ("atol", ctypes.c_double),
                ("method", ctypes.c_int), ("step_factor", ctypes.c_double), ("max_steps", ctypes.c_long),
                ("amp", ctypes.c_int * 4), ("threshold", ctypes.c_double), ("check_dt", ctypes.c_double),
                ("n_targets", ctypes.c_int), ("centres", D), ("weights", D), ("cubics", D), ("levels", D),
                ("periodic", U8), ("keep", ctypes.c_int), ("measures", ctypes.c_int), ("n_samples", ctypes.c_int),
                ("sample_times", D), ("samples", D), ("message", ctypes.POINTER(ctypes.c_char))]


class Result(ctypes.Structure):
    """adb_result (adb_engine.h): a run's report."""

    _fields_ = [("status", ctypes.c_int), ("target", ctypes.c_int), ("r_max", ctypes.c_double),
                ("t_dec", ctypes.c_double), ("t_last", ctypes.c_double), ("t_fail", ctypes.c_double),
                ("n_rhs", ctypes.c_long), ("n_steps", ctypes.c_long)]


class Trajectory(ctypes.Structure):
    """adb_trajectory (adb_engine.h): a run's accepted steps, malloc'd by the library (adb_release)."""

    _fields_ = [("t", D), ("y", D), ("k", ctypes.c_long)]


def layout() -> list[int]:
    """This mirror's layout in adb_abi_layout's order: per struct its size, then its fields' offsets."""
    out = []
    for struct in (Settings, Result, Trajectory):
        out.append(ctypes.sizeof(struct))
        out.extend(getattr(struct, name).offset for name, _ in struct._fields_)
    return out


_SETTINGS_P = ctypes.POINTER(Settings)
_RESULT_P = ctypes.POINTER(Result)
_TRAJECTORY_P = ctypes.POINTER(Trajectory)
SIGNATURES = {
    "adb_integrate": (ctypes.c_int, [D, D, _SETTINGS_P, _TRAJECTORY_P, D, _RESULT_P]),
    "adb_integrate_many": (None, [ctypes.c_int, D, D, _SETTINGS_P, ctypes.c_int, D, _RESULT_P]),
    "adb_release": (None, [_TRAJECTORY_P]),
    "adb_dense": (ctypes.c_int, [D, D, ctypes.c_long, D, _SETTINGS_P, ctypes.c_int, D, D]),
}


def check_layout(lib, path: str | Path, expected: list[int] | None = None) -> None:
    """Refuse (AnalysisError, one line) a library whose structs differ from the mirror (`expected`: the
    mirror's layout, a test may plant another)."""
    expected = layout() if expected is None else list(expected)
    try:
        probe = lib.adb_abi_layout
    except AttributeError:
        raise AnalysisError(f"{Path(path).name} exports no adb_abi_layout: not built on adb_engine.h") from None
    probe.restype = ctypes.c_long
    probe.argtypes = [ctypes.POINTER(ctypes.c_long), ctypes.c_long]
    buf = (ctypes.c_long * len(expected))()
    count = probe(buf, len(expected))
    got = list(buf)[:count]
    if got != expected:
        at = next((i for i, (a, b) in enumerate(zip(got, expected)) if a != b), min(len(got), len(expected)))
        raise AnalysisError(f"{Path(path).name}: adb_engine.h's struct layout differs from c_interface.py's mirror "
                            f"at entry {at} (C {got[at] if at < len(got) else 'none'}, Python "
                            f"{expected[at] if at < len(expected) else 'none'}); the mirror must follow the header")


def open_library(path: str | Path):
    """The driver library at `path`, its layout checked against the mirror and its entry points typed."""
    lib = ctypes.CDLL(str(path))
    check_layout(lib, path)
    for name, (restype, argtypes) in SIGNATURES.items():
        if hasattr(lib, name):
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
    return lib


def ptr(a: np.ndarray | None, kind=D):
    return None if a is None else a.ctypes.data_as(kind)


def _targets(model, targets):
    """(n, centres, matrices, cubics, levels, periodic) of early-stop regions (driver_common.h adb_in_target):
    a target is (centre, W) or (centre, W, K, level): e'We <= 1 (and e'We + K(e, e, e) <= level), W a matrix
    or a vector of weights w (W = diag(w^2))."""
    if not targets:
        return 0, None, None, None, None, None
    ny = model.n_states
    centres = np.ascontiguousarray([t[0] for t in targets], dtype=float)
    weights = np.ascontiguousarray([np.diag(np.square(t[1])) if np.ndim(t[1]) == 1 else t[1] for t in targets],
                                   dtype=float)
    if weights.shape[1:] != (ny, ny) or centres.shape[1:] != (ny,) or any(len(t) not in (2, 4) for t in targets):
        raise AnalysisError(f"a target region needs a centre of {ny} states and a weight vector or {ny} x {ny} "
                            f"matrix (and optionally a {ny} x {ny} x {ny} cubic form and a level)")
    cubics = levels = None
    if any(len(t) == 4 for t in targets):
        cubics = np.ascontiguousarray([t[2] if len(t) == 4 else np.zeros((ny,) * 3) for t in targets], dtype=float)
        levels = np.ascontiguousarray([t[3] if len(t) == 4 else 1.0 for t in targets], dtype=float)
        if cubics.shape[1:] != (ny, ny, ny):
            raise AnalysisError(f"a target region's cubic form must be {ny} x {ny} x {ny}")
    periodic = np.zeros(ny, dtype=np.uint8)
    periodic[list(model.angle_indices)] = 1
    return len(targets), centres, weights, cubics, levels, periodic


def settings(model, t_end: float, rtol: float, atol: float, threshold: float = 0.0, max_steps: int = 0, *,
             method: int = 0, step_factor: float = 0.0, check_dt: float = 0.0, targets=(), keep: bool = False,
             measures: bool = True, sample_times: np.ndarray | None = None, samples: np.ndarray | None = None,
             message=None) -> Settings:
    """An adb_settings for `model`; the arrays it points to are held by the returned object."""
    nt, centres, weights, cubics, levels, periodic = _targets(model, targets)
    s = Settings(t_end=float(t_end), rtol=float(rtol), atol=float(atol), method=int(method),
                 step_factor=float(step_factor), max_steps=int(max_steps), threshold=float(threshold),
                 check_dt=float(check_dt), n_targets=nt, centres=ptr(centres), weights=ptr(weights),
                 cubics=ptr(cubics), levels=ptr(levels), periodic=ptr(periodic, U8), keep=1 if keep else 0,
                 measures=1 if measures else 0, n_samples=0 if sample_times is None else len(sample_times),
                 sample_times=ptr(sample_times), samples=ptr(samples),
                 message=None if message is None else ctypes.cast(message, ctypes.POINTER(ctypes.c_char)))
    s.amp[:] = [int(i) for i in model.amplitude_indices]
    s.held = (centres, weights, cubics, levels, periodic, sample_times, samples, message)  # alive with s
    return s


def integrate(lib, model, y0, p, s: Settings):
    """One run: (status code, t, y (states x steps) of the kept steps, y_end, Result, wall seconds)."""
    y0 = np.ascontiguousarray(y0, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    traj = Trajectory()
    res = Result()
    y_end = np.zeros(model.n_states)
    start = time.perf_counter()
    code = lib.adb_integrate(ptr(y0), ptr(p), ctypes.byref(s), ctypes.byref(traj), ptr(y_end), ctypes.byref(res))
    wall = time.perf_counter() - start
    try:
        k = traj.k
        t = np.ctypeslib.as_array(traj.t, (k,)).copy() if k else np.zeros(0)
        y = np.ctypeslib.as_array(traj.y, (k, model.n_states)).T.copy() if k else np.zeros((model.n_states, 0))
    finally:
        if traj.k:
            lib.adb_release(ctypes.byref(traj))
    return code, t, y, y_end, res, wall


def single(code, t, y, y_end, res: Result, wall, message="") -> dict:
    """A run's report as the engines return it (a refused input: AnalysisError)."""
    status = STATUS[int(code)]
    if status == "bad_input":
        raise AnalysisError("the engine refused its input (t_end, rtol and atol must be > 0, the state finite)")
    return {"status": status, "t": t, "y": y, "r_max": float(res.r_max), "t_dec": float(res.t_dec), "y_end": y_end,
            "n_rhs": int(res.n_rhs), "n_steps": int(res.n_steps),
            "t_fail": None if status in (SUCCESS, STOPPED) else float(res.t_fail), "wall_s": wall, "message": message}


def integrate_many(lib, model, P, Y0, s: Settings, threads=None) -> dict:
    """Row k of Y0 with row k of P on `threads` threads (None: all): the engines' run_many report."""
    n = len(Y0)
    Y0 = np.ascontiguousarray(Y0, dtype=float)
    P = np.ascontiguousarray(P, dtype=float)
    res = (Result * n)()
    y_end = np.zeros((n, model.n_states))
    start = time.perf_counter()
    lib.adb_integrate_many(n, ptr(Y0), ptr(P), ctypes.byref(s), int(threads or 0), ptr(y_end), res)
    wall = time.perf_counter() - start
    rows = np.ctypeslib.as_array(res).view(np.dtype({"names": [f for f, _ in Result._fields_],
                                                     "formats": ["i4", "i4", "f8", "f8", "f8", "f8", "i8", "i8"],
                                                     "offsets": [getattr(Result, f).offset for f, _ in Result._fields_],
                                                     "itemsize": ctypes.sizeof(Result)}))
    codes = np.array([STATUS[int(c)] for c in rows["status"]])
    return {"status": codes, "r_max": rows["r_max"].copy(), "t_dec": rows["t_dec"].copy(),
            "t_last": rows["t_last"].copy(), "t_fail": rows["t_fail"].copy(), "y_end": y_end,
            "target": rows["target"].astype(np.int32), "n_rhs": rows["n_rhs"].astype(np.int64),
            "n_steps": rows["n_steps"].astype(np.int64), "wall_s": wall}


def dense(lib, model, p, t, y, times, s: Settings) -> tuple[int, np.ndarray]:
    """(code, states x times) of a run's continuous solution (its steps t, y as `integrate` returns them)."""
    T = np.ascontiguousarray(t, dtype=float)
    Y = np.ascontiguousarray(np.asarray(y).T, dtype=float)
    times = np.ascontiguousarray(times, dtype=float)
    out = np.zeros((len(times), model.n_states))
    code = lib.adb_dense(ptr(T), ptr(Y), len(T), ptr(np.ascontiguousarray(p, dtype=float)), ctypes.byref(s),
                         len(times), ptr(times), ptr(out))
    return code, out.T
