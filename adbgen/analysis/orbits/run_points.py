"""What the points of AUTO-07p's one-parameter run gain (`adbgen continue`, issue 21 and issue 34 item 5).

    add_lyapunov(model, points, NAME, p, follower)   first_lyapunov and criticality ("supercritical" |
                                                     "subcritical") at every Hopf point (`first_lyapunov`)
    add_margins(model, points, NAME, p)              margin, margin_uncertainty, marginal at every point with its
                                                     state (`steady.margin_at`)

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


def add_margins(model, points: list[dict], name: str, p: np.ndarray) -> None:
    """margin, margin_uncertainty, marginal (`steady.margin_at`, issue 34 item 5) at each point of AUTO's run
    that carries its state: AUTO's own "stability" is a sign; this says how far from zero, and whether the
    computation can certify it."""
    from .. import steady

    k = model.param_names.index(name)
    for row in points:
        if "state" not in row:
            continue
        q = np.array(p, float)
        q[k] = row[name]
        try:
            row.update(steady.margin_at(model, q, np.array([row["state"][s] for s in model.state_names])).to_json())
        except (AnalysisError, np.linalg.LinAlgError):
            continue
