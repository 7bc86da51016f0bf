"""Checks of the flexible-rotor family (issue 38 item 4: proven equal where the families overlap).

`single_plane_limit`: one node, two modes with identity mode shapes (the node's x, y translation), M_q =
M I, K_q = diag(k_X, k_Y), C_q = diag(c_X, c_Y), G_q = 0, w = (0, M), m_u = M: a Jeffcott rotor, whose
right-hand side x'' = M(x)^-1 f(x, x', t) must equal the single-plane fixed-frame model's, thesis (2.10),
(2.11), (2.13), with (X, Y) = (q_1, q_2), to round-off at random states and times.  Its negative control
is a wrong mode shape at the balancer node (the node's x picking up 5 % of mode 2), which must be caught.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np
import sympy as sp

from ...core.checks import DERIVED, CheckResult, Registered, timed
from ...core.lagrange import EquationsOfMotion
from ..single_plane.model import derive as derive_single_plane
from ..single_plane.scene import Scene, SpeedLaw
from .model import derive
from .scene import FlexibleScene, FlexibleSpeed, Modal, jeffcott_modal
from .symbols import t

RHS_TOLERANCE = 1e-11  # relative to the largest acceleration: round-off of a 2 + n linear solve
_STATES = 8  # random states compared per scene


def jeffcott_scene(single: Scene, modal: Modal | None = None) -> FlexibleScene:
    """The flexible scene of a single-plane scene (constant speed): its rotor as two identity modes."""
    (kx, ky), (cx, cy) = single.stiffness_xy(), single.damping_xy()
    return FlexibleScene(n=single.n, ball_mass=single.ball_mass, ball_damping=single.ball_damping,
                         race_radius=single.race_radius, unbalance_mass=single.rotor_mass,
                         eccentricity=single.eccentricity,
                         gravity=single.gravity, g=single.g, speed=FlexibleSpeed("constant", float(single.speed.omega)),
                         modal=modal or jeffcott_modal(single.rotor_mass, (kx, ky), (cx, cy)))


def accelerations(eom: EquationsOfMotion) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray]:
    """x'' = M^-1 f at (t, x, x') with the model's default parameters (the reference evaluation)."""
    values = {p.symbol: p.default for p in eom.parameters}
    x = [c.q for c in eom.coordinates]
    xd = [c.qd for c in eom.coordinates]
    mass = sp.lambdify((t, x, xd), eom.mass_matrix().xreplace(values), modules="numpy")
    force = sp.lambdify((t, x, xd), sp.Matrix(eom.forcing).xreplace(values), modules="numpy")
    return lambda time, q, qd: np.linalg.solve(np.array(mass(time, q, qd), dtype=float),
                                               np.array(force(time, q, qd), dtype=float).ravel())


def rhs_difference(single: Scene, modal: Modal | None = None, seed: int = 0) -> float:
    """The largest difference of the two models' accelerations over random states, relative to their size."""
    flexible = derive(jeffcott_scene(single, modal))
    reference = derive_single_plane(single)
    names = [c.name for c in reference.coordinates]
    if [c.name for c in flexible.coordinates] != ["q_1", "q_2"] + names[2:] or names[:2] != ["X", "Y"]:
        raise AssertionError(f"coordinates differ: {names} against {[c.name for c in flexible.coordinates]}")
    a, b = accelerations(flexible), accelerations(reference)
    rng = np.random.default_rng(seed)
    worst, size = 0.0, 0.0
    for _ in range(_STATES):
        time = rng.uniform(0, 0.1)
        q = np.concatenate([rng.normal(0, 1e-3, 2), rng.uniform(-np.pi, np.pi, single.n)])
        qd = np.concatenate([rng.normal(0, 0.3, 2), rng.normal(0, 5.0, single.n)])
        x, y = a(time, q, qd), b(time, q, qd)
        worst = max(worst, float(np.max(np.abs(x - y))))
        size = max(size, float(np.max(np.abs(y))))
    return worst / size


def single_plane_scenes() -> tuple[Scene, ...]:
    """The thesis' default set (5.1) with n = 2, and an anisotropic, unequal-ball, gravity scene with n = 3."""
    return (Scene(),
            Scene(n=3, ball_mass=(0.05, 0.04, 0.06), ball_damping=(1e-4, 2e-4, 1.5e-4), stiffness=(1.0e4, 1.3e4),
                  damping=(2.0, 3.0), gravity=True, speed=SpeedLaw("constant", omega=250.0)))


def wrong_shape(single: Scene) -> Modal:
    """The negative control: the node's x picks up 5 % of mode 2 (a wrong row of Phi at the balancer node)."""
    modal = jeffcott_modal(single.rotor_mass, single.stiffness_xy(), single.damping_xy())
    return replace(modal, node_shape=((1.0, 0.05), (0.0, 1.0)))


def single_plane_limit(wrong: bool = False) -> list[CheckResult]:
    out = []
    for i, single in enumerate(single_plane_scenes()):
        def run(single=single):
            diff = rhs_difference(single, wrong_shape(single) if wrong else None)
            return diff <= RHS_TOLERANCE, f"max |x''_flexible - x''_single| / max |x''| = {diff:.1e} (tol {RHS_TOLERANCE:.0e})"
        label = "wrong node shape" if wrong else f"n = {single.n}"
        out.append(timed(f"Jeffcott = single-plane ({label}, scene {i + 1})", "thesis (2.10), (2.11), (2.13)", run))
    return out


def single_plane_limit_check() -> CheckResult:
    """The check behind a generated flexible model (`models`): both scenes in one result."""
    results = single_plane_limit()
    return CheckResult("Jeffcott = single-plane", results[0].reference, all(r.passed for r in results),
                       "; ".join(r.detail for r in results), sum(r.seconds for r in results))


def registered(ns=()) -> list[Registered]:
    return [Registered("single-plane limit (Jeffcott)", DERIVED, lambda wrong: single_plane_limit(wrong),
                       "the balancer node's x with 5 % of mode 2 (a wrong mode shape)")]

