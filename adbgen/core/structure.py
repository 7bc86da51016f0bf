"""The structured solve of M q'' = f for rotor-with-balls mass matrices.

Order the coordinates as core (the rotor: X, Y and possibly the spin or tilts, r of them) and leaves
(the balls).  Each ball couples only to the core, so

    M = [[A, B], [C, D]],  D diagonal,

(C = B^T for Lagrange's rows; rows scaled separately, as in the thesis' dimensionless form, make M
non-symmetric, so the column b_i of B and the row c_i of C are kept apart), and with the Schur
complement S = A - sum_i b_i c_i / d_i (an r x r matrix of sums over balls),

    S a_core = f_core - sum_i b_i f_i / d_i,        a_i = (f_i - c_i . a_core) / d_i.

Written this way every quantity is a sum of n terms or an O(1) expression per ball, so the size of
the first-order system grows linearly with n; the full inverse of M is never formed.  Appendix A of
the thesis is this solve for r = 2: S = [[a, b], [b, c]] of (A.9)-(A.11), right-hand side (f, g) of
(A.12)-(A.13), and the back-substitution (A.6).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import sympy as sp

from .lagrange import EquationsOfMotion


@dataclass(frozen=True)
class StructuredSolve:
    """Schur-complement form of the accelerations of an `EquationsOfMotion`."""

    eom: EquationsOfMotion
    core: tuple[int, ...]
    leaves: tuple[int, ...]
    schur: sp.Matrix  # S = A - sum_i b_i c_i / d_i, r x r
    rhs: sp.Matrix  # f_core - sum_i b_i f_i / d_i
    leaf_accel: tuple[sp.Expr, ...]  # in terms of the core acceleration symbols

    @property
    def core_accel_symbols(self) -> list[sp.Symbol]:
        return [self.eom.coordinates[k].qdd for k in self.core]

    def core_accel(self, expand: bool = True) -> list[sp.Expr]:
        """Closed form of the core accelerations by Cramer's rule (r <= 3; for checks)."""
        return cramer(self.schur, self.rhs, expand)

    def accelerations(self, expand: bool = True) -> list[sp.Expr]:
        """All accelerations in closed form, ordered as the coordinates (size O(n^2): checks only).
        expand=False leaves the adjugate's products unexpanded (measures that emit them: common
        subexpressions are found when they are emitted, and expanding can take minutes)."""
        core = self.core_accel(expand)
        subs = dict(zip(self.core_accel_symbols, core))
        out: list[sp.Expr] = [sp.S.Zero] * self.eom.size
        for k, a in zip(self.core, core):
            out[k] = a
        for k, a in zip(self.leaves, self.leaf_accel):
            out[k] = a.xreplace(subs)
        return out

    def count_ops(self) -> int:
        """Operations of the structured form: S, its right-hand side and the back-substitution."""
        exprs = list(self.schur) + list(self.rhs) + list(self.leaf_accel)
        return int(sum(sp.count_ops(e) for e in exprs))


def cramer(S: sp.Matrix, rhs: sp.Matrix, expand: bool = True) -> list[sp.Expr]:
    """S^-1 rhs by the adjugate, for the small r x r core systems (r <= 3); numerators expanded or not."""
    r = S.rows
    if r > 3:
        raise ValueError("closed-form core solve is for r <= 3; solve S numerically instead")
    det = S.det(method="berkowitz")
    adj = S.adjugate(method="berkowitz")
    numerators = (sum((adj[i, j] * rhs[j] for j in range(r)), sp.S.Zero) for i in range(r))
    return [(sp.expand(u) if expand else u) / det for u in numerators]


def schur_solve(eom: EquationsOfMotion, core: Sequence[str]) -> StructuredSolve:
    """Build the structured solve; raises ValueError if two leaves are coupled in M."""
    names = [c.name for c in eom.coordinates]
    core_idx = tuple(names.index(c) for c in core)
    leaves = tuple(k for k in range(eom.size) if k not in core_idx)
    leafset = set(leaves)
    for (i, j) in eom.mass:
        if i != j and i in leafset and j in leafset:
            raise ValueError(f"leaves {names[i]} and {names[j]} are coupled: no Schur structure")
    r = len(core_idx)
    A = sp.Matrix(r, r, lambda a, b: eom.mass.get((core_idx[a], core_idx[b]), sp.S.Zero))
    S = A.copy()
    rhs = sp.Matrix([eom.forcing[k] for k in core_idx])
    leaf_accel = []
    core_accel = [eom.coordinates[k].qdd for k in core_idx]
    for i in leaves:
        d = eom.mass.get((i, i))
        if d is None:
            raise ValueError(f"coordinate {names[i]} has no inertia")
        b = sp.Matrix([eom.mass.get((k, i), sp.S.Zero) for k in core_idx])
        c = [eom.mass.get((i, k), sp.S.Zero) for k in core_idx]
        S -= b * sp.Matrix([c]) / d
        rhs -= b * eom.forcing[i] / d
        leaf_accel.append((eom.forcing[i] - sum(c[a] * core_accel[a] for a in range(r))) / d)
    S = S.applyfunc(sp.expand)
    rhs = rhs.applyfunc(sp.expand)
    return StructuredSolve(eom, core_idx, leaves, S, rhs, tuple(sp.expand(a) for a in leaf_accel))
