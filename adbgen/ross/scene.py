"""A ROSS rotor and one or two balancer planes -> an adbgen two-plane scene (issue 38 item 1).

The scene's keys are the two-plane family's (`adbgen.families.two_plane.scene.KEYS`, docs/scenes.md);
the mapping built here goes through `TwoPlaneScene.from_mapping`, so a rotor the scene cannot hold is
refused there with the key named.  Axial positions are from the centre of mass (`rotor` module).

One balancer plane: the paper's model has exactly two races in different planes, so the second race is
put at the mirror image of the first about the centre of mass (1 m when the first is at G) and
carries no balls (`masses = []`): it adds nothing to the equations.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from ..families.two_plane.scene import TwoPlaneScene
from .rotor import (RigidBody, RotorError, Support, Unbalance, imbalance, node_position, rigid_body, supports)

# The race's drag when the user gives none: the thesis' default scene's ratio D / (m R^2) = 1 1/s
# (D = 1.25e-4 N m s/rad, m = 0.05 kg, R = 0.05 m; docs/scenes.md, single-plane).
BALL_DRAG_RATE = 1.0


@dataclass(frozen=True)
class Bridged:
    """What the bridge read and the scene it built."""

    scene: TwoPlaneScene
    mapping: dict
    body: RigidBody
    bearings: tuple[Support, Support]
    planes: tuple[int, ...]
    speed: float


def scene_mapping(rotor, planes: list[int], balls: int, ball_mass: float, race_radius: float, speed: float,
                  unbalances: list[Unbalance] = (), ball_damping: float | None = None) -> Bridged:
    """The two-plane scene of `rotor` with `balls` balls of `ball_mass` in a race of `race_radius` at each
    node of `planes` (one or two), bearings' coefficients at `speed` (rad/s), spin constant at `speed`."""
    if not 1 <= len(planes) <= 2:
        raise RotorError(f"one or two balancer planes, got {len(planes)}")
    if len(set(planes)) != len(planes):
        raise RotorError(f"the two balancer planes must be different nodes, got {planes}")
    for what, v in (("--balls", balls), ("--ball-mass", ball_mass), ("--race-radius", race_radius),
                    ("--speed", speed)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise RotorError(f"{what} must be a positive number, got {v!r}")
    body = rigid_body(rotor)
    b1, b2 = supports(rotor, speed)
    l1, l2 = b1.z - body.z_cg, body.z_cg - b2.z
    if l1 < 0 or l2 < 0:
        raise RotorError(f"both bearings are on one side of the centre of mass (z_G = {body.z_cg:.6g} m, bearings "
                         f"at {b2.z:.6g} and {b1.z:.6g} m): the two-plane scene needs l_1, l_2 >= 0")
    drag = ball_mass * race_radius**2 * BALL_DRAG_RATE if ball_damping is None else ball_damping
    races = [{"z": node_position(rotor, n) - body.z_cg, "radius": race_radius, "masses": [ball_mass] * int(balls),
              "damping": drag} for n in planes]
    if len(races) == 1:  # the mirror plane about G, without balls
        races.append({"z": -races[0]["z"] if races[0]["z"] != 0 else 1.0, "radius": race_radius, "masses": [],
                      "damping": drag})
    mapping = {"rotor_mass": body.mass, "transverse_inertia": body.transverse_inertia,
               "polar_inertia": body.polar_inertia, **imbalance(rotor, body, list(unbalances)),
               "bearing_1": _bearing(l1, b1), "bearing_2": _bearing(l2, b2), "races": races,
               "speed": {"law": "constant", "omega": float(speed)}}
    scene = TwoPlaneScene.from_mapping(mapping)
    return Bridged(scene, mapping, body, (b1, b2), tuple(planes), float(speed))


def _bearing(position: float, s: Support) -> dict:
    one = lambda xy: xy[0] if xy[0] == xy[1] else list(xy)  # noqa: E731 (isotropic: one value)
    return {"position": position, "stiffness": one(s.k), "damping": one(s.c)}


def to_toml(mapping: dict, header: str) -> str:
    """The scene as TOML (floats by repr, so the file reads back to the same numbers)."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(float(v)) if isinstance(v, float) else repr(v)

    lines = [f"# {h}" for h in header.splitlines()]
    tables = []
    for k, v in mapping.items():
        if isinstance(v, dict):
            tables.append((f"[{k}]", v))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            tables.extend((f"[[{k}]]", item) for item in v)
        else:
            lines.append(f"{k} = {value(v)}")
    for head, table in tables:
        lines += ["", head] + [f"{k} = {value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def write(bridged: Bridged, out: Path, header: str) -> str:
    text = to_toml(bridged.mapping, header)
    TwoPlaneScene.from_mapping(tomllib.loads(text))  # what is written reads back
    Path(out).write_text(text, encoding="utf-8")
    return text
