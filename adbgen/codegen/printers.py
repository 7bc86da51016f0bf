"""What every target's printer shares: identifiers, numbers as floats, small powers as products, and
the ball-invariant order of terms.  Each target's printer (`targets/<name>/printer.py`) is a SymPy code
printer with `PrintRules` mixed in.

Small integer powers are printed as products (x*x, 1.0/(x*x)): exact, and cheaper than pow() in
both targets.  Identifiers come from one mapping per model, so a state or parameter whose name is
taken by the calling convention (the state ``y`` against the argument ``y``) gets a suffix
everywhere at once.
"""

from __future__ import annotations

import hashlib
import keyword
import re

import sympy as sp

from .ir.model import ModelIR

# Names the calling conventions of the targets use (arguments, modules, C keywords and macros).
RESERVED = frozenset({
    "t", "y", "p", "out", "dydt", "jac", "J", "np", "math", "numba", "njit", "f", "dfdu", "dfdp",
    "par", "u", "ndim", "icp", "ijac", "user_data", "ydot", "I", "auto", "break", "case", "char",
    "const", "continue", "default", "do", "double", "else", "enum", "extern", "float", "for", "goto",
    "if", "inline", "int", "long", "register", "restrict", "return", "short", "signed", "sizeof",
    "static", "struct", "switch", "typedef", "union", "unsigned", "void", "volatile", "while",
    "abs", "fabs", "min", "max", "integer", "doublereal",
    # the loop form's loop indices and the numba module's helpers (codegen/emit.py)
    "i", "j", "carray", "types", "cgutils", "intrinsic", "overload", "memset", "ARRAY2D", "APAR",
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


# A ball's index in a name: phi_3, phi_3_dot, m_3, Mcl_2_0, f_4 (one number between underscores or at
# the end).  Anonymising it gives every ball's symbols the same class.
# By name, not by the IR's ball split (`ir.balls`), on purpose: the order sees only an expression's symbols
# (a printer is made from the identifiers alone, `PrintRules`), it also orders the unrolled form and models
# without a ball split (balls not alike: `passes.ball_split.NoBallStructure`), and it anonymises every index
# alike, the ones the split does not own too (the flexible rotor's modes q_1, K_q_1_1, the two-plane
# supports k_1, l_1, the torque model's theta_0): classes taken from the split reorder those models' terms
# (tried: flexible_jeffcott_n2's and two_plane_rotating's numba, C, AUTO, Taylor and lanes files changed).
# The rule is what makes two names one class, so it stays one rule here.
_INDEX = re.compile(r"(?<=_)\d+(?=_|$)")


class BallInvariantOrder:
    """Print order of sums and products that is the same for every ball (exact exchange symmetry).

    SymPy orders the terms of a sum by the names of their symbols, so ball 1's ``-w_15*w_2`` and
    ball 3's ``-w_10*w_15`` (the same term) are printed, and rounded, in different orders, and balls
    that start together drift apart by round-off (thesis ch. 5's coincident states need them to stay
    together).  Here every symbol gets a class: a statement's class is a hash of its definition, any
    other symbol's is its name with the ball index anonymised (`_INDEX`).  Terms and factors are
    printed sorted by the classes, so ball i's equations are the same sequence of floating-point
    operations as ball j's.
    """

    def __init__(self, assignments=()):
        self._cls: dict[sp.Symbol, str] = {}
        self._memo: dict[sp.Basic, str] = {}
        for lhs, rhs in assignments:
            self._cls[lhs] = self.key(rhs)

    def key(self, expr: sp.Basic) -> str:
        hit = self._memo.get(expr)
        if hit is not None:
            return hit
        if expr.is_Symbol:
            out = self._cls.get(expr) or "s:" + _INDEX.sub("#", expr.name)
        elif expr.is_Number:
            out = "n:" + repr(float(expr))
        else:
            args = [self.key(a) for a in expr.args]
            if expr.is_Add or expr.is_Mul:
                args.sort()
            text = type(expr).__name__ + "(" + ",".join(args) + ")"
            out = "h:" + hashlib.sha1(text.encode()).hexdigest()[:20]
        self._memo[expr] = out
        return out

    def ordered(self, args) -> list:
        """Numbers first (SymPy's printers expect the coefficient first), then by class."""
        return sorted(args, key=lambda a: (not a.is_Number, self.key(a)))


class PrintRules:
    """What every target printer shares: the model's identifiers, floats for every number, small integer
    powers as products, and a ball-invariant order of terms and factors (`BallInvariantOrder`)."""

    def __init__(self, names: dict[sp.Symbol, str], *args):
        super().__init__(*args)
        self._names = names
        self._order = BallInvariantOrder()

    def set_program(self, assignments) -> None:
        """Use the classes of this program's statements for the print order of what follows."""
        self._order = BallInvariantOrder(assignments)

    def _print_Add(self, expr, order=None):
        return super()._print_Add(sp.Add(*self._order.ordered(expr.args), evaluate=False), order="none")

    def _print_Mul(self, expr, **kwargs):
        saved = self._settings["order"]
        self._settings["order"] = "none"
        try:
            text = super()._print_Mul(sp.Mul(*self._order.ordered(expr.args), evaluate=False), **kwargs)
        finally:
            self._settings["order"] = saved
        # SymPy prints a single denominator as "a/" + den; a power printed as a product (t*t) must then
        # be parenthesised: a/(t*t), not a/t*t (first met with the ramp's 1/t_ramp^2)
        dens = [f for f in expr.args if f.is_Pow and f.exp.is_Rational and f.exp.is_negative]
        if len(dens) == 1 and dens[0].exp.is_Integer and 2 <= -int(dens[0].exp) <= _MAX_PRODUCT_POWER:
            inner = self._print(sp.Pow(dens[0].base, -dens[0].exp))
            if text.endswith("/" + inner):
                text = text[: -len(inner)] + f"({inner})"
        return text

    def _print_Symbol(self, expr):
        return self._names.get(expr, expr.name)

    def _print_Integer(self, expr):
        return f"{float(expr)!r}"

    def _print_Rational(self, expr):
        return f"{float(expr.p)!r}/{float(expr.q)!r}"

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 2 <= abs(int(exp)) <= _MAX_PRODUCT_POWER:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"] + 1)
            prod = "*".join([b] * abs(int(exp)))
            return prod if exp > 0 else f"1.0/({prod})"
        if exp == -1:
            return f"1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'] + 1)}"
        return self._print_other_Pow(expr, rational)

    def _print_other_Pow(self, expr, rational=False):
        """A power the rules leave to the language's printer."""
        return super()._print_Pow(expr, rational=rational)
