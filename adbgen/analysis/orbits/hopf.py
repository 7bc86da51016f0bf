"""Hopf points of an equilibrium: refined, classified, the start of the cycles they give birth to, and the
Hopf curve in two parameters.

    hp = HopfPoint.at(model, pmap, y, lam)          eigenvectors, frequency, first Lyapunov coefficient
    x0, t0 = cycle_start(curve, hp)                  the first cycle of the branch and its direction
    HopfCurve(model, pmap2, follower)                the curve of Hopf points in two parameters (`boundary`)
    refine_hopf(model, pmap, y, lam, omega, follower) the Hopf point near an equilibrium AUTO-07p reported

The cycle branch leaves the Hopf point in the direction of the eigenvector: x(t) = y + a Re(q e^(i w t)),
T = 2 pi / w, the parameter unchanged to first order; the continuer's first step is taken along that
direction from the equilibrium itself (a branch switch), so no guess of the cycle's amplitude is needed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..loading import AnalysisError, Model
from .boundary import BoundaryCurve
from .first_lyapunov import criticality, first_lyapunov, hopf_vectors
from .parameters import ParameterMap


@dataclass
class HopfPoint:
    lam: float  # the parameter
    y: np.ndarray
    p: np.ndarray
    omega: float
    q: np.ndarray  # right eigenvector, |q| = 1
    l1: float
    info: dict

    @property
    def criticality(self) -> str:
        return criticality(self.l1)

    @classmethod
    def at(cls, model: Model, pmap: ParameterMap, y: np.ndarray, lam: float, omega: float | None = None,
           derivatives: str = "jet") -> "HopfPoint":
        p = pmap(lam)
        A = np.asarray(model.module.jac(0.0, y, p))
        ev, q, _ = hopf_vectors(A, omega)
        l1, info = first_lyapunov(model, p, y, float(ev.imag), derivatives=derivatives)
        return cls(float(lam), np.array(y, float), p, float(ev.imag), q, l1, info)


def cycle_start(curve, hp: HopfPoint) -> tuple[np.ndarray, np.ndarray]:
    """(x, tangent) for `continuer.run(curve, x, ..., tangent=tangent)`: the equilibrium as a degenerate
    cycle of period 2 pi / w, and the direction of the cycle branch there (the eigenvector's real part
    along the arcs, rotated by w t_i; period and parameter unchanged to first order)."""
    sh = curve.shooting
    T = 2 * math.pi / hp.omega
    m = sh.m
    t = T * np.arange(m) / m
    # phase the eigenvector so that Re q is orthogonal to Im q: the small cycle's point y + a Re q then lies
    # on the phase condition's hyperplane through y normal to the flow there, A Re q = -w Im q
    a, b = hp.q.real, hp.q.imag
    q = hp.q * np.exp(0.5j * math.atan2(-2 * (a @ b), a @ a - b @ b))
    X = np.tile(hp.y, (m, 1))
    V = np.real(q[None, :] * np.exp(1j * hp.omega * t)[:, None])
    x = curve.pack(X, T, hp.lam)
    tangent = curve.pack(V, 0.0, 0.0)
    sh.ref = hp.y.copy()
    sh.ref_f = -q.imag / np.linalg.norm(q.imag)
    return x, tangent


class HopfCurve(BoundaryCurve):
    """The Hopf curve in two parameters: a complex eigenvalue pair of the followed steady state on the
    imaginary axis (defining system in `boundary`: g = Re of the tracked pair).  Test functions: the pair's
    frequency (a Bogdanov-Takens point where it reaches 0) and the first Lyapunov coefficient l1 (a
    generalised Hopf point, Bautin, where it changes sign; from the exact jets, `lyapunov`)."""

    kind = "hopf"
    test_names = ("Bogdanov-Takens", "generalised Hopf")

    def candidates(self, ev):
        ev = np.asarray(ev, complex)
        return ev[ev.imag > 1e-9 * (1 + np.abs(ev))]

    def value(self, z):
        return float(z.real)

    def tests(self, x, data):
        l1 = first_lyapunov(self.model, self.pmap(data.lam), data.state, float(data.critical.imag))[0]
        return np.array([float(data.critical.imag), l1])

    def special(self, name, x, data):
        return {"kind": name, "frequency": float(data.critical.imag)}


def refine_hopf(model, pmap, y, lam, omega, follower):
    """The Hopf point near (y, lam): lam by Brent's method on the real part of the pair nearest i omega,
    the equilibrium re-solved at each trial (`follower(p, guess)`)."""
    from scipy.optimize import brentq

    state = {"y": np.array(y, float)}

    def g(v):
        state["y"] = follower(pmap(v), state["y"])
        A = np.asarray(model.module.jac(0.0, state["y"], pmap(v)))
        return float(hopf_vectors(A, omega)[0].real)
    d = 1e-6 * max(1.0, abs(lam))
    a, b = lam - d, lam + d
    try:
        ga, gb = g(a), g(b)
        for _ in range(8):
            if ga * gb < 0:
                break
            d *= 4
            a, b = lam - d, lam + d
            ga, gb = g(a), g(b)
        lam = brentq(g, a, b, xtol=1e-13, rtol=4e-16) if ga * gb < 0 else lam
        g(lam)
    except (AnalysisError, ValueError):
        pass
    return HopfPoint.at(model, pmap, state["y"], lam, omega)
