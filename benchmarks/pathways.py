"""A pathway is one way of integrating a problem (an engine of adbgen's registry, a baseline, a peer, a
floor loop); the benchmarks time pathways best-of-N, round-robin, and compare their final states with
a reference and their times at equal error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .problems import Problem

SLOW_S = 1.0  # a pathway slower than this on its first run is run once


@dataclass
class Pathway:
    """One way of integrating the problem: `run()` returns wall_s, y_end, n_rhs, n_steps, status."""

    key: str  # unique, e.g. "cyrk-dop853" or "heyoka@1e-09"
    kind: str  # "engine" (adbgen's registry), "baseline", "peer", "floor", ...
    name: str  # engine or peer name
    tol: float
    run: Callable[[], dict]
    runs_s: list = field(default_factory=list)
    last: dict = field(default_factory=dict)
    probe: Callable[[float], float] | None = None  # floors: seconds per call from one burst of ~t seconds

    def record(self) -> dict:
        out = {k: v for k, v in self.last.items() if k != "y_end"}
        out.update({"key": self.key, "kind": self.kind, "name": self.name, "tol": self.tol,
                    "runs_s": [round(t, 6) for t in self.runs_s],
                    "wall_s": round(min(self.runs_s), 6) if self.runs_s else None})
        return out


def engine_pathway(model, problem: Problem, engine: str, rtol: float | None = None, atol: float | None = None,
                   y0: dict | None = None, key: str | None = None) -> Pathway:
    """An engine of `adbgen.analysis.engines.ENGINES` on the problem (`analysis.simulate`, no trajectory)."""
    from adbgen.analysis.simulate import simulate

    p, y = problem.vectors(model)
    if y0 is not None:
        y = model.state(y0)
    rtol = problem.rtol if rtol is None else rtol
    atol = problem.atol if atol is None else atol

    def run():
        s = simulate(model, p, y, t_end=problem.t_end, rtol=rtol, atol=atol, engine=engine, keep_trajectory=False,
                     check=False)
        return {"wall_s": s.wall_s, "y_end": s.y_end, "n_rhs": int(s.n_rhs), "n_steps": int(s.n_steps),
                "status": s.status, "r_max": s.r_max, "t_dec": s.t_dec}

    return Pathway(key or engine, "engine", engine, rtol, run)


def measure(pathways: list[Pathway], repeats: int, slow_s: float = SLOW_S, progress=None) -> None:
    """Best-of-`repeats` timings, round-robin over the pathways (slow ones once)."""
    for r in range(max(1, repeats)):
        for pw in pathways:
            if r > 0 and (not pw.runs_s or pw.runs_s[0] > slow_s or pw.last.get("status") != "success"):
                continue
            try:
                out = pw.run()
            except Exception as exc:  # one broken pathway is recorded, not fatal to the benchmark
                pw.last = {"status": f"error: {type(exc).__name__}: {exc}"}
                continue
            pw.runs_s.append(float(out["wall_s"]))
            pw.last = out
            if progress and r == 0:
                progress(f"{pw.key:24s} {1e9 * out['wall_s']:10.2f} ns per call" if pw.kind == "floor" else
                         f"{pw.key:24s} {1e3 * out['wall_s']:10.2f} ms  n_rhs {out.get('n_rhs')}  "
                         f"steps {out.get('n_steps')}  {out.get('status')}")


def error(y_end, reference) -> float | None:
    """Largest absolute difference between two final states (None if either is missing)."""
    if y_end is None:
        return None
    y = np.asarray(y_end, float)
    if y.shape != np.shape(reference) or not np.all(np.isfinite(y)):
        return None
    return float(np.max(np.abs(y - reference)))


def time_at_error(points, target: float) -> dict | None:
    """A pathway's time at a given error, log-log interpolated from its (error, time) points.

    Points dominated by another (larger error and longer time) are dropped first: a tolerance that
    happens to land badly does not count against the pathway.  Inside the range of errors: linear
    interpolation of log time against log error between the neighbours (points sorted by error).
    Outside it: the nearest two points' line (extrapolated)."""
    pts = sorted((e, t) for e, t in points if e is not None and e > 0 and t is not None and t > 0)
    if not pts or target is None or target <= 0:
        return None
    # the pathway's best trade-offs only: drop a point when another one is both more accurate and faster
    pts = [(e, t) for e, t in pts if not any(e2 <= e and t2 < t for e2, t2 in pts)]
    if len(pts) == 1:
        return {"time_s": pts[0][1], "how": "single point", "error": pts[0][0]}
    le = [math.log(e) for e, _ in pts]
    lt = [math.log(t) for _, t in pts]
    x = math.log(target)
    if x <= le[0]:
        i, how = 0, "extrapolated"
    elif x >= le[-1]:
        i, how = len(pts) - 2, "extrapolated"
    else:
        i = max(k for k in range(len(pts) - 1) if le[k] <= x)
        how = "interpolated"
    if le[i + 1] == le[i]:
        return {"time_s": min(pts[i][1], pts[i + 1][1]), "how": how, "error": target}
    w = (x - le[i]) / (le[i + 1] - le[i])
    return {"time_s": math.exp(lt[i] + w * (lt[i + 1] - lt[i])), "how": how, "error": target}


__all__ = ["Pathway", "SLOW_S", "engine_pathway", "error", "measure", "time_at_error"]
