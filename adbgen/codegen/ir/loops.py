"""The loop form's data: kernels whose size does not grow with the number of balls (issue 10).

A `Kernel` is a list of operations (`Let`, `Var`, `Inc`, `Save`, `Fetch`, `Get`, `Put`) and loops
(`Balls` over the balls, `Columns` over the columns of a Jacobian), with SymPy expressions for the
arithmetic and integer positions (`Pos`) for the stores; the targets print it (`emit`).  `LoopForm`
holds one model's five kernels and its per-ball block (`ir.balls.BallSplit`); the pass that builds
them is `passes.loop_form`, and `straight_line` gives an unrolled program (`ir.model.Program`) the
same shape.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .balls import BallSplit


@dataclass(frozen=True)
class Pos:
    """An index: base + (the ball index i if ball) + (the column index j if column); or the parameter
    index of a ball's slot (its table), when slot is set."""

    base: int = 0
    ball: bool = False
    column: bool = False
    slot: str = ""


@dataclass(frozen=True)
class Let:
    sym: sp.Symbol
    expr: sp.Expr


@dataclass(frozen=True)
class Var:  # a mutable scalar (an accumulator)
    sym: sp.Symbol
    expr: sp.Expr


@dataclass(frozen=True)
class Inc:  # sym += expr
    sym: sp.Symbol
    expr: sp.Expr


@dataclass(frozen=True)
class Save:  # array[i * width + k] = sym, in a ball loop
    array: str
    k: int
    sym: sp.Symbol


@dataclass(frozen=True)
class Fetch:  # sym = array[i * width + k], in a ball loop (array[j * width + k] with column: column j's ball)
    sym: sp.Symbol
    array: str
    k: int
    column: bool = False


@dataclass(frozen=True)
class Get:  # sym = out[row, col]
    sym: sp.Symbol
    row: Pos
    col: Pos | None


@dataclass(frozen=True)
class Put:  # out[row, col] = expr (or += with add)
    row: Pos
    col: Pos | None
    expr: sp.Expr
    add: bool = False


@dataclass(frozen=True)
class Balls:
    ops: tuple
    count: int | None = None  # the loop's length: the model's balls (None) or this many


@dataclass(frozen=True)
class Guard:  # the function ends with "no result" unless condition holds (closed forms, `describe`)
    condition: sp.Basic


@dataclass(frozen=True)
class Columns:  # for j in range(count): the columns base + j
    count: int
    ops: tuple
    parameters: bool = False  # the columns are parameters (AUTO-07p maps their index)


@dataclass(frozen=True)
class Kernel:
    """One function: `ops` in order, writing an output of `shape` (zeroed first if `zero`)."""

    ops: tuple
    shape: tuple[int, ...]
    zero: bool
    arrays: tuple[tuple[str, int], ...] = ()  # (name, width): per-ball work arrays of n * width

    def walk(self):
        """Every operation, loops flattened, in order."""
        def go(ops):
            for op in ops:
                if isinstance(op, (Balls, Columns)):
                    yield from go(op.ops)
                else:
                    yield op
        return go(self.ops)

    def definitions(self) -> list[tuple[sp.Symbol, sp.Expr]]:
        return [(op.sym, op.expr) for op in self.walk() if isinstance(op, (Let, Var))]

    def count_ops(self) -> int:
        exprs = [op.expr for op in self.walk() if isinstance(op, (Let, Var, Inc, Put))]
        return int(sum(sp.count_ops(e) for e in exprs))


@dataclass(frozen=True)
class LoopForm:
    """The per-ball structure and the five kernels of one model."""

    split: BallSplit
    n_coordinates: int
    core: tuple[int, ...]  # coordinate indices of the core
    rhs: Kernel
    jac: Kernel
    jac_p: Kernel
    mass: Kernel
    forcing: Kernel
    extra: dict = field(default_factory=dict)

    def kernels(self) -> dict[str, Kernel]:
        return {"rhs": self.rhs, "jac": self.jac, "jac_p": self.jac_p, "mass": self.mass, "forcing": self.forcing}

    def fingerprint_text(self) -> str:
        s = self.split
        parts = [repr((s.first, s.n, [(sl.name, sl.indices, sl.coefficients) for sl in s.slots], self.core))]
        for name, k in self.kernels().items():
            parts.append(name + repr((k.shape, k.zero, k.arrays)))
            for op in k.walk():
                parts.append(type(op).__name__ + ":" + ";".join(
                    sp.srepr(v) if isinstance(v, sp.Basic) else repr(v) for v in vars(op).values()))
            parts.append(_shape_of(k.ops))
        return "\n".join(parts)


def _shape_of(ops) -> str:
    """The nesting of loops (the walk flattens it)."""
    out = []
    for op in ops:
        if isinstance(op, Balls):
            out.append("B(" + _shape_of(op.ops) + ")")
        elif isinstance(op, Columns):
            out.append(f"C{op.count}{'p' if op.parameters else ''}(" + _shape_of(op.ops) + ")")
        else:
            out.append(".")
    return "".join(out)


def straight_line(program, zero: bool) -> Kernel:
    """A straight-line program (`ir.model.Program`, the unrolled form) as a kernel without loops."""
    ops: list = [Let(sym, expr) for sym, expr in program.assignments]
    if len(program.shape) == 2:
        ncol = program.shape[1]
        ops += [Put(Pos(idx // ncol), Pos(idx % ncol), e) for idx, e in program.outputs]
    else:
        ops += [Put(Pos(idx), None, e) for idx, e in program.outputs]
    return Kernel(tuple(ops), program.shape, zero)
