"""Print a series program (`series.SeriesProgram`) as C99: the workspace struct, the constants'
set-up, and one function body that computes every series' coefficient K.

The body is written for any K (loops over the convolution index), and every helper it calls is
`always_inline`: called with a constant K (the engine's driver unrolls the orders of a step,
`analysis/engines/taylor_driver.c`), the compiler folds K and unrolls each convolution completely,
like a straight-line Taylor program; called with a run-time K (the library functions `<model>_taylor`
and `<model>_jet`), it is an ordinary loop.  Degrees known here bound the convolutions (a product
with the time costs a term or two) and zero the coefficients beyond a polynomial's degree.

Names in the struct: series v<N> (core, [MAXO + 2]) and b<N> (per ball, [NB][MAXO + 2]); constants
kc_<N>, kb_<N>[NB]; reciprocals of a quotient's leading coefficient rc_/rb_<node>; Piecewise flags
flag<N>; the Schur complement's LU factors (the kernel's own statements, once per step) sf_<name>.

Only a series whose past coefficients are read (a convolution's operand or result, one read at order 0
from a later order, a state, the time, a switch) keeps all its rows; every other one is written and read
at order K only and has one row, always row 0.  The series of an order-20 batch of 8 trajectories of the
two-ball rotor shrink from 86 kB to 37 kB (with the stepper's jet, 97 kB to 48 kB; at order 11, 57 kB to
29 kB): a step's series then stay in a 48 kB first-level cache instead of being evicted while the step
still needs them.  The order-11 batch on 1024 basin-map starts had run at 952-970 trajectories per CPU-s in
most runs and 1134-1152 in some, by where the workspace happened to lie; with the rows cut, 1133-1139 in
every run, the results bit for bit the same.
"""

from __future__ import annotations

import sympy as sp

from ..c.printer import CPrinter
from .series import INF, Branch, Def, Flag, Increment, Loop, Out, SeriesProgram, Solve


def _cf(v: float) -> str:
    text = repr(float(v))
    return text if any(c in text for c in ".eEn") else text + ".0"


