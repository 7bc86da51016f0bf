"""The single-plane family (thesis, 2005): an eccentric rotor in one plane with n balls in one race."""

from __future__ import annotations

from dataclasses import dataclass

from ..family import PackageFamily


@dataclass(frozen=True)
class SinglePlane(PackageFamily):
    name: str = "single-plane"
    title: str = "single-plane rotor with n balls in one race"
    reference: str = "thesis multi-ball ADB (2005)"

    def forms(self) -> dict:
        from . import reductions
        from .model import derive
        from .selection import smallest_model

        return {"fixed": derive, "nondimensional": reductions.nondimensionalise,
                "rotating": reductions.rotating_frame, "first-order": lambda scene: smallest_model(scene).system}

    def checks(self, ns=None) -> list:
        """The derivation's checks (``verify.registered``) and those that run a generated model."""
        return super().checks(ns) + science_checks()

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
