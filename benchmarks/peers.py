"""Peers for the benchmarks: JiTCODE and heyoka fed the same equations as adbgen's generated code.

Only benchmarks import this module (`adbgen bench simulate`, and the work-precision charts that
follow it); the peers are the optional extra ``pip install 'adbgen[peers]'``.  No SymPy here,
nor in the analysis layer: the peers read the generated module.

"The same equations" means the generated code itself: the statements of the model's numba
``rhs_inplace``, emitted as data beside it (program.json, `adbgen.codegen.program_tree`; read by
`generated_program`, never the module's source) in their order, with their operands in their printed,
ball-invariant order (`codegen/printers.py`), so that a peer evaluates every ball by the same
floating-point operations as the generated code does.  (Feeding the intermediate form's SymPy
expressions instead loses that order, and with it the exchange symmetry: measured, heyoka then splits
the balls that start together.)  Each peer gets the statements in its own input language:

- JiTCODE 1.7 (`jitcode.jitcode`): every computed statement as a *helper* (JiTCODE's named
  intermediate), the outputs as f; the parameters as control parameters (runtime values, as the
  generated C takes them).  SymEngine, which JiTCODE builds on, re-orders the terms of each
  expression by its own canonical order.  Its ``dop853`` backend is SciPy's ``ode('dop853')``
  (Hairer's Fortran DOP853) calling the compiled C function through Python for every evaluation.
- heyoka 7 (`heyoka.taylor_adaptive`): the statements evaluated on heyoka expressions (heyoka
  eliminates the common subexpressions itself); parameters as ``heyoka.par[i]``; an LLVM-compiled
  adaptive Taylor integrator.

`check_equations` compares each peer's rhs with the generated module's at random states: the peers
must integrate the generated code's equations, not a lookalike.
"""

from __future__ import annotations

import importlib
import json
import os
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np


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


def generated_program(module) -> tuple[list, dict]:
    """The generated rhs as data: ([(name, tree)], {index: tree}), read from the module's program.json
    (`adbgen.codegen.program_tree`: the statements of its ``rhs_inplace`` with every loop unrolled, in
    their order, each operation in the order the module performs it; the trees' forms are listed there).
    A module generated before program.json, or whose rhs the trees do not express, is refused."""
    path = Path(module.__file__).parent / "program.json"
    if not path.is_file():
        raise ValueError(f"{module.__name__} has no program.json beside it (generated before the rhs was "
                         f"emitted as data): run `adbgen regenerate`")
    data = json.loads(path.read_text())
    if "error" in data:
        raise ValueError(f"{module.__name__}: its rhs is not emitted as data: {data['error']}")
    outputs = dict(enumerate(data["outputs"]))
    if data["states"] != len(module.STATE_NAMES) or len(outputs) != len(module.STATE_NAMES):
        raise ValueError(f"{path} does not write every output of {module.__name__}")
    return [(name, tree) for name, tree in data["statements"]], outputs


def _translate(module, functions, states, params, time, bind=lambda name, value: value):
    """The outputs of the generated rhs evaluated on a peer's symbols, statement by statement
    (`adbgen.codegen.program_tree.evaluate`: functions are the peer's sin, cos, ..., select and less, and
    optionally power; bind(name, value) what later statements see for a computed statement)."""
    from adbgen.codegen.program_tree import evaluate

    statements, outputs = generated_program(module)
    return evaluate(statements, outputs, states, params, time, functions, bind)


def _power_by_products(base, k: int):
    """base ** k by squaring and products.  heyoka's Taylor recurrence for a power divides by the base,
    which is NaN where the base is 0 (the Hill run-up's series in t (45) at t = 0: measured,
    taylor_outcome.err_nf_state on the first step); products have no such division."""
    if isinstance(base, (int, float)):
        return base ** k
    result, square = None, base
    while k:
        if k & 1:
            result = square if result is None else result * square
        k >>= 1
        if k:
            square = square * square
    return result


