"""A ROSS rotor -> a flexible-rotor scene (issue 38 item 3): the first k modes, the balancer node's shapes.

Reduction: modal truncation of the undamped, non-spinning rotor's lateral motion.  ROSS's matrices
(`Rotor.M(speed)`, `K(speed)`, `C(speed)`, `G()`; its equations M u'' + (C + Omega G) u' + K u = f) are
restricted to the lateral degrees of freedom (x, y, alpha, beta: ROSS's Timoshenko elements couple them to
neither the axial nor the torsional ones), K v = w^2 M v is solved (symmetric, real: the modes of the rotor
at rest without damping), and the k lowest modes form Phi.  Why this basis: the balancer's forces act
at one node near the spin frequency, and the speed range of interest lies below the (k+1)-th natural
frequency, which is what truncation converges for (checked: `convergence`); the undamped non-spinning
modes are real, so the reduced M_q, K_q stay symmetric and the family's Lagrangian exists, with damping and
gyroscopy projected (C_q = Phi^T C Phi, G_q = Phi^T G Phi).  Craig-Bampton would keep the node's
translation exactly but adds its static constraint modes to every model; at one node, a node whose
translation is the modes' own is already represented.

Each mode is scaled so that its largest lateral translation along the shaft is 1 (the shapes
dimensionless, q in metres); entries of Phi^T M Phi, Phi^T K Phi that orthogonality makes zero are set to
exactly 0 (below `ORTHOGONAL` of the diagonal: round-off), so the model carries no k^2 zero products.  A
degenerate pair (an axisymmetric rotor's x and y modes share a frequency) is never split: k must end
between distinct frequencies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh

from .rotor import RotorError, Unbalance, node_position

ORTHOGONAL = 1e-10  # relative: off-diagonals of the projected M, K below it are round-off
DEGENERATE = 1e-6  # relative gap under which two natural frequencies are one (a pair)
TOLERANCE = 1e-3  # modal convergence: the critical speeds' relative change when one more mode pair is added


def lateral_dofs(rotor) -> tuple[np.ndarray, dict]:
    """The lateral degrees of freedom (x, y, alpha, beta of each shaft node), in ROSS's global order, and
    {node: (x index, y index)} within them."""
    names = {}
    for elm in rotor.shaft_elements:
        dofs = list(elm.dof_global_index.values())
        for name, k in elm.dof_mapping().items():
            base, end = name[:-2], name[-1]
            if base in ("x", "y", "alpha", "beta"):
                node = int(elm.n_l if end == "0" else elm.n_r)
                names[dofs[k]] = (base, node)
    index = np.array(sorted(names))
    where = {}
    for i, g in enumerate(index):
        base, node = names[g]
        if base in ("x", "y"):
            where.setdefault(node, {})[base] = i
    return index, {n: (d["x"], d["y"]) for n, d in where.items()}


@dataclass(frozen=True)
class Reduced:
    """The reduced matrices (lists for the scene), the natural frequencies of the modes kept, the basis."""

    mass: list
    stiffness: list
    damping: list
    gyroscopic: list
    node_shape: list
    gravity_load: list
    frequencies: tuple[float, ...]  # rad/s, the kept modes' undamped natural frequencies at rest
    basis: np.ndarray  # lateral dofs x k


def _clean(A: np.ndarray, symmetric: bool) -> list:
    scale = max(float(np.max(np.abs(np.diag(A)))), 1e-300)
    A = (A + A.T) / 2 if symmetric else (A - A.T) / 2
    A = np.where(np.abs(A) < ORTHOGONAL * scale, 0.0, A) if symmetric else A
    return [[float(v) for v in row] for row in A]


def reduce(rotor, node: int, k: int, speed: float) -> Reduced:
    """The first k lateral modes of `rotor` (bearings at `speed`), projected (module docstring)."""
    if int(node) not in [int(n) for n in rotor.nodes]:
        raise RotorError(f"node {node} is not a node of the rotor")
    if list(rotor.point_mass_elements):
        raise RotorError("the rotor has point masses (support masses): their dofs are not the shaft's; not reduced")
    index, where = lateral_dofs(rotor)
    sub = np.ix_(index, index)
    M = np.asarray(rotor.M(speed), dtype=float)[sub]
    K = np.asarray(rotor.K(speed), dtype=float)[sub]
    C = np.asarray(rotor.C(speed), dtype=float)[sub]
    G = np.asarray(rotor.G(), dtype=float)[sub]
    for name, A in (("stiffness", K), ("damping", C)):
        asym = np.max(np.abs(A - A.T)) / max(np.max(np.abs(A)), 1e-300)
        if asym > 1e-9:
            raise RotorError(f"the rotor's {name} matrix is not symmetric ({asym:.1e}: cross-coupled bearings); "
                             "the flexible family needs a Lagrangian (symmetric K, C)")
    w2, V = eigh(K, M)
    if not 1 <= k < len(w2):
        raise RotorError(f"k = {k} modes: between 1 and {len(w2) - 1}")
    w = np.sqrt(np.clip(w2, 0.0, None))
    if abs(w[k] - w[k - 1]) <= DEGENERATE * max(w[k], 1e-300):
        raise RotorError(f"k = {k} splits a pair of modes at {w[k]:.6g} rad/s: take k = {k - 1} or {k + 1}")
    V = V[:, :k]
    translations = [i for n, (ix, iy) in where.items() for i in (ix, iy)]
    V = V / np.max(np.abs(V[translations, :]), axis=0)
    ix, iy = where[int(node)]
    ey = np.zeros(len(index))
    ey[[iy_ for _, iy_ in where.values()]] = 1.0  # the rigid translation in y: gravity's direction (-y)
    return Reduced(_clean(V.T @ M @ V, True), _clean(V.T @ K @ V, True), _clean(V.T @ C @ V, True),
                   _clean(V.T @ G @ V, False), [[float(v) for v in V[ix]], [float(v) for v in V[iy]]],
                   [float(v) for v in V.T @ M @ ey], tuple(float(x) for x in w[:k]), V)


def node_shape(red: Reduced, rotor, node: int) -> list:
    """`node`'s rows of the reduced basis: its x and y translation per unit of each kept mode (2 x k)."""
    if int(node) not in [int(n) for n in rotor.nodes]:
        raise RotorError(f"node {node} is not a node of the rotor")
    ix, iy = lateral_dofs(rotor)[1][int(node)]
    return [[float(v) for v in red.basis[ix]], [float(v) for v in red.basis[iy]]]


