"""Exact symbolic identity tests for trigonometric polynomials and rational functions of them.

`simplify` is slow and not a decision procedure; the expressions of rotor mechanics are polynomials in
sines and cosines of sums of angles, divided by such polynomials, and for those a canonical form is
cheap: expand every sine and cosine of a sum, replace sin(a)**2 by 1 - cos(a)**2, expand.  Two
expressions are identical exactly when the numerator of their difference has canonical form 0.
"""

from __future__ import annotations

import sympy as sp


def _reduce_sin_squares(expr: sp.Expr) -> sp.Expr:
    def is_sin_power(e):
        return e.is_Pow and isinstance(e.base, sp.sin) and e.exp.is_Integer and e.exp >= 2

    def reduce(e):
        k = int(e.exp)
        return (1 - sp.cos(e.base.args[0]) ** 2) ** (k // 2) * e.base ** (k % 2)

    return expr.replace(is_sin_power, reduce)


def reduce_pythagorean(expr: sp.Expr) -> sp.Expr:
    """Expand and replace sin(a)**2 by 1 - cos(a)**2, keeping sines of sums as they are."""
    return sp.expand(_reduce_sin_squares(sp.expand(expr)))


def canonical_trig(expr: sp.Expr) -> sp.Expr:
    """Canonical form of a trigonometric polynomial: sums expanded, sin^2 -> 1 - cos^2."""
    expr = sp.expand(sp.expand_trig(sp.expand(expr)))
    return sp.expand(_reduce_sin_squares(expr))


def is_identity(lhs: sp.Expr, rhs: sp.Expr = sp.S.Zero) -> bool:
    """True when lhs - rhs is identically zero (exact, no numerics)."""
    diff = sp.expand(lhs - rhs)
    if diff == 0:
        return True
    numerator, _ = sp.fraction(sp.together(diff))
    canonical = canonical_trig(numerator)
    if canonical == 0:
        return True
    # Radicals (square roots of squares) need the symbols' sign assumptions: give SymPy one chance.
    # Without radicals the canonical form is decisive.
    has_radical = any(not p.exp.is_Integer for p in canonical.atoms(sp.Pow))
    return has_radical and sp.simplify(canonical) == 0


def assert_identity(lhs: sp.Expr, rhs: sp.Expr = sp.S.Zero, what: str = "identity") -> None:
    """Raise AssertionError naming `what` when lhs - rhs does not vanish identically."""
    if not is_identity(lhs, rhs):
        residue = canonical_trig(sp.fraction(sp.together(sp.expand(lhs - rhs)))[0])
        raise AssertionError(f"{what} does not hold; residue: {sp.sstr(residue)[:400]}")
