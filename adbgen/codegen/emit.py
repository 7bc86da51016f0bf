"""Print a loop-form kernel (`loops.Kernel`) as the body of a function in one target's language.

The arithmetic goes through the same printers as the straight-line programs (`printers`: floats for
numbers, small powers as products, the ball-invariant order of terms); this module adds the control
flow and the addressing, which differ by target:

    dialect   states   parameters         outputs                         loops
    py        y[k]     p[k]               out[r] / out[r, c]              for i in range(n):
    c         y[k]     p[k]               out[r] / out[r * ncol + c]      for (int i = 0; i < n; ++i)
    auto      u[k]     par[APAR(k)]       f[r], ARRAY2D(dfdu, r, c), ARRAY2D(dfdp, r, APAR(c))

Ball i reads its angle and rate from the states at first + i and N + first + i, and its own
parameters (`balls.Slot`) through index tables, ``ball_slot_<name>[i]`` (and ``..._coef[i]`` unless
every coefficient is 1): the only parts of a model's source that grow with n, with its metadata.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .balls import BallSplit
from .loops import Balls, Columns, Fetch, Get, Inc, Kernel, Let, Pos, Put, Save, Var


@dataclass(frozen=True)
class Dialect:
    """How one target's function addresses its arrays (see the module's table)."""

    language: str  # "py" or "c" (auto is C)
    states: str  # the state array's name
    params: str  # the parameter array's name
    out: str  # the output array's name
    ncol: int  # columns of a matrix output (0: a vector)
    auto: bool = False
    auto_columns: bool = False  # the output's columns are parameters (AUTO's dfdp)
    indent: str = "    "
    # a per-ball work array of `size` doubles (Python): the numba module puts it on the stack
    # (its `_scratch`; np.empty would cost a heap allocation, ~100 ns, per call)
    scratch: str = "np.empty({size})"

    def param(self, index: str) -> str:
        if self.auto:
            return f"{self.params}[{_apar(index)}]"
        return f"{self.params}[{index}]"

    def entry(self, row: str, col: str | None) -> str:
        if col is None:
            return f"{self.out}[{row}]"
        if self.auto:
            return f"ARRAY2D({self.out}, {row}, {_apar(col) if self.auto_columns else col})"
        if self.language == "py":
            return f"{self.out}[{row}, {col}]"
        if row.isdigit() and col.isdigit():
            return f"{self.out}[{int(row) * self.ncol + int(col)}]"
        return f"{self.out}[{_paren(row)} * {self.ncol} + {col}]"


def _apar(index: str) -> str:
    """AUTO's PAR index of model parameter `index` (PAR(11)-PAR(14) are AUTO's own)."""
    if index.isdigit():
        k = int(index)
        return str(k if k < 10 else k + 4)
    return f"APAR({index})"


def _paren(text: str) -> str:
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

    def let(self, depth: int, sym, value: str, mutable: bool = False) -> None:
        if self.d.language == "py":
            self.line(depth, f"{self.sym(sym)} = {value}")
        else:
            ctype = "doublereal" if self.d.auto else "double"
            self.line(depth, f"{'' if mutable else 'const '}{ctype} {self.sym(sym)} = {value};")

    def stmt(self, depth: int, text: str) -> None:
        self.line(depth, text if self.d.language == "py" else text + ";")

    # -- what a block reads
    @staticmethod
    def _free(ops) -> set:
        out = set()
        for op in ops:
            if isinstance(op, (Balls, Columns)):
                out |= Emitter._free(op.ops)
            elif isinstance(op, (Let, Var, Inc, Put)):
                out |= sp.sympify(op.expr).free_symbols
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
        if d.language == "c":
            if not d.auto and not any(s.name == "t" for s in used):
                self.line(depth, "(void)t;")
            if not any(s in self.state_index or s in ball_states for s in used):
                self.line(depth, f"(void){d.states};")
            if not any(s in self.param_index or s in ball_params for s in used):
                self.line(depth, f"(void){d.params};")
        for s, k in sorted(self.state_index.items(), key=lambda kv: kv[1]):
            if s in used:
                self.let(depth, s, f"{d.states}[{k}]")
        for q, k in sorted(self.param_index.items(), key=lambda kv: kv[1]):
            if q in used:
                self.let(depth, q, d.param(str(k)))
        n = self.split.n if self.split is not None else 0
        for name, width in self.k.arrays:
            if d.language == "py":
                self.line(depth, f"{name} = {d.scratch.format(size=n * width)}")
            else:
                self.line(depth, f"{'doublereal' if d.auto else 'double'} {name}[{n * width}];")
        if self.k.zero:
            self.zero(depth)

    def zero(self, depth: int) -> None:
        d = self.d
        size = 1
        for s in self.k.shape:
            size *= s
        if d.language == "py":
            self.line(depth, f"{d.out}[{', '.join([':'] * len(self.k.shape))}] = 0.0")
        elif d.auto and d.auto_columns:
            self.line(depth, f"for (int j = 0; j < {self.k.shape[1]}; ++j) {{")
            self.line(depth + 1, f"memset(&ARRAY2D({d.out}, 0, APAR(j)), 0, sizeof(doublereal) * {self.k.shape[0]});")
            self.line(depth, "}")
        else:
            ctype = "doublereal" if d.auto else "double"
            self.line(depth, f"memset({d.out}, 0, sizeof({ctype}) * {size});")

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
            elif isinstance(op, Balls):
                self.loop(depth, "i", self.split.n)
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
        if self.d.language == "py":
            self.line(depth, f"for {var} in range({count}):")
        else:
            self.line(depth, f"for (int {var} = 0; {var} < {count}; ++{var}) {{")

    def end(self, depth: int) -> None:
        if self.d.language == "c":
            self.line(depth, "}")

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
