"""The Taylor-series form of a model: its rhs kernel decomposed into elementary series operations.

Taylor's method needs the coefficients y_k of the solution y(t0 + s) = sum_k y_k s^k.  They follow
order by order from the right-hand side: if every intermediate quantity w of the rhs is kept as a
truncated series, w_K follows from its operands' coefficients up to K by the automatic-differentiation
recurrences (Jorba & Zou 2005, sec. 2; Moore 1966), and y_{K+1} = f_K / (K + 1).  This module turns
the model's rhs kernel (`codegen.ir.loops.Kernel`, the loop form or the straight-line one) into such a
program, once per model; `ccode` prints it as C, `evaluate` runs it in Python (the pre-write checks).

Operations (one `Node` each; w the result, u, v operands, c constants of the parameters):

    lin     w = c0 + sum_k c_k u_k                 w_K = sum_k c_k u_k,K (+ c0 at K = 0)
    mul     w = u v                                w_K = sum_j u_j v_{K-j}
    sqr     w = u^2                                the same sum, each cross term once
    div     w = u / v   (u may be a constant)      w_K = (u_K - sum_{j>=1} v_j w_{K-j}) / v_0
    sincos  (s, c) = (sin u, cos u)                s_K = 1/K sum_{j>=1} j u_j c_{K-j}, c_K likewise -s
    exp, log, sqrt, atan, pow (real exponent)     the standard recurrences (`recurrences`)
    ipow    w = u^n, u affine in s (the time)      w_K = C(n, K) u_0^(n-K) u_1^K
    select  w = flag ? u : v                       the branch of a Piecewise, decided at order 0
    acc     an accumulator: w = init + the increments the ball loops add (the Schur complement's sums)

and one block statement, `Solve`: the small linear system S x = g of the Schur complement (thesis
Appendix A, (A.7)-(A.8)) in series, S_0 x_K = g_K - sum_{j>=1} S_j x_{K-j}, with S_0 factorised once
per step by the kernel's own LU statements (no series of the LU factors, no reciprocals).

Structure kept: statements inside a `Balls` loop stay in a loop over the balls (one body, n copies
of its data), so the printed program's size does not depend on n; a statement inside the loop that
does not depend on the ball is hoisted before it; constant factors (parameters) are pulled out of
products and computed once per integration (`constants`), so a product by a parameter is not a
series product; a linear combination of products that share an operand becomes one product of that
operand and a linear combination (`_factor_products`).  Every node knows its degree in s (time is affine in s, parameters constant): a
product with the time costs O(1) per order, and coefficients beyond a node's degree are zero.

Exact exchange symmetry: every ball runs the same body, and sums and products take their operands in
the printers' ball-invariant order (`printers.BallInvariantOrder`), so identical balls that start
together get bitwise identical series.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
import sympy as sp

from ...ir import symbol_kinds as kinds
from ...ir.balls import BallSplit
from ...ir.loops import Balls, Fetch, Inc, Kernel, Let, Put, Save, Var
from ...printers import BallInvariantOrder

INF = 1 << 30  # the degree of a series that is not a polynomial in s
RELATIONS = {sp.StrictLessThan: "<", sp.LessThan: "<=", sp.StrictGreaterThan: ">", sp.GreaterThan: ">="}


class NotSeries(ValueError):
    """The kernel holds something the series form has no recurrence for."""


@dataclass(frozen=True)
class Node:
    """One series: computed at every order K from its operands' coefficients 0..K.

    `args`: operand node names; `coefs`: constant coefficients (lin: one per arg); `const`: lin's
    constant term, pow/ipow's exponent, select's flag name; `name2`: sincos's cosine.
    """

    name: str
    op: str
    args: tuple[str, ...] = ()
    coefs: tuple[sp.Expr, ...] = ()
    const: object = 0
    ball: bool = False
    degree: int = INF
    name2: str = ""
    index: int = -1  # state: its row (a ball state: the row of ball 0)


@dataclass(frozen=True)
class Term:
    """A value of the kernel: coef * node (node None: the constant coef)."""

    coef: sp.Expr
    node: str | None


@dataclass
class Def:
    node: Node


@dataclass
class Increment:  # inside a ball loop: acc_K += coef * arg_K (arg None: the constant coef at K = 0)
    acc: str
    coef: sp.Expr
    arg: str | None


@dataclass
class Loop:  # over the balls
    body: list


@dataclass
class Flag:
    """flag = lhs_0 REL rhs_0, decided at order 0; `switch` is the series lhs - rhs, whose first root in
    a step bounds the step (the branch must not change inside it)."""

    name: str
    rel: str
    switch: str  # node name of lhs - rhs (lin), or "" if constant
    lhs: Term
    rhs: Term


@dataclass
class Branch:
    flag: str
    then: list
    other: list


@dataclass
class Solve:
    """x = S^-1 g in series (the Schur complement's system).  S[a][b]: node name, or None where S_ab
    is identically zero; `lets`: the kernel's LU, forward and back substitution statements (sympy,
    over the symbols `s_syms`, `g_syms`), which compute the `x_syms` from them."""

    S: list
    g: list
    x: list
    s_syms: list
    g_syms: list
    x_syms: list
    lets: list  # [(symbol, expr)] in order
    factor_syms: list  # the lets that depend on S only (computed once per step, at order 0)


@dataclass
class Out:
    """The state's derivative: row (ball loop: row + i) gets coef * arg (arg None: the constant)."""

    row: int
    coef: sp.Expr
    arg: str | None
    ball: bool


