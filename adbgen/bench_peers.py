"""Peers for the benchmarks: JiTCODE and heyoka fed the same equations as adbgen's generated code.

Only benchmarks import this module (`adbgen bench simulate`, and the work-precision charts that
follow it); the peers are the optional extra ``pip install 'adbgen[peers]'``.  SymPy is used here,
never in the analysis layer.

"The same equations" means the rhs program of the model's intermediate form (`adbgen.codegen.ir`):
the straight-line code every target prints (per-ball blocks, the Schur complement of the ball block,
its unrolled LU solve, the back-substitution; thesis Appendix A).  Each peer gets it in its own
input language:

- JiTCODE 1.7 (`jitcode.jitcode`): every statement as a *helper* (JiTCODE's named intermediate),
  the outputs as f; the parameters as control parameters (runtime values, as the generated C takes
  them).  Its ``dop853`` backend is SciPy's ``ode('dop853')`` (Hairer's Fortran DOP853) calling the
  compiled C function through Python for every evaluation.
- heyoka 7 (`heyoka.taylor_adaptive`): each statement converted by ``heyoka.from_sympy`` with the
  earlier statements substituted as heyoka expressions (heyoka eliminates the common subexpressions
  itself); parameters as ``heyoka.par[i]``; an LLVM-compiled adaptive Taylor integrator.

`check_equations` compares each peer's rhs with the generated module's at random states: the peers
must integrate the generated code's equations, not a lookalike.
"""

from __future__ import annotations

import importlib
import os
import tempfile
import time
from contextlib import contextmanager
from functools import lru_cache

import numpy as np
import sympy as sp


class PeerUnavailable(RuntimeError):
    """A peer is not installed (the benchmark records it and goes on)."""


def peer_versions() -> dict:
    out = {}
    for name in ("jitcode", "heyoka", "symengine"):
        try:
            mod = importlib.import_module(name)
        except ImportError:
            out[name] = None
            continue
        version = getattr(mod, "__version__", None)
        if version is None:
            try:
                from importlib.metadata import version as dist_version

                version = dist_version(name)
            except Exception:  # pragma: no cover - metadata missing
                version = "unknown"
        out[name] = version
    return out


@lru_cache(maxsize=None)
def model_ir(name: str):
    """The intermediate form of a model of the default families, by its generated name."""
    from . import families

    kinds = families.kinds()
    for kind, make in kinds.items():
        prefix = kind + "_n"
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            return make(int(name[len(prefix):])).build()
    raise ValueError(f"{name!r} is not a model of the default families ({', '.join(kinds)})")


def _time_symbol(ir):
    """The free symbol of time in the rhs program (None for an autonomous model)."""
    known = {s.symbol for s in ir.states} | {p.symbol for p in ir.parameters} | {lhs for lhs, _ in ir.rhs.assignments}
    free = set()
    for _, e in list(ir.rhs.assignments) + list(ir.rhs.outputs):
        free |= sp.sympify(e).free_symbols - known
    if not free:
        return None
    if len(free) == 1 and next(iter(free)).name == "t":
        return next(iter(free))
    raise ValueError(f"unexpected free symbols in the rhs program: {sorted(map(str, free))}")


def _translate(ir, convert, states, params, time, bind=lambda lhs, value: value):
    """The rhs program's outputs in a peer's expressions.

    convert(expr, env) turns one SymPy expression into the peer's, env mapping its free symbols;
    bind(lhs, value) is what later statements see for a statement (the value itself, or a name)."""
    env = {s.symbol: v for s, v in zip(ir.states, states)}
    env.update({p.symbol: v for p, v in zip(ir.parameters, params)})
    t = _time_symbol(ir)
    if t is not None:
        env[t] = time
    for lhs, expr in ir.rhs.assignments:
        env[lhs] = bind(lhs, convert(expr, {k: env[k] for k in sp.sympify(expr).free_symbols}))
    outputs = [None] * ir.rhs.shape[0]
    for index, expr in ir.rhs.outputs:
        outputs[index] = convert(expr, {k: env[k] for k in sp.sympify(expr).free_symbols})
    return outputs


# -------------------------------------------------------------------------------------- heyoka

