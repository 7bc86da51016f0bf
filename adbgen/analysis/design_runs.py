"""The runs behind a design's transient objectives (issue 39 items 3 and 5): evaluated on the local Dask
cluster, with progress, and journalled so a killed design resumes where it stopped.  The designs' verdicts
(design.assess) go to the same journal and cluster (design.prefetch, design.scan_lines).

    Journal(folder)                   FOLDER/design-journal.jsonl: one line per finished evaluation (a run, or a
                                      design's verdict), keyed by what it computed (the run model's SOURCE_HASH,
                                      the parameters, the start, the settings; design.verdict_key); a rerun reads
                                      it and skips those evaluations
    evaluate(tasks, journal, ...)     {key: result} for tasks [(key, fn, args)]: the journalled ones read back,
                                      the others run on a local Dask cluster (threads: the compiled engines
                                      release the GIL, as `sweep` does), each journalled as it finishes
    run_params(problem, runs, ...)    the run model's parameters for a design at a box point: mapped by name,
                                      the speed by SCALES["speed"] (the final speed of a run-up), the rest the
                                      run model's own (its speed law, its friction)
    run_up(runs, p, y0)               r_max through a run-up with the run model's speed law (a prescribed
                                      schedule, core/speed_schedule.py: ramp, hold, reduction, recovery): the run
                                      lasts the schedule plus the default run at the final speed
    run_up_trace(runs, p, y0)         the same run with r(t) kept (TRACE_SAMPLES points) for the verification's
                                      figure, r at the end and whether it settled
    residual(runs, p, starts)         the residual imbalance from each start by the stick-slip engine
                                      hybrid-dop853 (engines/hybrid.py): the run model's measure at t_end that
                                      it names its residual (RESIDUAL_MEASURE: r in one plane, A in two) or
                                      --residual-measure's, and its RESIDUAL_QUANTILE quantile

A killed run loses at most the evaluations in flight: each line is written and flushed (os.fsync) when its
evaluation finishes, and a half-written last line (a kill mid-write) is ignored and recomputed.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from pathlib import Path

import numpy as np

from .loading import AnalysisError, Model
from .residual import residual_measure
from .units import default_t_end, default_threshold

JOURNAL = "design-journal.jsonl"
RESIDUAL_STARTS = 16  # starts of the residual objective: rotor at rest, ball angles uniform at random (seeded)
RESIDUAL_QUANTILE = 0.9
RESIDUAL_SEED = 20260
RESIDUAL_FORMAT = 2  # the residual run's record (residual_run): 2 adds at_rest; raise it when the record changes
# a schedule's parameters (core.speed_schedule.NAMES, the names every family gives them) read from the run model
SCHEDULE = ("t_ramp", "t_hold", "depth", "drop_rate", "t_plateau", "recovery_rate")


def key_of(*parts) -> str:
    """A journal key: the sha256 of the parts' JSON (floats by repr: the key changes with any digit)."""
    text = json.dumps(parts, sort_keys=True, default=lambda x: repr(x) if isinstance(x, float) else str(x))
    return hashlib.sha256(text.encode()).hexdigest()[:24]


class Journal:
    """FOLDER/design-journal.jsonl (None: nothing kept, every evaluation run)."""

    def __init__(self, folder: Path | None):
        self.path = None if folder is None else Path(folder) / JOURNAL
        self.done: dict[str, dict] = {}
        if self.path is not None and self.path.is_file():
            text = self.path.read_text()
            if text and not text.endswith("\n"):  # a line cut by a kill: dropped, or the next line would join it
                text = text[: text.rfind("\n") + 1]
                self.path.write_text(text)
            for line in text.splitlines():
                try:
                    row = json.loads(line)
                    self.done[row["key"]] = row["result"]
                except (json.JSONDecodeError, KeyError, TypeError):
                    continue  # a line cut by a kill: its evaluation runs again

    def put(self, key: str, result: dict) -> None:
        self.done[key] = result
        if self.path is None:
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with open(self.path, "a") as f:
            f.write(json.dumps({"key": key, "result": result}) + "\n")
            f.flush()
            os.fsync(f.fileno())


