"""Thesis Figs. 4.2, 4.3, 4.6, 4.7, 4.11, 4.12: one-parameter bifurcation diagrams of every steady state, in Omega
at fixed mu and in mu at fixed Omega, recomputed as what they show: on which intervals each state exists
(the generated module's closed form found) and on which it is stable (its spectrum; for the balanced family
the transverse one), every end bisected.  An existence end is a saddle-node or pitchfork of the diagram, a
stability end inside an existence interval a Hopf point or a real crossing.  Prose: templates/one_parameter.md.j2.
"""

from __future__ import annotations

import numpy as np

from ....analysis.loading import load_model

RANGES = {"Omega": (0.05, 6.0), "mu": (0.0005, 0.1)}
PANELS = (("4.2(a)", 2, "Omega", {"mu": 0.05}), ("4.2(b)", 2, "Omega", {"mu": 0.0025}),
          ("4.3(a)", 2, "mu", {"Omega": 0.5}), ("4.3(b)", 2, "mu", {"Omega": 1.5}),
          ("4.6(a)", 3, "Omega", {"mu": 0.05}), ("4.6(b)", 3, "Omega", {"mu": 0.005}),
          ("4.6(c)", 3, "Omega", {"mu": 0.0025}),
          ("4.7(a)", 3, "mu", {"Omega": 0.5}), ("4.7(b)", 3, "mu", {"Omega": 1.25}), ("4.7(c)", 3, "mu", {"Omega": 1.5}),
          ("4.11(a)", 4, "Omega", {"mu": 0.05}), ("4.11(b)", 4, "Omega", {"mu": 0.004}),
          ("4.11(c)", 4, "Omega", {"mu": 0.002}),
          ("4.12(a)", 4, "mu", {"Omega": 0.5}), ("4.12(b)", 4, "mu", {"Omega": 1.25}),
          ("4.12(c)", 4, "mu", {"Omega": 1.5}))
NOT_FOUND, STABLE, UNSTABLE = 0, 1, 2


def _kind(model, state: str, values: dict) -> int:
    from ....analysis.attractors import spectrum

    p = model.params(values)
    y = model.steady_state(state, p)
    if y is None:
        return NOT_FOUND
    return STABLE if spectrum(model, np.asarray(y, float), p).unstable() == 0 else UNSTABLE


def _intervals(flags: list[bool], xs, refine) -> list[tuple[float, float]]:
    """The intervals where flags hold, each inner end refined by `refine(a, b, flag_at_a)`."""
    out, start = [], (float(xs[0]) if flags[0] else None)
    for i in range(len(xs) - 1):
        if flags[i] == flags[i + 1]:
            continue
        x = refine(float(xs[i]), float(xs[i + 1]), flags[i])
        if flags[i + 1]:
            start = x
        else:
            out.append((start, x))
            start = None
    if start is not None:
        out.append((start, float(xs[-1])))
    return out


def state_intervals(n: int, state: str, parameter: str, fixed: dict, count: int = 400,
                    tol: float = 1e-8, span: tuple[float, float] | None = None) -> dict:
    """{"exists": intervals, "stable": intervals} of `state` along `parameter` over `span` (default RANGES) at
    `fixed`."""
    model = load_model(f"thesis_rotating_n{n}")
    lo, hi = span or RANGES[parameter]
    xs = np.linspace(lo, hi, count)
    kinds = [_kind(model, state, {**fixed, parameter: float(x)}) for x in xs]

    def refine_by(test):
        def refine(a, b, at_a):
            while b - a > tol:
                m = 0.5 * (a + b)
                a, b = (m, b) if test(m) == at_a else (a, m)
            return 0.5 * (a + b)
        return refine

    exists = lambda x: _kind(model, state, {**fixed, parameter: x}) != NOT_FOUND  # noqa: E731
    stable = lambda x: _kind(model, state, {**fixed, parameter: x}) == STABLE  # noqa: E731
    return {"exists": _intervals([k != NOT_FOUND for k in kinds], xs, refine_by(exists)),
            "stable": _intervals([k == STABLE for k in kinds], xs, refine_by(stable))}


def compute(panels=PANELS) -> list[dict]:
    out = []
    for figure, n, parameter, fixed in panels:
        model = load_model(f"thesis_rotating_n{n}")
        states = {s: state_intervals(n, s, parameter, fixed) for s in model.steady_states}
        out.append({"figure": figure, "n": n, "parameter": parameter, "fixed": fixed, "states": states})
    return out


def lines(panels: list[dict]) -> list[str]:
    from .templates import render

    return render("one_parameter", panels=panels, ranges=RANGES)
