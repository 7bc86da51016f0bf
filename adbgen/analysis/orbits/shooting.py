"""The shooting system of a periodic orbit: arcs of the compiled flow, their exact Jacobian, Newton.

Unknowns u = (x_0, ..., x_{m-1}, T) for an autonomous model (m arcs of T/m each; the period T free and a
phase condition fixing the point on the orbit), u = (x_0, ..., x_{m-1}) for a periodically forced one
(T = q 2 pi / w fixed by the forcing frequency w, q the subharmonic order; no phase condition):

    F_i = phi(t_i + T/m; t_i, x_i) - x_{i+1}        i = 0 .. m-2
    F_m = phi(t_m-1 + T/m; t_m-1, x_m-1) - x_0 - s   s = 2 pi k on the angles (k the windings: an angle
                                                     that laps returns modulo 2 pi k_i), 0 elsewhere
    g   = f(x_r) . (x_0 - x_r)                       the phase condition: x_0 on the hyperplane through a
                                                     reference point x_r normal to the flow there

The Jacobian is exact: d F_i / d x_i = Phi_i (the variational equations of `flow`), d F_i / d x_i+1 = -I,
d F_i / d T = f(end_i) / m, d F_i / d p along a direction dp = w_i (forced with the forcing frequency in
dp: the arcs' times move with it too).  The monodromy matrix is Phi_m-1 ... Phi_0; its eigenvalues are the Floquet multipliers.
Multiple shooting (m > 1) keeps each arc's Phi moderate where one arc over the whole period would
amplify errors beyond what Newton can use (long, unstable orbits).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..loading import AnalysisError, Model
from .flow import Flow

NEWTON_TOL = 1e-10  # |F| <= NEWTON_TOL (1 + |x|), relative to the states' size


class ShootingError(AnalysisError):
    """Newton on the shooting system did not converge."""


@dataclass
class Evaluation:
    """The shooting system at u: residual, Jacobian (square, in u) and the parameter column if asked."""

    F: np.ndarray
    A: np.ndarray | None
    Fk: np.ndarray | None
    X: np.ndarray  # arc starts, m x N
    ends: np.ndarray  # arc ends, m x N
    Phi: np.ndarray | None  # m x N x N
    T: float

    @property
    def monodromy(self) -> np.ndarray:
        M = self.Phi[0]
        for P in self.Phi[1:]:
            M = P @ M
        return M


class Shooting:
    """The shooting system of `model` at parameters p (see the module's docstring)."""

    def __init__(self, model: Model, flow: Flow, arcs: int = 1, shift: np.ndarray | None = None,
                 forcing: int | None = None, subharmonic: int = 1, t_start: float = 0.0):
        if arcs < 1:
            raise AnalysisError(f"arcs must be >= 1, got {arcs}")
        self.model, self.flow, self.m = model, flow, int(arcs)
        self.N = model.n_states
        self.shift = np.zeros(self.N) if shift is None else np.asarray(shift, float)
        self.forcing, self.q = forcing, int(subharmonic)
        self.forced = forcing is not None
        # a forced orbit's phase: the first arc starts at t_start (the forcing's time; 0 unless the orbit is
        # given at another instant); the parameter derivative below assumes t_start = 0
        self.t_start = float(t_start)
        self.ref: np.ndarray | None = None  # phase condition: reference point and the flow there
        self.ref_f: np.ndarray | None = None

    # --- unknowns ---------------------------------------------------------------------------------

    @property
    def size(self) -> int:
        return self.m * self.N + (0 if self.forced else 1)

    def period(self, u: np.ndarray, p: np.ndarray) -> float:
        return self.q * 2 * math.pi / p[self.forcing] if self.forced else float(u[-1])

    def pack(self, X: np.ndarray, T: float) -> np.ndarray:
        X = np.asarray(X, float).reshape(self.m, self.N)
        return X.ravel().copy() if self.forced else np.r_[X.ravel(), T]

    def arcs_of(self, u: np.ndarray) -> np.ndarray:
        return np.asarray(u[: self.m * self.N], float).reshape(self.m, self.N)

    def set_reference(self, x: np.ndarray, p: np.ndarray) -> None:
        """The phase condition's hyperplane: through x, normal to the flow at x."""
        self.ref = np.array(x, float)
        f = np.asarray(self.model.module.rhs(0.0, self.ref, p))
        self.ref_f = f / max(np.linalg.norm(f), 1e-300)

    # --- the system -------------------------------------------------------------------------------

    def evaluate(self, u: np.ndarray, p: np.ndarray, jacobian: bool = True, dp=None) -> Evaluation:
        m, N = self.m, self.N
        X = self.arcs_of(u)
        T = self.period(u, p)
        if not (T > 0 and math.isfinite(T)):
            raise ShootingError(f"the period left (0, inf): T = {T}")
        h = T / m
        t0 = self.t_start + np.arange(m) * h
        ends, Phi, W = self.flow.arcs(X, t0, h, p, phi=jacobian, dp=dp if jacobian else None)
        nxt = np.roll(X, -1, axis=0)
        nxt[-1] = X[0] + self.shift
        F = (ends - nxt).ravel()
        if not self.forced:
            if self.ref is None:
                self.set_reference(X[0], p)
            F = np.r_[F, self.ref_f @ (X[0] - self.ref)]
        if not jacobian:
            return Evaluation(F, None, None, X, ends, None, T)
        n = self.size
        A = np.zeros((n, n))
        for i in range(m):
            r = slice(i * N, (i + 1) * N)
            A[r, i * N:(i + 1) * N] = Phi[i]
            j = (i + 1) % m
            A[r, j * N:(j + 1) * N] -= np.eye(N)
        Fk = None
        rhs = self.model.module.rhs
        if not self.forced:
            fe = np.array([np.asarray(rhs(t0[i] + h, ends[i], p)) for i in range(m)])
            A[: m * N, -1] = (fe / m).ravel()
            A[-1, :N] = self.ref_f
            if dp is not None:
                Fk = np.r_[W.ravel(), 0.0]
        elif dp is not None:
            Fk = W.copy()
            dw = float(dp[self.forcing])
            if dw:  # the arcs' times scale with the forcing period: t_i = i T/m, dt_i/dw = -t_i/w
                w = p[self.forcing]
                for i in range(m):
                    ta, tb = t0[i], t0[i] + h
                    Fk[i] += (np.asarray(rhs(tb, ends[i], p)) * (-tb / w)
                              - Phi[i] @ np.asarray(rhs(ta, X[i], p)) * (-ta / w)) * dw
            Fk = Fk.ravel()
        return Evaluation(F, A, Fk, X, ends, Phi, T)

    def converged(self, ev: Evaluation, tol: float = NEWTON_TOL) -> bool:
        return float(np.max(np.abs(ev.F))) <= tol * (1.0 + float(np.max(np.abs(ev.X))))

    def solve(self, u0: np.ndarray, p: np.ndarray, tol: float = NEWTON_TOL, max_iter: int = 20,
              min_iter: int = 1) -> tuple[np.ndarray, Evaluation, int]:
        """Newton from u0 (minimum-norm steps; halved while the residual grows), at least `min_iter` steps so
        that the result is as accurate as the integration, not just inside the tolerance.  Returns (u, the
        evaluation at u with the Jacobian, iterations)."""
        u = np.array(u0, float)
        ev = self.evaluate(u, p)
        norm = float(np.max(np.abs(ev.F)))
        for it in range(max_iter + 1):
            if it >= min_iter and self.converged(ev, tol):
                return u, ev, it
            if it == max_iter:
                break
            step = np.linalg.lstsq(ev.A, -ev.F, rcond=1e-13)[0]
            lam = 1.0
            while True:
                trial = u + lam * step
                try:
                    ev_t = self.evaluate(trial, p)
                    n_t = float(np.max(np.abs(ev_t.F)))
                except AnalysisError:
                    n_t = math.inf
                if n_t < norm or lam < 1 / 64 or n_t <= tol:
                    break
                lam /= 2
            if not math.isfinite(n_t):
                raise ShootingError("shooting Newton: the arcs could not be integrated from the Newton step")
            u, ev, norm = trial, ev_t, n_t
        raise ShootingError(f"shooting Newton did not converge in {max_iter} steps (|F| = {norm:.3g}); start "
                            f"closer to the orbit (a longer --t-transient) or use more arcs")
