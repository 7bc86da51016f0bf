"""The flexible-rotor scene: a rotor's reduced modal matrices and the balancer node's mode shapes.

The numbers come from a finite-element model (ROSS, written by `adbgen.ross`), so the family never
imports ROSS.  The reduction is modal truncation of the undamped, non-spinning rotor: the first k
eigenvectors Phi of K x = w^2 M x (speed 0, no damping) give q-coordinates u = Phi q, and the
reduced matrices M_q = Phi^T M Phi, K_q = Phi^T K Phi, C_q = Phi^T C Phi, G_q = Phi^T G Phi.  Why
this basis: the balancer acts through one node's translation, the balls' forces are slow (near the
spin frequency) and the range of interest lies below the (k+1)-th natural frequency, which is exactly
what truncated modes converge for; undamped, non-spinning modes are real, so M_q, K_q stay symmetric
and the Lagrangian exists; damping and gyroscopy enter as the projected C_q and Omega G_q.
``node_shape`` is the balancer node's rows of Phi: its x and y translation per unit modal coordinate.

A scene in TOML::

    n = 2
    ball_mass = 0.05
    ball_damping = 1.25e-4
    race_radius = 0.05
    unbalance_mass = 1.0        # m_u (kg): the unbalanced body at the balancer node (its disk)
    eccentricity = 5.0e-4       # e (m): its centre of mass off the shaft's axis
    gravity = false
    [speed]
    law = "constant"
    omega = 400.0
    [modal]                     # k x k (2 x k for node_shape); written by adbgen.ross
    mass = [[1.0, 0.0], [0.0, 1.0]]
    stiffness = [[1.0e4, 0.0], [0.0, 1.0e4]]
    damping = [[2.0, 0.0], [0.0, 2.0]]
    gyroscopic = [[0.0, 0.0], [0.0, 0.0]]
    node_shape = [[1.0, 0.0], [0.0, 1.0]]
    gravity_load = [0.0, 1.0]  # Phi^T M e_y (kg): V = g gravity_load . q

A second balancer node (optional; balls in a second race, numbered after the first node's), with its own
2 x k translational shapes; the unbalance stays at the first node (generated with the loop form's per-ball
race radius and node shape, `models.ball_slots`; checked by `verify.two_plane_limit`)::

    [node_2]
    n = 2
    ball_mass = 0.05
    ball_damping = 1.25e-4
    race_radius = 0.05
    node_shape = [[1.0, 0.0], [0.0, 1.0]]
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from ...core import speed_schedule
from ...core.scene_fields import Key, number, per_ball
from ...errors import SceneError

Matrix = tuple[tuple[float, ...], ...]
_TOP = ("n", "ball_mass", "ball_damping", "race_radius", "unbalance_mass", "eccentricity", "gravity", "g", "speed",
        "modal", "node_2")
_NODE = ("n", "ball_mass", "ball_damping", "race_radius", "node_shape")
_MODAL = ("mass", "stiffness", "damping", "gyroscopic", "node_shape", "gravity_load", "reduction")
# the speed laws and their keys: the constant speed, and the schedule shared with the other families plus its start speed
_SPEED_KEYS = {"constant": {"law", "omega"}, "schedule": {"law", *speed_schedule.KEYS, "omega_start"}}
_SYMMETRY_TOL = 1e-9  # relative: what round-off in a projection Phi^T A Phi leaves of a symmetric A


def _matrix(name: str, value: Any, rows: int | None, cols: int | None) -> Matrix:
    if not isinstance(value, (list, tuple)) or not value or not all(isinstance(r, (list, tuple)) for r in value):
        raise SceneError(name, "must be a list of rows (a matrix)")
    if rows is not None and len(value) != rows:
        raise SceneError(name, f"needs {rows} rows, got {len(value)}")
    width = cols if cols is not None else len(value)
    out = []
    for i, row in enumerate(value):
        if len(row) != width:
            raise SceneError(name, f"row {i} needs {width} values, got {len(row)}")
        out.append(tuple(number(f"{name}[{i}][{j}]", v) for j, v in enumerate(row)))
    return tuple(out)


def _symmetry(name: str, a: Matrix, sign: int) -> Matrix:
    """a (sign = 1: symmetric, -1: skew) to round-off, returned exactly so (the Lagrangian needs it)."""
    k = len(a)
    scale = max((abs(v) for row in a for v in row), default=0.0) or 1.0
    for i in range(k):
        for j in range(k):
            if abs(a[i][j] - sign * a[j][i]) > _SYMMETRY_TOL * scale:
                what = "symmetric" if sign > 0 else "skew-symmetric"
                raise SceneError(name, f"must be {what}: entry [{i}][{j}] = {a[i][j]!r}, [{j}][{i}] = {a[j][i]!r}")
    return tuple(tuple((a[i][j] + sign * a[j][i]) / 2 for j in range(k)) for i in range(k))


@dataclass(frozen=True)
class Modal:
    """The reduced rotor: M_q q'' + (C_q + omega G_q) q' + K_q q = forces, and the balancer node's shapes."""

    mass: Matrix
    stiffness: Matrix
    damping: Matrix
    gyroscopic: Matrix
    node_shape: Matrix  # 2 x k: rows x, y of the balancer node's translation
    gravity_load: tuple[float, ...]  # Phi^T M e_y
    reduction: str = "modal truncation of the undamped non-spinning rotor"

    @property
    def k(self) -> int:
        return len(self.mass)


def jeffcott_modal(mass: float, stiffness: tuple[float, float], damping: tuple[float, float]) -> Modal:
    """The one-node, two-mode rotor whose modes are the node's x and y translation (a Jeffcott rotor)."""
    return Modal(((mass, 0.0), (0.0, mass)), ((stiffness[0], 0.0), (0.0, stiffness[1])),
                 ((damping[0], 0.0), (0.0, damping[1])), ((0.0, 0.0), (0.0, 0.0)), ((1.0, 0.0), (0.0, 1.0)),
                 (0.0, mass), "identity (the node's x, y translation: a Jeffcott rotor)")


