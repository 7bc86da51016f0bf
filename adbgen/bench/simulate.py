"""Benchmark (not a test): integrating problem A on every engine, against the peers and the floor.

Issue: simulation and stability, "A benchmark (not a timed test), `adbgen bench simulate`".

Problem A: the thesis model with n = 3 (`thesis_rotating_n3`), parameters (5.1) (the module's
DEFAULTS), phi(0) = (pi/3, -pi/3, pi), everything else 0, t in [0, 2000], rtol 1e-8, atol 1e-10.

Measured in one run (compare ratios, not absolute times across runs: the machine is shared):

- ``engines``: every engine of `adbgen.analysis.engines.ENGINES` on problem A: wall time of the
  integration alone (`Simulation.wall_s`), rhs evaluations, steps, and the error of the final state
  against the reference (largest absolute difference over the states);
- ``reference``: CyRK's Verner 8(7) (compiled; not the default engine's method) at rtol 1e-13,
  atol 1e-15, checked against SciPy's DOP853 on the numba rhs at the same tolerances: their
  difference bounds the reference's own error and must be far below every error it measures;
- ``peers``: JiTCODE (``dop853`` backend) and heyoka (Taylor), fed the same equations (the generated
  module's rhs statements in their order, `adbgen.bench.peers`), their setup (translation, compilation)
  timed apart from the integration; with the default engine, at the tolerances `SWEEP_TOLS` so that
  times can be compared at equal error (log-log interpolation of time against error);
- ``baselines``: the issue's starting points, the numba rhs as a Python callback of SciPy's
  ``solve_ivp`` DOP853 and ``ode('dop853')`` without events;
- ``floor``: ns per call of the generated C rhs in a C loop (gcc -O2, as the engines are built) and of
  the numba rhs in a jitted loop; an engine's floor is its rhs evaluations times the C ns per call;
  ``paired``: for the fast Runge-Kutta engines, wall / floor per round with the floor timed just
  before each integration (the median is robust to the machine's load; the target uses it);
- ``symmetry``: ``runs``: from phi(0) = (pi, pi, pi) identical balls must stay bitwise equal and
  reach the coincident state 2- (thesis: x = 0.1285, y = -0.0083, phi = 3.0772), for every pathway
  that runs problem A in under `SYMMETRY_MAX_S`, the peers included; ``rhs_symmetric_fraction``: how often
  the rhs itself (generated, and as each peer evaluates it) gives identical balls identical
  derivatives at random ball-symmetric states;
- ``many``: `simulate_many` over `MANY_N` trajectories of problem A (phi_1(0) varied) with 1 and 2
  threads, and the speed-up, beside a control (independent busy loops on OpenMP threads, timed just
  before each run) that shows what speed-up the shared machine could give at that moment;
- ``targets``: the issue's targets, each with pass/fail and the measured ratio.

Every timing is the best of `repeats` (all recorded); repeats run round-robin over the pathways, so
a burst of load on the machine hits all of them alike.  A pathway whose first run takes longer than
`SLOW_S` runs once (the SciPy implicit methods take 10-30 s here).
"""

from __future__ import annotations

import datetime
import math
import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np


DEFAULT_REPEATS = 7
SLOW_S = 1.0  # a pathway slower than this on its first run is run once
SWEEP_TOLS = (1e-7, 1e-8, 1e-9, 1e-10)
MANY_N = 64
RK_PREFIXES = ("cyrk-", "arkode-")  # the explicit Runge-Kutta engines (the floor target is theirs)
SYMMETRY_MAX_S = 2.0  # engines slower than this on problem A are not run from (pi, pi, pi) (time)
PAIRED_MAX_S = 0.2  # engines slower than this are left out of the paired floor ratios (time)
REFERENCE_RTOL, REFERENCE_ATOL = 1e-13, 1e-15
REFERENCE_ENGINE = "cyrk-vern8"
# thesis ch. 5: n = 3 from (pi, pi, pi) ends at the coincident state 2- (printed to 4 decimals)
THESIS_2MINUS = {"x": 0.1285, "y": -0.0083, "phi": 3.0772}
THESIS_2MINUS_TOL = 5e-4


@dataclass(frozen=True)
class Problem:
    """An initial-value problem on a generated model, set by name (states not given are 0)."""

    label: str
    model: str
    params: dict = field(default_factory=dict)
    y0: dict = field(default_factory=dict)
    t_end: float = 2000.0
    rtol: float = 1e-8
    atol: float = 1e-10

    def vectors(self, model):
        return model.params(self.params), model.state(self.y0)

    def to_json(self) -> dict:
        return {"label": self.label, "model": self.model, "params": dict(self.params), "y0": dict(self.y0),
                "t_end": self.t_end, "rtol": self.rtol, "atol": self.atol}


PROBLEM_A = Problem("A", "thesis_rotating_n3", {}, {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi})


def symmetric_y0(model) -> dict:
    """Every ball at pi, all else 0 (thesis ch. 5: for n = 3 the run ends at the coincident state 2-)."""
    return {name: math.pi for name in model.leaves}


