"""A Lagrangian in a rotating frame and its Jacobi integral h = sum q' dL/dq' - L.

With the frame's rate constant and no explicit time, h is conserved up to the Rayleigh power:
dh/dt = -q'.dF/dq' (thesis ch. 2's second route, paper section 2); both families check it.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .lagrange import EnergyTerm, EquationsOfMotion


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
