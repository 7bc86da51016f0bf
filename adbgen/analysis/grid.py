"""A sweep's grid: axes over parameters or initial states, read from ``--grid NAME=FROM:TO:COUNT``.

FROM and TO are both included (numpy.linspace) and may be expressions in pi (``7*pi/4``).  An axis
is a parameter of the model or one of its states (an initial value); everything not on an axis is
fixed by ``--set`` (parameters, default DEFAULTS) and ``--y0`` (states, default 0).  Grid points are
numbered in C order over the axes as given, so axis k is dimension k of the stored arrays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .loading import AnalysisError, Model, parse_value

MAX_POINTS = 100_000_000


@dataclass(frozen=True)
class Axis:
    name: str
    start: float
    stop: float
    count: int
    kind: str  # "parameter" or "state"

    @property
    def values(self) -> np.ndarray:
        return np.linspace(self.start, self.stop, self.count)

    def to_json(self) -> list:
        return [self.name, self.start, self.stop, self.count]


def parse_axis(text: str, model: Model) -> Axis:
    """``NAME=FROM:TO:COUNT`` -> Axis; one clear line for every bad form."""
    name, sep, rest = str(text).partition("=")
    name = name.strip()
    if not sep or not name:
        raise AnalysisError(f"--grid {text!r}: expected NAME=FROM:TO:COUNT")
    parts = rest.split(":")
    if len(parts) != 3:
        raise AnalysisError(f"--grid {text!r}: expected NAME=FROM:TO:COUNT (three fields after '=')")
    if name in model.param_names:
        kind = "parameter"
    elif name in model.state_names:
        kind = "state"
    else:
        raise AnalysisError(f"--grid {name}: unknown name for {model.name}; parameters: "
                            f"{', '.join(model.param_names)}; states: {', '.join(model.state_names)}")
    start = parse_value(parts[0], f"--grid {name} FROM")
    stop = parse_value(parts[1], f"--grid {name} TO")
    try:
        count = int(parts[2].strip())
    except ValueError:
        raise AnalysisError(f"--grid {name}: COUNT must be a whole number, got {parts[2]!r}") from None
    if count < 1:
        raise AnalysisError(f"--grid {name}: COUNT must be at least 1, got {count} (an empty grid)")
    if stop < start:
        raise AnalysisError(f"--grid {name}: reversed range, FROM {start:g} > TO {stop:g}")
    if count > 1 and stop == start:
        raise AnalysisError(f"--grid {name}: empty range, FROM = TO = {start:g} with COUNT {count} (use COUNT 1 "
                            f"or --set/--y0)")
    return Axis(name, start, stop, count, kind)


@dataclass(frozen=True)
class Tie:
    """An initial state that follows a grid axis: state = sign * axis value + offset (``--tie phi_3=phi_1+pi``,
    ``--tie phi_2=-phi_1``: the balls opposite about the x-axis of thesis Figs. 5.5(a), 5.7(a), 5.9(a))."""

    state: str
    axis: str
    offset: float
    sign: float = 1.0


def parse_tie(text: str, model: Model, axes: tuple[Axis, ...]) -> Tie:
    """``NAME=AXIS``, ``NAME=AXIS+OFFSET`` or ``NAME=AXIS-OFFSET`` (OFFSET a number or an expression in pi), each
    also with the axis negated (``NAME=-AXIS+OFFSET``)."""
    name, sep, rest = str(text).partition("=")
    name, rest = name.strip(), rest.strip()
    if not sep or not name or not rest:
        raise AnalysisError(f"--tie {text!r}: expected NAME=AXIS+OFFSET, e.g. phi_3=phi_1+pi")
    model.index(name)  # a state of the model, or one clear line
    sign = 1.0
    if rest.startswith("-") and any(rest[1:] == a.name or rest[1:].startswith((a.name + "+", a.name + "-"))
                                    for a in axes):
        sign, rest = -1.0, rest[1:]
    axis = next((a for a in axes if rest == a.name or rest.startswith(a.name + "+") or rest.startswith(a.name + "-")),
                None)
    if axis is None or axis.kind != "state":
        raise AnalysisError(f"--tie {name}: {rest!r} does not start with a state axis of the grid "
                            f"({', '.join(a.name for a in axes if a.kind == 'state') or 'none'})")
    tail = rest[len(axis.name):]
    offset = parse_value(tail, f"--tie {name} offset") if tail else 0.0
    return Tie(name, axis.name, offset, sign)


@dataclass(frozen=True)
class Grid:
    axes: tuple[Axis, ...]
    base_params: np.ndarray  # DEFAULTS with --set
    base_state: np.ndarray  # zeros with --y0
    ties: tuple[Tie, ...] = ()

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.count for a in self.axes)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes)

    def points(self, model: Model, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P, Y0) rows for the grid points with C-order indices `flat`."""
        flat = np.asarray(flat, dtype=np.int64)
        idx = np.unravel_index(flat, self.shape)
        P = np.repeat(self.base_params[None], len(flat), axis=0)
        Y0 = np.repeat(self.base_state[None], len(flat), axis=0)
        for axis, i in zip(self.axes, idx):
            column = axis.values[i]
            if axis.kind == "parameter":
                P[:, model.param_names.index(axis.name)] = column
            else:
                Y0[:, model.index(axis.name)] = column
        for tie in self.ties:
            Y0[:, model.index(tie.state)] = tie.sign * Y0[:, model.index(tie.axis)] + tie.offset
        return P, Y0


