"""Transients of a design (issue 39 items 3-4): t_dec at the operating point as an objective, and the
verification run of the chosen design at the corners of the operating box.

    operating_point(problem)           the base speed (if inside its range, else the range's middle), every other
                                       range at its middle, the imbalance at its maximum
    transient(problem, design, point)  one run from one of STARTS: t_dec, r_max, status, settled
    best_by_t_dec(problem, verdicts)   the feasible design with the smallest t_dec at the operating point
    verify(problem, design)            a run at every corner of the box (each range and the imbalance at its ends)
    verify_run_up(problem, design, runs)  the chosen design's run-up (issue 39 item 4) on the run model with a
                                       speed schedule, at the operating point; (None, why) where there is none
    by_t_dec(design)                   the Design's best replaced by the t_dec objective's (CANDIDATES at most)
    by_runs(design, objective, runs)   the same for r_max-run-up (the smallest r_max through the run model's
                                       run-up) and residual (the smallest RESIDUAL_QUANTILE quantile of the
                                       residual imbalance over the starts, stick-slip runs); every run evaluated
                                       by design_runs.evaluate (Dask, progress, the journal in --out)

STARTS: the rotor at rest and the balls at rest, either spread (ball k of n, in state order, at 2 pi k / n) or
bunched (ball k at 0.1 k rad).  Not exactly together: identical balls started at one angle stay together for
ever (the exchange symmetry keeps the set of equal angles invariant), so they can never balance and the run
would say nothing about the balancing state's basin.  Both starts are run in the verification (a locally
stable balancing state need not attract every start); the t_dec objective uses the first.  The run's length
and t_dec's threshold are the analysis layer's defaults (`units.default_t_end`: the thesis' t = 1000 at
Omega = 4 as revolutions; `units.default_threshold`: a tenth of the eccentricity).  A run is `settled` when
r at its end is below the threshold and t_dec is defined; a failed run is said as such, never counted as
settled.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from .design import Design, Problem, Verdict, active_limit, sensitivity
from .design_runs import (RESIDUAL_FORMAT, RESIDUAL_QUANTILE, RESIDUAL_SEED, RESIDUAL_STARTS, Journal, check_runs,
                          evaluate, key_of, residual_counts, residual_quantile, residual_run,
                          residual_starts, rest_start, run_params, run_up, run_up_trace)
from .loading import AnalysisError
from .residual import residual_measure
from .simulate import simulate
from .units import default_t_end, default_threshold

STARTS = ("balls spread at 2 pi k / n", "balls bunched at 0.1 k rad")  # the rotor and every rate at rest
BUNCH = 0.1  # rad between neighbouring balls of the bunched start
START_STATE = "rotor and balls at rest; " + " / ".join(STARTS)
CANDIDATES = 25  # objective t_dec: the feasible designs assessed that are run, evenly through them


def start_state(problem: Problem, which: str = STARTS[0]) -> np.ndarray:
    if which == STARTS[0]:
        return rest_start(problem.model)
    return rest_start(problem.model, BUNCH * np.arange(len(problem.model.role_indices("ball_angle"))))


def operating_point(problem: Problem) -> dict:
    m = problem.model
    speed = m.scales.get("speed")
    out = {}
    for a in problem.box:
        if a.name == problem.eccentricity:
            out[a.name] = a.high
        elif a.name == speed and a.low <= problem.base[m.param_names.index(speed)] <= a.high:
            out[a.name] = float(problem.base[m.param_names.index(speed)])
        else:
            out[a.name] = 0.5 * (a.low + a.high)
    return out


def transient(problem: Problem, design, point: dict, start: str = STARTS[0]) -> dict:
    m = problem.model
    p = problem.params(design, point)
    t_end, _ = default_t_end(m, p)
    threshold, _ = default_threshold(m, p)
    sim = simulate(m, p, start_state(problem, start), t_end=t_end, threshold=threshold, keep_trajectory=False, check=False)
    r_end = float(np.hypot(*[sim.y_end[i] for i in m.amplitude_indices[:2]]))
    ok = sim.status == "success"
    return {"point": {k: float(v) for k, v in point.items()}, "start": start, "status": sim.status, "t_end": float(t_end),
            "threshold": float(threshold), "t_dec": sim.t_dec if ok else None, "r_max": float(sim.r_max) if ok else None,
            "r_end": r_end if ok else None, "settled": bool(ok and sim.t_dec is not None and r_end < threshold)}


def best_by_t_dec(problem: Problem, verdicts: list[Verdict], journal: Journal | None = None, *,
                  workers: int | None = None, progress: bool = False) -> tuple[Verdict | None, list[dict]]:
    """The feasible design inside the varied box with the smallest t_dec at the operating point (among the
    designs given: not optimised between them), and every run."""
    point = operating_point(problem)
    cands = _feasible_inside(problem, verdicts)
    tasks = [(key_of("t_dec", problem.model.source_hash, problem.params(v.design, point).tolist(), STARTS[0]),
              transient, (problem, v.design, point)) for v in cands]
    done, _ = evaluate(tasks, journal or Journal(None), workers=workers, progress=progress, desc="design t_dec")
    runs, best, best_t = [], None, math.inf
    for v, (k, _, _) in zip(cands, tasks):
        run = {"design": dict(zip([a.name for a in problem.varied], v.design)), **done[k]}
        runs.append(run)
        if run["settled"] and run["t_dec"] < best_t:
            best, best_t = v, run["t_dec"]
    return best, runs


def candidates(design: Design) -> list[Verdict]:
    """The feasible designs assessed inside the varied box, CANDIDATES at most, evenly through them."""
    feasible = _feasible_inside(design.problem, design.verdicts)
    if len(feasible) > CANDIDATES:
        feasible = [feasible[round(k)] for k in np.linspace(0, len(feasible) - 1, CANDIDATES)]
    return feasible


def by_runs(design: Design, objective: str, runs, journal: Journal | None = None, *, run_time: float | None = None,
            workers: int | None = None, progress: bool = False, verdicts: list[Verdict] | None = None,
            run_set: dict | None = None, starts: int = RESIDUAL_STARTS, quantile: float = RESIDUAL_QUANTILE,
            target: float | None = None, measure: str | None = None) -> Design:
    """The best design by `objective` among `verdicts` (default: `candidates`), each run on the run model
    `runs` at the operating point with the parameters design_runs.run_params maps (`run_set`: the run model's own
    fixed values): r_max-run-up the smallest
    r_max through the run-up from the spread start (design_runs.run_up, `run_time` after the schedule);
    residual the smallest `quantile` quantile of the residual imbalance over `starts` of design_runs.residual_starts
    (stick-slip, `run_time` long, default units.default_t_end), at most `target` where one is given (none below it:
    no best design, infeasible), its summary in `design.residual`; the residual is the run model's measure
    `measure` at t_end (None: the one the run model names, residual.residual_measure).  A design whose run
    failed, or ended with a ball still slipping (undecided), is never chosen: its quantile is not computed."""
    problem = design.problem
    check_runs(objective, runs, measure)
    measure = residual_measure(runs, measure) if objective == "residual" else None
    point = operating_point(problem)
    cands = candidates(design) if verdicts is None else verdicts
    starts = residual_starts(runs, starts) if objective == "residual" else [rest_start(runs)]
    rows, tasks = [], []
    for v in cands:
        q, taken = run_params(problem, runs, v.design, point, run_set)
        t_after = run_time
        if objective == "residual" and t_after is None:
            t_after = default_t_end(runs, q)[0]
        keys = []
        for y0 in starts:
            # the residual's record says at_rest since RESIDUAL_FORMAT 2: older journal lines are not read; a
            # measure other than r is in the key (lines of r, written before the measure was named, are read back)
            k = key_of(objective, runs.source_hash, q.tolist(), y0.tolist(), t_after,
                       *((RESIDUAL_FORMAT,) if objective == "residual" else ()),
                       *((measure,) if measure not in (None, "r") else ()))
            fn, args = ((run_up, (runs, q, y0, t_after)) if objective == "r_max-run-up"
                        else (residual_run, (runs, q, y0, t_after, measure)))
            tasks.append((k, fn, args))
            keys.append(k)
        rows.append((v, keys, taken))
    done, _ = evaluate(tasks, journal or Journal(None), workers=workers, progress=progress, desc=f"design {objective}")
    out, best, best_value = [], None, math.inf
    for v, keys, taken in rows:
        results = [done[k] for k in keys]
        if objective == "r_max-run-up":
            value = results[0]["r_max"]
            run = {**results[0], "start": START_STATE.split(";")[0] + ", balls spread"}
        else:
            value = residual_quantile(results, quantile)
            counts = residual_counts(results)
            run = {"residual_quantile": value, "quantile": quantile, "starts": len(results),
                   "residuals": [r["residual"] for r in results], "failed": counts["failed"],
                   "at_rest": counts["at_rest"], "undecided": counts["undecided"],
                   "meets_target": None if target is None or value is None else bool(value <= target)}
            if target is not None and (value is None or value > target):
                value = None  # not chosen: its quantile is above the target, or not decided
        out.append({"design": dict(zip([a.name for a in problem.varied], v.design)), "point": point,
                    "run_model": runs.name, "mapped": taken, **run})
        if value is not None and value < best_value:
            best, best_value = v, value
    design.objective_runs = out
    if objective == "residual":
        design.residual = residual_summary(out, runs, run_set or {}, quantile, target, best_value if best else None,
                                           measure)
    return _choose(design, best)


def residual_summary(rows: list[dict], runs, own: dict, quantile: float, target: float | None,
                     chosen: float | None, measure: str = "r") -> dict:
    """The residual objective's summary (the --json key `residual`): the run model and what it keeps of its own,
    the starts and quantile, the target, the chosen design's quantile, the designs run and how many of their
    runs were at rest, undecided or failed, and why there is no choice (one line) where there is none."""
    from .units import units

    total = {k: sum(r[k] for r in rows) for k in ("at_rest", "undecided", "failed")}
    decided = [r["residual_quantile"] for r in rows if r["residual_quantile"] is not None]
    note = None
    if chosen is None:
        if not rows:
            note = "no feasible design to run"
        elif not decided:
            note = (f"no design has every run at rest: {total['undecided']} run(s) undecided (a ball still slipping at "
                    f"t_end; a longer --run-time may decide them), {total['failed']} failed")
        else:
            note = (f"no design reaches the target {target:.6g}: the smallest {quantile:g} quantile is "
                    f"{min(decided):.6g}")
    return {"run_model": runs.name, "kept": dict(sorted(own.items())), "unit": units(runs).length,
            "starts": rows[0]["starts"] if rows else None, "seed": RESIDUAL_SEED, "quantile": quantile,
            "target": target, "chosen_quantile": chosen, "designs_run": len(rows),
            "designs_decided": len(decided), **total, "note": note, "measure": measure}


def _feasible_inside(problem: Problem, verdicts: list[Verdict]) -> list[Verdict]:
    """The feasible designs inside the varied box, each once, in the order of their values."""
    return sorted({v.design: v for v in verdicts if v.feasible and _inside(problem, v)}.values(), key=lambda v: v.design)


def _choose(design: Design, best: Verdict | None) -> Design:
    """The design's best set to `best`, its active limit and sensitivities recomputed for it."""
    design.best = best
    design.active = active_limit(design.problem, best, design.boundaries)
    design.sensitivity = sensitivity(design.problem, best) if best is not None else []
    return design