@dataclass
class SeriesProgram:
    """A model's rhs as series statements (see the module docstring)."""

    name: str
    n_states: int
    n_params: int
    n_balls: int  # 0: no ball loops
    body: list
    nodes: dict  # name -> Node
    states: dict  # state row -> node name (core) / (ball node name, base row)
    ball_states: dict  # ball node name -> base row (row of ball 0)
    params: tuple  # parameter symbols, in order
    slots: tuple  # (name, symbol, indices, coefficients) of the balls' own parameters
    flags: list  # Flag statements (in order)
    uses_time: bool

    def walk(self, stmts=None):
        """Every statement, loops and branches flattened, in order."""
        for st in self.body if stmts is None else stmts:
            yield st
            if isinstance(st, Loop):
                yield from self.walk(st.body)
            elif isinstance(st, Branch):
                yield from self.walk(st.then)
                yield from self.walk(st.other)

    def constants(self) -> list[sp.Expr]:
        """Every constant the program multiplies by (coefficients, constant terms), in order."""
        out = []
        for st in self.walk():
            if isinstance(st, Def):
                out += list(st.node.coefs)
                if st.node.op in ("lin", "acc"):
                    out.append(sp.sympify(st.node.const))
                if st.node.op in ("div",) and not st.node.args[0]:
                    out.append(sp.sympify(st.node.const))
            elif isinstance(st, (Increment, Out)):
                out.append(st.coef)
            elif isinstance(st, Flag):
                out += [st.lhs.coef, st.rhs.coef]
        return out


