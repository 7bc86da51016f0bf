"""Two-parameter curves of codimension-one points (Hopf, fold, torus, period-doubling, fold of cycles): what
they share.

A boundary curve lives in the plane of two parameters x = (lambda_1, lambda_2) (lambda_2 on a log scale
when asked).  Its defining system is reduced to one scalar equation,

    g(x) = c(spectrum of the solution followed at p(x)) = 0,

the solution (a steady state, or a periodic orbit) re-found at each x by Newton from the last accepted one
(`EquilibriumFollower`, `OrbitFollower`), and c the critical quantity of the curve's kind, tracked along the
curve by continuity (the eigenvalue or multiplier nearest the last accepted critical one):

    hopf               Re of a complex eigenvalue pair                       (hopf.HopfCurve)
    fold               a real eigenvalue (a fold, or a branch point of a      (equilibrium: this module's
                       symmetric state)                                       FoldCurve)
    torus              |mu| - 1 of a complex multiplier pair                  (torus.TorusCurve)
    period-doubling    mu + 1 of a real multiplier                            (period_doubling.PeriodDoublingCurve)
    fold of cycles     mu - 1 of a real, non-trivial multiplier               (fold_cycle.FoldCycleCurve)

Its Jacobian [dg/dlambda_1, dg/dlambda_2] is taken by forward differences of g (each difference a solution
re-found at the shifted parameters: g itself is exact to Newton's and the integration's accuracy, so the
curve points are exact to those, whatever the differences' error); the continuer follows it.  Each kind adds
test functions for its codimension-two points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..loading import AnalysisError, Model
from .equilibrium import EquilibriumFollower
from .flow import Flow
from .orbit import shift_vector, sort_multipliers, trivial_index
from .parameters import ParameterMap
from .shooting import Shooting

DIFF_STEP = 1e-6


class OrbitFollower:
    """A periodic orbit re-found at any parameters by Newton shooting from the last one; its non-trivial
    multipliers."""

    kind = "orbit"

    def __init__(self, model: Model, orbit, flow: Flow | None = None):
        from . import describe

        self.model = model
        self.flow = flow or Flow(model)
        forcing = describe.forcing_parameter(model, orbit.p)
        self.shooting = Shooting(model, self.flow, len(orbit.arcs), shift_vector(model, orbit.windings), forcing,
                                 orbit.subharmonic)
        self.last = (orbit.arcs.copy(), float(orbit.period))

    def solve(self, p: np.ndarray, guess=None):
        X, T = self.last if guess is None else guess
        sh = self.shooting
        if not sh.forced:
            sh.set_reference(X[0], p)
        u, ev, _ = sh.solve(sh.pack(X, T), p)
        M = ev.monodromy
        mu = sort_multipliers(np.linalg.eigvals(M))
        Xn = sh.arcs_of(u)
        if not sh.forced:
            mu = np.delete(mu, trivial_index(mu, M, np.asarray(self.model.module.rhs(0.0, Xn[0], p))))
        return (Xn, sh.period(u, p)), mu

    def accept(self, state) -> None:
        self.last = (state[0].copy(), float(state[1]))


@dataclass
class BoundaryData:
    x: np.ndarray
    lam: tuple[float, float]
    state: object
    spectrum: np.ndarray
    critical: complex


class BoundaryCurve:
    """The curve g(lambda_1, lambda_2) = 0 of the subclass's kind (see the module's docstring)."""

    kind = ""
    test_names: tuple[str, ...] = ()
    size = 2

    def __init__(self, model: Model, pmap: ParameterMap, follower, log2: bool = False, range2=None):
        if len(pmap.free) != 2:
            raise AnalysisError("a boundary curve needs two free parameters")
        self.model, self.pmap, self.follower, self.log2 = model, pmap, follower, log2
        self.range2 = range2
        self.crit: complex | None = None
        self._cache: dict = {}
        self.weights = None
        self._grad = None  # the gradient of g at the last accepted point, reused by Newton nearby (a chord method)
        self._grad_x = None
        self._radius = 0.0

    # --- coordinates ------------------------------------------------------------------------------

    def lam(self, x) -> tuple[float, float]:
        return float(x[0]), float(10.0 ** x[1] if self.log2 else x[1])

    def x_of(self, lam1: float, lam2: float) -> np.ndarray:
        return np.array([lam1, math.log10(lam2) if self.log2 else lam2], float)

    def parameter(self, x) -> float:
        return float(x[0])

    # --- the critical quantity (subclasses) ---------------------------------------------------------

    def candidates(self, spectrum: np.ndarray) -> np.ndarray:
        """The values the critical one is tracked among: by default the real ones (to 1e-9 relative)."""
        spectrum = np.asarray(spectrum, complex)
        return spectrum[np.abs(spectrum.imag) <= 1e-9 * (1 + np.abs(spectrum))]

    def value(self, z: complex) -> float:
        raise NotImplementedError

    def critical(self, spectrum: np.ndarray) -> complex:
        c = self.candidates(spectrum)
        if not len(c):
            raise AnalysisError(f"no {self.kind} candidate in the spectrum")
        if self.crit is None:
            return complex(c[np.argmin([abs(self.value(z)) for z in c])])
        return complex(c[np.argmin(np.abs(c - self.crit))])

    # --- the defining system ------------------------------------------------------------------------

    def _solve(self, x):
        key = np.asarray(x, float).tobytes()
        if key not in self._cache:
            if len(self._cache) > 64:
                self._cache.clear()
            try:
                state, spectrum = self.follower.solve(self.pmap(self.lam(x)))
            except (ArithmeticError, ValueError) as exc:
                raise AnalysisError(f"the {self.follower.kind} could not be re-found ({type(exc).__name__})") from None
            self._cache[key] = (state, spectrum, self.critical(spectrum))
        return self._cache[key]

    def g(self, x) -> float:
        return self.value(self._solve(x)[2])

    def gradient(self, x, g0: float | None = None) -> np.ndarray:
        x = np.asarray(x, float)
        g0 = self.g(x) if g0 is None else g0
        grad = np.zeros(2)
        for j in range(2):
            h = DIFF_STEP * (1.0 + abs(x[j]))
            e = np.zeros(2)
            e[j] = h
            grad[j] = (self.g(x + e) - g0) / h
        return grad

    def evaluate(self, x):
        """g and its gradient; near the last accepted point (within three of the last steps) the gradient
        there is reused (Newton then converges linearly, and each iteration costs one solution, not three)."""
        x = np.asarray(x, float)
        g0 = self.g(x)
        if self._grad is not None and np.linalg.norm(x - self._grad_x) <= self._radius:
            grad = self._grad
        else:
            grad = self.gradient(x, g0)
        return np.array([g0]), grad[None, :]

    def data(self, x) -> BoundaryData:
        state, spectrum, crit = self._solve(x)
        return BoundaryData(np.array(x, float), self.lam(x), state, spectrum, crit)

    def accept(self, x, data: BoundaryData) -> None:
        self.follower.accept(data.state)
        self.crit = data.critical
        x = np.asarray(x, float)
        if self._grad_x is not None:
            self._radius = max(1e-4, 3 * float(np.linalg.norm(x - self._grad_x)))
        self._grad = self.gradient(x)
        self._grad_x = x.copy()
        self._cache.clear()

    def stop(self, x, data: BoundaryData):
        if self.range2 is not None:
            lo, hi = self.range2
            if not lo <= data.lam[1] <= hi:
                return "left the range of the second parameter"
        return None

    def tests(self, x, data) -> np.ndarray:
        return np.zeros(0)

    def special(self, name, x, data):
        return None


class FoldCurve(BoundaryCurve):
    """A real eigenvalue of a steady state through zero (a fold, or a symmetric state's branch point)."""

    kind = "fold"

    def value(self, z):
        return float(z.real)


def follower_for(model: Model, start) -> object:
    """An equilibrium follower from a state vector, an orbit follower from a PeriodicOrbit."""
    if hasattr(start, "multipliers"):
        return OrbitFollower(model, start)
    return EquilibriumFollower(model, start)