# ------------------------------------------------------------------------------------ pathways

@dataclass
class Pathway:
    """One way of integrating the problem: `run()` returns wall_s, y_end, n_rhs, n_steps, status."""

    key: str  # unique, e.g. "cyrk-dop853" or "heyoka@1e-09"
    kind: str  # "engine" (adbgen's registry) or "peer"
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
    from ..analysis.simulate import simulate

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


def baseline_pathways(model, problem: Problem) -> list[Pathway]:
    """The issue's starting points: the generated numba rhs as a Python callback, no events.

    "baseline:solve_ivp-dop853": ``solve_ivp(rhs, ..., method="DOP853")`` (the scipy-dop853 engine
    adds the r_max/t_dec events and dense output to this); "baseline:ode-dop853":
    ``scipy.integrate.ode(rhs).set_integrator("dop853")`` (Hairer's Fortran code, a Python call per
    evaluation: what JiTCODE's dop853 backend runs, with numba's rhs instead of JiTCODE's)."""
    from scipy.integrate import ode, solve_ivp

    p, y = problem.vectors(model)
    rhs = model.module.rhs

    def run_ivp():
        start = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, problem.t_end), y, method="DOP853", args=(p,), rtol=problem.rtol,
                        atol=problem.atol)
        wall = time.perf_counter() - start
        return {"wall_s": wall, "y_end": sol.y[:, -1].copy(), "n_rhs": int(sol.nfev), "n_steps": len(sol.t) - 1,
                "status": "success" if sol.status == 0 else f"failed: {sol.message}"}

    def run_ode():
        count = [0]

        def f(t, yy):
            count[0] += 1
            return rhs(t, yy, p)

        solver = ode(f).set_integrator("dop853", rtol=problem.rtol, atol=problem.atol, nsteps=10**7)
        solver.set_initial_value(y, 0.0)
        start = time.perf_counter()
        y_end = solver.integrate(problem.t_end)
        wall = time.perf_counter() - start
        return {"wall_s": wall, "y_end": np.array(y_end, float), "n_rhs": count[0], "n_steps": None,
                "status": "success" if solver.successful() else "failed"}

    return [Pathway("baseline:solve_ivp-dop853", "baseline", "solve_ivp DOP853, numba rhs, no events",
                    problem.rtol, run_ivp),
            Pathway("baseline:ode-dop853", "baseline", "scipy.integrate.ode dop853, numba rhs", problem.rtol, run_ode)]


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


# ----------------------------------------------------------------------------------- reference

def reference(model, problem: Problem, y0: dict | None = None) -> dict:
    """The final state at tight tolerance by a method other than the default engine's (Verner 8(7),
    compiled), checked by SciPy's DOP853 on the numba rhs (another method and implementation)."""
    from scipy.integrate import solve_ivp

    from ..analysis.simulate import simulate

    p, y = problem.vectors(model)
    if y0 is not None:
        y = model.state(y0)
    ref = simulate(model, p, y, t_end=problem.t_end, rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL,
                   engine=REFERENCE_ENGINE, keep_trajectory=False)
    start = time.perf_counter()
    sol = solve_ivp(model.module.rhs, (0.0, problem.t_end), y, method="DOP853", args=(p,), rtol=REFERENCE_RTOL,
                    atol=REFERENCE_ATOL)
    seconds = time.perf_counter() - start
    if sol.status != 0:
        raise RuntimeError(f"reference check failed: {sol.message}")
    return {"method": f"{REFERENCE_ENGINE} (CyRK Verner 8(7) on the generated C, compiled)", "rtol": REFERENCE_RTOL,
            "atol": REFERENCE_ATOL, "n_rhs": int(ref.n_rhs), "y_end": ref.y_end.copy(),
            "check_method": "scipy solve_ivp DOP853 on the generated numba rhs, same tolerances",
            "check_seconds": round(seconds, 3), "check_difference": error(sol.y[:, -1], ref.y_end)}


# ---------------------------------------------------------------------------------------- floor

