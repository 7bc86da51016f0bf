"""The steady states the stability and continuation commands start from.

    start_state(model, p, y0=None, label=None)   (state, label): named states (others 0), a labelled
                                                 steady state of the model, or its START
    labelled_state(model, label, p)              the model's closed-form steady state `label` at p
    pinned(model, y0, p, guess=None)             the steady state near guess, on the balanced family
                                                 of n >= 3 balls the member with y0's free angles
    pinned_start(model, p)                       START re-solved at p
    follower(model, y0)                          p -> the followed steady state at p
    default_start(model, p, pmap=None)           START at p, carried there where Newton from START lands
                                                 on another state than START's label

The labelled steady states are the generated module's own (`Model.steady_states`, compiled from the
family's closed forms and checked to be zeros of the rhs when they were written).
"""

from __future__ import annotations

import numpy as np

from . import steady
from .loading import AnalysisError, Model


def labelled_state(model: Model, label: str, p) -> np.ndarray:
    """The model's steady state `label` at p (rates zero); AnalysisError naming the labels if unknown,
    or saying where the state exists if it does not at p."""
    if label not in model.steady_states:
        known = ", ".join(model.steady_states)
        hint = f"labels: start, {known}" if known else "this model has only: start"
        raise AnalysisError(f"unknown state label {label!r}; {hint}")
    y = model.steady_state(label, p)
    if y is None:
        raise AnalysisError(f"state {label} does not exist at these parameters ({model.steady_state_note(label)})")
    return np.array(y, float)


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
    free = list(model.role_indices("ball_angle"))[2:] if steady.on_balanced_family(model, y0) else []
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


def balanced_label(model: Model, p) -> str | None:
    """The label of the model's balanced steady state (the rotor at rest at the origin) at p, if it has one."""
    ix, iy, _, _ = model.amplitude_indices
    for label in model.steady_states:
        y = model.steady_state(label, p)
        if y is not None and y[ix] == 0.0 and y[iy] == 0.0:
            return label
    return None


def follower(model: Model, y0):
    """p -> the followed steady state at p: where y0 is balanced (the rotor at rest at the origin) and the
    model has a closed-form balanced state, Newton from that closed form at p (the free angles of the
    n >= 3 family kept at y0's), else Newton from y0."""
    ix, iy, _, _ = model.amplitude_indices
    balanced = max(abs(y0[ix]), abs(y0[iy])) < 1e-12
    free = list(model.role_indices("ball_angle"))[2:] if steady.on_balanced_family(model, y0) else []

    def at(p):
        guess = None
        label = balanced_label(model, p) if balanced else None
        if label is not None:
            guess = labelled_state(model, label, p)
            guess[free] = y0[free]
        return pinned(model, y0, p, guess)
    return at


def default_start(model: Model, p, pmap=None, carried: bool = False) -> np.ndarray:
    """START at p: Newton from START (`pinned_start`), or START carried there along the path of
    `equilibrium.carried_start` (ties re-solved on the way) when `carried`; where the result is not the
    state START is at START_PARAMETERS (its label, `identify.default_label`), the carried one instead if
    that is.  The caller checks what it got (`identify.check`)."""
    from . import identify
    from .orbits.equilibrium import carried_start

    wanted = identify.default_label(model)
    y = carried_start(model, p, pmap) if carried else pinned_start(model, p)
    if wanted is None or carried or identify.identify(model, y, p).label == wanted:
        return y
    try:
        other = carried_start(model, p, pmap)
    except AnalysisError:
        return y
    return other if identify.identify(model, other, p).label == wanted else y


__all__ = ["balanced_label", "default_start", "follower", "labelled_state", "pinned", "pinned_start", "start_state"]
