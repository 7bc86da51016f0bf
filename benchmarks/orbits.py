"""Benchmark (not a test): periodic orbits (issue 21).  `adbgen bench orbits [--out FILE] [--orbit-parts PART ...]
[--quick]` -> ``benchmarks/orbits.json`` + PNG.

- ``newton``: one Newton step of the shooting system of the n = 3 orbit (thesis Fig. 5.16(a): n = 3,
  (5.1) with zeta = 0.25, the balls lapping the rotor): the arcs and their variational equations in the
  compiled driver, the bordered linear solve; best of N, and the cost split (integration, solve);
- ``branch``: a 200-point branch of cycles (n = 2, from H1 at Omega = 1.8822, mu = 0.05, zeta = beta =
  delta = 0.01) by Newton shooting with the generic continuer, against AUTO-07p's collocation (IPS = 2,
  NTST = 60, NCOL = 4, from the same HB label, 200 steps, run after its build) on the same branch; the
  agreement of the two at AUTO's points is part of the record;
- ``charts``: the stability charts of the two-plane paper (Figs. 10(a), 11, 13(a-d), 14(a, b); grid 81 x 25,
  curves continued from every stability change) each timed, against the issue's budget of 10 minutes on
  two cores.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .registry import QUICK, Benchmark, option
from .report import closing, opening, pyplot, save_figure, target, when, write

PARTS = ("newton", "branch", "charts")
CHART_BUDGET_S = 600.0


def _children_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def bench_newton(repeats: int = 20, say=print) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits import orbit
    from adbgen.analysis.orbits.flow import Flow
    from adbgen.analysis.orbits.shooting import Shooting

    m = load_model("thesis_rotating_n3")
    p = m.params({"zeta": 0.25})
    o = orbit.find(m, p, m.state({"phi_1": math.pi / 3, "phi_2": -math.pi / 3, "phi_3": math.pi}), 3000.0)
    flow = Flow(m)
    sh = Shooting(m, flow, len(o.arcs), orbit.shift_vector(m, o.windings))
    sh.set_reference(o.arcs[0], p)
    u0 = sh.pack(o.arcs + 1e-6, o.period)  # a little off the orbit: a real step
    best, best_int, best_solve = math.inf, math.inf, math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        ev = sh.evaluate(u0, p)
        t1 = time.perf_counter()
        step = np.linalg.lstsq(ev.A, -ev.F, rcond=1e-13)[0]
        t2 = time.perf_counter()
        best, best_int, best_solve = min(best, t2 - t0), min(best_int, t1 - t0), min(best_solve, t2 - t1)
    n0 = flow.n_rhs
    sh.evaluate(u0, p)
    evals = flow.n_rhs - n0
    say(f"newton: one step {1e3 * best:.3f} ms (integration {1e3 * best_int:.3f}, solve {1e3 * best_solve:.3f}), "
        f"{evals} evaluations of the augmented system")
    return {"model": m.name, "period": o.period, "windings": o.windings, "states": m.n_states,
            "augmented_states": m.n_states * (m.n_states + 1), "step_s": best, "integration_s": best_int,
            "solve_s": best_solve, "evaluations": evals, "repeats": repeats, "step_norm": float(np.linalg.norm(step))}


def bench_branch(points: int = 200, say=print) -> dict:
    from adbgen.analysis import auto07p, equilibrium_scan
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits import auto_cycles, branches, continuer, hopf
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model("thesis_rotating_n2")
    p = m.params({"Omega": 4.0, "mu": 0.05, "zeta": 0.01, "beta": 0.01, "delta": 0.01})
    sc = equilibrium_scan.scan(m, p, m.module.START, "Omega", 4.0, 1.7)
    pm = ParameterMap(m, p, ["Omega"])
    hp = hopf.HopfPoint.at(m, pm, sc.points[0].y, sc.points[0].value)
    t0, c0 = time.perf_counter(), time.process_time()
    ours = branches.from_hopf(m, pm, hp, continuer.Settings(ds=0.01, ds_max=0.05, max_points=points, bounds=(0.5, 4.0)),
                              amplitude=False)
    ours_s, ours_cpu = time.perf_counter() - t0, time.process_time() - c0
    j = ours.to_json()
    out = {"model": m.name, "hopf": hp.lam, "points": len(j["parameter"]), "ours_s": ours_s, "ours_cpu_s": ours_cpu,
           "ours_range": [j["parameter"][0], j["parameter"][-1]], "ours_specials": ours.specials}
    say(f"branch: shooting {len(j['parameter'])} points in {ours_s:.2f} s, Omega {j['parameter'][0]:.4f} to "
        f"{j['parameter'][-1]:.4f}")
    if auto07p.missing_tools():
        out["auto"] = None
        return out
    k = m.param_names.index("Omega")
    a, amp = auto07p.auto_parameter(k), auto07p.auto_parameter(m.n_params)
    with auto07p.Session(m) as session:
        one = auto07p.continue_one(m, "Omega", p, None, 0.5, session=session)  # also builds AUTO's executable
        session.keep_solutions(m.name)
        hb = min((q for q in one.labelled() if q.kind == "HB"), key=lambda q: abs(q.values[f"PAR({a})"] - hp.lam))
        t0, c0 = time.perf_counter(), _children_cpu()
        pts, _, _ = session.run(s=repr(m.name), IRS=hb.label, IPS=2, ISW=1, ICP=f"[{a}, 11, {amp}]", NTST=60, NCOL=4,
                                ISP=2, DS=-0.01, DSMAX=0.05, NMX=points, NPR=points, UZSTOP=auto07p._mapping({a: [0.5, 4.0]}),
                                U=None, PAR=None)
        auto_s, auto_cpu = time.perf_counter() - t0, _children_cpu() - c0
    theirs = auto_cycles._branch_json(pts, "Omega", f"PAR({a})", f"PAR({amp})", hb.values[f"PAR({a})"], False)
    cmp = auto_cycles.compare(ours, theirs, pm)
    out.update({"auto_s": auto_s, "auto_cpu_s": auto_cpu, "cpu_ratio": auto_cpu / ours_cpu, "auto_points": len(pts), "auto_range": [theirs["parameter"][0], theirs["parameter"][-1]],
                "auto_specials": theirs["points"], "agreement_period_rel": cmp["period_rel"], "agreement_parameter_rel": cmp["parameter_rel"],
                "ours_period_range": [min(j["period"]), max(j["period"])],
                "auto_period_range": [min(theirs["period"]), max(theirs["period"])],
                "auto_points_on_our_stretch": cmp["common"],
                "agreement_points": cmp["points"],
                "agreement_unrefined": cmp["unrefined"], "ratio": auto_s / ours_s})
    say(f"branch: AUTO {len(pts)} points in {auto_s:.2f} s wall, {auto_cpu:.2f} s CPU (shooting {ours_cpu:.2f} s CPU; "
        f"ratio AUTO/shooting {auto_s / ours_s:.2f} wall, {auto_cpu / ours_cpu:.2f} CPU); the two agree to "
        f"{max(cmp['period_rel'], cmp['parameter_rel']):.1e} at {len(cmp['points']) - cmp['unrefined']} of AUTO's "
        f"points ({sum(r.get('fixed') == 'parameter' for r in cmp['points'])} at its parameter value, "
        f"{sum(r.get('fixed') == 'period' for r in cmp['points'])} at its period; {cmp['unrefined']} not reached); "
        f"{cmp['common']} of AUTO's {len(pts)} steps on the stretch our {len(j['parameter'])} points cover")
    return out


def _chart(case, n1: int, n2: int):
    """One of the paper's charts as `adbgen continue --par Omega --par2 epsilon --tie ... --log2` computes it."""
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.orbits import charts
    from adbgen.analysis.orbits.parameters import ParameterMap

    m = load_model(case.model)
    pmap = ParameterMap(m, m.params(case.sets), ["Omega", "epsilon"], case.ties)
    lam0 = (3.0, 1e-3)
    return charts.compute(m, pmap, charts.chart_start(m, pmap, lam0), case.range1, case.range2, log2=True, n1=n1,
                          n2=n2, lam1_0=lam0[0], lam2_0=lam0[1])


