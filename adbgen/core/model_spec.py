"""A model offered for generation, as a family declares it: how to derive it, its start points, what
AUTO-07p continues, the reduction checks behind it and what the generated module says about itself.

This is the contract between the families and code generation: the families fill these in (in their
`models.py`), `adbgen.codegen` reads them (`codegen.spec.build` lowers a spec to the intermediate
form; `codegen.regenerate` runs its checks and writes it).  Data only: nothing here imports a family
or code generation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

from .checks import CheckResult
from .first_order import FirstOrderSystem

if TYPE_CHECKING:
    from .description import Description


@dataclass(frozen=True)
class Continuation:
    """What AUTO-07p follows from a model's start point: decided by the family, printed by the AUTO target.

    Steady states (autonomous models) are continued in `parameter` in the `direction` (+1 up, -1
    down), until it leaves `stop` (UZSTOP) if given.  Periodic orbits of an oscillator extension go in
    two stages: in `parameter` from the start orbit to its default, then in `second` (the forcing
    frequency).  `continuum`: the start lies on a continuum of steady states (free ball angles), so
    the continuation is singular there and the files say so.
    """

    parameter: str
    direction: int = -1
    stop: tuple[float, float] | None = None
    second: str = ""
    continuum: bool = False
    note: str = ""  # a remark for the constants file's header (lines)


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
    the reduction checks `regenerate` runs before it writes this model.  ``kind``: the family's name
    for this sort of model ("thesis_rotating", "two_plane_fixed", "scene", ...); ``describe(system)``:
    what the generated module says about itself (`core.description.Description`: roles, angles,
    measures, symmetries, closed-form steady states, ...), checked against the rendered code before
    anything is written.
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
    # each ball's own parameters, {slot: c * parameter} per ball (`codegen.passes.ball_split`); None: by name
    balls: Callable[[FirstOrderSystem], list[dict]] | None = None
    kind: str = ""
    describe: "Callable[[FirstOrderSystem], Description] | None" = None


def start_values(system: FirstOrderSystem, start: tuple) -> tuple:
    """(state, label, parameter values) from a start function's (state, label[, {name: value}])."""
    state, label, *where = start
    values = [p.default for p in system.parameters]
    if where:
        names = [p.name for p in system.parameters]
        for key, value in where[0].items():
            values[names.index(key)] = float(value)
    return state, label, values