class Heyoka:
    """heyoka's adaptive Taylor integrator on the model's rhs program (one per tolerance)."""

    name = "heyoka"

    def __init__(self, ir):
        try:
            import heyoka as hy
        except ImportError as exc:
            raise PeerUnavailable(f"heyoka is not installed ({exc}); pip install 'adbgen[peers]'") from None
        self.hy = hy
        self.ir = ir
        self.vars = [hy.make_vars(s.name) for s in ir.states]
        start = time.perf_counter()
        outputs = _translate(ir, lambda e, env: hy.from_sympy(sp.sympify(e), s_dict=env), self.vars,
                                [hy.par[i] for i in range(len(ir.parameters))], hy.time)
        self.translate_s = time.perf_counter() - start
        self.system = list(zip(self.vars, outputs))
        self.outputs = outputs
        self._integrators: dict[float, object] = {}
        self.compile_s: dict[float, float] = {}

    def integrator(self, tol: float, y0, p):
        """The compiled integrator for `tol`; its build is timed cold in compile_s[tol].

        heyoka keeps compiled code in a memory cache and an on-disk cache (~/.cache/heyoka): both are
        bypassed for the build (the disk cache switched off meanwhile, nothing deleted from it), so
        compile_s is what a first use costs."""
        if tol not in self._integrators:
            state = self.hy.llvm_state
            disk = getattr(state, "get_diskcache_enabled", lambda: None)()
            try:
                if disk:
                    state.set_diskcache_enabled(False)
                state.clear_memcache()
                start = time.perf_counter()
                ta = self.hy.taylor_adaptive(self.system, list(map(float, y0)), tol=float(tol),
                                             pars=list(map(float, p)))
                self.compile_s[tol] = time.perf_counter() - start
            finally:
                if disk:
                    state.set_diskcache_enabled(True)
            self._integrators[tol] = ta
        return self._integrators[tol]

    def rhs(self, y, p, t=0.0):
        """The rhs as heyoka evaluates it (a compiled function of the same expressions)."""
        cf = getattr(self, "_cfunc", None)
        if cf is None:
            cf = self._cfunc = self.hy.cfunc(self.outputs, vars=self.vars)
        return np.asarray(cf(np.asarray(y, float), pars=np.asarray(p, float), time=float(t)), float)

    def run(self, y0, p, t_end: float, tol: float) -> dict:
        ta = self.integrator(tol, y0, p)
        ta.time = 0.0
        ta.state[:] = np.asarray(y0, float)
        ta.pars[:] = np.asarray(p, float)
        start = time.perf_counter()
        res = ta.propagate_until(float(t_end))
        wall = time.perf_counter() - start
        outcome = res[0]
        ok = outcome == self.hy.taylor_outcome.time_limit and np.all(np.isfinite(ta.state))
        return {"wall_s": wall, "y_end": np.array(ta.state, float), "n_steps": int(res[3]), "n_rhs": None,
                "order": int(ta.order), "status": "success" if ok else f"failed: {outcome}"}


# ------------------------------------------------------------------------------------- JiTCODE

@contextmanager
def _scratch_cwd():
    """JiTCODE builds its module with setuptools in the current folder's context: run it elsewhere."""
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="adbgen-jitcode-") as tmp:
        os.chdir(tmp)
        try:
            yield tmp
        finally:
            os.chdir(old)


class JiTCODE:
    """JiTCODE's compiled C rhs (statements as helpers) with a SciPy ode backend ("dop853")."""

    name = "jitcode"

    def __init__(self, ir):
        try:
            import symengine as se
            from jitcode import jitcode, t as jt, y as jy
        except ImportError as exc:
            raise PeerUnavailable(f"jitcode is not installed ({exc}); pip install 'adbgen[peers]'") from None
        self.ir = ir
        n = len(ir.states)
        self.pars = [se.Symbol("par_" + p.name) for p in ir.parameters]
        helpers = []

        def convert(expr, env):
            return se.sympify(expr).subs({se.Symbol(k.name): v for k, v in env.items()})

        def bind(lhs, value):  # each statement becomes a helper, named like the generated code's
            helpers.append((se.Symbol("h_" + lhs.name), value))
            return helpers[-1][0]

        start = time.perf_counter()
        outputs = _translate(ir, convert, [jy(i) for i in range(n)], self.pars, jt, bind)
        self.translate_s = time.perf_counter() - start
        start = time.perf_counter()
        with _scratch_cwd():
            self.ode = jitcode(outputs, helpers=helpers, control_pars=self.pars, n=n, verbose=False)
            self.ode.compile_C()
        self.compile_s = time.perf_counter() - start

    def rhs(self, y, p, t=0.0):
        self.ode.set_parameters(*map(float, p))
        return np.asarray(self.ode.f(float(t), np.asarray(y, float)), float)

    def count_rhs(self, y0, p, t_end: float, rtol: float, atol: float, method: str = "dop853") -> int:
        """Evaluations the same integration takes (an untimed run with a counting wrapper)."""
        from scipy.integrate import ode

        self.ode.set_parameters(*map(float, p))
        f = self.ode.f
        count = [0]

        def counted(t, y):
            count[0] += 1
            return f(t, y)

        solver = ode(counted).set_integrator(method, rtol=rtol, atol=atol, nsteps=10**6)
        solver.set_initial_value(np.asarray(y0, float), 0.0)
        solver.integrate(float(t_end))
        return count[0]

    def run(self, y0, p, t_end: float, rtol: float, atol: float, method: str = "dop853") -> dict:
        from jitcode import UnsuccessfulIntegration

        self.ode.set_integrator(method, rtol=rtol, atol=atol)
        self.ode.set_parameters(*map(float, p))
        self.ode.set_initial_value(np.asarray(y0, float), 0.0)
        start = time.perf_counter()
        try:
            y_end = self.ode.integrate(float(t_end))
            status = "success"
        except UnsuccessfulIntegration as exc:
            y_end, status = np.full(len(y0), np.nan), f"failed: {exc}"
        wall = time.perf_counter() - start
        return {"wall_s": wall, "y_end": np.array(y_end, float), "n_steps": None, "n_rhs": None, "status": status}


PEERS = {"jitcode": JiTCODE, "heyoka": Heyoka}


def check_equations(peer, module, p, samples: int = 50, seed: int = 0) -> float:
    """Largest relative difference (norm-wise) between a peer's rhs and the generated module's."""
    rng = np.random.default_rng(seed)
    n = len(module.STATE_NAMES)
    worst = 0.0
    for _ in range(samples):
        y = rng.uniform(-1.0, 1.0, n)
        y[: n // 2] *= 0.1
        ref = np.asarray(module.rhs(0.0, y, p), float)
        got = peer.rhs(y, p)
        worst = max(worst, float(np.max(np.abs(got - ref)) / max(np.max(np.abs(ref)), 1e-300)))
    return worst


__all__ = ["Heyoka", "JiTCODE", "PEERS", "PeerUnavailable", "check_equations", "model_ir", "peer_versions"]
