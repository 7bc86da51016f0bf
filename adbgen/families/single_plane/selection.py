"""Model no more than the scene needs: the smallest form that is exact for it.

- isotropic support, equal balls, constant speed, no gravity: the autonomous rotating-frame system
  (2.25)-(2.27) in the thesis' dimensionless parameters (2 + n coordinates, no explicit time);
- the same with unequal balls (or no support stiffness, where the scalings (2.15)-(2.19) fail, or friction
  between ball and race, which the thesis' scalings do not cover): the rotating-frame system in the
  dimensional parameters, still autonomous;
- anisotropy, gravity or a prescribed run-up: the fixed-frame equations (2.10), (2.11), (2.13) with
  the spin prescribed (2 + n coordinates, explicit time);
- a driving torque: the fixed frame with the torsional equation (2.12) (3 + n coordinates).
"""

from __future__ import annotations

from dataclasses import dataclass

from .scene import Scene
from .model import derive
from .reductions import (FirstOrderSystem, first_order, non_autonomous_reasons, rotating_frame,
                         rotating_frame_dimensional)


@dataclass(frozen=True)
class SelectedModel:
    kind: str
    reason: str
    system: FirstOrderSystem


def smallest_model(scene: Scene) -> SelectedModel:
    if scene.speed.law == "torque":
        return SelectedModel("fixed-frame-torque", "the spin is driven by a torque: (2.12) is needed",
                             first_order(derive(scene)))
    reasons = non_autonomous_reasons(scene)
    if reasons:
        return SelectedModel("fixed-frame", ", ".join(reasons) + ": not autonomous in a rotating frame",
                             first_order(derive(scene)))
    if scene.equal_balls and scene.stiffness_xy()[0] > 0 and not scene.friction:
        return SelectedModel("rotating-frame", "isotropic, equal balls, constant speed, no gravity: autonomous (2.25)-(2.27)",
                             first_order(rotating_frame(scene)))
    return SelectedModel("rotating-frame-dimensional",
                         "isotropic, constant speed, no gravity: autonomous in the rotating frame; unequal balls "
                         "(or no support stiffness, or friction) keep the dimensional parameters",
                         first_order(rotating_frame_dimensional(scene)))
