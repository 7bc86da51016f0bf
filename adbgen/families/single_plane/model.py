"""The single-plane n-ball balancer by Lagrange's equations: thesis (2.2)-(2.13).

Kinematics (2.3)-(2.4) give positions; velocities (2.5)-(2.6) come from the chain-rule time
derivative; the energies (2.7)-(2.8), the Rayleigh function and the torque (2.9) go to the
term-by-term Lagrange engine.  Nothing of (2.10)-(2.13) is transcribed here: those printed equations
live in `adbgen.references.thesis` and are compared with the result in the tests.

Note on (2.7): for T = I_z psi'^2/2 + M |r_OG'|^2/2 to be the kinetic energy of the disc, I_z is the
moment of inertia about the centre of mass W (the text says "about C"); the derivation follows (2.7)
as printed, so the equation for psi carries I_z + M eps^2, as (2.12) does.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import sympy as sp

from ...core import Coordinate, EnergyTerm, EquationsOfMotion, lagrange_equations, speed_schedule, time_derivative
from ...core.friction import race_reaction, slip_direction, stick_row
from ...errors import SceneError
from .scene import Scene, profile_expression
from .symbols import DimensionalSymbols, t


@dataclass(frozen=True)
class SinglePlaneLagrangian:
    """Everything Lagrange's equations need, before they are formed."""

    scene: Scene
    symbols: DimensionalSymbols
    coordinates: tuple[Coordinate, ...]  # X, Y, [psi], phi_1..phi_n
    driven: tuple[Coordinate, ...]  # (psi,) when the speed is prescribed
    terms: tuple[EnergyTerm, ...]  # rotor, ball_1..ball_n
    forces: dict[str, sp.Expr]
    positions: dict[str, tuple[sp.Expr, sp.Expr]]  # body -> (x, y) in the fixed frame

    @property
    def all_coordinates(self) -> tuple[Coordinate, ...]:
        return self.coordinates + self.driven

    def lagrangian(self) -> sp.Expr:
        return sum((term.T - term.V for term in self.terms), sp.S.Zero)

    def rayleigh(self) -> sp.Expr:
        return sum((term.F for term in self.terms), sp.S.Zero)


def lagrangian(scene: Scene) -> SinglePlaneLagrangian:
    """Coordinates (2.2), positions (2.3)-(2.4), energies (2.7)-(2.8), dissipation and torque (2.9)."""
    s = DimensionalSymbols.for_scene(scene)
    X, Y, psi = Coordinate.make("X"), Coordinate.make("Y"), Coordinate.make("psi")
    phis = tuple(Coordinate.make(f"phi_{i + 1}") for i in range(scene.n))
    spin_is_free = scene.speed.law == "torque"
    coordinates = (X, Y) + ((psi,) if spin_is_free else ()) + phis
    driven = () if spin_is_free else (psi,)
    everything = coordinates + driven

    def kinetic(mass, x, y):
        vx, vy = (time_derivative(e, everything, t) for e in (x, y))  # (2.5), (2.6)
        return mass * (vx**2 + vy**2) / 2

    positions = {"rotor": (X.q + s.eps * sp.cos(psi.q), Y.q + s.eps * sp.sin(psi.q))}  # (2.3)
    rotor = EnergyTerm(
        "rotor",
        T=s.I_z * psi.qd**2 / 2 + kinetic(s.M, *positions["rotor"]),
        V=s.kX * X.q**2 / 2 + s.kY * Y.q**2 / 2 + s.M * s.g * positions["rotor"][1],
        F=s.cX * X.qd**2 / 2 + s.cY * Y.qd**2 / 2,
    )
    terms = [rotor]
    for i, phi in enumerate(phis):
        pos = (X.q + s.R * sp.cos(psi.q + phi.q), Y.q + s.R * sp.sin(psi.q + phi.q))  # (2.4)
        positions[f"ball_{i + 1}"] = pos
        terms.append(EnergyTerm(f"ball_{i + 1}", T=kinetic(s.m[i], *pos), V=s.m[i] * s.g * pos[1],
                                F=s.D[i] * phi.qd**2 / 2))
    forces = {"psi": s.tau0 - s.kappa * psi.qd} if spin_is_free else {}
    return SinglePlaneLagrangian(scene, s, coordinates, driven, tuple(terms), forces, positions)


