"""Code-generation targets: one folder each (its configuration in `__init__.py`, its jinja2 templates in
`templates/`, shipped as package data), registered in one place, `REGISTRY` below.

A target is a `Target`: its name, its files (template -> output path), the printer its programs are
printed with, and hooks that hold its decisions in Python rather than in templates (whether a model
gets it, which form of the model it renders, extra template data).  To add one (SymForce's
`codegen/backends/<language>/` in small):

1. make `targets/<name>/__init__.py` defining ``TARGET = Target(...)`` (or a subclass) and put its
   templates in `targets/<name>/templates/`; templates refer to each other as "<name>/<file>";
2. add one line to `REGISTRY`.

`register` adds a target at run time (tests, plug-ins outside the package).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..ir import ModelIR

# name -> "module:attribute", in rendering order; one line per target
REGISTRY: dict[str, str] = {
    "numba": "adbgen.codegen.targets.numba:TARGET",
    "c": "adbgen.codegen.targets.c:TARGET",
    "cvode": "adbgen.codegen.targets.cvode:TARGET",
    "auto": "adbgen.codegen.targets.auto:TARGET",
    "taylor": "adbgen.codegen.targets.taylor:TARGET",
}
_loaded: dict[str, "Target"] = {}


@dataclass(frozen=True)
class Target:
    """A code-generation target.

    ``files``: (template name, output path) pairs; the path may use {name} (the model's name).  A
    template that renders to blank text writes no file (an optional file).  ``language`` picks the
    printer of the programs: "py" (numba, plain Python) or "c" (C99).  ``loops``: see the field.
    """

    name: str
    files: tuple[tuple[str, str], ...]
    language: str
    templates: Path
    description: str = ""
    filters: dict = field(default_factory=dict)
    # prints the functions' `code` (the loop form or the unrolled one, through codegen/emit.py); a
    # target that prints the programs' statements one by one (programs.<fn>.assignments, ir.rhs)
    # leaves it False and gets the unrolled form
    loops: bool = False

    def skip_reason(self, ir: "ModelIR") -> str | None:
        """Why this target does not render the model (None: it does)."""
        return None

    def model_for(self, ir: "ModelIR") -> "ModelIR":
        """The form of the model this target renders (the AUTO target: a forced model's extension)."""
        return ir

    def context(self, ir: "ModelIR") -> dict:
        """Template data beyond the common context (decisions made here, in Python)."""
        return {}


def register(target: Target, replace: bool = False) -> None:
    """Add a target object at run time (one line; e.g. from a test or a plug-in)."""
    if target.name in names() and not replace:
        raise ValueError(f"a target named {target.name!r} is registered already")
    REGISTRY[target.name] = ""
    _loaded[target.name] = target
    _invalidate()


def unregister(name: str) -> None:
    REGISTRY.pop(name, None)
    _loaded.pop(name, None)
    _invalidate()


_generation = [0]


def _invalidate() -> None:
    _generation[0] += 1


def generation() -> int:
    """Changes whenever the registry does (so that caches of rendering know to rebuild)."""
    return _generation[0]


def names() -> tuple[str, ...]:
    return tuple(REGISTRY)


def get(name: str) -> Target:
    if name not in REGISTRY:
        raise KeyError(f"unknown target {name!r}; targets: {', '.join(REGISTRY)}")
    if name not in _loaded:
        module, attr = REGISTRY[name].split(":")
        _loaded[name] = getattr(importlib.import_module(module), attr)
    return _loaded[name]


def all_targets() -> tuple[Target, ...]:
    return tuple(get(name) for name in REGISTRY)
