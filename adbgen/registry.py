"""A registry of named objects, each given as a "module:attribute" string and imported when first asked for
(the families', `adbgen.families.REGISTRY`, and the code-generation targets', `adbgen.codegen.targets.REGISTRY`).
`register` adds an object at run time (tests, plug-ins outside the package).  Only the standard library is
imported here (the command line and the analysis layer load without SymPy)."""

from __future__ import annotations

import importlib
from typing import Any


def load(entry: str) -> Any:
    """The object a "module:attribute" string names."""
    module, attr = entry.split(":")
    return getattr(importlib.import_module(module), attr)


class Registry:
    """``entries``: name -> "module:attribute" ("" for an object registered at run time), in order; ``kind``
    and ``plural`` name the entries in messages ("family", "families")."""

    def __init__(self, kind: str, plural: str, entries: dict[str, str]):
        self.kind, self.plural, self.entries = kind, plural, entries
        self._loaded: dict[str, Any] = {}
        self.generation = 0  # changes whenever the registry does (caches built from it know to rebuild)

    def register(self, obj: Any, replace: bool = False) -> None:
        """Add an object (with a ``name``) at run time."""
        if obj.name in self.entries and not replace:
            raise ValueError(f"a {self.kind} named {obj.name!r} is registered already")
        self.entries[obj.name] = ""
        self._loaded[obj.name] = obj
        self.generation += 1

    def unregister(self, name: str) -> None:
        self.entries.pop(name, None)
        self._loaded.pop(name, None)
        self.generation += 1

    def names(self) -> tuple[str, ...]:
        return tuple(self.entries)

    def get(self, name: str) -> Any:
        if name not in self.entries:
            raise KeyError(f"unknown {self.kind} {name!r}; {self.plural}: {', '.join(self.entries)}")
        if name not in self._loaded:
            self._loaded[name] = load(self.entries[name])
        return self._loaded[name]

    def all(self) -> tuple:
        return tuple(self.get(name) for name in self.entries)
