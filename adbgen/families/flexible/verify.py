"""Checks of the flexible-rotor family (issue 38 item 4: proven equal where the families overlap).

`single_plane_limit`: one node, two modes with identity mode shapes (the node's x, y translation), M_q =
M I, K_q = diag(k_X, k_Y), C_q = diag(c_X, c_Y), G_q = 0, w = (0, M), m_u = M: a Jeffcott rotor, whose
right-hand side x'' = M(x)^-1 f(x, x', t) must equal the single-plane fixed-frame model's, thesis (2.10),
(2.11), (2.13), with (X, Y) = (q_1, q_2), to round-off at random states and times.  Its negative control
is a wrong mode shape at the balancer node (the node's x picking up 5 % of mode 2), which must be caught.

`two_plane_limit`: two nodes, four rigid-body modes q = (X, Y, phi_X, phi_Y) of the two-plane model's rotor
(paper section 2.1): a shaft point at z moves by (X + z phi_Y, Y - z phi_X) to first order, so a node's shape
is [[1, 0, 0, z], [0, 1, -z, 0]]; M_q = diag(M, M, J_t, J_t), K_q = sum_j S(z_j)^T diag(k_jX, k_jY) S(z_j) and
C_q likewise over the bearings at z_1 = +l_1, z_2 = -l_2 (paper (1)), G_q[phi_X, phi_Y] = -G_q[phi_Y, phi_X] =
J_p (the two-plane rotor's -J_p theta_0' phi_X phi_Y' in T).  The balls sit at the races' planes, ball k's
absolute angle theta_k = Omega t + phi_k.  Then x'' must equal the two-plane fixed-frame model's (paper (2),
(4), `two_plane.model.derive`) to round-off.  Exact only under stated restrictions: constant speed, no
misalignment (chi = 0: its (J_t - J_p) chi^2 and chi-forcing have no modal counterpart), no friction, and the
unbalance (at the first node) equal to the two-plane one only when that node is the centre-of-mass plane
(z = 0) with beta = 0, or eps = 0.  Why equality can hold exactly: the two-plane model keeps T to second
order and drops each ball's own tilt terms (m_k R_k^2, its item 2), so its balls enter through their race
centres' translation, which is all a mode-shape model gives them.  Negative control: the second node's tilt
sign flipped ([1, 0, 0, -z], [0, 1, z, 0]), which must be caught.
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
from ..two_plane.model import derive as derive_two_plane
from ..two_plane.scene import Bearing, Race, TwoPlaneScene, TwoPlaneSpeed
from .model import derive
from .scene import BalancerNode, FlexibleScene, FlexibleSpeed, Modal, jeffcott_modal
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


def two_plane_limit_check() -> CheckResult:
    """The check behind a generated two-node model (`models`): both scenes of `two_plane_limit` in one result."""
    results = two_plane_limit()
    return CheckResult("four rigid modes = two-plane", results[0].reference, all(r.passed for r in results),
                       "; ".join(r.detail for r in results), sum(r.seconds for r in results))


def law_applied(eom: EquationsOfMotion) -> EquationsOfMotion:
    """A prescribed run-up's equations with its driven_law (psi, psi', psi'' in t) substituted."""
    law = dict(eom.driven_law)
    return replace(eom.map(lambda e: e.xreplace(law)), driven=(), driven_law={}) if law else eom


def ramp_scene(omega_start: float = 60.0, omega: float = 160.0, ramp_time: float = 2.0) -> FlexibleScene:
    """Three modes (coupled M_q, K_q, C_q, a gyroscopic pair, a node moving in all three), three unequal balls,
    gravity: every term of the modal Lagrangian present; run up from omega_start to omega over ramp_time."""
    modal = Modal(((2.0, 0.1, 0.0), (0.1, 1.5, 0.0), (0.0, 0.0, 1.2)),
                  ((3e4, 2e3, 0.0), (2e3, 2.5e4, 0.0), (0.0, 0.0, 2e5)),
                  ((3.0, 0.5, 0.0), (0.5, 2.0, 0.0), (0.0, 0.0, 5.0)),
                  ((0.0, 0.02, 0.01), (-0.02, 0.0, 0.0), (-0.01, 0.0, 0.0)),
                  ((1.0, 0.0, 0.6), (0.0, 1.0, -0.3)), (0.3, 1.4, 0.2), "a test rotor in three modes")
    speed = FlexibleSpeed("schedule", omega, (("omega", omega), ("ramp_time", ramp_time), ("hold_time", 1.0),
                                              ("reduction_depth", 0.0), ("reduction_rate", 1.0),
                                              ("plateau_time", 0.0), ("recovery_rate", 1.0)), omega_start)
    return FlexibleScene(n=3, ball_mass=(0.05, 0.04, 0.06), ball_damping=(1e-4, 2e-4, 1.5e-4), race_radius=0.05,
                         unbalance_mass=2.0, eccentricity=3e-4, gravity=True, speed=speed, modal=modal)


def newton_accelerations(scene: FlexibleScene, time: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """The run-up's accelerations (q'', phi'') by Newton's law on each ball and the modal projection of the
    forces on the node, written directly (not by Lagrange's equations), on the ramp: psi = w0 t + a t^2 / 2,
    a = (omega - w0) / t_ramp.  Ball i (theta_i = psi + phi_i, e_r, e_t its radial and tangential unit
    vectors) accelerates at A_i = Phi q'' + R ((psi'' + phi_i'') e_t - (psi' + phi_i')^2 e_r); along the race
    m_i R e_t . A_i = -D_i phi_i' - m_i g R cos theta_i (thesis (2.7)-(2.9)); the modes: M_q q'' + (C_q + psi'
    G_q) q' + K_q q + g w + Phi^T [sum_i m_i (A_i + g e_y) + U (psi'' e_t(psi) - psi'^2 e_r(psi))] = 0."""
    modal, k, n = scene.modal, scene.k, scene.balls
    w0 = scene.speed.omega_start or 0.0
    a = (scene.speed.omega - w0) / dict(scene.speed.schedule)["ramp_time"]
    psi, dpsi, ddpsi = w0 * time + a * time**2 / 2, w0 + a * time, a
    M, K, C, G = (np.array(x) for x in (modal.mass, modal.stiffness, modal.damping, modal.gyroscopic))
    Phi, w = np.array(modal.node_shape), np.array(modal.gravity_load)
    g = scene.g if scene.gravity else 0.0
    m, D, R, U = np.array(scene.masses()), np.array(scene.ball_dampings()), scene.race_radius, \
        scene.unbalance_mass * scene.eccentricity
    phi, dphi = q[k:], qd[k:]
    qm, dqm = q[:k], qd[:k]
    er = lambda th: np.array([np.cos(th), np.sin(th)])  # noqa: E731
    et = lambda th: np.array([-np.sin(th), np.cos(th)])  # noqa: E731
    A = np.zeros((k + n, k + n))  # unknowns (q'', phi''): A x = b
    b = np.zeros(k + n)
    A[:k, :k] = M + sum(m) * Phi.T @ Phi
    b[:k] = -(C + dpsi * G) @ dqm - K @ qm - g * w - U * Phi.T @ (ddpsi * et(psi) - dpsi**2 * er(psi))
    for i in range(n):
        th, rate = psi + phi[i], dpsi + dphi[i]
        known = R * (ddpsi * et(th) - rate**2 * er(th)) + g * np.array([0.0, 1.0])  # A_i + g e_y without the unknowns
        A[:k, k + i] = m[i] * R * Phi.T @ et(th)
        b[:k] -= m[i] * Phi.T @ known
        A[k + i, :k] = m[i] * R * et(th) @ Phi
        A[k + i, k + i] = m[i] * R**2
        b[k + i] = -D[i] * dphi[i] - m[i] * g * R * np.cos(th) - m[i] * R * et(th) @ (R * ddpsi * et(th) - R * rate**2 * er(th))
    return np.linalg.solve(A, b)


def _random_states(rng, k: int, n: int, omega: float):
    q = np.concatenate([rng.normal(0, 1e-3, k), rng.uniform(-np.pi, np.pi, n)])
    qd = np.concatenate([rng.normal(0, 1e-3 * omega, k), rng.normal(0, 0.1 * omega, n)])
    return q, qd


def ramp_difference(scene: FlexibleScene, wrong: bool = False, seed: int = 0) -> float:
    """x'' of the generated run-up (Lagrange, psi driven, `model.derive`) against `newton_accelerations` at
    random states and times on the ramp, relative to their size.  wrong: psi'' with its sign flipped."""
    a = accelerations(law_applied(derive(scene, wrong)))
    rng = np.random.default_rng(seed)
    t_ramp = dict(scene.speed.schedule)["ramp_time"]
    worst, size = 0.0, 0.0
    for _ in range(_STATES):
        time = rng.uniform(0, t_ramp)
        q, qd = _random_states(rng, scene.k, scene.balls, scene.speed.omega)
        x, y = a(time, q, qd), newton_accelerations(scene, time, q, qd)
        worst = max(worst, float(np.max(np.abs(x - y))))
        size = max(size, float(np.max(np.abs(y))))
    return worst / size


def zero_rate_difference(scene: FlexibleScene, start: float = 1.0, seed: int = 1) -> float:
    """A schedule whose ramp starts at its final speed (omega_start = omega: no acceleration, psi = omega t at
    every t) against the constant-speed model of the same rotor, at random states and times on the ramp and
    after it, relative to their size.  start: omega_start / omega (1; 0.99 is the negative control, a ramp
    with a rate left in)."""
    flat = replace(scene, speed=replace(scene.speed, omega_start=start * scene.speed.omega))
    constant = replace(scene, speed=FlexibleSpeed("constant", scene.speed.omega))
    a, b = accelerations(law_applied(derive(flat))), accelerations(derive(constant))
    rng = np.random.default_rng(seed)
    t_ramp = dict(scene.speed.schedule)["ramp_time"]
    worst, size = 0.0, 0.0
    for _ in range(_STATES):
        time = rng.uniform(0, 2 * t_ramp)
        q, qd = _random_states(rng, scene.k, scene.balls, scene.speed.omega)
        x, y = a(time, q, qd), b(time, q, qd)
        worst = max(worst, float(np.max(np.abs(x - y))))
        size = max(size, float(np.max(np.abs(y))))
    return worst / size


def zero_rate(wrong: bool = False) -> list[CheckResult]:
    """With omega_start = omega the schedule's model equals the constant-speed model (`ramp_scene`).  wrong:
    omega_start 1 % below omega."""
    def run():
        diff = zero_rate_difference(ramp_scene(), 0.99 if wrong else 1.0)
        return diff <= RHS_TOLERANCE, f"max |x''_schedule - x''_constant| / max |x''| = {diff:.1e} (tol {RHS_TOLERANCE:.0e})"
    return [timed("zero-rate ramp = constant speed" + (" (omega_start 1 % low)" if wrong else ""), "thesis (2.14)", run)]


def run_up(wrong: bool = False) -> list[CheckResult]:
    """On a ramp (60 -> 160 rad/s in 2 s, psi'' = 50 rad/s^2, `ramp_scene`) the schedule's model equals Newton's
    law written directly.  wrong: psi'' with its sign flipped."""
    def run():
        diff = ramp_difference(ramp_scene(), wrong)
        return diff <= RHS_TOLERANCE, f"max |x''_Lagrange - x''_Newton| / max |x''| = {diff:.1e} (tol {RHS_TOLERANCE:.0e})"
    return [timed("run-up = Newton's law on the balls and the node" + (" (psi'' sign flipped)" if wrong else ""),
                  "thesis (2.7)-(2.9), (2.14)", run)]


def prescribed_speed_check() -> CheckResult:
    """The check behind a generated run-up (`models`): both comparisons in one result."""
    results = zero_rate() + run_up()
    return CheckResult("prescribed speed schedule", results[1].reference, all(r.passed for r in results),
                       "; ".join(r.detail for r in results), sum(r.seconds for r in results))


def registered(ns=()) -> list[Registered]:
    return [Registered("single-plane limit (Jeffcott)", DERIVED, lambda wrong: single_plane_limit(wrong),
                       "the balancer node's x with 5 % of mode 2 (a wrong mode shape)"),
            Registered("zero-rate ramp = constant speed", DERIVED, lambda wrong: zero_rate(wrong),
                       "the ramp's start speed 1 % below omega (a rate left in)"),
            Registered("run-up = Newton's law", DERIVED, lambda wrong: run_up(wrong),
                       "the spin's angular acceleration psi'' with its sign flipped"),
            Registered("two-plane limit (four rigid-body modes)", DERIVED, lambda wrong: two_plane_limit(wrong),
                       "the second node's tilt sign flipped (a wrong mode shape)")]



def plane_shape(z: float, tilt: float = 1.0) -> tuple[tuple[float, ...], ...]:
    """A rigid shaft's point at axial position z: (x, y) = (X + z phi_Y, Y - z phi_X) per unit of
    q = (X, Y, phi_X, phi_Y) (paper section 2.1, first order); tilt = -1 flips the tilt (the negative control)."""
    return ((1.0, 0.0, 0.0, tilt * z), (0.0, 1.0, -tilt * z, 0.0))


def _bearing_sum(two: TwoPlaneScene, what: str) -> tuple[tuple[float, ...], ...]:
    """sum_j S(z_j)^T diag(a_jX, a_jY) S(z_j) over the bearings at +l_1, -l_2 (paper (1)): K_q or C_q."""
    out = np.zeros((4, 4))
    for bearing, z in ((two.bearing_1, two.bearing_1.position), (two.bearing_2, -two.bearing_2.position)):
        shape = np.array(plane_shape(z))
        out += shape.T @ np.diag(bearing.xy(what)) @ shape
    return tuple(tuple(float(v) for v in row) for row in out)


def rigid_scene(two: TwoPlaneScene, tilt_2: float = 1.0) -> FlexibleScene:
    """The flexible scene of a two-plane scene: four rigid-body modes, one node per race (module docstring)."""
    if two.speed.law != "constant" or two.misalignment != 0.0 or two.friction:
        raise ValueError("the rigid-mode scene needs a constant speed, chi = 0 and no friction")
    if two.eccentricity != 0.0 and (two.races[0].z != 0.0 or two.imbalance_phase != 0.0):
        raise ValueError("the unbalance sits at the first node: it needs eps = 0, or race 1 at z = 0 and beta = 0")
    M, Jt, Jp = two.rotor_mass, two.transverse_inertia, two.polar_inertia
    gyro = tuple(tuple(Jp if (i, j) == (2, 3) else -Jp if (i, j) == (3, 2) else 0.0 for j in range(4))
                 for i in range(4))
    first, second = two.races
    modal = Modal(((M, 0, 0, 0), (0, M, 0, 0), (0, 0, Jt, 0), (0, 0, 0, Jt)), _bearing_sum(two, "stiffness"),
                  _bearing_sum(two, "damping"), gyro, plane_shape(first.z), (0.0,) * 4,
                  "four rigid-body modes of the two-plane rotor (X, Y, phi_X, phi_Y)")
    return FlexibleScene(n=len(first.masses), ball_mass=first.masses, ball_damping=first.damping,
                         race_radius=first.radius, unbalance_mass=M, eccentricity=two.eccentricity,
                         speed=FlexibleSpeed("constant", float(two.speed.omega)), modal=modal,
                         node_2=BalancerNode(plane_shape(second.z, tilt_2), len(second.masses), second.masses,
                                             second.damping, second.radius))


def two_plane_difference(two: TwoPlaneScene, tilt_2: float = 1.0, seed: int = 0) -> float:
    """The largest difference of x'' (flexible against two-plane) over random states, relative to their size;
    the balls' states map by theta_k = Omega t + phi_k, theta_k' = Omega + phi_k'."""
    flexible = derive(rigid_scene(two, tilt_2))
    reference = derive_two_plane(two)
    names = [c.name for c in reference.coordinates]
    n = two.n
    balls = [f"phi_{i + 1}" for i in range(n)]
    if names != ["X", "Y", "phi_X", "phi_Y"] + [f"theta_{i + 1}" for i in range(n)] or \
            [c.name for c in flexible.coordinates] != [f"q_{j + 1}" for j in range(4)] + balls:
        raise AssertionError(f"coordinates differ: {names} against {[c.name for c in flexible.coordinates]}")
    a, b = accelerations(flexible), accelerations(reference)
    omega = float(two.speed.omega)
    rng = np.random.default_rng(seed)
    worst, size = 0.0, 0.0
    for _ in range(_STATES):
        time = rng.uniform(0, 10.0 / omega)
        q = np.concatenate([rng.normal(0, 1e-2, 4), rng.uniform(-np.pi, np.pi, n)])
        qd = np.concatenate([rng.normal(0, 1e-2 * omega, 4), rng.normal(0, 0.1 * omega, n)])
        shift = np.concatenate([np.zeros(4), np.full(n, omega)])
        x, y = a(time, q, qd), b(time, q + shift * time, qd + shift)
        worst = max(worst, float(np.max(np.abs(x - y))))
        size = max(size, float(np.max(np.abs(y))))
    return worst / size