class Decomposer:
    """Builds a `SeriesProgram` from a kernel (see `decompose`)."""

    def __init__(self, kernel: Kernel, *, name: str, states: Sequence[sp.Symbol], params: Sequence[sp.Symbol],
                 time: sp.Symbol, split: BallSplit | None, n_coordinates: int):
        self.kernel = kernel
        self.name = name
        self.state_index = {s: k for k, s in enumerate(states)}
        self.n_states = len(states)
        self.params = tuple(params)
        self.param_set = set(params)
        self.time = time
        self.split = split
        self.N = n_coordinates
        self.slot_syms = set()
        if split is not None:
            self.slot_syms = {sl.symbol for sl in split.slots} \
                | {sp.Symbol(f"{sl.symbol.name}_coef", real=True) for sl in split.slots}
        self.nodes: dict[str, Node] = {}
        self.env: dict[sp.Symbol, Term] = {}
        self.order = BallInvariantOrder(kernel.definitions())
        self.frames: list[dict] = [{"stmts": [], "memo": {}, "kind": "top"}]
        self.count = 0
        self.flags: list[Flag] = []
        self.saved: dict[tuple[str, int], Term] = {}
        self.states: dict[int, str] = {}
        self.ball_states: dict[str, int] = {}
        self.uses_time = False
        self.in_loop = False
        self.ball_memo: dict = {}

    # ------------------------------------------------------------------ constants
    def is_const(self, expr: sp.Expr) -> bool:
        """Depends on the parameters only (directly or through constant statements of the kernel)."""
        free = sp.sympify(expr).free_symbols
        return all(s in self.param_set or s in self.slot_syms
                   or (s in self.env and isinstance(self.env[s], Term) and self.env[s].node is None) for s in free)

    def const_value(self, expr: sp.Expr) -> sp.Expr:
        """A constant expression in the parameters alone (the kernel's constant statements inlined)."""
        expr = sp.sympify(expr)
        sub = {s: self.env[s].coef for s in expr.free_symbols if s in self.env}
        return expr.xreplace(sub) if sub else expr

    def ball_const(self, expr: sp.Expr) -> bool:
        return bool(sp.sympify(expr).free_symbols & self.slot_syms)

    # ------------------------------------------------------------------ nodes
    def _key(self, op, args, coefs, const) -> tuple:
        return (op, tuple(args), tuple(sp.srepr(c) for c in coefs), sp.srepr(const) if isinstance(const, sp.Basic)
                else repr(const))

    def _lookup(self, key):
        for frame in reversed(self.frames):
            if key in frame["memo"]:
                return frame["memo"][key]
        return None

    def node(self, op: str, args=(), coefs=(), const=0, degree: int = INF, two: bool = False) -> str | tuple:
        """The node computing op(args) (an existing one if the same was made before, in scope)."""
        key = self._key(op, args, coefs, const)
        hit = self._lookup(key)
        if hit is not None:
            return hit
        ball = _is_ball(self.nodes, self.ball_const, op, args, coefs, const)
        if ball and not self.in_loop:
            raise NotSeries("a ball quantity outside the loop over the balls")
        prefix = "b" if ball else "v"
        name = f"{prefix}{self.count}"
        self.count += 1
        name2 = ""
        if two:
            name2 = f"{prefix}{self.count}"
            self.count += 1
        nd = Node(name, op, tuple(args), tuple(coefs), const, ball, degree, name2)
        self.nodes[name] = nd
        if name2:
            self.nodes[name2] = Node(name2, "cos_of", (name,), (), 0, ball, degree)
        frame = self._place(ball)
        frame["stmts"].append(Def(nd))
        result = (name, name2) if two else name
        frame["memo"][key] = result
        return result

    def _place(self, ball: bool) -> dict:
        """The frame a new node goes in: the innermost, but a loop-invariant node inside a loop (not
        inside a branch) goes before the loop (its `hoist` list)."""
        inner = self.frames[-1]
        if not ball and inner["kind"] == "loop":
            return inner["hoist"]
        return inner

    # ------------------------------------------------------------------ expressions
    def term(self, expr) -> Term:
        expr = sp.sympify(expr)
        if self.is_const(expr):
            return Term(self.const_value(expr), None)
        if expr.is_Symbol:
            return self.symbol(expr)
        if expr.is_Add:
            return self.add(expr.args)
        if expr.is_Mul:
            return self.mul(expr.args)
        if expr.is_Pow:
            return self.mul((expr,))
        if isinstance(expr, sp.Piecewise):
            return self.piecewise(expr)
        if isinstance(expr, (sp.sin, sp.cos)):
            arg = self.as_node(self.term(expr.args[0]))
            s, c = self.node("sincos", (arg,), two=True)
            return Term(sp.S.One, s if isinstance(expr, sp.sin) else c)
        if isinstance(expr, (sp.exp, sp.log)):
            arg = self.as_node(self.term(expr.args[0]))
            return Term(sp.S.One, self.node(type(expr).__name__, (arg,)))
        if isinstance(expr, sp.atan):  # atan' = u' / v with v = 1 + u^2, a series of its own
            arg = self.as_node(self.term(expr.args[0]))
            v = self.lin([(sp.S.One, self.power(arg, 2))], sp.S.One)
            return Term(sp.S.One, self.node("atan", (arg, v)))
        if isinstance(expr, sp.Rel):
            raise NotSeries(f"a relation outside a Piecewise condition: {expr}")
        raise NotSeries(f"no Taylor recurrence for {type(expr).__name__}: {expr}")

    def symbol(self, s: sp.Symbol) -> Term:
        if s in self.env:
            return self.env[s]
        if s == self.time:
            self.uses_time = True
            return Term(sp.S.One, self.node("time", degree=1))
        if s in self.state_index:
            k = self.state_index[s]
            name = self.node("state", const=k)
            self.states[k] = name
            return Term(sp.S.One, name)
        sp_ = self.split
        if sp_ is not None and s in (sp_.q, sp_.qd):
            base = sp_.first + (0 if s == sp_.q else self.N)
            key = self._key("bstate", (), (), base)
            hit = self._lookup(key)
            if hit is None:
                name = f"b{self.count}"
                self.count += 1
                self.nodes[name] = Node(name, "state", (), (), base, True, INF, index=base)
                self.frames[0]["memo"][key] = name  # every ball loop sees the ball's states
                self.ball_states[name] = base
                hit = name
            return Term(sp.S.One, hit)
        raise NotSeries(f"unknown symbol {s} in the rhs kernel")

    def as_node(self, t: Term) -> str:
        """t as one node (a lin node if it carries a coefficient)."""
        if t.node is None:
            raise NotSeries("a constant where a series is needed")
        if t.coef == 1:
            return t.node
        return self.lin([(t.coef, t.node)], sp.S.Zero)

    def lin(self, terms: list[tuple[sp.Expr, str]], const: sp.Expr) -> str:
        deg = max([self.nodes[n].degree for _, n in terms] + [0])
        return self.node("lin", tuple(n for _, n in terms), tuple(c for c, _ in terms), sp.sympify(const), degree=deg)

    def add(self, args) -> Term:
        const = sp.S.Zero
        merged: dict[str, sp.Expr] = {}
        order: list[str] = []
        for a in self.order.ordered(list(args)):
            t = self.term(a)
            if t.node is None:
                const += t.coef
            else:
                if t.node not in merged:
                    merged[t.node] = sp.S.Zero
                    order.append(t.node)
                merged[t.node] += t.coef
        terms = [(merged[n], n) for n in order if merged[n] != 0]
        if not terms:
            return Term(const, None)
        if len(terms) == 1 and const == 0:
            return Term(terms[0][0], terms[0][1])
        return Term(sp.S.One, self.lin(terms, const))

    def mul(self, args) -> Term:
        coef = sp.S.One
        num: list[tuple[str, int]] = []  # (node, integer power >= 1)
        den: list[tuple[str, int]] = []
        for a in self.order.ordered(list(args)):
            if self.is_const(a):
                coef *= self.const_value(a)
                continue
            base, exp = (a.base, a.exp) if a.is_Pow else (a, sp.S.One)
            if exp.is_Integer:
                t = self.term(base)
                if t.node is None:  # cannot happen: a is not constant
                    raise NotSeries(f"unexpected constant base {base}")
                coef *= t.coef ** exp
                (num if exp > 0 else den).append((t.node, abs(int(exp))))
            elif exp.is_Rational or self.is_const(exp):
                u = self.as_node(self.term(base))  # the coefficient stays inside: sqrt(-2 u) is not sqrt(-2) sqrt(u)
                if exp == sp.Rational(1, 2):
                    num.append((self.node("sqrt", (u,)), 1))
                else:
                    num.append((self.node("pow", (u,), const=sp.sympify(exp)), 1))
            else:
                raise NotSeries(f"a power with a varying exponent: {a}")
        top = self.product(num)
        if not den:
            return Term(coef, top)
        bottom = self.product(den)
        if top is None:
            return Term(sp.S.One, self.node("div", ("", bottom), const=coef))
        return Term(coef, self.node("div", (top, bottom)))

    def power(self, base: str, n: int) -> str:
        if n == 1:
            return base
        deg = self.nodes[base].degree
        if deg <= 1 and n > 2:
            return self.node("ipow", (base,), const=n, degree=n * deg)
        if n == 2:
            return self.node("sqr", (base,), degree=_deg_mul(deg, deg))
        if n == 3:
            sq = self.power(base, 2)
            return self.mul_nodes(sq, base)
        if n == 4:
            return self.power(self.power(base, 2), 2)
        return self.node("pow", (base,), const=sp.Integer(n))

    def mul_nodes(self, a: str, b: str) -> str:
        if a == b:
            return self.power(a, 2)
        deg = _deg_mul(self.nodes[a].degree, self.nodes[b].degree)
        return self.node("mul", (a, b), degree=deg)

    def product(self, factors: list[tuple[str, int]]) -> str | None:
        if not factors:
            return None
        out = None
        for node, n in factors:
            p = self.power(node, n)
            out = p if out is None else self.mul_nodes(out, p)
        return out

    def piecewise(self, expr: sp.Piecewise) -> Term:
        if len(expr.args) != 2 or expr.args[1][1] is not sp.true:  # e.g. a sign's three branches
            raise NotSeries(f"only two-branch Piecewise (value, condition), (value, True): {expr}")
        (e1, c1), (e2, c2) = expr.args
        flag = self.flag(c1)
        results = []
        for branch in (e1, e2):
            frame = {"stmts": [], "memo": {}, "kind": "branch"}
            self.frames.append(frame)
            try:
                # the branch's value as one node, made inside the branch (a scaled value's lin node too)
                t = self.term(branch)
                node = self.as_node(t) if t.node is not None else self.lin([], t.coef)
            finally:
                self.frames.pop()
            results.append((node, frame["stmts"]))
        (a, s1), (b, s2) = results
        ball = self.nodes[a].ball or self.nodes[b].ball
        deg = max(self.nodes[a].degree, self.nodes[b].degree)
        name = f"{'b' if ball else 'v'}{self.count}"
        self.count += 1
        nd = Node(name, "select", (a, b), (), flag, ball, deg)
        self.nodes[name] = nd
        frame = self._place(ball)
        frame["stmts"].append(Branch(flag, s1, s2))
        frame["stmts"].append(Def(nd))
        return Term(sp.S.One, name)

    def flag(self, cond) -> str:
        if cond in self.env:
            t = self.env[cond]
            if isinstance(t, str):
                return t
        if not isinstance(cond, tuple(RELATIONS)):
            raise NotSeries(f"a Piecewise condition that is not <, <=, >, >=: {cond}")
        lhs, rhs = self.term(cond.lhs), self.term(cond.rhs)
        diff = self.add((cond.lhs, -cond.rhs))
        switch = self.as_node(diff) if diff.node is not None else ""
        name = f"flag{len(self.flags)}"
        f = Flag(name, RELATIONS[type(cond)], switch, lhs, rhs)
        self.flags.append(f)
        ball = any(t.node is not None and self.nodes[t.node].ball for t in (lhs, rhs)) \
            or any(self.ball_const(t.coef) for t in (lhs, rhs))
        self._place(ball)["stmts"].append(f)
        return name

    # ------------------------------------------------------------------ the kernel
    def run(self) -> SeriesProgram:
        ops = list(self.kernel.ops)
        solve_at = _find_solve(ops)
        k = 0
        while k < len(ops):
            op = ops[k]
            if solve_at is not None and k == solve_at[0]:
                self.solve(ops[solve_at[0]:solve_at[1]])
                k = solve_at[1]
                continue
            self.op(op)
            k += 1
        body = _merge_accumulators(self.frames[0]["stmts"], self.nodes)
        body, self.count = _factor_products(body, self.nodes, self.count, self.ball_const)
        missing = set(range(self.n_states)) - {st.row for st in _walk(body) if isinstance(st, Out) and not st.ball} \
            - {st.row + i for st in _walk(body) if isinstance(st, Out) and st.ball
               for i in range(self.split.n if self.split else 0)}
        if missing:
            raise NotSeries(f"the rhs kernel does not write rows {sorted(missing)}")
        slots = ()
        if self.split is not None:
            slots = tuple((sl.name, sl.symbol, sl.indices, sl.coefficients) for sl in self.split.slots)
        return SeriesProgram(self.name, self.n_states, len(self.params), self.split.n if self.split else 0, body,
                             self.nodes, self.states, self.ball_states, self.params, slots, self.flags,
                             self.uses_time)

    def op(self, op) -> None:
        if isinstance(op, Let):
            expr = sp.sympify(op.expr)
            if isinstance(expr, sp.Rel):
                self.env[op.sym] = self.flag(expr)  # a condition, named (the ramp's t < t_ramp)
            else:
                self.env[op.sym] = self.term(expr)
        elif isinstance(op, Var):
            if self.in_loop:
                raise NotSeries("an accumulator declared inside a loop")
            t = self.term(op.expr)
            deg = 0 if t.node is None else self.nodes[t.node].degree
            args, coefs = ((t.node,), (t.coef,)) if t.node is not None else ((), ())
            const = t.coef if t.node is None else sp.S.Zero
            name = f"v{self.count}"
            self.count += 1
            nd = Node(name, "acc", args, coefs, const, False, deg)
            self.nodes[name] = nd
            self.frames[-1]["stmts"].append(Def(nd))
            self.env[op.sym] = Term(sp.S.One, name)
        elif isinstance(op, Inc):
            acc = self.env[op.sym].node
            t = self.term(op.expr)
            self.frames[-1]["stmts"].append(Increment(acc, t.coef, t.node))
            nd = self.nodes[acc]
            deg = max(nd.degree, 0 if t.node is None else self.nodes[t.node].degree)
            self.nodes[acc] = Node(nd.name, nd.op, nd.args, nd.coefs, nd.const, nd.ball, deg)
        elif isinstance(op, Save):
            self.saved[(op.array, op.k)] = self.env[op.sym]
        elif isinstance(op, Fetch):
            self.env[op.sym] = self.saved[(op.array, op.k)]
        elif isinstance(op, Put):
            if op.col is not None or op.add:
                raise NotSeries("a matrix output in the rhs kernel")
            t = self.term(op.expr)
            self.frames[-1]["stmts"].append(Out(op.row.base, t.coef, t.node, op.row.ball))
        elif isinstance(op, Balls):
            if self.split is None:
                raise NotSeries("a ball loop without the ball structure")
            hoist = {"stmts": [], "memo": {}, "kind": "hoist"}
            # a ball's series persist through the whole order (every loop sees ball i's): one memo
            frame = {"stmts": [], "memo": self.ball_memo, "kind": "loop", "hoist": hoist}
            # hoisted nodes are visible after the loop too: memo them in the enclosing frame
            hoist["memo"] = self.frames[-1]["memo"]
            self.frames.append(frame)
            self.in_loop = True
            try:
                for inner in op.ops:
                    self.op(inner)
            finally:
                self.frames.pop()
                self.in_loop = False
            self.frames[-1]["stmts"] += hoist["stmts"]
            self.frames[-1]["stmts"].append(Loop(frame["stmts"]))
        else:
            raise NotSeries(f"unexpected {type(op).__name__} in the rhs kernel")

    def solve(self, lets: list) -> None:
        """The structured solve's statements (LU of the accumulated S, forward and back substitution)
        as one series solve, after checking numerically that they compute S^-1 g."""
        S_syms, g_syms, x_syms, factor = _solve_symbols(lets)
        r = len(g_syms)
        S = [[None] * r for _ in range(r)]
        for a in range(r):
            for b in range(r):
                sym = S_syms[a][b]
                t = self.env.get(sym)
                if t is None:
                    raise NotSeries(f"the solve's {sym} is not an accumulator")
                S[a][b] = t.node
        g = [self.env[s].node for s in g_syms]
        x = []
        for a in range(r):
            name = f"v{self.count}"
            self.count += 1
            self.nodes[name] = Node(name, "solved", (), (), a, False, INF)
            x.append(name)
            self.env[x_syms[a]] = Term(sp.S.One, name)
        self.frames[-1]["stmts"].append(Solve(S, g, x, [s for row in S_syms for s in row], g_syms, x_syms,
                                              [(op.sym, op.expr) for op in lets], factor))


