"""Model families: each a folder (`single_plane/`, `two_plane/`) with a `family.py` defining ``FAMILY``,
an object of the `Family` protocol, and one registry, `REGISTRY` below, that the command line,
`regenerate`, the benchmarks and the tests read.

To add a family: make `families/<name>/` (scene, model, reductions, checks, models offered for
generation, commands) with `family.py` defining ``FAMILY``, and add one line to `REGISTRY`.
`register` adds a family object at run time (tests, plug-ins outside the package).
"""

from __future__ import annotations

from ..registry import Registry
from .family import Family

# name -> "module:attribute", in order (the order of generated/ and of `adbgen verify`); one line per family
REGISTRY: dict[str, str] = {
    "single-plane": "adbgen.families.single_plane.family:FAMILY",
    "two-plane": "adbgen.families.two_plane.family:FAMILY",
    "flexible": "adbgen.families.flexible.family:FAMILY",
}
_registry = Registry("family", "families", REGISTRY)
register = _registry.register  # add a family object at run time: register(family, replace=False)
unregister = _registry.unregister
names = _registry.names
get = _registry.get
all_families = _registry.all


def kinds() -> dict:
    """Every family's model kinds indexed by the number of balls, {kind: n -> ModelSpec}."""
    out = {}
    for family in all_families():
        out.update(family.kinds())
    return out


__all__ = ["kinds", "Family", "REGISTRY", "all_families", "get", "names", "register", "unregister"]