def _numeric(fn, name):
    """fn, or Python's math on plain numbers (a peer's sqrt may refuse a float: ``sqrt(3.0)``)."""
    import math

    exact = getattr(math, name)

    def call(*args):
        return exact(*args) if all(isinstance(a, (int, float)) for a in args) else fn(*args)

    return call


def _functions(lib, names=("sin", "cos", "tan", "exp", "log", "sqrt", "atan")) -> dict:
    return {n: _numeric(getattr(lib, n), n) for n in names if hasattr(lib, n)}


# -------------------------------------------------------------------------------------- heyoka

class Heyoka:
    """heyoka's adaptive Taylor integrator on the generated rhs (one integrator per tolerance)."""

    name = "heyoka"
    label = "heyoka (the generated statements)"

    def __init__(self, module, compact_mode: bool = False):
        self.compact_mode = compact_mode  # heyoka's compact mode: fast builds of large systems, slower steps
        try:
            import heyoka as hy
        except ImportError as exc:
            raise PeerUnavailable(f"heyoka is not installed ({exc}); pip install 'adbgen[peers]'") from None
        self.hy = hy
        self.n_model = len(module.STATE_NAMES)
        start = time.perf_counter()
        self.vars, outputs = self._equations(module, hy)
        self.translate_s = time.perf_counter() - start
        self.system = list(zip(self.vars, outputs))
        self.outputs = outputs
        self._integrators: dict[float, object] = {}
        self.compile_s: dict[float, float] = {}

    def _equations(self, module, hy):
        """(state variables, right-hand sides): the generated module's statements on heyoka expressions."""
        variables = [hy.make_vars(name) for name in module.STATE_NAMES]
        functions = {**_functions(hy), "select": hy.select, "less": hy.lt, "power": _power_by_products}
        outputs = _translate(module, functions, variables, [hy.par[i] for i in range(len(module.PARAM_NAMES))],
                             hy.time)
        return variables, outputs

    def full_state(self, y, t: float = 0.0):
        """The peer's state for a model state (the hand-written run-up adds the spin angle)."""
        return [float(v) for v in y]

    def integrator(self, tol: float, y0, p, cold: bool = True):
        """The compiled integrator for `tol`; its build is timed in compile_s[tol] (cold by default).

        heyoka keeps compiled code in a memory cache and an on-disk cache (~/.cache/heyoka): with
        `cold` both are bypassed for the build (the disk cache switched off meanwhile, nothing deleted
        from it), so compile_s is what a first use costs; cold=False lets heyoka use its caches (the
        work-precision benchmark builds one integrator per tolerance and problem and times only runs)."""
        if tol not in self._integrators:
            state = self.hy.llvm_state
            disk = cold and getattr(state, "get_diskcache_enabled", lambda: None)()
            try:
                if disk:
                    state.set_diskcache_enabled(False)
                if cold:
                    state.clear_memcache()
                start = time.perf_counter()
                ta = self.hy.taylor_adaptive(self.system, self.full_state(y0), tol=float(tol),
                                             pars=list(map(float, p)), compact_mode=self.compact_mode)
                self.compile_s[tol] = time.perf_counter() - start
            finally:
                if disk:
                    state.set_diskcache_enabled(True)
            self._integrators[tol] = ta
        return self._integrators[tol]

    def rhs(self, y, p, t=0.0, fp_type=None):
        """The rhs as heyoka evaluates it (a compiled function of the same expressions), the model's rows;
        with `fp_type` (np.longdouble, heyoka.real128) evaluated in that type from y, p, t as given (doubles
        widened exactly) and rounded to double at the end (`check_extended`)."""
        fp = float if fp_type is None else fp_type
        cache = self.__dict__.setdefault("_cfuncs", {})
        if fp not in cache:
            cache[fp] = (self.hy.cfunc(self.outputs, vars=self.vars) if fp_type is None else
                         self.hy.cfunc(self.outputs, vars=self.vars, fp_type=fp_type))
        out = cache[fp](np.array(self.full_state(y, t), dtype=fp), pars=np.array(p, dtype=fp), time=fp(t))
        return np.array(out, dtype=float)[: self.n_model]

    def run_extended(self, y0, p, t_end: float, tol: float = 1e-19, fp_type=None, threshold=None,
                     amplitude=None, breakpoints=()) -> dict:
        """One run in extended precision (default heyoka's fp_type=np.longdouble: x86's 80-bit format, 64-bit
        mantissa, eps 1.1e-19; or `fp_type`, e.g. heyoka.real128, `extended_type`): the final state, rounded
        to double, for a reference whose round-off is far below any double-precision run's (compact mode: the
        build is a second, not minutes).  With `threshold` and `amplitude` (the model's amplitude_indices:
        r = sqrt(y[ix]^2 + y[iy]^2)) also t_dec = sup{t : r(t) >= threshold}, as the engines define it
        (adb_engine.h): the last crossing of r^2 = threshold^2, located by heyoka's event detection in the
        same type (a non-terminal event on r^2 - threshold^2); None when r(t_end) >= threshold, 0 when r never
        reaches it.  `breakpoints` (`time_breakpoints`): times the run stops at, so that no step crosses
        a switch of a piecewise law of time."""
        hy = self.hy
        ld = np.longdouble if fp_type is None else fp_type
        if fp_type is None and np.finfo(ld).eps >= np.finfo(float).eps:
            raise PeerUnavailable("long double is no wider than double on this platform")
        self._p = list(map(float, p))  # the hand-written run-up's spin angle reads them
        crossings = []
        events = {}
        if threshold is not None:
            ix, iy = int(amplitude[0]), int(amplitude[1])
            r2 = self.vars[ix] * self.vars[ix] + self.vars[iy] * self.vars[iy]
            events["nt_events"] = [hy.nt_event(r2 - float(threshold) ** 2,
                                               lambda ta, t, d_sgn: crossings.append(float(t)), fp_type=ld)]
        start = time.perf_counter()
        ta = hy.taylor_adaptive(self.system, np.array(self.full_state(y0), dtype=ld), tol=ld(tol),
                                pars=np.array(p, dtype=ld), fp_type=ld, compact_mode=True, **events)
        built = time.perf_counter()
        steps, ok = 0, True
        for stop in [b for b in sorted(breakpoints) if 0.0 < b < t_end] + [t_end]:
            res = ta.propagate_until(ld(stop))
            steps += int(res[3])
            ok = ok and res[0] == hy.taylor_outcome.time_limit
        y_end = np.array(ta.state[: self.n_model], dtype=float)
        ok = ok and bool(np.all(np.isfinite(y_end)))
        out = {"y_end": y_end, "order": int(ta.order),
               "n_steps": steps, "build_s": built - start, "run_s": time.perf_counter() - built,
               "status": "success" if ok else f"failed: {res[0]}"}
        if threshold is not None:
            ix, iy = int(amplitude[0]), int(amplitude[1])
            above = y_end[ix] ** 2 + y_end[iy] ** 2 >= float(threshold) ** 2
            out["t_dec"] = None if above else (max(crossings) if crossings else 0.0)
        return out

    def run(self, y0, p, t_end: float, tol: float) -> dict:
        ta = self.integrator(tol, y0, p)
        ta.time = 0.0
        ta.state[:] = np.asarray(self.full_state(y0), float)
        ta.pars[:] = np.asarray(p, float)
        start = time.perf_counter()
        res = ta.propagate_until(float(t_end))
        wall = time.perf_counter() - start
        outcome = res[0]
        ok = outcome == self.hy.taylor_outcome.time_limit and np.all(np.isfinite(ta.state))
        return {"wall_s": wall, "y_end": np.array(ta.state, float)[: self.n_model], "n_steps": int(res[3]),
                "n_rhs": None, "order": int(ta.order), "status": "success" if ok else f"failed: {outcome}"}


