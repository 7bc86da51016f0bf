"""The one common-subexpression pass of code generation (issue 33): the straight-line programs'
(`passes.lowering`), the loop form's kernels (`passes.loop_form`) and the self-description's
(`passes.description`) all call `cse` (or `cse_lets`, the same with `Let` statements).  Each caller
gives only the prefix of its temporaries' names (w_, v_, wc_, wb_, wd_, w_m_, ...), so the
temporaries of one function never collide; the elimination itself is SymPy's, with no
optimisations and the canonical order, so the same expressions give the same statements in the
same order on every run (the generated files are deterministic).
"""

from __future__ import annotations

from typing import Sequence

import sympy as sp

from ..ir.loops import Let


def cse(exprs: Sequence[sp.Expr], prefix: str) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    """Common subexpressions of `exprs`, in a deterministic order with names prefix0, prefix1, ... (the one
    CSE of code generation: the lowered programs', the loop form's and the self-description's)."""
    symbols = sp.numbered_symbols(prefix, real=True)
    replacements, reduced = sp.cse(list(exprs), symbols=symbols, optimizations=None, order="canonical")
    return list(replacements), list(reduced)


def cse_lets(exprs: Sequence[sp.Expr], prefix: str) -> tuple[list[Let], list[sp.Expr]]:
    """`cse` with its temporaries as `Let` statements."""
    replacements, reduced = cse(exprs, prefix)
    return [Let(s, e) for s, e in replacements], reduced
