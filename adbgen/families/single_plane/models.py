"""The single-plane models offered for generation: the default set of `generated/`, a model for any n,
and the smallest exact model of any scene; with their start points (AUTO-07p) and reduction checks.

The default set (issue: code generation, item 3):

- ``thesis_rotating_n{2,3,4}``: the thesis' autonomous rotating-frame system (2.25)-(2.27) in first-
  order form (Appendix A), dimensionless parameters mu, Omega, zeta, beta, delta; AUTO starts from
  the balanced state (3.6) at the defaults (5.1) and continues it in Omega;
- ``single_plane_fixed_n{2,3,4}``: the fixed-frame equations (2.10), (2.11), (2.13) of a rotor on an
  anisotropic support (k_Y = 1.2 k_X, c_Y = 1.2 c_X) with gravity at constant speed, dimensional
  parameters; periodically forced, so it keeps explicit time (AUTO gets it autonomous through the
  oscillator (40), from an exact orbit at g = 0, in g and then in omega).

A scene given on the command line gets the smallest model that is exact for it (`smallest_model`),
with the checks of the family for its number of balls.
"""

from __future__ import annotations

import math
from dataclasses import replace

import sympy as sp

from ...core.model_spec import Check, Continuation, ModelSpec
from ...core.first_order import FirstOrderSystem
from . import description, friction
from . import steady_states as ss
from . import verify
from .model import derive
from .reductions import first_order, thesis_chain
from .scene import Scene
from .selection import smallest_model

FAMILY = "single-plane"


# the proportionate forms of checks that scale badly in n (`Check.scaled`), above FULL_CHECKS_MAX_N
SCALED = {"steady_states": "steady_states_numeric"}


def checks(*kinds: str, n: int) -> tuple[Check, ...]:
    """The family's reduction checks by name (functions of `verify` taking n), for n balls; above
    `verify.FULL_CHECKS_MAX_N` balls with their proportionate forms (`SCALED`) for `regenerate`."""
    def scaled(kind):
        if n <= verify.FULL_CHECKS_MAX_N or kind not in SCALED:
            return None
        return lambda fn=getattr(verify, SCALED[kind]): fn(n)
    return tuple(Check((FAMILY, kind, n), lambda fn=getattr(verify, kind): fn(n), scaled(kind)) for kind in kinds)


def balanced_start(system: FirstOrderSystem, n: int, state: str = "balanced",
                   **overrides: float) -> tuple[tuple[float, ...] | None, str, dict]:
    """The balanced state (3.6) (phi_3.. = pi, as in the thesis' ch. 4) at the defaults or `overrides`.

    For n = 1 no balanced state exists unless mu = delta: the coincident state 2+ (3.9) is used, as it
    is when `state` = "coincident".  `regenerate` checks that the start is a steady state of the
    generated right-hand side.
    """
    values = {p.name: p.default for p in system.parameters} | overrides
    numeric = None
    if state == "balanced" and n >= 2 and ss.balanced_exists(n, values["mu"], values["delta"]):
        # the thesis puts phi_3.. at pi; where that leaves phi_1,2 no solution (odd n), alternate pi, 0
        for free, how in (([sp.pi] * (n - 2), "phi_3.. = pi"),
                          ([sp.pi if k % 2 == 0 else sp.S.Zero for k in range(n - 2)], "phi_3.. = pi, 0, pi, ...")):
            try:
                numeric = ss.evaluate(ss.balanced(n, free), values)
                label = f"balanced state 1 (3.6), {how}" if n > 2 else "balanced state 1 (3.6)"
                break
            except ValueError:
                continue
    if numeric is None:
        try:
            numeric, label = ss.evaluate(ss.coincident(n, 1), values), "coincident state 2+ (3.9)"
        except ValueError:
            return None, "", {}
    positions = [numeric[s.name] for s in system.states[: len(system.coordinates)]]
    start = tuple(float(v) for v in positions) + (0.0,) * len(positions)
    if not all(math.isfinite(v) for v in start):
        return None, "", {}
    where = ", ".join(f"{k} = {v!r}" for k, v in sorted(overrides.items()))
    return start, f"{label} at the defaults" + (f" but {where}" if where else ""), overrides


def steady_continuation(parameter: str | tuple[str, ...], stop: tuple[float, float] | None = None):
    """Continue the start's steady state in `parameter` (the first of them the model has: the spin
    speed is Omega in the thesis' dimensionless form, omega in the dimensional one) towards 1 (the
    thesis' critical speeds lie below the defaults), flagging a start on the continuum of balanced
    states (n >= 3)."""
    def decide(system: FirstOrderSystem, start: tuple) -> Continuation:
        state, label, values = start
        names = [p.name for p in system.parameters]
        name = next(p for p in ((parameter,) if isinstance(parameter, str) else parameter) if p in names)
        value = values[names.index(name)]
        n = sum(1 for c in system.coordinates if c.name.startswith("phi_"))
        return Continuation(name, direction=-1 if value > 1 else 1, stop=stop,
                            continuum=n >= 3 and label.startswith("balanced"))
    return decide


