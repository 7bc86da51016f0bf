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
  module's rhs statements in their order, `benchmarks.peers`), their setup (translation, compilation)
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

import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from .floor import floor_pathways, floor_record, paired_floor
from .pathways import SLOW_S, Pathway, engine_pathway, error, measure, time_at_error
from .problems import PROBLEM_A, Problem, rhs_symmetry, symmetric_y0, symmetry_record
from .registry import ENGINE_NAMES, NO_PEERS, REPEATS, Benchmark, require_known_engines, require_positive_repeats
from .report import describe_targets, load_average, opening, closing, pyplot, save_figure, target, when, write
from .threads import MANY_N, many

DEFAULT_REPEATS = 7
SWEEP_TOLS = (1e-7, 1e-8, 1e-9, 1e-10)
RK_PREFIXES = ("cyrk-", "arkode-")  # the explicit Runge-Kutta engines (the floor target is theirs)
SYMMETRY_MAX_S = 2.0  # engines slower than this on problem A are not run from (pi, pi, pi) (time)
PAIRED_MAX_S = 0.2  # engines slower than this are left out of the paired floor ratios (time)
REFERENCE_RTOL, REFERENCE_ATOL = 1e-13, 1e-15
REFERENCE_ENGINE = "cyrk-vern8"


# ------------------------------------------------------------------------------------ pathways

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


# ----------------------------------------------------------------------------------- reference

