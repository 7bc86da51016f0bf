"""Numeric evaluation of a first-order system straight from its symbolic structured form.

This is the *reference* evaluator used to check the derivation numerically (Jacobi integral along a
trajectory, reductions compared by simulation, stability cross-checks).  It keeps the Schur structure:
S and its right-hand side are evaluated, the r x r system is solved with numpy, then the balls are
back-substituted.  Generated code (numba, C) is what users run; this exists to check it and the
derivation.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .first_order import FirstOrderSystem
from .symbols import t


class NumericFirstOrder:
    """rhs(t, y, p) of a FirstOrderSystem, y = (positions, rates), p ordered as `parameter_names`."""

    def __init__(self, system: FirstOrderSystem):
        solve = system.solve
        eom = solve.eom
        law = dict(eom.driven_law)
        self.state_names = system.state_names
        self.parameter_names = tuple(p.name for p in system.parameters)
        self.defaults = np.array([p.default for p in system.parameters], dtype=float)
        q = [c.q for c in eom.coordinates]
        qd = [c.qd for c in eom.coordinates]
        params = [p.symbol for p in system.parameters]
        accel = solve.core_accel_symbols
        prep = lambda exprs: [sp.sympify(e).xreplace(law) for e in exprs]  # noqa: E731
        self._schur = sp.lambdify((t, q, qd, params), prep(solve.schur), modules="numpy", cse=True)
        self._rhs = sp.lambdify((t, q, qd, params), prep(solve.rhs), modules="numpy", cse=True)
        self._leaf = sp.lambdify((t, q, qd, accel, params), prep(solve.leaf_accel), modules="numpy", cse=True)
        self.n = len(q)
        self.r = len(solve.core)
        self._core = np.array(solve.core)
        self._leaves = np.array(solve.leaves, dtype=int)

    def __call__(self, time: float, y: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
        p = self.defaults if p is None else p
        q, qd = y[: self.n], y[self.n:]
        S = np.array(self._schur(time, q, qd, p), dtype=float).reshape(self.r, self.r)
        a = np.linalg.solve(S, np.array(self._rhs(time, q, qd, p), dtype=float))
        out = np.empty(2 * self.n)
        out[: self.n] = qd
        out[self.n + self._core] = a
        if len(self._leaves):
            out[self.n + self._leaves] = self._leaf(time, q, qd, a, p)
        return out

    def index(self, name: str) -> int:
        return self.state_names.index(name)
