"""Which models are generated: the default set of `generated/`, and a model for any scene.

The default set (issue: code generation, item 3):

- ``thesis_rotating_n{2,3,4}``: the thesis' autonomous rotating-frame system (2.25)-(2.27) in first-
  order form (Appendix A), dimensionless parameters mu, Omega, zeta, beta, delta; AUTO starts from
  the balanced state (3.6) at the defaults (5.1);
- ``single_plane_fixed_n{2,3,4}``: the fixed-frame equations (2.10), (2.11), (2.13) of a rotor on an
  anisotropic support (k_Y = 1.2 k_X, c_Y = 1.2 c_X) with gravity at constant speed, dimensional
  parameters; periodically forced, so it keeps explicit time (AUTO gets it autonomous through the
  oscillator (u, v) = (sin omega t, cos omega t), see templates/auto).

A scene given on the command line gets the smallest model that is exact for it (`smallest_model`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from ..scene import Scene
from ..single_plane import steady_states as ss
from ..single_plane.model import derive
from ..single_plane.reductions import FirstOrderSystem, first_order, thesis_chain
from ..single_plane.selection import smallest_model
from .ir import ModelIR, build


@dataclass(frozen=True)
class ModelSpec:
    """A named model: how to derive its first-order system, and its AUTO start point."""

    name: str
    title: str
    n: int
    system: Callable[[], FirstOrderSystem]
    # system -> (state, label) at the defaults, or (state, label, {parameter: value}) elsewhere
    start: Callable[[FirstOrderSystem], tuple] = lambda system: (None, "")
    # periodically forced models: the start (a point on a periodic orbit) of the oscillator extension
    orbit_start: Callable[[FirstOrderSystem], tuple] | None = None

    def build(self) -> ModelIR:
        system = self.system()
        extension = None
        orbit = _start_values(system, self.orbit_start(system)) if self.orbit_start is not None else (None,)
        if orbit[0] is not None:  # (no exact orbit known, e.g. one ball: no extension)
            start, label, values = orbit
            extension = build(self.name, system, title=self.title + ", autonomous extension (oscillator)",
                              n_balls=self.n, start=start, start_label=label, start_parameters=values,
                              oscillator=True)
        start, label, values = _start_values(system, self.start(system))
        return build(self.name, system, title=self.title, n_balls=self.n, start=start, start_label=label,
                     start_parameters=values, autonomous_extension=extension)


def _start_values(system: FirstOrderSystem, start: tuple) -> tuple:
    state, label, *where = start
    values = [p.default for p in system.parameters]
    if where:
        names = [p.name for p in system.parameters]
        for key, value in where[0].items():
            values[names.index(key)] = float(value)
    return state, label, values


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


def thesis_rotating(n: int) -> ModelSpec:
    return ModelSpec(
        f"thesis_rotating_n{n}",
        f"Single-plane balancer with {n} ball{'s' if n > 1 else ''}, rotating frame, dimensionless (thesis)",
        n, lambda: thesis_chain(n)["first_order"], lambda system: balanced_start(system, n))


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


def single_plane_fixed(n: int) -> ModelSpec:
    return ModelSpec(
        f"single_plane_fixed_n{n}",
        f"Single-plane balancer with {n} ball{'s' if n > 1 else ''}, fixed frame, anisotropic support, gravity",
        n, lambda: first_order(derive(fixed_scene(n))), orbit_start=lambda system: balanced_orbit_start(system, n))


FAMILIES = {"thesis_rotating": thesis_rotating, "single_plane_fixed": single_plane_fixed}


def default_set() -> list[ModelSpec]:
    return [family(n) for family in FAMILIES.values() for n in (2, 3, 4)]


def for_scene(scene: Scene, name: str | None = None) -> ModelSpec:
    """The smallest exact model of a scene (`adbgen regenerate --scene`)."""
    selected = smallest_model(scene)
    name = name or f"scene_{selected.kind.replace('-', '_')}_n{scene.n}"
    start = (lambda system: balanced_start(system, scene.n)) if selected.kind == "rotating-frame" else \
        (lambda system: (None, ""))
    return ModelSpec(name, f"Single-plane balancer with {scene.n} balls: {selected.reason}", scene.n,
                     lambda: selected.system, start)


def lowering_error(ir: ModelIR, system: FirstOrderSystem, samples: int = 20, seed: int = 0) -> float:
    """Largest relative difference between the rhs program and a dense solve at random points.

    The reference lambdifies the whole mass matrix and forcing and solves M q'' = f with numpy:
    independent of the structured lowering (no Schur complement), and valid for any core size.
    """
    from .interpret import compile_program

    rng = np.random.default_rng(seed)
    eom = system.solve.eom
    law = dict(eom.driven_law)
    args = (eom.time, list(system.states), [p.symbol for p in system.parameters])
    mass = sp.lambdify(args, eom.mass_matrix().xreplace(law), modules="numpy")
    forcing = sp.lambdify(args, [sp.sympify(e).xreplace(law) for e in eom.forcing], modules="numpy")
    program = compile_program(ir, "rhs")
    N = eom.size
    worst = 0.0
    defaults = np.array([p.default for p in system.parameters])
    for _ in range(samples):
        y = rng.uniform(-1, 1, ir.n_states)
        y[: ir.n_coordinates] *= 0.1
        p = defaults * rng.uniform(0.5, 1.5, defaults.size)
        time = float(rng.uniform(0, 10))
        acc = np.linalg.solve(np.array(mass(time, y, p), dtype=float), np.array(forcing(time, y, p), dtype=float))
        a, b = np.array(program(time, y, p)), np.concatenate([y[N:], acc])
        worst = max(worst, float(np.max(np.abs(a - b)) / max(1e-300, float(np.max(np.abs(b))))))
    return worst
