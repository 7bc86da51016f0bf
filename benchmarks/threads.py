"""Many trajectories on one and on two threads (`simulate_many`), beside a control that shows what
speed-up the shared machine could give at that moment: independent busy loops on OpenMP threads
(c/omp_control.c), timed just before each run.
"""

from __future__ import annotations

import subprocess
import tempfile
from pathlib import Path

import numpy as np

from .problems import Problem
from .timing import c_compiler, c_file, cpu_of_process

MANY_N = 64


def many(model, problem: Problem, n: int = MANY_N, threads=(1, 2), repeats: int = 3, engine: str | None = None,
         spread: float = 0.5) -> dict:
    """simulate_many over n trajectories (the first ball's angle = problem's +- spread) with each
    thread count.

    cpu_s (the process' CPU time over the call) beside wall_s shows whether the cores were free: on a
    loaded machine 2 threads get less than two cores and the speed-up says more about the load."""
    from adbgen.analysis.simulate import simulate_many

    p, y = problem.vectors(model)
    Y0 = np.repeat(y[None, :], n, axis=0)
    i1 = model.role_indices("ball_angle")[0]
    Y0[:, i1] += np.linspace(-spread, spread, n)
    runs: dict[int, list] = {k: [] for k in threads}
    ends: dict[int, np.ndarray] = {}
    n_rhs = None
    statuses = set()
    cpu: dict[int, list] = {k: [] for k in threads}
    control_runs: dict[int, list] = {k: [] for k in threads}
    with tempfile.TemporaryDirectory(prefix="adbgen-omp-") as tmp:
        try:
            control = ParallelControl(Path(tmp))
        except (RuntimeError, OSError, subprocess.CalledProcessError):
            control = None
        for _ in range(max(1, repeats)):
            for k in threads:
                if control is not None:
                    control_runs[k].append(control.run(k))
                before = cpu_of_process()
                ens = simulate_many(model, p[None, :], Y0, t_end=problem.t_end, rtol=problem.rtol,
                                    atol=problem.atol, engine=engine, threads=k)
                cpu[k].append(cpu_of_process() - before)
                runs[k].append(float(ens.wall_s))
                ends[k] = ens.y_end
                n_rhs = int(np.sum(ens.n_rhs))
                statuses |= set(map(str, ens.status))
    best = {k: min(v) for k, v in runs.items()}
    out = {"n_trajectories": n, "phi_1_spread": spread, "engine": engine or "default", "total_rhs": n_rhs,
           "statuses": sorted(statuses),
           "threads": {str(k): {"runs_s": [round(t, 6) for t in runs[k]], "wall_s": round(best[k], 6),
                                "cpu_s": [round(t, 6) for t in cpu[k]]} for k in threads},
           "identical_across_threads": all(np.array_equal(ends[threads[0]], ends[k]) for k in threads)}
    if 1 in best and len(threads) > 1:
        out["speedup"] = {str(k): round(best[1] / best[k], 3) for k in threads if k != 1}
    if all(control_runs.values()):
        out["control"] = {"what": "independent busy loops on OpenMP threads (gcc -O2 -fopenmp), run just "
                                  "before each simulate_many call: the speed-up the machine gave at that moment",
                          "threads": {str(k): {"runs_s": [round(t, 6) for t in v], "wall_s": round(min(v), 6)}
                                      for k, v in control_runs.items()}}
        if 1 in control_runs and len(threads) > 1:
            out["control"]["speedup"] = {str(k): round(min(control_runs[1]) / min(control_runs[k]), 3)
                                         for k in threads if k != 1}
            if "speedup" in out:  # the engine's speed-up as a share of what the machine gave
                out["speedup_over_control"] = {k: round(v / out["control"]["speedup"][k], 3)
                                               for k, v in out["speedup"].items()}
    return out


class ParallelControl:
    """Builds c/omp_control.c once; run(threads) returns its wall seconds (about `seconds` on one core)."""

    def __init__(self, folder: Path, tasks: int = 64, seconds: float = 0.3):
        cc = c_compiler()
        if not cc:
            raise RuntimeError("no C compiler")
        self.exe = folder / "omp_control"
        subprocess.run([cc, "-O2", "-fopenmp", str(c_file("omp_control.c")), "-o", str(self.exe)], check=True,
                       capture_output=True)
        self.tasks = tasks
        self.work = 1000
        while True:  # calibrate on one thread
            t = self.run(1)
            if t > 0.05 or self.work > 1 << 40:
                break
            self.work *= 8
        self.work = max(1, int(self.work * seconds / t))

    def run(self, threads: int) -> float:
        out = subprocess.run([str(self.exe), str(threads), str(self.tasks), str(self.work)], check=True,
                             capture_output=True, text=True).stdout
        return float(out.split()[0])


__all__ = ["MANY_N", "ParallelControl", "many"]
