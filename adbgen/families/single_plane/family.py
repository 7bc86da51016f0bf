"""The single-plane family (thesis, 2005): an eccentric rotor in one plane with n balls in one race."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SinglePlane:
    name: str = "single-plane"
    title: str = "single-plane rotor with n balls in one race"
    reference: str = "thesis multi-ball ADB (2005)"

    @property
    def scene_type(self) -> type:
        from .scene import Scene

        return Scene

    def load_scene(self, path):
        from .scene import Scene

        return Scene.load(path)

    def derive(self, scene):
        from .model import derive

        return derive(scene)

    def forms(self) -> dict:
        from . import reductions
        from .model import derive
        from .selection import smallest_model

        return {"fixed": derive, "nondimensional": reductions.nondimensionalise,
                "rotating": reductions.rotating_frame, "first-order": lambda scene: smallest_model(scene).system}

    def verify(self, progress, ns=(1, 2, 3, 4, 6)) -> list:
        from ...core.checks import run_registered
        from .verify import run_all

        return run_all(tuple(ns), progress=progress) + run_registered(science_checks(), progress)

    def checks(self, ns=(1, 2, 3, 4, 6)) -> list:
        from .verify import registered

        return registered(tuple(ns)) + science_checks()

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
        from .commands import register

        register(subparsers)

    def reproductions(self) -> dict:
        return {"thesis": "adbgen.families.single_plane.science.reproduce:REPRODUCTION",
                "thesis-orbits": "adbgen.families.single_plane.science.periodic_orbits:REPRODUCTION"}

    def science_commands(self) -> str:
        return "adbgen.families.single_plane.science.commands:register"


# checks that run a generated model (the analysis layer, which the derivation's verify.py may not import): named
# like the reproductions, "module:attribute" of a core.checks.Registered
SCIENCE_CHECKS = ("adbgen.families.single_plane.science.stick_slip_energy:REGISTERED",)


def science_checks() -> list:
    from importlib import import_module

    out = []
    for ref in SCIENCE_CHECKS:
        module, attribute = ref.split(":")
        out.append(getattr(import_module(module), attribute))
    return out


FAMILY = SinglePlane()
