"""Which of a module's closed-form steady states (its self-description's STEADY_STATES) a state is: the state a
chart or a stability map follows, so that a point where Newton failed is retried from that state's closed form,
and a point where the closed form has no solution is said to have none ("does not exist"), never confused with
a failure ("not computed")."""

from __future__ import annotations

import math

import numpy as np

from .loading import AnalysisError, Model

MATCH = 1e-6  # max difference (angles wrapped), relative to the state's size, for a state to be a closed form's


def _distance(a, b) -> float:
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.max(np.abs(np.remainder(d + math.pi, 2 * math.pi) - math.pi))) if d.size else 0.0


def label_of(model: Model, y, p) -> str | None:
    """The label of the closed-form steady state that y is at parameters p, or None (none of them)."""
    y = np.asarray(y, float)
    for name in model.steady_states:
        try:
            z = model.steady_state(name, p)
        except (AnalysisError, ArithmeticError, ValueError):
            continue
        if z is not None and _distance(z, y) < MATCH * (1.0 + float(np.max(np.abs(y)))):
            return name
    return None