def reference(model, problem: Problem, y0: dict | None = None) -> dict:
    """The final state at tight tolerance by a method other than the default engine's (Verner 8(7),
    compiled), checked by SciPy's DOP853 on the numba rhs (another method and implementation)."""
    from scipy.integrate import solve_ivp

    from adbgen.analysis.simulate import simulate

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
        else:  # heyoka on the generated statements, or on the hand-written form (heyoka-hand)
            rec["method"] = f"{peer.label}: adaptive Taylor (LLVM), tol = relative and absolute tolerance"
            rec["compile_s"] = {}
            for tol in tols:
                peer.integrator(tol, y, p)  # compile now, outside the timings
                rec["compile_s"][f"{tol:g}"] = round(peer.compile_s[tol], 3)
                pathways.append(Pathway(f"{name}@{tol:g}", "peer", name, tol,
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
    for name in ("jitcode", "heyoka", "heyoka-hand"):
        peer = setup.get(name, {}).get("_peer")
        if peer is None:
            continue
        res = peer.run(y, p, problem.t_end, problem.rtol, problem.atol) if name == "jitcode" else \
            peer.run(y, p, problem.t_end, problem.rtol)
        out[f"{name}@{problem.rtol:g}"] = symmetry_record(model, res["y_end"])
    return out


# ------------------------------------------------------------------------------------- targets

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
        out.append(target("default engine vs the fastest peer at equal error",
                           "peer time / default time >= 1", peers[fastest]["time_s"] / t0, 1.0,
                           f"{default} {1e3 * t0:.2f} ms at error {e0:.2e}; fastest peer {fastest} "
                           f"{1e3 * peers[fastest]['time_s']:.2f} ms at that error ({peers[fastest]['how']})"))
    else:
        out.append(target("default engine vs the fastest peer at equal error", "peer time / default time >= 1",
                           None, 1.0, "no peer measured"))
    if t0 and "jitcode" in peers:
        same = next((r for r in result["peers"]["runs"] if r["key"] == f"jitcode@{result['problem']['rtol']:g}"), None)
        extra = f"; at the same rtol: {same['wall_s'] / t0:.2f}x" if same and same.get("wall_s") else ""
        out.append(target("default engine vs JiTCODE dop853", "JiTCODE time / default time >= 4",
                           peers["jitcode"]["time_s"] / t0, 4.0,
                           f"at equal error {peers['jitcode']['how']}{extra}"))
    else:
        out.append(target("default engine vs JiTCODE dop853", "JiTCODE time / default time >= 4", None, 4.0,
                           "JiTCODE not measured"))
    floor = result.get("floor", {})
    paired = {k: v["median"] for k, v in floor.get("paired", {}).items() if k.startswith(RK_PREFIXES)}
    ratios = floor.get("ratio", {})
    nan = float("nan")
    if paired:
        best = min(paired, key=paired.get)
        out.append(target("a Runge-Kutta engine within 1.5x of its floor", "1.5 / (wall / floor) >= 1",
                           1.5 / paired[best], 1.0,
                           f"best {best}: {paired[best]:.2f}x its floor (median of paired rounds; best-of "
                           f"ratio {ratios.get(best, nan):.2f}x); default {default}: "
                           f"{paired.get(default, nan):.2f}x (best-of {ratios.get(default, nan):.2f}x)"))
    else:
        out.append(target("a Runge-Kutta engine within 1.5x of its floor", "1.5 / (wall / floor) >= 1", None, 1.0,
                           "no floor measured"))
    many_ = result.get("many", {})
    speed = many_.get("speedup", {}).get("2")
    control = many_.get("control", {}).get("speedup", {}).get("2")
    out.append(target("many trajectories: second core", "wall(1 thread) / wall(2 threads) >= 1.7", speed, 1.7,
                       f"{many_.get('n_trajectories')} trajectories of problem {result['problem']['label']}"
                       + (f"; the parallel control got {control:.2f}x at the same moments" if control else "")))
    return out


# ----------------------------------------------------------------------------------------- run

def _cold_build(model, engine, rtol: float, atol: float) -> float | None:
    """Seconds to compile a compiled engine's library for the model from scratch (a scratch cache); for
    `auto`, the library of what it picks at (rtol, atol) (a Taylor engine: one library per order)."""
    from adbgen.analysis.engines import compiled, taylor

    order = None
    if hasattr(engine, "picked"):
        engine, _, _, record = engine.picked(rtol, atol, model)
        order = record.get("order")
    if order is None and not hasattr(engine, "driver"):
        return None
    old = os.environ.get("ADBGEN_CACHE")
    with tempfile.TemporaryDirectory(prefix="adbgen-cold-") as tmp:
        os.environ["ADBGEN_CACHE"] = tmp
        try:
            start = time.perf_counter()
            if order is not None:
                taylor.build(model, int(order))
            else:
                compiled.build(model, engine.driver, engine.libs)
            return round(time.perf_counter() - start, 3)
        except Exception:
            return None
        finally:
            if old is None:
                os.environ.pop("ADBGEN_CACHE", None)
            else:
                os.environ["ADBGEN_CACHE"] = old


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
    from adbgen.analysis.engines import DEFAULT, ENGINES
    from adbgen.analysis.loading import load_model

    say = progress or (lambda line: None)
    result, started = opening("simulate")
    model = load_model(problem.model)
    p, y = problem.vectors(model)
    names = list(engines) if engines else list(ENGINES)
    if DEFAULT not in names:
        names.insert(0, DEFAULT)
    result.update({"notes": NOTES, "problem": problem.to_json(), "default_engine": DEFAULT,
                   "settings": {"repeats": repeats, "slow_s": slow_s, "sweep_tols": list(sweep_tols), "many_n": many_n,
                                "many_repeats": many_repeats, "engines": names, "peers": peers, "baseline": baseline}})

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
    result["default_engine_cold_build_s"] = _cold_build(model, ENGINES[DEFAULT], problem.rtol, problem.atol)
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
        result["load_average_before_timing"] = load_average()
        measure(pathways + baselines + sweep + peer_paths + floors, repeats, slow_s, progress=say)
        probe = next((pw.probe for pw in floors if pw.probe is not None), None)
        rk = [pw for pw in pathways if pw.name.startswith(RK_PREFIXES) and pw.runs_s
              and min(pw.runs_s) < PAIRED_MAX_S and pw.last.get("status") == "success"]
        paired = paired_floor(rk, probe, repeats) if probe is not None else {}
    result["load_average_after_timing"] = load_average()

    for pw in pathways + baselines + sweep + peer_paths:
        pw.last["error"] = error(pw.last.get("y_end"), y_ref)
    result["reference"] = {**{k: v for k, v in ref.items() if k != "y_end"},
                           "y_end": dict(zip(model.state_names, map(float, y_ref)))}
    errors = [pw.last["error"] for pw in pathways + baselines + sweep + peer_paths if pw.last.get("error")]
    smallest = min(errors) if errors else None
    check = ref["check_difference"]
    result["reference"]["smallest_error_measured"] = smallest
    # an error within 100x the reference's own (its check difference) is not resolved by it: such runs are
    # named (below_resolution: their error is only "at most resolution"), and the reference is converged
    # when it resolves every other error, not when it is 100x better than runs as accurate as itself
    resolution = None if check is None else 100 * check
    below = sorted({pw.name for pw in pathways + baselines + sweep + peer_paths
                    if pw.last.get("error") and resolution is not None and pw.last["error"] <= resolution})
    resolved = [e for e in errors if resolution is None or e > resolution]
    result["reference"]["resolution"] = resolution
    result["reference"]["below_resolution"] = below
    result["reference"]["converged"] = bool(check is not None and (not resolved or check <= 0.01 * min(resolved)))
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
    result["load_average_before_many"] = load_average()
    result["many"] = many(model, problem, many_n, repeats=many_repeats) if many_n else {}
    say(f"many: {result['many'].get('threads')} speed-up {result['many'].get('speedup')}")
    result["targets"] = evaluate_targets(result)
    return closing(result, started)


# --------------------------------------------------------------------------------------- chart

def chart(result: dict, path: str | Path) -> Path:
    """Bar chart of the integration wall time per pathway (log scale), the default's floor marked."""
    plt = pyplot()

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
    date = f"{when(result)} UTC" + (f", load average {load[0]:.1f} on {result['machine'].get('cpus')} cores"
                                    if load[0] is not None else "")
    ax.set_title(f"Problem {p['label']}: {p['model']}, t in [0, {p['t_end']:g}], rtol {p['rtol']:g}, "
                 f"atol {p['atol']:g}\n{date}\nred: default engine, blue: compiled engines, grey: solve_ivp, "
                 "green: peers", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def run(args, out: str) -> int:
    require_positive_repeats(args)
    require_known_engines(args)
    result = bench_simulate(repeats=args.repeats or DEFAULT_REPEATS, engines=args.engines, peers=not args.no_peers,
                            progress=lambda line: print(line, flush=True))
    path = write(result, out)
    png = chart(result, Path(out).with_suffix(".png"))
    for line in describe_targets(result):
        print(line)
    print(f"wrote {path} and {png} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("simulate", run, (REPEATS.but("best of N (default 7)"), ENGINE_NAMES, NO_PEERS))


__all__ = ["BENCHMARK", "DEFAULT_REPEATS", "baseline_pathways", "bench_simulate", "chart", "equal_error",
           "evaluate_targets", "peer_pathways", "reference"]
