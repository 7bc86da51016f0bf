"""Benchmark (not a test): what stiction costs a sweep of starts (issue 37, "Speed in a benchmark": a sweep of
10,000 starts with stiction within 3x the same sweep without it).
`adbgen bench friction [--starts N] [--t-end T] [--page]` -> ``benchmarks/friction.json``.

The rotor is friction_scene.toml (test_hybrid_engine.py's braked-rotor scene, so its model is the cached
one), run as an unbalanced free rotor (eps = 1e-3 m, tau0 = 0, no ball drag) started at 100 rad/s with both
balls at rest on the race, the starts a grid of ball angles phi_1 x phi_2 over [0, 2 pi] (about `--starts`
points).  Both sweeps run in one invocation, each the whole `run_sweep` (Dask, the store, no figures):

* with stiction: mu_r = 0.002, mu_s = 0.005 on the scene's stick/slip model (hybrid-dop853, chosen by the
  model), `--measure residual`: the residual imbalance's distribution is recorded with the time;
* without: the same scene without its friction keys (today's model, the default engine), `--measure r_max`,
  the same starts, end time and tolerances.

The ratio is with / without (wall seconds of the two sweeps, measured back to back on the same machine); with
`--repeats N` the two sweeps alternate N times and each side's time is the median of its N runs (every run is
recorded).  The load average at the start and the end is recorded: a run that starts with a 1-minute load
average above `QUIET_LOAD` (something else was running on the two cores) is indicative only, and its page
says so.
"""

from __future__ import annotations

import math
import statistics
import tempfile
import time
from pathlib import Path

from .registry import REPEATS, Benchmark, option, require_positive_repeats
from .report import closing, opening, when, write

ROOT = Path(__file__).resolve().parents[1]
SCENE = Path(__file__).with_name("friction_scene.toml")
PAGE = ROOT / "docs" / "benchmarks" / "friction.md"
TARGET = 3.0  # the "within 3x"
DEFAULT_STARTS = 10_000
DEFAULT_T_END = 10.0  # s: 160 turns at 100 rad/s, five decay times 2 M / c of the support
ROTOR = {"eps": 1e-3, "tau0": 0.0, "kappa": 0.0}
FRICTION = {"mu_r": 0.002, "mu_s": 0.005}
START = ["psi_dot=100"]
FRICTION_KEYS = ("rolling_resistance", "static_friction")
QUIET_LOAD = 0.5  # 1-minute load average at the start below which nothing else was running


def frictionless(text: str) -> str:
    """The scene without its friction keys: the same rotor on today's model."""
    return "".join(line for line in text.splitlines(keepends=True) if line.split("=")[0].strip() not in FRICTION_KEYS)


def grid(starts: int) -> tuple[int, list[str]]:
    k = max(2, round(math.sqrt(starts)))
    return k * k, [f"phi_1=0:2*pi:{k}", f"phi_2=0:2*pi:{k}"]


def verdict(ratio: float, points: int) -> bool | None:
    """The target (ratio <= TARGET) decided only on a run of the full DEFAULT_STARTS starts."""
    return (ratio <= TARGET) if points >= DEFAULT_STARTS else None


def _sweep(model, measure, values, axes, t_end, out, workers):
    from adbgen.analysis.sweep import SweepSpec, run_sweep

    spec = SweepSpec(model=str(model.folder), grid=axes, measure=measure, set=[f"{k}={v}" for k, v in values.items()],
                     y0=START, t_end=t_end)
    t = time.perf_counter()
    summary = run_sweep(spec, out, workers=workers, progress=False, figures=False)
    return time.perf_counter() - t, summary


def bench_friction(starts: int, t_end: float, workers: int | None = None, progress=print, repeats: int = 1) -> dict:
    from adbgen.analysis.loading import load_model

    result, started = opening("friction")
    points, axes = grid(starts)
    runs: dict[str, list[float]] = {"with": [], "without": []}
    with tempfile.TemporaryDirectory() as tmp:
        free_scene = Path(tmp) / "frictionless.toml"
        free_scene.write_text(frictionless(SCENE.read_text()))
        progress("models (cached after the first run; the stick/slip model takes minutes to generate)")
        stick, free = load_model(scene=SCENE), load_model(scene=free_scene)
        for k in range(repeats):  # alternated, so a change of load falls on both sides
            progress(f"run {k + 1}/{repeats}, with stiction: {points} starts")
            s, with_sum = _sweep(stick, "residual", {**ROTOR, **FRICTION}, axes, t_end, Path(tmp) / f"with{k}", workers)
            runs["with"].append(round(s, 2))
            progress(f"  {s:.1f} s; without stiction: {points} starts")
            s, without_sum = _sweep(free, "r_max", ROTOR, axes, t_end, Path(tmp) / f"without{k}", workers)
            runs["without"].append(round(s, 2))
            progress(f"  {s:.1f} s")
    with_s, without_s = statistics.median(runs["with"]), statistics.median(runs["without"])
    ratio = with_s / without_s
    result.update({
        "scene": str(SCENE.relative_to(ROOT)), "rotor": ROTOR, "friction": FRICTION, "initial_state": START,
        "grid": axes, "starts": points, "starts_asked": starts, "default_starts": DEFAULT_STARTS,
        "reduced": points < DEFAULT_STARTS, "t_end": t_end,
        "repeats": repeats,
        "with_stiction": {"model": stick.name, "engine": "hybrid-dop853 (chosen by the model)", "wall_s": round(with_s, 2),
                          "runs_wall_s": runs["with"],
                          "integrated": with_sum["integrated"], "residual": with_sum["residual"]},
        "without_stiction": {"model": free.name, "engine": "auto (the default)", "wall_s": round(without_s, 2),
                             "runs_wall_s": runs["without"],
                             "integrated": without_sum["integrated"]},
        "ratio": round(ratio, 3), "target": f"ratio <= {TARGET:g} at {DEFAULT_STARTS} starts",
        "target_met": verdict(ratio, points),
    })
    return closing(result, started)


