"""Benchmark (not a test): speed against accuracy, `adbgen bench precision` (issue 14, items 1 and 2).

Work-precision: for each problem, every pathway integrates from t = 0 to t_end at the tolerances
`TOLS` (rtol = tol, atol = tol x the problem's `atol_ratio`); its global error is the largest
absolute difference of the final state from a reference, plotted against the CPU time of the
integration (`TIME`; wall time recorded beside it; one curve per pathway, `chart`).  The reference
is CyRK's Verner 8(7) at rtol 1e-14 (not the default's method), checked by heyoka's Taylor method at
tol 1e-15 (another method, another implementation; CyRK's DOP853 where heyoka fails): their
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

import datetime
import math
import shutil
import subprocess
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .simulate import Pathway, Problem, _load, _target, engine_pathway, error, measure, time_at_error

TOLS = tuple(10.0 ** -k for k in range(3, 13))
QUICK_TOLS = (1e-4, 1e-7)
REF_TOL = 1e-14
CHECK_TOL = 1e-15
SLOW_S = 0.5
MAX_RUN_S = 20.0
QUICK_MAX_RUN_S = 0.5
BUDGET_S = 480.0
QUICK_BUDGET_S = 40.0
PROBE_FRACTION = 0.01
CHEAP_S = 0.5  # runs faster than this go on after the time budget is spent
# heyoka's default mode compiles a large rhs (the Hill run-up's series) for minutes at high order (measured
# 71 s at tol 1e-15 for B, 240 statements); above this many it runs in compact mode (2-3 s per tolerance)
HEYOKA_COMPACT_ABOVE = 150
ATTRACTOR_TOL = 1e-2
TDEC_REL = 0.01
TDEC_DT = 0.25
THRESHOLD = 1e-3
TARGET_ERROR = 1e-8
# the charts and targets compare CPU time (this process and its children; single-threaded pathways):
# on the shared machine it moves less with the load than wall time, which is recorded beside it
TIME = "cpu_s"
CHART_RANGE = (1e-12, 1e-4)
CVODE_LIBS = ("-lsundials_cvode", "-lsundials_nvecserial", "-lsundials_sunmatrixdense",
              "-lsundials_sunlinsoldense", "-lm")


@dataclass(frozen=True)
class PrecisionProblem:
    problem: Problem
    atol_ratio: float
    what: str
    thesis_model: bool = True  # the hand-written baseline applies

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
                          1e-2, "stiff: thesis n = 3, beta = 1000, mu = 0.01, else (5.1), phi(0) as A"),
}


# ------------------------------------------------------------------------------------ pathways

@dataclass
class Curve:
    """One pathway across the tolerances: make(tol, t_end) -> a `Pathway` (run once per tolerance)."""

    name: str
    kind: str  # engine, ivp, cvode-main, peer
    description: str
    make: Callable[[float, float], Pathway]
    adbgen: bool  # generated code on an adbgen pathway (the targets' "adbgen pathway")
    t_dec_of: Callable[[float], float | None] | None = None  # untimed t_dec run (peers, cvode-main)
    setup: dict = field(default_factory=dict)
    points: list = field(default_factory=list)  # Pathway per tolerance that ran
    skipped: list = field(default_factory=list)
    probe: dict | None = None


def _t_dec_grid(t, r, threshold: float = THRESHOLD) -> float | None:
    """sup{t: r(t) >= threshold} from samples (linear between them); None if r ends above it."""
    r = np.asarray(r, float)
    if not len(r) or not np.all(np.isfinite(r)) or r[-1] >= threshold:
        return None
    above = np.nonzero(r >= threshold)[0]
    if not len(above):
        return 0.0
    k = above[-1]
    w = (r[k] - threshold) / (r[k] - r[k + 1])
    return float(t[k] + w * (t[k + 1] - t[k]))


def _ivp_curve(model, pp: PrecisionProblem, key: str, description: str, rhs, method: str, setup: dict,
               adbgen: bool, want_t_dec: bool) -> Curve:
    """solve_ivp on a Python-callable rhs(t, y, p) (no events; dense output for t_dec only)."""
    from scipy.integrate import solve_ivp

    p, y0 = pp.problem.vectors(model)
    ix, iy = model.amplitude_indices[:2]

    def make(tol, t_end):
        def run():
            start, cpu = time.perf_counter(), time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                sol = solve_ivp(rhs, (0.0, t_end), y0, method=method, args=(p,), rtol=tol, atol=tol * pp.atol_ratio,
                                dense_output=want_t_dec)
            wall, cpu = time.perf_counter() - start, time.process_time() - cpu
            out = {"wall_s": wall, "cpu_s": cpu, "y_end": sol.y[:, -1].copy(), "n_rhs": int(sol.nfev),
                   "n_steps": len(sol.t) - 1,
                   "status": "success" if sol.status == 0 else f"failed: {sol.message}"}
            if want_t_dec and sol.status == 0:
                grid = np.arange(0.0, t_end + TDEC_DT / 2, TDEC_DT)
                yy = sol.sol(grid)
                out["t_dec"] = _t_dec_grid(grid, np.hypot(yy[ix], yy[iy]))
            return out

        return Pathway(f"{key}@{tol:g}", "ivp", key, tol, run)

    return Curve(key, "ivp", description, make, adbgen, setup=setup)


def lambdify_rhs(model_name: str) -> tuple[Callable, dict]:
    """sympy.lambdify(modules="math", cse=True) of a model's equations as rhs(t, y, p) -> ndarray.

    The closed form (Cramer's rule on the rotor core) where adbgen has one (core <= 3 coordinates);
    otherwise the mass matrix and forcing lambdified and solved by numpy.linalg.solve per call."""
    import sympy as sp

    from .. import families

    start = time.perf_counter()
    spec = next((s for f in families.all_families() for s in f.models() if s.name == model_name), None)
    if spec is None:
        raise KeyError(f"no model spec named {model_name!r}")
    system = spec.system()
    eom = system.solve.eom
    law = dict(eom.driven_law)
    args = (eom.time, list(system.states), [q.symbol for q in system.parameters])
    if len(system.solve.core) <= 3:
        closed = [sp.sympify(e).xreplace(law) for e in system.rhs()]
        fn = sp.lambdify(args, closed, modules="math", cse=True)
        form = "closed form (Cramer's rule), sympy.lambdify(modules='math', cse=True)"

        def rhs(t, y, p):
            return np.asarray(fn(t, y, p), float)
    else:
        size = eom.size
        M = sp.zeros(size, size)
        for (i, j), e in eom.mass.items():
            M[i, j] = sp.sympify(e).xreplace(law)
        f = [sp.sympify(e).xreplace(law) for e in eom.forcing]
        fm = sp.lambdify(args, M.tolist(), modules="math", cse=True)
        ff = sp.lambdify(args, f, modules="math", cse=True)
        form = ("mass matrix and forcing, sympy.lambdify(modules='math', cse=True), numpy.linalg.solve per call "
                "(adbgen has no closed form for a core of more than 3 coordinates)")

        def rhs(t, y, p):
            acc = np.linalg.solve(np.asarray(fm(t, y, p), float), np.asarray(ff(t, y, p), float))
            return np.concatenate([np.asarray(y[size:], float), acc])
    return rhs, {"form": form, "lambdify_s": round(time.perf_counter() - start, 3)}


def _rhs_difference(model, rhs, samples: int = 20, seed: int = 0) -> float:
    rng = np.random.default_rng(seed)
    p = model.params()
    worst = 0.0
    for _ in range(samples):
        y = rng.uniform(-1.0, 1.0, model.n_states) * 0.1
        t = float(rng.uniform(0.0, 300.0))
        ref = np.asarray(model.module.rhs(t, y, p), float)
        worst = max(worst, float(np.max(np.abs(np.asarray(rhs(t, y, p)) - ref)) / np.max(np.abs(ref))))
    return worst


class CvodeMain:
    """The emitted ``<model>_cvode_main.c`` built with gcc -O2 against SUNDIALS, run as a program."""

    def __init__(self, model, folder: Path):
        name = model.name
        src = model.c_source().parent
        sources = [src / f"{name}_cvode_main.c", src / f"{name}_cvode.c", src / f"{name}.c"]
        cc = shutil.which("gcc") or shutil.which("cc")
        if not cc or not all(s.is_file() for s in sources):
            raise RuntimeError("no C compiler or no emitted CVODE driver")
        self.exe = folder / f"{name}_cvode_main"
        start = time.perf_counter()
        subprocess.run([cc, "-std=c99", "-O2", "-I", str(src), "-o", str(self.exe), *map(str, sources), *CVODE_LIBS],
                       check=True, capture_output=True, text=True)
        self.compile_s = time.perf_counter() - start
        self.names = model.state_names

    def run(self, y0, p, t_end, rtol, atol, n_out: int = 1) -> dict:
        cmd = [str(self.exe), repr(float(t_end)), str(n_out), repr(rtol), repr(atol), *map(repr, map(float, y0)), "--",
               *map(repr, map(float, p))]
        start = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            return {"wall_s": wall, "y_end": None, "status": f"failed: {proc.stderr.strip()[:200]}", "n_rhs": None,
                    "n_steps": None}
        rows = np.array([[float(v) for v in line.split()] for line in proc.stdout.splitlines() if line.strip()])
        stats = dict(item.split("=") for item in proc.stderr.split() if "=" in item)
        return {"wall_s": wall, "y_end": rows[-1, 1:], "t": rows[:, 0], "y": rows[:, 1:].T, "status": "success",
                "n_rhs": int(stats["rhs_evals"]) if "rhs_evals" in stats else None,
                "n_steps": int(stats["steps"]) if "steps" in stats else None}


def curves(model, pp: PrecisionProblem, folder: Path, *, engines=None, peers: bool = True, lambdify: bool = True,
           want_t_dec: bool = False, progress=None) -> list[Curve]:
    """Every pathway of the benchmark for one problem (set up, compiled and warmed, not yet timed)."""
    from . import baseline as bench_baseline
    from ..analysis.engines import DEFAULT, ENGINES

    say = progress or (lambda line: None)
    problem = pp.problem
    p, y0 = problem.vectors(model)
    out: list[Curve] = []
    names = list(engines) if engines else list(ENGINES)
    if DEFAULT not in names:
        names.insert(0, DEFAULT)
    for name in names:
        def make(tol, t_end, name=name):
            pr = Problem(problem.label, problem.model, problem.params, problem.y0, t_end)
            return engine_pathway(model, pr, name, rtol=tol, atol=tol * pp.atol_ratio, key=f"{name}@{tol:g}")

        out.append(Curve(name, "engine", ENGINES[name].description, make, adbgen=True))

    out.append(_ivp_curve(model, pp, "ivp:numba-dop853", "generated numba rhs, solve_ivp DOP853, no events",
                          model.module.rhs, "DOP853", {}, True, want_t_dec))
    if pp.thesis_model:
        bench_baseline.check_layout(model.module)
        setup = {"max_relative_difference_to_generated": bench_baseline.max_difference(model.module, samples=50)}
        out.append(_ivp_curve(model, pp, "ivp:handwritten-dop853",
                              "hand-written numba rhs of thesis Appendix A (bench.baseline), solve_ivp DOP853",
                              bench_baseline.rhs, "DOP853", setup, False, want_t_dec))
    if lambdify:
        try:
            rhs, setup = lambdify_rhs(model.name)
            setup["max_relative_difference_to_generated"] = _rhs_difference(model, rhs)
            for method in ("RK45", "DOP853"):
                out.append(_ivp_curve(model, pp, f"ivp:lambdify-{method.lower()}",
                                      f"{setup['form']}, solve_ivp {method}", rhs, method, dict(setup), False,
                                      want_t_dec))
            say(f"lambdify: {setup}")
        except Exception as exc:  # recorded, not fatal
            say(f"lambdify failed: {type(exc).__name__}: {exc}")
    try:
        cv = CvodeMain(model, folder)
    except Exception as exc:
        say(f"cvode-main not built: {exc}")
    else:
        ix, iy = model.amplitude_indices[:2]

        def make_cv(tol, t_end):
            return Pathway(f"cvode-main@{tol:g}", "cvode-main", "cvode-main", tol,
                           lambda: cv.run(y0, p, t_end, tol, tol * pp.atol_ratio))

        def t_dec_cv(tol):
            res = cv.run(y0, p, problem.t_end, tol, tol * pp.atol_ratio, n_out=int(problem.t_end / TDEC_DT))
            return _t_dec_grid(res["t"], np.hypot(res["y"][ix], res["y"][iy])) if res["y_end"] is not None else None

        out.append(Curve("cvode-main", "cvode-main", "emitted <model>_cvode_main.c (CVODE BDF, Newton, dense, "
                         "generated Jacobian), gcc -O2, run as a process (start-up included)", make_cv, adbgen=True,
                         t_dec_of=t_dec_cv if want_t_dec else None, setup={"compile_s": round(cv.compile_s, 3)}))
    if peers:
        out += _peer_curves(model, pp, want_t_dec, say)
    return out


def heyoka_compact(model) -> bool:
    from .peers import generated_program

    return len(generated_program(model.module)[0]) > HEYOKA_COMPACT_ABOVE


def _peer_curves(model, pp: PrecisionProblem, want_t_dec: bool, say) -> list[Curve]:
    from . import peers as bench_peers

    problem = pp.problem
    p, y0 = problem.vectors(model)
    ix, iy = model.amplitude_indices[:2]
    grid = np.arange(0.0, problem.t_end + TDEC_DT / 2, TDEC_DT)
    out = []
    compact = heyoka_compact(model)
    for name, cls in bench_peers.PEERS.items():
        try:
            peer = cls(model.module, compact_mode=compact) if name == "heyoka" else cls(model.module)
        except Exception as exc:  # not installed or failed to build: recorded, not fatal
            say(f"peer {name} unavailable: {exc}")
            continue
        setup = {"translate_s": round(peer.translate_s, 4),
                 "equations_max_relative_difference": bench_peers.check_equations(peer, model.module, p)}
        if name == "jitcode":
            setup["compile_s"] = round(peer.compile_s, 3)

            def make(tol, t_end, peer=peer):
                return Pathway(f"peer:jitcode-dop853@{tol:g}", "peer", "peer:jitcode-dop853", tol,
                               lambda: peer.run(y0, p, t_end, tol, tol * pp.atol_ratio))

            def t_dec_of(tol, peer=peer):
                peer.ode.set_integrator("dop853", rtol=tol, atol=tol * pp.atol_ratio)
                peer.ode.set_parameters(*map(float, p))
                peer.ode.set_initial_value(np.asarray(y0, float), 0.0)
                ys = np.array([y0] + [peer.ode.integrate(t) for t in grid[1:]])
                return _t_dec_grid(grid, np.hypot(ys[:, ix], ys[:, iy]))

            out.append(Curve("peer:jitcode-dop853", "peer", "JiTCODE (helpers = the generated statements), "
                             "dop853 backend (scipy ode, a Python call per evaluation)", make, adbgen=False,
                             t_dec_of=t_dec_of if want_t_dec else None, setup=setup))
        else:
            setup["compile_s"] = {}
            setup["compact_mode"] = compact

            def make(tol, t_end, peer=peer, setup=setup):
                if tol not in peer._integrators:
                    peer.integrator(tol, y0, p, cold=False)
                    setup["compile_s"][f"{tol:g}"] = round(peer.compile_s[tol], 3)
                return Pathway(f"peer:heyoka@{tol:g}", "peer", "peer:heyoka", tol, lambda: peer.run(y0, p, t_end, tol))

            def t_dec_of(tol, peer=peer):
                ta = peer.integrator(tol, y0, p, cold=False)
                ta.time = 0.0
                ta.state[:] = np.asarray(y0, float)
                ta.pars[:] = np.asarray(p, float)
                res = ta.propagate_grid(grid)
                ys = np.asarray(res[-1])
                return _t_dec_grid(grid, np.hypot(ys[:, ix], ys[:, iy]))

            out.append(Curve("peer:heyoka", "peer", "heyoka adaptive Taylor (LLVM), tol = rtol = atol; compiled per "
                             "tolerance outside the timings (caches allowed)", make, adbgen=False,
                             t_dec_of=t_dec_of if want_t_dec else None, setup=setup))
        say(f"peer {name}: {setup}")
    return out


# ----------------------------------------------------------------------------------- reference

def reference(model, pp: PrecisionProblem, t_end: float, ref_tol: float = REF_TOL,
              check_tol: float = CHECK_TOL) -> dict:
    """Final state by CyRK Vern8 at rtol ref_tol, checked by heyoka's Taylor method at check_tol (or, if
    heyoka is missing, CyRK DOP853 at ref_tol): their difference is the reference's resolution."""
    from ..analysis.simulate import simulate

    p, y0 = pp.problem.vectors(model)
    start = time.perf_counter()
    ref = simulate(model, p, y0, t_end=t_end, rtol=ref_tol, atol=ref_tol * pp.atol_ratio, engine="cyrk-vern8",
                   keep_trajectory=False)
    out = {"method": "cyrk-vern8 (CyRK Verner 8(7), compiled)", "rtol": ref_tol, "atol": ref_tol * pp.atol_ratio,
           "seconds": round(time.perf_counter() - start, 3), "n_rhs": int(ref.n_rhs), "y_end": ref.y_end.copy(),
           "t_dec": ref.t_dec, "r_max": ref.r_max}
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


