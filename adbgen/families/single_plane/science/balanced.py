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


def family_member(model, p_values: dict, free: float, n: int = 3):
    """The member of the n = 3 balanced family (3.6) with phi_3 = `free`: x = y = 0, every rate 0, and
    cos phi_1 + cos phi_2 = -delta/mu - cos phi_3, sin phi_1 + sin phi_2 = -sin phi_3 solved for phi_1 > phi_2;
    None where phi_3 leaves no solution (|the right-hand side| > 2)."""
    p = model.params(p_values)
    names = list(model.param_names)
    mu_, delta_ = p[names.index("mu")], p[names.index("delta")]
    a, b = -delta_ / mu_ - np.cos(free), -np.sin(free)
    half = np.hypot(a, b) / 2
    if n != 3 or half > 1:
        return None
    centre, spread = np.arctan2(b, a), np.arccos(half)
    return model.state({"phi_1": centre + spread, "phi_2": centre - spread, "phi_3": free})


def family_margin(model, p_values: dict, count: int = 361) -> tuple[float, float]:
    """The n = 3 balanced family's best member: (smallest leading real part of the transverse spectrum over the
    family, the phi_3 where it is), phi_3 on `count` points of [-pi, pi].  Positive: no member is linearly
    stable (the thesis' ch. 4 analyses the phi_3 = pi member alone)."""
    from ....analysis.attractors import spectrum

    p = model.params(p_values)
    best = (float("inf"), float("nan"))
    for free in np.linspace(-np.pi, np.pi, count):
        y = family_member(model, p_values, float(free))
        if y is None:
            continue
        best = min(best, (spectrum(model, y, p).abscissa, float(free)))
    return best


def family_zeta_limit(model, lo: float = 0.01, hi: float = 0.1, xtol: float = 1e-5) -> float | None:
    """The rotor damping zeta from which no member of the n = 3 balanced family is linearly stable (the zero
    of `family_margin` in [lo, hi], Omega, beta as the model's defaults (5.1)); None without a sign change."""
    from scipy.optimize import brentq

    f = lambda z: family_margin(model, {"zeta": float(z)}, count=181)[0]  # noqa: E731
    a, b = f(lo), f(hi)
    if a * b > 0:
        return None
    return float(brentq(f, lo, hi, xtol=xtol))
