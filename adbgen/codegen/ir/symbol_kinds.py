"""What a statement's symbol stands for, recorded where the name is made (issue 33 item 4).

A later pass that must recognise some statements (the Taylor target's series form finds the
structured solve of thesis Appendix A, (A.9)-(A.13), in the rhs kernel) looks the symbol's kind up
here instead of testing its name's prefix.  The code that makes such a name (`passes.loop_form`, `passes.lowering`)
registers it with its kind and its indices; a name made twice must be made with the same kind.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

SCHUR = "Schur complement"  # S_a_b: the core block reduced by the balls, (A.9)-(A.13); index (a, b)
SCHUR_RHS = "Schur right-hand side"  # g_a: its right-hand side; index (a,)
SOLVE_FACTOR = "solve factor"  # LU_i_k, LU_i_j_k: S's unrolled LU factors; Uinv_k: 1 / U_kk
SOLVE_FORWARD = "solve forward"  # z_a = (L^-1 g)_a; index (a,)
SOLVE_RESULT = "solve result"  # x_a = (U^-1 z)_a: a core acceleration; index (a,)
KINDS = (SCHUR, SCHUR_RHS, SOLVE_FACTOR, SOLVE_FORWARD, SOLVE_RESULT)
# the statements of the structured solve proper (S and g are its inputs)
SOLVE = frozenset({SOLVE_FACTOR, SOLVE_FORWARD, SOLVE_RESULT})


@dataclass(frozen=True)
class Entry:
    kind: str
    index: tuple[int, ...] = ()


_REGISTRY: dict[sp.Symbol, Entry] = {}


def register(sym: sp.Symbol, kind: str, *index: int) -> sp.Symbol:
    """Record `sym` as a `kind` with `index`; refuses a second, different record of the same symbol."""
    if kind not in KINDS:
        raise ValueError(f"unknown symbol kind {kind!r} (one of {', '.join(KINDS)})")
    entry = Entry(kind, tuple(index))
    old = _REGISTRY.setdefault(sym, entry)
    if old != entry:
        raise ValueError(f"symbol {sym.name} made as a {kind} {entry.index} but already a {old.kind} {old.index}")
    return sym


def make(name: str, kind: str, *index: int) -> sp.Symbol:
    """A real symbol named `name`, registered as a `kind` with `index`."""
    return register(sp.Symbol(name, real=True), kind, *index)


def kind_of(sym: sp.Basic) -> str | None:
    """The kind `sym` was made as, or None for a symbol no one registered."""
    entry = _REGISTRY.get(sym)
    return entry.kind if entry is not None else None


def index_of(sym: sp.Basic) -> tuple[int, ...]:
    """The indices `sym` was made with (KeyError for a symbol no one registered)."""
    return _REGISTRY[sym].index


__all__ = ["Entry", "KINDS", "SCHUR", "SCHUR_RHS", "SOLVE", "SOLVE_FACTOR", "SOLVE_FORWARD", "SOLVE_RESULT",
           "index_of", "kind_of", "make", "register"]
