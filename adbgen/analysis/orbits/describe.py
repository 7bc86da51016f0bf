"""What the orbit code needs to know about a generated model, read from the model's self-description.

    angle_indices(model)        states on which the rhs is 2 pi-periodic (ANGLES; LEAVES before it existed)
    amplitude_indices(model)    the two states whose hypot is the amplitude r (AMPLITUDE; else the first two
                                core coordinates)
    forcing_parameter(model)    index of the parameter w whose 2 pi / w is the forcing period of a periodically
                                forced model (FORCING_FREQUENCY), None for an autonomous one
    measures(model)             names of the compiled amplitude measures the module emits (MEASURES), e.g. "A"

Nothing here names a family or a model: a module that predates a field gets the documented fallback, and
the forcing frequency of a forced module that does not declare it is found by what the rhs does (the
parameter w for which rhs(t + 2 pi / w) = rhs(t) at random states), never by its name.
"""

from __future__ import annotations

import math

import numpy as np

from ..loading import AnalysisError, Model


def angle_indices(model: Model) -> tuple[int, ...]:
    names = getattr(model.module, "ANGLES", None)
    if names is None:
        return tuple(model.angle_indices)
    return tuple(model.index(n) for n in names)


def amplitude_indices(model: Model) -> tuple[int, int]:
    names = getattr(model.module, "AMPLITUDE", None)
    if names is None:
        return tuple(model.amplitude_indices[:2])
    return model.index(names[0]), model.index(names[1])


def measures(model: Model) -> tuple[str, ...]:
    """Compiled measures the module emits besides r (MEASURES, e.g. a vibration measure "A")."""
    names = tuple(getattr(model.module, "MEASURES", ()) or ())
    return tuple(n for n in names if n != "r") if hasattr(model.module, "measure") else ()


def measure(model: Model, name: str, t: np.ndarray, Y: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The measure `name` along samples (times t, one state per row of Y): the module's compiled
    measures_along where it has it (all measures at once, MEASURES' order), else measure() per sample."""
    along = getattr(model.module, "measures_along", None)
    if along is not None:
        k = tuple(model.module.MEASURES).index(name)
        return np.asarray(along(np.ascontiguousarray(t, dtype=float), np.ascontiguousarray(np.asarray(Y).T), p))[k]
    fn = model.module.measure
    return np.array([fn(name, float(tk), np.ascontiguousarray(y), p) for tk, y in zip(t, Y)])


def forcing_parameter(model: Model, p: np.ndarray | None = None) -> int | None:
    """The forcing frequency's parameter index (None: autonomous)."""
    if model.autonomous:
        return None
    name = getattr(model.module, "FORCING_FREQUENCY", None)
    if name is not None:
        if not name:
            raise AnalysisError(f"{model.name} depends on time but is not periodically forced (no forcing "
                                f"frequency): it has no periodic orbits to follow")
        return model.param_names.index(name)
    return _detect_forcing(model, model.params() if p is None else np.asarray(p, float))


def _detect_forcing(model: Model, p: np.ndarray) -> int:
    """The parameter w with rhs(t + 2 pi/w, y) = rhs(t, y) != rhs(t + 0.37 (2 pi/w), y) at random states, and
    still so when w itself is moved (a parameter that merely equals the forcing frequency, or a divisor of it,
    at these values fails that)."""
    rng = np.random.default_rng(7)
    Y = rng.normal(scale=0.3, size=(3, model.n_states))
    ts = rng.uniform(0.0, 10.0, size=3)
    rhs = model.module.rhs

    def periodic(q, k) -> bool:
        T = 2 * math.pi / q[k]
        same = moved = True
        for t, y in zip(ts, Y):
            a, b, c = (np.asarray(rhs(t + s, y, q)) for s in (0.0, T, 0.37 * T))
            scale = 1e-9 * max(1.0, float(np.max(np.abs(a))))
            same &= bool(np.max(np.abs(a - b)) <= scale)
            moved &= bool(np.max(np.abs(a - c)) > 1e3 * scale)
        return same and moved
    for k, w in enumerate(p):
        if not (w > 0 and math.isfinite(w)) or not periodic(p, k):
            continue
        q = np.array(p, float)
        q[k] *= 1.0137
        if periodic(q, k):
            return k
    raise AnalysisError(f"{model.name} depends on time, but not periodically through any one parameter's "
                        f"2 pi / value: it has no forced periodic orbits to follow")