_SESSION: list = []  # the open session's client (session()): evaluate() submits to it instead of starting a cluster


class session:
    """`with session(workers):` one local Dask cluster kept open for every evaluate() inside it (the optimiser's
    evaluations come one after another: starting a cluster for each would cost more than its lines)."""

    def __init__(self, workers: int | None = None):
        self.workers = workers

    def __enter__(self):
        from distributed import Client, LocalCluster

        from .sweep import default_workers

        self.cluster = LocalCluster(n_workers=1, threads_per_worker=self.workers or default_workers(), processes=False,
                                    dashboard_address=":0")
        self.client = Client(self.cluster)
        _SESSION.append(self.client)
        return self

    def __exit__(self, *exc):
        _SESSION.remove(self.client)
        self.client.close()
        self.cluster.close()
        return False


def evaluate(tasks: list, journal: Journal, *, workers: int | None = None, progress: bool = True,
             desc: str = "design", each=None) -> tuple[dict, int]:
    """({key: result}, how many ran now) for tasks [(key, fn, args)]: the journalled read back, the rest on a
    local Dask cluster (one process, a thread per core), each journalled as it finishes; `progress`: the
    project's bar on stderr (adbgen.progress: from two seconds on); `each(key, result)`, when given, is called
    in this thread as each task finishes (a result the journal cannot hold is kept by the caller)."""
    out = {k: journal.done[k] for k, _, _ in tasks if k in journal.done}
    pending = [(k, fn, args) for k, fn, args in tasks if k not in journal.done]
    pending = list({k: (k, fn, args) for k, fn, args in pending}.values())  # a task given twice runs once
    if not pending:
        return out, 0
    from contextlib import nullcontext

    from distributed import as_completed

    from ..progress import bar

    with (nullcontext(None) if _SESSION else session(workers)) as opened, \
            bar(len(pending), desc, progress, unit="run") as update:
        client = _SESSION[-1] if opened is None else opened.client
        futures = {client.submit(fn, *args, pure=False): k for k, fn, args in pending}
        for count, fut in enumerate(as_completed(futures), 1):
            k = futures[fut]
            result = fut.result()
            journal.put(k, result)
            out[k] = result
            if each is not None:
                each(k, result)
            update(count)
    return out, len(pending)


# ---------------------------------------------------------------------------------------- run model

def run_params(problem, runs: Model, design, point: dict, fixed: dict | None = None) -> tuple[np.ndarray, list[str]]:
    """(the run model's parameters, the names it takes from the design problem): each parameter the run model
    shares by name with the design's model takes the design's value at `point`, unless `fixed` gives it; the run
    model's speed (SCALES["speed"]) the design's speed there; every other (speed law, friction) keeps the run
    model's value or takes `fixed`'s ({name: value}: --run-set, and a frictionless twin's friction, which the run
    model keeps).
    AnalysisError when no varied parameter reaches the run model (its runs would not depend on the design)."""
    m = problem.model
    p = problem.params(design, point)
    fixed = fixed or {}
    q = np.array(runs.params(fixed), float)
    taken = []
    for k, name in enumerate(runs.param_names):
        if name in m.param_names and name not in fixed:  # a fixed value is the run model's own (its friction)
            q[k] = p[m.param_names.index(name)]
            taken.append(name)
    speed, own = m.scales.get("speed"), runs.scales.get("speed")
    if speed is not None and own is not None and own not in taken and own not in fixed:
        q[runs.param_names.index(own)] = p[m.param_names.index(speed)]
        taken.append(own)
    varied = {a.name for a in problem.varied} | set(problem.ties)
    if not varied & set(taken) - {own}:
        raise AnalysisError(f"the run model {runs.name} shares none of the varied parameters "
                            f"({', '.join(sorted(varied))}) with {m.name}: its runs would not depend on the design")
    return q, taken


