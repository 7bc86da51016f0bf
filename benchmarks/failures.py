"""Benchmark (not a test): where methods fail (issue 14, item 3).

`adbgen bench failures [--out FILE] [--quick]` writes ``benchmarks/failures.json`` and its charts
``failures_<part>.png``.  Parts (each a key of the JSON):

- ``fixed_step``: problem A (thesis n = 3, (5.1), phi(0) = (pi/3, -pi/3, pi), t in [0, 2000]) by fixed-
  step explicit Runge-Kutta (classical RK4 and the RK45 / DOP853 tableaus, `bench.fixed_step`): error
  of the final state against a tight reference for a range of steps, the blow-up step (grid, then
  bisection) and the Jacobian's spectral radius along the reference trajectory: h_blow |lambda|_max
  against the tableau's stability boundary along arg lambda (RK4: 2.785 on the real axis, 2.828 on
  the imaginary one);
- ``jacobi``: |J(t) - J(0)| of the Jacobi integral (thesis model at zeta = beta = 0) over t = 1e5 for an
  explicit (cyrk-dop853), an implicit (cvode-bdf) and a structure-preserving method (implicit midpoint
  by SUNDIALS ARKStep at a fixed step, `bench.jacobi`);
- ``stiff``: rhs evaluations, steps and wall time of explicit (cyrk-dop853, cyrk-rk45) and implicit
  (cvode-bdf, scipy-radau with the analytic Jacobian) engines as the ball damping beta grows (in the
  thesis' scaling (2.15)-(2.19) a ball's motion relative to the race decays at a rate ~ beta, so the
  Jacobian's spectral radius ``rho_at_start`` grows with beta while the slow rotor modes stay);
- ``symmetry``: from phi(0) = (pi, pi, pi) do the three balls stay bitwise together and which state
  does each pathway reach (the thesis: the coincident state 2-); `bench_simulate.symmetry_record`;
- ``merging``: the converse failure: the two balls of a race that come within round-off merge for
  ever.  (a) the Hill run-up of the two-plane paper's section 6 (`two_plane_hill`, c_b/m = 0.1 and
  0.01, balls of a race on opposite sides, rotor at rest) on every pathway, and in pair coordinates
  (mean, half-difference; `bench.pairs`) by the same CyRK solver; (b) the thesis model n = 2 started
  with the balls a distance 2 d0 apart, d0 from 1e-20 (far below ulp(pi) = 4.4e-16) to 1e-10: the
  exact solution separates them (the coincident state is unstable), the original formulation cannot
  even represent the start.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .problems import PROBLEM_A, THESIS_2MINUS, symmetric_y0, symmetry_record
from .registry import QUICK, Benchmark
from .report import closing, load_average, opening, pyplot, save_figure, when, write

REF_RTOL, REF_ATOL = 1e-13, 1e-15
STIFF_BETAS = (0.01, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4)
STIFF_ENGINES = ("cyrk-dop853", "cyrk-rk45", "cvode-bdf", "scipy-radau")
SYMMETRY_ENGINES = ("cyrk-dop853", "cyrk-vern8", "cyrk-vern7", "cyrk-rk45", "cyrk-rk23", "cvode-adams",
                    "arkode-erk8", "arkode-dp5", "arkode-erk6", "cvode-bdf", "scipy-dop853")
MERGE_ENGINES = ("cyrk-dop853", "cyrk-vern8", "cyrk-rk45", "arkode-dp5", "cvode-adams", "cvode-bdf", "scipy-dop853")
HILL_PAIRS = (("theta_1", "theta_2"), ("theta_3", "theta_4"))


def _say(progress, line):
    if progress:
        progress(line)


# ------------------------------------------------------------------------------------ fixed step

def fixed_step_part(quick: bool, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from . import fixed_step as fs

    model = load_model(PROBLEM_A.model)
    p, y0 = PROBLEM_A.vectors(model)
    t_end = 200.0 if quick else PROBLEM_A.t_end
    ref = simulate(model, p, y0, t_end=t_end, rtol=REF_RTOL, atol=REF_ATOL, engine="cyrk-vern8")
    check = simulate(model, p, y0, t_end=t_end, rtol=REF_RTOL, atol=REF_ATOL, engine="cyrk-dop853",
                     keep_trajectory=False)
    tabs = fs.tableaus()
    out: dict = {"problem": PROBLEM_A.to_json() | {"t_end": t_end},
                 "reference": {"engine": "cyrk-vern8", "rtol": REF_RTOL, "atol": REF_ATOL,
                               "check": "cyrk-dop853 at the same tolerances",
                               "check_difference": float(np.max(np.abs(check.y_end - ref.y_end)))},
                 "how": "numba fixed-step loop over the generated rhs_inplace (CyRK and solve_ivp have no "
                        "fixed-step mode); blow-up = a state component non-finite or above 1e3 before t_end",
                 "tableaus": {}}
    boundaries = {name: (lambda th, tb=tb: fs.stability_boundary(tb, th)) for name, tb in tabs.items()}
    idx = np.unique(np.linspace(0, len(ref.t) - 1, 100 if quick else 400).astype(int))
    spec = fs.spectrum_along(model, p, ref.t[idx], ref.y[:, idx], boundaries)
    out["spectrum"] = spec
    steps = [100, 141, 200, 283, 400, 566, 800] if quick else [1000, 1414, 2000, 2828, 4000, 5657, 8000, 11314,
                                                                16000, 22627, 32000, 45255, 64000]
    for name, tb in tabs.items():
        rows = []
        for n in steps:
            r = fs.run_fixed(model, p, y0, t_end, int(round(n * t_end / 2000.0 if not quick else n)), tb)
            err = float(np.max(np.abs(r["y_end"] - ref.y_end))) if r["ok"] else None
            rows.append({"h": r["h"], "ok": r["ok"], "t_fail": r["t_fail"], "error": err, "n_rhs": r["n_rhs"],
                         "wall_s": round(r["wall_s"], 6)})
        blow = fs.blow_up_step(model, p, y0, t_end, tb, np.geomspace(0.05, 2.0, 16 if quick else 30))
        h_blow = blow["h_blow"]
        pred = spec["predicted_h_limit"][name]["h"]
        rec = {"stages": len(tb[1]), "boundary_real_axis": fs.stability_boundary(tb, math.pi),
               "boundary_imaginary_axis": fs.stability_boundary(tb, math.pi / 2),
               "boundary_at_arg_rho_max": fs.stability_boundary(tb, abs(spec["arg_at_rho_max"])),
               "runs": rows, "blow_up": blow, "h_blow": h_blow, "predicted_h_limit": pred,
               "h_blow_times_rho_max": None if h_blow is None else h_blow * spec["rho_max"],
               "h_blow_over_predicted": None if h_blow is None else h_blow / pred}
        out["tableaus"][name] = rec
        _say(progress, f"fixed step {name:7s}: blow-up h {h_blow}, h|lambda|max {rec['h_blow_times_rho_max']}, "
                       f"predicted {pred:.4f}")
    return out


# ---------------------------------------------------------------------------------------- Jacobi

def jacobi_part(quick: bool, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from . import jacobi as bj

    model = load_model(PROBLEM_A.model)
    p = model.params({"zeta": 0.0, "beta": 0.0})
    y0 = model.state(PROBLEM_A.y0)
    H = bj.jacobi_function(model.n_coordinates - 2)
    J0 = float(H(model, y0[:, None], p)[0])
    t_end = 1e3 if quick else 1e5
    h = 0.02
    stride = 50
    out = {"model": model.name, "parameters": {"zeta": 0.0, "beta": 0.0, **{k: float(v) for k, v in zip(
        model.param_names, p) if k not in ("zeta", "beta")}}, "y0": PROBLEM_A.y0, "t_end": t_end, "J0": J0,
        "integral": "h = sum q' dL/dq' - L of the rotating-frame Lagrangian (families/single_plane/jacobi.py), "
                    "lambdified with SymPy in the benchmark", "methods": {}}
    runs = {}
    for eng, rtol, atol in (("cyrk-dop853", 1e-8, 1e-10), ("cvode-bdf", 1e-8, 1e-10)):
        s = simulate(model, p, y0, t_end=t_end, rtol=rtol, atol=atol, engine=eng, keep_trajectory=True,
                     samples=20001, check=False)
        runs[eng] = ({"kind": "explicit" if eng.startswith("cyrk") else "implicit", "rtol": rtol, "atol": atol,
                      "status": s.status, "n_rhs": int(s.n_rhs), "n_steps": int(s.n_steps),
                      "wall_s": round(s.wall_s, 4)}, s.t, s.y)
    times = np.arange(1, int(round(t_end / (h * stride))) + 1) * h * stride
    m = bj.midpoint(model, p, y0, h, times)
    runs["arkode-implicit-midpoint"] = ({"kind": "structure-preserving (symmetric, symplectic in canonical "
                                                 "variables)", "h": h, "status": m["status"], "n_rhs": m["n_rhs"],
                                         "n_steps": m["n_steps"], "newton_iters": m["newton_iters"],
                                         "jac_evals": m["jac_evals"], "wall_s": round(m["wall_s"], 4)},
                                        np.concatenate([[0.0], m["t"]]), np.column_stack([y0, m["y"]]))
    for name, (rec, t, Y) in runs.items():
        J = H(model, Y, p)
        rec.update(bj.drift_curve(t, J, J0))
        # growth law: slope of log max|dJ| against log t over the last two decades
        tt, ee = np.array(rec["t"]), np.array(rec["max_abs_dJ"])
        sel = (tt >= t_end / 100) & (ee > 0)
        rec["loglog_slope_last_two_decades"] = (float(np.polyfit(np.log(tt[sel]), np.log(ee[sel]), 1)[0])
                                                if sel.sum() > 2 else None)
        out["methods"][name] = rec
        _say(progress, f"jacobi {name:26s} max |dJ| {rec['max_abs_dJ_all']:.3e} final {rec['final_abs_dJ']:.3e} "
                       f"wall {rec['wall_s']} s")
    return out


# ----------------------------------------------------------------------------------------- stiff

def stiff_part(quick: bool, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate

    model = load_model(PROBLEM_A.model)
    t_end = 20.0 if quick else 200.0
    betas = STIFF_BETAS[::2] if quick else STIFF_BETAS
    mu = float(model.params()[model.param_names.index("mu")])
    max_steps = 200_000 if quick else 2_000_000
    out = {"model": model.name, "y0": PROBLEM_A.y0, "t_end": t_end, "rtol": 1e-6, "atol": 1e-9, "mu": mu,
           "max_steps": max_steps, "rows": []}
    for beta in betas:
        p = model.params({"beta": beta})
        y0 = model.state(PROBLEM_A.y0)
        lam = np.linalg.eigvals(np.asarray(model.module.jac(0.0, y0, p)))
        row = {"beta": beta, "beta_over_mu": beta / mu, "rho_at_start": float(np.max(np.abs(lam))),
               "engines": {}}
        for eng in STIFF_ENGINES:
            s = simulate(model, p, y0, t_end=t_end, rtol=1e-6, atol=1e-9, engine=eng, keep_trajectory=False,
                         max_steps=max_steps, check=False)
            row["engines"][eng] = {"status": s.status, "n_rhs": int(s.n_rhs), "n_steps": int(s.n_steps),
                                   "wall_s": round(s.wall_s, 5), "t_fail": s.t_fail,
                                   "y_end": dict(zip(model.state_names, map(float, s.y_end)))}
            _say(progress, f"stiff beta {beta:7g} {eng:12s} {s.status:10s} steps {s.n_steps:9d} "
                           f"wall {1e3 * s.wall_s:9.1f} ms")
        ok = [e for e in row["engines"].values() if e["status"] == "success"]
        if len(ok) > 1:
            ends = np.array([[e["y_end"][k] for k in model.state_names] for e in ok])
            row["spread_of_final_states"] = float(np.max(ends.max(axis=0) - ends.min(axis=0)))
        out["rows"].append(row)
    return out


# -------------------------------------------------------------------------------------- symmetry

def symmetry_part(quick: bool, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from .pathways import engine_pathway
    from .problems import Problem
    from . import fixed_step as fs

    model = load_model(PROBLEM_A.model)
    t_end = 200.0 if quick else PROBLEM_A.t_end
    problem = Problem("A", PROBLEM_A.model, {}, PROBLEM_A.y0, t_end)
    y_sym = symmetric_y0(model)
    out = {"y0": y_sym, "t_end": t_end, "thesis_2minus": dict(THESIS_2MINUS),
           "runs": {}}
    for eng in SYMMETRY_ENGINES[:3] if quick else SYMMETRY_ENGINES:
        r = engine_pathway(model, problem, eng, y0=y_sym).run()
        out["runs"][eng] = symmetry_record(model, r["y_end"]) | {"wall_s": round(r["wall_s"], 4)}
    p = model.params()
    r = fs.run_fixed(model, p, model.state(y_sym), t_end, int(round(t_end / 0.05)), fs.RK4)
    out["runs"]["fixed-rk4 (h = 0.05, numba)"] = symmetry_record(model, r["y_end"]) | {"wall_s": round(r["wall_s"], 4)}
    for name, rec in out["runs"].items():
        _say(progress, f"symmetry {name:28s} bitwise {rec['bitwise_equal']!s:5s} 2- {rec['ends_at_2minus']!s:5s} "
                       f"x {rec['x']:.4f} y {rec['y']:.4f}")
    out["peers"] = "JiTCODE and heyoka: see benchmarks/simulate.json symmetry (adbgen bench simulate)"
    return out


# --------------------------------------------------------------------------------------- merging

def _merge_stats(t, sep) -> dict:
    """Per pair: minimal separation, when, the final one, and the time from which it is exactly 0 to
    the end (merged for ever), if it is."""
    t = np.asarray(t)
    out = []
    for row in np.atleast_2d(sep):
        k = int(np.argmin(row))
        nz = np.nonzero(row != 0)[0]
        merged_from = None
        if row[-1] == 0:
            merged_from = float(t[nz[-1] + 1]) if len(nz) else float(t[0])
        out.append({"min": float(row[k]), "t_min": float(t[k]), "final": float(row[-1]), "merged_from": merged_from})
    return out


def _pairs_equal(y, ia, ib) -> list:
    """Per race: both the angles and the rates of its two balls the same double (merged for ever)."""
    eq = np.asarray(y)[ia] == np.asarray(y)[ib]
    return [bool(eq[2 * q] and eq[2 * q + 1]) for q in range(len(ia) // 2)]


def _log_curve(t, sep, points: int = 300) -> dict:
    t = np.asarray(t)
    idx = np.unique(np.linspace(0, len(t) - 1, points).astype(int))
    return {"t": t[idx].tolist(), "sep": np.atleast_2d(sep)[:, idx].tolist()}


def merging_part(quick: bool, progress=None) -> dict:
    from adbgen.analysis.loading import load_model
    from adbgen.analysis.simulate import simulate
    from . import pairs as bp

    out: dict = {"hill": {}, "thesis_n2": {}}
    # (a) the section-6 Hill run-up
    m = load_model("two_plane_hill")
    mass = float(m.params()[m.param_names.index("m_1")])
    ia, ib = bp.pair_indices(m, HILL_PAIRS)
    a_ang = np.array([m.index(k) for k, _ in HILL_PAIRS])
    b_ang = np.array([m.index(l) for _, l in HILL_PAIRS])
    t_end = 1000.0 if quick else 3000.0
    y0 = m.state({"theta_2": math.pi, "theta_4": math.pi})
    _, pair_in, _ = bp.make_pair_rhs(m, HILL_PAIRS, compensate=True)
    _, pair_nc, _ = bp.make_pair_rhs(m, HILL_PAIRS, compensate=False)
    ix = m.index("X")
    for ratio in ((0.1,) if quick else (0.1, 0.01)):
        cb = ratio * mass
        p = m.params({"c_bb": cb, "c_bt": cb})
        case = {"c_b_over_m": ratio, "c_bb": cb, "c_bt": cb, "t_end": t_end, "rtol": 1e-10, "atol": 1e-12,
                "y0": "rotor at rest, theta_2 = theta_4 = pi (balls of a race on opposite sides)", "pathways": {}}
        for eng in (MERGE_ENGINES[:2] if quick else MERGE_ENGINES):
            s = simulate(m, p, y0, t_end=t_end, rtol=1e-10, atol=1e-12, engine=eng, samples=20001, check=False)
            sep = bp.separation(s.y, a_ang, b_ang)
            case["pathways"][eng] = {"formulation": "original", "status": s.status, "pairs": _merge_stats(s.t, sep),
                                     "final_bitwise_equal": _pairs_equal(s.y_end, ia, ib),
                                     "X_end": float(s.y_end[ix]), "wall_s": round(s.wall_s, 4),
                                     "points": int(len(s.t)), "curve": _log_curve(s.t, sep)}
        for label, fn, z0, pair in (
                ("cyrk DOP853 (numba callback), original", m.module.rhs_inplace, y0, False),
                ("cyrk DOP853 (numba callback), pair coordinates", pair_in, bp.to_pairs(y0, ia, ib), True),
                ("cyrk DOP853 (numba callback), pair coordinates without the rounding correction", pair_nc,
                 bp.to_pairs(y0, ia, ib), True)):
            r = bp.cyrk_solve(fn, m.n_states, z0, p, t_end, 1e-10, 1e-12)
            Y = r["y"]
            sep = bp.wrapped(2 * Y[b_ang]) if pair else bp.separation(Y, a_ang, b_ang)
            y_end = bp.from_pairs(Y[:, -1], ia, ib) if pair else Y[:, -1]
            case["pathways"][label] = {"formulation": "pair" if pair else "original", "status": r["status"],
                                       "final_bitwise_equal": _pairs_equal(y_end, ia, ib) if not pair else
                                       [bool(Y[ib[2 * q], -1] == 0 and Y[ib[2 * q + 1], -1] == 0)
                                        for q in range(len(HILL_PAIRS))],
                                       "pairs": _merge_stats(r["t"], sep), "X_end": float(y_end[ix]),
                                       "wall_s": round(r["wall_s"], 4), "points": int(len(r["t"])),
                                       "curve": _log_curve(r["t"], sep)}
        for name, rec in case["pathways"].items():
            _say(progress, f"merging hill c_b/m={ratio:g} {name[:60]:60s} min sep {[q['min'] for q in rec['pairs']]} "
                           f"merged from {[q['merged_from'] for q in rec['pairs']]} X_end {rec['X_end']:.6g}")
        out["hill"][f"{ratio:g}"] = case
    # (b) thesis n = 2 from a separation below round-off
    m2 = load_model("thesis_rotating_n2")
    pairs2 = (("phi_1", "phi_2"),)
    ia2, ib2 = bp.pair_indices(m2, pairs2)
    _, pin2, _ = bp.make_pair_rhs(m2, pairs2, compensate=True)
    _, pnc2, _ = bp.make_pair_rhs(m2, pairs2, compensate=False)
    p2 = m2.params()
    t2 = 500.0 if quick else 2000.0
    i1, i2 = m2.index("phi_1"), m2.index("phi_2")
    jx, jy = m2.index("x"), m2.index("y")
    for d0 in ((1e-20,) if quick else (1e-20, 1e-17, 1e-15, 1e-12)):
        row = {"d0": d0, "t_end": t2, "runs": {}}
        y0o = m2.state({"phi_1": math.pi + d0, "phi_2": math.pi - d0})
        zp = m2.state({"phi_1": math.pi, "phi_2": d0})
        for label, fn, z, pair in (("original", m2.module.rhs_inplace, y0o, False),
                                   ("pair coordinates", pin2, zp, True),
                                   ("pair coordinates without the rounding correction", pnc2, zp, True)):
            r = bp.cyrk_solve(fn, m2.n_states, z, p2, t2, 1e-10, 1e-12)
            Y = r["y"]
            y_end = bp.from_pairs(Y[:, -1], ia2, ib2) if pair else Y[:, -1]
            sep = bp.wrapped(2 * Y[i2]) if pair else bp.wrapped(Y[i1] - Y[i2])
            row["runs"][label] = {"start_separation_represented": float(sep[0]), "final_separation": float(sep[-1]),
                                  "r_end": float(math.hypot(y_end[jx], y_end[jy])), "status": r["status"],
                                  "curve": _log_curve(r["t"], sep[None, :])}
            _say(progress, f"merging thesis n=2 d0={d0:g} {label:50s} start {sep[0]:.3g} final sep {sep[-1]:.4g} "
                           f"r_end {math.hypot(y_end[jx], y_end[jy]):.3g}")
        out["thesis_n2"][f"{d0:g}"] = row
    out["thesis_n2_model"] = {"model": m2.name, "parameters": dict(zip(m2.param_names, map(float, p2)))}
    return out


# ----------------------------------------------------------------------------------------- charts

def charts(result: dict, out: Path) -> list[Path]:
    plt = pyplot()

    paths = []
    stem = out.with_suffix("")

    def save(fig, part):
        fig.tight_layout()
        paths.append(save_figure(fig, f"{stem}_{part}.png", dpi=110))

    stamp = f"{when(result)} UTC, load {result['machine']['load_average_at_start']}"
    fx = result.get("fixed_step")
    if fx:
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        for (name, rec), col in zip(fx["tableaus"].items(), ("C0", "C1", "C2")):
            pts = [(r["h"], r["error"]) for r in rec["runs"] if r["ok"] and r["error"]]
            if pts:
                ax.loglog(*zip(*pts), "o-", color=col, label=f"{name} (stages {rec['stages']})")
            if rec["h_blow"]:
                ax.axvline(rec["h_blow"], color=col, ls="--", lw=1)
            ax.axvline(rec["predicted_h_limit"], color=col, ls=":", lw=1)
        ax.set_xlabel("fixed step h")
        ax.set_ylabel("error of the final state (max abs)")
        ax.set_title(f"Problem A by fixed-step RK: dashed = measured blow-up step, dotted = stability limit\n"
                     f"predicted from the Jacobian's spectrum along the trajectory (|lambda|max "
                     f"{fx['spectrum']['rho_max']:.3f}); {stamp}", fontsize=8)
        ax.legend(fontsize=8)
        save(fig, "fixed_step")
    jc = result.get("jacobi")
    if jc:
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        for name, rec in jc["methods"].items():
            t, e = np.array(rec["t"]), np.array(rec["max_abs_dJ"])
            keep = e > 0
            extra = f"h = {rec['h']}" if "h" in rec else f"rtol {rec['rtol']:g}"
            ax.loglog(t[keep], e[keep], label=f"{name} ({rec['kind'].split(' ')[0]}, {extra}; {rec['wall_s']:.3g} s)")
        ax.set_xlabel("t")
        ax.set_ylabel("max over [0, t] of |J - J(0)|")
        ax.set_title(f"Jacobi integral, thesis n = 3, zeta = beta = 0, t to {jc['t_end']:g}\n{stamp}", fontsize=8)
        ax.legend(fontsize=7)
        save(fig, "jacobi")
    st = result.get("stiff")
    if st:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        for eng in STIFF_ENGINES:
            xs, steps, walls = [], [], []
            for row in st["rows"]:
                e = row["engines"].get(eng)
                if e:
                    xs.append(row["beta"])
                    steps.append(e["n_steps"])
                    walls.append(e["wall_s"])
            axes[0].loglog(xs, steps, "o-", label=eng)
            axes[1].loglog(xs, walls, "o-", label=eng)
        axes[0].set_ylabel(f"steps (cap {st['max_steps']})")
        axes[1].set_ylabel("wall time [s]")
        for ax in axes:
            ax.set_xlabel("ball damping beta (Jacobian spectral radius ~ beta)")
            ax.legend(fontsize=7)
        fig.suptitle(f"Stiffness: thesis n = 3, t in [0, {st['t_end']:g}], rtol {st['rtol']:g}; {stamp}", fontsize=9)
        save(fig, "stiff")
    mg = result.get("merging")
    if mg and mg.get("hill"):
        cases = list(mg["hill"].values())
        fig, axes = plt.subplots(1, len(cases) + 1, figsize=(5 * (len(cases) + 1), 4.2))
        for ax, case in zip(axes, cases):
            for name, rec in case["pathways"].items():
                if not (name.startswith("cyrk") or name in ("cvode-bdf", "scipy-dop853")):
                    continue
                t = np.array(rec["curve"]["t"])
                s = np.array(rec["curve"]["sep"][0])
                ax.semilogy(t, np.maximum(s, 1e-30), lw=1, label=name.replace("cyrk DOP853 (numba callback), ", ""))
            ax.axhline(1e-30, color="k", lw=0.5)
            ax.set_title(f"Hill run-up (45), c_b/m = {case['c_b_over_m']:g}: |theta_1 - theta_2|\n"
                         "(0 drawn at 1e-30)", fontsize=8)
            ax.set_xlabel("t")
            ax.legend(fontsize=6)
        ax = axes[-1]
        for d0, row in mg["thesis_n2"].items():
            for label, rec in row["runs"].items():
                t = np.array(rec["curve"]["t"])
                s = np.array(rec["curve"]["sep"][0])
                ls = {"original": "-", "pair coordinates": "--"}.get(label, ":")
                ax.semilogy(t, np.maximum(s, 1e-30), ls, lw=1, label=f"d0 {d0}, {label[:28]}")
        ax.set_title("thesis n = 2 from phi = pi +- d0: |phi_1 - phi_2|", fontsize=8)
        ax.set_xlabel("t")
        ax.legend(fontsize=5)
        fig.suptitle(stamp, fontsize=8)
        save(fig, "merging")
    return paths


# ------------------------------------------------------------------------------------------ main

PARTS = {"fixed_step": fixed_step_part, "jacobi": jacobi_part, "stiff": stiff_part, "symmetry": symmetry_part,
         "merging": merging_part}


def bench_failures(quick: bool = False, parts=None, progress=None) -> dict:
    result, started = opening("failures")
    result.update({"quick": quick, "seconds_per_part": {}})
    for name in parts or PARTS:
        t0 = time.perf_counter()
        result[name] = PARTS[name](quick, progress)
        result["seconds_per_part"][name] = round(time.perf_counter() - t0, 1)
        result.setdefault("load_average_after_part", {})[name] = load_average()
    return closing(result, started)


def run(args, out: str) -> int:
    result = bench_failures(quick=args.quick, progress=lambda line: print(line, flush=True))
    path = write(result, out)
    pngs = charts(result, Path(out))
    print(f"wrote {path} and {', '.join(map(str, pngs))} ({result['seconds']} s)")
    return 0


BENCHMARK = Benchmark("failures", run, (QUICK.but("short runs (checks the machinery)"),))


__all__ = ["BENCHMARK", "PARTS", "bench_failures", "charts"]
