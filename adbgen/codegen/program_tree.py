"""The right-hand side as data: the numba module's rhs_inplace, unrolled, as expression trees (issue 33
item 2), written beside the module (`<model>/program.json`) for programs that evaluate the generated
equations on their own numbers or symbols (the benchmarks' peers: JiTCODE, heyoka) without reading the
generated source.

The trees are the statements of the loop-form kernel the numba target prints (`emit.Emitter`), in its
order, with every loop unrolled (ball i's loads, tables and work arrays resolved to states, parameters
and numbers) and every operation in the order the printer writes it (`printers.PrintRules`: the
ball-invariant order of terms and factors, small integer powers as products, SymPy's code printer's
numerator / denominator split of a product), so a peer evaluating a tree on floats performs the very
floating-point operations of the generated rhs (tested: bitwise equal).

A tree is a number, or a list whose first item says what it is:

    ["y", k], ["p", k], ["t"]           the state, the parameter, the time
    ["v", name]                         an earlier statement's value
    ["+", a, b, ...], ["*", a, b, ...]  left to right: ((a + b) + ...), ((a * b) * ...)
    ["/", a, b], ["neg", a]             a / b, -a
    ["pow", a, k]                       a ** k (an exponent the printer leaves to **)
    ["sin", a], ["cos", a], ...         math's function of that name (sqrt, exp, log, tan, atan, ...)
    ["<", l, r]                         the condition l < r (a statement may hold one)
    ["select", c, a, b]                 a where the condition c holds, else b (a piecewise law in t)

``program.json``: {"states": N, "statements": [[name, tree], ...], "outputs": [tree of out[0], ...]}.
Statements come in the module's order: the states and parameters the rhs reads first, then each ball's
loads and statements, ball after ball.
"""

from __future__ import annotations

import json

import sympy as sp
from sympy.core.mul import _keep_coeff

from .emit import Emitter
from .ir.model import TIME, ModelIR
from .ir.loops import Balls, Columns, Fetch, Get, Guard, Inc, Kernel, Let, Put, Save, Var
from .printers import _MAX_PRODUCT_POWER, BallInvariantOrder, identifiers

_FUNCTIONS = {sp.sin: "sin", sp.cos: "cos", sp.tan: "tan", sp.exp: "exp", sp.log: "log", sp.atan: "atan",
              sp.asin: "asin", sp.acos: "acos", sp.sinh: "sinh", sp.cosh: "cosh", sp.tanh: "tanh"}


class ProgramError(ValueError):
    """The kernel holds what the trees do not express (the numba module's rhs changed its form)."""