def _merge_accumulators(body: list, nodes: dict) -> list:
    """One accumulator for each distinct (initial value, increments): the Schur complement's S_01 and
    S_10 of a symmetric mass matrix are accumulated twice by the kernel, the same sums."""
    signature: dict[str, list] = {}
    for st in _walk(body):
        if isinstance(st, Def) and st.node.op == "acc":
            nd = st.node
            signature[nd.name] = [nd.args, tuple(sp.srepr(c) for c in nd.coefs), sp.srepr(sp.sympify(nd.const))]
        elif isinstance(st, Increment):
            signature[st.acc].append((sp.srepr(sp.sympify(st.coef)), st.arg))
    first: dict = {}
    alias: dict[str, str] = {}
    for name, sig in signature.items():
        key = repr(sig)
        if key in first:
            alias[name] = first[key]
        else:
            first[key] = name
    if not alias:
        return body

    def rn(n):
        return alias.get(n, n) if n else n

    for name, nd in list(nodes.items()):
        if name in alias:
            del nodes[name]
        elif any(a in alias for a in nd.args):
            nodes[name] = Node(nd.name, nd.op, tuple(rn(a) for a in nd.args), nd.coefs, nd.const, nd.ball, nd.degree,
                               nd.name2, nd.index)

    def go(stmts):
        out = []
        for st in stmts:
            if isinstance(st, Def):
                if st.node.name in alias:
                    continue
                st = Def(nodes[st.node.name])
            elif isinstance(st, Increment):
                if st.acc in alias:
                    continue
                st = Increment(st.acc, st.coef, rn(st.arg))
            elif isinstance(st, Loop):
                st = Loop(go(st.body))
            elif isinstance(st, Branch):
                st = Branch(st.flag, go(st.then), go(st.other))
            elif isinstance(st, Solve):
                st = Solve([[rn(n) for n in row] for row in st.S], [rn(n) for n in st.g], st.x, st.s_syms, st.g_syms,
                           st.x_syms, st.lets, st.factor_syms)
            elif isinstance(st, Out):
                st = Out(st.row, st.coef, rn(st.arg), st.ball)
            elif isinstance(st, Flag):
                st = Flag(st.name, st.rel, rn(st.switch), Term(st.lhs.coef, rn(st.lhs.node)),
                          Term(st.rhs.coef, rn(st.rhs.node)))
            out.append(st)
        return out

    return go(body)


