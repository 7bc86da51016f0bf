"""Stability of the thesis' balanced state at given parameters (thesis ch. 3-4), shared by the chapter-4
limits (reproduce.py) and the sweeps' thresholds (sweeps.py)."""

from __future__ import annotations

import numpy as np


def balanced_stable(model, values: dict) -> bool | None:
    """Is the balanced state (3.6) stable at these parameters?  The member of the n >= 3 family that the
    model's closed form gives (phi_3.. = pi where that has a solution: the generated module's
    `steady_state("1", p)`), polished by Newton; deflated spectrum.  None where the state does not exist
    (mu < delta/n, (3.14)) or Newton fails.

    Seeded at the parameters themselves: Newton from START (the member at the defaults (5.1)) wanders off
    the continuum where the member has moved far (n = 4 at mu = 0.015: phi_1 = 0.841 against START's 0.451),
    which an earlier version counted as unstable."""
    from ....analysis.attractors import amplitude_of, newton, spectrum

    p = model.params(values)
    seed = model.steady_state("1", p) if "1" in model.steady_states else np.array(model.module.START, float)
    if seed is None:
        return None
    y = newton(model, np.asarray(seed, float), p)
    if y is None or amplitude_of(model, y) > 1e-8:
        return None
    return spectrum(model, y, p).unstable() == 0
