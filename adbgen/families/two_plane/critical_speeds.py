"""Rigid-body critical speeds of the two-plane rotor: paper (11), (32) and the values quoted for (42), (43).

A critical speed is a spin speed Omega at which the undamped rotor has a natural whirl at frequency Omega.
Both routes start from the *derived* equations (ball angles frozen, c = 0):

- isotropic supports: in the rotating frame such a whirl is a zero-frequency mode, so the critical
  speeds are the zeros of det(-df/dr) at rest, a polynomial in Omega^2 equal to
  det(K - Omega^2 (M - G))^2 (the forward whirls of (11), (32));
- anisotropic supports: in the fixed frame, det(K - Omega^2 M_r + i Omega D) = 0 with D = -df/dq'
  (the gyroscopic matrix, proportional to Omega), again a polynomial in Omega^2.  The paper found its
  values for (43) as the peaks of the imbalance response; `response_peaks` does that too.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import sympy as sp
from scipy.optimize import minimize_scalar

from ...core import EquationsOfMotion
from .model import derive
from .reductions import CORE, ROTATING_CORE, rotating_frame
from .scene import TwoPlaneScene
from .symbols import TwoPlaneSymbols


def _linear_rotor(eom: EquationsOfMotion, core) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Mass, damping-plus-gyroscopic and stiffness matrices of the rotor rows (rates and tilts at zero)."""
    idx = [eom.index(n) for n in core]
    coords = [eom.coordinates[k] for k in idx]
    rest = {c.qd: 0 for c in eom.coordinates}
    rest.update({c.q: 0 for c in coords})
    f = sp.Matrix([eom.forcing[k] for k in idx])
    K = -f.jacobian([c.q for c in coords]).xreplace(rest)
    D = -f.jacobian([c.qd for c in coords]).xreplace(rest)
    M = sp.Matrix(len(idx), len(idx), lambda a, b: eom.mass.get((idx[a], idx[b]), sp.S.Zero)).xreplace(rest)
    return M.applyfunc(sp.expand), D.applyfunc(sp.expand), K.applyfunc(sp.expand)


def _undamped(scene: TwoPlaneScene, s: TwoPlaneSymbols) -> dict:
    return {sym: 0 for sym in set(s.c.values())}


def critical_speed_polynomial(scene: TwoPlaneScene, values: dict | None = None) -> tuple[sp.Poly, sp.Symbol]:
    """The polynomial in w = Omega^2 whose positive roots are the critical speeds squared.

    ``values`` (symbol -> number) are substituted before the determinant is formed (much faster).
    """
    s = TwoPlaneSymbols.for_scene(scene)
    w = sp.Symbol("w", positive=True)
    values = dict(values or {})
    values.pop(s.Omega, None)
    scene = replace(scene, speed=replace(scene.speed, law="constant"))
    sub = lambda A: A.xreplace(_undamped(scene, s)).xreplace(values)  # noqa: E731
    if scene.isotropic:
        M, D, K = _linear_rotor(rotating_frame(scene), ROTATING_CORE)
        det = sub(K).det(method="berkowitz")
    else:
        M, D, K = _linear_rotor(derive(scene), CORE)
        det = (sub(K) - s.Omega**2 * sub(M) + sp.I * s.Omega * sub(D)).det(method="berkowitz")
    det = sp.expand(sp.expand(det).xreplace({s.Omega: sp.sqrt(w)}))
    return sp.Poly(det, w), w


def exact_values(scene: TwoPlaneScene, with_balls: bool = True) -> dict:
    """The scene's parameter defaults as exact rationals (so repeated roots stay exactly repeated)."""
    s = TwoPlaneSymbols.for_scene(scene)
    values = {p.symbol: sp.Rational(repr(p.default)) for p in s.parameters}
    if not with_balls:
        values.update({m: 0 for m in s.m})
    return values


def critical_speeds(scene: TwoPlaneScene, with_balls: bool = True) -> list[float]:
    """Distinct positive critical speeds at the scene's parameter values, ascending.

    with_balls=False takes the plain rotor (m_k = 0), as (11) and the values quoted for (42), (43) do.
    """
    poly, w = critical_speed_polynomial(scene, exact_values(scene, with_balls))
    roots = sp.Poly(poly.sqf_part(), w).nroots(n=30)
    return sorted(float(sp.sqrt(r)) for r in roots if r.is_real and r > 0)


def response_peaks(scene: TwoPlaneScene, imbalance: str, grid=np.linspace(0.3, 5.0, 941)) -> list[float]:
    """Speeds of the maximum steady response to a static ('static': |X|, |Y|) or couple ('couple':
    |phi_X|, |phi_Y|) imbalance of the damped plain rotor, from the derived fixed-frame equations."""
    s = TwoPlaneSymbols.for_scene(scene)
    eom = derive(replace(scene, speed=replace(scene.speed, law="constant")))
    M, D, K = _linear_rotor(eom, CORE)
    values = {p.symbol: p.default for p in s.parameters}
    values.update({m: 0.0 for m in s.m})
    values.pop(s.Omega, None)
    values.update({s.eps: 1.0 if imbalance == "static" else 0.0, s.chi: 1.0 if imbalance == "couple" else 0.0})
    th0 = sp.Symbol("theta_0", real=True)
    idx = [eom.index(n) for n in CORE]
    rest = {c.qd: 0 for c in eom.coordinates} | {c.q: 0 for c in eom.coordinates}
    # Forcing at theta_0 = Omega t: f = Re(F e^{i Omega t}), F = f(0) - i f(pi/2) (each row is A cos + B sin).
    f = sp.Matrix([eom.forcing[k] for k in idx]).xreplace({eom.coordinates[k].q: 0 for k in idx})
    f = f.xreplace({c.qd: 0 for c in eom.coordinates}).xreplace({sp.Symbol("t", real=True): th0 / s.Omega})
    F = f.xreplace({th0: 0}) - sp.I * f.xreplace({th0: sp.pi / 2})
    lam = sp.lambdify([s.Omega], [M.xreplace(rest).xreplace(values), D.xreplace(values), K.xreplace(values),
                                   F.xreplace({c.q: 0 for c in eom.coordinates}).xreplace(values)], modules="numpy")
    pick = [0, 1] if imbalance == "static" else [2, 3]

    def amplitude(om):
        Mn, Dn, Kn, Fn = (np.array(a, dtype=complex) for a in lam(om))
        U = np.linalg.solve(Kn - om**2 * Mn + 1j * om * Dn, Fn.ravel())
        return float(np.linalg.norm(U[pick]))

    amp = np.array([amplitude(om) for om in grid])
    peaks = [i for i in range(1, len(grid) - 1) if amp[i] > amp[i - 1] and amp[i] >= amp[i + 1]]
    out = []
    for i in peaks:
        res = minimize_scalar(lambda om: -amplitude(om), bounds=(grid[i - 1], grid[i + 1]), method="bounded",
                              options={"xatol": 1e-9})
        out.append(float(res.x))
    return out
