"""Linear stability of equilibria of M(q) q'' = f(q, q') (thesis ch. 4).

At an equilibrium q* (q' = q'' = 0, f(q*, 0) = 0) the term (dM/dq) q'' of the linearisation vanishes,
so exactly

    M(q*) dq'' = K dq + C dq',   K = df/dq (q*, 0),  C = df/dq' (q*, 0),

and the Jacobian of the first-order system is [[0, I], [M^-1 K, M^-1 C]].  M, K and C are derived
symbolically once and evaluated numerically; no finite differences.

Equilibria of the balanced family (3.6) with n > 2 balls form an (n - 2)-dimensional set, so n - 2
eigenvalues are zero there; `Spectrum` counts eigenvalues near zero apart from those that decide
stability.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from .lagrange import EquationsOfMotion


@dataclass(frozen=True)
class Spectrum:
    eigenvalues: np.ndarray  # sorted by decreasing real part
    zero_tol: float

    @property
    def n_unstable(self) -> int:
        return int(np.sum(self.eigenvalues.real > self.zero_tol))

    @property
    def n_zero(self) -> int:
        return int(np.sum(np.abs(self.eigenvalues) <= self.zero_tol))

    @property
    def stable(self) -> bool:
        """No eigenvalue with positive real part (zero ones belong to a family of equilibria)."""
        return self.n_unstable == 0

    def leading(self, skip_zero: bool = True) -> complex:
        """The eigenvalue of largest real part, ignoring the family's zero eigenvalues."""
        ev = self.eigenvalues[np.abs(self.eigenvalues) > self.zero_tol] if skip_zero else self.eigenvalues
        return complex(ev[0])


class Linearisation:
    """Exact linearisation of an EquationsOfMotion at its equilibria, evaluated numerically."""

    def __init__(self, eom: EquationsOfMotion):
        self.eom = eom
        self.parameter_names = tuple(p.name for p in eom.parameters)
        self.defaults = np.array([p.default for p in eom.parameters], dtype=float)
        q = [c.q for c in eom.coordinates]
        rest = {c.qd: sp.S.Zero for c in eom.coordinates}
        f = sp.Matrix(eom.forcing)
        K = f.jacobian(q).xreplace(rest)
        C = f.jacobian([c.qd for c in eom.coordinates]).xreplace(rest)
        M = eom.mass_matrix().xreplace(rest)
        params = [p.symbol for p in eom.parameters]
        self._mkc = sp.lambdify((q, params), [M, K, C], modules="numpy", cse=True)
        self._f = sp.lambdify((q, params), list(f.xreplace(rest)), modules="numpy", cse=True)
        self.n = len(q)

    def parameters(self, **values: float) -> np.ndarray:
        p = self.defaults.copy()
        for name, value in values.items():
            p[self.parameter_names.index(name)] = value
        return p

    def point(self, state: dict[str, float]) -> np.ndarray:
        """The coordinate vector of a state given by name (e.g. from `steady_states.evaluate`)."""
        return np.array([state[c.name] for c in self.eom.coordinates], dtype=float)

    def residual(self, q, p) -> np.ndarray:
        """f(q, 0): zero at an equilibrium."""
        return np.asarray(self._f(np.asarray(q, float), p), dtype=float)

    def jacobian(self, q, p) -> np.ndarray:
        M, K, C = (np.asarray(a, dtype=float) for a in self._mkc(np.asarray(q, float), p))
        n = self.n
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = np.eye(n)
        J[n:, :n] = np.linalg.solve(M, K)
        J[n:, n:] = np.linalg.solve(M, C)
        return J

    def spectrum(self, q, p, zero_tol: float = 1e-9) -> Spectrum:
        ev = np.linalg.eigvals(self.jacobian(q, p))
        return Spectrum(ev[np.argsort(-ev.real, kind="stable")], zero_tol)


def hopf_crossing(linearisation: Linearisation, state_at, parameter: str, bracket: tuple[float, float],
                  fixed: dict[str, float] | None = None, xtol: float = 1e-12) -> float:
    """Where the leading non-zero eigenvalue of the equilibrium state_at(value) has zero real part.

    ``state_at(value)`` returns the equilibrium (coordinates) at that parameter value; the root is
    bracketed by ``bracket`` (the leading real part must change sign across it).
    """
    fixed = dict(fixed or {})

    def leading_real(value: float) -> float:
        p = linearisation.parameters(**{**fixed, parameter: value})
        return linearisation.spectrum(state_at(value), p).leading().real

    return brentq(leading_real, *bracket, xtol=xtol)
