"""What a single-plane model with ball-race friction emits about it (issue 37, item 1): each ball's normal
force N_i and its switching function, the ball's angular velocity relative to the race phi_i'.

The normal force is `model.normal_forces` (Lagrange's equation of a radial coordinate released from the
race, its multiplier), written in the model's own coordinates: in a rotating frame through (2.23)-(2.24),
the spin by its law, and the accelerations X'', Y'' by the model's structured solve (so N_i is the
reaction along the solution, friction included).  They are measures of the self-description, rendered
through the intermediate form like every other output.
"""

from __future__ import annotations

import sympy as sp

from ...core import Coordinate, canonical_trig
from ...core.first_order import FirstOrderSystem
from ...core.frames import rotating_substitution
from .model import lagrangian, normal_forces, speed_law_substitution
from .scene import Scene
from .symbols import t


def normal_force_names(n: int) -> tuple[str, ...]:
    return tuple(f"normal_force_{i + 1}" for i in range(n))


def slip_rate_names(n: int) -> tuple[str, ...]:
    return tuple(f"slip_rate_{i + 1}" for i in range(n))


def normal_forces_in(scene: Scene, system: FirstOrderSystem) -> tuple[sp.Expr, ...]:
    """N_i in the coordinates, rates and parameters of `system` (a model of `scene`) and t: the
    accelerations replaced by the system's closed-form solve."""
    lag = lagrangian(scene)
    forces = normal_forces(lag)
    eom = system.solve.eom
    names = [c.name for c in eom.coordinates]
    law = speed_law_substitution(scene, lag.symbols)
    sub: dict = {}
    if "x" in names:  # a rotating frame at the constant spin speed (2.23)-(2.24)
        sub = rotating_substitution(lag.symbols.omega)[1]
    if scene.speed.law == "constant":
        sub |= law
    elif scene.speed.law in ("profile", "schedule"):
        sub |= dict(eom.driven_law)
    accelerations = dict(zip((c.qdd for c in eom.coordinates), system.solve.accelerations()))
    out = []
    for N in forces:
        N = N.xreplace(sub)
        if "x" in names:
            N = canonical_trig(N)
            if t in N.free_symbols:
                raise AssertionError("the normal force still depends on t in the rotating frame")
        out.append(N.xreplace(accelerations).xreplace(dict(eom.driven_law)))  # the solve keeps a run-up's inputs
    return tuple(out)


def measures(scene: Scene, system: FirstOrderSystem) -> dict[str, sp.Expr]:
    """{normal_force_i: N_i, slip_rate_i: phi_i'} of a friction scene's model ({} without friction)."""
    if not scene.friction:
        return {}
    out = dict(zip(normal_force_names(scene.n), normal_forces_in(scene, system)))
    rates = (Coordinate.make(f"phi_{i + 1}").qd for i in range(scene.n))
    return out | dict(zip(slip_rate_names(scene.n), rates))