def bench_charts(quick: bool = False, say=print) -> dict:
    from adbgen.families.two_plane.charts import CHARTS

    rows = {}
    for case in CHARTS:
        if case.same_as:
            rows[case.figure] = {"same_as": case.same_as, **rows[case.same_as]}
            continue
        n1, n2 = (21, 5) if quick else (81, 25)
        t0 = time.perf_counter()
        c = _chart(case, n1, n2)
        wall = time.perf_counter() - t0
        rows[case.figure] = {"model": case.model, "grid": [n1, n2], "wall_s": wall,
                             "curves": {k: sum(1 for cv in c.curves if cv.kind == k) for k in
                                        sorted({cv.kind for cv in c.curves})},
                             "curve_points": sum(len(cv.points) for cv in c.curves)}
        say(f"chart {case.figure}: {wall:.1f} s, {rows[case.figure]['curves']}")
    return rows


def bench_orbits(parts=PARTS, quick: bool = False, progress=print) -> dict:
    result, started = opening("orbits")
    if "newton" in parts:
        result["newton"] = bench_newton(5 if quick else 20, progress)
    if "branch" in parts:
        result["branch"] = bench_branch(40 if quick else 200, progress)
    if "charts" in parts:
        result["charts"] = bench_charts(quick, progress)
        worst = max(r["wall_s"] for r in result["charts"].values())
        result["targets"] = [target("charts", "each chart of item 4 under 10 minutes on two cores (budget / slowest >= 1)",
                                    CHART_BUDGET_S / worst, 1.0, f"slowest {worst:.0f} s")]
    return closing(result, started)


