"""Loop rolling: the loop form's kernels (`ir.loops`) built from the per-ball block, so that programs do
not grow with the number of balls.

A `Kernel` is a list of operations (`Let`, `Var`, `Inc`, `Save`, `Fetch`, `Get`, `Put`) and loops
(`Balls` over the balls, `Columns` over the columns of a Jacobian), with SymPy expressions for the
arithmetic and integer positions (`Pos`) for the stores; the targets print it (`emit`).  Built from
the per-ball block (`passes.ball_split`), kept once:

- rhs: the core's parts, then one loop over the balls accumulating the Schur complement
  S = A0 + sum_i (A_i - b_i c_i / d_i) and its right-hand side g = f0 + sum_i (fc_i - b_i f_i / d_i)
  (thesis Appendix A, (A.9)-(A.13)) and keeping b_i/d_i, c_i, 1/d_i, f_i per ball; the unrolled LU
  of the small S (no pivoting, as in `lowering`); a loop back-substituting a_i = (f_i - c_i . a) / d_i
  (A.6).
- jac, jac_p: M d(q'')/dz = dR/dz with R = f - M q'' at fixed accelerations (as in `lowering`): the
  core's derivative entries, then a loop over the balls storing their derivative entries (the
  columns of the ball's own states and of its own parameters, the core columns' ball rows), then one
  loop over the columns solving each in place with the factorised S and the kept per-ball data.
- mass, forcing: the core block summed over the balls, the balls' entries in a loop.
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

from ..ir import symbol_kinds as kinds
from ..ir.balls import BallSplit
from ..ir.loops import Balls, Columns, Fetch, Get, Inc, Kernel, Let, LoopForm, Pos, Put, Save, Var
from .cse import cse_lets


def _kernel(ops, shape, zero: bool, arrays=()) -> Kernel:
    """A kernel without the per-ball arrays nothing reads back (and the stores into them)."""
    fetched = set()

    def scan(block):
        for op in block:
            if isinstance(op, (Balls, Columns)):
                scan(op.ops)
            elif isinstance(op, Fetch):
                fetched.add(op.array)

    def prune(block):
        out = []
        for op in block:
            if isinstance(op, Balls):
                op = Balls(prune(op.ops))
            elif isinstance(op, Columns):
                op = Columns(op.count, prune(op.ops), op.parameters)
            elif isinstance(op, Save) and op.array not in fetched:
                continue
            out.append(op)
        return tuple(out)

    scan(ops)
    return Kernel(prune(ops), tuple(shape), zero, tuple((a, w) for a, w in arrays if a in fetched))


def _sym(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


class _Kernels:
    """Builds the five kernels of one model from its per-ball split."""

    def __init__(self, split: BallSplit, coordinates, core: Sequence[int], extra_rates: Sequence[sp.Expr],
                 extra_states: Sequence[sp.Symbol], parameters: Sequence):
        self.s = split
        self.coords = coordinates
        self.core = list(core)
        self.r = len(core)
        self.N = len(coordinates)
        self.extra_rates = list(extra_rates)
        self.extra_states = list(extra_states)
        self.params = list(parameters)
        self.slot_syms = {sl.symbol for sl in split.slots}

    # -- positions
    def core_row(self, a: int, offset: int = 0) -> Pos:
        return Pos(offset + self.core[a])

    def ball_row(self, offset: int = 0) -> Pos:
        return Pos(offset + self.s.first, ball=True)

    # -- the structured solve shared by rhs and the Jacobians
    def accelerations(self) -> tuple[list[sp.Symbol], sp.Symbol]:
        """The names `solve` gives the core's accelerations, and the ball's (`ball_accel`)."""
        return [kinds.make(f"xa_{a}", kinds.SOLVE_RESULT, a) for a in range(self.r)], _sym("ball_acc")

    def solve(self, later: Sequence[sp.Expr] = ()) -> tuple:
        """The structured solve's ops, the core accelerations' symbols and the LU factors.

        `later`: per-ball expressions a second ball loop evaluates after the solve (a Jacobian's
        entries, in the accelerations of `accelerations`); they are CSE'd with the ball's block, what
        they share with it that does not need the accelerations (sin, cos of the ball's angle, ...) is
        computed in the first loop and kept per ball (array w_keep).  Returns also the second loop's
        prefix (fetches and the statements that need the accelerations) and `later` reduced."""
        s, r = self.s, self.r
        pre, red = cse_lets([e for row in s.A0 for e in row] + list(s.f0), "wc_")
        ops: list = list(pre)
        Sacc = [[kinds.make(f"S_{a}_{b}", kinds.SCHUR, a, b) for b in range(r)] for a in range(r)]
        G = [kinds.make(f"g_{a}", kinds.SCHUR_RHS, a) for a in range(r)]
        for a in range(r):
            for b in range(r):
                ops.append(Var(Sacc[a][b], red[a * r + b]))
        for a in range(r):
            ops.append(Var(G[a], red[r * r + a]))
        body_exprs = [e for row in s.A for e in row] + list(s.fc) + list(s.B) + list(s.C) + [s.D, s.f]
        lets, red = cse_lets(body_exprs + list(later), "wb_")
        red, red_later = red[: len(body_exprs)], red[len(body_exprs):]
        xa, acc = self.accelerations()
        late_syms = set(xa) | {acc}
        early, late = [], []
        for let in lets:
            if sp.sympify(let.expr).free_symbols & late_syms:
                late_syms.add(let.sym)
                late.append(let)
            else:
                early.append(let)
        wanted = set().union(*(sp.sympify(e).free_symbols for e in [op.expr for op in late] + red_later))
        keep = [let.sym for let in early if let.sym in wanted]
        lets = early
        it = iter(red)
        A = [[next(it) for _ in range(r)] for _ in range(r)]
        fc = [next(it) for _ in range(r)]
        B = [next(it) for _ in range(r)]
        C = [next(it) for _ in range(r)]
        D, f = next(it), next(it)
        body: list = list(lets)
        dinv, fl = _sym("ball_dinv"), _sym("ball_f")
        body += [Let(dinv, 1 / D), Let(fl, f)]
        bd = [_sym(f"ball_bd_{a}") for a in range(r)]
        cc = [_sym(f"ball_c_{a}") for a in range(r)]
        body += [Let(bd[a], B[a] * dinv) for a in range(r)] + [Let(cc[a], C[a]) for a in range(r)]
        for a in range(r):
            for b in range(r):
                body.append(Inc(Sacc[a][b], A[a][b] - bd[a] * cc[b]))
        for a in range(r):
            body.append(Inc(G[a], fc[a] - bd[a] * fl))
        body += [Save("w_bd", a, bd[a]) for a in range(r)] + [Save("w_c", a, cc[a]) for a in range(r)]
        body += [Save("w_dinv", 0, dinv), Save("w_f", 0, fl)]
        body += [Save("w_keep", k, sym) for k, sym in enumerate(keep)]
        ops.append(Balls(tuple(body)))
        lu_ops, factors = self.factor(Sacc)
        ops += lu_ops
        sol_ops, xc = self.core_solve(factors, G, "a")
        ops += sol_ops
        assert xc == xa
        self.keep_width = len(keep)
        return ops, xc, factors, [Fetch(sym, "w_keep", k) for k, sym in enumerate(keep)] + late, red_later

    def factor(self, S) -> tuple[list, dict]:
        """Unrolled LU (Doolittle, no pivoting) of the r x r Schur complement, as `lowering._Builder.factor`."""
        r = self.r
        ops = []
        U = [row[:] for row in S]
        L = [[sp.S.Zero] * r for _ in range(r)]
        for k in range(r):
            for i in range(k + 1, r):
                L[i][k] = kinds.make(f"LU_{i}_{k}", kinds.SOLVE_FACTOR, i, k)
                ops.append(Let(L[i][k], U[i][k] / U[k][k]))
                for j in range(k + 1, r):
                    sym = kinds.make(f"LU_{i}_{j}_{k}", kinds.SOLVE_FACTOR, i, j, k)
                    ops.append(Let(sym, U[i][j] - L[i][k] * U[k][j]))
                    U[i][j] = sym
        Uinv = [kinds.make(f"Uinv_{k}", kinds.SOLVE_FACTOR, k) for k in range(r)]
        ops += [Let(Uinv[k], 1 / U[k][k]) for k in range(r)]
        return ops, {"L": L, "U": U, "Uinv": Uinv}

    def core_solve(self, fac: dict, g: Sequence[sp.Expr], tag: str) -> tuple[list, list[sp.Symbol]]:
        r = self.r
        ops, z = [], []
        for a in range(r):
            sym = kinds.make(f"z{tag}_{a}", kinds.SOLVE_FORWARD, a)
            ops.append(Let(sym, g[a] - sp.Add(*[fac["L"][a][b] * z[b] for b in range(a)])))
            z.append(sym)
        x = [None] * r
        for a in reversed(range(r)):
            sym = kinds.make(f"x{tag}_{a}", kinds.SOLVE_RESULT, a)
            ops.append(Let(sym, (z[a] - sp.Add(*[fac["U"][a][b] * x[b] for b in range(a + 1, r)])) * fac["Uinv"][a]))
            x[a] = sym
        return ops, x

    def ball_accel(self, xc) -> tuple[list, sp.Symbol]:
        """Ball i's acceleration (A.6) from the kept c_i, 1/d_i, f_i (ops for a ball loop)."""
        r = self.r
        cc = [_sym(f"ball_c_{a}") for a in range(r)]
        ops = [Fetch(cc[a], "w_c", a) for a in range(r)]
        dinv, fl = _sym("ball_dinv"), _sym("ball_f")
        ops += [Fetch(dinv, "w_dinv", 0), Fetch(fl, "w_f", 0)]
        acc = _sym("ball_acc")
        ops.append(Let(acc, (fl - sp.Add(*[cc[a] * xc[a] for a in range(r)])) * dinv))
        return ops, acc

    def arrays(self, r: int) -> tuple[tuple[str, int], ...]:
        return (("w_bd", r), ("w_c", r), ("w_dinv", 1), ("w_f", 1)) + \
            ((("w_keep", self.keep_width),) if getattr(self, "keep_width", 0) else ())

    # -- the kernels
    def rhs(self) -> Kernel:
        N, r = self.N, self.r
        self.keep_width = 0
        ops, xc, _, _, _ = self.solve()
        core_rates = [self.coords[k].qd for k in self.core]
        ops += [Put(Pos(k), None, rate) for k, rate in zip(self.core, core_rates)]
        ops += [Put(self.core_row(a, N), None, xc[a]) for a in range(r)]
        acc_ops, acc = self.ball_accel(xc)
        ops.append(Balls(tuple([Put(self.ball_row(), None, self.s.qd)] + acc_ops + [Put(self.ball_row(N), None, acc)])))
        ops += [Put(Pos(2 * N + e), None, rate) for e, rate in enumerate(self.extra_rates)]
        return _kernel(ops, (2 * N + len(self.extra_rates),), False, self.arrays(r))

    def residuals(self):
        """R = f - M q'' at fixed accelerations: the core's part (r rows), the ball's share of the core
        rows (r) and the ball's own row, in the generic ball symbols."""
        s, r = self.s, self.r
        qdd = [self.coords[k].qdd for k in self.core]
        R0 = [s.f0[a] - sp.Add(*[s.A0[a][b] * qdd[b] for b in range(r)]) for a in range(r)]
        Rb = [s.fc[a] - sp.Add(*[s.A[a][b] * qdd[b] for b in range(r)]) - s.B[a] * s.qdd for a in range(r)]
        rho = s.f - sp.Add(*[s.C[a] * qdd[a] for a in range(r)]) - s.D * s.qdd
        return R0, Rb, rho, qdd

    def column_solve(self, count: int, fac: dict, parameters: bool, base: int = 0) -> Columns:
        """Solve the columns base..base+count-1 in place: rows N.. of out hold dR/dz on entry,
        d(q'')/dz on exit (any column: every ball's row may be nonzero)."""
        N, r = self.N, self.r
        col = Pos(base, column=True)
        ops: list = []
        g = [_sym(f"col_g_{a}") for a in range(r)]
        for a in range(r):
            v = _sym(f"col_v_{a}")
            ops += [Get(v, self.core_row(a, N), col), Var(g[a], v)]
        bd = [_sym(f"ball_bd_{a}") for a in range(r)]
        v = _sym("col_vb")
        ops.append(Balls(tuple([Fetch(bd[a], "w_bd", a) for a in range(r)] + [Get(v, self.ball_row(N), col)]
                               + [Inc(g[a], -bd[a] * v) for a in range(r)])))
        sol, x = self.core_solve(fac, g, "c")
        ops += sol
        ops += [Put(self.core_row(a, N), col, x[a]) for a in range(r)]
        cc = [_sym(f"ball_c_{a}") for a in range(r)]
        dinv, v2 = _sym("ball_dinv"), _sym("col_vl")
        ops.append(Balls(tuple([Fetch(cc[a], "w_c", a) for a in range(r)] + [Fetch(dinv, "w_dinv", 0),
                               Get(v2, self.ball_row(N), col),
                               Put(self.ball_row(N), col, (v2 - sp.Add(*[cc[a] * x[a] for a in range(r)])) * dinv)])))
        return Columns(count, tuple(ops), parameters)

    def ball_column_solve(self, fac: dict, base: int) -> Columns:
        """Solve the columns of ball j's own state (base + j) in place: dR/dz is nonzero in the core
        rows and ball j's row only, so g = v_core - (b_j/d_j) v_j, and every other ball's row is
        -(c_i . a) / d_i."""
        N, r = self.N, self.r
        col = Pos(base, column=True)
        own = Pos(N + self.s.first, column=True)
        g = [_sym(f"colb_g_{a}") for a in range(r)]
        vj, dj = _sym("colb_vj"), _sym("colb_dinv")
        bd = [_sym(f"colb_bd_{a}") for a in range(r)]
        ops: list = [Get(vj, own, col)] + [Fetch(bd[a], "w_bd", a, column=True) for a in range(r)]
        for a in range(r):
            v = _sym(f"colb_v_{a}")
            ops += [Get(v, self.core_row(a, N), col), Let(g[a], v - bd[a] * vj)]
        sol, x = self.core_solve(fac, g, "b")
        ops += sol
        ops += [Put(self.core_row(a, N), col, x[a]) for a in range(r)]
        cc = [_sym(f"ball_c_{a}") for a in range(r)]
        dinv = _sym("ball_dinv")
        ops.append(Balls(tuple([Fetch(cc[a], "w_c", a) for a in range(r)] + [Fetch(dinv, "w_dinv", 0),
                               Put(self.ball_row(N), col, -sp.Add(*[cc[a] * x[a] for a in range(r)]) * dinv)])))
        ops += [Fetch(dj, "w_dinv", 0, column=True), Put(own, col, vj * dj, add=True)]
        return Columns(self.s.n, tuple(ops))

    def core_derivatives(self, ops: list, xc, wrt, R0) -> list:
        """Appends the oscillator's rows and the core part's entries d/dz, (z, column) in `wrt`, to
        `ops`; returns the ops that give a ball loop its acceleration (`ball_accel`)."""
        N, r = self.N, self.r
        for e, rate in enumerate(self.extra_rates):
            for z, col in wrt:
                d = sp.diff(rate, z)
                if d != 0:
                    ops.append(Put(Pos(2 * N + e), col, d))
        accel = dict(zip([self.coords[k].qdd for k in self.core], xc))
        keys, exprs = [], []
        for a in range(r):
            for z, col in wrt:
                d = sp.diff(R0[a], z)
                if d != 0:
                    keys.append((self.core_row(a, N), col))
                    exprs.append(d.xreplace(accel))
        lets, red = cse_lets(exprs, "wd_")
        ops += lets + [Put(row, col, e) for (row, col), e in zip(keys, red)]
        acc_ops, _ = self.ball_accel(xc)
        return acc_ops

    def ball_derivatives(self, Rb, rho, qdd, columns) -> tuple[list, list]:
        """A ball's entries d/dz of its share of the core rows and of its own row, (z, column,
        factor) in `columns`, in the accelerations' symbols (`accelerations`)."""
        N, r = self.N, self.r
        xa, acc = self.accelerations()
        accel = {**dict(zip(qdd, xa)), self.s.qdd: acc}
        keys, exprs = [], []
        for row, R in [(self.core_row(a, N), Rb[a]) for a in range(r)] + [(self.ball_row(N), rho)]:
            for z, col, factor in columns:
                d = sp.diff(R, z)
                if d != 0:
                    keys.append((row, col))
                    exprs.append((factor * d).xreplace(accel))
        return keys, exprs

    def jac(self) -> Kernel:
        N, r = self.N, self.r
        S = 2 * N + len(self.extra_rates)
        core_z = [(self.coords[k].q, Pos(k)) for k in self.core] + [(self.coords[k].qd, Pos(N + k)) for k in self.core] \
            + [(z, Pos(2 * N + e)) for e, z in enumerate(self.extra_states)]
        own = [(self.s.q, Pos(self.s.first, ball=True)), (self.s.qd, Pos(N + self.s.first, ball=True))]
        R0, Rb, rho, qdd = self.residuals()
        keys, exprs = self.ball_derivatives(Rb, rho, qdd, [(z, col, 1) for z, col in core_z + own])
        ops, xc, fac, later, red = self.solve(exprs)
        ops += [Put(Pos(k), Pos(N + k), sp.S.One) for k in self.core]
        acc_ops = self.core_derivatives(ops, xc, core_z, R0)
        body = [Put(self.ball_row(), Pos(N + self.s.first, ball=True), sp.S.One)] + acc_ops + later
        body += [Put(row, col, e, add=not row.ball) for (row, col), e in zip(keys, red)]
        ops.append(Balls(tuple(body)))
        first, n = self.s.first, self.s.n
        for start, stop in ((0, first), (first + n, N + first), (N + first + n, S)):
            if stop > start:
                ops.append(self.column_solve(stop - start, fac, False, start))
        ops += [self.ball_column_solve(fac, first), self.ball_column_solve(fac, N + first)]
        return _kernel(ops, (S, S), True, self.arrays(r))

    def jac_p(self) -> Kernel:
        N, r = self.N, self.r
        S, P = 2 * N + len(self.extra_rates), len(self.params)
        shared = [(p.symbol, Pos(k)) for k, p in enumerate(self.params)]
        slots = [(sl.symbol, Pos(slot=sl.name), 1 if sl.unit_coefficients else _sym(f"{sl.symbol.name}_coef"))
                 for sl in self.s.slots]
        R0, Rb, rho, qdd = self.residuals()
        keys, exprs = self.ball_derivatives(Rb, rho, qdd, [(z, col, 1) for z, col in shared] + slots)
        ops, xc, fac, later, red = self.solve(exprs)
        acc_ops = self.core_derivatives(ops, xc, shared, R0)
        body = acc_ops + later + [Put(row, col, e, add=True) for (row, col), e in zip(keys, red)]
        ops.append(Balls(tuple(body)))
        ops.append(self.column_solve(P, fac, True))
        return _kernel(ops, (S, P), True, self.arrays(r))

    def mass(self) -> Kernel:
        s, r = self.s, self.r
        pre, red = cse_lets([e for row in s.A0 for e in row], "wc_")
        ops: list = list(pre)
        Sacc = [[_sym(f"S_{a}_{b}") for b in range(r)] for a in range(r)]
        ops += [Var(Sacc[a][b], red[a * r + b]) for a in range(r) for b in range(r)]
        lets, red = cse_lets([e for row in s.A for e in row] + list(s.B) + list(s.C) + [s.D], "wb_")
        body: list = list(lets)
        body += [Inc(Sacc[a][b], red[a * r + b]) for a in range(r) for b in range(r)]
        body += [Put(self.core_row(a), self.ball_row(), red[r * r + a]) for a in range(r)]
        body += [Put(self.ball_row(), self.core_row(a), red[r * r + r + a]) for a in range(r)]
        body.append(Put(self.ball_row(), self.ball_row(), red[-1]))
        ops.append(Balls(tuple(body)))
        ops += [Put(self.core_row(a), self.core_row(b), Sacc[a][b]) for a in range(r) for b in range(r)]
        return Kernel(tuple(ops), (self.N, self.N), True)

    def forcing(self) -> Kernel:
        s, r = self.s, self.r
        pre, red = cse_lets(list(s.f0), "wc_")
        ops: list = list(pre)
        F = [_sym(f"F_{a}") for a in range(r)]
        ops += [Var(F[a], red[a]) for a in range(r)]
        lets, red = cse_lets(list(s.fc) + [s.f], "wb_")
        body: list = list(lets) + [Inc(F[a], red[a]) for a in range(r)] + [Put(self.ball_row(), None, red[-1])]
        ops.append(Balls(tuple(body)))
        ops += [Put(self.core_row(a), None, F[a]) for a in range(r)]
        return Kernel(tuple(ops), (self.N,), True)


def build_loops(split: BallSplit, coordinates, core: Sequence[int], parameters: Sequence,
                extra_rates: Sequence[sp.Expr] = (), extra_states: Sequence[sp.Symbol] = ()) -> LoopForm:
    k = _Kernels(split, coordinates, core, extra_rates, extra_states, parameters)
    return LoopForm(split, len(coordinates), tuple(core), k.rhs(), k.jac(), k.jac_p(), k.mass(), k.forcing())
