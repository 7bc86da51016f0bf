"""The flow of a generated model and its derivatives, from the compiled variational driver.

    Flow(model).arcs(X0, T0, H, p)            end states of m arcs (rows), integrated in C
    Flow(model).arcs(..., phi=True, dp=e_3)   ... with Phi = d end / d start and w = d end / d p along dp
    Flow(model).sample(y0, t0, times, p)      the state at `times` (CyRK's dense output)

`engines/variational_driver.c` integrates y' = f, Phi' = J Phi and w' = J w + f_p dp as one
system with CyRK's DOP853 (the default engine's solver), J and f_p the generated analytic Jacobians,
so the monodromy matrix of an orbit and the shooting Newton's Jacobian come from the variational
equations, not from finite differences.  The library is compiled once per model with its C source
(`engines.compiled.build`, cached) and called through ctypes with the GIL released; several arcs run
on OpenMP threads inside it.
"""

from __future__ import annotations

import ctypes
import threading
from functools import lru_cache

import numpy as np

from ..engines.compiled import _cyrk_methods, _cyrk_pointers, build
from ..loading import AnalysisError, Model

RTOL, ATOL = 1e-11, 1e-12
MAX_STEPS = 2_000_000
_lock = threading.Lock()
_D = ctypes.POINTER(ctypes.c_double)
_I = ctypes.POINTER(ctypes.c_int)
_L = ctypes.POINTER(ctypes.c_long)
STATUS = {0: "success", 1: "max_steps", 2: "step_underflow", 3: "nonfinite", 4: "solver_failure"}


class FlowError(AnalysisError):
    """An arc could not be integrated (step limit, step-size underflow, non-finite state)."""


def _ptr(a):
    return a.ctypes.data_as(_D)


# the driver's three entry points as variational_driver.c declares them (name: restype, argtypes), set at load so
# that a wrong argument is refused by ctypes instead of being read by C as an address or a number (issue 33
# item 1: no untyped call into a driver, as hybrid.RUN_ARGTYPES); like the hybrid driver, this one is outside
# adb_engine.h (it owns its arcs and their variational equations), so it is typed here
_F, _C = ctypes.c_double, ctypes.c_int
SIGNATURES = {
    "adb_var_init": (ctypes.c_int, [ctypes.POINTER(ctypes.c_void_p)]),
    "adb_var_arcs": (None, [_C, _D, _D, _D, _D, _D, _C, _F, _F, _C, ctypes.c_long, _C, _D, _D, _D, _I, _L]),
    "adb_var_sample": (ctypes.c_int, [_D, _F, _D, _C, _D, _F, _F, _C, ctypes.c_long, _D]),
}


@lru_cache(maxsize=None)
def _library(path: str):
    lib = ctypes.CDLL(path)
    for name, (restype, argtypes) in SIGNATURES.items():
        getattr(lib, name).restype = restype
        getattr(lib, name).argtypes = argtypes
    lib.adb_var_init((ctypes.c_void_p * 9)(*_cyrk_pointers()))
    return lib


def library(model: Model):
    # the model's jac_p through a define of its own (build's defines name rhs and jac only)
    with _lock:
        return _library(str(build(model, "variational_driver.c", [f"-DADB_JAC_P={model.name}_jac_p"])))


class Flow:
    """Arcs of `model` with their variational equations (see the module's docstring)."""

    def __init__(self, model: Model, rtol: float = RTOL, atol: float = ATOL, method: str = "DOP853",
                 threads: int = 1, max_steps: int = MAX_STEPS):
        self.model, self.rtol, self.atol, self.threads, self.max_steps = model, rtol, atol, threads, max_steps
        self.method = _cyrk_methods()[method]
        self.lib = library(model)
        self.n_rhs = 0  # evaluations of the augmented system so far (each costs one rhs and, with Phi, one jac)

    def arcs(self, X0, T0, H, p, phi: bool = False, dp=None):
        """End states (m x N) of the arcs from (T0[i], X0[i]) over H[i]; with phi, also Phi (m x N x N) and,
        with dp (a direction in parameter space), w = d end / d p along dp (m x N).  Returns (X, Phi or None,
        W or None)."""
        N = self.model.n_states
        X0 = np.ascontiguousarray(np.atleast_2d(X0), dtype=float)
        m = len(X0)
        T0 = np.ascontiguousarray(np.broadcast_to(np.asarray(T0, float), (m,)))
        H = np.ascontiguousarray(np.broadcast_to(np.asarray(H, float), (m,)))
        p = np.ascontiguousarray(p, dtype=float)
        X = np.zeros((m, N))
        P = np.zeros((m, N, N)) if phi else np.zeros(1)
        with_w = phi and dp is not None
        W = np.zeros((m, N)) if with_w else np.zeros(1)
        dpv = np.ascontiguousarray(dp, dtype=float) if with_w else None
        status = np.zeros(m, np.int32)
        counts = np.zeros(2, np.int64)
        self.lib.adb_var_arcs(
            m, _ptr(X0), _ptr(T0), _ptr(H), _ptr(p), None if dpv is None else _ptr(dpv), 1 if phi else 0,
            ctypes.c_double(self.rtol), ctypes.c_double(self.atol), self.method, ctypes.c_long(self.max_steps),
            int(self.threads), _ptr(X), _ptr(P), _ptr(W), status.ctypes.data_as(_I), counts.ctypes.data_as(_L))
        self.n_rhs += int(counts[0])
        bad = np.nonzero(status)[0]
        if len(bad):
            i = int(bad[0])
            raise FlowError(f"{self.model.name}: arc {i} from t = {T0[i]:.6g} over {H[i]:.6g} failed "
                            f"({STATUS.get(int(status[i]), status[i])})")
        return X, (P if phi else None), (W if with_w else None)

    def end(self, x0, t0: float, h: float, p) -> np.ndarray:
        return self.arcs(x0, t0, h, p)[0][0]

    def sample(self, y0, t0: float, times, p) -> np.ndarray:
        """The state at `times` (increasing, after t0), times x states, on the solver's dense output."""
        times = np.ascontiguousarray(times, dtype=float)
        out = np.zeros((len(times), self.model.n_states))
        code = self.lib.adb_var_sample(
            _ptr(np.ascontiguousarray(y0, dtype=float)), ctypes.c_double(t0), _ptr(np.ascontiguousarray(p, dtype=float)),
            len(times), _ptr(times), ctypes.c_double(self.rtol), ctypes.c_double(self.atol), self.method,
            ctypes.c_long(self.max_steps), _ptr(out))
        if code:
            raise FlowError(f"{self.model.name}: sampling from t = {t0:.6g} to {times[-1]:.6g} failed "
                            f"({STATUS.get(int(code), code)})")
        return out
