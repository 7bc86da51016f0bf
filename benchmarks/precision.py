"""Benchmark (not a test): speed against accuracy, `adbgen bench precision` (issue 14, items 1 and 2).

Work-precision: for each problem, every pathway integrates from t = 0 to t_end at the tolerances
`TOLS` (rtol = tol, atol = tol x the problem's `atol_ratio`); its global error is the largest
absolute difference of the final state from a reference, plotted against the CPU time of the
integration (`TIME`; wall time recorded beside it; one curve per pathway, `chart`).  The reference
is computed in extended precision (heyoka's Taylor method in long double at tol 1e-19 on the
hand-written equations, checked by the same on the generated statements, `reference`): a double-precision
reference's own round-off over the horizon (1.5e-13 on problem A) had left the tightest levels
unmeasurable.  The stiff problem C (or a machine without heyoka) keeps CyRK's Verner 8(7) at rtol 1e-14,
checked by heyoka's Taylor method at tol 1e-15 (CyRK's DOP853 where heyoka fails).  The check's
difference is the reference's resolution, recorded, and errors below ten times it are marked as such.

Problems (`PROBLEMS`):

- A: thesis model n = 3 (`thesis_rotating_n3`) at (5.1), phi(0) = (pi/3, -pi/3, pi), t in [0, 2000]
  (as `bench_simulate.PROBLEM_A`).  For n >= 3 the balanced states form a family (thesis ch. 3), so
  the final ball angles carry the integration error (they are not contracted away).
- B: the two-plane run-up of the paper's section 6, Hill profile (45) with (3.6, 200, 3)
  (`two_plane_hill`), dynamic imbalance eps/R = chi = 5e-5 (eps/R + chi = 1e-4), imbalance phase 1,
  balls m = 1e-4 with race damping c_b/m = 0.1 (c_bb = c_bt = 1e-5, Figure 16 (d), (f), (h)), rotor
  at rest, the balls of each race on opposite sides; t in [0, 1000] (past the resynchronisation near
  t = 800).  atol = 1e-5 rtol: the rotor's states are of order 1e-5.
- C: stiff: the thesis model n = 3 with heavy ball damping beta = 1000 and light balls mu = 0.01,
  else (5.1), phi(0) as A, t in [0, 2000].  The real parts of the Jacobian's eigenvalues at the
  initial state (`stiffness`, recorded in the results) run from -1014.8, -1014.8, -1000.0 (the balls'
  damping, beta) to 3.4e-5 in magnitude: a stiffness ratio max |Re| / min |Re| of 3.0e7.  An explicit
  method's step is held to its stability interval (measured: CyRK's DOP853 takes 3.82 million
  evaluations, about 318000 steps of h = 6.3e-3, |h lambda| = 6.4, at every tolerance from 1e-3 to
  1e-6: its cost does not fall with the tolerance), while BDF's steps follow the slow dynamics
  (cvode-bdf: 20000-110000 evaluations).

Pathways (`curves`), one definition each:

- every engine of `adbgen.analysis.engines.ENGINES` (`bench_simulate.engine_pathway`): CyRK
  dop853/vern8/vern7/rk45/rk23, SUNDIALS cvode-bdf/cvode-adams/arkode-*, and the scipy-* engines,
  which are the generated numba rhs in solve_ivp (RK45, DOP853, Radau, LSODA, BDF; the implicit ones
  with the generated analytic Jacobian and, as ``-fdjac``, without), with the r_max/t_dec events;
- ``ivp:numba-dop853``: the generated numba rhs in solve_ivp DOP853 without events (the like of the
  next two);
- ``ivp:handwritten-dop853``: the hand-written numba rhs of thesis Appendix A (`bench.baseline`) in
  solve_ivp DOP853 (problems A and C, the thesis model);
- ``ivp:lambdify-rk45`` and ``ivp:lambdify-dop853``: ``sympy.lambdify(modules="math", cse=True)`` of
  the closed form (thesis model; the two-plane model's 4 x 4 core has no closed form in adbgen, so
  for B the mass matrix and forcing are lambdified and solved with ``numpy.linalg.solve`` per call,
  as a user would) in solve_ivp, the default RK45 and DOP853;
- ``cvode-main``: the emitted ``<model>_cvode_main.c`` compiled with gcc -O2 and run as a program
  (CVODE BDF, Newton, dense, the generated Jacobian); its wall time is the process' (start-up of a
  few ms included: `startup_s` records it);
- ``peer:jitcode-dop853`` and ``peer:heyoka`` (`bench.peers`: the generated rhs' statements fed to
  JiTCODE and heyoka; heyoka compiles one integrator per tolerance, outside the timings, in its compact
  mode for a rhs of more than `HEYOKA_COMPACT_ABOVE` statements (B): the default mode took 71 s to
  build B's integrator at tol 1e-15).

Cost control: before the sweep each pathway runs once at the loosest tolerance over a short horizon
(`PROBE_FRACTION` of t_end); if that predicts more than `max_run_s` for the full run, the pathway is
skipped (recorded with the measured probe time and the reason).  Tolerances then go from loose to
tight; a pathway stops when its next run is predicted to exceed `max_run_s` (its last time times the
growth between its last two runs) or, if its last run took more than `CHEAP_S`, when the problem's
share of the time budget is spent; the skipped tolerances are recorded with the last measured time
and the reason.  Runs faster than `SLOW_S` are repeated (best of `repeats`, round-robin over the
pathways at one tolerance).

Problem A also gives, per pathway, the loosest tolerance from which on every tighter tolerance
reaches the reference's attractor (final ball angles within `ATTRACTOR_TOL` rad, rotor amplitude
below the threshold) and t_dec within 1 % (issue 14, item 3, first bullet), charted
(`chart_reliable`).  t_dec is the engines' own (from their events); for the other
pathways it is read from their dense output or, for the peers and cvode-main, from an untimed run on
a grid (`TDEC_DT`), linearly interpolated.  The two differ at loose tolerances: events see a
crossing of the threshold only where r - threshold changes sign between step ends, so an excursion
above it that starts and ends within one step is missed (measured: solve_ivp DOP853 at rtol 1e-3 on
problem A, steps about 1.2 long near t = 770: last crossing event at t = 761.29, while its dense
output exceeds 1e-3 (up to 1.014e-3) until t = 776.26, the reference's t_dec being 776.02).
"""