class _Trees:
    """SymPy expressions to trees, in the numba printer's operation order (see the module docstring)."""

    def __init__(self, order: BallInvariantOrder, env: dict):
        self.order = order
        self.env = env  # symbol -> tree

    def __call__(self, e) -> object:
        e = sp.sympify(e)
        if e.is_Symbol:
            if e in self.env:
                return self.env[e]
            if e == TIME:
                return ["t"]
            raise ProgramError(f"unknown symbol {e} in the rhs")
        if e.is_Number or e.is_NumberSymbol:
            return float(e)
        if e.is_Add:
            return ["+", *[self(a) for a in self.order.ordered(e.args)]]
        if e.is_Mul:
            return self.mul(sp.Mul(*self.order.ordered(e.args), evaluate=False))
        if e.is_Pow:
            return self.power(e)
        if isinstance(e, sp.Piecewise):
            return self.piecewise(e.args)
        if isinstance(e, (sp.StrictLessThan, sp.StrictGreaterThan)):  # a condition (a statement may hold one)
            return self.less(e)
        if e.func in _FUNCTIONS:
            return [_FUNCTIONS[e.func], *[self(a) for a in e.args]]
        if isinstance(e, sp.atan2):
            return ["atan2", self(e.args[0]), self(e.args[1])]
        raise ProgramError(f"no tree for {type(e).__name__}: {e}")

    def factors(self, e) -> list:
        """The operands a factor contributes to a product chain: a small integer power printed as a
        product without parentheses contributes its base that many times, anything else itself."""
        if e.is_Pow and e.exp.is_Integer and 2 <= int(e.exp) <= _MAX_PRODUCT_POWER:
            return [self(e.base)] * int(e.exp)
        if e.is_Rational and not e.is_Integer:  # printed p/q, unparenthesised in a product: p / q first
            return [["/", float(e.p), float(e.q)]]
        return [self(e)]

    @staticmethod
    def chain(items: list) -> object:
        return items[0] if len(items) == 1 else ["*", *items]

    def mul(self, expr) -> object:
        """sympy's CodePrinter._print_Mul with PrintRules' order: sign, numerator chain, denominator."""
        c, rest = expr.as_coeff_Mul()
        negative = c < 0
        if negative:
            expr = _keep_coeff(-c, rest)
        num, den = [], []
        for item in sp.Mul.make_args(expr):
            if item.is_commutative and item.is_Pow and item.exp.is_Rational and item.exp.is_negative:
                den.append(sp.Pow(item.base, -item.exp, evaluate=False) if item.exp != -1 else sp.Pow(item.base, 1))
            else:
                num.append(item)
        num = num or [sp.S.One]
        chain = [f for x in num for f in self.factors(x)]
        first = chain[0]
        if negative:  # Python's unary minus binds to the first operand: (-a) * b * ...
            chain[0] = ["neg", first] if not isinstance(first, float) else -first
        out = self.chain(chain)
        if len(den) == 1:
            d = den[0]
            small = d.is_Pow and d.exp.is_Integer and 2 <= int(d.exp) <= _MAX_PRODUCT_POWER
            if small:  # PrintRules parenthesises a/(t*t)
                return ["/", out, self.chain(self.factors(d))]
            return ["/", out, self(d)]
        if den:
            return ["/", out, self.chain([f for x in den for f in self.factors(x)])]
        return out

    def power(self, e) -> object:
        base, exp = e.as_base_exp()
        if exp.is_Integer and 2 <= abs(int(exp)) <= _MAX_PRODUCT_POWER:
            prod = self.chain([self(base)] * abs(int(exp)))
            return prod if exp > 0 else ["/", 1.0, prod]
        if exp == -1:
            return ["/", 1.0, self(base)]
        if exp == sp.Rational(1, 2):
            return ["sqrt", self(base)]
        if exp == sp.Rational(-1, 2):
            return ["/", 1.0, ["sqrt", self(base)]]
        return ["pow", self(base), int(exp) if exp.is_Integer else self(exp)]

    def piecewise(self, pieces) -> object:
        (value, cond), rest = pieces[0], pieces[1:]
        if cond is sp.true or cond == True:  # noqa: E712 - SymPy's true
            return self(value)
        if not rest:
            raise ProgramError(f"a piecewise expression without a last, unconditional piece: {pieces}")
        test = self(cond) if cond.is_Symbol else self.less(cond)
        return ["select", test, self(value), self.piecewise(rest)]

    def less(self, cond) -> list:
        if isinstance(cond, sp.StrictLessThan):
            return ["<", self(cond.lhs), self(cond.rhs)]
        if isinstance(cond, sp.StrictGreaterThan):
            return ["<", self(cond.rhs), self(cond.lhs)]
        raise ProgramError(f"unsupported condition in the rhs: {cond} (only < and >)")


def rhs_program(ir: ModelIR) -> dict:
    """The rhs kernel unrolled into statements and outputs (the module docstring's trees)."""
    kernel: Kernel = ir.kernels()["rhs"]
    names = identifiers(ir)
    split = ir.loops.split if ir.loops is not None else None
    env: dict = {}
    trees = _Trees(BallInvariantOrder(kernel.definitions()), env)
    statements: list = []
    taken: dict[str, int] = {}
    outputs: dict[int, object] = {}
    arrays: dict[str, dict[int, object]] = {name: {} for name, _ in kernel.arrays}
    widths = dict(kernel.arrays)
    N = ir.n_coordinates

    def emit(sym, tree):
        """A statement, named as the module names it (re-assignments numbered); later statements read a
        state or parameter read directly, anything else by the statement's name."""
        name = names.get(sym, sym.name)
        k = taken.get(name, 0)
        taken[name] = k + 1
        fresh = name if k == 0 else f"{name}__{k}"
        statements.append([fresh, tree])
        env[sym] = tree if isinstance(tree, list) and tree[0] in ("y", "p") else ["v", fresh]

    def index(pos, i: int | None) -> int:
        if pos.slot:
            return int(tables[pos.slot][i])
        return pos.base + (i if pos.ball else 0)

    tables = {sl.name: sl.indices for sl in split.slots} if split is not None else {}
    used = Emitter._free(kernel.ops)
    for k, s in enumerate(ir.states):  # the prologue: states, then parameters, in their order
        if s.symbol in used:
            emit(s.symbol, ["y", k])
    for k, q in enumerate(ir.parameters):
        if q.symbol in used:
            emit(q.symbol, ["p", k])

    def run(ops, i: int | None):
        for op in ops:
            if isinstance(op, (Let, Var)):
                emit(op.sym, trees(op.expr))
            elif isinstance(op, Inc):
                emit(op.sym, ["+", env[op.sym], trees(op.expr)])
            elif isinstance(op, Save):
                w = widths[op.array]
                arrays[op.array][i * w + op.k] = env[op.sym]
            elif isinstance(op, Fetch) and not op.column:
                emit(op.sym, arrays[op.array][i * widths[op.array] + op.k])
            elif isinstance(op, Put) and op.col is None:
                value = trees(op.expr)
                row = index(op.row, i)
                outputs[row] = ["+", outputs[row], value] if op.add else value
            elif isinstance(op, Balls):
                for b in range(split.n if op.count is None else op.count):
                    loads(op.ops, b)
                    run(op.ops, b)
            elif isinstance(op, (Get, Guard, Columns, Fetch, Put)):
                raise ProgramError(f"{ir.name}: the rhs holds {type(op).__name__}, which its trees do not express")
            else:  # pragma: no cover - every operation is handled above
                raise ProgramError(f"{ir.name}: unknown operation {op!r}")

    def loads(ops, b: int):
        """Ball b's angle, rate and own parameters (`emit.Emitter.ball_loads`)."""
        free = Emitter._flat_free(ops)
        if split.q in free:
            emit(split.q, ["y", split.first + b])
        if split.qd in free:
            emit(split.qd, ["y", N + split.first + b])
        for sl in split.slots:
            coef = sp.Symbol(f"{sl.symbol.name}_coef", real=True)
            value = ["p", int(sl.indices[b])]
            if sl.symbol in free:
                emit(sl.symbol, value if sl.unit_coefficients else ["*", float(sl.coefficients[b]), value])
            if coef in free:
                emit(coef, float(sl.coefficients[b]))

    if kernel.zero:
        outputs.update({k: 0.0 for k in range(ir.n_states)})
    run(kernel.ops, None)
    if sorted(outputs) != list(range(ir.n_states)):
        raise ProgramError(f"{ir.name}: the rhs does not write every output")
    return {"states": ir.n_states, "statements": statements, "outputs": [outputs[k] for k in range(ir.n_states)]}


