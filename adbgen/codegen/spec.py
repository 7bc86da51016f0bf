"""A model offered for generation: how to derive it, its start points, what AUTO-07p continues, and the
reduction checks behind it, all as data that the family fills in and `regenerate` reads."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..core.checks import CheckResult
from ..core.first_order import FirstOrderSystem
from .ir import Continuation, ModelIR
from .lowering import DEFAULT_FORM, build


@dataclass(frozen=True)
class Check:
    """A reduction check behind a model; `key` identifies it, so a check shared by models runs once.

    `scaled`: its proportionate form, run by `regenerate` unless --full-checks (issue 10: a check that
    scales badly in n, e.g. exact symbolic zeros of O(n)-term sums, replaced at large n by what is
    structurally sufficient); None: the full form always runs."""

    key: tuple
    run: Callable[[], CheckResult]
    scaled: Callable[[], CheckResult] | None = None


def no_start(system: FirstOrderSystem) -> tuple:
    return None, ""


@dataclass(frozen=True)
class ModelSpec:
    """A named model of a family.

    ``start(system)`` gives (state, label) at the defaults or (state, label, {parameter: value}) where
    the state is a steady state, or (None, "") when none is known; ``continuation`` says what AUTO-07p
    follows from it.  A periodically forced model may give ``orbit_start``, a point of an exact
    periodic orbit of its oscillator extension, with ``orbit_continuation`` (two stages).  ``checks``:
    the reduction checks `regenerate` runs before it writes this model.
    """

    name: str
    title: str
    n: int
    system: Callable[[], FirstOrderSystem]
    start: Callable[[FirstOrderSystem], tuple] = no_start
    orbit_start: Callable[[FirstOrderSystem], tuple] | None = None
    family: str = ""
    checks: tuple[Check, ...] = ()
    continuation: Continuation | Callable[[FirstOrderSystem, tuple], Continuation | None] | None = None
    orbit_continuation: Continuation | None = None
    # each ball's own parameters, {slot: c * parameter} per ball (`codegen.balls`); None: by name
    balls: Callable[[FirstOrderSystem], list[dict]] | None = None

    def build(self, system: FirstOrderSystem | None = None, form: str = DEFAULT_FORM) -> ModelIR:
        system = system if system is not None else self.system()
        slots = self.balls(system) if self.balls is not None else None
        extension = None
        orbit = start_values(system, self.orbit_start(system)) if self.orbit_start is not None else (None,)
        if orbit[0] is not None:  # (no exact orbit known, e.g. one ball: no extension)
            start, label, values = orbit
            extension = build(self.name, system, title=self.title + ", autonomous extension (oscillator)",
                              n_balls=self.n, start=start, start_label=label, start_parameters=values,
                              oscillator=True, continuation=self.orbit_continuation, balls=slots, form=form)
        start, label, values = start_values(system, self.start(system))
        continuation = self.continuation
        if callable(continuation):
            continuation = continuation(system, (start, label, values))
        return build(self.name, system, title=self.title, n_balls=self.n, start=start, start_label=label,
                     start_parameters=values, autonomous_extension=extension,
                     continuation=continuation if start is not None else None, balls=slots, form=form)


def start_values(system: FirstOrderSystem, start: tuple) -> tuple:
    """(state, label, parameter values) from a start function's (state, label[, {name: value}])."""
    state, label, *where = start
    values = [p.default for p in system.parameters]
    if where:
        names = [p.name for p in system.parameters]
        for key, value in where[0].items():
            values[names.index(key)] = float(value)
    return state, label, values
