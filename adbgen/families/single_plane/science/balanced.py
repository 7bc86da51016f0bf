"""Stability of the thesis' balanced state at given parameters (thesis ch. 3-4), shared by the chapter-4
limits (reproduce.py) and the sweeps' thresholds (sweeps.py)."""

from __future__ import annotations

import numpy as np


def balanced_stable(model, values: dict) -> bool | None:
    """Is the balanced state (continued by Newton from START, the member of the n >= 3 family with
    phi_3 (, phi_4) = pi) stable at these parameters?  Deflated spectrum; None if Newton fails."""
    from ....analysis.attractors import amplitude_of, newton, spectrum

    p = model.params(values)
    y = newton(model, np.array(model.module.START, float), p)
    if y is None or amplitude_of(model, y) > 1e-8:
        return None
    return spectrum(model, y, p).unstable() == 0