class CEmitter:
    """C text of one series program (see the module docstring for the names).

    Lanes: every operation runs over lanes, `TS_CORE` (b < TS_B: the trajectories of a batch, 1 for
    one trajectory) for a core series and `TS_BALLS` (i < TS_NBP balls, padded to a multiple of 4 with
    copies of ball 0, times b < TS_B) for a ball's: the balls of one trajectory are the SIMD lanes of
    one instruction (an operation's lane loop vectorises once its convolution is unrolled), and a batch
    of trajectories is a second lane dimension.  Core series are [order][TS_B], ball series
    [order][TS_LB] with lane i * TS_B + b."""

    def __init__(self, prog: SeriesProgram, prefix: str):
        self.prog = prog
        self.prefix = prefix
        self.nb = prog.n_balls
        self.nbp = ((prog.n_balls + 3) // 4) * 4 if prog.n_balls else 0
        self.consts: dict = {}  # (srepr, ball) -> name
        self.core_consts: list = []
        self.ball_consts: list = []
        self.slot_syms = {sym for _, sym, _, _ in prog.slots}
        self.param_names = {sym: f"pb[{k}]" for k, sym in enumerate(prog.params)}
        self.recips: dict[str, bool] = {}  # reciprocal's name -> per ball (insertion order)
        self.solve_fields: list[str] = []
        for c in self.prog.constants():
            self.const(c)
        # series with a history: found by printing the body once (ptr and at record what they are asked)
        self.history: set[str] = set(prog.states.values()) | set(prog.ball_states)
        self.history |= {f.switch for f in prog.flags if f.switch}
        if self.time_node():
            self.history.add(self.time_node())
        self._collecting = True
        self.block(self.prog.body, 1)
        self._collecting = False

    # ------------------------------------------------------------------ constants
    def const(self, expr) -> str:
        """A C expression for a constant, inside a lane loop: a literal, or w->kc_N[b] / w->kb_N[TS_L]."""
        e = sp.sympify(expr)
        if e.is_number:
            return _cf(float(e))
        ball = bool(e.free_symbols & self.slot_syms)
        key = (sp.srepr(e), ball)
        if key not in self.consts:
            if ball:
                name = f"kb_{len(self.ball_consts)}"
                self.ball_consts.append((name, e))
            else:
                name = f"kc_{len(self.core_consts)}"
                self.core_consts.append((name, e))
            self.consts[key] = name
        name = self.consts[key]
        return f"w->{name}[TS_L]" if ball else f"w->{name}[b]"

    # ------------------------------------------------------------------ series access (inside a lane loop)
    def at(self, name: str, k: str = "K") -> str:
        nd = self.prog.nodes[name]
        if k != "K":
            self.history.add(name)
        elif not self._collecting and name not in self.history:
            k = "0"  # a series without history: its one row
        return f"w->{name}[{k}][TS_L]" if nd.ball else f"w->{name}[{k}][b]"

    def rows(self, name: str) -> str:
        return "TS_MAXO + 2" if name in self.history else "1"

    def deg(self, name: str) -> int:
        return self.prog.nodes[name].degree

    @staticmethod
    def _lo_hi(da: int, db: int) -> tuple[str, str]:
        """Bounds of j in sum_j a_j b_{K-j} for degrees da, db: max(0, K - db) .. min(K, da)."""
        lo = "0" if db >= INF else f"TS_MAX(0, K - {db})"
        hi = "K" if da >= INF else f"TS_MIN(K, {da})"
        return lo, hi

    @staticmethod
    def lanes(ball: bool) -> str:
        return "TS_BALLS" if ball else "TS_CORE"

    # ------------------------------------------------------------------ nodes
    def ptr(self, name: str) -> str:
        """(pointer to coefficient 0, stride between coefficients) of a series, inside a lane loop."""
        nd = self.prog.nodes[name]
        self.history.add(name)
        return f"&w->{name}[0][TS_L], TS_LB" if nd.ball else f"&w->{name}[0][b], TS_B"

    def node(self, nd) -> list[str]:
        op, a = nd.op, nd.args
        if op in ("state", "time", "cos_of", "solved"):
            return []
        w = self.at(nd.name)
        loop = self.lanes(nd.ball)
        if op in ("lin", "acc"):
            terms = [f"{self.const(c)} * {self.at(u)}" if sp.sympify(c) != 1 else self.at(u)
                     for c, u in zip(nd.coefs, a)]
            const = sp.sympify(nd.const)
            body = " + ".join(terms) if terms else "0.0"
            stmt = f"{w} = {body} + (K == 0 ? {self.const(const)} : 0.0);" if const != 0 else f"{w} = {body};"
        elif op == "mul":
            u, v = a
            lo, hi = self._lo_hi(self.deg(u), self.deg(v))
            stmt = f"{w} = ts_dot({self.ptr(u)}, {self.ptr(v)}, {lo}, {hi}, K);"
        elif op == "sqr":
            stmt = f"{w} = ts_sqr({self.ptr(a[0])}, K);"
        elif op == "div":
            u, v = a
            r = self.recip(nd)
            top = f"(K == 0 ? {self.const(nd.const)} : 0.0)" if not u else self.at(u)
            stmt = (f"{{ if (K == 0) {r} = 1.0 / {self.at(v, '0')}; "
                    f"{w} = ({top} - ts_dot({self.ptr(v)}, {self.ptr(nd.name)}, 1, K, K)) * {r}; }}")
        elif op == "sincos":
            stmt = f"ts_sincos({self.ptr(a[0])}, {self.ptr(nd.name)}, {self.ptr(nd.name2)}, K);"
        elif op in ("exp", "log", "sqrt"):
            stmt = f"ts_{op}({self.ptr(a[0])}, {self.ptr(nd.name)}, K);"
        elif op == "atan":
            stmt = f"ts_atan({self.ptr(a[0])}, {self.ptr(a[1])}, {self.ptr(nd.name)}, K);"
        elif op == "pow":
            e = sp.sympify(nd.const)
            if not e.is_number:
                raise ValueError(f"a power with a parameter as exponent: {e}")
            stmt = f"ts_pow({self.ptr(a[0])}, {self.ptr(nd.name)}, {_cf(float(e))}, K);"
        elif op == "ipow":
            stmt = f"{w} = ts_ipow_affine({self.ptr(a[0])}, {int(nd.const)}, K);"
        elif op == "select":
            u, v = a
            stmt = f"{w} = w->{nd.const}[b] ? {self.at(u)} : {self.at(v)};"
        else:  # pragma: no cover
            raise ValueError(op)
        if nd.degree < INF and op != "ipow":
            # a polynomial in s: nothing to compute past its degree (the bounds above assume so)
            return [f"if (K <= {nd.degree}) {{", f"    {loop} {stmt}", "} else {", f"    {loop} {w} = 0.0;", "}"]
        return [f"{loop} {stmt}"]

    def recip(self, nd) -> str:
        """A quotient's 1 / v_0 (per lane), inside a lane loop."""
        name = ("rb_" if nd.ball else "rc_") + nd.name
        self.recips.setdefault(name, nd.ball)
        return f"w->{name}[TS_L]" if nd.ball else f"w->{name}[b]"

    # ------------------------------------------------------------------ statements
    def block(self, stmts, depth: int) -> list[str]:
        ind = "    " * depth
        lines: list[str] = []
        for st in stmts:
            if isinstance(st, Def):
                lines += [ind + ln for ln in self.node(self.prog.nodes[st.node.name])]
            elif isinstance(st, Increment):
                lines += [ind + ln for ln in self.increment(st)]
            elif isinstance(st, Loop):
                lines += self.block(st.body, depth)  # every statement runs over the ball lanes
            elif isinstance(st, Flag):
                if any(t.node is not None and self.prog.nodes[t.node].ball for t in (st.lhs, st.rhs)):
                    raise ValueError("a Piecewise condition that depends on a ball")
                lines.append(f"{ind}if (K == 0) TS_CORE w->{st.name}[b] = {self.term0(st.lhs)} {st.rel} "
                             f"{self.term0(st.rhs)};")
            elif isinstance(st, Branch):
                # one trajectory: only the branch taken; a batch (lanes may differ): both, selected per lane
                lines.append("#if TS_B == 1")
                lines.append(f"{ind}if (w->{st.flag}[0]) {{")
                lines += self.block(st.then, depth + 1)
                lines.append(f"{ind}}} else {{")
                lines += self.block(st.other, depth + 1)
                lines.append(f"{ind}}}")
                lines.append("#else")
                lines += self.block(st.then, depth)
                lines += self.block(st.other, depth)
                lines.append("#endif")
            elif isinstance(st, Solve):
                lines += [ind + ln for ln in self.solve(st)]
            elif isinstance(st, Out):
                lines += [ind + ln for ln in self.out(st)]
            else:  # pragma: no cover
                raise TypeError(st)
        return lines

    def increment(self, st: Increment) -> list[str]:
        """acc += the balls' values, summed in ball order (the order the kernel's loop adds them)."""
        acc = f"w->{st.acc}"
        c = sp.sympify(st.coef)
        if st.arg is None:
            return [f"if (K == 0) TS_CORE for (int i = 0; i < {self.nb}; ++i) {acc}[0][b] += {self.const(c)};"]
        term = self.at(st.arg) if c == 1 else f"{self.const(c)} * {self.at(st.arg)}"
        cur = self.at(st.acc)
        return [f"TS_CORE {{ double s_ = {cur}; for (int i = 0; i < {self.nb}; ++i) s_ += {term}; {cur} = s_; }}"]

    def out(self, st: Out) -> list[str]:
        c = sp.sympify(st.coef)
        if st.arg is None:
            value = f"K == 0 ? {self.const(c)} : 0.0"
        else:
            value = self.at(st.arg) if c == 1 else f"{self.const(c)} * {self.at(st.arg)}"
        if st.ball:
            return [f"for (int i = 0; i < {self.nb}; ++i) for (int b = 0; b < TS_B; ++b) "
                    f"f[({st.row} + i) * TS_B + b] = {value};"]
        return [f"TS_CORE f[{st.row} * TS_B + b] = {value};"]

    def term0(self, t) -> str:
        c = self.const(t.coef)
        return c if t.node is None else f"{c} * {self.at(t.node, '0')}"

    def solve(self, st: Solve) -> list[str]:
        """S x = g in series: K = 0 factorises S_0 by the kernel's statements and solves; K > 0 solves
        S_0 x_K = g_K - sum_{j>=1} S_j x_{K-j} with the same factors.  Per trajectory lane."""
        r = len(st.g)
        factors = set(st.factor_syms)
        names0 = {st.s_syms[a * r + b]: (self.at(st.S[a][b], "0") if st.S[a][b] else "0.0")
                  for a in range(r) for b in range(r)}
        for sym in st.factor_syms:  # (in the statements' order: the output must not depend on hashing)
            field = f"sf_{sym.name}"
            if field not in self.solve_fields:
                self.solve_fields.append(field)
        fac = {s: f"w->sf_{s.name}[b]" for s in factors}
        local = {sym: f"ts_{sym.name}" for sym, _ in st.lets if sym not in factors}
        lines = ["if (K == 0) TS_CORE {"]
        printer = CPrinter({**names0, **fac, **local, **{st.g_syms[a]: self.at(st.g[a], "0") for a in range(r)}})
        printer.set_program(st.lets)
        for sym, expr in st.lets:
            if sym in factors:
                lines.append(f"    w->sf_{sym.name}[b] = {printer.doprint(expr)};")
            else:
                lines.append(f"    const double ts_{sym.name} = {printer.doprint(expr)};")
        for a in range(r):
            lines.append(f"    {self.at(st.x[a], '0')} = ts_{st.x_syms[a].name};")
        lines.append("} else TS_CORE {")
        for a in range(r):
            terms = [self.at(st.g[a])]
            for b in range(r):
                n = st.S[a][b]
                if n and self.deg(n) > 0:
                    hi = "K" if self.deg(n) >= INF else f"TS_MIN(K, {self.deg(n)})"
                    terms.append(f"ts_dot({self.ptr(n)}, {self.ptr(st.x[b])}, 1, {hi}, K)")
            lines.append(f"    const double ts_r{a} = " + " - ".join(terms) + ";")
        printer = CPrinter({**names0, **fac, **local, **{st.g_syms[a]: f"ts_r{a}" for a in range(r)}})
        printer.set_program(st.lets)
        for sym, expr in st.lets:
            if sym not in factors:
                lines.append(f"    const double ts_{sym.name} = {printer.doprint(expr)};")
        for a in range(r):
            lines.append(f"    {self.at(st.x[a])} = ts_{st.x_syms[a].name};")
        lines.append("}")
        return lines

    # ------------------------------------------------------------------ the pieces the template prints
    def body(self) -> str:
        return "\n".join(self.block(self.prog.body, 1)) + "\n"

    def fields(self) -> list[str]:
        """Declarations of the workspace struct's members."""
        self.body()  # collects the constants, reciprocals and factors the body uses
        out = []
        for name, nd in sorted(self.prog.nodes.items(), key=lambda kv: int(kv[0][1:])):
            out.append(f"double {name}[{self.rows(name)}][{'TS_LB' if nd.ball else 'TS_B'}];")
        out += [f"double {name}[TS_B];" for name, _ in self.core_consts]
        out += [f"double {name}[TS_LB];" for name, _ in self.ball_consts]
        out += [f"double {name}[{'TS_LB' if ball else 'TS_B'}];" for name, ball in self.recips.items()]
        out += [f"double {name}[TS_B];" for name in self.solve_fields]
        out += [f"int {f.name}[TS_B];" for f in self.prog.flags]
        if not out:
            out.append("double unused;")
        return out

    def setup(self) -> str:
        """Body of the set-up function: the constants from p (lane b's parameters at p + b * NP)."""
        self.body()
        n_params = len(self.prog.params)
        lines = ["    (void)w;", "    (void)p;"]
        if self.core_consts:
            printer = CPrinter(dict(self.param_names))
            lines.append("    TS_CORE {")
            lines.append(f"        const double *pb = p + b * {n_params};")
            for name, e in self.core_consts:
                lines.append(f"        w->{name}[b] = {printer.doprint(e)};")
            lines.append("    }")
        if self.ball_consts:
            lines.append("    TS_BALLS {")
            lines.append(f"        const double *pb = p + b * {n_params};")
            lines.append(f"        const int ib = i < {self.nb} ? i : 0;  /* padding lanes: copies of ball 0 */")
            names = dict(self.param_names)
            for sname, sym, indices, coefficients in self.prog.slots:
                table = f"ball_slot_{sname}"
                value = f"pb[{table}[ib]]" if all(c == 1.0 for c in coefficients) \
                    else f"{table}_coef[ib] * pb[{table}[ib]]"
                lines.append(f"        const double {sym.name} = {value};")
                names[sym] = sym.name
            printer = CPrinter(names)
            for name, e in self.ball_consts:
                lines.append(f"        w->{name}[TS_L] = {printer.doprint(e)};")
            lines.append("    }")
        return "\n".join(lines) + "\n"

    def load(self) -> str:
        """Body of ts_load(w, K, row): coefficient K of every state series from row (row[state * TS_B + b])."""
        lines = []
        for idx, name in sorted(self.prog.states.items()):
            lines.append(f"    TS_CORE w->{name}[K][b] = row[{idx} * TS_B + b];")
        for name, base in sorted(self.prog.ball_states.items(), key=lambda kv: kv[1]):
            lines.append(f"    TS_BALLS w->{name}[K][TS_L] = row[({base} + (i < {self.nb} ? i : 0)) * TS_B + b];")
        if not lines:
            lines.append("    (void)w; (void)K; (void)row;")
        return "\n".join(lines) + "\n"

    def time_node(self) -> str | None:
        return next((n for n, nd in self.prog.nodes.items() if nd.op == "time"), None)

    def switches(self) -> list[tuple[str, str]]:
        """(flag, series) of the Piecewise conditions whose sign change ends a step."""
        return [(f.name, f.switch) for f in self.prog.flags if f.switch]

    def count(self, order: int) -> dict:
        """Floating-point operations of one trajectory's coefficients 0..order (the per-step work of an
        order-`order` Taylor method before the step size and the polynomial's evaluation), a multiply
        and an add each one: {'total', 'per_op'}.  Ball operations count once per ball (not per lane)."""
        nb = max(self.prog.n_balls, 1)
        per: dict = {}

        def add(kind, n, ball):
            per[kind] = per.get(kind, 0) + n * (nb if ball else 1)

        for st in self.prog.walk():
            if isinstance(st, Def):
                nd = self.prog.nodes[st.node.name]
                for K in range(order):
                    add(nd.op, _flops(nd, K, self.prog), nd.ball)
            elif isinstance(st, Increment):
                for K in range(order):
                    add("acc", 2 if st.arg is not None else (1 if K == 0 else 0), True)
            elif isinstance(st, Solve):
                r = len(st.g)
                for K in range(order):
                    n = 0
                    if K > 0:
                        for a in range(r):
                            for b in range(r):
                                nm = st.S[a][b]
                                if nm and self.deg(nm) > 0:
                                    n += 2 * min(K, self.deg(nm))
                    n += 2 * r * r  # forward and back substitution (order 0 also factorises: r^3)
                    add("solve", n + (r ** 3 if K == 0 else 0), False)
            elif isinstance(st, Out):
                for K in range(order):
                    add("out", 1 if sp.sympify(st.coef) != 1 else 0, st.ball)
        return {"total": int(sum(per.values())), "per_op": per}


def _flops(nd, K: int, prog) -> int:
    """Flops of node nd at order K (a multiply-add counted as 2)."""
    d = nd.degree
    if K > d:
        return 0
    op = nd.op
    if op in ("lin", "acc"):
        return 2 * len(nd.args)
    if op == "mul":
        da, db = (prog.nodes[a].degree for a in nd.args)
        lo, hi = max(0, K - db), min(K, da)
        return 2 * max(0, hi - lo + 1)
    if op == "sqr":
        return K + 2
    if op == "div":
        return 2 * K + 2
    if op == "sincos":
        return 0 if K == 0 else 6 * K + 2  # j u_j once, two dot products, two scalings
    if op in ("exp",):
        return 0 if K == 0 else 3 * K + 1
    if op in ("log", "sqrt", "atan", "pow"):
        return 0 if K == 0 else 4 * K + 3
    if op == "ipow":
        return 6
    return 0


__all__ = ["CEmitter"]