@dataclass(frozen=True)
class BalancerNode:
    """A second balancer node: its 2 x k translational mode shapes, its race radius and its balls."""

    node_shape: Matrix
    n: int = 2
    ball_mass: float | tuple[float, ...] = 0.05
    ball_damping: float | tuple[float, ...] = 1.25e-4
    race_radius: float = 0.05

    def masses(self) -> tuple[float, ...]:
        return self.ball_mass if isinstance(self.ball_mass, tuple) else (self.ball_mass,) * self.n

    def ball_dampings(self) -> tuple[float, ...]:
        return self.ball_damping if isinstance(self.ball_damping, tuple) else (self.ball_damping,) * self.n

    @classmethod
    def from_mapping(cls, data: Any, k: int) -> "BalancerNode":
        if not isinstance(data, Mapping):
            raise SceneError("node_2", "a balancer node is a table with n, ball_mass, ball_damping, race_radius, "
                                       "node_shape")
        for key in sorted(map(str, data)):
            if key not in _NODE:
                raise SceneError(f"node_2.{key}", "unknown option")
        if "node_shape" not in data:
            raise SceneError("node_2.node_shape", "missing")
        n = data.get("n", 2)
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise SceneError("node_2.n", f"must be a whole number of balls >= 1, got {n!r}")
        return cls(_matrix("node_2.node_shape", data["node_shape"], 2, k), n,
                   per_ball("node_2.ball_mass", data.get("ball_mass", 0.05), n, positive=True),
                   per_ball("node_2.ball_damping", data.get("ball_damping", 1.25e-4), n, nonnegative=True),
                   number("node_2.race_radius", data.get("race_radius", 0.05), positive=True))