def stiffness(model, pp: PrecisionProblem) -> dict:
    """Eigenvalues of the generated Jacobian at the initial state: the stiffness ratio
    max |Re lambda| / min |Re lambda| over the eigenvalues with |Re lambda| > 1e-12."""
    p, y0 = pp.problem.vectors(model)
    ev = np.linalg.eigvals(np.asarray(model.module.jac(0.0, y0, p), float))
    re = np.abs(ev.real)
    nz = re[re > 1e-12]
    return {"eigenvalues_real_sorted": sorted(float(v) for v in ev.real),
            "stiffness_ratio": float(nz.max() / nz.min()) if len(nz) else None}


# ---------------------------------------------------------------------------------------- sweep

def sweep(model, pp: PrecisionProblem, cs: list[Curve], tols, *, t_end: float, repeats: int, max_run_s: float,
          budget_s: float, progress=None) -> None:
    """Run the curves from loose to tight tolerance with the cost control of the module docstring."""
    say = progress or (lambda line: None)
    started = time.perf_counter()
    tols = sorted(tols, reverse=True)
    active = []
    for c in cs:  # probe: the loosest tolerance over a short horizon
        horizon = t_end * PROBE_FRACTION
        try:
            res = c.make(tols[0], horizon).run()
        except Exception as exc:
            c.skipped.append({"tol": tols[0], "reason": f"error in the probe: {type(exc).__name__}: {exc}"})
            continue
        predicted = res["wall_s"] / PROBE_FRACTION
        c.probe = {"t_end": horizon, "wall_s": round(res["wall_s"], 6), "predicted_full_s": round(predicted, 3)}
        if predicted > max_run_s:
            why = (f"probe over [0, {horizon:g}] took {res['wall_s']:.3g} s: predicted {predicted:.3g} s for the "
                   f"full run at tol {tols[0]:g} > {max_run_s:g} s")
            c.skipped += [{"tol": t, "reason": why,
                           "last_measured_s": round(res["wall_s"], 6)} for t in tols]
            say(f"  skip {c.name}: predicted {predicted:.3g} s")
        else:
            active.append(c)
    for k, tol in enumerate(tols):
        if not active:
            break
        pws = [_track_cpu(c.make(tol, t_end)) for c in active]
        measure(pws, repeats, SLOW_S)
        still = []
        over_budget = time.perf_counter() - started > budget_s
        for c, pw in zip(active, pws):
            c.points.append(pw)
            ok = pw.last.get("status") == "success" and pw.runs_s
            last = min(pw.runs_s) if pw.runs_s else None
            if ok and len(c.points) >= 2 and c.points[-2].runs_s:
                growth = min(10.0, max(1.2, last / min(c.points[-2].runs_s)))
            else:
                growth = 2.0
            rest = tols[k + 1:]
            reason = None
            if not ok:
                reason = f"failed at tol {tol:g}: {pw.last.get('status')}"
            elif last * growth > max_run_s:
                reason = (f"next run predicted {last * growth:.3g} s (last {last:.3g} s x growth {growth:.2g}) "
                          f"> {max_run_s:g} s")
            elif over_budget and last > CHEAP_S:
                reason = f"problem time budget {budget_s:g} s spent (runs under {CHEAP_S:g} s go on)"
            if reason and rest:
                c.skipped += [{"tol": t, "reason": reason, "last_measured_s": last} for t in rest]
            elif not reason:
                still.append(c)
        say(f"  tol {tol:g}: " + ", ".join(f"{c.name} {1e3 * min(pw.runs_s):.3g} ms" for c, pw in zip(active, pws)
                                           if pw.runs_s))
        active = still