def two_plane_scenes() -> tuple[TwoPlaneScene, ...]:
    """Paper (10) without the unbalance (races at z = +-2), and an anisotropic, asymmetric scene with race 1
    at the centre-of-mass plane carrying the unbalance, three unequal balls in race 2."""
    return (TwoPlaneScene(eccentricity=0.0),
            TwoPlaneScene(rotor_mass=1.3, transverse_inertia=2.1, polar_inertia=0.7, eccentricity=0.02,
                          bearing_1=Bearing(2.5, (0.5, 0.7), (0.01, 0.02)), bearing_2=Bearing(3.5, (0.6, 0.4), 0.015),
                          races=(Race(0.0, 1.0, (0.003, 0.002), 3e-5), Race(-1.5, 0.8, (0.002, 0.0025, 0.003), 2e-5)),
                          speed=TwoPlaneSpeed("constant", omega=2.4)))


def two_plane_limit(wrong: bool = False) -> list[CheckResult]:
    out = []
    for i, two in enumerate(two_plane_scenes()):
        def run(two=two):
            diff = two_plane_difference(two, -1.0 if wrong else 1.0)
            return diff <= RHS_TOLERANCE, (f"max |x''_flexible - x''_two-plane| / max |x''| = {diff:.1e} "
                                           f"(tol {RHS_TOLERANCE:.0e})")
        label = "node 2 tilt sign flipped" if wrong else f"n = {two.n}"
        out.append(timed(f"four rigid modes = two-plane ({label}, scene {i + 1})", "paper (1), (2), (4); chi = 0", run))
    return out
