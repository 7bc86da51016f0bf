"""What the orbit code needs to know about a generated model, read from the model's self-description.

    angle_indices(model)        states on which the rhs is 2 pi-periodic (ANGLES)
    amplitude_indices(model)    the two states whose hypot is the amplitude r (AMPLITUDE)
    forcing_parameter(model)    index of the parameter w whose 2 pi / w is the forcing period of a periodically
                                forced model (FORCING_FREQUENCY), None for an autonomous one
    measures(model)             names of the compiled amplitude measures the module emits (MEASURES), e.g. "A"

Nothing here names a family or a model, and nothing is guessed: every field is the module's own
(`loading.Model` refuses a module that predates one: regenerate it).
"""

from __future__ import annotations

import numpy as np

from ..loading import AnalysisError, Model


def angle_indices(model: Model) -> tuple[int, ...]:
    return tuple(model.angle_indices)


def amplitude_indices(model: Model) -> tuple[int, int]:
    """(The positions of) the two AMPLITUDE states; a first-order model's need not be coordinates."""
    a, b = model.amplitude
    return model.index(a), model.index(b)


def measures(model: Model) -> tuple[str, ...]:
    """Compiled measures the module emits besides r (MEASURES, e.g. a vibration measure "A")."""
    return tuple(n for n in model.measures if n != "r")


def measure(model: Model, name: str, t: np.ndarray, Y: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The measure `name` along samples (times t, one state per row of Y): the module's compiled
    measures_along (all measures at once, MEASURES' order)."""
    return np.asarray(model.measure(name, np.asarray(t, dtype=float), np.asarray(Y, dtype=float).T, p))


def forcing_parameter(model: Model, p: np.ndarray | None = None) -> int | None:
    """The forcing frequency's parameter index (None: autonomous).  `p` is not used (kept for callers)."""
    if model.autonomous:
        return None
    name = model.forcing_frequency
    if not name:
        raise AnalysisError(f"{model.name} depends on time but is not periodically forced (no forcing "
                            f"frequency): it has no periodic orbits to follow")
    return model.param_names.index(name)