# ------------------------------------------------------------------------------------- records

def _cpu() -> float:
    """CPU seconds of this process and its finished children (cvode-main runs as a child)."""
    import resource

    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def _track_cpu(pw: Pathway) -> Pathway:
    """Record the CPU time of each run of `pw` (its own figure when it gives one: the solve_ivp runs
    leave out their untimed t_dec evaluation) in pw.cpu_runs and in the run's ``cpu_s``."""
    inner, runs = pw.run, []

    def run():
        before = _cpu()
        out = inner()
        spent = _cpu() - before
        out.setdefault("cpu_s", spent)
        runs.append(out["cpu_s"])
        return out

    pw.run, pw.cpu_runs = run, runs
    return pw


def curve_record(c: Curve, y_ref, resolution: float | None, attractor=None) -> dict:
    pts = []
    for pw in c.points:
        rec = pw.record()
        cpu = getattr(pw, "cpu_runs", [])
        rec["runs_cpu_s"] = [round(v, 6) for v in cpu]
        rec["cpu_s"] = round(min(cpu), 6) if cpu else None
        e = error(pw.last.get("y_end"), y_ref)
        rec["error"] = e
        rec["below_resolution"] = bool(e is not None and resolution is not None and e < 10 * resolution)
        if attractor is not None and pw.last.get("status") == "success":
            rec.update(attractor(c, pw))
        pts.append(rec)
    return {"name": c.name, "kind": c.kind, "description": c.description, "adbgen": c.adbgen, "setup": c.setup,
            "probe": c.probe, "points": pts, "skipped": c.skipped}


