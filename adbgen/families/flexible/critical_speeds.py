"""Critical speeds of the reduced rotor (no balls): where a damped natural frequency of
M_q q'' + (C_q + Omega G_q) q' + K_q q = 0 equals the spin speed Omega (the Campbell diagram's crossings
with omega = Omega, as ROSS finds them for the full model), with the whirl direction of each.

Numbers only, from the scene's matrices: the quadratic eigenproblem as the first-order A(Omega) =
[[0, I], [-M^-1 K, -M^-1 (C + Omega G)]], its eigenvalues with positive imaginary part sorted are the damped
natural frequencies w_d,i(Omega); each crossing w_d,i(Omega) = Omega is bracketed on a grid and refined by
Brent's method.  Whirl: forward when the balancer node's orbit turns with the spin (from x to y, as psi
does and as ROSS's spin does: its forward modes stiffen with speed), backward otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .scene import Modal

GRID = 200


@dataclass(frozen=True)
class Crossing:
    speed: float  # rad/s
    whirl: str  # "forward" or "backward"


def _eigen(modal: Modal, speed: float) -> tuple[np.ndarray, np.ndarray]:
    M, K, C, G = (np.array(a, dtype=float) for a in (modal.mass, modal.stiffness, modal.damping, modal.gyroscopic))
    k = len(M)
    A = np.block([[np.zeros((k, k)), np.eye(k)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    lam, vec = np.linalg.eig(A)
    keep = lam.imag > 0
    lam, vec = lam[keep], vec[:k, keep]
    order = np.argsort(lam.imag)
    return lam[order], vec[:, order]


def damped_frequencies(modal: Modal, speed: float) -> np.ndarray:
    return _eigen(modal, speed)[0].imag


def whirl(modal: Modal, speed: float, i: int) -> str:
    """Forward or backward: the sign of the node's orbit's angular momentum x y' - y x' = -w Im(conj(a) b)
    for the mode x(t), y(t) = Re((a, b) e^{i w t}) (positive: turning from x to y, with the spin psi)."""
    lam, vec = _eigen(modal, speed)
    shape = np.array(modal.node_shape, dtype=float) @ vec[:, i]
    turn = float(np.imag(np.conj(shape[0]) * shape[1]))
    return "forward" if turn < 0 else "backward"


def crossings(modal: Modal, top: float, xtol: float = 1e-12) -> list[Crossing]:
    """Every crossing in (0, top], ascending."""
    speeds = np.linspace(0.0, top, GRID)
    wd = [damped_frequencies(modal, s) for s in speeds]
    count = min(len(w) for w in wd)
    wd = np.array([w[:count] for w in wd])
    out = []
    for i in range(count):
        gap = wd[:, i] - speeds
        for j in np.nonzero(np.sign(gap[:-1]) * np.sign(gap[1:]) < 0)[0]:
            s = brentq(lambda x, i=i: float(damped_frequencies(modal, x)[i]) - x, speeds[j], speeds[j + 1],
                       xtol=xtol * top, rtol=4 * np.finfo(float).eps)
            out.append(Crossing(float(s), whirl(modal, s, i)))
    return sorted(out, key=lambda c: c.speed)


def damping_ratio(modal: Modal, speed: float) -> float:
    """zeta = -Re(lambda) / |lambda| of the mode whose damped natural frequency at `speed` is nearest to it
    (at a critical speed: the mode that crosses there)."""
    lam = _eigen(modal, speed)[0]
    i = int(np.argmin(np.abs(lam.imag - speed)))
    return float(-lam[i].real / abs(lam[i]))
