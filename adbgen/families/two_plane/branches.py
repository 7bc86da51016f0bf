"""The normal form against the full model: paper Figure 9 and the stability statements (37)-(38).

The steady states of the full rotating-frame equations (7)-(8) (damped, all eight coordinates) are
continued in the deviatoric ball angle by Newton's method (scipy.optimize.root at each step, a secant
predictor between steps): natural-parameter continuation in alpha_hat, which stays regular through the
pitchfork where continuation in m would not.

- B: alpha_hat_12 = s given; unknowns x, y, phi_x, phi_y, the mean angles of both races, alpha_hat_34, m;
- C3-type: one race coincident (alpha_1 = alpha_2, or alpha_3 = alpha_4), the other split by +-s;
  unknowns x, y, phi_x, phi_y, both mean angles, m (the coincident pair's second row is the first's).

m - m_c is then fitted by c_0 + c_2 s^2 + c_4 s^4 and c_2 compared with the normal form's slope;
stability comes from the eigenvalues of the exact linearisation of the full model.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.optimize import root

from ...core.linearisation import Linearisation
from .reductions import rotating_frame
from .scene import TwoPlaneScene

RACE_DAMPING_RATIO = 0.01  # c_b / m of (10)


@dataclass(frozen=True)
class Branch:
    kind: str  # "B", "Ct3" (top coincident, bottom split), "Cb3"
    s: np.ndarray  # the continuation parameter alpha_hat
    m: np.ndarray
    states: np.ndarray  # rows: x, y, phi_x, phi_y, alpha_1..alpha_4

    def fit(self, m_c: float | None = None, s_max: float = 0.3) -> tuple[float, float]:
        """(intercept, slope) of m = c_0 + c_2 s^2 + c_4 s^4 over s <= s_max (c_0 fixed to m_c if given)."""
        keep = self.s <= s_max + 1e-12
        s2 = self.s[keep] ** 2
        if m_c is not None:
            A = np.column_stack([s2, s2**2])
            coef, *_ = np.linalg.lstsq(A, self.m[keep] - m_c, rcond=None)
            return m_c, float(coef[0])
        A = np.column_stack([np.ones_like(s2), s2, s2**2])
        coef, *_ = np.linalg.lstsq(A, self.m[keep], rcond=None)
        return float(coef[0]), float(coef[1])


@lru_cache(maxsize=4)
def full_model(scene: TwoPlaneScene) -> Linearisation:
    return Linearisation(rotating_frame(scene))


class FullSteadyStates:
    """Steady states and eigenvalues of the derived (7)-(8) for a symmetric scene, ball mass m free."""

    def __init__(self, scene: TwoPlaneScene, **values: float):
        if scene.n != 4:
            raise ValueError("the branches of section 3 need two balls per race")
        self.lin = full_model(replace(scene, speed=replace(scene.speed, law="constant")))
        self.values = values

    def parameters(self, m: float) -> np.ndarray:
        v = dict(self.values)
        v.update({f"m_{i + 1}": m for i in range(4)})
        v.update({"c_bt": RACE_DAMPING_RATIO * m, "c_bb": RACE_DAMPING_RATIO * m})
        return self.lin.parameters(**v)

    @staticmethod
    def _state(kind: str, z: np.ndarray, s: float) -> np.ndarray:
        x, y, px, py = z[:4]
        if kind == "B":
            b12, b34, h34 = z[4:7]
            return np.array([x, y, px, py, b12 + s, b12 - s, b34 + h34, b34 - h34])
        b12, b34 = z[4:6]
        if kind == "Ct3":
            return np.array([x, y, px, py, b12, b12, b34 + s, b34 - s])
        return np.array([x, y, px, py, b12 + s, b12 - s, b34, b34])

    def _residual(self, kind: str, z: np.ndarray, s: float) -> np.ndarray:
        r = self.lin.residual(self._state(kind, z, s), self.parameters(z[-1]))
        if kind == "Ct3":
            return r[[0, 1, 2, 3, 4, 6, 7]]
        if kind == "Cb3":
            return r[[0, 1, 2, 3, 4, 5, 6]]
        return r

    def continue_branch(self, kind: str, m_guess: float, s_values=np.arange(0.02, 0.3001, 0.02)) -> Branch:
        z = np.array([0, 0, 0, 0, np.pi, np.pi] + ([s_values[0]] if kind == "B" else []) + [m_guess], float)
        history, ms, states = [], [], []
        for s in s_values:
            guess = z if len(history) < 2 else 2 * history[-1] - history[-2]  # secant predictor
            sol = root(lambda w: self._residual(kind, w, s), guess, method="hybr", options={"xtol": 1e-13})
            if not sol.success or np.abs(self._residual(kind, sol.x, s)).max() > 1e-11:
                raise RuntimeError(f"Newton failed on {kind} at alpha_hat = {s:.3f}: {sol.message}")
            z = sol.x
            history.append(z)
            ms.append(z[-1])
            states.append(self._state(kind, z, s))
        return Branch(kind, np.asarray(s_values, float), np.array(ms), np.array(states))

    def spectrum(self, branch: Branch, i: int):
        return self.lin.spectrum(branch.states[i], self.parameters(branch.m[i]), zero_tol=1e-12)