class HeyokaHandwritten(Heyoka):
    """heyoka on the equations a heyoka user writes by hand (`bench.handwritten`: thesis Appendix A for
    problem A, the paper's (2), (4) for problem B), parameters as heyoka.par."""

    name = "heyoka-hand"
    label = "heyoka (hand-written: Appendix A / paper (2), (4))"

    def _equations(self, module, hy):
        from . import handwritten

        form = handwritten.form_of(module.NAME)
        if form is None:
            raise PeerUnavailable(f"no hand-written form of {module.NAME} (only problems A and B have one)")
        self.form = form
        self._names = list(module.PARAM_NAMES)
        return (handwritten.thesis_appendix_a if form == "A" else handwritten.two_plane_hill)(hy, module)

    def full_state(self, y, t: float = 0.0):
        y = [float(v) for v in y]
        if self.form == "B":  # the spin angle theta_0(t) = integral of the Hill profile, 0 at t = 0
            y.append(self._spin_angle(t))
        return y

    def _spin_angle(self, t: float) -> float:
        if t == 0.0:
            return 0.0
        from scipy.integrate import quad

        p = getattr(self, "_p", None)
        if p is None:
            raise RuntimeError("the run-up's spin angle needs the parameters: call rhs(y, p, t)")
        names = self._names
        om_max, om_cyl, t_half = (p[names.index(k)] for k in ("Omega_max", "Omega_cyl", "t_half"))
        return quad(lambda s: om_max * (om_cyl * s) ** 3 / (t_half ** 3 + (om_cyl * s) ** 3), 0.0, t,
                    epsabs=0.0, epsrel=1e-13, limit=200)[0]

    def rhs(self, y, p, t=0.0):
        self._p = list(map(float, p))
        return super().rhs(y, p, t)


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

    def __init__(self, module):
        try:
            import symengine as se
            from jitcode import jitcode, t as jt, y as jy
        except ImportError as exc:
            raise PeerUnavailable(f"jitcode is not installed ({exc}); pip install 'adbgen[peers]'") from None
        n = len(module.STATE_NAMES)
        self.pars = [se.Symbol("par_" + name) for name in module.PARAM_NAMES]
        helpers = []

        def bind(name, value):  # each computed statement becomes a helper, named like the generated code's
            helpers.append((se.Symbol("h_" + name), value))
            return helpers[-1][0]

        start = time.perf_counter()
        functions = {**_functions(se), "select": lambda c, a, b: se.Piecewise((a, c), (b, True)), "less": se.Lt}
        outputs = _translate(module, functions, [jy(i) for i in range(n)], self.pars, jt, bind)
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