@dataclass(frozen=True)
class FlexibleSpeed:
    """The spin, prescribed: ``constant``, psi = omega t (thesis (2.14)), or ``schedule``, the run-up ramp, hold
    and temporary speed reduction every family offers (`core.speed_schedule`, the same keys and parameter
    names), here with an optional start speed ``omega_start`` (default 0: from rest) the ramp leaves from, so
    a run-up through a critical speed need not start at rest."""

    law: str = "constant"
    omega: float = 400.0
    schedule: tuple[tuple[str, float], ...] = ()  # (key, value) in speed_schedule.KEYS order (law = "schedule")
    omega_start: float | None = None  # the ramp's speed at t = 0 (law = "schedule"); None: from rest, no parameter

    @classmethod
    def from_mapping(cls, data: Any) -> "FlexibleSpeed":
        if not isinstance(data, Mapping):
            raise SceneError("speed", "a [speed] table: law = \"constant\" (omega) or \"schedule\"")
        law = data.get("law", "constant")
        allowed = _SPEED_KEYS.get(law)
        if allowed is None:
            raise SceneError("speed", f"the flexible family's speed laws are {', '.join(map(repr, _SPEED_KEYS))}; "
                                          f"got {law!r}")
        for key in sorted(map(str, data)):
            if key not in allowed:
                raise SceneError(f"speed.{key}", f"unknown option for law = {law!r}")
        if law == "constant":
            return cls("constant", number("speed.omega", data.get("omega", 400.0), positive=True))
        schedule = speed_schedule.validate(data)
        start = number("speed.omega_start", data["omega_start"], nonnegative=True) if "omega_start" in data else None
        return cls("schedule", dict(schedule)["omega"], schedule, start)


