"""The flexible-rotor family (issue 38): a rotor reduced to k modes (numbers from a finite-element model,
e.g. ROSS through `adbgen.ross`) with n balls in a race at one balancer node."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Flexible:
    name: str = "flexible"
    title: str = "flexible rotor in k modes with n balls at one node"
    reference: str = "single-plane model (thesis 2005) where they overlap"

    @property
    def scene_type(self) -> type:
        from .scene import FlexibleScene

        return FlexibleScene

    def load_scene(self, path):
        from .scene import FlexibleScene

        return FlexibleScene.load(path)

    def derive(self, scene):
        from .model import derive

        return derive(scene)

    def forms(self) -> dict:
        from .model import derive
        from .models import for_scene

        return {"fixed": derive, "first-order": lambda scene: for_scene(scene).system()}

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
        from .models import KINDS

        return dict(KINDS)

    def model_for_scene(self, scene, name=None):
        from .models import for_scene

        return for_scene(scene, name)

    def register_commands(self, subparsers) -> None:
        return None  # no commands of its own: simulate, steady, stability run its models by their description

    def reproductions(self) -> dict:
        return {}

    def science_commands(self) -> str:
        return ""


FAMILY = Flexible()
