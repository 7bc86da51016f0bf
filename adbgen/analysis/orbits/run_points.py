"""What the points of AUTO-07p's one-parameter run gain (`adbgen continue`, issue 21 and issue 34 item 5).

    add_lyapunov(model, points, NAME, p, follower)   first_lyapunov and criticality ("supercritical" |
                                                     "subcritical") at every Hopf point (`first_lyapunov`)
    add_margins(model, points, NAME, p, follower)    margin, margin_uncertainty, marginal at every point with its
                                                     state (`steady.margin_at`); at a bifurcation point the
                                                     uncertainty also counts where AUTO placed it

The rows are AUTO's points as `auto07p` writes them to JSON (NAME: the continued parameter, "state" by
state name); a point whose computation fails keeps what it had and gains nothing.
"""

from __future__ import annotations

import numpy as np

from ..loading import AnalysisError


def add_lyapunov(model, points: list[dict], name: str, p: np.ndarray, follower) -> None:
    """first_lyapunov, criticality at each HB point of AUTO's run (its state refined at its parameter)."""
    from .first_lyapunov import criticality, first_lyapunov

    k = model.param_names.index(name)
    for row in points:
        if row.get("type") != "HB" or "state" not in row:
            continue
        q = p.copy()
        q[k] = row[name]
        try:
            y = follower(q, np.array([row["state"][s] for s in model.state_names]))
            l1, _ = first_lyapunov(model, q, y, row.get("frequency"))
        except AnalysisError:
            continue
        row["first_lyapunov"] = l1
        row["criticality"] = criticality(l1)


def add_margins(model, points: list[dict], name: str, p: np.ndarray, follower=None) -> None:
    """margin, margin_uncertainty, marginal (`steady.margin_at`, issue 34 item 5) at each point of AUTO's run
    that carries its state: AUTO's own "stability" is a sign; this says how far from zero, and whether the
    computation can certify it.  At a bifurcation point (a row with "location_uncertainty", HB / LP / BP) the
    margin is zero at the exact point by definition, so the computed one is mostly the error in where AUTO
    placed it: the uncertainty gains |d margin / d NAME| x that location error (`location_slope`)."""
    from .. import steady

    k = model.param_names.index(name)
    for row in points:
        if "state" not in row:
            continue
        q = np.array(p, float)
        q[k] = row[name]
        y = np.array([row["state"][s] for s in model.state_names])
        try:
            margin = steady.margin_at(model, q, y)
        except (AnalysisError, np.linalg.LinAlgError):
            continue
        if "location_uncertainty" in row and follower is not None:
            slope = location_slope(model, q, y, k, follower, at=margin.value)
            # no state on either side: the location's effect is unknown, so nothing is certified (inf)
            margin = margin.widened(abs(slope) * row["location_uncertainty"] if np.isfinite(slope) else np.inf,
                                    f"+ |d margin / d {name}| ({abs(slope):.3g}) x where AUTO-07p placed the point"
                                    if np.isfinite(slope) else
                                    f"the point's location error unknown (no steady state beside it in {name}): nothing certified")
        row.update(margin.to_json())


def location_slope(model, q: np.ndarray, y: np.ndarray, k: int, follower, *, at: float, rel: float = 1e-6) -> float:
    """d margin / d p_k at the point (q, y), whose margin is `at` (its caller has it): a central difference of `steady.margin_at` over the state
    followed to q_k +- h, h = rel max(1, |q_k|) (the margin is smooth in p_k through a Hopf point; its O(h^2)
    error is far below the slope at 1e-6); one-sided where one side has no state (beside a fold, where the
    slope is unbounded and the one-sided difference large); nan where neither side has one."""
    from .. import steady

    h = rel * max(1.0, abs(q[k]))
    side = {}
    for sign in (-1.0, 1.0):
        qs = np.array(q, float)
        qs[k] += sign * h
        try:
            side[sign] = steady.margin_at(model, qs, follower(qs, y)).value
        except (AnalysisError, np.linalg.LinAlgError):
            continue
    if len(side) == 2:
        return (side[1.0] - side[-1.0]) / (2 * h)
    if len(side) == 1:
        sign, value = next(iter(side.items()))
        return sign * (value - at) / h
    return float("nan")