@dataclass(frozen=True)
class FlexibleScene:
    """A flexible rotor with n balls in a race at one balancer node (optionally a second), spun at a constant speed."""

    n: int = 2
    ball_mass: float | tuple[float, ...] = 0.05
    ball_damping: float | tuple[float, ...] = 1.25e-4
    race_radius: float = 0.05
    unbalance_mass: float = 1.0  # m_u, kg: the unbalanced body at the balancer node
    eccentricity: float = 5.0e-4  # e, m: its centre of mass off the axis (unbalance m_u e)
    gravity: bool = False
    g: float = 9.80665
    speed: FlexibleSpeed = field(default_factory=FlexibleSpeed)
    modal: Modal = field(default_factory=lambda: jeffcott_modal(1.0, (1.0e4, 1.0e4), (2.0, 2.0)))
    node_2: BalancerNode | None = None  # a second balancer node (its balls numbered after the first's)

    @property
    def k(self) -> int:
        return self.modal.k

    @property
    def balls(self) -> int:
        """All balls: the first node's n, then the second node's."""
        return self.n + (self.node_2.n if self.node_2 else 0)

    def ball_node(self) -> tuple[int, ...]:
        """The node (0: the first, 1: node_2) of each ball."""
        return (0,) * self.n + (1,) * (self.node_2.n if self.node_2 else 0)

    @property
    def omega(self) -> float:
        return self.speed.omega

    @property
    def equal_balls(self) -> bool:
        return (not isinstance(self.ball_mass, tuple) and not isinstance(self.ball_damping, tuple)
                and self.node_2 is None)

    def masses(self) -> tuple[float, ...]:
        return self.ball_mass if isinstance(self.ball_mass, tuple) else (self.ball_mass,) * self.n

    def ball_dampings(self) -> tuple[float, ...]:
        return self.ball_damping if isinstance(self.ball_damping, tuple) else (self.ball_damping,) * self.n

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any]) -> "FlexibleScene":
        if not isinstance(data, Mapping):
            raise SceneError("<root>", "a scene is a table of options")
        for key in sorted(map(str, data)):
            if key not in _TOP:
                raise SceneError(key, "unknown option")
        n = data.get("n", 2)
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise SceneError("n", f"must be a whole number of balls >= 1, got {n!r}")
        gravity = data.get("gravity", False)
        if not isinstance(gravity, bool):
            raise SceneError("gravity", f"must be true or false, got {gravity!r}")
        speed = FlexibleSpeed.from_mapping(data.get("speed", {"law": "constant", "omega": 400.0}))
        modal = data.get("modal")
        if not isinstance(modal, Mapping):
            raise SceneError("modal", "needs a [modal] table (mass, stiffness, damping, gyroscopic, node_shape)")
        for key in sorted(map(str, modal)):
            if key not in _MODAL:
                raise SceneError(f"modal.{key}", "unknown option")
        for key in ("mass", "stiffness", "node_shape"):
            if key not in modal:
                raise SceneError(f"modal.{key}", "missing")
        mass = _symmetry("modal.mass", _matrix("modal.mass", modal["mass"], None, None), 1)
        k = len(mass)
        zeros = [[0.0] * k for _ in range(k)]
        stiffness = _symmetry("modal.stiffness", _matrix("modal.stiffness", modal["stiffness"], k, k), 1)
        damping = _symmetry("modal.damping", _matrix("modal.damping", modal.get("damping", zeros), k, k), 1)
        gyro = _symmetry("modal.gyroscopic", _matrix("modal.gyroscopic", modal.get("gyroscopic", zeros), k, k), -1)
        shape = _matrix("modal.node_shape", modal["node_shape"], 2, k)
        load = modal.get("gravity_load", [0.0] * k)
        if not isinstance(load, (list, tuple)) or len(load) != k:
            raise SceneError("modal.gravity_load", f"needs k = {k} values")
        load = tuple(number(f"modal.gravity_load[{i}]", v) for i, v in enumerate(load))
        reduction = modal.get("reduction", Modal.reduction)
        if not isinstance(reduction, str):
            raise SceneError("modal.reduction", "must be a text saying how the matrices were reduced")
        return cls(
            n=n,
            ball_mass=per_ball("ball_mass", data.get("ball_mass", 0.05), n, positive=True),
            ball_damping=per_ball("ball_damping", data.get("ball_damping", 1.25e-4), n, nonnegative=True),
            race_radius=number("race_radius", data.get("race_radius", 0.05), positive=True),
            unbalance_mass=number("unbalance_mass", data.get("unbalance_mass", 1.0), positive=True),
            eccentricity=number("eccentricity", data.get("eccentricity", 5.0e-4), nonnegative=True),
            gravity=gravity,
            g=number("g", data.get("g", 9.80665), positive=True),
            speed=speed,
            modal=Modal(mass, stiffness, damping, gyro, shape, load, reduction),
            node_2=BalancerNode.from_mapping(data["node_2"], k) if "node_2" in data else None,
        )

    @classmethod
    def load(cls, path: str | Path) -> "FlexibleScene":
        path = Path(path)
        try:
            data = tomllib.loads(path.read_text())
        except OSError as exc:
            raise SceneError("<file>", f"cannot read {path}: {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise SceneError("<file>", f"{path} is not valid TOML: {exc}") from None
        return cls.from_mapping(data)


# the smallest scene file: the Jeffcott rotor's two identity modes (the scene reference's base mapping)
DEFAULT_PRESET = "jeffcott"


def _preset(name: str) -> dict:
    if name != DEFAULT_PRESET:
        raise SceneError("preset", f"unknown preset {name!r}")
    m = jeffcott_modal(1.0, (1.0e4, 1.0e4), (2.0, 2.0))
    return {"modal": {"mass": [list(r) for r in m.mass], "stiffness": [list(r) for r in m.stiffness],
                      "damping": [list(r) for r in m.damping], "node_shape": [list(r) for r in m.node_shape]}}


# the second node's defaults as the reference shows them (the field is None without one)
KEY_DEFAULTS = {f"node_2.{k}": getattr(BalancerNode, k) for k in ("n", "ball_mass", "ball_damping", "race_radius")}
_SCHEDULE = {"speed": {"law": "schedule", "omega": 400.0, "ramp_time": 1.0}}  # the smallest schedule (tests of KEYS)
_NODE_2 = {"node_2": {"node_shape": [[1.0, 0.0], [0.0, 1.0]]}}  # the smallest second node (tests of KEYS)

KEYS = (
    Key("n", "", "other", "number of balls in the race at the balancer node", "a whole number >= 1"),
    Key("ball_mass", "kg", "positive", "m or [m_1, ..., m_n]"),
    Key("ball_damping", "N m s/rad", "nonnegative", "D or [D_1, ..., D_n], viscous drag on each ball"),
    Key("race_radius", "m", "positive", "R, radius of the race"),
    Key("unbalance_mass", "kg", "positive", "m_u, the unbalanced body (disk) at the balancer node"),
    Key("eccentricity", "m", "nonnegative", "eps, its centre of mass off the shaft's axis (unbalance m_u eps)"),
    Key("gravity", "", "other", "gravity along -y through the modal gravity load", "true or false"),
    Key("g", "m/s^2", "positive", "gravitational acceleration"),
    Key("speed.law", "", "other", "how the spin is governed", '"constant" or "schedule"'),
    Key("speed.omega", "rad/s", "positive", "constant spin speed, or the speed a schedule runs up to and returns to"),
    Key("speed.ramp_time", "s", "positive", "a schedule's run-up from omega_start to omega, at a constant rate",
        context={"speed": {"law": "schedule", "omega": 400.0}}),
    Key("speed.omega_start", "rad/s", "nonnegative", "the speed a schedule's ramp starts from at t = 0 (default 0: "
        "from rest)", context=_SCHEDULE),
    Key("speed.hold_time", "s", "nonnegative", "a schedule's time at omega before the temporary reduction (default 0)",
        context=_SCHEDULE),
    Key("speed.reduction_depth", "", "other", "a schedule's temporary speed reduction, a fraction of omega (default 0)",
        "a number in [0, 1)", _SCHEDULE),
    Key("speed.reduction_rate", "rad/s^2", "positive", "how fast the speed falls to the reduced speed "
        "(default omega / ramp_time)", context=_SCHEDULE),
    Key("speed.plateau_time", "s", "nonnegative", "time held at the reduced speed (default 0)", context=_SCHEDULE),
    Key("speed.recovery_rate", "rad/s^2", "positive", "how fast the speed returns to omega (default omega / ramp_time)",
        context=_SCHEDULE),
    Key("modal.mass", "kg", "other", "M_q = Phi^T M Phi, k x k", "symmetric"),
    Key("modal.stiffness", "N/m", "other", "K_q = Phi^T K Phi, k x k", "symmetric"),
    Key("modal.damping", "N s/m", "other", "C_q = Phi^T C Phi, k x k (default 0)", "symmetric"),
    Key("modal.gyroscopic", "kg", "other", "G_q = Phi^T G Phi, k x k, force -omega G_q q' (default 0)",
        "skew-symmetric"),
    Key("modal.node_shape", "", "other", "the balancer node's x and y translation per unit of each mode", "2 x k"),
    Key("modal.gravity_load", "kg", "other", "Phi^T M e_y, k values (default 0)", "k numbers"),
    Key("modal.reduction", "", "other", "how the matrices were reduced (text, carried to the model's title)",
        "text"),
    Key("node_2.n", "", "other", "number of balls at an optional second balancer node",
        "a whole number >= 1"),
    Key("node_2.ball_mass", "kg", "positive", "m or [m_1, ..., m_n] of the second node's balls", context=_NODE_2),
    Key("node_2.ball_damping", "N m s/rad", "nonnegative", "D or [D_1, ..., D_n] of the second node's balls",
        context=_NODE_2),
    Key("node_2.race_radius", "m", "positive", "radius of the second node's race", context=_NODE_2),
    Key("node_2.node_shape", "", "other", "the second node's x and y translation per unit of each mode", "2 x k"),
)