def page(result: dict) -> str:
    """docs/benchmarks/friction.md from the results."""
    m, w, wo = result["machine"], result["with_stiction"], result["without_stiction"]
    d = w["residual"]
    q = d["quantiles"]
    reduced = (f" **Reduced run: {result['starts']} starts, not the {result['default_starts']} of the target** "
               "(the shared machine was loaded); the target is not decided by it." if result["reduced"] else "")
    fmt = (lambda v: "-" if v is None else f"{v:.3g}")
    quiet = quiet_start(result)
    repeats = result.get("repeats", 1)
    median = f" (median of {repeats} alternated runs: {w['runs_wall_s']} and {wo['runs_wall_s']})" if repeats > 1 else ""
    return "\n".join([
        "# What stiction costs a sweep (`adbgen bench friction`)", "",
        f"**Run record** (from [`benchmarks/friction.json`](../../benchmarks/friction.json)): {when(result)} "
        f"UTC, {m.get('cpu', 'machine not recorded')}, load average {m.get('load_average_at_start')} at the start and "
        f"{m.get('load_average_at_end')} at the end ("
        + ("nothing else running on the machine at the start" if quiet else "shared with other sessions: not a quiet machine")
        + "); command "
        f"`adbgen bench friction --starts {result['starts_asked']} --t-end {result['t_end']:g}"
        + (f" --repeats {repeats}" if repeats > 1 else "") + f"`.{reduced}", "",
        f"What it runs: `{result['scene']}` as an unbalanced free rotor ({', '.join(f'{k} = {v:g}' for k, v in result['rotor'].items())}), "
        f"started at psi' = 100 rad/s with the balls at rest on the race, over a grid of ball angles "
        f"({', '.join(result['grid'])}), to t_end = {result['t_end']:g} s; with stiction "
        f"({', '.join(f'{k} = {v:g}' for k, v in result['friction'].items())}) on the stick/slip model "
        f"({w['engine']}, `--measure residual`) and without friction on today's model ({wo['engine']}, "
        "`--measure r_max`).", "",
        "| sweep | starts | integrated | wall s |", "| --- | --- | --- | --- |",
        f"| with stiction | {result['starts']} | {w['integrated']} | {w['wall_s']} |",
        f"| without | {result['starts']} | {wo['integrated']} | {wo['wall_s']} |", "",
        f"Wall seconds{median}.", "",
        f"Ratio with / without: {result['ratio']} (target: {result['target']}; "
        + ("met" if result["target_met"] else "not met" if result["target_met"] is False else "not decided by this run")
        + ")." + ("" if quiet else " Times on a loaded shared machine: indicative only, no speed claim."), "",
        "## The residual imbalance at rest (with stiction)", "",
        f"{d['at_rest']} starts at rest at t_end, {d['not_at_rest']} with a ball still slipping (undecided), "
        f"{d['failed']} failed (the last two not counted). r at rest: median {fmt(q['50'])}, 90 % {fmt(q['90'])}, "
        f"99 % {fmt(q['99'])}, max {fmt(q['max'])} (m).", "",
        "Re-run: `adbgen bench friction [--starts N] [--t-end T] [--repeats N] --page`.", ""])


def quiet_start(result: dict) -> bool:
    """Whether nothing else ran when the benchmark started (1-minute load average below QUIET_LOAD)."""
    load = result["machine"].get("load_average_at_start")
    return bool(load) and load[0] < QUIET_LOAD


def run(args, out: str) -> int:
    from adbgen.cli_types import UsageError

    starts = args.starts if args.starts is not None else DEFAULT_STARTS
    if starts < 4:
        raise UsageError(f"--starts must be >= 4, got {starts}")
    t_end = DEFAULT_T_END if args.t_end is None else args.t_end
    if not (math.isfinite(t_end) and t_end > 0):
        raise UsageError(f"--t-end must be a finite number > 0, got {t_end}")
    require_positive_repeats(args)
    result = bench_friction(starts, float(t_end), progress=lambda line: print(line, flush=True),
                            repeats=args.repeats or 1)
    written = [write(result, out)]
    if args.page:
        PAGE.write_text(page(result))
        written.append(PAGE)
    print(f"{result['starts']} starts: with stiction {result['with_stiction']['wall_s']} s, without "
          f"{result['without_stiction']['wall_s']} s, ratio {result['ratio']} (target {result['target']}); wrote "
          + ", ".join(map(str, written)))
    return 0


BENCHMARK = Benchmark("friction", run, (
    option("--starts", type=int, default=None, help=f"starts per sweep (default {DEFAULT_STARTS}; a square grid)"),
    option("--t-end", type=float, default=None, help=f"end time of every run, s (default {DEFAULT_T_END:g})"),
    option("--page", action="store_true", help="also write docs/benchmarks/friction.md from the results"),
    REPEATS.but("alternate the two sweeps N times, each side's median kept (default 1)"),
))
