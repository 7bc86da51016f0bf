"""Print a loop-form kernel (`loops.Kernel`) as the body of a function in one target's language.

The arithmetic goes through the same printers as the straight-line programs (`printers`: floats for
numbers, small powers as products, the ball-invariant order of terms); this module adds the control
flow and the addressing, which differ by target:

    dialect   states   parameters         outputs                         loops
    py        y[k]     p[k]               out[r] / out[r, c]              for i in range(n):
    c         y[k]     p[k]               out[r] / out[r * ncol + c]      for (int i = 0; i < n; ++i)
    auto      u[k]     par[APAR(k)]       f[r], ARRAY2D(dfdu, r, c), ARRAY2D(dfdp, r, APAR(c))

Ball i reads its angle and rate from the states at first + i and N + first + i, and its own
parameters (`ir.balls.Slot`) through index tables, ``ball_slot_<name>[i]`` (and ``..._coef[i]`` unless
every coefficient is 1): the only parts of a model's source that grow with n, with its metadata.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .ir.balls import BallSplit
from .ir.loops import Balls, Columns, Fetch, Get, Guard, Inc, Kernel, Let, Pos, Put, Save, Var
from .ir.model import TIME


@dataclass(frozen=True)
class Dialect:
    """How one target's function addresses its arrays and writes its statements (the module's table):
    the part of printing that differs by language.  Each target defines its own beside its
    configuration (`targets/<name>/dialect.py`); this base class holds what they share.

    ``time``: the function has an argument t (a C dialect silences it when unused)."""

    states: str  # the state array's name
    params: str  # the parameter array's name
    out: str  # the output array's name
    ncol: int  # columns of a matrix output (0: a vector)
    indent: str = "    "
    time: bool = True

    def param(self, index: str) -> str:
        return f"{self.params}[{index}]"

    def entry(self, row: str, col: str | None) -> str:
        """The output's element (row, col) (col None: a vector's element)."""
        raise NotImplementedError

    def let(self, name: str, value: str, mutable: bool = False) -> str:
        """A scalar's definition (an accumulator's when `mutable`)."""
        raise NotImplementedError

    def stmt(self, text: str) -> str:
        return text

    def loop(self, var: str, count: int) -> str:
        raise NotImplementedError

    def end(self) -> str | None:
        """What closes a loop (None: nothing, the indentation does)."""
        return None

    def array(self, name: str, size: int) -> str:
        """A work array of `size` doubles."""
        raise NotImplementedError

    def zero(self, shape: tuple[int, ...]) -> list[tuple[int, str]]:
        """Lines (extra depth, text) that set every entry of the output to zero."""
        raise NotImplementedError

    def unused(self, time: bool, states: bool, params: bool) -> list[str]:
        """Lines silencing the arguments the function does not read (False: not read)."""
        return []

    def guard(self, condition: str) -> list[tuple[int, str]]:
        """Lines (extra depth, text) that end the function with "no result" unless `condition` holds."""
        raise NotImplementedError


def paren(text: str) -> str:
    """`text` parenthesised unless it is a name or a number (an index expression in a product)."""
    return f"({text})" if not text.isidentifier() and not text.isdigit() else text


def slot_table(name: str) -> str:
    return f"ball_slot_{name}"


def _pos(p: Pos) -> str:
    if p.slot:
        return f"{slot_table(p.slot)}[i]"
    parts = ([str(p.base)] if p.base or not (p.ball or p.column) else []) + (["i"] if p.ball else []) \
        + (["j"] if p.column else [])
    return " + ".join(parts)


class Emitter:
    """Prints one kernel; `names` maps state and parameter symbols to identifiers."""

    def __init__(self, kernel: Kernel, dialect: Dialect, printer, names: dict, split: BallSplit | None,
                 n_coordinates: int, states, parameters):
        self.k = kernel
        self.d = dialect
        self.p = printer
        self.names = names
        self.split = split
        self.N = n_coordinates
        self.state_index = {s: k for k, s in enumerate(states)}
        self.param_index = {q: k for k, q in enumerate(parameters)}
        self.lines: list[str] = []
        self.declared: set = set()
        printer.set_program(kernel.definitions())

    def expr(self, e) -> str:
        return self.p.doprint(sp.sympify(e))

    def sym(self, s) -> str:
        return self.p.doprint(s)

    def line(self, depth: int, text: str) -> None:
        self.lines.append(self.d.indent * depth + text)

    def lines_at(self, depth: int, lines) -> None:
        for extra, text in lines:
            self.line(depth + extra, text)

    def let(self, depth: int, sym, value: str, mutable: bool = False) -> None:
        self.line(depth, self.d.let(self.sym(sym), value, mutable))

    def stmt(self, depth: int, text: str) -> None:
        self.line(depth, self.d.stmt(text))

    # -- what a block reads
    @staticmethod
    def _free(ops) -> set:
        out = set()
        for op in ops:
            if isinstance(op, (Balls, Columns)):
                out |= Emitter._free(op.ops)
            elif isinstance(op, (Let, Var, Inc, Put)):
                out |= sp.sympify(op.expr).free_symbols
            elif isinstance(op, Guard):
                out |= sp.sympify(op.condition).free_symbols
        return out

    @staticmethod
    def _flat_free(ops) -> set:
        """Symbols read by the operations of this block, not of the loops nested in it."""
        out = set()
        for op in ops:
            if isinstance(op, (Let, Var, Inc, Put)):
                out |= sp.sympify(op.expr).free_symbols
        return out

    def prologue(self, depth: int) -> None:
        used = self._free(self.k.ops)
        d = self.d
        ball_states, ball_params = set(), set()
        if self.split is not None:
            ball_states = {self.split.q, self.split.qd}
            ball_params = {sl.symbol for sl in self.split.slots} \
                | {sp.Symbol(f"{sl.symbol.name}_coef", real=True) for sl in self.split.slots}
        for text in d.unused(time=not d.time or TIME in used,
                             states=any(s in self.state_index or s in ball_states for s in used),
                             params=any(s in self.param_index or s in ball_params for s in used)):
            self.line(depth, text)
        for s, k in sorted(self.state_index.items(), key=lambda kv: kv[1]):
            if s in used:
                self.let(depth, s, f"{d.states}[{k}]")
        for q, k in sorted(self.param_index.items(), key=lambda kv: kv[1]):
            if q in used:
                self.let(depth, q, d.param(str(k)))
        n = self.split.n if self.split is not None else 0
        for name, width in self.k.arrays:
            self.line(depth, d.array(name, n * width))
        if self.k.zero:
            self.lines_at(depth, d.zero(self.k.shape))

    def ball_loads(self, depth: int, ops) -> None:
        used = self._flat_free(ops)
        s, d = self.split, self.d
        if s.q in used:
            self.let(depth, s.q, f"{d.states}[{s.first} + i]")
        if s.qd in used:
            self.let(depth, s.qd, f"{d.states}[{self.N + s.first} + i]")
        for sl in s.slots:
            if sl.symbol in used:
                value = d.param(f"{slot_table(sl.name)}[i]")
                if not sl.unit_coefficients:
                    value = f"{slot_table(sl.name)}_coef[i] * {value}"
                self.let(depth, sl.symbol, value)
            coef = sp.Symbol(f"{sl.symbol.name}_coef", real=True)
            if coef in used:
                self.let(depth, coef, f"{slot_table(sl.name)}_coef[i]")

    def block(self, ops, depth: int, widths: dict) -> None:
        d = self.d
        for op in ops:
            if isinstance(op, Let):
                self.let(depth, op.sym, self.expr(op.expr))
            elif isinstance(op, Var):
                self.let(depth, op.sym, self.expr(op.expr), mutable=True)
            elif isinstance(op, Inc):
                self.stmt(depth, f"{self.sym(op.sym)} += {self.expr(op.expr)}")
            elif isinstance(op, Save):
                self.stmt(depth, f"{op.array}[{self._slot(op.array, op.k, widths)}] = {self.sym(op.sym)}")
            elif isinstance(op, Fetch):
                self.let(depth, op.sym, f"{op.array}[{self._slot(op.array, op.k, widths, 'j' if op.column else 'i')}]")
            elif isinstance(op, Get):
                self.let(depth, op.sym, d.entry(_pos(op.row), None if op.col is None else _pos(op.col)))
            elif isinstance(op, Put):
                target = d.entry(_pos(op.row), None if op.col is None else _pos(op.col))
                self.stmt(depth, f"{target} {'+=' if op.add else '='} {self.expr(op.expr)}")
            elif isinstance(op, Guard):
                self.lines_at(depth, d.guard(self.expr(op.condition)))
            elif isinstance(op, Balls):
                self.loop(depth, "i", self.split.n if op.count is None else op.count)
                if self.split is not None:
                    self.ball_loads(depth + 1, op.ops)
                self.block(op.ops, depth + 1, widths)
                self.end(depth)
            elif isinstance(op, Columns):
                self.loop(depth, "j", op.count)
                self.block(op.ops, depth + 1, widths)
                self.end(depth)
            else:  # pragma: no cover - every operation is handled above
                raise TypeError(op)

    @staticmethod
    def _slot(array: str, k: int, widths: dict, var: str = "i") -> str:
        w = widths[array]
        index = var if w == 1 else f"{var} * {w}"
        return index if k == 0 else f"{index} + {k}"

    def loop(self, depth: int, var: str, count: int) -> None:
        self.line(depth, self.d.loop(var, count))

    def end(self, depth: int) -> None:
        text = self.d.end()
        if text is not None:
            self.line(depth, text)

    def emit(self, depth: int = 1) -> str:
        self.prologue(depth)
        self.block(self.k.ops, depth, dict(self.k.arrays))
        return "\n".join(self.lines) + "\n"


def tables(split: BallSplit) -> list[tuple[str, str, tuple]]:
    """(name, "int" | "double", values) of the ball-slot tables a model's loops read."""
    out = []
    for sl in split.slots:
        out.append((slot_table(sl.name), "int", sl.indices))
        if not sl.unit_coefficients:
            out.append((slot_table(sl.name) + "_coef", "double", sl.coefficients))
    return out
