"""Simulations of the two-plane model: run-ups in the fixed frame, constant speed in the rotating frame.

Both use the single-plane reference evaluator `NumericFirstOrder` (structured solve: the rotor's 4x4
core solved numerically, balls back-substituted) on the two-plane first-order form; a prescribed
run-up enters through ``driven_law`` (theta_0, theta_0', theta_0'' in t: the ramp of section 6 or the
Hill profile (45)).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp

from ...core.numeric import NumericFirstOrder
from .model import derive
from .reductions import first_order, rotating_frame
from .scene import TwoPlaneScene


@lru_cache(maxsize=8)
def fixed_frame_rhs(scene: TwoPlaneScene) -> NumericFirstOrder:
    return NumericFirstOrder(first_order(derive(scene)))


@lru_cache(maxsize=8)
def rotating_frame_rhs(scene: TwoPlaneScene) -> NumericFirstOrder:
    return NumericFirstOrder(first_order(rotating_frame(scene)))


@dataclass(frozen=True)
class Run:
    t: np.ndarray
    y: np.ndarray  # states on the rows, as `state_names`
    state_names: tuple[str, ...]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.y[self.state_names.index(name)]


def simulate(rhs: NumericFirstOrder, y0, t_span, t_eval=None, rtol: float = 1e-10, **params: float) -> Run:
    p = rhs.defaults.copy()
    for name, value in params.items():
        p[rhs.parameter_names.index(name)] = value
    sol = solve_ivp(rhs, t_span, np.asarray(y0, float), args=(p,), method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                    t_eval=t_eval)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    return Run(sol.t, sol.y, rhs.state_names)


def to_rotating(state: np.ndarray, names: tuple[str, ...], angle: float, omega: float) -> dict[str, float]:
    """A fixed-frame state (X, Y, phi_X, phi_Y, theta_k and rates) in the frame turned by `angle` at
    the rate `omega`: q = r e^{i angle} (5)-(6), theta_k = angle + alpha_k."""
    v = dict(zip(names, state))
    q1, q1d = v["X"] + 1j * v["Y"], v["X_dot"] + 1j * v["Y_dot"]
    q2, q2d = v["phi_Y"] - 1j * v["phi_X"], v["phi_Y_dot"] - 1j * v["phi_X_dot"]
    turn = np.exp(-1j * angle)
    r1, r2 = q1 * turn, q2 * turn
    r1d, r2d = (q1d - 1j * omega * q1) * turn, (q2d - 1j * omega * q2) * turn
    out = {"x": r1.real, "y": r1.imag, "phi_y": r2.real, "phi_x": -r2.imag,
           "x_dot": r1d.real, "y_dot": r1d.imag, "phi_y_dot": r2d.real, "phi_x_dot": -r2d.imag}
    for name, value in v.items():
        if name.startswith("theta_") and not name.startswith("theta_0"):
            out[name.replace("theta", "alpha")] = value - (omega if name.endswith("_dot") else angle)
    return out