def _attractor_check(model, ref: dict, p):
    """A closure: does a run reach the reference's attractor with t_dec within 1 %? (problem A)"""
    angles = list(model.angle_indices)
    ix, iy = model.amplitude_indices[:2]
    t_ref = ref["t_dec"]

    def check(c: Curve, pw: Pathway) -> dict:
        y = np.asarray(pw.last["y_end"], float)
        d = np.remainder(y[angles] - ref["y_end"][angles] + math.pi, 2 * math.pi) - math.pi
        same = bool(np.max(np.abs(d)) <= ATTRACTOR_TOL and math.hypot(y[ix], y[iy]) < THRESHOLD)
        if "t_dec" in pw.last:
            t_dec, how = pw.last["t_dec"], "own"
        elif c.t_dec_of is not None:
            t_dec, how = c.t_dec_of(pw.tol), f"untimed run on a grid of {TDEC_DT:g}"
        else:
            t_dec, how = None, "not available"
        ok_t = bool(t_dec is not None and t_ref is not None and abs(t_dec - t_ref) <= TDEC_REL * t_ref)
        return {"attractor_angle_difference": float(np.max(np.abs(d))), "same_attractor": same, "t_dec": t_dec,
                "t_dec_how": how, "t_dec_within_1pct": ok_t, "reliable": bool(same and ok_t)}

    return check


