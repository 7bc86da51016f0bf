"""Run a series program (`series.SeriesProgram`) in plain Python: the reference semantics of the
recurrences, used by the pre-write checks (no compiler at `regenerate` time) and by the tests that
compare the emitted C with it.

    taylor(prog, t, y, p, order)            the solution's coefficients y_0..y_order (order+1 x states)
    jet(prog, t, ycoef, p, order, tdot=0)   f(t + tdot s, sum_k ycoef_k s^k) to order `order`

Slow (a Python loop per coefficient), exact to rounding; the arithmetic is whatever the operands are
(floats, or mpmath's mpf for a high-precision reference).
"""

from __future__ import annotations

import math

import sympy as sp

from .series import Branch, Def, Flag, Increment, Loop, Out, SeriesProgram, Solve

_REL = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


class _Run:
    def __init__(self, prog: SeriesProgram, t, p, order: int, ode: bool, tdot, lib=math):
        self.prog = prog
        self.order = order
        self.ode = ode
        self.lib = lib
        self.nb = max(prog.n_balls, 1)
        self.zero = lib.mpf(0) if hasattr(lib, "mpf") else 0.0
        self.t, self.tdot = t, tdot
        self.values = {sym: p[k] for k, sym in enumerate(prog.params)}
        self.ball_values = []
        for i in range(self.nb):
            vals = {}
            for name, sym, indices, coefficients in prog.slots:
                vals[sym] = coefficients[i] * p[indices[i]]
            self.ball_values.append(vals)
        self._const: dict = {}
        self.s: dict = {}  # name -> list (core) or list of lists (ball)
        for name, nd in prog.nodes.items():
            n = order + 2
            self.s[name] = [[self.zero] * n for _ in range(self.nb)] if nd.ball else [self.zero] * n
        self.flags: dict = {}
        self.factors: dict = {}
        self.f = [[self.zero] * (order + 1) for _ in range(prog.n_states)]

    # -- constants
    def const(self, expr, i: int | None = None):
        key = (expr, i)
        if key not in self._const:
            e = sp.sympify(expr)
            vals = dict(self.values)
            if i is not None:
                vals.update(self.ball_values[i])
            if self.lib is math:
                self._const[key] = float(e.xreplace({k: sp.Float(v) for k, v in vals.items()}))
            else:
                self._const[key] = self.lib.mpf(str(sp.N(e.xreplace({k: sp.Float(str(v), 40) for k, v in vals.items()}), 40)))
        return self._const[key]

    def ser(self, name: str, i: int | None):
        s = self.s[name]
        return s[i] if self.prog.nodes[name].ball else s

    # -- one node at order K
    def node(self, nd, K: int, i: int | None):
        L = self.lib
        w = self.ser(nd.name, i)
        a = [self.ser(x, i) if x else None for x in nd.args]
        op = nd.op
        if op == "state":
            return  # set by the outputs of the order before (or the input)
        if op == "time":
            w[K] = self.t if K == 0 else (self.tdot if K == 1 else self.zero)
        elif op in ("lin", "acc"):
            v = sum((self.const(c, i) * u[K] for c, u in zip(nd.coefs, a)), self.zero)
            if K == 0:
                v += self.const(nd.const, i)
            w[K] = v
        elif op == "mul":
            u, v = a
            w[K] = sum((u[j] * v[K - j] for j in range(K + 1)), self.zero)
        elif op == "sqr":
            u = a[0]
            w[K] = sum((u[j] * u[K - j] for j in range(K + 1)), self.zero)
        elif op == "div":
            u, v = a
            top = (self.const(nd.const, i) if K == 0 else self.zero) if u is None else u[K]
            w[K] = (top - sum((v[j] * w[K - j] for j in range(1, K + 1)), self.zero)) / v[0]
        elif op == "sincos":
            u = a[0]
            c = self.ser(nd.name2, i)
            if K == 0:
                w[0], c[0] = L.sin(u[0]), L.cos(u[0])
            else:
                w[K] = sum((j * u[j] * c[K - j] for j in range(1, K + 1)), self.zero) / K
                c[K] = -sum((j * u[j] * w[K - j] for j in range(1, K + 1)), self.zero) / K
        elif op == "exp":
            u = a[0]
            w[K] = L.exp(u[0]) if K == 0 else sum((j * u[j] * w[K - j] for j in range(1, K + 1)), self.zero) / K
        elif op == "log":
            u = a[0]
            w[K] = L.log(u[0]) if K == 0 else \
                (u[K] - sum((j * w[j] * u[K - j] for j in range(1, K)), self.zero) / K) / u[0]
        elif op == "sqrt":
            u = a[0]
            w[K] = L.sqrt(u[0]) if K == 0 else \
                (u[K] - sum((w[j] * w[K - j] for j in range(1, K)), self.zero)) / (2 * w[0])
        elif op == "atan":
            u, v = a  # v = 1 + u^2
            w[K] = L.atan(u[0]) if K == 0 else \
                (K * u[K] - sum(((K - j) * v[j] * w[K - j] for j in range(1, K)), self.zero)) / (K * v[0])
        elif op == "pow":
            u = a[0]
            e = self.const(nd.const, i)
            if K == 0:
                w[0] = u[0] ** e
            else:
                w[K] = sum(((e * (K - j) - j) * u[K - j] * w[j] for j in range(K)), self.zero) / (K * u[0])
        elif op == "ipow":
            u = a[0]
            n = int(nd.const)
            w[K] = math.comb(n, K) * u[0] ** (n - K) * u[1] ** K if K <= n else self.zero
        elif op == "select":
            u, v = a
            w[K] = u[K] if self.flags[nd.const] else v[K]
        elif op in ("cos_of", "solved"):
            return
        else:  # pragma: no cover
            raise ValueError(op)

    def block(self, stmts, K: int, i: int | None = None):
        for st in stmts:
            if isinstance(st, Def):
                self.node(self.prog.nodes[st.node.name], K, i)
            elif isinstance(st, Increment):
                acc = self.ser(st.acc, None)
                if st.arg is None:
                    if K == 0:
                        acc[0] += self.const(st.coef, i)
                else:
                    acc[K] += self.const(st.coef, i) * self.ser(st.arg, i)[K]
            elif isinstance(st, Loop):
                for b in range(self.prog.n_balls):
                    self.block(st.body, K, b)
            elif isinstance(st, Flag):
                if K == 0:
                    def value(term):
                        c = self.const(term.coef, i)
                        return c if term.node is None else c * self.ser(term.node, i)[0]
                    self.flags[st.name] = _REL[st.rel](value(st.lhs), value(st.rhs))
            elif isinstance(st, Branch):
                self.block(st.then if self.flags[st.flag] else st.other, K, i)
            elif isinstance(st, Solve):
                self.solve(st, K)
            elif isinstance(st, Out):
                v = self.const(st.coef, i)
                v = (v if K == 0 else self.zero) if st.arg is None else v * self.ser(st.arg, i)[K]
                row = st.row + (i if st.ball else 0)
                self.f[row][K] = v
            else:  # pragma: no cover
                raise TypeError(st)

    def solve(self, st: Solve, K: int):
        r = len(st.g)
        x = [self.s[n] for n in st.x]
        S = [[self.s[n] if n else None for n in row] for row in st.S]
        g = [self.s[n] for n in st.g]
        if K == 0:
            vals = {st.s_syms[a * r + b]: S[a][b][0] for a in range(r) for b in range(r)}
            vals |= {st.g_syms[a]: g[a][0] for a in range(r)}
            self.factors = {}
        else:
            vals = dict(self.factors)
            for a in range(r):
                acc = g[a][K]
                for b in range(r):
                    if S[a][b] is not None and self.prog.nodes[st.S[a][b]].degree > 0:
                        acc -= sum((S[a][b][j] * x[b][K - j] for j in range(1, K + 1)), self.zero)
                vals[st.g_syms[a]] = acc
        for sym, expr in st.lets:
            if K > 0 and sym in st.factor_syms:
                continue
            vals[sym] = _ev(expr, vals, self.lib)
            if K == 0 and sym in st.factor_syms:
                self.factors[sym] = vals[sym]
        if K == 0:
            for s_ in st.s_syms:
                self.factors[s_] = vals[s_]
        for a in range(r):
            x[a][K] = vals[st.x_syms[a]]


