"""The flexible-rotor balancer by Lagrange's equations (thesis (2.1)), in modal coordinates.

Coordinates: the k modal coordinates q of the reduced rotor (`scene.Modal`) and the balls' angles phi_i in
the race.  The spin is prescribed, psi = omega t (thesis (2.14)).  Positions:

- the balancer node (race centre) at Phi q (Phi: the node's 2 x k translational mode shapes);
- ball i at Phi q + R (cos(psi + phi_i), sin(psi + phi_i)) (thesis (2.4) with the node for (X, Y)).

Energies: the rotor's T = q'^T M_q q' / 2 + U psi' (Phi q') . (-sin psi, cos psi) (the unbalance U = m_u eps
at the node: the cross term of m_u |Phi q' + e psi' (-sin psi, cos psi)|^2 / 2 not already in M_q; its
Lagrange term is the forcing U omega^2 Phi^T (cos psi, sin psi)), V = q^T K_q q / 2 + g w . q (w the
modal gravity load), Rayleigh F = q'^T C_q q' / 2; the gyroscopic force Q = -omega G_q q' (G_q skew: no
work).  Balls as in thesis (2.7)-(2.9).  With k = 2, Phi = I, M_q = M I, w = (0, M), m_u = M this is the
single-plane fixed-frame model (2.10), (2.11), (2.13) with X, Y = q_1, q_2 (checked in `verify`).

A second balancer node (`scene.BalancerNode`) adds balls at Phi_2 q + R_2 (cos(psi + phi_i), sin(psi + phi_i)):
the balls enter through their race centres' translation only (no tilt of the race), which is what the
two-plane model keeps of a ball (paper section 2.2; `verify.two_plane_limit`).
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import sympy as sp

from ...core import Coordinate, EnergyTerm, EquationsOfMotion, lagrange_equations, speed_schedule, time_derivative
from .scene import FlexibleScene
from .symbols import FlexibleSymbols, t


def coordinates(scene: FlexibleScene) -> tuple[tuple[Coordinate, ...], tuple[Coordinate, ...], Coordinate]:
    qs = tuple(Coordinate.make(f"q_{j + 1}") for j in range(scene.k))
    phis = tuple(Coordinate.make(f"phi_{i + 1}") for i in range(scene.balls))
    return qs, phis, Coordinate.make("psi")


def energy_terms(scene: FlexibleScene, s: FlexibleSymbols) -> tuple[tuple[EnergyTerm, ...], dict[str, sp.Expr]]:
    """The rotor's and each ball's T, V, F, and the gyroscopic generalised forces (module docstring)."""
    qs, phis, psi = coordinates(scene)
    everything = qs + phis + (psi,)
    q = sp.Matrix([c.q for c in qs])
    qd = sp.Matrix([c.qd for c in qs])
    nodes = [shape * q for shape in s.shapes]  # each balancer node's (x, y)
    node_rate = s.Phi * qd
    spin_dir = sp.Matrix([-sp.sin(psi.q), sp.cos(psi.q)])
    rotor = EnergyTerm(
        "rotor",
        T=(qd.T * s.M * qd)[0] / 2 + s.U * psi.qd * (node_rate.T * spin_dir)[0],
        V=(q.T * s.K * q)[0] / 2 + s.g * (s.w.T * q)[0],
        F=(qd.T * s.C * qd)[0] / 2,
    )
    terms = [rotor]
    for i, phi in enumerate(phis):
        node, R = nodes[s.ball_node[i]], s.radii[s.ball_node[i]]
        pos = (node[0] + R * sp.cos(psi.q + phi.q), node[1] + R * sp.sin(psi.q + phi.q))
        vx, vy = (time_derivative(e, everything, t) for e in pos)
        terms.append(EnergyTerm(f"ball_{i + 1}", T=s.m[i] * (vx**2 + vy**2) / 2, V=s.m[i] * s.g * pos[1],
                                F=s.D[i] * phi.qd**2 / 2))
    gyro = -psi.qd * (s.G * qd)  # ROSS's G times the current spin speed: omega at constant speed
    forces = {c.name: gyro[j] for j, c in enumerate(qs) if gyro[j] != 0}
    return tuple(terms), forces


def speed_law(scene: FlexibleScene, s: FlexibleSymbols, wrong: bool = False) -> dict[sp.Symbol, sp.Expr]:
    """psi, psi', psi'' in t (thesis (2.14)): omega t at constant speed; the schedule's exact angle, speed and
    acceleration (`core.speed_schedule.law`, its ramp from omega_start).  wrong: psi'' with its sign flipped
    (the negative control of `verify.prescribed_speed`)."""
    psi = Coordinate.make("psi")
    if scene.speed.law == "constant":
        law = {psi.q: s.omega * t, psi.qd: s.omega, psi.qdd: sp.S.Zero}
    else:
        angle, speed, acceleration = speed_schedule.law(t, start=s.omega_start)
        law = {psi.q: angle, psi.qd: speed, psi.qdd: acceleration}
    if wrong:
        law[psi.qdd] = -law[psi.qdd]
    return law


@lru_cache(maxsize=32)
def derive(scene: FlexibleScene, wrong: bool = False) -> EquationsOfMotion:
    """Fixed-frame equations M(q) x'' = f for x = (q_1..q_k, phi_1..phi_n).  At constant speed psi = omega t
    is substituted; under a schedule psi, psi', psi'' stay inputs with ``driven_law`` giving them in t, so the
    angular-acceleration terms (the balls' -m R^2 psi'', the unbalance's U psi'' Phi^T (-sin psi, cos psi))
    come from Lagrange's equations with psi a driven coordinate.  wrong: `speed_law`'s negative control."""
    s = FlexibleSymbols.for_scene(scene)
    qs, phis, psi = coordinates(scene)
    terms, forces = energy_terms(scene, s)
    eom = lagrange_equations(qs + phis, terms, t, forces=forces, driven=(psi,), parameters=s.parameters,
                             reference="flexible rotor, modal truncation; Lagrange thesis (2.1), balls (2.4), (2.7)-(2.9)")
    law = speed_law(scene, s, wrong)
    if scene.speed.law == "constant":
        return replace(eom.map(lambda e: sp.expand(e.xreplace(law))), driven=())
    return replace(eom, driven_law=law)
