"""Validation of scene fields shared by every family: numbers, per-ball lists, X/Y pairs, the speed law.

Each helper returns the value or raises SceneError naming the field, so a bad scene gives one line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from ..errors import SceneError


def number(name: str, value: Any, *, positive: bool = False, nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(name, f"must be a number, got {value!r}")
    try:
        value = float(value)
    except OverflowError:
        raise SceneError(name, "must be finite, got an integer too large for a float") from None
    if not math.isfinite(value):
        raise SceneError(name, f"must be finite, got {value!r}")
    if positive and value <= 0:
        raise SceneError(name, f"must be positive, got {value!r}")
    if nonnegative and value < 0:
        raise SceneError(name, f"must be non-negative, got {value!r}")
    return value


def per_ball(name: str, value: Any, n: int, **kw) -> tuple[float, ...] | float:
    """A scalar (the same for every ball) or a list of exactly n values."""
    if isinstance(value, (list, tuple)):
        if len(value) != n:
            raise SceneError(name, f"needs one value or n = {n} values, got {len(value)}")
        return tuple(number(f"{name}[{i}]", v, **kw) for i, v in enumerate(value))
    return number(name, value, **kw)


def friction_coefficients(rolling: Any, static: Any, n: int):
    """(mu_r, mu_s) of a scene's balls (issue 37), each None (absent), one value or n values, both families:
    the stick phase needs the friction while a ball slips, and mu_s >= mu_r for every ball (with mu_r > mu_s a
    ball whose stiction breaks would decelerate at once in its slip: it could neither stick nor slip)."""
    rolling, static = (None if v is None else per_ball(key, v, n, nonnegative=True)
                       for key, v in (("rolling_resistance", rolling), ("static_friction", static)))
    if static is not None:
        if rolling is None:
            raise SceneError("static_friction", "needs rolling_resistance (the friction while a ball slips)")
        pairs = zip(*(v if isinstance(v, tuple) else (v,) * n for v in (rolling, static)))
        for i, (r, s) in enumerate(pairs):
            if s < r:
                raise SceneError("static_friction", f"must be >= rolling_resistance (ball {i + 1}: {s!r} < {r!r})")
    return rolling, static


class BallFriction:
    """What a scene with `rolling_resistance`, `static_friction` (each None, one value or n) and `n` says about
    ball-race friction (issue 37), in both families."""

    @property
    def friction(self) -> bool:
        """Friction between ball and race is modelled (rolling_resistance given, zero or not)."""
        return self.rolling_resistance is not None

    @property
    def stiction(self) -> bool:
        """The stick phase is modelled (static_friction given): the model carries each ball's mode."""
        return self.static_friction is not None

    def static_frictions(self) -> tuple[float, ...]:
        s = self.static_friction
        return s if isinstance(s, tuple) else (0.0 if s is None else s,) * self.n

    def rolling_resistances(self) -> tuple[float, ...]:
        r = self.rolling_resistance
        return r if isinstance(r, tuple) else (0.0 if r is None else r,) * self.n


def xy(name: str, value: Any, **kw) -> tuple[float, float] | float:
    """A scalar (isotropic) or a pair (X, Y)."""
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise SceneError(name, f"needs one value or two values [X, Y], got {len(value)}")
        return (number(f"{name}[0]", value[0], **kw), number(f"{name}[1]", value[1], **kw))
    return number(name, value, **kw)


def speed_law_name(data: Any, fields: Mapping[str, set]) -> str:
    """The 'law' of a [speed] table, checked against ``fields`` {law: allowed keys}."""
    if not isinstance(data, Mapping):
        raise SceneError("speed", f"must be a table with a 'law', got {data!r}")
    law = data.get("law", "constant")
    if not isinstance(law, str) or law not in fields:
        raise SceneError("speed.law", f"unknown speed law {law!r}; choose one of {', '.join(fields)}")
    for key in sorted(set(map(str, data)) - fields[law]):
        raise SceneError(f"speed.{key}", f"unknown option for law {law!r}")
    return law


# --- what a scene format documents about each key (the scene reference, docs/scenes.md) ---------------

DOMAINS = ("positive", "nonnegative", "real", "other")


@dataclass(frozen=True)
class Key:
    """One key of a scene file as its format accepts it: the TOML path ("speed.omega", "races[].z"), the
    unit, the domain the validator enforces ("positive" | "nonnegative" | "real", each checked against
    the validator by tests/families/test_scene_reference.py, or "other" with the rule in `allowed`), what
    it means, and the context it needs (e.g. {"speed": {"law": "torque"}} for speed.tau0).  Defaults are
    not written here: the reference reads them off the scene class's own defaults."""

    path: str
    unit: str
    domain: str
    meaning: str
    allowed: str = ""
    context: Mapping[str, Any] | None = None
