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

from dataclasses import dataclass

import sympy as sp

from ..mechanics import EnergyTerm, EquationsOfMotion, canonical_trig, lagrange_equations
from ..scene import Scene
from .model import lagrangian, speed_law_substitution
from .reductions import rotating_substitution, scaling
from .symbols import beta, nondimensional_parameters, omega_n, t, zeta


@dataclass(frozen=True)
class RotatingLagrangian:
    terms: tuple[EnergyTerm, ...]
    eom: EquationsOfMotion  # Lagrange's equations of the terms
    L: sp.Expr
    F: sp.Expr

    def jacobi_integral(self) -> sp.Expr:
        """h = sum_k q'_k dL/dq'_k - L."""
        return sp.expand(sum((c.qd * sp.diff(self.L, c.qd) for c in self.eom.coordinates), sp.S.Zero) - self.L)

    def jacobi_rate_identities(self) -> tuple[list[sp.Expr], sp.Expr]:
        """Expressions that vanish identically when h is conserved up to the Rayleigh power.

        (1) dh/dq' - M q' (so that dh/dq' . q'' = q'^T f along the flow, no inverse needed);
        (2) dh/dq . q' + q'^T f + q' . dF/dq' (= dh/dt + Rayleigh power along the flow).
        """
        h = self.jacobi_integral()
        coords = self.eom.coordinates
        Mq = [sum((self.eom.mass.get((k, j), sp.S.Zero) * cj.qd for j, cj in enumerate(coords)), sp.S.Zero)
              for k in range(len(coords))]
        first = [sp.expand(sp.diff(h, c.qd) - Mq[k]) for k, c in enumerate(coords)]
        rate = sum((sp.diff(h, c.q) * c.qd + c.qd * f + c.qd * sp.diff(self.F, c.qd)
                    for c, f in zip(coords, self.eom.forcing)), sp.S.Zero)
        return first, sp.expand(rate)


def rotating_lagrangian(scene: Scene) -> RotatingLagrangian:
    """The rotating-frame, dimensionless Lagrangian of a thesis scene without gravity."""
    if scene.gravity:
        raise ValueError("with gravity the rotating-frame Lagrangian depends on t: no Jacobi integral")
    lag = lagrangian(scene)
    law = speed_law_substitution(scene, lag.symbols)
    sub, _ = scaling(scene)
    (x, y), rot = rotating_substitution()
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
