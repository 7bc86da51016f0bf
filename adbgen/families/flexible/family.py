"""The flexible-rotor family (issue 38): a rotor reduced to k modes (numbers from a finite-element model,
e.g. ROSS through `adbgen.ross`) with n balls in a race at one balancer node."""

from __future__ import annotations

from dataclasses import dataclass

from ..family import PackageFamily


@dataclass(frozen=True)
class Flexible(PackageFamily):
    name: str = "flexible"
    title: str = "flexible rotor in k modes with n balls at one node"
    reference: str = "single-plane model (thesis 2005) where they overlap"
    scene_class = "FlexibleScene"

    def register_commands(self, subparsers) -> None:
        return None  # no commands of its own: simulate, steady, stability run its models by their description


FAMILY = Flexible()