def _inside(problem: Problem, v: Verdict) -> bool:
    """The design lies in the varied box (not a finite difference's step beyond a range's end)."""
    return all(a.low <= x <= a.high for a, x in zip(problem.varied, v.design))


def verify(problem: Problem, design, journal: Journal | None = None, *, workers: int | None = None,
           progress: bool = False) -> list[dict]:
    """A run from each of STARTS at every corner of the box (each non-degenerate axis at its low and high end)."""
    axes = [a for a in problem.box if not a.fixed]
    fixed = {a.name: a.low for a in problem.box if a.fixed}
    points = [({**fixed, **dict(zip([a.name for a in axes], ends))}, start)
              for ends in itertools.product(*[(a.low, a.high) for a in axes]) for start in STARTS]
    tasks = [(key_of("verify", problem.model.source_hash, problem.params(design, pt).tolist(), start),
              transient, (problem, design, pt, start)) for pt, start in points]
    done, _ = evaluate(tasks, journal or Journal(None), workers=workers, progress=progress, desc="design verification")
    return [done[k] for k, _, _ in tasks]


def by_t_dec(design: Design, journal: Journal | None = None, *, workers: int | None = None,
             progress: bool = False) -> Design:
    """The best design by t_dec at the operating point among (at most CANDIDATES of) the feasible designs
    assessed inside the varied box; its limit and sensitivities recomputed.  None where no candidate settles within the run."""
    problem = design.problem
    best, design.objective_runs = best_by_t_dec(problem, candidates(design), journal, workers=workers, progress=progress)
    return _choose(design, best)


