"""The pathways of the work-precision benchmark (`adbgen bench precision`), one definition each: a
`Curve` makes a `Pathway` per tolerance.  See `precision`'s docstring for what each pathway is.

t_dec of a pathway without events (solve_ivp without events, the peers, cvode-main) is read from
samples on a grid (`TDEC_DT`), linearly interpolated (`t_dec_grid`).
"""

from __future__ import annotations

import shutil
import subprocess
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from .pathways import Pathway, engine_pathway
from .problems import Problem
from .symbolic import lambdify_rhs

if TYPE_CHECKING:
    from .precision import PrecisionProblem

TDEC_DT = 0.25
THRESHOLD = 1e-3
# heyoka's default mode compiles a large rhs (the Hill run-up's series) for minutes at high order (measured
# 71 s at tol 1e-15 for B, 240 statements); above this many it runs in compact mode (2-3 s per tolerance)
HEYOKA_COMPACT_ABOVE = 150
CVODE_LIBS = ("-lsundials_cvode", "-lsundials_nvecserial", "-lsundials_sunmatrixdense",
              "-lsundials_sunlinsoldense", "-lm")


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


def t_dec_grid(t, r, threshold: float = THRESHOLD) -> float | None:
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
                out["t_dec"] = t_dec_grid(grid, np.hypot(yy[ix], yy[iy]))
            return out

        return Pathway(f"{key}@{tol:g}", "ivp", key, tol, run)

    return Curve(key, "ivp", description, make, adbgen, setup=setup)


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
    from adbgen.analysis.engines import DEFAULT, ENGINES

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
            return t_dec_grid(res["t"], np.hypot(res["y"][ix], res["y"][iy])) if res["y_end"] is not None else None

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
            peer = cls(model.module, compact_mode=compact) if name.startswith("heyoka") else cls(model.module)
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
                return t_dec_grid(grid, np.hypot(ys[:, ix], ys[:, iy]))

            out.append(Curve("peer:jitcode-dop853", "peer", "JiTCODE (helpers = the generated statements), "
                             "dop853 backend (scipy ode, a Python call per evaluation)", make, adbgen=False,
                             t_dec_of=t_dec_of if want_t_dec else None, setup=setup))
        else:  # heyoka on the generated statements ("heyoka") or on the hand-written form ("heyoka-hand")
            setup["compile_s"] = {}
            setup["compact_mode"] = compact
            key = f"peer:{name}"

            def make(tol, t_end, peer=peer, setup=setup, key=key):
                if tol not in peer._integrators:
                    peer.integrator(tol, y0, p, cold=False)
                    setup["compile_s"][f"{tol:g}"] = round(peer.compile_s[tol], 3)
                return Pathway(f"{key}@{tol:g}", "peer", key, tol, lambda: peer.run(y0, p, t_end, tol))

            def t_dec_of(tol, peer=peer):
                ta = peer.integrator(tol, y0, p, cold=False)
                ta.time = 0.0
                ta.state[:] = np.asarray(peer.full_state(y0), float)
                ta.pars[:] = np.asarray(p, float)
                res = ta.propagate_grid(grid)
                ys = np.asarray(res[-1])
                return t_dec_grid(grid, np.hypot(ys[:, ix], ys[:, iy]))

            out.append(Curve(key, "peer", f"{peer.label}: adaptive Taylor (LLVM), tol = rtol = atol; compiled per "
                             "tolerance outside the timings (caches allowed)", make, adbgen=False,
                             t_dec_of=t_dec_of if want_t_dec else None, setup=setup))
        say(f"peer {name}: {setup}")
    return out




__all__ = ["CVODE_LIBS", "Curve", "CvodeMain", "HEYOKA_COMPACT_ABOVE", "TDEC_DT", "THRESHOLD", "curves",
           "heyoka_compact", "t_dec_grid"]
