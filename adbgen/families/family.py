"""What a model family offers the rest of adbgen (the `Family` protocol), and `PackageFamily`, the one
implementation of it that the families in this package share."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any, Callable, Protocol, Sequence, runtime_checkable

if TYPE_CHECKING:
    import argparse
    from pathlib import Path

    from ..core.model_spec import ModelSpec
    from ..core.checks import CheckResult, Registered


@runtime_checkable
class Family(Protocol):
    """A model family: a kind of machine (single-plane rotor, two-plane rotor, ...) from scene to models.

    ``name`` is its key in the registry and on the command line (``adbgen verify --model NAME``,
    ``adbgen regenerate --family NAME``).

    A family's science (published values, reproductions, plots of its own quantities, commands that run
    the generated models) sits in its ``science`` sub-package above the analysis layer; the hooks
    `reproductions` and `science_commands` name it by "module:attribute" strings, so that the family's
    derivations never import it (the command line loads them).  Both may be left out by a family with
    no science of its own (they then count as empty).
    """

    name: str
    title: str
    reference: str  # the source its equations are checked against
    scene_type: type

    def load_scene(self, path: "str | Path") -> Any:
        """A validated scene from a TOML file (SceneError naming the field otherwise)."""

    def derive(self, scene: Any) -> Any:
        """The equations of motion of a scene by Lagrange's equations (an EquationsOfMotion)."""

    def forms(self) -> dict[str, Callable[[Any], Any]]:
        """The named forms of a scene's model, e.g. {"fixed": ..., "rotating": ..., "first-order": ...}."""

    def verify(self, progress: Callable[["CheckResult"], None], ns: Sequence[int] = ()) -> list["CheckResult"]:
        """Every check of the family (``adbgen verify``); ``ns``: numbers of balls where it matters."""

    def checks(self, ns: Sequence[int] = ()) -> list["Registered"]:
        """The registered checks behind ``verify``: each with its kind (what it compares) and a
        deliberately wrong variant it must reject (tests/families/test_negative_controls.py)."""

    def models(self) -> list["ModelSpec"]:
        """The models of the default set in generated/, each with start points and checks."""

    def kinds(self) -> dict[str, Callable[[int], "ModelSpec"]]:
        """The family's model kinds indexed by the number of balls, {kind: n -> ModelSpec}
        (``adbgen regenerate --n``, the code-generation benchmark); {} if it offers none."""

    def model_for_scene(self, scene: Any, name: str | None = None) -> "ModelSpec":
        """The smallest exact model of a scene, with the family's checks (``regenerate --scene``)."""

    def register_commands(self, subparsers: "argparse._SubParsersAction") -> None:
        """Add the family's command-line subcommands."""

    def reproductions(self) -> dict[str, str]:
        """The family's sections of ``adbgen reproduce``: {key (``--only KEY``): "module:attribute" of an
        `adbgen.analysis.reproduction.Reproduction`}, in the document's order."""

    def science_commands(self) -> str:
        """"module:function" adding the family's commands that run generated models, or ""."""


class PackageFamily:
    """A family whose parts stand under fixed names in the modules of its own package, imported when first
    asked for: ``scene.<scene_class>``, ``model.derive``, ``verify.registered``, ``models.default_set`` /
    ``KINDS`` / ``for_scene`` and ``commands.register``.  A family's ``family.py`` subclasses it (as a
    frozen dataclass with ``name``, ``title`` and ``reference``) and overrides only what differs."""

    scene_class = "Scene"

    def _module(self, name: str):
        return importlib.import_module(f"{type(self).__module__.rpartition('.')[0]}.{name}")

    @property
    def scene_type(self) -> type:
        return getattr(self._module("scene"), self.scene_class)

    def load_scene(self, path):
        return self.scene_type.load(path)

    def derive(self, scene):
        return self._module("model").derive(scene)

    def forms(self) -> dict:
        for_scene = self._module("models").for_scene
        return {"fixed": self._module("model").derive, "first-order": lambda scene: for_scene(scene).system()}

    def checks(self, ns=None) -> list:
        """The ``verify.registered`` checks; ``ns`` None: the family's default numbers of balls."""
        registered = self._module("verify").registered
        return registered() if ns is None else registered(tuple(ns))

    def verify(self, progress, ns=None) -> list:
        from ..core.checks import run_registered

        return run_registered(self.checks(ns), progress)

    def models(self) -> list:
        return self._module("models").default_set()

    def kinds(self) -> dict:
        return dict(self._module("models").KINDS)

    def model_for_scene(self, scene, name=None):
        return self._module("models").for_scene(scene, name)

    def register_commands(self, subparsers) -> None:
        self._module("commands").register(subparsers)

    def reproductions(self) -> dict:
        return {}

    def science_commands(self) -> str:
        return ""