def _uses(body: list, nodes: dict) -> dict:
    """How many times each node is read (by nodes, increments, outputs, the solve, flags)."""
    n: dict[str, int] = {}

    def use(name):
        if name:
            n[name] = n.get(name, 0) + 1
    for nd in nodes.values():
        for a in nd.args:
            use(a)
    for st in _walk(body):
        if isinstance(st, Increment):
            use(st.acc), use(st.arg)
        elif isinstance(st, Out):
            use(st.arg)
        elif isinstance(st, Solve):
            for name in [*(x for row in st.S for x in row), *st.g, *st.x]:
                use(name)
        elif isinstance(st, Flag):
            use(st.switch), use(st.lhs.node), use(st.rhs.node)
    return n


def _factor_products(body: list, nodes: dict, count: int, ball_const) -> tuple[list, int]:
    """Distributivity: in a linear combination sum_j c_j u v_j of products that share an operand u (and are
    read nowhere else), one product u (sum_j c_j v_j) instead of one per term.  The ball's quantities of
    the rotor's equations are such sums (thesis (A.12)-(A.13): the rotor's velocities times cos phi_i and
    sin phi_i), so a ball's products go from 13 to 9 in the single-plane rotor and from 21 to 13 in the
    two-plane one (a linear combination costs O(1) per order, a product O(K)): flops per step at order 11
    6,274 -> 5,218 (thesis n = 2), 22,320 -> 18,448 (two-plane rotating frame).  The batch of 8
    trajectories at order 11 (heyoka's steps) measured 1349-1373 trajectories per CPU-s against 1133-1139
    before (1024 basin-map starts, one thread; heyoka 975-989 in the same runs).  A new combination
    of rotor series only goes before the ball loop; the terms keep the combination's (ball-invariant)
    order, so exchange symmetry is kept.  Not inside a Piecewise branch."""
    uses = _uses(body, nodes)
    made: dict = {}  # (id of the statement list, the combination's sorted terms) -> (that list, node)

    def is_ball(args, coefs=()) -> bool:
        return _is_ball(nodes, ball_const, "lin", args, coefs, 0)

    def new(op, args, coefs=(), const=0, degree=INF):
        nonlocal count
        ball = _is_ball(nodes, ball_const, op, args, coefs, const)
        name = f"{'b' if ball else 'v'}{count}"
        count += 1
        nodes[name] = Node(name, op, tuple(args), tuple(coefs), const, ball, degree)
        return nodes[name]

    def group(nd):
        """[(u, [(c, v, product)])] of the combination's single-use products sharing an operand u."""
        cands = [(c, a) for c, a in zip(nd.coefs, nd.args)
                 if nodes[a].op == "mul" and uses.get(a, 0) == 1 and nodes[a].args[0] != nodes[a].args[1]]
        groups = []
        while True:
            freq: dict[str, int] = {}
            for _, a in cands:
                for u in nodes[a].args:
                    freq[u] = freq.get(u, 0) + 1
            u = next((u for _, a in cands for u in nodes[a].args if freq[u] >= 2), None)
            if u is None:
                return groups
            members = [(c, next(x for x in nodes[a].args if x != u), a) for c, a in cands if u in nodes[a].args]
            groups.append((u, members))
            cands = [(c, a) for c, a in cands if u not in nodes[a].args]

    def go(stmts, hoist):
        out = []

        def place(ball: bool) -> list:  # a rotor-only node inside the ball loop goes before the loop
            return out if ball or hoist is None else hoist

        for st in stmts:
            if isinstance(st, Loop):
                before: list = []
                st = Loop(go(st.body, before))
                out += before
            elif isinstance(st, Def) and st.node.op == "lin":
                nd = nodes[st.node.name]
                groups = group(nd)
                if groups:
                    drop = set()
                    coefs, args = [], []
                    for u, members in groups:
                        vs, cs = [v for _, v, _ in members], [c for c, _, _ in members]
                        where = place(is_ball(vs, cs))
                        key = (id(where), tuple(sorted((v, sp.srepr(sp.sympify(c))) for c, v in zip(cs, vs))))
                        if key not in made:  # (the list is kept in the value: its id cannot be reused)
                            comb = new("lin", vs, cs, sp.S.Zero, max(nodes[v].degree for v in vs))
                            where.append(Def(comb))
                            made[key] = (where, comb)
                        comb = made[key][1]
                        prod = new("mul", [u, comb.name], degree=_deg_mul(nodes[u].degree, comb.degree))
                        place(prod.ball).append(Def(prod))
                        drop |= {p for _, _, p in members}
                        coefs.append(sp.S.One), args.append(prod.name)
                    for c, a in zip(nd.coefs, nd.args):
                        if a not in drop:
                            coefs.append(c), args.append(a)
                    for a in drop:
                        del nodes[a]
                    nodes[nd.name] = Node(nd.name, "lin", tuple(args), tuple(coefs), nd.const, nd.ball, nd.degree,
                                          nd.name2, nd.index)
                    st = Def(nodes[nd.name])
            out.append(st)
        return out

    body = go(body, None)

    def prune(stmts):
        res = []
        for st in stmts:
            if isinstance(st, Def) and st.node.name not in nodes:
                continue
            if isinstance(st, Loop):
                st = Loop(prune(st.body))
            res.append(st)
        return res

    return prune(body), count