def loosest_reliable(rec: dict) -> dict:
    """The loosest tolerance from which on every tighter measured tolerance is reliable."""
    pts = sorted((p for p in rec["points"] if "reliable" in p), key=lambda q: q["tol"])
    if not pts:
        return {"tol": None, "why": "no successful run"}
    best = None
    for p in pts:  # tight to loose
        if not p["reliable"]:
            break
        best = p["tol"]
    return {"tol": best, "tightest_measured": pts[0]["tol"],
            "why": None if best is not None else "the tightest measured tolerance is not reliable"}


# ------------------------------------------------------------------------------------- targets

def _curve_points(rec: dict) -> list[tuple[float, float]]:
    return [(p["error"], p[TIME]) for p in rec["points"] if p.get("error") and p.get(TIME)
            and p.get("status") == "success"]


def _interpolated(rec: dict, e: float) -> float | None:
    pts = _curve_points(rec)
    errs = [x for x, _ in pts]
    if not errs or not (min(errs) <= e <= max(errs)):
        return None
    r = time_at_error(pts, e)
    return r["time_s"] if r else None


def precision_targets(prob: dict, default: str) -> list[dict]:
    """Targets on problem A: at error 1e-8 best adbgen vs fastest peer and vs lambdify; default engine
    left of every peer's curve over 1e-4..1e-12 (where both curves cover the error)."""
    out = []
    recs = prob["curves"]
    at = {}
    for rec in recs:
        r = time_at_error(_curve_points(rec), TARGET_ERROR)
        if r:
            at[rec["name"]] = {**r, "error_range": [min(x for x, _ in _curve_points(rec)),
                                                    max(x for x, _ in _curve_points(rec))]}
    prob["time_at_1e-8"] = at
    adb = {k: v for k, v in at.items() if next(r for r in recs if r["name"] == k)["adbgen"]}
    peers = {k: v for k, v in at.items() if k.startswith("peer:")}
    lam = {k: v for k, v in at.items() if k.startswith("ivp:lambdify")}
    best = min(adb, key=lambda k: adb[k]["time_s"]) if adb else None
    if best and peers:
        fastest = min(peers, key=lambda k: peers[k]["time_s"])
        ratio = peers[fastest]["time_s"] / adb[best]["time_s"]
        out.append(_target("A, error 1e-8: best adbgen pathway vs the fastest peer", "peer / adbgen >= 1", ratio, 1.0,
                           f"{best} {1e3 * adb[best]['time_s']:.3g} ms CPU ({adb[best]['how']}); {fastest} "
                           f"{1e3 * peers[fastest]['time_s']:.3g} ms CPU ({peers[fastest]['how']})"))
    else:
        out.append(_target("A, error 1e-8: best adbgen pathway vs the fastest peer", "peer / adbgen >= 1", None, 1.0,
                           "not measured"))
    if best and lam:
        fastest = min(lam, key=lambda k: lam[k]["time_s"])
        ratio = lam[fastest]["time_s"] / adb[best]["time_s"]
        out.append(_target("A, error 1e-8: best adbgen pathway vs lambdify + solve_ivp", "lambdify / adbgen >= 50",
                           ratio, 50.0, f"{best} {1e3 * adb[best]['time_s']:.3g} ms CPU; the faster lambdify pathway "
                           f"{fastest} {lam[fastest]['time_s']:.3g} s CPU ({lam[fastest]['how']}, its errors "
                           f"{lam[fastest]['error_range'][0]:.1e}..{lam[fastest]['error_range'][1]:.1e})"))
    else:
        out.append(_target("A, error 1e-8: best adbgen pathway vs lambdify + solve_ivp", "lambdify / adbgen >= 50",
                           None, 50.0, "not measured"))
    # default engine on or left of every peer's curve
    levels = [10.0 ** (-k / 2) for k in range(8, 25)]  # 1e-4 .. 1e-12, half decades
    drec = next((r for r in recs if r["name"] == default), None)
    worst, rows, best_by_level = None, [], []
    for e in levels:
        td = _interpolated(drec, e) if drec else None
        times = {r["name"]: _interpolated(r, e) for r in recs}
        times = {k: v for k, v in times.items() if v}
        if times:
            winner = min(times, key=times.get)
            best_by_level.append({"error": e, "fastest": winner, "time_s": times[winner],
                                  "default_time_s": td})
        for r in recs:
            if not r["name"].startswith("peer:"):
                continue
            tp = times.get(r["name"])
            if td and tp:
                rows.append({"error": e, "peer": r["name"], "peer_s": tp, "default_s": td, "ratio": tp / td})
                worst = tp / td if worst is None else min(worst, tp / td)
    prob["default_vs_peers"] = rows
    prob["fastest_by_error"] = best_by_level
    lost = sorted({f"{r['peer']} at {r['error']:.0e}" for r in rows if r["ratio"] < 1.0})
    out.append(_target("A: default engine on or left of every peer's curve, errors 1e-4..1e-12",
                       "min over errors and peers of peer time / default time >= 1", worst, 1.0,
                       ("default slower than " + ", ".join(lost)) if lost else
                       ("compared where both curves cover the error (interpolated)" if rows else "no overlap")))
    return out


