"""First-order form y' = F(y), y = (positions, rates), of M(q) q'' = f by the structured solve.

Thesis Appendix A's construction, for any model: the accelerations come from the Schur complement of
the diagonal (ball) block over a small core (the rotor), never from M^-1 (`core.structure`).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .lagrange import Coordinate, EquationsOfMotion, Parameter
from .structure import StructuredSolve, schur_solve


@dataclass(frozen=True)
class FirstOrderSystem:
    """y' = F(y) with y = (positions, rates), accelerations from the structured solve.

    Thesis Appendix A: states (A.1)-(A.2) (ordered here positions first, then rates), the rotor
    accelerations (A.7)-(A.8) from the 2x2 (generally r x r) Schur system and the ball
    accelerations (A.6) by back-substitution.
    """

    solve: StructuredSolve
    parameters: tuple[Parameter, ...]
    reference: str

    @property
    def coordinates(self) -> tuple[Coordinate, ...]:
        return self.solve.eom.coordinates

    @property
    def states(self) -> tuple[sp.Symbol, ...]:
        return tuple(c.q for c in self.coordinates) + tuple(c.qd for c in self.coordinates)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    def rhs(self) -> list[sp.Expr]:
        """F(y) in closed form (O(n^2) in size: for checks; generated code uses the structure)."""
        return [c.qd for c in self.coordinates] + self.solve.accelerations()

    def count_ops(self) -> int:
        return self.solve.count_ops()


def first_order(eom: EquationsOfMotion, core: tuple[str, ...], reference: str | None = None) -> FirstOrderSystem:
    """Structured first-order form with the coordinates named in `core` as the Schur core."""
    return FirstOrderSystem(schur_solve(eom, core), eom.parameters,
                            reference or f"structured solve (core {', '.join(core)}) of {eom.reference}")