PEERS = {"jitcode": JiTCODE, "heyoka": Heyoka, "heyoka-hand": HeyokaHandwritten}


def extended_type():
    """The widest floating-point type this heyoka build integrates in at a practical cost: (type, name, eps).
    heyoka.real128 (IEEE quadruple: 113-bit mantissa, eps 1.9e-34, software arithmetic) where the build has it,
    else np.longdouble where it is wider than double (x86: 64-bit mantissa, eps 1.1e-19).  heyoka.real (MPFR,
    any precision) is not used: at 113 bits it is quadruple's precision at a higher cost, and wider still
    costs more again than the held-out scenes need (their round-off floor in quadruple is far below any rtol)."""
    try:
        import heyoka as hy
    except ImportError as exc:
        raise PeerUnavailable(f"heyoka is not installed ({exc}); pip install 'adbgen[peers]'") from None
    if getattr(hy, "_with_real128", lambda: False)():
        return hy.real128, "real128", 2.0 ** -112  # 1.93e-34
    if np.finfo(np.longdouble).eps < np.finfo(float).eps:
        return np.longdouble, "long double", float(np.finfo(np.longdouble).eps)
    raise PeerUnavailable("this heyoka build has no real128 and long double is no wider than double")


def check_extended(peer, module, p, fp_type, samples: int = 20, seed: int = 0, t_span: float = 1.0) -> float:
    """Largest relative difference (norm-wise) between the peer's rhs evaluated in `fp_type` and the
    generated module's (double) rhs, at random states and times in [0, t_span] (time-dependent laws): the
    translation in extended precision is the generated program (round-off only: ~1e-16), not a lookalike."""
    return _worst_difference(lambda y, t: peer.rhs(y, p, t, fp_type=fp_type), module, p, samples, seed, t_span)


