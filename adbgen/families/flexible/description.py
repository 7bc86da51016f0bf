"""What a flexible-rotor model says about itself (`core.description`): its modal coordinates are
translations (the balancer node's mode shapes are dimensionless, so q is in metres), the balls' angles,
the node's displacement as a measure, the balls' exchanges, and its forcing frequency omega (the model
is the fixed frame at constant speed: periodically forced; under a speed schedule none, and no steady state).

    B    the balanced state: the node at rest (q = 0) with the balls cancelling the unbalance,
         U + sum_i m_i R e^(i phi_i) = 0; for two equal balls phi = pi +- arccos(m_u eps / (2 m R)).  No modal
         force then acts (the node's forces cancel at every instant), so it is an equilibrium of the
         forced fixed-frame model for all t; given without gravity (w = 0) for two equal balls.
"""

from __future__ import annotations

import sympy as sp

from ...core.description import Candidate, ClosedForm, Description, SteadyState, ball_exchanges
from ...core.first_order import FirstOrderSystem
from .scene import FlexibleScene


def node_displacement(system: FirstOrderSystem, scene: FlexibleScene) -> sp.Expr:
    """|Phi q|: the balancer node's displacement from the bearing axis (the quantity a balancer reduces)."""
    p = {q.name: q.symbol for q in system.parameters}
    q = {c.name: c.q for c in system.coordinates}
    x = sum((p[f"Phi_x_{j + 1}"] * q[f"q_{j + 1}"] for j in range(scene.k) if f"Phi_x_{j + 1}" in p), sp.S.Zero)
    y = sum((p[f"Phi_y_{j + 1}"] * q[f"q_{j + 1}"] for j in range(scene.k) if f"Phi_y_{j + 1}" in p), sp.S.Zero)
    return sp.sqrt(x**2 + y**2)


def balanced_form(system: FirstOrderSystem) -> ClosedForm:
    p = {q.name: q.symbol for q in system.parameters}
    ratio = p["m_u"] * p["eps"] / (2 * p["m"] * p["R"])
    a = sp.acos(ratio)
    guards = (sp.Gt(p["m"], 0, evaluate=False), sp.Gt(p["R"], 0, evaluate=False), sp.Ge(1 - ratio**2, 0))
    return ClosedForm("B", (), (Candidate(guards, {"phi_1": sp.pi + a, "phi_2": sp.pi - a}),))


def describe(system: FirstOrderSystem, scene: FlexibleScene, parameter_sets: dict | None = None) -> Description:
    coords = [c.name for c in system.coordinates]
    roles = {c: "translation" if c.startswith("q_") else "ball_angle" for c in coords}
    units = {c: "m" if roles[c] == "translation" else "rad" for c in coords}
    balls = [c for c in coords if roles[c] == "ball_angle"]
    own = None if scene.equal_balls else {b: (f"m_{i + 1}", f"D_{i + 1}") for i, b in enumerate(balls)}
    forms, states = (), ()
    if scene.node_2 is None:
        exchanges = ball_exchanges(balls, own)
    else:  # balls exchange within their node only (the nodes differ in shape and race radius)
        first, second = balls[:scene.n], balls[scene.n:]
        exchanges = ball_exchanges(first, own, tag=" (node 1)") + ball_exchanges(second, own, tag=" (node 2)")
    constant = scene.speed.law == "constant"  # a schedule: explicit time, not periodic, no balanced state for all t
    if constant and scene.n == 2 and scene.equal_balls and not scene.gravity:
        p = {q.name: q.symbol for q in system.parameters}
        forms = (balanced_form(system),)
        states = (SteadyState("B", "balanced state: the balancer node at rest, phi = pi +- arccos(m_u eps/(2 m R)); "
                                   "exists where m_u eps <= 2 m R", "B", (),
                              sp.Le(p["m_u"] * p["eps"], 2 * p["m"] * p["R"])),)
    return Description(
        time_unit="s", units=units, roles=roles, angles=tuple(balls), amplitude=(coords[0], coords[1]),
        measures={"node": node_displacement(system, scene)}, forcing_frequency="omega" if constant else "",
        symmetries=exchanges, parameter_sets=dict(parameter_sets or {}),
        scales={"eccentricity": "eps", "speed": "omega"}, closed_forms=forms, steady_states=states)
