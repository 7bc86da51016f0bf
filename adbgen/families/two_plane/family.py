"""The two-plane family (Rodrigues, Champneys, Friswell & Wilson 2011): a rigid rotor on two bearings with
balls in two races."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class TwoPlane:
    name: str = "two-plane"
    title: str = "two-plane rigid rotor with balls in two races"
    reference: str = "two-plane automatic balancing (2011)"

    @property
    def scene_type(self) -> type:
        from .scene import TwoPlaneScene

        return TwoPlaneScene

    def load_scene(self, path):
        from .scene import TwoPlaneScene

        return TwoPlaneScene.load(path)

    def derive(self, scene):
        from .model import derive

        return derive(scene)

    def forms(self) -> dict:
        from .model import derive
        from .models import for_scene
        from .reductions import rotating_frame

        return {"fixed": derive, "rotating": rotating_frame, "first-order": lambda scene: for_scene(scene).system()}

    def verify(self, progress, ns=()) -> list:
        from .verify import run_all

        return run_all(progress=progress)

    def checks(self, ns=()) -> list:
        from .verify import registered

        return registered(tuple(ns))

    def models(self) -> list:
        from .models import default_set

        return default_set()

    def kinds(self) -> dict:
        return {}  # the paper's set-ups have two balls per race; its models are not indexed by n

    def model_for_scene(self, scene, name=None):
        from .models import for_scene

        return for_scene(scene, name)

    def register_commands(self, subparsers) -> None:
        from .commands import register

        register(subparsers)

    def reproductions(self) -> dict:
        return {"two-plane": "adbgen.families.two_plane.science.reproduce:REPRODUCTION",
                "two-plane-orbits": "adbgen.families.two_plane.science.periodic_orbits:REPRODUCTION"}

    def science_commands(self) -> str:
        return ""


FAMILY = TwoPlane()
