"""The lowering: a first-order system to the intermediate form (`ir`): by default the loop form
(`ball_split.split` verifies the per-ball block, `loop_form.build_loops` makes the kernels), or the
straight-line programs below (`build(form="unrolled")`, and any model whose balls are not alike).

Structure (thesis Appendix A, generalised in `adbgen.core.structure`): the mass matrix is
M = [[A, B], [C, D]] over core (rotor) and leaf (ball) coordinates with D diagonal.  The programs
never form M^-1: per ball they evaluate B_i, C_i, D_i, f_i (O(1) each, after common-subexpression
elimination), accumulate the r x r Schur complement S = A - sum_i B_i C_i / D_i and its right-hand
side, solve S a = g by an unrolled LU factorisation (no pivoting: S is the Schur complement of a
row-scaled symmetric positive definite matrix, so its leading minors are positive), and back-
substitute a_i = (f_i - C_i . a) / D_i.  The rhs program therefore grows linearly in n.

Jacobian.  Differentiating M(q) q'' = f(q, q') at fixed accelerations gives
M d(q'')/dy_j = d(f - M q'')/dy_j =: dR/dy_j.  The derivatives dR/dy_j are sparse (a ball's row
depends on the core and its own angle only: O(n) entries in all), and each column is solved with the
*same* factorised Schur complement.  The Jacobian is dense (every acceleration depends on every
angle through the rotor), so its O(n^2) entries cost O(n^2) multiply-adds; the expressions that are
differentiated stay O(n).  Parameter derivatives (for AUTO-07p's dfdp) use the same construction.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import sympy as sp

from ...core.first_order import FirstOrderSystem
from ...core.oscillator import Oscillator
from ...errors import AdbgenError
from ..ir import symbol_kinds as kinds
from ..ir.model import Continuation, ModelIR, Program, State
from ..names import validate_name
from .ball_split import BALL_PREFIX, NoBallStructure, split as split_balls
from .cse import cse
from .loop_form import build_loops

if TYPE_CHECKING:
    from ..ir.description import SelfDescription

# Names the programs create; chosen so they cannot collide with a model's parameter names
# (M, m, D, k, c, eps, ...; `build` checks it).
_TEMP_PREFIX = "w_"


class _Names:
    """Fresh, stable statement names."""

    def __init__(self):
        self.made: set[str] = set()

    def __call__(self, name: str) -> sp.Symbol:
        if name in self.made:
            raise ValueError(f"statement name {name} used twice")
        self.made.add(name)
        return sp.Symbol(name, real=True)


@dataclass(frozen=True)
class _Blocks:
    """M and f after the speed law (and the oscillator), indexed for the structure; made once per build."""

    coordinates: tuple
    core: tuple[int, ...]
    leaves: tuple[int, ...]
    mass: dict  # {(row, col): entry}, nonzero entries only
    f: tuple[sp.Expr, ...]

    @property
    def N(self) -> int:
        return len(self.coordinates)


def _blocks(system: FirstOrderSystem, oscillator: bool) -> tuple[_Blocks, Oscillator | None]:
    solve = system.solve
    eom = solve.eom
    law = dict(eom.driven_law)
    mass = {k: sp.sympify(v).xreplace(law) for k, v in eom.mass.items()}
    f = [sp.sympify(e).xreplace(law) for e in eom.forcing]
    osc = None
    if oscillator:
        osc = Oscillator.detect(list(mass.values()) + f, eom.time)
        mass = {k: osc.substitute(v, eom.time) for k, v in mass.items()}
        f = [osc.substitute(e, eom.time) for e in f]
    return _Blocks(eom.coordinates, tuple(solve.core), tuple(solve.leaves), mass, tuple(f)), osc


class _Builder:
    """Emits the structured solve as statements (shared by rhs, jac and jac_p)."""

    def __init__(self, blocks: _Blocks):
        self.coordinates = blocks.coordinates
        self.core = list(blocks.core)
        self.leaves = list(blocks.leaves)
        self.r = len(self.core)
        self.N = blocks.N
        self.names = _Names()
        self.statements: list[tuple[sp.Symbol, sp.Expr]] = []
        mass = blocks.mass
        self.mass_entries = mass
        self.A = [[mass.get((i, j), sp.S.Zero) for j in self.core] for i in self.core]
        self.B = [[mass.get((a, i), sp.S.Zero) for a in self.core] for i in self.leaves]  # column of M
        self.C = [[mass.get((i, a), sp.S.Zero) for a in self.core] for i in self.leaves]  # row of M
        self.D = [mass[(i, i)] for i in self.leaves]
        self.f = list(blocks.f)

    def emit(self, name: str, expr: sp.Expr, kind: str | None = None, *index: int) -> sp.Expr:
        """Assign expr to a named statement unless it is trivial (a number or a symbol); a `kind`
        registers the name (`symbol_kinds`)."""
        expr = sp.sympify(expr)
        if expr.is_Atom:
            return expr
        sym = self.names(name)
        if kind is not None:
            kinds.register(sym, kind, *index)
        self.statements.append((sym, expr))
        return sym

    def base(self) -> dict:
        """CSE the mass blocks and forcing together, emit them and return their handles.

        Records the full expression behind every emitted name in ``self.known`` so that later
        expressions (the Jacobian's derivatives) can reuse them instead of recomputing.
        """
        flat = [e for row in self.A for e in row] + [e for row in self.B for e in row] \
            + [e for row in self.C for e in row] + list(self.D) + list(self.f)
        repl, red = cse(flat, _TEMP_PREFIX)
        full: dict[sp.Symbol, sp.Expr] = {}
        for sym, expr in repl:
            self.names.made.add(sym.name)
            self.statements.append((sym, expr))
            full[sym] = expr.xreplace(full)
        it = iter(zip(red, flat))

        def handle(name):
            reduced, original = next(it)
            sym = self.emit(name, reduced)
            if sym.is_Symbol and sym.name == name:
                full[sym] = original
            return sym

        r, L = self.r, len(self.leaves)
        A = [[handle(f"Mcc_{a}_{b}") for b in range(r)] for a in range(r)]
        B = [[handle(f"Mcl_{i}_{a}") for a in range(r)] for i in range(L)]
        C = [[handle(f"Mlc_{i}_{a}") for a in range(r)] for i in range(L)]
        D = [handle(f"Mll_{i}") for i in range(L)]
        f = [handle(f"f_{k}") for k in range(self.N)]
        self.known = {expr: sym for sym, expr in full.items() if not expr.is_Atom}
        return {"A": A, "B": B, "C": C, "D": D, "f": f}

    def factor(self, h: dict) -> dict:
        """Schur complement S and its unrolled LU factors (Doolittle, no pivoting)."""
        r, L = self.r, len(self.leaves)
        Dinv = [self.emit(f"Mllinv_{i}", 1 / h["D"][i]) for i in range(L)]
        BD = [[self.emit(f"BD_{i}_{a}", h["B"][i][a] * Dinv[i]) for a in range(r)] for i in range(L)]
        S = [[self.emit(f"S_{a}_{b}", h["A"][a][b] - sp.Add(*[BD[i][a] * h["C"][i][b] for i in range(L)]), kinds.SCHUR, a, b)
              for b in range(r)] for a in range(r)]
        U = [row[:] for row in S]
        Lf = [[sp.S.Zero] * r for _ in range(r)]
        for k in range(r):
            for i in range(k + 1, r):
                Lf[i][k] = self.emit(f"LU_{i}_{k}", U[i][k] / U[k][k], kinds.SOLVE_FACTOR, i, k)
                for j in range(k + 1, r):
                    U[i][j] = self.emit(f"LU_{i}_{j}_{k}", U[i][j] - Lf[i][k] * U[k][j], kinds.SOLVE_FACTOR, i, j, k)
        Uinv = [self.emit(f"Uinv_{k}", 1 / U[k][k], kinds.SOLVE_FACTOR, k) for k in range(r)]
        return {**h, "Dinv": Dinv, "BD": BD, "L": Lf, "U": U, "Uinv": Uinv}

    def solve(self, fac: dict, core_rhs: Sequence[sp.Expr], leaf_rhs: Sequence[sp.Expr], tag: str) -> list[sp.Expr]:
        """M x = v by the structure, v = (core_rhs at core rows, leaf_rhs at leaf rows).

        Returns x ordered as the coordinates.  Zero entries of v cost nothing (a ball whose row of
        v is zero contributes neither to the reduced right-hand side nor to its own back-substitution
        beyond C_i . x_core).
        """
        r, L = self.r, len(self.leaves)
        g = [self.emit(f"gs{tag}_{a}", core_rhs[a] - sp.Add(*[fac["BD"][i][a] * leaf_rhs[i] for i in range(L)]))
             for a in range(r)]
        z = []
        for a in range(r):
            z.append(self.emit(f"zs{tag}_{a}", g[a] - sp.Add(*[fac["L"][a][b] * z[b] for b in range(a)])))
        xc = [sp.S.Zero] * r
        for a in reversed(range(r)):
            xc[a] = self.emit(f"xs{tag}_{a}", (z[a] - sp.Add(*[fac["U"][a][b] * xc[b] for b in range(a + 1, r)]))
                              * fac["Uinv"][a])
        xl = [self.emit(f"xs{tag}_{r + i}", (leaf_rhs[i] - sp.Add(*[fac["C"][i][a] * xc[a] for a in range(r)]))
                        * fac["Dinv"][i]) for i in range(L)]
        x = [sp.S.Zero] * self.N
        for a, k in enumerate(self.core):
            x[k] = xc[a]
        for i, k in enumerate(self.leaves):
            x[k] = xl[i]
        return x


def _residual_rows(builder: _Builder) -> list[sp.Expr]:
    """R_k = f_k - sum_j M_kj q''_j with the accelerations as symbols (after the speed law)."""
    acc = [c.qdd for c in builder.coordinates]
    rows = []
    for k in range(builder.N):
        row = builder.f[k]
        for j in range(builder.N):
            entry = builder.mass_entries.get((k, j))
            if entry is not None:
                row -= entry * acc[j]
        rows.append(row)
    return rows


def _rhs_program(blocks: _Blocks, osc: Oscillator | None) -> Program:
    b = _Builder(blocks)
    h = b.base()
    fac = b.factor(h)
    x = b.solve(fac, [h["f"][k] for k in b.core], [h["f"][k] for k in b.leaves], "")
    N = b.N
    coords = blocks.coordinates
    outputs = [(k, coords[k].qd) for k in range(N)] + [(N + k, x[k]) for k in range(N)]
    extra = osc.rates() if osc is not None else ()
    outputs += [(2 * N + r, rate) for r, rate in enumerate(extra)]
    return Program(tuple(b.statements), tuple(outputs), (2 * N + len(extra),))


def _derivative_program(blocks: _Blocks, wrt: Sequence[sp.Symbol], top: dict[tuple[int, int], sp.Expr],
                        osc: Oscillator | None) -> Program:
    """d(y')/dz for z in `wrt`: the rows of the accelerations by the structured solve per column
    (and the oscillator's rows, if any, by plain differentiation)."""
    b = _Builder(blocks)
    N = b.N
    rows = _residual_rows(b)
    deriv = {}
    for k, row in enumerate(rows):
        free = row.free_symbols
        for j, z in enumerate(wrt):
            if z in free:
                d = sp.diff(row, z)
                if d != 0:
                    deriv[(k, j)] = d
    keys = sorted(deriv)
    h = b.base()
    fac = b.factor(h)
    acc = b.solve(fac, [h["f"][k] for k in b.core], [h["f"][k] for k in b.leaves], "")
    # the derivatives were taken at fixed accelerations: the solved ones go in, and the
    # subexpressions already computed for the right-hand side are reused, not recomputed
    accel_of = {c.qdd: acc[k] for k, c in enumerate(blocks.coordinates)}
    exprs = [deriv[key].xreplace(accel_of).xreplace(b.known) for key in keys]
    repl, red = cse(exprs, "v_")
    for sym, expr in repl:
        b.names.made.add(sym.name)
        b.statements.append((sym, expr))
    dR = {key: b.emit(f"dR_{key[0]}_{key[1]}", e) for key, e in zip(keys, red)}
    ncol = len(wrt)
    outputs = [((i, j), v) for (i, j), v in top.items()]
    for j in range(ncol):
        core_v = [dR.get((k, j), sp.S.Zero) for k in b.core]
        leaf_v = [dR.get((k, j), sp.S.Zero) for k in b.leaves]
        if all(v == 0 for v in core_v + leaf_v):
            continue
        x = b.solve(fac, core_v, leaf_v, f"_{j}")
        outputs += [((N + k, j), x[k]) for k in range(N) if x[k] != 0]
    extra = osc.rates() if osc is not None else ()
    for r, rate in enumerate(extra):
        outputs += [((2 * N + r, j), d) for j, z in enumerate(wrt) if (d := sp.diff(rate, z)) != 0]
    flat = sorted(((i * ncol + j), v) for (i, j), v in outputs)
    return Program(tuple(b.statements), tuple(flat), (2 * N + len(extra), ncol))


def _mass_forcing_programs(blocks: _Blocks) -> tuple[Program, Program]:
    N = blocks.N
    keys = sorted(blocks.mass)
    repl, red = cse([blocks.mass[k] for k in keys], _TEMP_PREFIX)
    mass = Program(tuple(repl), tuple((i * N + j, e) for (i, j), e in zip(keys, red)), (N, N))
    repl, red = cse(blocks.f, _TEMP_PREFIX)
    forcing = Program(tuple(repl), tuple((k, e) for k, e in enumerate(red) if e != 0), (N,))
    return mass, forcing


def _describe(k: int, coordinates, leaves: set[int]) -> str:
    """What state k of y = (positions, rates) is, by its place, not its name (the rates are thesis (A.1)'s; the
    order is not (A.2)'s, which interleaves each coordinate with its rate)."""
    N = len(coordinates)
    if k >= N:
        return f"rate of {coordinates[k - N].name}"
    return "angle of a ball (rad)" if k in leaves else "rotor coordinate"


# The one switch between the two forms (issue 10): "loops" (the per-ball block once, loops over the
# balls; the default) or "unrolled" (straight-line programs, every ball written out).  A model whose
# balls are not alike (`ball_split.NoBallStructure`) has no loop form: asked for it, the lowering refuses
# (`LoopFormError`, naming the ball and the term; issue 20) rather than fall back to the unrolled form.
FORMS = ("loops", "unrolled")
DEFAULT_FORM = "loops"


class LoopFormError(AdbgenError):
    """The loop form was requested of a model whose balls have no common per-ball block."""


def build(name: str, system: FirstOrderSystem, *, title: str, n_balls: int,
          start: Sequence[float] | None = None, start_label: str = "",
          start_parameters: Sequence[float] | None = None, oscillator: bool = False,
          autonomous_extension: "ModelIR | None" = None, continuation: Continuation | None = None,
          balls: Sequence[dict] | None = None, form: str = DEFAULT_FORM,
          description: "SelfDescription | None" = None) -> ModelIR:
    """Lower a first-order system to the intermediate form (pure: same input, same output).

    With `oscillator`, the periodically forced system is lowered in its autonomous extension
    (`Oscillator`): two more states, osc_sin and osc_cos, after the rates.  `balls`: each ball's own
    parameters ({slot: c * parameter}, `ball_split.split`; default: those named <stem>_<i>).  `form`: see
    `FORMS`.  `description`: the self-description (`description.lower_description`), carried as it is.
    """
    if form not in FORMS:
        raise ValueError(f"form {form!r}: one of {', '.join(FORMS)}")
    validate_name(name)
    eom = system.solve.eom
    coords = system.coordinates
    N = len(coords)
    leaves = set(system.solve.leaves)
    states = tuple(State(s.name, s, _describe(k, coords, leaves)) for k, s in enumerate(system.states))
    params = tuple(system.parameters)
    y_syms = list(system.states)
    blocks, osc = _blocks(system, oscillator)
    if osc is not None:
        states += (State(osc.sin.name, osc.sin, f"sin({osc.frequency} t) on the oscillator's limit cycle (paper (40))"),
                   State(osc.cos.name, osc.cos, f"cos({osc.frequency} t) on the oscillator's limit cycle (paper (40))"))
        y_syms += [osc.sin, osc.cos]
    taken = {s.name for s in states} | {p.name for p in params}
    loop_form = None
    if form == "loops":
        try:
            split = split_balls(coords, blocks.core, blocks.leaves, blocks.mass, blocks.f, params, balls)
        except NoBallStructure as exc:  # never a silent fallback: the form produced is the form requested
            raise LoopFormError(f"{name}: the loop form was requested, but the balls have no per-ball split: {exc} "
                                "(--form unrolled writes every ball out)") from exc
        loop_form = build_loops(split, coords, blocks.core, params, osc.rates() if osc is not None else (),
                                [osc.sin, osc.cos] if osc is not None else ())
    if loop_form is not None:
        rhs = jac = jac_p = mass = forcing = None
        kernels = loop_form.kernels().values()
        made = [sym.name for k in kernels for sym, _ in k.definitions()]
        time_free = all(eom.time not in sp.sympify(op.expr).free_symbols
                        for op in loop_form.rhs.walk() if hasattr(op, "expr"))
        if any(name.startswith(BALL_PREFIX) for name in taken):
            raise ValueError(f"model symbols may not start with {BALL_PREFIX!r} (the loops' names)")
    else:
        rhs = _rhs_program(blocks, osc)
        time_free = all(eom.time not in e.free_symbols for _, e in rhs.assignments) and \
            all(eom.time not in e.free_symbols for _, e in rhs.outputs)
        jac = _derivative_program(blocks, y_syms, {(k, N + k): sp.S.One for k in range(N)}, osc)
        jac_p = _derivative_program(blocks, [p.symbol for p in params], {}, osc)
        mass, forcing = _mass_forcing_programs(blocks)
        made = [lhs.name for prog in (rhs, jac, jac_p, mass, forcing) for lhs, _ in prog.assignments]
    clash = taken & set(made)
    if clash:
        raise ValueError(f"statement names clash with model symbols: {sorted(clash)}")
    unrolled = None
    if loop_form is not None:
        unrolled = functools.cache(lambda: build(
            name, system, title=title, n_balls=n_balls, start=start, start_label=start_label,
            start_parameters=start_parameters, oscillator=oscillator, continuation=continuation,
            autonomous_extension=autonomous_extension.as_unrolled() if autonomous_extension is not None else None,
            form="unrolled", description=description))
    return ModelIR(
        name=name, title=title, reference=system.reference, n_balls=n_balls, autonomous=time_free,
        states=states, parameters=params,
        core=tuple(coords[k].name for k in blocks.core), leaves=tuple(coords[k].name for k in blocks.leaves),
        mass_pattern=tuple(sorted(blocks.mass)), rhs=rhs, jac=jac, jac_p=jac_p, mass=mass,
        forcing=forcing, start=tuple(float(v) for v in start) if start is not None else None,
        start_label=start_label,
        start_parameters=tuple(float(v) for v in (start_parameters if start_parameters is not None
                                                 else [p.default for p in params])) if start is not None else None,
        forcing_frequency=str(osc.frequency) if osc is not None else "",
        autonomous_extension=autonomous_extension, continuation=continuation, loops=loop_form,
        unrolled_form=unrolled, description=description,
    )