from __future__ import annotations

import math
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .pathways import error
from .precision_charts import HEADLINE, chart, chart_percall, chart_reliable
from .precision_curves import THRESHOLD, curves, heyoka_compact
from .precision_sweep import (ATTRACTOR_TOL, PROBE_FRACTION, SLOW_S, TDEC_REL, TIME, attractor_check, curve_record,
                              auto_targets, loosest_reliable, precision_targets, sweep)
from .problems import Problem
from .registry import (BALL_COUNTS, ENGINE_NAMES, NO_PEERS, QUICK, REPEATS, Benchmark, option, require_known_engines,
                       require_positive_repeats)
from .report import closing, describe_targets, jsonable, load_average, opening, utc_now, write
from adbgen.cli_types import UsageError

TOLS = tuple(10.0 ** -k for k in range(3, 15))  # to 1e-14: the peers' curves reach error 1e-13 (issue 22)
QUICK_TOLS = (1e-4, 1e-7)
REF_TOL = 1e-14
CHECK_TOL = 1e-15
EXTENDED_TOL = 1e-19  # heyoka in long double (eps 1.1e-19)
MAX_RUN_S = 20.0
QUICK_MAX_RUN_S = 0.5
BUDGET_S = 480.0
QUICK_BUDGET_S = 40.0


@dataclass(frozen=True)
class PrecisionProblem:
    problem: Problem
    atol_ratio: float
    what: str
    thesis_model: bool = True  # the hand-written baseline applies
    # the reference in extended precision (heyoka, long double); not for the stiff problem, where an
    # explicit Taylor method's steps are held to its stability interval
    extended_reference: bool = True

    @property
    def label(self) -> str:
        return self.problem.label


