"""The flexible-rotor models offered for generation, with start points and checks.

One kind, ``flexible_fixed``: the fixed frame (under a speed schedule, explicit time without a start or
AUTO-07p files; otherwise) at constant speed with the balls' angles taken from the spin
(the model's own coordinates: a ball sits at psi + phi_i), periodically forced at omega; its balanced
state (the node at rest) is an exact periodic orbit, from where AUTO-07p continues the oscillator
extension in omega.  The default set's model is the two-mode Jeffcott rotor of `verify` (one node, identity
mode shapes), proven equal to the single-plane fixed-frame model.
"""

from __future__ import annotations

import math

from ...core.first_order import first_order
from ...core.model_spec import Check, Continuation, ModelSpec
from ..single_plane.models import mass_balanced_angles
from . import description, verify
from .model import derive
from .scene import FlexibleScene

FAMILY = "flexible"


def core(scene: FlexibleScene) -> tuple[str, ...]:
    """The Schur core: the k modal coordinates (the balls are back-substituted, thesis Appendix A)."""
    return tuple(f"q_{j + 1}" for j in range(scene.k))


def self_cancelling_angles(masses) -> tuple[float, ...] | None:
    """Angles with sum_i m_i e^(i phi_i) = 0 (a second node's balls: no unbalance there): equal balls spread
    evenly, else `mass_balanced_angles` with no imbalance to cancel; None where none exists."""
    if len(set(masses)) == 1 and len(masses) >= 2:
        return tuple(2 * math.pi * i / len(masses) for i in range(len(masses)))
    return mass_balanced_angles(masses, 0.0, 0.0, 1.0)


def balanced_orbit(scene: FlexibleScene):
    """The node at rest with the balls cancelling U (weighted by their masses), oscillator at (sin, cos)(0);
    exact without gravity (with gravity the node sags and the state is not known in closed form).  A second
    node's balls cancel each other (`self_cancelling_angles`): no force reaches either node, so the state is
    exact with two nodes as well."""
    def start(system):
        values = {p.name: p.default for p in system.parameters}
        if scene.gravity:
            return None, "", {}
        masses = [values.get(f"m_{i + 1}", values.get("m")) for i in range(scene.balls)]
        angles = mass_balanced_angles(masses[:scene.n], values["m_u"], values["eps"], values["R"])
        if angles is not None and scene.node_2 is not None:
            second = self_cancelling_angles(masses[scene.n:])
            angles = None if second is None else tuple(angles) + tuple(second)
        if angles is None:
            return None, "", {}
        by_name = {f"phi_{i + 1}": a for i, a in enumerate(angles)}
        positions = [by_name.get(c.name, 0.0) for c in system.coordinates]
        return (tuple(float(v) for v in positions) + (0.0,) * len(positions) + (0.0, 1.0),
                "balanced state: the node at rest, sum m_i R e^(i phi_i) = -m_u eps (exact periodic orbit, t = 0)", {})
    return start


def ball_slots(scene: FlexibleScene):
    """Each ball's own parameters for the loop form (`codegen.passes.ball_split`): m_i, D_i for unequal balls, none for
    equal ones (they share m, D).  Given, not found by name: the mode shapes' Phi_x_1, Phi_x_2, ... and the
    matrices' entries are indexed like ball parameters but belong to the rotor."""
    def slots(system) -> list[dict]:
        if scene.equal_balls:
            return [{} for _ in range(scene.n)]
        names = {p.name: p.symbol for p in system.parameters}
        out = [{"m": names[f"m_{i + 1}"], "D": names[f"D_{i + 1}"]} for i in range(scene.balls)]
        if scene.node_2 is not None:  # each ball's race radius and node shape (`symbols`: one pattern for both)
            shapes = sorted(n[len("Phi_"):] for n in names if n.startswith("Phi_"))
            for i, node in enumerate(scene.ball_node()):
                prefix, radius = ("Phi", "R") if node == 0 else ("Phi2", "R_2")
                out[i] |= {"R": names[radius], **{f"Phi_{e}": names[f"{prefix}_{e}"] for e in shapes}}
        return out
    return slots


def for_scene(scene: FlexibleScene, name: str | None = None) -> ModelSpec:
    checks = (Check((FAMILY, "single_plane_limit"), verify.single_plane_limit_check),)
    if scene.node_2 is not None:
        checks += (Check((FAMILY, "two_plane_limit"), verify.two_plane_limit_check),)
    if scene.speed.law == "constant":
        title, orbit, continuation = "fixed frame", balanced_orbit(scene), Continuation("omega", direction=-1)
    else:  # explicit time without a period: no periodic orbit for AUTO-07p
        title, orbit, continuation = "fixed frame, speed schedule", None, None
        checks += (Check((FAMILY, "prescribed_speed"), verify.prescribed_speed_check),)
    law = "" if scene.speed.law == "constant" else "schedule_"
    nodes = "one node" if scene.node_2 is None else "two nodes"
    return ModelSpec(
        name or f"scene_flexible_{law}k{scene.k}_n{scene.balls}",
        f"Flexible rotor, {scene.k} modes ({scene.modal.reduction}), {scene.balls} balls at {nodes}, {title}",
        scene.balls, lambda: first_order(derive(scene), core(scene)), orbit_start=orbit, family=FAMILY,
        checks=checks, orbit_continuation=continuation, kind="flexible_fixed",
        balls=ball_slots(scene),
        describe=lambda system: description.describe(system, scene, {"scene": {p.name: p.default
                                                                                for p in system.parameters}}))


def flexible_fixed(n: int) -> ModelSpec:
    """The Jeffcott rotor as a flexible model (one node, two identity modes) with n balls."""
    from ..single_plane.scene import Scene

    return for_scene(verify.jeffcott_scene(Scene(n=n)), f"flexible_jeffcott_n{n}")


KINDS = {"flexible_fixed": flexible_fixed}


def default_set() -> list[ModelSpec]:
    return [flexible_fixed(2)]