def program_json(ir: ModelIR, source_hash: str) -> str:
    """`rhs_program` as JSON text, led by the source hash (what it was made from, as every emitted
    file's header): one statement per line (readable diffs), floats as Python writes them (exact round
    trip).  A kernel the trees do not express gives {"source_hash", "states": N, "error": why} (its
    readers refuse it, saying why), not a wrong program."""
    try:
        data = rhs_program(ir)
    except ProgramError as exc:
        return json.dumps({"source_hash": source_hash, "states": ir.n_states, "error": str(exc)})
    lines = ['{"source_hash": %s,' % json.dumps(source_hash), ' "states": %d,' % data["states"], ' "statements": [']
    lines += [" " + json.dumps(s) + ("," if k < len(data["statements"]) - 1 else "") for k, s in enumerate(data["statements"])]
    lines += [' ],', ' "outputs": [']
    lines += [" " + json.dumps(o) + ("," if k < len(data["outputs"]) - 1 else "") for k, o in enumerate(data["outputs"])]
    lines += [" ]}"]
    return "\n".join(lines)


def evaluate(statements, outputs, states, params, time, functions: dict, bind=lambda name, value: value) -> list:
    """The outputs of the trees (`rhs_program`'s statements and outputs) on any numbers or symbols.

    ``functions``: the math functions by the trees' names (sin, cos, ...), ``select`` and ``less`` for a
    piecewise law (an evaluator's own conditional: a symbolic one needs it, Python's truth test would
    not do), and optionally ``power`` for an integer power; bind(name, value) is what later statements
    see for a computed statement (the value itself, or a named helper of the evaluator's)."""
    env: dict = {}

    def value(tree):
        if not isinstance(tree, list):
            return float(tree)
        op = tree[0]
        if op == "y":
            return states[tree[1]]
        if op == "p":
            return params[tree[1]]
        if op == "t":
            return time
        if op == "v":
            return env[tree[1]]
        if op == "select":
            return functions["select"](value(tree[1]), value(tree[2]), value(tree[3]))
        if op == "<":
            return functions["less"](value(tree[1]), value(tree[2]))
        args = [value(a) for a in tree[1:]]
        if op in ("+", "*"):
            out = args[0]
            for a in args[1:]:
                out = out + a if op == "+" else out * a
            return out
        if op == "/":
            return args[0] / args[1]
        if op == "neg":
            return -args[0]
        if op == "pow":
            k = tree[2]
            if "power" in functions and isinstance(k, (int, float)) and k == int(k) and k >= 1:
                return functions["power"](args[0], int(k))
            return args[0] ** args[1]
        if op not in functions:
            raise ProgramError(f"the rhs uses {op!r}, which the evaluator is not given")
        return functions[op](*args)

    for name, tree in statements:
        v = value(tree)
        env[name] = v if isinstance(tree, list) and tree[0] in ("y", "p") else bind(name, v)
    return [value(outputs[i]) for i in range(len(outputs))]
