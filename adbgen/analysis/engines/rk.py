"""The DOP853 engines compiled with the model (issue 22 items 3 and 4).

    rk-dop853        rk_driver.c: Hairer's DOP853 in C, in one translation unit with the generated C rhs
                     (no call through a pointer per stage): cyrk-dop853's method, controller and reports
                     (status codes, early stop, r_max and t_dec on the method's 7th-order interpolant)
    rk-dop853-batch  rk_batch_driver.c: the same step on a vector of ADB_LANES trajectories (8 with
                     AVX-512, 4 with AVX2, else 1), the rhs from the lanes target
                     (generated/<model>/<model>_lanes.h), per-lane step sizes; ensembles only: its
                     run_many without r_max/t_dec (sweeps' attractor labels), everything else (a single
                     run, ensembles with measures, a model the lanes target skips) by rk-dop853

Both are built with gcc -O3 -march=native -ffp-contract=off (no fused multiply-add, so the batch engine
with ADB_EXACT_MATH reproduces the scalar one bit for bit) into $ADBGEN_CACHE/engines, keyed by the
drivers' sources, the model's file, the flags and the CPU the code is compiled for.
"""

from __future__ import annotations

import ctypes
import os
import threading
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..loading import AnalysisError
from . import c_interface as ci
from .compiled import HERE, CyRKEngine, _Compiled, compile_cached

CFLAGS = ["-std=gnu99", "-O3", "-march=native", "-ffp-contract=off", "-fPIC", "-shared", "-fopenmp"]
# glibc's sincos(x) and its sin(x), cos(x) can differ in the last bit, and GCC merges a sin and a cos of
# one argument into sincos where it sees both: the scalar rhs and the lane-by-lane one give it different
# chances.  The exact-math builds (the batch engine's bitwise twin of the scalar one, for tests) call
# each function as written.
SEPARATE_SINCOS = ["-fno-builtin-sin", "-fno-builtin-cos"]
_lock = threading.Lock()


@lru_cache(maxsize=1)
def cpu_flags() -> frozenset[str]:
    """The CPU's feature flags (/proc/cpuinfo; empty where it is not readable)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("flags"):
                return frozenset(line.split(":", 1)[1].split())
    except OSError:
        pass
    return frozenset()


def lanes() -> int:
    """Trajectories per vector for this CPU: 8 (avx512f), 4 (avx2 with fma), else 1 (the scalar
    fallback); ADBGEN_LANES overrides (1, 2, 4 or 8)."""
    forced = os.environ.get("ADBGEN_LANES")
    if forced:
        if forced not in ("1", "2", "4", "8"):
            raise AnalysisError(f"ADBGEN_LANES must be 1, 2, 4 or 8, not {forced!r}")
        return int(forced)
    flags = cpu_flags()
    if "avx512f" in flags:
        return 8
    if "avx2" in flags and "fma" in flags:
        return 4
    return 1


def build(model, driver: str, source: Path, defines: list[str], libs: list[str]) -> Path:
    """Compile `driver` with the model's `source` (included by the driver) into a cached shared library (keyed
    by the CPU too: -march=native)."""
    return compile_cached(model, HERE / driver, source, CFLAGS, defines, libs, Path(driver).stem,
                          f"{Path(driver).stem} engine", key=(" ".join(sorted(cpu_flags())),))


@lru_cache(maxsize=None)
def _open(path: str):
    lib = ci.open_library(path)
    if hasattr(lib, "adb_rk_time_rhs"):
        lib.adb_rk_time_rhs.restype = ctypes.c_double
    if hasattr(lib, "adb_rk_time_rhs_along"):
        lib.adb_rk_time_rhs_along.restype = ctypes.c_double
    return lib


def _sizes(model) -> list[str]:
    return [f"-DADB_NY={model.n_states}", f"-DADB_NP={model.n_params}"]


def scalar_library(model, exact_math: bool = False):
    source = model.c_source()
    defines = [f'-DADB_MODEL_SOURCE="{source.name}"', f"-DADB_RHS={model.name}_rhs", *_sizes(model),
               *(SEPARATE_SINCOS if exact_math else [])]
    with _lock:
        return _open(str(build(model, "rk_driver.c", source, defines, [])))


def lanes_source(model) -> Path | None:
    """The model's lanes header, or None (the lanes target skips models whose rhs branches)."""
    path = model.folder / f"{model.name}_lanes.h"
    return path if path.is_file() else None