_PHI0 = {"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}
_M_BALL = 1e-4
PROBLEMS = {
    "A": PrecisionProblem(Problem("A", "thesis_rotating_n3", {}, dict(_PHI0), 2000.0), 1e-2,
                          "thesis n = 3 at (5.1), phi(0) = (pi/3, -pi/3, pi)"),
    "B": PrecisionProblem(Problem("B", "two_plane_hill",
                                  {"epsilon": 5e-5, "chi": 5e-5, "beta": 1.0, "m_1": _M_BALL, "m_2": _M_BALL,
                                   "m_3": _M_BALL, "m_4": _M_BALL, "c_bb": 0.1 * _M_BALL, "c_bt": 0.1 * _M_BALL},
                                  {"theta_2": math.pi, "theta_4": math.pi}, 1000.0), 1e-5,
                          "two-plane Hill run-up (45), paper section 6, c_b/m = 0.1", thesis_model=False),
    "C": PrecisionProblem(Problem("C", "thesis_rotating_n3", {"beta": 1000.0, "mu": 0.01}, dict(_PHI0), 2000.0),
                          1e-2, "stiff: thesis n = 3, beta = 1000, mu = 0.01, else (5.1), phi(0) as A",
                          extended_reference=False),
}




# ----------------------------------------------------------------------------------- reference

def reference(model, pp: PrecisionProblem, t_end: float, ref_tol: float = REF_TOL,
              check_tol: float = CHECK_TOL) -> dict:
    """The final state every pathway's error is measured against, and its resolution.

    In extended precision where the problem allows (`extended`): heyoka's Taylor method in long double at
    tol EXTENDED_TOL on the hand-written equations, checked by the same on the generated statements (another
    formulation of the model); their difference is the resolution.  A double-precision reference cannot
    resolve the tightest levels: its own round-off over the horizon is the floor (measured on problem A:
    CyRK Vern8 at rtol 1e-14 is 1.5e-13 from the extended one, which two formulations agree on to 3e-17).
    Otherwise (the stiff problem, or heyoka missing): CyRK Vern8 at rtol ref_tol, checked by heyoka's Taylor
    method at check_tol (or CyRK DOP853 at ref_tol).  The Vern8 run is always made: problem A's t_dec and
    r_max come from it, and its distance from an extended reference is recorded."""
    from adbgen.analysis.simulate import simulate

    p, y0 = pp.problem.vectors(model)
    start = time.perf_counter()
    ref = simulate(model, p, y0, t_end=t_end, rtol=ref_tol, atol=ref_tol * pp.atol_ratio, engine="cyrk-vern8",
                   keep_trajectory=False)
    out = {"method": "cyrk-vern8 (CyRK Verner 8(7), compiled)", "rtol": ref_tol, "atol": ref_tol * pp.atol_ratio,
           "seconds": round(time.perf_counter() - start, 3), "n_rhs": int(ref.n_rhs), "y_end": ref.y_end.copy(),
           "t_dec": ref.t_dec, "r_max": ref.r_max}
    if pp.extended_reference:
        try:
            return {**out, **extended(model, pp, y0, p, t_end, ref.y_end)}
        except Exception as exc:  # heyoka missing, no wider long double, a failed run: the double reference
            out["extended_fallback_because"] = f"{type(exc).__name__}: {exc}"
    start = time.perf_counter()
    try:
        from . import peers as bench_peers

        peer = bench_peers.Heyoka(model.module, compact_mode=heyoka_compact(model))
        peer.integrator(check_tol, y0, p, cold=False)
        res = peer.run(y0, p, t_end, check_tol)
        if res["status"] != "success":
            raise RuntimeError(f"heyoka {res['status']}")
        check_y, check_method = res["y_end"], f"heyoka adaptive Taylor, tol {check_tol:g}"
    except Exception as exc:  # heyoka missing or failing: another method of another family
        out["check_fallback_because"] = f"{type(exc).__name__}: {exc}"
        chk = simulate(model, p, y0, t_end=t_end, rtol=ref_tol, atol=ref_tol * pp.atol_ratio, engine="cyrk-dop853",
                       keep_trajectory=False)
        check_y, check_method = chk.y_end, f"cyrk-dop853 at rtol {ref_tol:g}"
    out.update({"check_method": check_method, "check_seconds": round(time.perf_counter() - start, 3),
                "check_difference": error(check_y, ref.y_end)})
    return out


def extended(model, pp: PrecisionProblem, y0, p, t_end: float, double_y) -> dict:
    """`reference`'s extended-precision part: heyoka in long double on the hand-written equations (the
    generated statements where the model has none) and, as the check, on the generated statements."""
    from . import handwritten, peers as bench_peers

    hand = handwritten.form_of(model.module.NAME) is not None
    first = (bench_peers.HeyokaHandwritten if hand else bench_peers.Heyoka)(model.module)
    start = time.perf_counter()
    a = first.run_extended(y0, p, t_end, EXTENDED_TOL)
    seconds = time.perf_counter() - start
    start = time.perf_counter()
    # the check: the other formulation; with one formulation only, the same at a tolerance ten times looser
    b = (bench_peers.Heyoka(model.module).run_extended(y0, p, t_end, EXTENDED_TOL) if hand
         else first.run_extended(y0, p, t_end, 10 * EXTENDED_TOL))
    for run in (a, b):
        if run["status"] != "success":
            raise RuntimeError(f"heyoka in long double: {run['status']}")
    what = "the hand-written equations" if hand else "the generated statements"
    return {"method": f"heyoka adaptive Taylor in extended precision (long double), tol {EXTENDED_TOL:g}, on {what}",
            "rtol": EXTENDED_TOL, "atol": EXTENDED_TOL, "seconds": round(seconds, 3), "n_rhs": None,
            "order": a["order"], "n_steps": a["n_steps"], "y_end": a["y_end"],
            "check_method": ("the same on the generated statements" if hand else
                             f"the same at tol {10 * EXTENDED_TOL:g}"),
            "check_seconds": round(time.perf_counter() - start, 3), "check_difference": error(b["y_end"], a["y_end"]),
            "double_reference": f"cyrk-vern8 at rtol {REF_TOL:g}: its difference from this reference below",
            "double_reference_difference": error(double_y, a["y_end"])}


def stiffness(model, pp: PrecisionProblem) -> dict:
    """Eigenvalues of the generated Jacobian at the initial state: the stiffness ratio
    max |Re lambda| / min |Re lambda| over the eigenvalues with |Re lambda| > 1e-12."""
    p, y0 = pp.problem.vectors(model)
    ev = np.linalg.eigvals(np.asarray(model.module.jac(0.0, y0, p), float))
    re = np.abs(ev.real)
    nz = re[re > 1e-12]
    return {"eigenvalues_real_sorted": sorted(float(v) for v in ev.real),
            "stiffness_ratio": float(nz.max() / nz.min()) if len(nz) else None}




# ----------------------------------------------------------------------------------------- run

NOTES = (
    "error: largest absolute difference of the final state from the reference (reference.method: heyoka's "
    "Taylor method in extended precision, long double at tol 1e-19, where the problem allows; else CyRK Vern8 at "
    "rtol 1e-14), whose resolution is reference.check_difference (reference.check_method); below_resolution: "
    "error < 10x that. cpu_s (charts and targets): CPU seconds of the run (process and children; runs_cpu_s: all), the "
    "integration call with its small Python wrapper; wall_s: the integration alone (best of the repeats when "
    "faster than slow_s; runs_s: all), no builds "
    "(engines built, numba compiled, peers compiled beforehand; cvode-main is a process and includes its "
    "start-up). rtol = tol, atol = tol x atol_ratio (heyoka: tol). skipped: tolerances not run, with the reason "
    "and the last measured time. time_at_1e-8: log-log interpolation of time against error between a "
    "pathway's runs (extrapolated outside them, marked). The machine is a shared 2-core VM: compare ratios "
    "within this run; load averages recorded."
)


def bench_precision(problems=("A", "B", "C"), *, quick: bool = False, tols=None, engines=None, peers: bool = True,
                    lambdify: bool = True, repeats: int | None = None, max_run_s: float | None = None,
                    budget_s: float | None = None, t_end: float | None = None, percall: bool = True,
                    percall_ns=None, progress=None) -> dict:
    """The whole benchmark (module docstring); returns the JSON-ready result."""
    from . import percall as bench_percall
    from adbgen.analysis.engines import DEFAULT
    from adbgen.analysis.loading import load_model

    say = progress or (lambda line: None)
    result, started = opening("precision")
    tols = tuple(tols or (QUICK_TOLS if quick else TOLS))
    repeats = repeats or (1 if quick else 5)
    max_run_s = max_run_s or (QUICK_MAX_RUN_S if quick else MAX_RUN_S)
    budget_s = budget_s or (QUICK_BUDGET_S if quick else BUDGET_S)
    result.update({"notes": NOTES, "default_engine": DEFAULT, "problems": {},
                   "settings": {"problems": list(problems), "quick": quick, "tols": list(tols), "repeats": repeats,
                                "slow_s": SLOW_S, "max_run_s": max_run_s, "budget_s": budget_s,
                                "probe_fraction": PROBE_FRACTION, "reference_tol": REF_TOL, "check_tol": CHECK_TOL,
                                "attractor_tol": ATTRACTOR_TOL, "t_dec_relative": TDEC_REL, "threshold": THRESHOLD,
                                "time_compared": TIME}})
    share = budget_s / max(1, len(problems))
    for label in problems:
        pp = PROBLEMS[label]
        horizon = t_end or (pp.problem.t_end / 10 if quick else pp.problem.t_end)
        model = load_model(pp.problem.model)
        say(f"problem {label}: {pp.what}, t in [0, {horizon:g}]")
        rec: dict = {"what": pp.what, "problem": {**pp.problem.to_json(), "t_end": horizon, "rtol": None,
                                                  "atol": None, "atol_ratio": pp.atol_ratio},
                     "stiffness": stiffness(model, pp)}
        ref = reference(model, pp, horizon)
        say(f"  reference {ref['seconds']} s, check {ref['check_method']}: difference {ref['check_difference']:.2e}")
        with tempfile.TemporaryDirectory(prefix="adbgen-precision-") as tmp:
            cs = curves(model, pp, Path(tmp), engines=engines, peers=peers, lambdify=lambdify,
                        want_t_dec=(label == "A"), progress=lambda line: say("  " + line))
            for c in cs:  # warm: compiled engines' libraries, numba, first calls
                try:
                    c.make(tols[0], min(1.0, horizon)).run()
                except Exception as exc:
                    say(f"  warm-up of {c.name} failed: {exc}")
            rec["load_average_before_timing"] = load_average()
            sweep(model, pp, cs, tols, t_end=horizon, repeats=repeats, max_run_s=max_run_s, budget_s=share,
                  progress=say)
            rec["load_average_after_timing"] = load_average()
            p, _ = pp.problem.vectors(model)
            check = attractor_check(model, ref, p) if label == "A" else None
            rec["curves"] = [curve_record(c, ref["y_end"], ref["check_difference"], check) for c in cs]
        errs = [q["error"] for r in rec["curves"] for q in r["points"] if q.get("error")]
        rec["reference"] = {**{k: v for k, v in ref.items() if k != "y_end"},
                            "y_end": dict(zip(model.state_names, map(float, ref["y_end"]))),
                            "smallest_error_measured": min(errs) if errs else None}
        rec["reference"]["converged"] = bool(ref["check_difference"] is not None and errs
                                             and ref["check_difference"] <= 0.1 * min(errs))
        if label == "A":
            rec["reference"]["t_dec"] = ref["t_dec"]
            rec["loosest_reliable"] = {r["name"]: loosest_reliable(r) for r in rec["curves"]}
        result["problems"][label] = rec
    result["targets"] = precision_targets(result["problems"]["A"], DEFAULT) if "A" in result["problems"] else []
    result["targets"] += auto_targets(result["problems"], DEFAULT)
    if percall:
        ns = tuple(percall_ns or ((2, 4) if quick else bench_percall.NS))
        result["load_average_before_percall"] = load_average()
        result["percall"] = bench_percall.bench_percall(ns, quick=quick, progress=say)
        result["targets"] = bench_percall.targets(result["percall"]) + result["targets"]
    return closing(result, started)


def rerun_percall(previous: dict | None, ns=None, progress=None) -> dict:
    """The per-call part alone, measured again and put into a previous result (its work-precision part kept
    as it was, with its own date): for a change that moves the generated code's cost per call but not the
    integrations' conclusions.  The per-call targets are replaced, the others kept; `percall_date` and
    `percall_commit` say when and on what the per-call part ran."""
    from . import percall as bench_percall

    if previous is not None and previous.get("benchmark") != "precision":
        raise ValueError("the results file holds no `adbgen bench precision` result")
    result = dict(previous or {"benchmark": "precision", "problems": {}, "targets": []})
    result["load_average_before_percall"] = load_average()
    result["percall"] = bench_percall.bench_percall(tuple(ns or bench_percall.NS), quick=False, progress=progress)
    kept = [t for t in result.get("targets", []) if not str(t.get("target", t.get("name", ""))).startswith("per call")]
    result["targets"] = bench_percall.targets(result["percall"]) + kept
    result["percall_date"] = utc_now()
    try:
        result["percall_commit"] = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                                                  cwd=Path(__file__).parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        result["percall_commit"] = None
    return jsonable(result)


def run(args, out: str) -> int:
    problems = args.problems or list(PROBLEMS)
    unknown = [p for p in problems if p not in PROBLEMS]
    if unknown:
        raise UsageError(f"unknown problem {unknown[0]!r}; choose from {', '.join(PROBLEMS)}")
    require_positive_repeats(args)
    for name, value in (("--max-run", args.max_run), ("--budget", args.budget), ("--t-end", args.t_end)):
        if value is not None and not (value > 0):
            raise UsageError(f"{name} must be > 0, got {value}")
    require_known_engines(args)
    if args.only_percall:
        import json

        previous = json.loads(Path(out).read_text()) if Path(out).exists() else None
        try:
            result = rerun_percall(previous, tuple(args.n) if args.n_given else None,
                                   progress=lambda line: print(line, flush=True))
        except ValueError as exc:
            raise UsageError(f"{out}: {exc}") from None
        path = write(result, out)
        png = chart_percall(result, f"{Path(out).with_suffix('')}_percall.png")
        for line in describe_targets(result):
            print(line)
        print(f"wrote {path} (per-call part replaced) and {png}")
        return 0
    result = bench_precision(
        tuple(problems), quick=args.quick, engines=args.engines, peers=not args.no_peers, repeats=args.repeats,
        max_run_s=args.max_run, budget_s=args.budget, t_end=args.t_end, percall=not args.no_percall,
        percall_ns=tuple(args.n) if args.n_given else None, progress=lambda line: print(line, flush=True))
    path = write(result, out)
    stem = Path(out).with_suffix("")
    charts = [chart(result, label, f"{stem}_{label}.png") for label in result["problems"]]
    if "A" in result["problems"]:
        charts.append(chart(result, "A", f"{stem}_A_headline.png", only=HEADLINE))
        charts.append(chart_reliable(result, f"{stem}_A_reliable.png"))
    if result.get("percall"):
        charts.append(chart_percall(result, f"{stem}_percall.png"))
    for line in describe_targets(result):
        print(line)
    print(f"wrote {path} and {', '.join(map(str, charts))} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("precision", run, (
    BALL_COUNTS.but("the per-call part's (default 2 4 8 16 32)"),
    REPEATS.but("best of N for runs under slow_s (default 5; quick 1)"),
    ENGINE_NAMES, NO_PEERS,
    option("--problems", nargs="+", default=None, help="problems (default A B C)"),
    QUICK.but("2 tolerances, 1/10 of the horizon, n = 2 4 (about a minute)"),
    option("--max-run", type=float, default=None, help="skip a pathway's tighter tolerances once a run is predicted "
           "to take longer than this [s] (default 20; quick 0.5)"),
    option("--budget", type=float, default=None, help="time budget of the work-precision part [s], shared by the "
           "problems (default 480; quick 40)"),
    option("--t-end", type=float, default=None, help="integrate every problem to this time (default: each problem's)"),
    option("--no-percall", action="store_true", help="skip the per-call part"),
    option("--only-percall", action="store_true", help="run the per-call part alone and put it into the results "
           "file in place of its per-call part (the work-precision part is kept)"),
))


__all__ = ["BENCHMARK", "PROBLEMS", "PrecisionProblem", "TOLS", "bench_precision", "reference", "rerun_percall",
           "stiffness"]