def thesis_rotating(n: int) -> ModelSpec:
    return ModelSpec(
        f"thesis_rotating_n{n}",
        f"Single-plane balancer with {n} ball{'s' if n > 1 else ''}, rotating frame, dimensionless (thesis)",
        n, lambda: thesis_chain(n)["first_order"], lambda system: balanced_start(system, n), family=FAMILY,
        checks=checks("rotating", "appendix_a", "steady_states", n=n),
        continuation=steady_continuation("Omega", stop=(0.5, 6.0)), kind="thesis_rotating",
        describe=description.thesis_rotating)


def fixed_scene(n: int) -> Scene:
    return Scene.from_mapping({"n": n, "stiffness": [1.0e4, 1.2e4], "damping": [2.0, 2.4], "gravity": True})


def balanced_orbit_start(system: FirstOrderSystem, n: int) -> tuple:
    """A point of an exact periodic orbit of the fixed-frame model, for its oscillator extension.

    Without gravity, with the balls in a balanced state ((3.6) with delta/mu = M eps/(m R)) the
    rotor's centre stays at rest: no support force acts, anisotropic or not, and each ball keeps its
    place, so X = Y = 0, phi_i constant, all rates zero, osc = (sin, cos)(omega t) is a solution.
    AUTO-07p starts there (g = 0) and continues in g to the scene's value.
    """
    values = {p.name: p.default for p in system.parameters}
    ratio = {"mu": values["m"] / values["M"], "delta": values["eps"] / values["R"]}
    if n < 2 or not ss.balanced_exists(n, ratio["mu"], ratio["delta"]):
        return None, "", {}
    free = [sp.pi if k % 2 == 0 else sp.S.Zero for k in range(n - 2)]
    angles = ss.evaluate(ss.balanced(n, free), ratio)
    positions = [0.0 if s.name in ("X", "Y") else angles[s.name] for s in system.states[: len(system.coordinates)]]
    start = tuple(float(v) for v in positions) + (0.0,) * len(positions) + (0.0, 1.0)
    how = "" if n == 2 else ", phi_3.. = pi, 0, ..."
    return start, f"balanced periodic orbit (3.6){how} at g = 0, t = 0 (exact: rotor centre at rest)", {"g": 0.0}


def _supercritical_note(scene: Scene) -> str:
    kx, ky = scene.stiffness if isinstance(scene.stiffness, tuple) else (scene.stiffness,) * 2
    return (f"The rotor's natural frequencies sqrt(k_X/M) = {math.sqrt(kx / scene.rotor_mass):.1f}, "
            f"sqrt(k_Y/M) = {math.sqrt(ky / scene.rotor_mass):.1f} rad/s lie below that range:\n"
            "the rotor runs supercritical, as at the thesis' Omega = 4.")


def single_plane_fixed(n: int) -> ModelSpec:
    scene = fixed_scene(n)
    return ModelSpec(
        f"single_plane_fixed_n{n}",
        f"Single-plane balancer with {n} ball{'s' if n > 1 else ''}, fixed frame, anisotropic support, gravity",
        n, lambda: first_order(derive(scene)), orbit_start=lambda system: balanced_orbit_start(system, n),
        family=FAMILY, checks=checks("prescribed_speed", n=n),
        orbit_continuation=Continuation("g", second="omega", continuum=n >= 3, note=_supercritical_note(scene)),
        kind="single_plane_fixed",
        describe=lambda system: description.fixed_frame(system, {description.FIXED_SET: {
            p.name: p.default for p in system.parameters}}))


# the model kinds of the family, by n (`adbgen regenerate --n`) and the default set of generated/
KINDS = {"thesis_rotating": thesis_rotating, "single_plane_fixed": single_plane_fixed}


def default_set() -> list[ModelSpec]:
    return [kind(n) for kind in KINDS.values() for n in (2, 3, 4)]


def mass_balanced_angles(masses, M: float, eps: float, R: float) -> tuple[float, ...] | None:
    """Ball angles that cancel the rotor's imbalance, sum_i m_i R e^(i phi_i) = -M eps (the balanced
    state (3.6) weighted by the masses, for unequal balls); None where no such state exists.

    phi_3.. are set (pi, 0, pi, ...; all pi; all 0; or spread evenly) and phi_1,2 close the triangle
    (law of cosines); of these the one farthest from a collinear (degenerate) triangle is taken, so the
    family's tangent is regular there."""
    n = len(masses)
    if n < 2:
        return None
    m1, m2 = masses[0], masses[1]
    patterns = [[math.pi if k % 2 == 0 else 0.0 for k in range(n - 2)], [math.pi] * (n - 2), [0.0] * (n - 2)]
    if n >= 4:
        patterns.append([2 * math.pi * k / (n - 2) for k in range(n - 2)])
    best = None
    for free in patterns:
        c = complex(-M * eps / R) - sum(m * complex(math.cos(a), math.sin(a)) for m, a in zip(masses[2:], free))
        size = abs(c)
        margin = min(size - abs(m1 - m2), m1 + m2 - size) / (m1 + m2)
        if margin <= 1e-9 or (best is not None and margin <= best[0]):
            continue
        a = math.acos(max(-1.0, min(1.0, (size**2 + m1**2 - m2**2) / (2 * m1 * size))))
        b = math.atan2(m1 * math.sin(a), size - m1 * math.cos(a))
        theta = math.atan2(c.imag, c.real)
        best = (margin, (theta + a, theta - b, *free))
    if best is None:
        return None
    return tuple(math.remainder(x, 2 * math.pi) for x in best[1])