def floor_pathways(model, y, p, folder: Path, target: float = 0.01, inner: int = 5) -> list[Pathway]:
    """ns per call of the generated rhs as pathways (timed in the round-robin with the integrations).

    "floor:c": the C rhs in a C loop (gcc -O2, as the engines are built; a separate timing program,
    `bench_codegen._C_MAIN`); "floor:numba": rhs_inplace in a jitted loop.  Each run times `inner`
    bursts of about `target` seconds of calls and keeps the fastest (short bursts find the quiet
    moments of a shared machine, as the integrations' best-of-N does); `wall_s` holds seconds per call."""
    from .codegen import _calibrate, _numba_loop, build_c_timer, run_c_timer

    y = np.ascontiguousarray(y, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    out = []
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc:
        src = model.c_source()
        for suffix in (".c", ".h"):
            shutil.copy(src.with_suffix(suffix), folder / (model.name + suffix))
        exe, _ = build_c_timer(folder, model.name, y, p, cc=cc)

        def run_c():
            return {"wall_s": 1e-9 * run_c_timer(exe, target, inner, False)["rhs"]["min_ns"], "status": "success"}

        out.append(Pathway("floor:c", "floor", "C rhs, gcc -O2, in a C loop", 0.0, run_c,
                           probe=lambda seconds: 1e-9 * run_c_timer(exe, seconds, 1, False)["rhs"]["min_ns"]))
    buf = np.empty(model.n_states)
    loop = _numba_loop(model.module.rhs_inplace)
    loop(y, p, buf, 1)
    calls = _calibrate(lambda k: loop(y, p, buf, k), target)

    def run_numba():
        best = math.inf
        for _ in range(inner):
            start = time.perf_counter()
            loop(y, p, buf, calls)
            best = min(best, (time.perf_counter() - start) / calls)
        return {"wall_s": best, "status": "success"}

    out.append(Pathway("floor:numba", "floor", "numba rhs_inplace in a jitted loop", 0.0, run_numba))
    return out


def floor_record(floors: list[Pathway], engines: list[dict]) -> dict:
    """ns per call (best of the rounds) and, per engine, floor = n_rhs x ns and wall / floor."""
    out: dict = {"c_flags": "-std=c99 -O2"}
    for pw in floors:
        out[pw.key.split(":")[1] + "_rhs_loop"] = {"what": pw.name, "runs_ns": [round(1e9 * t, 2) for t in pw.runs_s],
                                                   "min_ns": round(1e9 * min(pw.runs_s), 2) if pw.runs_s else None}
    per_call = next((min(pw.runs_s) for pw in floors if pw.key == "floor:c" and pw.runs_s), None)
    out["basis"] = "C" if per_call else "numba"
    if per_call is None:
        per_call = next((min(pw.runs_s) for pw in floors if pw.runs_s), None)
    out["seconds_per_call"] = per_call
    out["floor_s"], out["ratio"] = {}, {}
    for rec in engines:
        if per_call and rec.get("n_rhs") and rec.get("wall_s"):
            out["floor_s"][rec["key"]] = round(rec["n_rhs"] * per_call, 6)
            out["ratio"][rec["key"]] = round(rec["wall_s"] / (rec["n_rhs"] * per_call), 3)
    return out


def paired_floor(engines: list[Pathway], probe: Callable[[float], float], rounds: int) -> dict:
    """wall / floor per round, the floor timed by a burst of C rhs calls just before each integration.

    On a shared machine the best-of-N wall time and the best-of-N ns per call may come from moments
    of different load; a ratio taken from two measurements seconds apart mostly cancels the load, so
    its median is the robust figure (the best-of ratio is kept beside it)."""
    out = {}
    for _ in range(max(1, rounds)):
        for pw in engines:
            per_call = probe(min(max(min(pw.runs_s), 0.005), 0.05))
            run = pw.run()
            if run.get("status") == "success" and run.get("n_rhs"):
                out.setdefault(pw.key, []).append(run["wall_s"] / (run["n_rhs"] * per_call))
    return {key: {"ratios": [round(v, 3) for v in values], "median": round(float(np.median(values)), 3)}
            for key, values in out.items()}


# ----------------------------------------------------------------------------------------- many

def many(model, problem: Problem, n: int = MANY_N, threads=(1, 2), repeats: int = 3, engine: str | None = None,
         spread: float = 0.5) -> dict:
    """simulate_many over n trajectories (phi_1(0) = problem's +- spread) with each thread count.

    cpu_s (the process' CPU time over the call) beside wall_s shows whether the cores were free: on a
    loaded machine 2 threads get less than two cores and the speed-up says more about the load."""
    from ..analysis.simulate import simulate_many

    p, y = problem.vectors(model)
    Y0 = np.repeat(y[None, :], n, axis=0)
    i1 = model.index(model.leaves[0])
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
                before = _cpu()
                ens = simulate_many(model, p[None, :], Y0, t_end=problem.t_end, rtol=problem.rtol,
                                    atol=problem.atol, engine=engine, threads=k)
                cpu[k].append(_cpu() - before)
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


def _cpu() -> float:
    """CPU seconds of this process, all threads (with wall time: were the cores really free?)."""
    import resource

    use = resource.getrusage(resource.RUSAGE_SELF)
    return use.ru_utime + use.ru_stime


# A control for the thread speed-up: independent busy loops (no memory traffic, no shared state) on
# OpenMP threads, built with the engines' flags.  Its speed-up is what the machine gives two threads
# at that moment; on a shared machine whose other core is busy it is near 1, whatever the engine does.
_OMP_CONTROL = r"""
#include <stdio.h>
#include <stdlib.h>
#include <omp.h>
int main(int argc, char **argv)
{
    int threads = atoi(argv[1]), tasks = atoi(argv[2]);
    long work = atol(argv[3]);
    double sum = 0.0, t0 = omp_get_wtime();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+:sum)
    for (int i = 0; i < tasks; ++i) {
        double x = i;
        for (long k = 0; k < work; ++k) x = x * 1.0000001 + 1e-9;
        sum += x;
    }
    printf("%.9f %g\n", omp_get_wtime() - t0, sum);
    return 0;
}
"""


class ParallelControl:
    """Builds the control once; run(threads) returns its wall seconds (about `seconds` on one core)."""

    def __init__(self, folder: Path, tasks: int = 64, seconds: float = 0.3):
        cc = shutil.which("gcc") or shutil.which("cc")
        if not cc:
            raise RuntimeError("no C compiler")
        src = folder / "omp_control.c"
        src.write_text(_OMP_CONTROL)
        self.exe = folder / "omp_control"
        subprocess.run([cc, "-O2", "-fopenmp", str(src), "-o", str(self.exe)], check=True, capture_output=True)
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


# ------------------------------------------------------------------------------------- symmetry

def symmetry_record(model, y_end) -> dict:
    """Are the balls' angles and rates bitwise equal, and is the end state the thesis' 2-?"""
    y = np.asarray(y_end, float)
    angles = [model.index(name) for name in model.leaves]
    rates = [model.index(name + "_dot") for name in model.leaves]
    equal = bool(all(y[i] == y[angles[0]] for i in angles) and all(y[i] == y[rates[0]] for i in rates))
    ix, iy = model.amplitude_indices[:2]
    phis = [float(y[i]) for i in angles]
    spread = float(max(phis) - min(phis))
    phi = float(np.mean(phis))
    two_minus = (abs(y[ix] - THESIS_2MINUS["x"]) <= THESIS_2MINUS_TOL
                 and abs(y[iy] - THESIS_2MINUS["y"]) <= THESIS_2MINUS_TOL
                 and abs(phi - THESIS_2MINUS["phi"]) <= THESIS_2MINUS_TOL)
    return {"bitwise_equal": equal, "angle_spread": spread, "x": float(y[ix]), "y": float(y[iy]), "phi": phis,
            "ends_at_2minus": bool(two_minus)}


def rhs_symmetry(model, fn, samples: int = 200, seed: int = 1) -> float:
    """Fraction of random ball-symmetric states (all balls at one angle and rate) at which fn(y) gives
    every ball bitwise the same derivatives: 1.0 for a ball-invariant evaluation order."""
    rng = np.random.default_rng(seed)
    angles = [model.index(name) for name in model.leaves]
    rates = [model.index(name + "_dot") for name in model.leaves]
    same = 0
    for _ in range(samples):
        y = rng.uniform(-0.1, 0.1, model.n_states)
        y[angles] = rng.uniform(-math.pi, math.pi)
        y[rates] = rng.uniform(-1.0, 1.0)
        f = np.asarray(fn(y), float)
        same += all(f[i] == f[angles[0]] for i in angles) and all(f[i] == f[rates[0]] for i in rates)
    return same / samples


# -------------------------------------------------------------------------------------- peers

def peer_pathways(model, problem: Problem, tols, setup: dict, progress=None) -> list[Pathway]:
    """JiTCODE dop853 and heyoka at each tolerance; `setup` receives their build records."""
    from . import peers as bench_peers

    p, y = problem.vectors(model)
    pathways = []
    ratio = problem.atol / problem.rtol
    for name, cls in bench_peers.PEERS.items():
        try:
            peer = cls(model.module)
        except bench_peers.PeerUnavailable as exc:
            setup[name] = {"skipped": str(exc)}
            continue
        except Exception as exc:  # a peer that fails to build is recorded, not fatal to the benchmark
            setup[name] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        rec = {"translate_s": round(peer.translate_s, 4),
               "equations_max_relative_difference": bench_peers.check_equations(peer, model.module, p)}
        if name == "jitcode":
            rec["compile_s"] = round(peer.compile_s, 3)
            rec["backend"] = "dop853 (scipy.integrate.ode, Hairer's Fortran DOP853; a Python call per rhs evaluation)"
            for tol in tols:
                pathways.append(Pathway(f"jitcode@{tol:g}", "peer", "jitcode", tol,
                                        _jitcode_run(peer, y, p, problem.t_end, tol, tol * ratio)))
        else:
            rec["method"] = "adaptive Taylor (LLVM), tol = relative and absolute tolerance"
            rec["compile_s"] = {}
            for tol in tols:
                peer.integrator(tol, y, p)  # compile now, outside the timings
                rec["compile_s"][f"{tol:g}"] = round(peer.compile_s[tol], 3)
                pathways.append(Pathway(f"heyoka@{tol:g}", "peer", "heyoka", tol,
                                        _heyoka_run(peer, y, p, problem.t_end, tol)))
        rec["_peer"] = peer
        setup[name] = rec
        if progress:
            progress(f"peer {name}: setup {rec.get('compile_s')} s, equations differ by "
                     f"{rec['equations_max_relative_difference']:.1e}")
    return pathways


def _jitcode_run(peer, y, p, t_end, rtol, atol):
    counted = {}

    def run():
        out = peer.run(y, p, t_end, rtol, atol)
        if "n_rhs" not in counted:
            counted["n_rhs"] = peer.count_rhs(y, p, t_end, rtol, atol)
        out["n_rhs"] = counted["n_rhs"]
        return out

    return run


def _heyoka_run(peer, y, p, t_end, tol):
    return lambda: peer.run(y, p, t_end, tol)


def _peer_symmetry(setup: dict, model, problem: Problem) -> dict:
    out = {}
    p, _ = problem.vectors(model)
    y = model.state(symmetric_y0(model))
    for name in ("jitcode", "heyoka"):
        peer = setup.get(name, {}).get("_peer")
        if peer is None:
            continue
        res = peer.run(y, p, problem.t_end, problem.rtol, problem.atol) if name == "jitcode" else \
            peer.run(y, p, problem.t_end, problem.rtol)
        out[f"{name}@{problem.rtol:g}"] = symmetry_record(model, res["y_end"])
    return out


# ------------------------------------------------------------------------------------- targets

def _target(name: str, goal: str, ratio: float | None, need: float, detail: str) -> dict:
    passed = None if ratio is None else bool(ratio >= need)
    return {"target": name, "goal": goal, "measured_ratio": None if ratio is None else round(ratio, 3),
            "required_ratio": need, "passed": passed,
            "by": None if ratio is None else round(ratio / need, 3), "detail": detail}


def evaluate_targets(result: dict) -> list[dict]:
    """The issue's targets; measured_ratio >= required_ratio passes, `by` = measured / required."""
    default = result["default_engine"]
    eng = {r["key"]: r for r in result["engines"]}
    d = eng.get(default, {})
    t0, e0 = d.get("wall_s"), d.get("error")
    out = []
    equal = result.get("equal_error", {})
    peers = {k: v for k, v in equal.get("peers", {}).items() if v}
    if t0 and peers:
        fastest = min(peers, key=lambda k: peers[k]["time_s"])
        out.append(_target("default engine vs the fastest peer at equal error",
                           "peer time / default time >= 1", peers[fastest]["time_s"] / t0, 1.0,
                           f"{default} {1e3 * t0:.2f} ms at error {e0:.2e}; fastest peer {fastest} "
                           f"{1e3 * peers[fastest]['time_s']:.2f} ms at that error ({peers[fastest]['how']})"))
    else:
        out.append(_target("default engine vs the fastest peer at equal error", "peer time / default time >= 1",
                           None, 1.0, "no peer measured"))
    if t0 and "jitcode" in peers:
        same = next((r for r in result["peers"]["runs"] if r["key"] == f"jitcode@{result['problem']['rtol']:g}"), None)
        extra = f"; at the same rtol: {same['wall_s'] / t0:.2f}x" if same and same.get("wall_s") else ""
        out.append(_target("default engine vs JiTCODE dop853", "JiTCODE time / default time >= 4",
                           peers["jitcode"]["time_s"] / t0, 4.0,
                           f"at equal error {peers['jitcode']['how']}{extra}"))
    else:
        out.append(_target("default engine vs JiTCODE dop853", "JiTCODE time / default time >= 4", None, 4.0,
                           "JiTCODE not measured"))
    floor = result.get("floor", {})
    paired = {k: v["median"] for k, v in floor.get("paired", {}).items() if k.startswith(RK_PREFIXES)}
    ratios = floor.get("ratio", {})
    nan = float("nan")
    if paired:
        best = min(paired, key=paired.get)
        out.append(_target("a Runge-Kutta engine within 1.5x of its floor", "1.5 / (wall / floor) >= 1",
                           1.5 / paired[best], 1.0,
                           f"best {best}: {paired[best]:.2f}x its floor (median of paired rounds; best-of "
                           f"ratio {ratios.get(best, nan):.2f}x); default {default}: "
                           f"{paired.get(default, nan):.2f}x (best-of {ratios.get(default, nan):.2f}x)"))
    else:
        out.append(_target("a Runge-Kutta engine within 1.5x of its floor", "1.5 / (wall / floor) >= 1", None, 1.0,
                           "no floor measured"))
    many_ = result.get("many", {})
    speed = many_.get("speedup", {}).get("2")
    control = many_.get("control", {}).get("speedup", {}).get("2")
    out.append(_target("many trajectories: second core", "wall(1 thread) / wall(2 threads) >= 1.7", speed, 1.7,
                       f"{many_.get('n_trajectories')} trajectories of problem {result['problem']['label']}"
                       + (f"; the parallel control got {control:.2f}x at the same moments" if control else "")))
    return out


# ----------------------------------------------------------------------------------------- run

def _versions() -> dict:
    import importlib

    out = {}
    for name in ("CyRK", "scipy", "numpy", "numba", "matplotlib"):
        try:
            out[name] = importlib.import_module(name).__version__
        except ImportError:
            out[name] = None
    sundials = Path("/usr/include/sundials/sundials_config.h")
    if sundials.is_file():
        for line in sundials.read_text().splitlines():
            if "SUNDIALS_VERSION " in line:
                out["sundials"] = line.split()[-1].strip('"')
    from .peers import peer_versions

    out.update(peer_versions())
    return out


def _cold_build(model, engine) -> float | None:
    """Seconds to compile a compiled engine's library for the model from scratch (a scratch cache)."""
    from ..analysis.engines import compiled

    if not hasattr(engine, "driver"):
        return None
    old = os.environ.get("ADBGEN_CACHE")
    with tempfile.TemporaryDirectory(prefix="adbgen-cold-") as tmp:
        os.environ["ADBGEN_CACHE"] = tmp
        try:
            start = time.perf_counter()
            compiled.build(model, engine.driver, engine.libs)
            return round(time.perf_counter() - start, 3)
        except Exception:
            return None
        finally:
            if old is None:
                os.environ.pop("ADBGEN_CACHE", None)
            else:
                os.environ["ADBGEN_CACHE"] = old


def _load() -> list | None:
    return [round(v, 2) for v in os.getloadavg()] if hasattr(os, "getloadavg") else None


NOTES = (
    'wall_s: best of the repeats (runs_s: all of them), the integration alone (no import, build or '
    "compilation; peers' setup in peers.setup, the default engine's library build from scratch in "
    "default_engine_cold_build_s: later runs load it from adbgen's cache). Repeats run round-robin "
    'over the pathways; a pathway slower than slow_s on its first run runs once. error: largest '
    'absolute difference of the final state from the reference (compiled Verner 8(7) at rtol 1e-13, '
    'atol 1e-15), whose own error is bounded by reference.check_difference (SciPy DOP853 at the same '
    "tolerances). floor: the engine's rhs evaluations times the best ns per call of the generated C "
    'rhs in a C loop (gcc -O2, the flags the engines are built with); floor.ratio = wall / floor. '
    "equal_error: each peer's time at the default engine's error, interpolated log-log between its "
    'runs at the sweep tolerances (heyoka: tol; JiTCODE and the default engine: rtol, atol = rtol / '
    "100). symmetry.runs: from phi(0) = (pi, pi, pi); bitwise_equal = every ball's angle and rate "
    "identical at t_end; ends_at_2minus = within 5e-4 of the thesis' printed 2- state. "
    'symmetry.rhs_symmetric_fraction: share of 200 random ball-symmetric states at which the rhs '
    'gives every ball bitwise the same derivatives (heyoka: its compiled function of the same '
    'expressions, not its Taylor recursions). many.threads.*.cpu_s: CPU time of the process during '
    'each run (cpu_s well below threads x wall_s: the cores were busy with other work); many.control:'
    ' the same speed-up for independent busy loops on OpenMP threads, measured just before each run: '
    "what the machine could give at that moment. heyoka's compile_s is cold (its memory and disk "
    'caches bypassed). The machine is a shared 2-core VM (load averages recorded): compare ratios '
    'within this run.'
)


def _engine_record(pw: Pathway, engine) -> dict:
    rec = pw.record()
    if rec.get("wall_s") and rec.get("n_rhs"):
        rec["ns_per_rhs"] = round(1e9 * rec["wall_s"] / rec["n_rhs"], 1)
    if engine is not None:
        rec["description"] = engine.description
        rec["symmetric_declared"] = bool(engine.symmetric)
    return rec


def equal_error(default: Pathway, sweep: list[Pathway], peers: list[Pathway]) -> dict:
    """(tol, wall, error) curves of the default engine and each peer, and each peer's time at the
    default engine's error (`time_at_error`)."""
    by_name: dict[str, list] = {}
    for pw in [default] + sweep + peers:
        by_name.setdefault(pw.name, []).append(pw)
    curves = {name: [{"tol": pw.tol, "wall_s": pw.record()["wall_s"], "error": pw.last.get("error")}
                     for pw in sorted(pws, key=lambda q: -q.tol)] for name, pws in by_name.items()}
    e0 = default.last.get("error")
    out = {"default_error": e0, "default_wall_s": default.record()["wall_s"], "curves": curves, "peers": {}}
    for name in sorted({pw.name for pw in peers}):
        out["peers"][name] = time_at_error([(c["error"], c["wall_s"]) for c in curves[name]], e0)
    return out


def bench_simulate(problem: Problem = PROBLEM_A, *, repeats: int = DEFAULT_REPEATS, engines=None,
                   peers: bool = True, sweep_tols=SWEEP_TOLS, many_n: int = MANY_N, many_repeats: int = 5,
                   slow_s: float = SLOW_S, floor_target: float = 0.01, baseline: bool = True,
                   progress=None) -> dict:
    """Run the whole benchmark; returns the JSON-ready result (see the module docstring)."""
    from ..analysis.engines import DEFAULT, ENGINES
    from ..analysis.loading import load_model
    from .codegen import machine

    say = progress or (lambda line: None)
    started = time.perf_counter()
    mach = machine()
    mach["load_average_at_start"] = _load()
    model = load_model(problem.model)
    p, y = problem.vectors(model)
    names = list(engines) if engines else list(ENGINES)
    if DEFAULT not in names:
        names.insert(0, DEFAULT)
    result: dict = {"benchmark": "simulate", "date": datetime.datetime.now(datetime.timezone.utc).isoformat(
        timespec="seconds"), "machine": mach, "versions": _versions(), "notes": NOTES,
        "problem": problem.to_json(), "default_engine": DEFAULT,
        "settings": {"repeats": repeats, "slow_s": slow_s, "sweep_tols": list(sweep_tols), "many_n": many_n,
                     "many_repeats": many_repeats, "engines": names, "peers": peers, "baseline": baseline}}

    # build every compiled engine once (cached libraries, numba) outside the timings
    short = Problem(problem.label, problem.model, problem.params, problem.y0, min(1.0, problem.t_end),
                    problem.rtol, problem.atol)
    warm = {}
    for name in names:
        start = time.perf_counter()
        try:
            engine_pathway(model, short, name).run()
            warm[name] = round(time.perf_counter() - start, 3)
        except Exception as exc:
            warm[name] = f"error: {exc}"
    result["engine_setup_s"] = warm
    result["default_engine_cold_build_s"] = _cold_build(model, ENGINES[DEFAULT])
    say(f"engines built/loaded: {warm}; {DEFAULT} cold build {result['default_engine_cold_build_s']} s")

    ref = reference(model, problem)
    say(f"reference: {ref['method']}; check {ref['check_seconds']} s, difference {ref['check_difference']:.2e}")

    pathways = [engine_pathway(model, problem, name) for name in names]
    sweep = [engine_pathway(model, problem, DEFAULT, rtol=tol, atol=tol * problem.atol / problem.rtol,
                            key=f"{DEFAULT}@{tol:g}") for tol in sweep_tols if tol != problem.rtol]
    setup: dict = {}
    peer_paths = peer_pathways(model, problem, sweep_tols, setup, progress=say) if peers else []
    baselines = baseline_pathways(model, problem) if baseline else []
    y_ref = ref["y_end"]
    with tempfile.TemporaryDirectory(prefix="adbgen-floor-") as tmp:
        floors = floor_pathways(model, y_ref, p, Path(tmp), target=floor_target)
        result["load_average_before_timing"] = _load()
        measure(pathways + baselines + sweep + peer_paths + floors, repeats, slow_s, progress=say)
        probe = next((pw.probe for pw in floors if pw.probe is not None), None)
        rk = [pw for pw in pathways if pw.name.startswith(RK_PREFIXES) and pw.runs_s
              and min(pw.runs_s) < PAIRED_MAX_S and pw.last.get("status") == "success"]
        paired = paired_floor(rk, probe, repeats) if probe is not None else {}
    result["load_average_after_timing"] = _load()

    for pw in pathways + baselines + sweep + peer_paths:
        pw.last["error"] = error(pw.last.get("y_end"), y_ref)
    result["reference"] = {**{k: v for k, v in ref.items() if k != "y_end"},
                           "y_end": dict(zip(model.state_names, map(float, y_ref)))}
    errors = [pw.last["error"] for pw in pathways + baselines + sweep + peer_paths if pw.last.get("error")]
    smallest = min(errors) if errors else None
    check = ref["check_difference"]
    result["reference"]["smallest_error_measured"] = smallest
    result["reference"]["converged"] = bool(check is not None and (smallest is None or check <= 0.01 * smallest))
    result["engines"] = [_engine_record(pw, ENGINES.get(pw.name)) for pw in pathways]
    default_pw = next(pw for pw in pathways if pw.name == DEFAULT)
    result["equal_error"] = equal_error(default_pw, sweep, peer_paths)
    result["peers"] = {"setup": {k: {kk: vv for kk, vv in v.items() if kk != "_peer"} if isinstance(v, dict) else v
                                 for k, v in setup.items()},
                       "runs": [pw.record() for pw in peer_paths]}
    result["default_sweep"] = [pw.record() for pw in sweep]
    result["baselines"] = [pw.record() for pw in baselines]

    floor = result["floor"] = floor_record(floors, result["engines"])
    floor["paired"] = paired
    say(f"floor: {1e9 * (floor['seconds_per_call'] or math.nan):.1f} ns per call ({floor['basis']}); "
        f"{DEFAULT} at {floor['ratio'].get(DEFAULT)}x its floor")

    # exchange symmetry from (pi, pi, pi)
    sym = {}
    for pw in pathways:
        if pw.runs_s and pw.runs_s[0] <= SYMMETRY_MAX_S and pw.last.get("status") == "success":
            out = engine_pathway(model, problem, pw.name, y0=symmetric_y0(model)).run()
            sym[pw.name] = symmetry_record(model, out["y_end"])
    if peers:
        sym.update(_peer_symmetry(setup, model, problem))
    rhs_sym = {"generated numba rhs": rhs_symmetry(model, lambda yy: model.module.rhs(0.0, yy, p))}
    for name, rec in setup.items():
        if isinstance(rec, dict) and "_peer" in rec:
            rhs_sym[name] = rhs_symmetry(model, lambda yy, peer=rec["_peer"]: peer.rhs(yy, p))
    result["symmetry"] = {"runs": sym, "rhs_symmetric_fraction": rhs_sym}

    # many trajectories
    result["load_average_before_many"] = _load()
    result["many"] = many(model, problem, many_n, repeats=many_repeats) if many_n else {}
    say(f"many: {result['many'].get('threads')} speed-up {result['many'].get('speedup')}")
    result["machine"]["load_average_at_end"] = _load()
    result["targets"] = evaluate_targets(result)
    result["seconds"] = round(time.perf_counter() - started, 1)
    return _jsonable(result)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


# --------------------------------------------------------------------------------------- chart

def chart(result: dict, path: str | Path) -> Path:
    """Bar chart of the integration wall time per pathway (log scale), the default's floor marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    default = result["default_engine"]
    rows = [(r["key"], r["wall_s"], r.get("error"), "default" if r["key"] == default else
             ("scipy" if r["key"].startswith("scipy-") else "compiled")) for r in result["engines"] if r.get("wall_s")]
    rtol = result["problem"]["rtol"]
    rows += [(r["key"].split(":")[1], r["wall_s"], r.get("error"), "scipy") for r in result.get("baselines", [])
             if r.get("wall_s")]
    setup = result.get("peers", {}).get("setup", {})
    for r in result.get("peers", {}).get("runs", []):
        if r.get("wall_s") and (r["tol"] == rtol or r["name"] == "heyoka" and r["tol"] in (1e-8, 1e-9)):
            compile_s = setup.get(r["name"], {}).get("compile_s")
            if isinstance(compile_s, dict):
                compile_s = compile_s.get(f"{r['tol']:g}")
            label = r["key"] + (f" (+{compile_s:.2g} s setup)" if compile_s is not None else "")
            rows.append((label, r["wall_s"], r.get("error"), "peer"))
    rows.sort(key=lambda row: row[1])
    colours = {"default": "#d62728", "compiled": "#1f77b4", "scipy": "#7f7f7f", "peer": "#2ca02c"}
    fig, ax = plt.subplots(figsize=(9, 0.32 * len(rows) + 1.8))
    ypos = np.arange(len(rows))
    ax.barh(ypos, [1e3 * r[1] for r in rows], color=[colours[r[3]] for r in rows])
    for k, (_, wall, err, _) in enumerate(rows):
        ax.text(1e3 * wall * 1.08, k, f"{1e3 * wall:.3g} ms" + (f"  (err {err:.1e})" if err else ""),
                va="center", fontsize=7)
    ax.set_yticks(ypos, [r[0] for r in rows], fontsize=8)
    ax.set_xscale("log")
    floor = result.get("floor", {}).get("floor_s", {}).get(default)
    lo = min([r[1] for r in rows] + ([floor] if floor else []))
    ax.set_xlim(1e3 * lo / 2, 1e3 * max(r[1] for r in rows) * 8)
    ax.set_ylim(-1.3, len(rows) - 0.4)
    if floor:
        ax.axvline(1e3 * floor, color=colours["default"], ls="--", lw=1)
        ax.text(1e3 * floor * 1.05, -1.0, f"floor of {default}: {1e3 * floor:.3g} ms (evaluations x C ns per call)",
                color=colours["default"], fontsize=7, va="center")
    p = result["problem"]
    ax.set_xlabel("wall time of the integration [ms] (best of the repeats, log scale)")
    load = result.get("load_average_before_timing") or [None]
    when = f"{result.get('date', '')[:16].replace('T', ' ')} UTC" + (f", load average {load[0]:.1f} on "
                                                                       f"{result['machine'].get('cpus')} cores"
                                                                       if load[0] is not None else "")
    ax.set_title(f"Problem {p['label']}: {p['model']}, t in [0, {p['t_end']:g}], rtol {p['rtol']:g}, "
                 f"atol {p['atol']:g}\n{when}\nred: default engine, blue: compiled engines, grey: solve_ivp, "
                 "green: peers", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def save_figure(fig, path: str | Path, dpi: int = 120) -> Path:
    """Write a matplotlib figure through a temporary file (a failed write leaves the old chart)."""
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    tmp.replace(path)
    return path


def describe_targets(result: dict) -> list[str]:
    lines = []
    for t in result.get("targets", []):
        mark = {True: "PASS", False: "FAIL", None: "n/a "}[t["passed"]]
        ratio = "-" if t["measured_ratio"] is None else f"{t['measured_ratio']:.2f} (need {t['required_ratio']})"
        lines.append(f"{mark} {t['target']}: {ratio}; {t['detail']}")
    return lines


__all__ = ["PROBLEM_A", "ParallelControl", "Pathway", "Problem", "baseline_pathways", "bench_simulate", "chart",
           "describe_targets", "engine_pathway", "equal_error", "error", "evaluate_targets", "floor_pathways",
           "floor_record", "many", "measure", "paired_floor", "reference", "rhs_symmetry", "save_figure",
           "symmetric_y0", "symmetry_record", "time_at_error"]
