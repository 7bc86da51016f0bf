"""Ball-race friction as both families derive it (issue 37): the race's normal force on a ball as the
multiplier of the race constraint, and the direction of a ball's slip.

Shared by `families.single_plane.model` and `families.two_plane.model` (moved here from the single-plane
model when the two-plane family got friction): the idea is the same in both, only the ball's position
differs.
"""

from __future__ import annotations

import sympy as sp

from .lagrange import Coordinate, EnergyTerm, lagrange_equations, time_derivative


def slip_direction(rate: sp.Expr) -> sp.Expr:
    """sign(rate) as a Piecewise (1, -1, and 0 at rate = 0): the direction of a ball's slip on the race in a
    model without stiction (at rest the slip law says nothing and the force is 0).  Written with branches
    rather than sign() so that its derivative is 0 on each side (sign's is a Dirac delta, which no target
    prints).  A model with stiction takes the direction from the ball's mode instead (slip_dir_i)."""
    return sp.Piecewise((1, rate > 0), (-1, rate < 0), (0, True))


def stick_row(slip_row: sp.Expr, stuck: sp.Symbol, mass: sp.Expr, radius: sp.Expr,
              relative_acceleration: sp.Expr) -> sp.Expr:
    """A ball's row of the hybrid system (issue 37 item 2): its slip row while stuck = 0, the constraint
    m R^2 (ball's acceleration relative to the race) = 0 while stuck = 1.  The race's friction, which the slip
    row holds, is then the constraint's multiplier (the required tangential force, which the families emit as
    stick_force); `stuck` is a parameter set by the event driver."""
    return (1 - stuck) * slip_row + stuck * mass * radius**2 * relative_acceleration


def race_reaction(mass: sp.Expr, position, rho: Coordinate, radius: sp.Expr, coordinates, t: sp.Symbol,
                  potential: sp.Expr = sp.S.Zero) -> sp.Expr:
    """N, the race's push on a ball towards the race's centre: the ball's `position` is written with a radial
    coordinate rho in place of the race radius; Lagrange's equation (2.1) for rho, with the race constraint
    rho = radius carried by its multiplier (the generalised force -N), is evaluated on the race (rho = radius,
    rho' = rho'' = 0).  `coordinates`: every other coordinate the position moves with (driven or free), whose
    rates and accelerations N holds; `potential` the ball's potential energy (gravity), in the same terms."""
    velocity = [time_derivative(x, tuple(coordinates) + (rho,), t) for x in position]
    term = EnergyTerm("ball", T=mass * sum(v**2 for v in velocity) / 2, V=potential)
    radial = lagrange_equations((rho,), (term,), t, driven=tuple(coordinates))
    on_race = {rho.q: radius, rho.qd: sp.S.Zero, rho.qdd: sp.S.Zero}
    return -radial.residual(0).xreplace(on_race)  # residual = Q_rho = -N
