"""Print the intermediate form's programs as Python (for numba) or C99 statements.

Small integer powers are printed as products (x*x, 1.0/(x*x)): exact, and cheaper than pow() in
both targets.  Identifiers come from one mapping per model, so a state or parameter whose name is
taken by the calling convention (the state ``y`` against the argument ``y``) gets a suffix
everywhere at once.
"""

from __future__ import annotations

import keyword
import math

import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.pycode import PythonCodePrinter

from .ir import ModelIR

# Names the calling conventions of the targets use (arguments, modules, C keywords and macros).
RESERVED = frozenset({
    "t", "y", "p", "out", "dydt", "jac", "J", "np", "math", "numba", "njit", "f", "dfdu", "dfdp",
    "par", "u", "ndim", "icp", "ijac", "user_data", "ydot", "I", "auto", "break", "case", "char",
    "const", "continue", "default", "do", "double", "else", "enum", "extern", "float", "for", "goto",
    "if", "inline", "int", "long", "register", "restrict", "return", "short", "signed", "sizeof",
    "static", "struct", "switch", "typedef", "union", "unsigned", "void", "volatile", "while",
    "abs", "fabs", "min", "max", "integer", "doublereal",
}) | frozenset(keyword.kwlist)

_MAX_PRODUCT_POWER = 4


def identifiers(ir: ModelIR) -> dict[sp.Symbol, str]:
    """Symbol -> identifier for the states, parameters and time of a model."""
    out = {}
    taken = set()
    for sym in [s.symbol for s in ir.states] + [p.symbol for p in ir.parameters]:
        name = sym.name
        while name in RESERVED or name in taken:
            name += "_"
        taken.add(name)
        out[sym] = name
    return out


class _Rules:
    """What both printers share: the model's identifiers, floats for every number, small integer
    powers as products."""

    def __init__(self, names: dict[sp.Symbol, str], *args):
        super().__init__(*args)
        self._names = names

    def _print_Symbol(self, expr):
        return self._names.get(expr, expr.name)

    def _print_Integer(self, expr):
        return f"{float(expr)!r}"

    def _print_Rational(self, expr):
        return f"{float(expr.p)!r}/{float(expr.q)!r}"

    def _print_Mul(self, expr):
        # SymPy prints a single denominator as "a/" + den; a power printed as a product (t*t) must then
        # be parenthesised: a/(t*t), not a/t*t (first met with the ramp's 1/t_ramp^2)
        text = super()._print_Mul(expr)
        dens = [f for f in expr.args if f.is_Pow and f.exp.is_Rational and f.exp.is_negative]
        if len(dens) == 1 and dens[0].is_Pow and dens[0].exp.is_Integer and 2 <= -int(dens[0].exp) <= _MAX_PRODUCT_POWER:
            inner = self._print(sp.Pow(dens[0].base, -dens[0].exp))
            if text.endswith("/" + inner):
                text = text[: -len(inner)] + f"({inner})"
        return text

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 2 <= abs(int(exp)) <= _MAX_PRODUCT_POWER:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"] + 1)
            prod = "*".join([b] * abs(int(exp)))
            return prod if exp > 0 else f"1.0/({prod})"
        if exp == -1:
            return f"1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'] + 1)}"
        return super()._print_Pow(expr, rational=rational) if not isinstance(self, C99CodePrinter) \
            else super()._print_Pow(expr)


class PythonPrinter(_Rules, PythonCodePrinter):
    """math-module Python that numba compiles in nopython mode."""

    def __init__(self, names: dict[sp.Symbol, str]):
        super().__init__(names, {"fully_qualified_modules": True, "standard": "python3"})


class CPrinter(_Rules, C99CodePrinter):
    """C99 with <math.h>; constants as literals (M_PI, M_E are POSIX, not C99)."""

    def _print_Pi(self, expr):
        return repr(math.pi)

    def _print_Exp1(self, expr):
        return repr(math.e)
