"""The equilibrium curve: a steady state followed in one parameter, and the solver the two-parameter
curves of `boundary` use to re-find it.

    EquilibriumCurve(model, pmap)        for `continuer.run`: x = (y, lambda) (`continuation.scan` runs it)
    EquilibriumFollower(model, y0, p0)   the steady state near y0 at any p, warm-started, with its spectrum
    homotopy(model, y0, p0, p1)          y0 (a steady state at p0) carried to p1 along the straight line

Defining system F(y, lambda) = f(y, p(lambda)) = 0 with the Jacobian [J, f_p dp/dlambda] (both generated),
plus, on a continuum of equilibria (the balanced family of n >= 3 balls), the pins T^T (y - y_a) = 0
that keep Newton on one member (`steady.family_tangent`; the curve then has as many more equations).
Test functions on the transverse spectrum (the family's neutral zeros removed, `steady.transverse_spectrum`):

    hopf      prod_{i<j, complex pairs} (lambda_i + lambda_j) scaled: zero when a pair crosses the axis
              (or two real eigenvalues sum to zero: a neutral saddle, refused by `special`)
    fold      d lambda / ds, watched by the continuer; a real eigenvalue through zero without a turn is a
              branch point (the continuer's "real" test: the product of the real eigenvalues' signs)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import steady
from ..loading import AnalysisError, Model
from .parameters import ParameterMap

SPECIAL_TOL = 1e-6
LEADING = 4  # the leading real parts watched as margins


@dataclass
class EquilibriumData:
    lam: float
    p: np.ndarray
    y: np.ndarray
    spectrum: np.ndarray  # transverse
    tangent: np.ndarray  # the family's tangent space (N x k)


def spectrum_of(model: Model, y: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    J = steady.jacobian(model, y, p)
    T = steady.family_tangent(model, y, p, J)
    return steady.transverse_spectrum(J, T), T


def hopf_test(ev: np.ndarray) -> float:
    """prod over pairs i < j of (l_i + l_j) / (1 + |l_i + l_j|), real: its sign changes when a complex pair
    crosses the imaginary axis (and when two real eigenvalues' sum passes zero)."""
    ev = np.asarray(ev, complex)
    i, j = np.triu_indices(len(ev), 1)
    s = ev[i] + ev[j]
    keep = ~((np.abs(s.imag) > 1e-12 * (1 + np.abs(ev[i]))) & (ev[i].imag * ev[j].imag > 0))
    s = s[keep]
    return float(np.real(np.prod(s / (1 + np.abs(s)))))


def real_test(ev: np.ndarray) -> float:
    """prod of the real eigenvalues' tanh: its sign changes when a real eigenvalue passes zero."""
    ev = np.asarray(ev, complex)
    real = ev[np.abs(ev.imag) <= 1e-12 * (1 + np.abs(ev))].real
    return float(np.prod(np.tanh(real))) if len(real) else 1.0


class EquilibriumCurve:
    """A steady state of `model` along pmap's free parameter (see the module's docstring)."""

    test_names = ("hopf", "real")

    def __init__(self, model: Model, pmap: ParameterMap, progress=None):
        self.model, self.pmap, self.progress = model, pmap, progress
        self.N = model.n_states
        self.T = np.zeros((self.N, 0))
        self.anchor = None
        self.size = self.N + 1

    def parameter(self, x) -> float:
        return float(x[-1])

    def evaluate(self, x):
        y, lam = x[:-1], float(x[-1])
        p = self.pmap(lam)
        f = steady.residual(self.model, y, p)
        J = steady.jacobian(self.model, y, p)
        fl = np.asarray(self.model.module.jac_p(0.0, y, p)) @ self.pmap.direction(lam)
        A = np.hstack([J, fl[:, None]])
        if self.T.shape[1]:  # pins onto one member of the continuum: rows T^T (y - anchor), square via lstsq
            f = np.r_[f, self.T.T @ (y - self.anchor)]
            A = np.vstack([A, np.hstack([self.T.T, np.zeros((self.T.shape[1], 1))])])
            # the continuer needs n x (n + 1): drop as many rows of f as pins were added, in the family's
            # directions (J T = 0 makes those rows dependent on the rest)
            Q, _ = np.linalg.qr(np.hstack([self.T, np.eye(self.N)]))
            keep = Q[:, self.T.shape[1]:self.N]
            f = np.r_[keep.T @ f[:self.N], f[self.N:]]
            A = np.vstack([keep.T @ A[:self.N], A[self.N:]])
        return f, A

    def data(self, x) -> EquilibriumData:
        y, lam = x[:-1], float(x[-1])
        p = self.pmap(lam)
        ev, T = spectrum_of(self.model, y, p)
        return EquilibriumData(lam, p, y.copy(), ev, T)

    def tests(self, x, data: EquilibriumData) -> np.ndarray:
        return np.array([hopf_test(data.spectrum), real_test(data.spectrum)])

    def margins(self, data: EquilibriumData) -> np.ndarray:
        """The stability margins watched by the continuer: the LEADING largest real parts of the transverse
        spectrum (one heading for zero bounds the step; an extremum of one inside a step is checked), padded
        with -1 (constant: no bound) on a smaller spectrum."""
        r = np.sort(np.asarray(data.spectrum, complex).real)[::-1][:LEADING]
        return np.pad(r, (0, LEADING - len(r)), constant_values=-1.0)

    def special(self, name, x, data: EquilibriumData):
        ev = data.spectrum
        tol = SPECIAL_TOL * max(1.0, float(np.max(np.abs(ev))))
        if name == "hopf":
            pair = ev[(ev.imag > tol)]
            if len(pair) and np.min(np.abs(pair.real)) <= tol:
                z = pair[np.argmin(np.abs(pair.real))]
                return {"kind": "hopf", "frequency": float(z.imag)}
            return None
        if name == "real":
            real = ev[np.abs(ev.imag) <= tol]
            if len(real) and np.min(np.abs(real.real)) <= tol:
                return {"kind": "branch"}
            return None
        return None

    def accept(self, x, data: EquilibriumData) -> None:
        self.T, self.anchor = data.tangent, x[:-1].copy()
        if self.progress is not None:
            self.progress(float(x[-1]))


class EquilibriumFollower:
    """The steady state near the last one found, at any parameters; its transverse spectrum."""

    kind = "equilibrium"

    def __init__(self, model: Model, y0: np.ndarray):
        self.model = model
        self.last = np.array(y0, float)

    def solve(self, p: np.ndarray, guess: np.ndarray | None = None):
        y0 = self.last if guess is None else guess
        free = self._pins(y0)
        extra = None
        if free:
            rows = np.zeros((len(free), self.model.n_states))
            rows[range(len(free)), free] = 1.0
            extra = (lambda y: y[free] - y0[free], lambda y: rows)
        y, _ = steady.newton(self.model, p, y0, extra=extra)
        ev, _ = spectrum_of(self.model, y, p)
        return y, ev

    def _pins(self, y0) -> list[int]:
        """The free angles of a balanced continuum (n >= 3): held at the start's values."""
        T = steady.balanced_family_tangent(self.model, y0)
        return list(self.model.angle_indices)[2:] if T.shape[1] else []

    def accept(self, state) -> None:
        self.last = np.array(state, float)


def homotopy(model: Model, y0: np.ndarray, p0: np.ndarray, p1: np.ndarray, steps: int = 40) -> np.ndarray:
    """The steady state y0 at p0 carried to p1: Newton at p0 + s (p1 - p0), s = 1/steps .. 1 (halving the step
    where Newton fails), so that many parameters set at once (--set) do not throw Newton onto another state."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    return carry(model, y0, lambda s: p0 + s * (p1 - p0), steps)


def carry(model: Model, y0: np.ndarray, path, steps: int = 40) -> np.ndarray:
    """The steady state y0 at path(0) carried to path(1): Newton at path(s), s = 1/steps .. 1, each from the
    state before (the step halved where Newton fails)."""
    follower = EquilibriumFollower(model, y0)
    s, ds, y = 0.0, 1.0 / steps, np.array(y0, float)
    while s < 1.0:
        t = min(1.0, s + ds)
        try:
            y, _ = follower.solve(path(t), y)
        except AnalysisError:
            ds /= 2
            if ds < 1e-6:
                raise AnalysisError("the start state could not be carried to the --set parameters (it ceases to "
                                    "exist on the way?)") from None
            continue
        follower.accept(y)
        s = t
        ds = min(2 * ds, 1.0 / steps)
    return y


def carried_start(model, p, pmap=None):
    """START carried to p.  Without ties: a straight homotopy from START_PARAMETERS.  With ties (pmap.ties),
    the state is re-solved along the ties, not only the parameters: first at START_PARAMETERS with the ties
    applied, then along a path of the untied parameters from START's values to p's (geometric where a value
    keeps its sign, straight otherwise) with the ties applied at every point.  Several parameters set at once
    can throw plain Newton, or a straight homotopy, onto another steady state: the paper's charts tie the
    balls' mass to the imbalance (m/M = eps/R + chi), and only along the tie does B stay balanced (a straight
    homotopy from START to eps = 5e-5 lands on an off-centre state, x = 2.8e-5)."""
    y0 = np.array(model.module.START, float)
    p0 = np.array(model.module.START_PARAMETERS, float)
    if pmap is None or not pmap.ties:
        return homotopy(model, y0, p0, p)
    p = np.asarray(p, float)
    # the untied parameters at the end: p's free values on pmap's base (which holds the --set values)
    base1 = np.array(pmap.base, float)
    base1[pmap.index] = p[pmap.index]
    tied = lambda b: ParameterMap(model, b, [], ties=pmap.ties)([])  # noqa: E731
    y = homotopy(model, y0, p0, tied(p0))
    same = (p0 * base1 > 0)
    mag0, mag1 = np.abs(np.where(same, p0, 1.0)), np.abs(np.where(same, base1, 1.0))

    def path(t):
        return tied(np.where(same, np.sign(base1) * mag0 ** (1 - t) * mag1 ** t, p0 + t * (base1 - p0)))
    return carry(model, y, path, 60)
