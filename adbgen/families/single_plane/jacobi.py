"""The rotating-frame Lagrangian and its Jacobi integral.

Second route to (2.25)-(2.27): instead of transforming the *equations* (reductions.py), transform the
*Lagrangian* of (2.7)-(2.9): psi = omega t, the scalings (2.15)-(2.19) (L / (M R^2 omega_n^2)), the
rotating coordinates (2.23)-(2.24); then apply Lagrange's equations (2.1) anew.  The tests show the two
routes give the same equations (rotor rows equal, ball rows equal up to the factor mu of the
scaling), so the reductions commute with Lagrange's equations.

With zeta = beta = 0 the rotating-frame Lagrangian does not depend on t, so the Jacobi integral
h = sum_k q'_k dL/dq'_k - L is conserved.  With damping, dh/dt = -sum_k q'_k dF/dq'_k (the power of
the Rayleigh forces), which holds as an exact identity too.
"""

from __future__ import annotations

import sympy as sp

from ...core import EnergyTerm, canonical_trig, lagrange_equations
from ...core.frames import rotating_substitution
from ...core.jacobi import RotatingLagrangian
from .scene import Scene
from .model import lagrangian, speed_law_substitution
from .reductions import scaling
from .symbols import Omega, beta, nondimensional_parameters, omega_n, t, zeta


def rotating_lagrangian(scene: Scene) -> RotatingLagrangian:
    """The rotating-frame, dimensionless Lagrangian of a thesis scene without gravity."""
    if scene.gravity:
        raise ValueError("with gravity the rotating-frame Lagrangian depends on t: no Jacobi integral")
    lag = lagrangian(scene)
    law = speed_law_substitution(scene, lag.symbols)
    sub, _ = scaling(scene)
    (x, y), rot = rotating_substitution(Omega)
    s = lag.symbols
    energy_scale = s.M * s.R**2 * omega_n**2

    state = {x.q, x.qd, y.q, y.qd} | {sym for c in lag.coordinates for sym in (c.q, c.qd)}

    def transform(e: sp.Expr, scale: sp.Expr = energy_scale) -> sp.Expr:
        e = sp.expand(sp.sympify(e).xreplace(law).xreplace(sub) / scale)
        e = canonical_trig(e.xreplace(rot))
        # Additive constants (I_z omega^2 / 2, M eps^2 omega^2 / 2) change neither equations nor h's rate.
        return sp.Add(*(a for a in sp.Add.make_args(e) if a.free_symbols & state))

    # F is a power: in the time t omega_n it scales by M R^2 omega_n^3, not by the energy scale.
    terms = tuple(EnergyTerm(tm.label, transform(tm.T), transform(tm.V), transform(tm.F, energy_scale * omega_n))
                  for tm in lag.terms)
    for tm in terms:
        if tm.free_symbols() & {t, s.M, s.R, omega_n}:
            raise AssertionError(f"term {tm.label} is not autonomous and dimensionless")
    coords = (x, y) + tuple(c for c in lag.coordinates if c.name.startswith("phi_"))
    params = nondimensional_parameters(scene.nondimensional())
    eom = lagrange_equations(coords, terms, t, parameters=params,
                             reference="thesis (2.25)-(2.27) via the rotating-frame Lagrangian")
    L = sum((tm.T - tm.V for tm in terms), sp.S.Zero)
    F = sum((tm.F for tm in terms), sp.S.Zero)
    return RotatingLagrangian(terms, eom, sp.expand(L), sp.expand(F))


def undamped(expr: sp.Expr) -> sp.Expr:
    return expr.xreplace({zeta: 0, beta: 0})