def chart(result: dict, path: Path) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    if "branch" in result and result["branch"].get("auto_s"):
        b = result["branch"]
        axes[0].bar([0, 1], [b["ours_s"], b["auto_s"]], color=["C0", "C1"])
        axes[0].set_xticks([0, 1], [f"shooting ({b['points']} points)", f"AUTO-07p ({b['auto_points']} points)"], fontsize=7)
        axes[0].set_ylabel("wall time [s]")
        axes[0].set_title(f"200-point branch, n = 2 from H1 (agree to {max(b['agreement_period_rel'], b.get('agreement_parameter_rel', 0.0)):.0e})", fontsize=8)
    if "charts" in result:
        names = list(result["charts"])
        axes[1].bar(range(len(names)), [result["charts"][k]["wall_s"] for k in names], color="C2")
        axes[1].axhline(CHART_BUDGET_S, color="C3", lw=0.8, ls="--")
        axes[1].set_xticks(range(len(names)), names, fontsize=7)
        axes[1].set_ylabel("wall time [s]")
        axes[1].set_title("stability charts (grid 81 x 25 + curves); dashed: 10 minutes", fontsize=8)
    fig.suptitle(f"Periodic orbits: {when(result)} UTC, load {result['machine']['load_average_at_start']}", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)


def run(args, out: str) -> int:
    parts = tuple(args.orbit_parts or PARTS)
    result = bench_orbits(parts, quick=args.quick, progress=lambda line: print(line, flush=True))
    path = write(result, out)
    png = chart(result, Path(out).with_suffix(".png"))
    print(f"wrote {path} and {png} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("orbits", run, (
    QUICK.but("short runs (checks the machinery)"),
    option("--orbit-parts", nargs="+", choices=PARTS, help="only these parts (default: all)"),
))


__all__ = ["BENCHMARK", "bench_branch", "bench_charts", "bench_newton", "bench_orbits", "chart"]
