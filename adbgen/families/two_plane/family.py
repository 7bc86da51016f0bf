"""The two-plane family (Rodrigues, Champneys, Friswell & Wilson 2011): a rigid rotor on two bearings with
balls in two races."""

from __future__ import annotations

from dataclasses import dataclass

from ..family import PackageFamily


@dataclass(frozen=True)
class TwoPlane(PackageFamily):
    name: str = "two-plane"
    title: str = "two-plane rigid rotor with balls in two races"
    reference: str = "two-plane automatic balancing (2011)"
    scene_class = "TwoPlaneScene"

    def forms(self) -> dict:
        from .model import derive
        from .models import for_scene
        from .reductions import rotating_frame

        return {"fixed": derive, "rotating": rotating_frame, "first-order": lambda scene: for_scene(scene).system()}

    def checks(self, ns=None) -> list:
        """The derivation's checks (``verify.registered``) and those that run a generated model (the analysis
        layer, which the derivation's verify.py may not import; loaded by name as single_plane's are)."""
        from importlib import import_module

        return super().checks(ns) + [getattr(import_module(module), attribute)
                                     for module, attribute in (ref.split(":") for ref in SCIENCE_CHECKS)]

    def kinds(self) -> dict:
        return {}  # the paper's set-ups have two balls per race; its models are not indexed by n

    def reproductions(self) -> dict:
        return {"two-plane": "adbgen.families.two_plane.science.reproduce:REPRODUCTION",
                "two-plane-orbits": "adbgen.families.two_plane.science.periodic_orbits:REPRODUCTION"}


# checks that run a generated model, "module:attribute" of a core.checks.Registered
SCIENCE_CHECKS = ("adbgen.families.two_plane.science.stick_slip_energy:REGISTERED",)

FAMILY = TwoPlane()
