"""Equivariance of the symmetric set-up under gamma_12, gamma_34 and gamma_r: paper (13)-(16).

The rotating-frame system (7)-(8) is written A(u) u' = B(u) with u = [r, alpha, r', alpha'] (12),
A = diag(I, M(q)) and B = [q', f(q, q')].  A symmetry gamma (a signed permutation of u, (15)-(16))
must satisfy gamma A(u) gamma^-1 = A(gamma u) (13) and gamma B(u) = B(gamma u) (14).  With the static
imbalance of section 3 all three hold; a misalignment chi != 0 breaks gamma_r (footnote 1: the races
then carry unequal imbalance), leaving D_2 = <gamma_12, gamma_34>.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ...core import EquationsOfMotion, is_identity

# (15)-(16) on coordinate names: name -> (image name, sign)
GAMMAS = {
    "gamma_12": {"alpha_1": ("alpha_2", 1), "alpha_2": ("alpha_1", 1)},
    "gamma_34": {"alpha_3": ("alpha_4", 1), "alpha_4": ("alpha_3", 1)},
    "gamma_r": {"alpha_1": ("alpha_3", 1), "alpha_3": ("alpha_1", 1), "alpha_2": ("alpha_4", 1),
                "alpha_4": ("alpha_2", 1), "phi_x": ("phi_x", -1), "phi_y": ("phi_y", -1)},
}


@dataclass(frozen=True)
class FirstOrderPair:
    """A(u), B(u) of (12) and the state u."""

    states: tuple[sp.Symbol, ...]
    A: sp.Matrix
    B: sp.Matrix


def first_order_pair(eom: EquationsOfMotion) -> FirstOrderPair:
    n = eom.size
    A = sp.diag(sp.eye(n), eom.mass_matrix())
    B = sp.Matrix([c.qd for c in eom.coordinates] + list(eom.forcing))
    states = tuple(c.q for c in eom.coordinates) + tuple(c.qd for c in eom.coordinates)
    return FirstOrderPair(states, A, B)


def action(eom: EquationsOfMotion, gamma: str) -> sp.Matrix:
    """The matrix of gamma on u (positions and rates transform alike)."""
    names = [c.name for c in eom.coordinates]
    n = len(names)
    P = sp.zeros(2 * n, 2 * n)
    for i, name in enumerate(names):
        image, sign = GAMMAS[gamma].get(name, (name, 1))
        j = names.index(image)
        P[i, j] = P[n + i, n + j] = sign
    return P


def _transformed(pair: FirstOrderPair, P: sp.Matrix) -> dict:
    u = sp.Matrix(pair.states)
    return dict(zip(pair.states, P * u))


def equivariance_residues(eom: EquationsOfMotion, gamma: str) -> tuple[sp.Matrix, sp.Matrix]:
    """(13) gamma A gamma^-1 - A(gamma u) and (14) gamma B - B(gamma u) (zero when gamma is a symmetry)."""
    pair = first_order_pair(eom)
    P = action(eom, gamma)
    sub = _transformed(pair, P)
    return P * pair.A * P.T - pair.A.xreplace(sub), P * pair.B - pair.B.xreplace(sub)


def is_equivariant(eom: EquationsOfMotion, gamma: str) -> bool:
    """Exact: every entry of both residues of (13)-(14) vanishes identically."""
    dA, dB = equivariance_residues(eom, gamma)
    return all(is_identity(x) for x in list(dA) + list(dB))


class NumericEquivariance:
    """(13)-(14) evaluated at numbers, for property tests over random parameters and states."""

    def __init__(self, eom: EquationsOfMotion):
        self.pair = first_order_pair(eom)
        self.parameter_names = tuple(p.name for p in eom.parameters)
        params = [p.symbol for p in eom.parameters]
        self._AB = sp.lambdify((self.pair.states, params), [self.pair.A, self.pair.B], modules="numpy", cse=True)
        self.P = {g: np.array(action(eom, g), dtype=float) for g in GAMMAS}

    def residue(self, gamma: str, u: np.ndarray, p: np.ndarray) -> float:
        """max |(13)| + max |(14)|, relative to the size of A and B."""
        P = self.P[gamma]
        A, B = (np.array(x, dtype=float) for x in self._AB(u, p))
        A2, B2 = (np.array(x, dtype=float) for x in self._AB(P @ u, p))
        scale = 1.0 + np.abs(A).max() + np.abs(B).max()
        return float((np.abs(P @ A @ P.T - A2).max() + np.abs(P @ B.ravel() - B2.ravel()).max()) / scale)
