"""The Taylor engine: Taylor's method on the model's emitted series (the `taylor` target's
`<model>_taylor.c`) in a compiled C driver (`taylor_driver.c`), called through ctypes like the other
compiled engines.

    taylor         order from the tolerance and Jorba & Zou's step (heyoka's rule: order
                   ceil(-ln(rtol) / 2 + 1), step factor 1), or a tuned (order, factor) per tolerance
                   (`TaylorEngine.settings`)
    taylor-batch   the same stepper on a vector of trajectories per SIMD lane group (the series program
                   compiled with TS_B = the CPU's lanes), groups on OpenMP threads (ensembles, sweeps)
    taylor-batch-inf  taylor-batch with heyoka's whole rule: the step in the state's inf norm (Jorba &
                   Zou's, `NORMS`), order ceil(-ln(rtol) / 2 + 1), step factor 1: heyoka's steps

The order is fixed when the driver is compiled (every order of a step unrolled, each convolution a
straight line), so each order is its own shared library, built once per model and order under
``$ADBGEN_CACHE/engines`` (gcc -O3 -march=native: 2-10 s the first time, milliseconds after).
"""

from __future__ import annotations

import ctypes
import hashlib
import math
import os
import platform
import threading
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..loading import AnalysisError
from . import c_interface as ci
from .compiled import HERE, _Compiled, compile_cached
from .rk import lanes

CFLAGS = ["-std=gnu99", "-O3", "-march=native", "-ffp-contract=off", "-fPIC", "-shared", "-fopenmp"]
MIN_ORDER, MAX_ORDER = 2, 40
_lock = threading.Lock()


def heyoka_order(tol: float) -> int:
    """Jorba & Zou's order for a tolerance, as heyoka computes it: ceil(-ln(tol) / 2 + 1), at least 2."""
    return max(MIN_ORDER, min(MAX_ORDER, math.ceil(-math.log(tol) / 2 + 1)))


def nominal_error(order: int, factor: float) -> float:
    """The truncation term of one step relative to the component's weight, as the step rule aims it:
    h = factor rho exp(-0.7 / (p - 1)) / e^2 with |y_p| rho^p = w gives |y_p| h^p = w (factor
    exp(-0.7 / (p - 1)) / e^2)^p (Jorba & Zou 2005, sec. 3.3).  heyoka's rule (factor 1, order
    ceil(-ln(tol) / 2 + 1)) makes it tol / 15 or less; a larger factor trades it for longer steps."""
    return (factor * math.exp(-0.7 / (order - 1)) / math.e ** 2) ** order


def taylor_source(model) -> Path:
    path = model.folder / f"{model.name}_taylor.c"
    if not path.is_file():
        raise AnalysisError(f"{model.name}: no Taylor series at {path} (regenerate with the 'taylor' target)")
    return path


@lru_cache(maxsize=1)
def _machine() -> str:
    """What -march=native compiles for (a cached library is only valid on the same kind of CPU)."""
    flags = ""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith(("flags", "model name")):
                    flags += line
                if line.startswith("flags"):
                    break
    except OSError:
        pass
    return platform.machine() + hashlib.sha256(flags.encode()).hexdigest()[:12]


NORMS = {"component": 0, "max": 1}  # the step rule's norm (taylor_driver.c ADB_TS_NORM)


def build(model, order: int, batch: int = 1, vector_math: bool = False, norm: str = "component") -> Path:
    """Compile the driver with the model's series at `order` (and `batch` trajectories per lane group, the
    batch variant; `vector_math`: sin, cos and pow from libmvec over the lanes) into a cached shared
    library."""
    if not MIN_ORDER <= order <= MAX_ORDER:
        raise AnalysisError(f"Taylor order {order} is not in {MIN_ORDER}..{MAX_ORDER}")
    source = taylor_source(model)
    vector_math = vector_math and batch > 1
    defines = [f'-DADB_TS_SOURCE="{source}"', f"-DADB_TS_PREFIX={model.name}", f"-DADB_TS_ORDER={order}",
               f"-DADB_NY={model.n_states}", f"-DADB_NP={model.n_params}", f"-DTS_B={batch}",
               f"-DTS_VECTOR_MATH={1 if vector_math else 0}", f"-DADB_TS_NORM={NORMS[norm]}",
               # the per-order functions and their table (taylor_driver.c): one FN(K) per order K < order
               "-DADB_TS_ORDERS(FN)=" + " ".join(f"FN({k})" for k in range(order))]
    kind = f"taylor{order}" + (f"x{batch}" if batch > 1 else "") + ("v" if vector_math else "") + \
        ("m" if norm == "max" else "")
    # not builtins: GCC would merge sin and cos into a scalar sincos per lane before the vectoriser sees the
    # simd declarations (taylor_driver.c)
    flags = CFLAGS + (["-fno-builtin-sin", "-fno-builtin-cos", "-fno-builtin-pow"] if vector_math else [])
    return compile_cached(model, HERE / "taylor_driver.c", source, flags, defines,
                          ["-lmvec"] if vector_math else [], kind, f"Taylor engine (order {order})",
                          key=(_machine(),))


@lru_cache(maxsize=None)
def _load_cached(path: str, batch: int):
    lib = ci.open_library(path)
    if batch == 1:
        lib.adb_taylor_jet.restype = ctypes.c_int
        lib.adb_taylor_jet.argtypes = [ctypes.c_double, ci.D, ci.D, ci.D]
    return lib