def scene_mapping(rotor, node: int, k: int, balls: int, ball_mass: float, race_radius: float, speed: float,
                  unbalance: Unbalance | None = None, ball_damping: float | None = None,
                  node_2: int | None = None) -> dict:
    """The flexible scene's mapping: `balls` balls at `node`, the rotor in k modes at `speed`.

    The unbalance is the user's at the balancer node (kg m; its phase only turns the frame): m_u is the
    disk mass at the node (the node's translational mass without a disk), eps = magnitude / m_u.
    `node_2`: a second balancer node (the scene's [node_2]), its shapes the same reduction's basis rows at
    that node, its race the same balls, ball mass, drag and race radius as the first's; the family carries
    the unbalance at the first node only, so an unbalance at `node_2` is refused (list that plane first)."""
    from .scene import BALL_DRAG_RATE

    for what, v in (("--balls", balls), ("--ball-mass", ball_mass), ("--race-radius", race_radius), ("--speed", speed)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise RotorError(f"{what} must be a positive number, got {v!r}")
    if node_2 is not None and int(node_2) == int(node):
        raise RotorError(f"the two balancer nodes must be different nodes, got {node} twice")
    if unbalance is not None and int(unbalance.node) != int(node):
        hint = f" (give --plane {unbalance.node} first)" if node_2 is not None and int(unbalance.node) == int(node_2) else ""
        raise RotorError(f"the flexible scene carries the unbalance at the balancer node {node}, "
                         f"not at node {unbalance.node}{hint}")
    red = reduce(rotor, node, k, speed)
    second = node_shape(red, rotor, node_2) if node_2 is not None else None
    disks = [float(d.m) for d in rotor.disk_elements if int(d.n) == int(node)]
    index, where = lateral_dofs(rotor)
    x = index[where[int(node)][0]]
    m_u = sum(disks) if disks else float(np.asarray(rotor.M(speed), dtype=float)[x, x])
    eps = (unbalance.magnitude / m_u) if unbalance is not None else 0.0
    drag = ball_mass * race_radius**2 * BALL_DRAG_RATE if ball_damping is None else ball_damping
    where_ = f"balancer at node {node} (z = {node_position(rotor, node):.6g} m)"
    if second is not None:
        where_ = (f"balancers at nodes {node} (z = {node_position(rotor, node):.6g} m) and {node_2} "
                  f"(z = {node_position(rotor, node_2):.6g} m)")
    mapping = {"n": int(balls), "ball_mass": float(ball_mass), "ball_damping": float(drag),
               "race_radius": float(race_radius), "unbalance_mass": float(m_u), "eccentricity": float(eps),
               "speed": {"law": "constant", "omega": float(speed)},
               "modal": {"mass": red.mass, "stiffness": red.stiffness, "damping": red.damping,
                         "gyroscopic": red.gyroscopic, "node_shape": red.node_shape, "gravity_load": red.gravity_load,
                         "reduction": f"modal truncation of the undamped non-spinning rotor: {k} lateral modes of "
                                      f"ROSS's {len(index)} lateral dofs, {where_}, bearings at {speed:.6g} rad/s"}}
    if second is not None:
        mapping["node_2"] = {"n": int(balls), "ball_mass": float(ball_mass), "ball_damping": float(drag),
                             "race_radius": float(race_radius), "node_shape": second}
    return mapping


def shape_mismatch(rotor, shapes: dict, evectors) -> float:
    """How far a scene's 2 x k shapes {node: shape} are from ROSS's own mode shapes at those nodes: the largest
    difference over the k modes, each of ROSS's eigenvectors (`ModalResults.evectors` of the undamped,
    non-spinning rotor, the modes in the reduction's order: frequencies distinct, all lateral; the caller
    checks ROSS's `wn` against `Reduced.frequencies`) made real by its largest
    entry's phase and scaled the bridge's way (largest lateral translation 1), with one sign per mode over all
    the nodes given (the scene's).  Round-off when each shape is its node's; a wrong node or mode order gives
    order one.  A mirror-symmetric rotor cannot tell two mirror nodes apart (a mode's sign is free)."""
    index, where = lateral_dofs(rotor)
    for node in shapes:
        if int(node) not in where:
            raise RotorError(f"node {node} is not a node of the rotor")
    rows = [i for node in shapes for i in where[int(node)]]
    translations = [i for n, (a, b) in where.items() for i in (a, b)]
    ours = np.vstack([np.asarray(shape, dtype=float) for shape in shapes.values()])
    if np.shape(evectors)[1] < ours.shape[1]:
        raise RotorError(f"ROSS's modal results hold {np.shape(evectors)[1]} modes, the shapes {ours.shape[1]}: "
                         "run_modal with more num_modes")
    worst = 0.0
    for j in range(ours.shape[1]):
        u = np.asarray(evectors, dtype=complex)[index, j]
        u = (u / u[np.argmax(np.abs(u))]).real
        u = u / np.max(np.abs(u[translations]))
        theirs = u[rows] if np.dot(u[rows], ours[:, j]) >= 0 else -u[rows]
        worst = max(worst, float(np.max(np.abs(theirs - ours[:, j]))))
    return worst


@dataclass(frozen=True)
class Convergence:
    """The fewest modes whose first `count` forward-whirl critical speeds stay within `tolerance` (relative)
    of those of every larger k up to the full lateral model; the speeds of each k tried."""

    k: int | None  # None: not converged below the full model
    tolerance: float
    speeds: dict  # k -> the first `count` forward critical speeds (rad/s)

    def line(self) -> str:
        if self.k is None:
            return f"not converged to {self.tolerance:g} below k = {max(self.speeds)} modes"
        return (f"k = {self.k} modes: the first {len(self.speeds[self.k])} forward critical speeds "
                f"{', '.join(f'{w:.6g}' for w in self.speeds[self.k])} rad/s are within {self.tolerance:g} of "
                f"those of every larger k up to the full lateral model (k = {max(self.speeds)})")


def forward_speeds(modal, top: float, count: int) -> list[float]:
    from ..families.flexible.critical_speeds import crossings

    return [c.speed for c in crossings(modal, top) if c.whirl == "forward"][:count]  # count None: all


def convergence(rotor, node: int, speed: float, top: float, count: int | None = 3, tolerance: float = TOLERANCE,
                k_max: int | None = None) -> Convergence:
    """Modal convergence (the smallest-model rule, issue 38 item 3): the first `count` forward critical
    speeds below `top` (None: as many as the full model has there) for every admissible k (a k splitting a degenerate pair is skipped) up to `k_max`
    (default: every lateral mode but one, the full model to round-off), and the fewest k whose speeds are
    within `tolerance` of every larger k's.  Why not "one more mode changes them by less than the
    tolerance": on ROSS's example rotor (node 2) k = 6, 7, 8 all give a third forward critical speed of
    905.161 rad/s, k = 10 gives 867.748 and ROSS 866.827 (the mode that carries it couples only to the
    9th and 10th); a criterion that looks one mode ahead stops at k = 6, 4 % off."""
    from ..families.flexible.scene import FlexibleScene

    index, _ = lateral_dofs(rotor)
    k_max = k_max or len(index) - 1
    speeds: dict = {}
    if count is None:
        count = len(forward_speeds(FlexibleScene.from_mapping(scene_mapping(rotor, node, k_max, 1, 1.0, 1.0, speed))
                                   .modal, top, None))
    for k in range(1, k_max + 1):
        try:
            mapping = scene_mapping(rotor, node, k, 1, 1.0, 1.0, speed)
        except RotorError as exc:
            if "splits a pair" in str(exc):
                continue
            raise
        speeds[k] = forward_speeds(FlexibleScene.from_mapping(mapping).modal, top, count)
    close = lambda a, b: len(a) == count and len(b) == count and all(  # noqa: E731
        abs(x - y) < tolerance * y for x, y in zip(a, b))
    ks = sorted(speeds)
    for i, k in enumerate(ks):
        if all(close(speeds[k], speeds[j]) for j in ks[i:]):
            return Convergence(k, tolerance, speeds)
    return Convergence(None, tolerance, speeds)


def flexible_scene(rotor, node: int, balls: int, ball_mass: float, race_radius: float, speed: float, top: float, *,
                   unbalance: Unbalance | None = None, ball_damping: float | None = None, modes: int | None = None,
                   tolerance: float = TOLERANCE, node_2: int | None = None) -> tuple[dict, Convergence | None]:
    """The flexible scene's mapping in the converged number of modes for the forward critical speeds below
    `top` (or `modes` given), and the convergence that chose it (None when `modes` was given).  `node_2`: a
    second balancer node (`scene_mapping`); the critical speeds, hence k, do not depend on the nodes."""
    conv = None
    if modes is None:
        conv = convergence(rotor, node, speed, top, None, tolerance)
        if conv.k is None:
            raise RotorError(f"modal truncation does not converge to {tolerance:g} below the full lateral model "
                             f"(k = {max(conv.speeds)}): give --modes")
        modes = conv.k
    return scene_mapping(rotor, node, modes, balls, ball_mass, race_radius, speed, unbalance, ball_damping,
                         node_2), conv


def write(mapping: dict, out, header: str) -> str:
    """The flexible scene as TOML, checked to read back."""
    import tomllib
    from pathlib import Path

    from ..families.flexible.scene import FlexibleScene
    from .scene import to_toml

    text = to_toml(mapping, header)
    FlexibleScene.from_mapping(tomllib.loads(text))
    Path(out).write_text(text, encoding="utf-8")
    return text
