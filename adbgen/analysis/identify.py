"""Which of a model's labelled steady states a state is (issue 34, item 4).

    identify(model, y, p)                 Identity: the label of the module's STEADY_STATES that y is at p
                                          (or None), how it was told, and y's distance from it
    default_label(model)                  the label START is at START_PARAMETERS (None: START is unlabelled)
    check(model, y, p, wanted, start)     Identity of y, or AnalysisError (one line) when y is not `wanted`

A labelled state is told by its closed form (the generated module's `steady_state(label, p)`):

* a *balanced* label (its closed form has the rotor at rest: every translation and tilt, and every rate,
  zero) is the set of all such states, so y is it when its rotor is at rest; the balls' angles do not
  matter (the mirror images of n = 2, every member of the n >= 3 continuum (3.6)).  Where the closed form is
  not given at p (a balanced state whose closed form holds only without a couple imbalance, say), a
  label whose closed form is balanced at the module's START_PARAMETERS or DEFAULTS is still told this way:
  the balanced state is the one with the rotor at rest, wherever it has a formula or not.
* any other label is y's when the rotor coordinates agree and the ball angles agree as sets (modulo 2 pi,
  so exchanging identical balls gives the same state).

Tolerances: a state refined by Newton (|rhs| <= 1e-12 relative) is within ~1e-13 of its closed form;
SAME = 1e-6 of the eccentricity scale (1e-8 without one) separates that from a different state (the
off-centre state the paper's charts can be thrown onto has its rotor at x = 2.8e-5 for eps = 5e-5).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .loading import AnalysisError, Model

SAME = 1e-6  # relative to the eccentricity scale (absolute 1e-8 for models without one)
ABSOLUTE = 1e-8


@dataclass(frozen=True)
class Identity:
    label: str | None  # a label of the module's STEADY_STATES, or None: none of them
    distance: float  # from the label's closed form (or, for a balanced label, the rotor's largest displacement)
    how: str  # "closed form", "rotor at rest" (closed form not given here) or "" (no label matched)
    rotor: float  # the rotor's largest displacement or rate (0 for a balanced state)

    def to_json(self) -> dict:
        return {"followed_state": self.label, "state_distance": float(self.distance), "identified_by": self.how or None}

    def describe(self, model: Model) -> str:
        if self.label is not None:
            return f"state {self.label}"
        known = ", ".join(model.steady_states) or "none"
        return f"a steady state that is none of the labelled ones ({known}): rotor displaced by {self.rotor:.3g}"


def _rotor_indices(model: Model) -> list[int]:
    """The rotor's coordinates (translations and tilts) and every rate."""
    core = [i for i, r in enumerate(model.roles) if r in ("translation", "tilt")]
    return core + [i for i, r in enumerate(model.roles) if r.endswith("_rate")]


def _balls(model: Model) -> list[int]:
    return list(model.role_indices("ball_angle"))


def tolerance(model: Model, p) -> float:
    ecc = model.scales.get("eccentricity")
    if ecc is not None:
        eps = abs(float(np.asarray(p)[model.param_names.index(ecc)]))
        if eps > 0:
            return SAME * eps
    return ABSOLUTE


def rotor_size(model: Model, y) -> float:
    idx = _rotor_indices(model)
    return float(np.max(np.abs(np.asarray(y)[idx]))) if idx else 0.0


def _angle_gap(a: np.ndarray, b: np.ndarray) -> float:
    """The largest difference of two sets of angles, matched in sorted order modulo 2 pi."""
    if len(a) == 0:
        return 0.0
    wa, wb = np.sort(np.mod(a, 2 * math.pi)), np.sort(np.mod(b, 2 * math.pi))
    best = math.inf
    for shift in range(len(wa)):  # sets on the circle: the sorted lists may be rotated against each other
        d = np.abs(np.angle(np.exp(1j * (wa - np.roll(wb, shift)))))
        best = min(best, float(np.max(d)))
    return best


def _balanced_somewhere(model: Model, label: str) -> bool:
    """The label's closed form has the rotor at rest at START_PARAMETERS or DEFAULTS (where it is given)."""
    for p in (getattr(model.module, "START_PARAMETERS", None), getattr(model.module, "DEFAULTS", None)):
        if p is None:
            continue
        y = model.steady_state(label, p)
        if y is not None:
            return rotor_size(model, y) == 0.0
    return False


def identify(model: Model, y, p) -> Identity:
    """Which of the module's labelled steady states y is at p (see the module's docstring)."""
    y, p = np.asarray(y, float), np.asarray(p, float)
    tol = tolerance(model, p)
    rotor = rotor_size(model, y)
    balls = _balls(model)
    core = [i for i, r in enumerate(model.roles) if r in ("translation", "tilt")]
    best = None
    for label in model.steady_states:
        closed = model.steady_state(label, p)
        if closed is not None and rotor_size(model, closed) == 0.0 or closed is None and _balanced_somewhere(model, label):
            d, how = rotor, "closed form" if closed is not None else "rotor at rest (its closed form is not given here)"
        elif closed is not None:
            rates = [i for i, r in enumerate(model.roles) if r.endswith("_rate")]
            d = max(float(np.max(np.abs(y[core] - closed[core]), initial=0.0)), _angle_gap(y[balls], closed[balls]),
                    float(np.max(np.abs(y[rates]), initial=0.0)))
            how = "closed form"
        else:
            continue
        if d <= tol and (best is None or d < best.distance):
            best = Identity(label, d, how, rotor)
    return best or Identity(None, math.nan, "", rotor)


def default_label(model: Model) -> str | None:
    """The label the module's START is at its START_PARAMETERS (None: no START, or none of the labels)."""
    start = getattr(model.module, "START", None)
    p0 = getattr(model.module, "START_PARAMETERS", None)
    if start is None or p0 is None:
        return None
    return identify(model, start, p0).label


def check(model: Model, y, p, wanted: str | None, what: str = "the start") -> Identity:
    """y's identity at p; AnalysisError in one line when `wanted` (a label) is given and y is not it."""
    found = identify(model, y, p)
    if wanted is not None and found.label != wanted:
        absent = wanted in model.steady_states and model.steady_state(wanted, p) is None
        raise AnalysisError(f"{what} is not state {wanted} at these parameters: Newton from it found "
                            f"{found.describe(model)}" + (f" (the closed form of {wanted} gives none here)" if absent
                                                          else "")
                            + "; refused (choose the state with --state, or carry it there along the parameters)")
    return found