def _worst_difference(rhs, module, p, samples: int, seed: int, t_span=None) -> float:
    """max over random states (and times in [0, t_span]; t = 0 without one) of |rhs(y, t) - module.rhs| over
    max |module.rhs|."""
    rng = np.random.default_rng(seed)
    n = len(module.STATE_NAMES)
    worst = 0.0
    for _ in range(samples):
        y = rng.uniform(-1.0, 1.0, n)
        y[: n // 2] *= 0.1
        t = 0.0 if t_span is None else float(rng.uniform(0.0, t_span))
        ref = np.asarray(module.rhs(t, y, p), float)
        worst = max(worst, float(np.max(np.abs(rhs(y, t) - ref)) / max(np.max(np.abs(ref)), 1e-300)))
    return worst


def time_breakpoints(module, p, t_end: float, grid: int = 2001, seed: int = 0) -> list[float]:
    """The times in (0, t_end) where a piecewise law of time switches branch: the roots of l - r for each
    condition ["<", l, r] of the generated program (program.json) that depends on t and the parameters
    only (the same margin at two random states), found on an even grid of `grid` times and refined by
    bisection to double precision.  A Taylor integrator (heyoka) expands ``select`` on the branch the step
    starts on, so a step across a switch integrates part of it on the wrong branch, unnoticed by its error
    control: the reference stops at each of these times (`Heyoka.run_extended`; the run-up's ramp at
    t = t_ramp, measured: without the stop, t_dec on 33_two_plane_ramp came out 3.7e-3 late in real128, with it
    the check reference's (Taylor order 20) t_dec to 4e-12 in long double)."""
    import math

    from scipy.optimize import brentq

    from adbgen.codegen.program_tree import evaluate

    statements, outputs = generated_program(module)
    n = len(module.STATE_NAMES)
    functions = {name: getattr(math, name) for name in ("sin", "cos", "tan", "exp", "log", "sqrt", "atan")}

    def margins(y, t):
        found = []
        evaluate(statements, outputs, y, list(map(float, p)), float(t),
                 {**functions, "select": lambda c, a, b: a if c else b,
                  "less": lambda l, r: found.append(l - r) or l < r})
        return np.array(found, float)

    rng = np.random.default_rng(seed)
    a, b = rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)
    if margins(a, 0.0).size == 0:  # no condition at all: no law of time switches
        return []
    times = np.linspace(0.0, float(t_end), grid)
    table = np.array([margins(a, t) for t in times])
    other = np.array([margins(b, t) for t in times[:: max(1, grid // 50)]])
    laws = [k for k in range(table.shape[1]) if np.array_equal(other[:, k], table[:: max(1, grid // 50), k])]
    out = set()
    for k in laws:
        for i in np.nonzero(np.signbit(table[:-1, k]) != np.signbit(table[1:, k]))[0]:
            root = brentq(lambda t: margins(a, t)[k], times[i], times[i + 1], xtol=1e-15 * max(1.0, t_end))
            if 0.0 < root < t_end:
                out.add(float(root))
    return sorted(out)


def check_equations(peer, module, p, samples: int = 50, seed: int = 0) -> float:
    """Largest relative difference (norm-wise) between a peer's rhs and the generated module's."""
    return _worst_difference(lambda y, t: peer.rhs(y, p), module, p, samples, seed)


__all__ = ["Heyoka", "HeyokaHandwritten", "JiTCODE", "PEERS", "PeerUnavailable", "check_equations", "check_extended", "extended_type", "generated_program", "time_breakpoints", "peer_versions"]