def _is_ball(nodes: dict, ball_const, op: str, args, coefs, const) -> bool:
    """Whether a node op(args; coefs, const) is a ball's (one value per ball): an operand, a coefficient or
    (of a lin, acc, div or pow) the constant depends on the ball.  The decomposer's and the factoring's rule."""
    return any(nodes[a].ball for a in args if a) or any(ball_const(c) for c in coefs) \
        or (op in ("lin", "acc", "div", "pow") and isinstance(const, sp.Basic) and ball_const(const))


def _deg_mul(a: int, b: int) -> int:
    return INF if a >= INF or b >= INF else a + b


def _walk(stmts):
    for st in stmts:
        yield st
        if isinstance(st, Loop):
            yield from _walk(st.body)
        elif isinstance(st, Branch):
            yield from _walk(st.then)
            yield from _walk(st.other)


def _find_solve(ops) -> tuple[int, int] | None:
    """[start, stop) of the top-level run of the structured solve's statements (the symbols made as
    `symbol_kinds.SOLVE` by `loops._Kernels.solve`), if any."""
    idx = [k for k, op in enumerate(ops) if isinstance(op, Let) and kinds.kind_of(op.sym) in kinds.SOLVE]
    if not idx:
        return None
    start, stop = idx[0], idx[-1] + 1
    if idx != list(range(start, stop)):
        return None
    return start, stop


