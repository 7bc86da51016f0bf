"""The steady states the stability and continuation commands start from.

    start_state(model, p, y0=None, label=None)   (state, label): named states (others 0), a labelled
                                                 steady state of the model, or its START
    labelled_state(model, label, p)              the model's labelled steady state at p
    pinned(model, y0, p, guess=None)             the steady state near guess, on the balanced family
                                                 of n >= 3 balls the member with y0's free angles
    pinned_start(model, p)                       START re-solved at p
    follower(model, y0)                          p -> the followed steady state at p
"""

from __future__ import annotations

import numpy as np

from . import closed_forms, steady
from .loading import AnalysisError, Model


def labelled_state(model: Model, label: str, p) -> np.ndarray:
    """The model's steady state `label` at p (rates zero); AnalysisError naming the labels if unknown,
    or saying it does not exist at p."""
    return closed_forms.state(model, label, p)


def start_state(model: Model, p, y0: dict | None = None, label: str | None = None) -> tuple[np.ndarray, str]:
    """(state vector, label): the named states y0 (those not named 0), the labelled steady state, or the
    model's START (label None or "start")."""
    if y0:
        return model.state(y0), "y0"
    label = label or "start"
    if label == "start":
        start = getattr(model.module, "START", None)
        if start is None:
            raise AnalysisError(f"{model.name} has no START state; give --y0 or --state")
        return np.array(start, float), "start"
    return labelled_state(model, label, p), label


def pinned(model: Model, y0, p, guess=None) -> np.ndarray:
    """The steady state near `guess` (default y0) at p; on the n >= 3 balanced family with the free
    angles kept at y0's (the member AUTO's regularised func follows)."""
    free = list(model.angle_indices)[2:] if steady.on_balanced_family(model, y0) else []
    extra = None
    if free:
        rows = np.zeros((len(free), model.n_states))
        rows[range(len(free)), free] = 1.0
        extra = (lambda y: y[free] - y0[free], lambda y: rows)
    y, _ = steady.newton(model, p, y0 if guess is None else guess, extra=extra)
    return y


def pinned_start(model: Model, p) -> np.ndarray:
    """START, re-solved at p (see `pinned`)."""
    y0 = np.array(model.module.START, float)
    return y0 if np.array_equal(p, model.module.START_PARAMETERS) else pinned(model, y0, p)


def follower(model: Model, y0):
    """p -> the followed steady state at p: the balanced state (3.6) from its closed form where y0 is
    one (x = y = 0), else Newton from y0."""
    core = [model.index(c) for c in model.module.CORE]
    balanced = closed_forms.is_thesis_model(model) and np.max(np.abs(y0[core])) < 1e-12

    def at(p):
        guess = None
        if balanced:
            guess = closed_forms.state(model, "1", p)
            if steady.on_balanced_family(model, y0):
                guess[list(model.angle_indices)[2:]] = y0[list(model.angle_indices)[2:]]
        return pinned(model, y0, p, guess)
    return at


__all__ = ["follower", "labelled_state", "pinned", "pinned_start", "start_state"]