def batch_library(model, n_lanes: int | None = None, exact_math: bool = False):
    """The ensemble library for `n_lanes` (default: this CPU's) lanes, or None without a lanes header."""
    source = lanes_source(model)
    if source is None:
        return None
    n_lanes = n_lanes or lanes()
    defines = [f'-DADB_LANES_SOURCE="{source.name}"', f"-DADB_RHS_LANES={model.name}_rhs_lanes", *_sizes(model),
               f"-DADB_LANES={n_lanes}", f"-DADB_EXACT_MATH={1 if exact_math else 0}",
               *(SEPARATE_SINCOS if exact_math else [])]
    with _lock:
        return _open(str(build(model, "rk_batch_driver.c", source, defines, ["-lmvec"])))


class RKEngine(CyRKEngine):
    """DOP853 in C with the model's rhs in the same translation unit (rk_driver.c)."""

    driver = "rk_driver.c"
    prefix = "adb_rk"
    method_id = 0

    def __init__(self, name: str = "rk-dop853", description: str = "", exact_math: bool = False):
        self.method = "DOP853"
        self.name = name
        self.exact_math = exact_math  # sin and cos as written, never merged into sincos (tests)
        self.description = description or ("DOP853 (Hairer) in C, compiled with the model's rhs in one translation "
                                           "unit; cyrk-dop853's method and reports without a call per stage")

    def library(self, model):
        return scalar_library(model, self.exact_math)

    def time_rhs(self, model, p, y, calls: int = 200_000) -> float:
        """ns per evaluation of the rhs as this engine's library compiles it (the floor of item 3)."""
        lib = self.library(model)
        y = np.ascontiguousarray(y, dtype=float)
        p = np.ascontiguousarray(p, dtype=float)
        return float(lib.adb_rk_time_rhs(y.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
                                         p.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), ctypes.c_long(calls)))

    def time_rhs_along(self, model, p, states) -> float:
        """ns per evaluation of the rhs at each of `states` (rows: a run's accepted steps, in order), chained
        as a run's stages are: the floor of item 3 at the states the run visits."""
        lib = self.library(model)
        Y = np.ascontiguousarray(states, dtype=float)
        if Y.ndim != 2 or Y.shape[1] != model.n_states or len(Y) == 0:
            raise ValueError(f"states must be a non-empty (k, {model.n_states}) array, not {Y.shape}")
        p = np.ascontiguousarray(p, dtype=float)
        return float(lib.adb_rk_time_rhs_along(Y.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), ctypes.c_long(len(Y)),
                                               p.ctypes.data_as(ctypes.POINTER(ctypes.c_double))))


class RKBatchEngine(RKEngine):
    """rk-dop853's step on a vector of trajectories (rk_batch_driver.c, the lanes target's rhs)."""

    def __init__(self, name: str = "rk-dop853-batch", exact_math: bool = False, n_lanes: int | None = None):
        super().__init__(name, "DOP853 on SIMD lanes (4-8 trajectories per vector, per-lane steps; the lanes "
                               "target's rhs, libmvec sin/cos) for ensembles without r_max/t_dec; else rk-dop853",
                         exact_math)
        self.n_lanes = n_lanes

    def _many_call(self, model, rtol, atol):
        lib = batch_library(model, self.n_lanes, self.exact_math)
        return (self.library(model) if lib is None else lib), {"method": 0}

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        engine = self if not measures else RKEngine(exact_math=self.exact_math)
        return _Compiled.run_many(engine, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=threads,
                                  check_dt=check_dt, targets=targets, measures=measures)