_loaded: dict = {}


def library(model, order: int, batch: int = 1, vector_math: bool = False, norm: str = "component"):
    """The loaded library of `build`.  A repeated call for the same model files (their path and
    SOURCE_HASH), order, batch and cache folder skips build's reading and hashing (a tenth of a
    millisecond under load, a twentieth of a short run)."""
    key = (str(model.folder), model.name, getattr(model, "source_hash", None), order, batch, vector_math, norm,
           os.environ.get("ADBGEN_CACHE"), os.environ.get("XDG_CACHE_HOME"))
    with _lock:
        lib = _loaded.get(key) if key[2] else None
        if lib is None:
            lib = _loaded[key] = _load_cached(str(build(model, order, batch, vector_math, norm)), batch)
        return lib


class TaylorEngine(_Compiled):
    """Taylor's method, compiled per model and order (taylor_driver.c)."""

    driver = "taylor_driver.c"
    prefix = "adb_taylor"
    native_events = True
    symmetric = True

    def __init__(self, name: str = "taylor", description: str = "", table=None, norm: str = "component"):
        if norm not in NORMS:
            raise AnalysisError(f"unknown step norm {norm!r}; norms: {', '.join(NORMS)}")
        self.name = name
        self.description = description or (
            "Taylor's method (order from the tolerance, Jorba & Zou's step) on the emitted series, compiled")
        # (tol, order, factor) rows, ascending tol: a tuned choice (the auto engine's measurements); None:
        # heyoka's rule
        self.table = table
        self.norm = norm  # the step rule's norm (NORMS)

    def settings(self, rtol: float, atol: float) -> tuple[int, float]:
        """(order, step factor) for a tolerance: the table's row for the largest tol <= rtol, else
        heyoka's rule with factor 1."""
        if self.table:
            rows = [r for r in self.table if r[0] <= rtol * (1 + 1e-9)]
            if rows:
                _, order, fac = max(rows, key=lambda r: r[0])
                return int(order), float(fac)
        return heyoka_order(rtol), 1.0

    def library(self, model, order: int | None = None):
        return library(model, order if order is not None else heyoka_order(1e-8), norm=self.norm)

    def _single_call(self, model, rtol, atol):
        order, fac = self.settings(rtol, atol)
        picked = {"engine": self.name, "rtol": rtol, "atol": atol, "order": order, "step_factor": fac}
        return library(model, order, norm=self.norm), {"step_factor": fac}, picked

    batch = 1  # trajectories per lane group of the compiled series (the batch variant: the CPU's lanes)
    vector_math = False  # sin, cos and pow from libmvec over the lanes (the batch variant unless exact_math)

    def _many_call(self, model, rtol, atol):
        order, fac = self.settings(rtol, atol)
        return library(model, order, self.batch, self.vector_math, self.norm), {"step_factor": fac}

    dense = _Compiled.dense_output

    def jet(self, model, t: float, y, p, order: int) -> np.ndarray:
        """The solution's Taylor coefficients (order + 1 rows of states) through (t, y), by the engine's
        compiled stepper of that order."""
        lib = library(model, order)
        out = np.zeros((order + 1, model.n_states))
        lib.adb_taylor_jet(float(t), ci.ptr(np.ascontiguousarray(y, dtype=float)),
                           ci.ptr(np.ascontiguousarray(p, dtype=float)), ci.ptr(out))
        return out


class TaylorBatchEngine(TaylorEngine):
    """The batch variant: `run_many` advances a vector of trajectories per lane group (the CPU's doubles per
    SIMD register, `rk.lanes()`: 8 with AVX-512, 4 with AVX2; every operation of a step on the group at
    once; each trajectory its own step size, events and early stop), a group per OpenMP thread; one
    trajectory (`run`) is the single stepper's.  sin, cos and pow come from libmvec over the lanes
    (`exact_math=True`: libm lane by lane, each trajectory bit for bit the single stepper's).

    `norm="max"` (and no table: heyoka's order, factor 1) is `taylor-batch-inf`: Jorba & Zou's step rule
    in the state's inf norm with heyoka's order, as heyoka applies them, so it takes heyoka's steps
    trajectory by trajectory (tested; 5913 per trajectory on 1024 basin-map starts, heyoka 5913) and the
    two differ only in what a step costs.  Each step holds the error of every component to the largest
    one's scale (the rotor's x, y beside the balls' angles), which suits ensembles that ask for
    attractors (labels), not for r_max/t_dec of small whirls."""


    def __init__(self, name: str = "taylor-batch", description: str = "", table=None, exact_math: bool = False,
                 n_lanes: int | None = None, norm: str = "component"):
        super().__init__(name, description or (
            "Taylor's method on SIMD lanes (4-8 trajectories per vector, libmvec sin/cos/pow; ensembles, "
            "sweeps); one trajectory as taylor"), table=table, norm=norm)
        self.exact_math = exact_math
        self._n_lanes = n_lanes

    @property
    def vector_math(self) -> bool:
        return not self.exact_math

    @property
    def batch(self) -> int:
        return max(2, self._n_lanes or lanes())


__all__ = ["CFLAGS", "TaylorBatchEngine", "TaylorEngine", "build", "heyoka_order", "library",
           "nominal_error", "taylor_source"]