def _scene_balanced(system: FirstOrderSystem, scene: Scene, orbit: bool) -> tuple:
    """A scene's balanced start: the steady state (rotating frame) or the exact periodic orbit of the
    oscillator extension (fixed frame: rotor at rest, no support force, anisotropic or not; at g = 0,
    from where AUTO-07p continues in g to the scene's value)."""
    values = {p.name: p.default for p in system.parameters}
    masses = [values.get(f"m_{i + 1}", values.get("m")) for i in range(scene.n)]
    angles = mass_balanced_angles(masses, values["M"], values["eps"], values["R"])
    if angles is None:
        return None, "", {}
    coords = [c.name for c in system.coordinates]
    by_name = {f"phi_{i + 1}": a for i, a in enumerate(angles)}
    positions = [by_name.get(name, 0.0) for name in coords]
    start = tuple(float(v) for v in positions) + (0.0,) * len(positions) + ((0.0, 1.0) if orbit else ())
    how = "balanced state (3.6) weighted by the ball masses" + (", phi_3.. = pi, 0, ..." if scene.n > 2 else "")
    if not orbit:
        return start, how, {}
    at = {"g": 0.0} if "g" in values else {}
    return start, f"{how}: periodic orbit with the rotor at rest" + (" at g = 0" if at else ""), at


def for_scene(scene: Scene, name: str | None = None) -> ModelSpec:
    """The smallest exact model of a scene (`adbgen regenerate --scene`), with a start for AUTO-07p
    where one is known: the balanced state (rotating frame; for unequal balls weighted by the masses)
    or, for a fixed-frame scene at constant speed, the balanced periodic orbit of its oscillator
    extension (issue 24: forced scenes continue on the command line)."""
    selected = smallest_model(scene)
    name = name or f"scene_{selected.kind.replace('-', '_')}_n{scene.n}"
    rotating = selected.kind == "rotating-frame"
    dimensional = selected.kind == "rotating-frame-dimensional"
    forced = selected.kind == "fixed-frame" and scene.speed.law == "constant"
    if scene.friction:
        # the balanced states are stuck states (every ball at rest on the race): Coulomb's law in slip
        # chatters there and the stick phase (issue 37 item 2) runs only on the hybrid engine, so no start is offered
        start = lambda system: (None, "")  # noqa: E731
    elif rotating:
        start = lambda system: balanced_start(system, scene.n)  # noqa: E731
    elif dimensional:
        start = lambda system: _scene_balanced(system, scene, orbit=False)  # noqa: E731
    else:
        start = lambda system: (None, "")  # noqa: E731
    kinds = ("fixed_frame", "prescribed_speed") + (("rotating", "appendix_a") if rotating else ())
    orbit = None
    if forced:
        second = "omega" if scene.gravity else ""
        orbit = Continuation("g" if scene.gravity else "omega", second=second, continuum=scene.n >= 3,
                             note=_supercritical_note(scene))
    if selected.kind == "rotating-frame":
        describe = lambda system: description.describe(  # noqa: E731
            system, rotating=True, dimensionless=True, thesis_states=True, forcing="")
    elif selected.kind == "rotating-frame-dimensional":
        describe = lambda system: description.describe(system, rotating=True, dimensionless=False, forcing="")  # noqa: E731
    else:
        describe = description.fixed_frame
    if scene.friction:
        # the normal forces and slip rates as measures; no closed-form steady state and no periodic orbit
        # for AUTO-07p: they are stuck states, where Coulomb's law in slip has no derivative (item 2)
        forced, orbit, plain = False, None, describe

        def describe(system):
            d = plain(system)
            d = replace(d, closed_forms=(), steady_states=(), measures={**d.measures, **friction.measures(scene, system)})
            # the rotating frame with equal balls: the balanced state of its frictionless limit (mu_r = 0), where
            # `adbgen design --objective residual` finds the design's margins
            return description.frictionless_balanced(system, d) if dimensional else d
        kinds += ("friction_zero_limit", "normal_force")
    return ModelSpec(name, f"Single-plane balancer with {scene.n} balls: {selected.reason}", scene.n,
                     lambda: selected.system, start, family=FAMILY, checks=checks(*kinds, n=scene.n),
                     continuation=steady_continuation(("Omega", "omega")) if rotating or dimensional else None,
                     kind="scene", describe=describe,
                     orbit_start=(lambda system: _scene_balanced(system, scene, orbit=True)) if forced else None,
                     orbit_continuation=orbit)