def rest_start(runs: Model, angles=None) -> np.ndarray:
    """The rotor and every rate at rest, the balls at `angles` (default spread at 2 pi k / n)."""
    y = np.zeros(runs.n_states)
    balls = list(runs.role_indices("ball_angle"))
    # spread: (2 pi / n) k, the start the design's transients have used (design_transients.STARTS)
    y[balls] = 2 * np.pi / max(len(balls), 1) * np.arange(len(balls)) if angles is None else angles
    return y


def schedule_time(runs: Model, p: np.ndarray) -> float:
    """The time the run model's speed schedule takes to reach its final speed for good (speed_schedule.law):
    ramp + hold + fall + plateau + recovery, from the parameters the model has (0 for those it lacks)."""
    names = runs.param_names
    v = {n: float(p[names.index(n)]) for n in SCHEDULE if n in names}
    if "t_ramp" not in v:
        raise AnalysisError(f"{runs.name} has no run-up (no t_ramp parameter): r_max-run-up needs a scene whose "
                            "[speed] law is a schedule")
    speed = runs.scales.get("speed")
    omega = float(p[names.index(speed)]) if speed else 0.0
    drop = omega * v.get("depth", 0.0)
    return (v["t_ramp"] + v.get("t_hold", 0.0) + v.get("t_plateau", 0.0)
            + (drop / v["drop_rate"] if drop and v.get("drop_rate") else 0.0)
            + (drop / v["recovery_rate"] if drop and v.get("recovery_rate") else 0.0))


def run_up(runs: Model, p: np.ndarray, y0: np.ndarray, t_after: float | None = None) -> dict:
    """r_max through the run model's run-up from y0: the schedule, then `t_after` (default: the default run at
    the final speed, units.default_t_end); t_dec to a tenth of the eccentricity (units.default_threshold)."""
    from .simulate import simulate

    t_after = default_t_end(runs, p)[0] if t_after is None else t_after
    t_end = schedule_time(runs, p) + t_after
    threshold = default_threshold(runs, p)[0]
    sim = simulate(runs, p, y0, t_end=t_end, threshold=threshold, keep_trajectory=False, check=False)
    ok = sim.status == "success"
    return {"status": sim.status, "t_end": float(t_end), "threshold": float(threshold),
            "r_max": float(sim.r_max) if ok else None, "t_dec": sim.t_dec if ok else None}


TRACE_SAMPLES = 801  # the verification run-up's r(t) kept for its figure (and the journal)


def run_up_trace(runs: Model, p: np.ndarray, y0: np.ndarray, t_after: float | None = None) -> dict:
    """run_up's numbers with the trajectory kept: `schedule_end` (schedule_time, the final speed reached for
    good), r at the end, `settled` (r_end below the threshold and t_dec defined, as design_transients.transient
    says it) and `trace` {t, r} (TRACE_SAMPLES points, for the figure)."""
    from .engines import engine
    from .simulate import simulate

    t_after = default_t_end(runs, p)[0] if t_after is None else t_after
    end = schedule_time(runs, p)
    t_end = end + t_after
    threshold = default_threshold(runs, p)[0]
    sim = simulate(runs, p, y0, t_end=t_end, threshold=threshold, samples=TRACE_SAMPLES, check=False)
    ok = sim.status == "success"
    i, j = runs.amplitude_indices[:2]
    t, r = np.array([]), np.array([])
    if ok and sim.y is not None:
        t, y = sim.t, sim.y
        eng, rtol, atol = engine(sim.engine), sim.rtol, sim.atol
        if hasattr(eng, "picked"):  # the auto engine: the engine (and tolerance) that ran
            eng, rtol, atol, _ = eng.picked(sim.rtol, sim.atol, runs)
        if callable(getattr(eng, "dense", None)):  # an even grid on the continuous solution (the steps alias the spin)
            t = np.linspace(0.0, sim.t[-1], TRACE_SAMPLES)
            y = eng.dense(runs, p, sim.t, sim.y, t, rtol, atol)
        r = np.hypot(y[i], y[j])
    r_end = float(math.hypot(sim.y_end[i], sim.y_end[j])) if ok else None
    return {"status": sim.status, "t_end": float(t_end), "schedule_end": float(end), "threshold": float(threshold),
            "r_max": float(sim.r_max) if ok else None, "t_dec": sim.t_dec if ok else None, "r_end": r_end,
            "settled": bool(ok and sim.t_dec is not None and r_end < threshold),
            "trace": {"t": [float(x) for x in t], "r": [float(x) for x in r]}}


