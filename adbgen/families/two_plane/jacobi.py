"""The two-plane rotating-frame Lagrangian and its Jacobi integral (isotropic supports, constant speed).

Second route to (7)-(8): transform the (truncated) Lagrangian of `model.lagrangian` instead of the
equations: theta_0 = Omega t, q = r e^{i Omega t} (5)-(6), theta_k = Omega t + alpha_k; then apply
Lagrange's equations anew (after adding a total time derivative that makes the gyroscopic term
frame-invariant, see below).  The tests show both routes give the same equations, and that without
damping h = sum q' dL/dq' - L is conserved (dh/dt = -q'.dF/dq' identically, so exactly conserved for
c = c_b = 0).  The class holding L, F and h is the single-plane one: nothing here is model-specific.
"""

from __future__ import annotations

import sympy as sp

from ...errors import ReductionError
from ...core import Coordinate, EnergyTerm, canonical_trig, lagrange_equations
from ...core.jacobi import RotatingLagrangian
from ...core.frames import rotating_substitution
from .model import lagrangian, speed_law
from .reductions import _tilt_substitution, non_autonomous_reasons
from .scene import TwoPlaneScene
from .symbols import t


def rotating_lagrangian(scene: TwoPlaneScene) -> RotatingLagrangian:
    reasons = non_autonomous_reasons(scene)
    if reasons:
        raise ReductionError(", ".join(reasons) + ": the rotating-frame Lagrangian depends on t")
    lag = lagrangian(scene)
    s = lag.symbols
    (x, y), sub = rotating_substitution(s.Omega)
    (px, py), tilt = _tilt_substitution(s.Omega)
    sub.update(tilt)
    sub.update(speed_law(scene, s))
    alphas = []
    for c in lag.coordinates[4:]:
        a = Coordinate.make(c.name.replace("theta", "alpha"))
        alphas.append(a)
        sub.update({c.q: s.Omega * t + a.q, c.qd: s.Omega + a.qd})
    coords = (x, y, px, py, *alphas)
    state = {sym for c in coords for sym in (c.q, c.qd)}

    def transform(expr):
        expr = canonical_trig(sp.sympify(expr).xreplace(sub))
        # Constant terms (the spin energies J_p Omega^2/2, ...) change neither the equations nor h's rate.
        return sp.Add(*(a for a in sp.Add.make_args(expr) if a.free_symbols & state))

    # The gyroscopic term -J_p Omega phi_X phi_Y' of T turns with the frame; adding the total derivative
    # d/dt(J_p Omega phi_X phi_Y / 2) (no change to the equations) makes it the invariant
    # -J_p Omega (phi_X phi_Y' - phi_Y phi_X')/2, so that L itself is free of t.
    pX, pY = (Coordinate.make(n) for n in ("phi_X", "phi_Y"))
    gauge = s.Jp * s.Omega * (pX.qd * pY.q + pX.q * pY.qd) / 2
    terms = tuple(EnergyTerm(tm.label, transform(tm.T + (gauge if tm.label == "rotor" else 0)), transform(tm.V),
                             transform(tm.F)) for tm in lag.terms)
    for tm in terms:
        if t in tm.free_symbols():
            raise AssertionError(f"term {tm.label} depends on t in the rotating frame")
    eom = lagrange_equations(coords, terms, t, parameters=s.parameters,
                             reference="paper (7)-(8) via the rotating-frame Lagrangian")
    L = sum((tm.T - tm.V for tm in terms), sp.S.Zero)
    F = sum((tm.F for tm in terms), sp.S.Zero)
    return RotatingLagrangian(terms, eom, sp.expand(L), sp.expand(F))


def undamped(scene: TwoPlaneScene) -> dict:
    """Bearing and race damping set to zero."""
    from .symbols import TwoPlaneSymbols

    s = TwoPlaneSymbols.for_scene(scene)
    return {sym: 0 for sym in set(s.c.values()) | set(s.cb)}
