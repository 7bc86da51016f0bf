"""`hybrid-dop853` in the engine registry: the stick-slip hybrid system (hybrid.py) behind the interface every
engine has (`run`, `run_many`, the same result keys), so `adbgen simulate` and `adbgen sweep` run it.

A model with stick and slip modes (its self-description has the parameters stuck_k; `hybrid.switching`)
gets this engine by default (`engines.engine_for`); another engine asked for such a model is refused, since
none of them switches modes.  Besides the usual keys a run says per ball whether it ended stuck (`stuck`)
and the residual imbalance at the end (`r_end`, the rotor centre's amplitude r = sqrt(X^2 + Y^2) at t_end,
the quantity the issue calls r at rest).  r_max and t_dec are read off the `samples` output points (as
matlab-ode45 does), not located on the continuous solution: said in `picked`.  A failed run's r_max is over
the part integrated, its last state included, as every engine's.
"""

from __future__ import annotations

import time

import numpy as np

from ..results import SUCCESS
from . import hybrid

# hybrid.STATUS names -> the project's statuses (results.FAILURES); max_events has no other engine's twin;
# no_consistent_mode is said as itself (a ball that can neither stick nor slip, not a solver's failure)
_STATUS = {"success": SUCCESS, "max_steps": "max_steps", "step_underflow": "step_underflow",
           "nonfinite": "nonfinite", "max_events": "solver_failure", "no_consistent_mode": "no_consistent_mode"}


def has_stick_phase(model) -> bool:
    """Whether the model's self-description carries stick/slip modes (a parameter stuck_1)."""
    return "stuck_1" in model.param_names


def _decay_time(t, r, threshold) -> float:
    """t_dec on the samples: the last sample time with r >= threshold (0 if none), NaN if r(t_end) >= it."""
    if not len(r) or r[-1] >= threshold:
        return float("nan")
    above = np.flatnonzero(r >= threshold)
    return float(t[above[-1]]) if len(above) else 0.0


class HybridEngine:
    """The event-driven stick-slip engine (hybrid_driver.c) as a registered engine."""

    name = "hybrid-dop853"
    description = ("DOP853 with stick/slip events (a stuck ball is the constraint phi' = 0 while inside the "
                   "stiction cone): the engine for models with static friction; r_max, t_dec on samples")
    symmetric = False  # not checked bit for bit: events are decided per ball
    native_events = False  # r_max and t_dec on the output samples
    stick_slip = True  # runs the stick/slip modes (capabilities: "stick-slip")

    def run(self, model, p, y0, t_end, rtol, atol, threshold, max_steps, keep_trajectory=True, samples=0):
        n = max(int(samples), 201)
        start = time.perf_counter()
        out = hybrid.run(model, p, y0, 0.0, float(t_end), t_eval=np.linspace(0.0, float(t_end), n), rtol=rtol,
                         atol=atol, max_steps=int(max_steps))
        wall = time.perf_counter() - start
        ix, iy, _, _ = model.amplitude_indices
        status = _STATUS.get(out.status, "solver_failure")
        finite = bool(np.all(np.isfinite(out.y_end)))
        if status == SUCCESS and not finite:
            status = "nonfinite"
        r = np.hypot(out.y[:, ix], out.y[:, iy]) if len(out.t) else np.zeros(0)
        ok = status == SUCCESS
        # r_max over the part integrated, failed or not (the status says a run failed): the samples reached and,
        # on a failure, the state it stopped at (the last sample may lie well before it), as every engine reports
        reached = np.append(r, np.hypot(out.y_end[ix], out.y_end[iy])) if not ok else r
        reached = reached[np.isfinite(reached)]
        sw = hybrid.switching(model)
        stuck = [bool(out.params_end[i] == 1.0) for i in sw.stuck]
        r_end = float(np.hypot(out.y_end[ix], out.y_end[iy])) if ok else float("nan")
        return {"status": status, "t": out.t if keep_trajectory else np.zeros(0),
                "y": out.y.T if keep_trajectory else np.zeros((model.n_states, 0)),
                "r_max": float(reached.max()) if len(reached) else float("nan"),
                "t_dec": _decay_time(out.t, r, threshold) if ok else float("nan"),
                "y_end": out.y_end, "n_rhs": 12 * out.steps, "n_steps": out.steps,  # DOP853: 12 stages a step
                "t_fail": None if ok else out.t_end, "wall_s": wall,
                "message": "" if ok else f"hybrid engine: {out.status} at t = {out.t_end:g}",
                "stuck": stuck, "r_end": r_end, "events": len(out.events),
                "picked": {"engine": self.name, "stuck": stuck, "r_end": r_end, "events": len(out.events),
                           "r_max_t_dec": f"on {n} output samples"}}

    def run_many(self, model, P, Y0, t_end, rtol, atol, threshold, max_steps, threads=None, check_dt=0.0,
                 targets=(), measures=True):
        if targets:
            from ..loading import AnalysisError
            raise AnalysisError("hybrid-dop853 has no early stop (its rest states are stuck states, not basins)")
        rows = [self.run(model, P[k], Y0[k], t_end, rtol, atol, threshold, max_steps, False) for k in range(len(Y0))]
        stuck = np.array([r["stuck"] for r in rows], dtype=bool)
        return {"status": np.array([r["status"] for r in rows]), "r_max": np.array([r["r_max"] for r in rows]),
                "t_dec": np.array([r["t_dec"] for r in rows]), "y_end": np.array([r["y_end"] for r in rows]),
                "t_last": np.array([t_end if r["t_fail"] is None else r["t_fail"] for r in rows]),
                "t_fail": np.array([np.nan if r["t_fail"] is None else r["t_fail"] for r in rows]),
                "target": np.full(len(rows), -1), "n_rhs": np.array([r["n_rhs"] for r in rows]),
                "n_steps": np.array([r["n_steps"] for r in rows]), "wall_s": sum(r["wall_s"] for r in rows),
                "stuck": stuck, "r_end": np.array([r["r_end"] for r in rows]),
                "picked": {"engine": self.name}}


ENGINE = HybridEngine()
