"""Model families: each a folder (`single_plane/`, `two_plane/`) with a `family.py` defining ``FAMILY``,
an object of the `Family` protocol, and one registry, `REGISTRY` below, that the command line,
`regenerate`, the benchmarks and the tests read.

To add a family: make `families/<name>/` (scene, model, reductions, checks, models offered for
generation, commands) with `family.py` defining ``FAMILY``, and add one line to `REGISTRY`.
`register` adds a family object at run time (tests, plug-ins outside the package).
"""

from __future__ import annotations

import importlib

from .family import Family

# name -> "module:attribute", in order (the order of generated/ and of `adbgen verify`); one line per family
REGISTRY: dict[str, str] = {
    "single-plane": "adbgen.families.single_plane.family:FAMILY",
    "two-plane": "adbgen.families.two_plane.family:FAMILY",
    "flexible": "adbgen.families.flexible.family:FAMILY",
}
_loaded: dict[str, Family] = {}


def register(family: Family, replace: bool = False) -> None:
    """Add a family object at run time."""
    if family.name in REGISTRY and not replace:
        raise ValueError(f"a family named {family.name!r} is registered already")
    REGISTRY[family.name] = ""
    _loaded[family.name] = family


def unregister(name: str) -> None:
    REGISTRY.pop(name, None)
    _loaded.pop(name, None)


def names() -> tuple[str, ...]:
    return tuple(REGISTRY)


def get(name: str) -> Family:
    if name not in REGISTRY:
        raise KeyError(f"unknown family {name!r}; families: {', '.join(REGISTRY)}")
    if name not in _loaded:
        module, attr = REGISTRY[name].split(":")
        _loaded[name] = getattr(importlib.import_module(module), attr)
    return _loaded[name]


def all_families() -> tuple[Family, ...]:
    return tuple(get(name) for name in REGISTRY)


def kinds() -> dict:
    """Every family's model kinds indexed by the number of balls, {kind: n -> ModelSpec}."""
    out = {}
    for family in all_families():
        out.update(family.kinds())
    return out


__all__ = ["kinds", "Family", "REGISTRY", "all_families", "get", "names", "register", "unregister"]