def residual_starts(runs: Model, count: int = RESIDUAL_STARTS, seed: int = RESIDUAL_SEED) -> np.ndarray:
    """`count` starts: the rotor and every rate at rest, each ball's angle uniform in [0, 2 pi) (seeded)."""
    rng = np.random.default_rng(seed)
    balls = len(runs.role_indices("ball_angle"))
    return np.array([rest_start(runs, rng.uniform(0, 2 * np.pi, balls)) for _ in range(count)])


def residual_run(runs: Model, p: np.ndarray, y0: np.ndarray, t_end: float, measure: str = "r") -> dict:
    """One stick-slip run (hybrid-dop853) from y0 to t_end: the residual imbalance, the run model's measure
    `measure` at t_end (analysis.residual.residual_at_end, as the sweep reads it: "r" the rotor's displacement
    where the balls came to rest, or another of its MEASURES, e.g. the one it names, Model.residual_measure),
    each ball's final mode, and `at_rest`: every ball stuck at t_end (the residual is then where the balls
    stopped; analysis.residual's AT_REST)."""
    from .engines import hybrid
    from .residual import residual_at_end

    run = hybrid.run(runs, p, y0, 0.0, t_end, t_eval=np.array([t_end]))
    i, j = runs.amplitude_indices[:2]
    ok = run.status == "success"
    stuck = hybrid.switching(runs).stuck
    value = None
    if ok:
        r = math.hypot(run.y_end[i], run.y_end[j])
        value = float(residual_at_end(runs, measure, np.array([r]), np.array([t_end]), np.array([run.y_end]),
                                      np.array([p]), np.array([False]))[0])
    return {"status": run.status, "t_end": float(t_end), "residual": value, "measure": measure,
            "modes": list(run.modes(len(stuck))), "events": len(run.events),
            "at_rest": bool(ok and all(run.params_end[k] == 1 for k in stuck))}


def residual_counts(results: list[dict]) -> dict:
    """{"at_rest", "undecided" (a ball still slipping at t_end), "failed"} over the starts' runs."""
    failed = sum(r["status"] != "success" for r in results)
    rest = sum(r["status"] == "success" and r.get("at_rest", True) for r in results)
    return {"at_rest": rest, "undecided": len(results) - failed - rest, "failed": failed}


def residual_quantile(results: list[dict], q: float = RESIDUAL_QUANTILE) -> float | None:
    """The q quantile of the residual over the starts; None when a run failed or ended with a ball still slipping
    (undecided): such a run's r is not a residual at rest, and counting it as one would call it balanced."""
    values = [r["residual"] for r in results]
    if not values or any(v is None for v in values) or any(r.get("at_rest") is False for r in results):
        return None
    return float(np.quantile(values, q))


def check_runs(objective: str, runs: Model, measure: str | None = None) -> None:
    """A one-line AnalysisError where the run model lacks what `objective` needs (before any computing); for
    residual also an unknown `measure` (residual.residual_measure)."""
    if objective == "residual" and not has_stick_phase(runs):
        raise AnalysisError(f"--objective residual: {runs.name} has no stick phase (a scene with static_friction "
                            "makes one): no residual imbalance to compute")
    if objective == "residual":
        residual_measure(runs, measure)
    if objective == "r_max-run-up" and "t_ramp" not in runs.param_names:
        raise AnalysisError(f"--objective r_max-run-up: {runs.name} has no run-up (no t_ramp parameter): give --runs "
                            "a scene whose [speed] law is a schedule, or a run-up model")


def has_stick_phase(model: Model) -> bool:
    from .engines import hybrid

    try:
        hybrid.switching(model)
    except AnalysisError:
        return False
    return True