# ----------------------------------------------------------------------------------------- run

NOTES = (
    "error: largest absolute difference of the final state from the reference (CyRK Vern8 at rtol 1e-14), "
    "whose resolution is reference.check_difference (heyoka Taylor at tol 1e-15); below_resolution: error < 10x "
    "that. cpu_s (charts and targets): CPU seconds of the run (process and children; runs_cpu_s: all), the "
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
    from ..analysis.engines import DEFAULT
    from ..analysis.loading import load_model
    from .codegen import machine
    from .simulate import _jsonable, _versions

    say = progress or (lambda line: None)
    started = time.perf_counter()
    tols = tuple(tols or (QUICK_TOLS if quick else TOLS))
    repeats = repeats or (1 if quick else 5)
    max_run_s = max_run_s or (QUICK_MAX_RUN_S if quick else MAX_RUN_S)
    budget_s = budget_s or (QUICK_BUDGET_S if quick else BUDGET_S)
    mach = machine()
    mach["load_average_at_start"] = _load()
    result: dict = {"benchmark": "precision", "date": datetime.datetime.now(datetime.timezone.utc).isoformat(
        timespec="seconds"), "machine": mach, "versions": _versions(), "notes": NOTES, "default_engine": DEFAULT,
        "settings": {"problems": list(problems), "quick": quick, "tols": list(tols), "repeats": repeats,
                     "slow_s": SLOW_S, "max_run_s": max_run_s, "budget_s": budget_s, "probe_fraction": PROBE_FRACTION,
                     "reference_tol": REF_TOL, "check_tol": CHECK_TOL, "attractor_tol": ATTRACTOR_TOL,
                     "t_dec_relative": TDEC_REL, "threshold": THRESHOLD, "time_compared": TIME},
        "problems": {}}
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
            rec["load_average_before_timing"] = _load()
            sweep(model, pp, cs, tols, t_end=horizon, repeats=repeats, max_run_s=max_run_s, budget_s=share,
                  progress=say)
            rec["load_average_after_timing"] = _load()
            p, _ = pp.problem.vectors(model)
            check = _attractor_check(model, ref, p) if label == "A" else None
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
    if "A" in result["problems"]:
        result["targets"] = precision_targets(result["problems"]["A"], DEFAULT)
    else:
        result["targets"] = []
    if percall:
        ns = tuple(percall_ns or ((2, 4) if quick else bench_percall.NS))
        result["load_average_before_percall"] = _load()
        result["percall"] = bench_percall.bench_percall(ns, quick=quick, progress=say)
        result["targets"] = bench_percall.targets(result["percall"]) + result["targets"]
    result["machine"]["load_average_at_end"] = _load()
    result["seconds"] = round(time.perf_counter() - started, 1)
    return _jsonable(result)


def rerun_percall(previous: dict | None, ns=None, progress=None) -> dict:
    """The per-call part alone, measured again and put into a previous result (its work-precision part kept
    as it was, with its own date): for a change that moves the generated code's cost per call but not the
    integrations' conclusions.  The per-call targets are replaced, the others kept; `percall_date` and
    `percall_commit` say when and on what the per-call part ran."""
    import subprocess

    from . import percall as bench_percall
    from .simulate import _jsonable

    if previous is not None and previous.get("benchmark") != "precision":
        raise ValueError("the results file holds no `adbgen bench precision` result")
    result = dict(previous or {"benchmark": "precision", "problems": {}, "targets": []})
    result["load_average_before_percall"] = _load()
    result["percall"] = bench_percall.bench_percall(tuple(ns or bench_percall.NS), quick=False, progress=progress)
    kept = [t for t in result.get("targets", []) if not str(t.get("target", t.get("name", ""))).startswith("per call")]
    result["targets"] = bench_percall.targets(result["percall"]) + kept
    result["percall_date"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    try:
        result["percall_commit"] = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                                                  cwd=Path(__file__).parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        result["percall_commit"] = None
    return _jsonable(result)


# --------------------------------------------------------------------------------------- charts

_KIND_STYLE = {"engine": "-", "ivp": "--", "cvode-main": "-.", "peer": ":"}
_PEER_COLOURS = {"peer:jitcode-dop853": "#2ca02c", "peer:heyoka": "#9467bd"}


def _save(fig, path: Path) -> Path:
    from .simulate import save_figure

    return save_figure(fig, path, dpi=110)


HEADLINE = ("cyrk-dop853", "cyrk-vern8", "cvode-bdf", "cvode-main", "scipy-dop853", "ivp:numba-dop853",
            "ivp:handwritten-dop853", "ivp:lambdify-rk45", "ivp:lambdify-dop853", "peer:jitcode-dop853", "peer:heyoka")


def chart(result: dict, label: str, path: str | Path, only=None) -> Path:
    """Work-precision chart of one problem: error (y) against wall time (x), log-log, a curve per pathway
    (`only`: just these pathways, e.g. `HEADLINE`).  Failed runs, and errors above 1 (a run that ended
    on another attractor), are left off."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prob = result["problems"][label]
    default = result["default_engine"]
    fig, ax = plt.subplots(figsize=(11, 7))
    palette = [c for i, c in enumerate(plt.get_cmap("tab20").colors) if i not in (4, 5, 6, 7, 8, 9)]
    # (greens and purples are the peers', red the default's)
    k = 0
    for rec in prob["curves"]:
        if only is not None and rec["name"] not in only:
            continue
        pts = sorted(((q[TIME], q["error"], q["tol"]) for q in rec["points"] if q.get(TIME) and q.get("error")
                      and q["error"] <= 1.0 and q.get("status") == "success"), key=lambda v: -v[2])
        if not pts:
            continue
        xs, ys = [v[0] for v in pts], [v[1] for v in pts]
        if rec["name"] == default:
            ax.plot(xs, ys, "-o", color="#d62728", lw=3, ms=5, label=f"{rec['name']} (default)", zorder=5)
        else:
            colour = _PEER_COLOURS.get(rec["name"], "#2ca02c") if rec["kind"] == "peer" else \
                palette[k % len(palette)]
            k += rec["kind"] != "peer"
            marker = "s" if rec["kind"] == "peer" else ("^" if rec["kind"] == "ivp" else ".")
            ax.plot(xs, ys, _KIND_STYLE.get(rec["kind"], "-"), marker=marker, color=colour,
                    lw=2.2 if rec["kind"] == "peer" else 1.1, ms=5, label=rec["name"])
    res = prob["reference"].get("check_difference")
    if res:
        ax.axhspan(1e-18, 10 * res, color="#cccccc", alpha=0.4, lw=0)
        ax.text(0.99, 10 * res, "reference resolution x 10", transform=ax.get_yaxis_transform(), ha="right",
                va="bottom", fontsize=7, color="#555555")
    ax.set_xscale("log")
    ax.set_yscale("log")
    errs = [q["error"] for r in prob["curves"] for q in r["points"] if q.get("error") and q["error"] <= 1.0
            and (only is None or r["name"] in only)]
    if errs:
        ax.set_ylim(max(min(errs) / 3, 1e-16), max(errs) * 3)
    ax.set_xlabel("CPU time of the integration [s] (best of the repeats, log)")
    ax.set_ylabel("global error: max |y(t_end) - y_ref(t_end)| (log)")
    load = prob.get("load_average_before_timing") or [None]
    pr = prob["problem"]
    ax.set_title(f"Problem {label}: {prob['what']}\n{pr['model']}, t in [0, {pr['t_end']:g}], tolerances "
                 f"{min(result['settings']['tols']):g}..{max(result['settings']['tols']):g}; "
                 f"{result['date'][:16].replace('T', ' ')} UTC, load {load[0]} on {result['machine'].get('cpus')} "
                 "cores", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    return _save(fig, path)


def chart_reliable(result: dict, path: str | Path) -> Path:
    """Problem A: per pathway, the loosest tolerance from which on runs reach the right attractor with
    t_dec within 1 % (bars: -log10 tol; a pathway with none shown empty)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prob = result["problems"]["A"]
    rows = sorted(prob["loosest_reliable"].items(), key=lambda kv: (kv[1]["tol"] is None, -(kv[1]["tol"] or 0)))
    fig, ax = plt.subplots(figsize=(8, 0.28 * len(rows) + 1.5))
    y = np.arange(len(rows))
    vals = [-math.log10(v["tol"]) if v["tol"] else 0.0 for _, v in rows]
    ax.barh(y, vals, color=["#d62728" if k == result["default_engine"] else "#1f77b4" for k, _ in rows])
    for i, (_, v) in enumerate(rows):
        ax.text(vals[i] + 0.1, i, f"{v['tol']:g}" if v["tol"] else (v.get("why") or "none"), va="center", fontsize=7)
    ax.set_yticks(y, [k for k, _ in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("-log10 of the loosest reliable tolerance (smaller bar = looser tolerance suffices)")
    ax.set_title(f"Problem A: loosest tolerance reaching the reference attractor with t_dec within 1 %\n"
                 f"(reference t_dec = {prob['reference'].get('t_dec') or float('nan'):.2f}; engines: t_dec from "
                 f"their events, others: from a grid of {TDEC_DT:g})", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def chart_percall(result: dict, path: str | Path) -> Path:
    """ns per call against n (log-log): generated numba and C, hand-written, lambdify; rhs and jac."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result["percall"]["rows"]
    series = [("numba_rhs_loop", "generated numba rhs (jitted loop)", "#d62728", "-o"),
              ("c_rhs_loop", "generated C rhs (C loop, -O2)", "#1f77b4", "-o"),
              ("handwritten_rhs_loop", "hand-written numba rhs, thesis App. A", "#2ca02c", "-s"),
              ("numba_rhs_python", "generated numba rhs called from Python", "#ff7f0e", "--o"),
              ("lambdify_math", "lambdify math, cse (from Python)", "#7f7f7f", "-^"),
              ("lambdify_numpy", "lambdify numpy, cse (from Python)", "#bcbd22", "-^"),
              ("numba_jac_loop", "generated numba jac (jitted loop)", "#d62728", ":x"),
              ("c_jac_loop", "generated C jac (C loop)", "#1f77b4", ":x"),
              ("lambdify_jac_math", "lambdify math jac (from Python)", "#7f7f7f", ":^")]
    fig, ax = plt.subplots(figsize=(9, 6))
    for key, label, colour, style in series:
        pts = [(r["n"], r[key]["ns"]) for r in rows if isinstance(r.get(key), dict)]
        if pts:
            ax.plot(*zip(*pts), style, color=colour, label=label)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("number of balls n (thesis model, 2n + 4 states)")
    ax.set_ylabel("ns per call (median of the repeats)")
    load = result.get("load_average_before_percall") or [None]
    ax.set_title(f"Cost per call, {result['date'][:16].replace('T', ' ')} UTC, load {load[0]}", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, path)


def describe_targets(result: dict) -> list[str]:
    from .simulate import describe_targets as describe

    return describe(result)


__all__ = ["rerun_percall", "Curve", "CvodeMain", "HEADLINE", "PROBLEMS", "PrecisionProblem", "TOLS", "bench_precision", "chart",
           "chart_percall", "chart_reliable", "curve_record", "curves", "describe_targets", "lambdify_rhs",
           "loosest_reliable", "precision_targets", "reference", "stiffness", "sweep"]
