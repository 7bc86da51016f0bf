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
from ...core import lagrange_equations
from .model import lagrangian, normal_forces, speed_law_substitution, stick_forces
from .scene import Scene
from .symbols import DimensionalSymbols, t


def normal_force_names(n: int) -> tuple[str, ...]:
    return tuple(f"normal_force_{i + 1}" for i in range(n))


def slip_rate_names(n: int) -> tuple[str, ...]:
    return tuple(f"slip_rate_{i + 1}" for i in range(n))


def stick_force_names(n: int) -> tuple[str, ...]:
    return tuple(f"stick_force_{i + 1}" for i in range(n))


def stick_margin_names(n: int) -> tuple[str, ...]:
    return tuple(f"stick_margin_{i + 1}" for i in range(n))


def normal_forces_in(scene: Scene, system: FirstOrderSystem) -> tuple[sp.Expr, ...]:
    """N_i in the coordinates, rates and parameters of `system` (a model of `scene`) and t: the
    accelerations replaced by the system's closed-form solve."""
    return _in_model(scene, system, normal_forces(lagrangian(scene)))


def stick_forces_in(scene: Scene, system: FirstOrderSystem) -> tuple[sp.Expr, ...]:
    """F_i (`model.stick_forces`: the frictionless phi_i row of Lagrange's equations over R) in the model's
    coordinates, its accelerations by the model's solve: while ball i is stuck (stuck_i = 1, phi_i'' = 0 in
    the solve) the tangential force the race must exert to hold it."""
    lag = lagrangian(scene)
    frictionless = lagrange_equations(lag.coordinates, lag.terms, t, forces=lag.forces, driven=lag.driven,
                                      parameters=lag.symbols.parameters)
    # meaningful in the stuck mode only (the driver evaluates it with stuck_i = 1): phi_i'' = 0 written in
    forces = [F.xreplace({Coordinate.make(f"phi_{i + 1}").qdd: sp.S.Zero})
              for i, F in enumerate(stick_forces(lag, frictionless))]
    return _in_model(scene, system, forces)


def _in_model(scene: Scene, system: FirstOrderSystem, forces) -> tuple[sp.Expr, ...]:
    """Fixed-frame expressions in X, Y, psi, phi_i, their rates and accelerations, written in the coordinates
    of `system`: its frame, its speed law, its accelerations from its solve."""
    lag = lagrangian(scene)
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
    out, accelerations = [], None
    for N in forces:
        N = N.xreplace(sub)
        if "x" in names:
            N = canonical_trig(N)
            if t in N.free_symbols:
                raise AssertionError("a force still depends on t in the rotating frame")
        if accelerations is None and any(c.qdd in N.free_symbols for c in eom.coordinates):
            accelerations = dict(zip((c.qdd for c in eom.coordinates), system.solve.accelerations(expand=False)))
        out.append(N.xreplace(accelerations or {}).xreplace(dict(eom.driven_law)))  # the solve keeps a run-up's inputs
    return tuple(out)


def measures(scene: Scene, system: FirstOrderSystem) -> dict[str, sp.Expr]:
    """{normal_force_i: N_i, slip_rate_i: phi_i'} of a friction scene's model ({} without friction); with
    stiction also the stick phase's switching function, stick_margin_i = mu_s_i N_i - |F_i| (>= 0 while a
    stuck ball holds, `stick_forces_in`), and stick_force_i = F_i, whose sign says which way a released ball
    slips.  The event driver reads slip_rate_i (slip -> stick) and stick_margin_i (stick -> slip)."""
    if not scene.friction:
        return {}
    normal = normal_forces_in(scene, system)
    out = dict(zip(normal_force_names(scene.n), normal))
    rates = (Coordinate.make(f"phi_{i + 1}").qd for i in range(scene.n))
    out |= dict(zip(slip_rate_names(scene.n), rates))
    if scene.stiction:
        mu_s = DimensionalSymbols.for_scene(scene).mu_s
        force = stick_forces_in(scene, system)
        out |= dict(zip(stick_force_names(scene.n), force))
        out |= {name: mu_s[i] * normal[i] - sp.Abs(force[i]) for i, name in enumerate(stick_margin_names(scene.n))}
    return out
