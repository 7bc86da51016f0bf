"""SciPy's solve_ivp on the generated numba functions: the reference path (a Python call per step).

Kept selectable (`scipy-dop853`, `scipy-rk45`, `scipy-radau`, `scipy-lsoda`, `scipy-bdf`) because
it is what users know and what the compiled engines are checked against.  It does not promise exact
symmetry: its stage combinations go through BLAS matrix products, which may round identical
components differently.  r_max and t_dec come from solve_ivp's events (extrema of r and crossings of
the threshold) on its dense output; a maximum of r above the threshold counts for t_dec, whose
excursion's end is then found on the dense output (brentq).

solve_ivp has no step limit: the method is run as a subclass of its scipy OdeSolver (`_limited`) that refuses
the step after `max_steps` accepted ones and stops at a non-finite derivative, both as a failed step, so
solve_ivp returns the part integrated (a run under the limit computes exactly what the plain method does).
A failed run reports r_max over that part, as the compiled engines do.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import scipy.integrate
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..results import SUCCESS

METHODS = {"dop853": "DOP853", "rk45": "RK45", "radau": "Radau", "lsoda": "LSODA", "bdf": "BDF"}
_IMPLICIT = {"Radau", "LSODA", "BDF"}


class _NonFinite(Exception):
    def __init__(self, t):
        self.t = float(t)


def _limited(method: str, max_steps: int):
    """scipy's OdeSolver `method` stopping as a failed step (solve_ivp then keeps the steps accepted before it)
    when `max_steps` steps are taken (`hit_limit`) or a derivative is non-finite (`failed_at`: its time).  Only
    `_step_impl` is wrapped (where OdeSolver's documentation has a solver put its step; solve_ivp has no step limit
    to pass): every step the method takes is its own, bit for bit.  A class per run, so that its
    two outcomes are read off the class after solve_ivp (which keeps no solver)."""
    base = getattr(scipy.integrate, method)

    class Limited(base):
        hit_limit = False
        failed_at = None

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.taken = 0

        def _step_impl(self):
            if self.taken >= max_steps:
                type(self).hit_limit = True
                return False, f"solve_ivp {method}: max_steps = {max_steps} steps taken before t_end"
            try:
                ok, message = super()._step_impl()
            except _NonFinite as exc:
                type(self).failed_at = exc.t
                return False, "non-finite derivative"
            self.taken += ok
            return ok, message

    return Limited


def _decay_time(sol, peaks, r, ix, iy, threshold) -> float:
    """t_dec = sup{t : r(t) >= H} on the dense output, r(t_end) < H: the last crossing event, or the end of
    the excursion at the latest maximum of r above H when later (an excursion that starts and ends
    inside one step changes no sign of r^2 - H^2 at step ends); 0 when r never reaches H.  `peaks`: r at
    the extremum events, as r_max has them."""
    crossings = sol.t_events[0]
    last = float(crossings[-1]) if len(crossings) else None
    above = [float(te) for te, v in zip(sol.t_events[1], peaks) if v >= threshold]
    if above and (last is None or above[-1] > last):
        te = above[-1]
        t_next = float(sol.t[np.searchsorted(sol.t, te, side="right")])  # r(t_end) < H: a step end follows

        def g(t):
            y = sol.sol(t)
            return y[ix] * y[ix] + y[iy] * y[iy] - threshold * threshold

        if g(t_next) < 0:
            return float(brentq(g, te, t_next, xtol=1e-12, rtol=4 * np.finfo(float).eps))
        last = te if last is None else max(last, te)
    if last is not None:
        return last
    return 0.0 if r.max() < threshold else float("nan")


class ScipyEngine:
    native_events = True
    symmetric = False

    def __init__(self, key: str, use_jac: bool = True):
        self.method = METHODS[key]
        self.use_jac = use_jac and self.method in _IMPLICIT
        self.name = "scipy-" + key + ("" if use_jac or self.method not in _IMPLICIT else "-fdjac")
        self.description = f"scipy.integrate.solve_ivp {self.method}" + \
            (" with the generated analytic Jacobian" if self.use_jac else "") + "; a Python call per step"

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=0):
        mod = model.module
        ix, iy, ixd, iyd = model.amplitude_indices
        count = [0]

        def f(t, y):
            count[0] += 1
            out = mod.rhs(t, y, p)
            if not np.all(np.isfinite(out)):  # solve_ivp would shrink the step for ever on NaN
                raise _NonFinite(t)
            return out

        def crossing(t, y):
            return y[ix] * y[ix] + y[iy] * y[iy] - threshold * threshold

        def extremum(t, y):
            return y[ix] * y[ixd] + y[iy] * y[iyd]

        kwargs = {"jac": (lambda t, y: mod.jac(t, y, p))} if self.use_jac else {}
        method = _limited(self.method, max_steps)
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                sol = solve_ivp(f, (0.0, t_end), np.asarray(y0, float), method=method, rtol=rtol, atol=atol,
                                dense_output=True, events=(crossing, extremum), **kwargs)
        except _NonFinite as exc:  # at the start, before a step: nothing integrated
            y_start = np.asarray(y0, float)  # what was reached: the start, as the compiled engines report it
            return {"status": "nonfinite", "t": np.zeros(0), "y": np.zeros((len(y0), 0)),
                    "r_max": float(np.hypot(y_start[ix], y_start[iy])), "t_dec": float("nan"),
                    "y_end": y_start.copy(), "n_rhs": count[0], "n_steps": 0,
                    "t_fail": exc.t, "wall_s": time.perf_counter() - start, "message": "non-finite derivative"}
        wall = time.perf_counter() - start
        y_end = sol.y[:, -1]
        t_last = float(sol.t[-1])
        finite = bool(np.all(np.isfinite(sol.y)))
        r = np.hypot(sol.y[ix], sol.y[iy])
        # r_max over the part integrated, failed or not (the output says a run failed): the accepted steps and
        # the extrema located inside them
        peaks = [float(np.hypot(*sol.sol(te)[[ix, iy]])) for te in sol.t_events[1]]
        r_max = float(np.nanmax(np.concatenate([r, peaks])))
        if sol.status == 0 and finite:
            if r[-1] >= threshold:
                t_dec = float("nan")
            else:
                t_dec = _decay_time(sol, peaks, r, ix, iy, threshold)
            status, t_fail = SUCCESS, None
        else:
            bad = np.nonzero(~np.all(np.isfinite(sol.y), axis=0))[0]
            if method.hit_limit:
                status = "max_steps"
            else:
                status = "nonfinite" if (not finite or "finite" in sol.message) else (
                    "step_underflow" if "step size" in sol.message.lower() else "solver_failure")
            t_fail = float(sol.t[bad[0]]) if len(bad) else (method.failed_at if method.failed_at is not None
                                                            else t_last)
            t_dec = float("nan")
        return {"status": status, "t": sol.t, "y": sol.y, "r_max": r_max, "t_dec": t_dec, "y_end": y_end,
                "n_rhs": int(sol.nfev), "n_steps": int(len(sol.t) - 1), "t_fail": t_fail, "wall_s": wall,
                "message": "" if status == SUCCESS else sol.message}

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        rows = [self.run(model, P[k], Y0[k], t_end, rtol, atol, threshold, max_steps, False) for k in range(len(Y0))]
        return {"status": np.array([r["status"] for r in rows]), "r_max": np.array([r["r_max"] for r in rows]),
                "t_dec": np.array([r["t_dec"] for r in rows]), "y_end": np.array([r["y_end"] for r in rows]),
                "t_last": np.array([t_end if r["t_fail"] is None else r["t_fail"] for r in rows]),
                "t_fail": np.array([np.nan if r["t_fail"] is None else r["t_fail"] for r in rows]),
                "target": np.full(len(rows), -1), "n_rhs": np.array([r["n_rhs"] for r in rows]),
                "n_steps": np.array([r["n_steps"] for r in rows]), "wall_s": sum(r["wall_s"] for r in rows)}
