"""The ROSS bridge: a ROSS rotor (object or saved file) -> an adbgen two-plane scene and a rigidity verdict.

Issue 38 items 1 and 2.  ROSS (`ross-rotordynamics`, the optional extra ``adbgen[ross]``) is imported
only when a rotor is read.  Modules: `rotor` (what the rotor is as a rigid body on two bearings, from
ROSS's own matrices and element sums), `scene` (the two-plane scene's mapping and its TOML),
`rigidity` (the rigid model's critical speeds against ROSS's Campbell diagram).  The steps, with the
example rotor's numbers: docs/ross.md.
"""

from __future__ import annotations

from dataclasses import dataclass

from .rigidity import AGREEMENT, MARGIN, Verdict, verdict
from .rotor import RotorError, Unbalance, load_rotor, speed_dependent
from .scene import Bridged, scene_mapping

# No operating speed given and none in the rotor (`rated_w`): 1.5 x the rigid model's highest critical
# speed; a balancer balances above the rotor's critical speeds (paper section 3), and 1.5 keeps it clear.
ABOVE_CRITICAL = 1.5


@dataclass(frozen=True)
class FromRoss:
    bridged: Bridged
    verdict: Verdict | None  # None when the check was not asked for


def operating_speed(rotor, speed: float | None, planes, balls, ball_mass, race_radius) -> tuple[float, list | None]:
    """The speed the bearings' coefficients are taken at and the scene spins at, and the rigid model's
    critical speeds when they were computed to find it (bearings independent of speed: the same)."""
    if speed is not None:
        return float(speed), None
    if getattr(rotor, "rated_w", None):
        return float(rotor.rated_w), None
    if speed_dependent(rotor):
        raise RotorError("the bearings' coefficients depend on speed and the rotor has no rated_w: give --speed")
    from ..families.two_plane.critical_speeds import critical_speeds

    probe = scene_mapping(rotor, planes, balls, ball_mass, race_radius, 1.0)
    crit = critical_speeds(probe.scene, with_balls=False)
    return ABOVE_CRITICAL * max(crit), crit


def from_ross(source, planes: list[int], balls: int, ball_mass: float, race_radius: float, *,
              speed: float | None = None, unbalances: list[Unbalance] = (), ball_damping: float | None = None,
              check: bool = True, margin: float = MARGIN, agreement: float = AGREEMENT) -> FromRoss:
    """Read the rotor, build the scene, and (``check``) decide whether the rigid scene is enough."""
    from ..families.two_plane.critical_speeds import critical_speeds

    rotor = load_rotor(source)
    omega, crit = operating_speed(rotor, speed, planes, balls, ball_mass, race_radius)
    bridged = scene_mapping(rotor, planes, balls, ball_mass, race_radius, omega, unbalances, ball_damping)
    if not check:
        return FromRoss(bridged, None)
    top = max(omega, float(getattr(rotor, "max_w", None) or 0.0))
    rigid = crit if crit is not None else critical_speeds(bridged.scene, with_balls=False)
    return FromRoss(bridged, verdict(rotor, rigid, top, margin, agreement))


__all__ = ["AGREEMENT", "MARGIN", "FromRoss", "RotorError", "Unbalance", "Verdict", "from_ross", "load_rotor",
           "operating_speed", "scene_mapping", "verdict"]