def normal_forces(lag: SinglePlaneLagrangian) -> tuple[sp.Expr, ...]:
    """N_i, the race's push on ball i towards the rotor's centre C (positive while the ball presses on the
    race's outer wall), from the same Lagrangian: ball i is given a radial coordinate rho_i (its position
    (2.4) with rho_i in place of R), Lagrange's equation (2.1) for rho_i carries the race constraint
    rho_i = R through its multiplier, the generalised force -N_i, and is evaluated on the race (rho_i = R,
    rho_i' = rho_i'' = 0).  So N_i = m_i (R (psi' + phi_i')^2 - X'' cos(psi + phi_i) - Y'' sin(psi + phi_i)
    - g sin(psi + phi_i)) appears without being written here: centrifugal, Coriolis (none radially on a
    race of fixed radius), the rotor's acceleration and gravity, in the model's coordinates, rates and
    accelerations (X'', Y'' are the model's; the spin's are its inputs or coordinate)."""
    s = lag.symbols
    X, Y, psi = Coordinate.make("X"), Coordinate.make("Y"), Coordinate.make("psi")
    out = []
    for i in range(lag.scene.n):
        phi, rho = Coordinate.make(f"phi_{i + 1}"), Coordinate.make(f"rho_{i + 1}")
        pos = (X.q + rho.q * sp.cos(psi.q + phi.q), Y.q + rho.q * sp.sin(psi.q + phi.q))
        out.append(sp.expand(race_reaction(s.m[i], pos, rho, s.R, lag.all_coordinates, t, s.m[i] * s.g * pos[1])))
    return tuple(out)


def friction_forces(lag: SinglePlaneLagrangian) -> dict[str, sp.Expr]:
    """{phi_i: Q_i}: the generalised force of the race's friction on ball i while it slips, Q_i =
    -R mu_r_i N_i sign(phi_i') (a tangential force mu_r_i N_i against the ball's motion relative to the
    race, at the race radius R; with stiction slip_dir_i, the ball's mode, in place of sign(phi_i')).  The
    pair of forces on ball and race does virtual work only through phi_i (the contact points move together
    with X, Y, psi), so no other row gets a term.  N_i is taken signed (`normal_forces`): the model holds
    while the ball presses on the outer wall (N_i > 0), which the emitted normal force shows."""
    s = lag.symbols
    normal = normal_forces(lag)
    # With stiction the direction is the ball's mode slip_dir_i (set by the event driver), not sign(phi_i'):
    # each mode's vector field is then smooth and continues past phi_i' = 0, so the driver locates the stop
    # on it (event-driven Coulomb friction as Otter, Elmqvist and Mattsson 1999 give it for the Modelica
    # library: forward slip, backward slip and stick each a smooth system).  sign(phi_i') in the field would
    # flip inside a step, the numerical solution would chatter at phi_i' ~ 0 without crossing it at a step's
    # end, and the step size would shrink without bound (the stall of docs/friction.md).
    direction = s.slip_dir or tuple(slip_direction(Coordinate.make(f"phi_{i + 1}").qd)
                                    for i in range(lag.scene.n))
    return {f"phi_{i + 1}": -s.R * s.mu_r[i] * direction[i] * normal[i] for i in range(lag.scene.n)}


def stick_rows(lag: SinglePlaneLagrangian, residuals: list[sp.Expr], coordinates) -> list[sp.Expr]:
    """The hybrid system's rows (issue 37 item 2): ball i's row is its slip row while stuck_i = 0 and the
    constraint m_i R^2 phi_i'' = 0 while stuck_i = 1 (the race's friction, the only force that row has
    beyond the frictionless ones, is then whatever holds phi_i' = 0: a Lagrange multiplier, given by
    `stick_forces`).  No other row holds the friction force, so the constrained system is exactly this."""
    s = lag.symbols
    names = [c.name for c in coordinates]
    out = list(residuals)
    for i in range(lag.scene.n):
        k = names.index(f"phi_{i + 1}")
        out[k] = stick_row(residuals[k], s.stuck[i], s.m[i], s.R, coordinates[k].qdd)
    return out


