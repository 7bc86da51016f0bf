"""The Jacobi integral along long runs (issue 14, item 3): an explicit, an implicit and a
structure-preserving method at zeta = beta = 0, where it is conserved.

The integral.  With zeta = beta = 0 the rotating-frame Lagrangian of the thesis model has no explicit
time, so h = sum_k q'_k dL/dq'_k - L is a constant of motion (thesis ch. 2's second route; derived once
in `adbgen.families.single_plane.jacobi`, its rate identity checked there).  The generated modules do
not carry h: ``mass_matrix`` gives the kinetic part (1/2) q'^T M q' only up to the ball rows' scaling by
mu, and h's potential part (T_0 - V) is not a program of the intermediate form (``forcing`` mixes
gyroscopic, potential and damping forces), so it cannot be rebuilt from them without integrating.  The
benchmark therefore evaluates the derived expression itself, lambdified once here with SymPy (a
benchmark module, not the analysis layer, which never imports SymPy); its symbols are the generated
model's state and parameter names, so it takes the same vectors.

The structure-preserving method.  The installed SUNDIALS (6.4) has neither ARKODE's SPRKStep
(symplectic partitioned RK, from 6.6) nor the ``ARKODE_IMPLICIT_MIDPOINT_1_2`` table (7.x), but its
ARKStep integrates any diagonally implicit Butcher table given by coefficients
(``ARKodeButcherTable_Create``) at a fixed step (``ARKStepSetFixedStep``) with Newton's method on the
generated analytic Jacobian: with the one-stage Gauss-Legendre table (A = 1/2, b = 1, c = 1/2) that
is the implicit midpoint rule, y_{n+1} = y_n + h f(t_n + h/2, (y_n + y_{n+1}) / 2), symmetric
(time-reversible) and symplectic for canonical Hamiltonian systems, and exact for every quadratic
invariant.  Our equations are in (q, q'), not canonical (q, p) with p = M(q) q' + gyroscopic terms,
so symplecticity is not promised in these variables; what the benchmark measures is whether the
error of h stays bounded (no secular drift), as it does for symmetric methods on reversible systems.
The driver, c/midpoint.c beside this module, is a few lines of C around SUNDIALS, compiled with the
model's generated C source.
"""

from __future__ import annotations

import ctypes
import hashlib
import math
import subprocess
import tempfile
import time
from functools import lru_cache
from pathlib import Path

import numpy as np

from .timing import c_file


def jacobi_function(n: int = 3):
    """h(y, p) of the thesis model with n balls, vectorised over the last axis of y (states on the
    first axis, in the generated model's order), from the derived rotating-frame Lagrangian."""
    import sympy as sp

    from adbgen.families.single_plane.jacobi import rotating_lagrangian
    from adbgen.families.single_plane.scene import Scene

    h = rotating_lagrangian(Scene(n=n)).jacobi_integral()
    return _lambdified(sp.srepr(h))


@lru_cache(maxsize=None)
def _lambdified(text: str):
    import sympy as sp

    h = sp.sympify(text)
    names = sorted(str(s) for s in h.free_symbols)
    f = sp.lambdify([sp.Symbol(s) for s in names], h, modules="numpy", cse=True)

    def evaluate(model, y, p):
        y = np.asarray(y, float)
        p = np.asarray(p, float)
        values = []
        for name in names:
            if name in model.state_names:
                values.append(y[model.index(name)])
            else:
                values.append(p[model.param_names.index(name)])
        return np.asarray(f(*values), float) * np.ones(y.shape[1:])

    return evaluate


@lru_cache(maxsize=None)
def _midpoint_library(c_source: str, name: str, ny: int, np_: int) -> ctypes.CDLL:
    from adbgen.analysis.engines.compiled import SUNDIALS_LIBS, compiler
    from adbgen.analysis.loading import cache_dir

    src = Path(c_source)
    driver = c_file("midpoint.c")
    key = hashlib.sha256(driver.read_bytes() + src.read_bytes()).hexdigest()[:16]
    target = cache_dir() / "bench" / f"{name}-midpoint-{key}.so"
    if not target.is_file():
        target.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(prefix="adbgen-midpoint-") as tmp:
            so = Path(tmp) / "midpoint.so"
            cmd = [compiler(), "-std=gnu99", "-O2", "-fPIC", "-shared", f"-I{src.parent}",
                   f'-DADB_MODEL_SOURCE="{src}"', f"-DADB_RHS={name}_rhs", f"-DADB_JAC={name}_jac",
                   f"-DADB_NY={ny}", str(driver), "-o", str(so), *SUNDIALS_LIBS, "-lsundials_arkode", "-lm"]
            subprocess.run(cmd, check=True, capture_output=True, text=True)
            so.replace(target)
    lib = ctypes.CDLL(str(target))
    lib.adb_midpoint.restype = ctypes.c_int
    return lib


def midpoint(model, p, y0, h: float, times, rtol: float = 1e-10, atol: float = 1e-12) -> dict:
    """The implicit midpoint rule at the fixed step h (SUNDIALS ARKStep), sampled at `times`."""
    lib = _midpoint_library(str(model.c_source()), model.name, model.n_states, model.n_params)
    D = ctypes.POINTER(ctypes.c_double)
    times = np.ascontiguousarray(times, float)
    out = np.zeros((len(times), model.n_states))
    counts = np.zeros(5, np.int64)
    y0 = np.ascontiguousarray(y0, float)
    p = np.ascontiguousarray(p, float)
    start = time.perf_counter()
    code = lib.adb_midpoint(y0.ctypes.data_as(D), p.ctypes.data_as(D), ctypes.c_double(h), ctypes.c_double(rtol),
                            ctypes.c_double(atol), len(times), times.ctypes.data_as(D), out.ctypes.data_as(D),
                            counts.ctypes.data_as(ctypes.POINTER(ctypes.c_long)))
    wall = time.perf_counter() - start
    k = int(counts[4])
    return {"status": "success" if code == 0 else f"failed ({code}) at t = {times[k] if k < len(times) else math.nan}",
            "t": times[:k], "y": out[:k].T, "n_steps": int(counts[0]), "n_rhs": int(counts[1]),
            "newton_iters": int(counts[2]), "jac_evals": int(counts[3]), "wall_s": wall}


def drift_curve(t, J, J0, points: int = 400) -> dict:
    """|J(t) - J(0)| on a log grid of times: the running maximum, so the curve is monotone and a
    short excursion between samples is not lost."""
    t = np.asarray(t, float)
    err = np.maximum.accumulate(np.abs(np.asarray(J, float) - J0))
    grid = np.geomspace(max(t[t > 0].min(), 1e-2), t.max(), points) if np.any(t > 0) else np.zeros(0)
    idx = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 1)
    return {"t": grid.tolist(), "max_abs_dJ": err[idx].tolist(), "final_abs_dJ": float(abs(J[-1] - J0)),
            "max_abs_dJ_all": float(err[-1])}


__all__ = ["drift_curve", "jacobi_function", "midpoint"]
