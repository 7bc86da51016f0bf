"""The residual imbalance at rest over a sweep of starts (issue 37, item 3): its distribution.

A run of a model with stick/slip modes is at rest at t_end when every ball has ended stuck on the race; its
residual imbalance is then r = sqrt(X^2 + Y^2) at t_end (what the balls, stopped short of the balanced
position, leave), or another of the model's own measures at t_end where its family defines the imbalance
otherwise (`residual_at_end`: the name `residual_measure` resolves, one of the model's MEASURES, so this module
names no family; e.g. a rigid rotor's mean amplitude A at two points one unit from the midspan, which sees the
moment imbalance that r of the centre alone misses).  Runs whose balls still move at t_end (not at rest:
undecided) and failed runs are counted apart and never enter the distribution.  The histogram has fixed edges from 0 to the largest
residual at rest (BINS bins), so it is deterministic for a given set of values.
"""

from __future__ import annotations

import numpy as np

from .loading import AnalysisError

BINS = 40
QUANTILES = (50, 90, 99)

# at_rest codes of the sweep store's variable `at_rest`
AT_REST, MOVING, NOT_RUN = 1, 0, -1


def at_rest_codes(stuck: np.ndarray, failed: np.ndarray) -> np.ndarray:
    """Per run: AT_REST (every ball stuck at t_end), MOVING (some ball still slipping) or NOT_RUN (failed)."""
    stuck = np.atleast_2d(np.asarray(stuck, dtype=bool))
    codes = np.where(stuck.all(axis=1), AT_REST, MOVING).astype(np.int8)
    return np.where(np.asarray(failed, dtype=bool), NOT_RUN, codes).astype(np.int8)


def residual_measure(model, given: str | None = None) -> str:
    """Which of a model's measures is its residual imbalance, for `sweep --measure residual` and `design --objective
    residual` alike: `given` (--residual-measure: an explicit name wins, "r" included), else the one the model's
    family names (Model.residual_measure: two planes' A, r elsewhere).  A one-line AnalysisError where the name is
    not one of the model's measures (both commands refuse it with this wording)."""
    name = model.residual_measure if given is None else given
    if name not in model.measures:
        raise AnalysisError(f"--residual-measure: {name!r} is not a measure of {model.name}; its measures: "
                            f"{', '.join(model.measures)}")
    return name


def residual_at_end(model, name: str, r_end: np.ndarray, t_last: np.ndarray, y_end: np.ndarray, P: np.ndarray,
                    failed: np.ndarray) -> np.ndarray:
    """Per run, the measure `name` of the model at its end state (t_last, y_end, the run's parameters P); "r"
    is the engine's r_end.  NaN for failed runs (their end state is no result)."""
    if name == "r":
        return np.asarray(r_end, float)
    failed = np.asarray(failed, dtype=bool)
    out = np.full(len(P), np.nan)
    for k in np.flatnonzero(~failed):
        out[k] = model.measure(name, float(t_last[k]), np.asarray(y_end[k], float), np.asarray(P[k], float))
    return out


def distribution(residual: np.ndarray, at_rest: np.ndarray, bins: int = BINS) -> dict:
    """{"at_rest", "not_at_rest", "failed" (counts), "quantiles": {"50", "90", "99", "max"} of r at rest (None
    when no run is at rest), "histogram": {"edges", "counts"}} of the runs given (computed points only)."""
    residual = np.asarray(residual, float).ravel()
    at_rest = np.asarray(at_rest).ravel()
    rest = residual[(at_rest == AT_REST) & np.isfinite(residual)]
    out = {"at_rest": int(rest.size), "not_at_rest": int((at_rest == MOVING).sum()),
           "failed": int((at_rest == NOT_RUN).sum() + ((at_rest == AT_REST) & ~np.isfinite(residual)).sum())}
    if not rest.size:
        out["quantiles"] = {**{str(q): None for q in QUANTILES}, "max": None}
        out["histogram"] = {"edges": [], "counts": []}
        return out
    out["quantiles"] = {**{str(q): float(np.percentile(rest, q)) for q in QUANTILES}, "max": float(rest.max())}
    top = float(rest.max()) if rest.max() > 0 else 1.0
    counts, edges = np.histogram(rest, bins=bins, range=(0.0, top))
    out["histogram"] = {"edges": edges.tolist(), "counts": counts.astype(int).tolist()}
    return out