def stick_forces(lag: SinglePlaneLagrangian, frictionless: EquationsOfMotion) -> tuple[sp.Expr, ...]:
    """F_i, the tangential force the race must exert on ball i (positive along increasing phi_i) for the
    accelerations in it to hold: the frictionless model's phi_i row M q'' - f (Lagrange's equation (2.1)
    without the friction) divided by R, since with friction that row reads M q'' - f = Q_i = R F_i.
    Evaluated at the constrained accelerations (phi_i'' = 0) it is the stuck ball's required force, which
    holds while |F_i| <= mu_s N_i (the stiction cone); fixed-frame coordinates."""
    return tuple(frictionless.residual(frictionless.index(f"phi_{i + 1}")) / lag.symbols.R
                 for i in range(lag.scene.n))


def speed_law_substitution(scene: Scene, symbols: DimensionalSymbols) -> dict[sp.Symbol, sp.Expr]:
    """psi, psi', psi'' as functions of t for a prescribed speed (2.14), or {} for torque drive."""
    psi = Coordinate.make("psi")
    law = scene.speed.law
    if law == "constant":
        return {psi.q: symbols.omega * t, psi.qd: symbols.omega, psi.qdd: sp.S.Zero}
    if law == "schedule":  # ramp, hold, temporary speed reduction (`core.speed_schedule`)
        angle, Om, acc = speed_schedule.law(t)
        return {psi.q: angle, psi.qd: Om, psi.qdd: acc}
    if law == "profile":
        Om = profile_expression(str(scene.speed.omega))
        tau = sp.Dummy("tau", real=True)
        angle = sp.integrate(Om.subs(t, tau), (tau, 0, t))
        if angle.has(sp.Integral):
            raise SceneError("speed.omega", "the profile has no closed-form angle; give a simpler Omega(t)")
        return {psi.q: angle, psi.qd: Om, psi.qdd: sp.diff(Om, t)}
    return {}


@lru_cache(maxsize=64)
def derive(scene: Scene) -> EquationsOfMotion:
    """Fixed-frame equations of motion M q'' = f of the scene, thesis (2.10)-(2.13).

    With a constant speed the spin is substituted (psi = omega t), giving explicitly time-dependent
    equations for X, Y, phi_i.  With a profile the spin psi, psi', psi'' stay as input symbols and
    ``driven_law`` gives them as functions of t.  With a torque the spin is a coordinate.
    """
    lag = lagrangian(scene)
    reference = "thesis (2.10)-(2.13)" if scene.speed.law == "torque" else "thesis (2.10), (2.11), (2.13)"
    forces = dict(lag.forces)
    if scene.friction:
        forces |= friction_forces(lag)
        reference += " with ball-race friction in slip (issue 37)"
    if scene.stiction:
        reference += " and stick"
    eom = lagrange_equations(lag.coordinates, lag.terms, t, forces=forces, driven=lag.driven,
                             parameters=lag.symbols.parameters, reference=reference)
    if scene.friction:  # the friction rows hold X'', Y'' (in N_i): moved into the mass matrix (rows only)
        rows = eom.residuals()
        if scene.stiction:
            rows = stick_rows(lag, rows, eom.coordinates)
        eom = EquationsOfMotion.from_residuals(rows, eom.coordinates, t, driven=eom.driven,
                                               parameters=eom.parameters, reference=eom.reference)
    law = speed_law_substitution(scene, lag.symbols)
    if scene.speed.law == "constant":
        eom = replace(eom.map(lambda e: sp.expand(e.xreplace(law))), driven=())
    elif scene.speed.law in ("profile", "schedule"):
        eom = replace(eom, driven_law=law)
    return eom