def _ev(expr, vals, lib):
    """A solve statement (sums, products, quotients of symbols) on the given values."""
    e = sp.sympify(expr)
    if e.is_Symbol:
        return vals[e]
    if e.is_Number:
        return lib.mpf(str(e)) if hasattr(lib, "mpf") else float(e)
    args = [_ev(a, vals, lib) for a in e.args]
    if e.is_Add:
        out = args[0]
        for v in args[1:]:
            out = out + v
        return out
    if e.is_Mul:
        out = args[0]
        for v in args[1:]:
            out = out * v
        return out
    if e.is_Pow:
        return args[0] ** int(e.exp) if e.exp.is_Integer else args[0] ** args[1]
    raise ValueError(f"unexpected {e} in the solve")


def _run(prog, t, p, order, ode, tdot, lib):
    return _Run(prog, t, p, order, ode, tdot, lib)


def _load_states(run: _Run, coef_rows):
    """State series from rows of coefficients (row k: the states' coefficient k)."""
    prog = run.prog
    for k, row in enumerate(coef_rows):
        for idx, name in prog.states.items():
            run.s[name][k] = row[idx]
        for name, base in prog.ball_states.items():
            for i in range(prog.n_balls):
                run.s[name][i][k] = row[base + i]


def taylor(prog: SeriesProgram, t, y, p, order: int, lib=math) -> list[list]:
    """The Taylor coefficients y_0..y_order of the solution through (t, y): rows of states."""
    run = _run(prog, t, p, order, True, 1 if lib is math else lib.mpf(1), lib)
    rows = [list(y)]
    _load_states(run, rows)
    for K in range(order):
        run.block(prog.body, K)
        nxt = [run.f[r][K] / (K + 1) for r in range(prog.n_states)]
        rows.append(nxt)
        for idx, name in prog.states.items():
            run.s[name][K + 1] = nxt[idx]
        for name, base in prog.ball_states.items():
            for i in range(prog.n_balls):
                run.s[name][i][K + 1] = nxt[base + i]
    return rows


def jet(prog: SeriesProgram, t, ycoef, p, order: int, tdot=0.0, lib=math) -> list[list]:
    """f(t + tdot s, y(s)) to order `order` for y(s) = sum_k ycoef[k] s^k (rows of states; missing rows
    are 0): rows f_0..f_order.  With ycoef = (y0, u) and tdot = 0, row k is D^k f(y0)[u]^k / k!."""
    run = _run(prog, t, p, order, False, tdot, lib)
    zero = run.zero
    rows = [list(r) for r in ycoef] + [[zero] * prog.n_states for _ in range(order + 1 - len(ycoef))]
    _load_states(run, rows[: order + 1])
    for K in range(order + 1):
        run.block(prog.body, K)
    return [[run.f[r][K] for r in range(prog.n_states)] for K in range(order + 1)]


def flags(prog: SeriesProgram, t, y, p) -> tuple:
    """The Piecewise conditions' values at (t, y, p) (the branches order 0 takes)."""
    run = _run(prog, t, p, 0, True, 1.0, math)
    _load_states(run, [list(y)])
    run.block(prog.body, 0)
    return tuple(run.flags.get(f.name) for f in prog.flags)


__all__ = ["flags", "jet", "taylor"]