def _solve_symbols(lets) -> tuple[list, list, list, list]:
    """(S symbols r x r, g symbols, x symbols, factor lets) of the solve's statements, checked: the
    statements must compute x = S^-1 g (random diagonally dominant S, random g, against numpy)."""
    defined = {op.sym for op in lets}
    free = set().union(*(sp.sympify(op.expr).free_symbols for op in lets)) - defined
    x_syms = sorted((op.sym for op in lets if kinds.kind_of(op.sym) == kinds.SOLVE_RESULT), key=kinds.index_of)
    r = len(x_syms)
    by_index = {(kinds.kind_of(s), kinds.index_of(s)): s for s in free if kinds.kind_of(s) in (kinds.SCHUR, kinds.SCHUR_RHS)}
    S_syms = [[by_index.get((kinds.SCHUR, (a, b)), sp.Symbol(f"S_{a}_{b}", real=True)) for b in range(r)]
              for a in range(r)]
    g_syms = [by_index.get((kinds.SCHUR_RHS, (a,))) for a in range(r)]
    if r == 0 or any(s is None for s in g_syms) or free - set(g_syms) - {s for row in S_syms for s in row}:
        raise NotSeries("the structured solve's statements are not LU, forward and back substitution of S, g")
    rng = np.random.default_rng(7)
    for _ in range(3):
        Sn = rng.uniform(-1, 1, (r, r)) + r * np.eye(r)
        gn = rng.uniform(-1, 1, r)
        vals = {S_syms[a][b]: Sn[a, b] for a in range(r) for b in range(r)} | {g_syms[a]: gn[a] for a in range(r)}
        for op in lets:
            vals[op.sym] = float(sp.sympify(op.expr).xreplace(vals))
        got = np.array([vals[s] for s in x_syms])
        if not np.allclose(got, np.linalg.solve(Sn, gn), rtol=1e-12, atol=1e-12):
            raise NotSeries("the structured solve's statements do not compute S^-1 g")
    # the factorisation: statements that do not depend on g (computed once per step)
    g_dep = set(g_syms)
    factor = []
    for op in lets:
        if sp.sympify(op.expr).free_symbols & g_dep:
            g_dep.add(op.sym)
        else:
            factor.append(op.sym)
    return S_syms, g_syms, x_syms, factor


def decompose(ir) -> SeriesProgram:
    """The series program of a model's rhs (`ir`: a `ModelIR`); NotSeries if it has no series form."""
    kernel = ir.kernels()["rhs"]
    split = ir.loops.split if ir.loops is not None else None
    d = Decomposer(kernel, name=ir.name, states=[s.symbol for s in ir.states],
                   params=[p.symbol for p in ir.parameters], time=ir.time, split=split, n_coordinates=ir.n_coordinates)
    return d.run()


__all__ = ["INF", "Branch", "Decomposer", "Def", "Flag", "Increment", "Loop", "Node", "NotSeries", "Out",
           "SeriesProgram", "Solve", "Term", "decompose"]