def verify_run_up(problem: Problem, design, runs, journal: Journal | None = None, *,
                  run_time: float | None = None, run_set: dict | None = None, workers: int | None = None,
                  progress: bool = False) -> tuple[dict | None, str | None]:
    """(the run, None) or (None, why in one line): the chosen design's run-up on the run model `runs` (--runs,
    default the design's own) where its speed law is a schedule (a `t_ramp` parameter; core/speed_schedule.py),
    at the operating point with the parameters design_runs.run_params maps (`run_set`: the run model's own), from
    the rotor at rest and the balls spread, `run_time` after the schedule (design_runs.run_up_trace: r_max, t_dec,
    r at the end, settled, r(t)).  A run model sharing no varied parameter with the design runs no run of it."""
    if "t_ramp" not in runs.param_names:
        return None, (f"no run-up: {runs.name} has no speed schedule (no t_ramp parameter); give --runs a run-up "
                      "model or a scene whose [speed] law is a schedule")
    point = operating_point(problem)
    try:
        q, taken = run_params(problem, runs, design, point, run_set)
    except AnalysisError as exc:
        return None, f"no run-up: {exc}"
    y0 = rest_start(runs)
    k = key_of("verify-run-up", runs.source_hash, q.tolist(), y0.tolist(), run_time)
    done, _ = evaluate([(k, run_up_trace, (runs, q, y0, run_time))], journal or Journal(None), workers=workers,
                       progress=progress, desc="design verification run-up")
    return {"design": dict(zip([a.name for a in problem.varied], design)), "point": point, "run_model": runs.name,
            "mapped": taken, "start": START_STATE.split(";")[0] + ", balls spread", **done[k]}, None
