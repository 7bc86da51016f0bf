"""The per-ball block of a balancer model as data (`BallSplit`: the core's parts and one generic ball,
thesis Appendix A's blocks of M and f), and a ball's own parameters (`Slot`); made and verified
against every ball by `passes.ball_split`.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Slot:
    """A ball's own parameter: ball i's value is coefficients[i] * p[indices[i]]."""

    name: str
    symbol: sp.Symbol  # the generic symbol, ball_<name>
    indices: tuple[int, ...]
    coefficients: tuple[float, ...]

    @property
    def unit_coefficients(self) -> bool:
        return all(c == 1.0 for c in self.coefficients)


@dataclass(frozen=True)
class BallSplit:
    """The model as core parts plus one generic per-ball block (r = core size, n balls).

    Ball i is coordinate ``first + i``.  Core: A0 (r x r), f0 (r) of shared symbols only.  Per ball:
    its shares A (r x r) and fc (r) of the core rows, its column B (r) and row C (r) of M, its
    inertia D and forcing f.
    """

    first: int
    n: int
    q: sp.Symbol
    qd: sp.Symbol
    qdd: sp.Symbol
    slots: tuple[Slot, ...]
    A0: tuple[tuple[sp.Expr, ...], ...]
    f0: tuple[sp.Expr, ...]
    A: tuple[tuple[sp.Expr, ...], ...]
    fc: tuple[sp.Expr, ...]
    B: tuple[sp.Expr, ...]
    C: tuple[sp.Expr, ...]
    D: sp.Expr
    f: sp.Expr