def make_grid(model: Model, grid: list[str], params: dict[str, float], y0: dict[str, float],
              ties: list[str] = ()) -> Grid:
    """The grid of `--grid` items with the fixed values of --set and --y0 and the `--tie`d states (a name
    given twice, in two of these, or tied to itself is refused)."""
    if not grid:
        raise AnalysisError("no grid: give at least one --grid NAME=FROM:TO:COUNT")
    axes = tuple(parse_axis(item, model) for item in grid)
    seen: set[str] = set()
    for a in axes:
        if a.name in seen:
            raise AnalysisError(f"--grid {a.name} given twice")
        seen.add(a.name)
        if a.name in params or a.name in y0:
            raise AnalysisError(f"{a.name} is both a grid axis and fixed by --set/--y0")
    tied = tuple(parse_tie(item, model, axes) for item in ties or ())
    for t in tied:
        if t.state in seen or t.state in y0:
            raise AnalysisError(f"--tie {t.state}: already a grid axis, fixed by --y0 or tied")
        seen.add(t.state)
    size = math.prod(a.count for a in axes)
    if size > MAX_POINTS:
        raise AnalysisError(f"the grid has {size} points; at most {MAX_POINTS} per sweep")
    return Grid(axes, model.params(params), model.state(y0), tied)


_GREEK = frozenset("alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi pi rho sigma tau "
                   "upsilon phi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma Upsilon Phi Psi Omega".split())


def tex(name: str) -> str:
    """A generated model's name as TeX: a Greek letter's name as the letter, the text after the first
    "_" as its subscript, a trailing "_dot" as a dot (``phi_1_dot`` -> ``\\dot\\phi_{1}``, ``eps`` ->
    ``\\varepsilon``); any other name as it is."""
    dot = name.endswith("_dot")
    base = name[:-4] if dot else name
    head, sep, sub = base.partition("_")
    symbol = "\\varepsilon" if head == "eps" else ("\\" + head if head in _GREEK else head)
    text = symbol + (f"_{{{sub}}}" if sep else "")
    return ("\\dot" + ("" if symbol.startswith("\\") else " ") + text) if dot else text


def axis_symbol(name: str, kind: str = "parameter") -> str:
    """The symbol of a grid axis for figure labels: a parameter, or an initial state '(0)'."""
    return f"${tex(name)}(0)$" if kind == "state" else f"${tex(name)}$"
