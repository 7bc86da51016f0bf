"""The Taylor target's checks before anything is written (`regenerate` refuses a model that fails).

1. The series program's coefficients y_0..y_5 (run in Python, `pyeval`) against the Lie derivatives
   L_f^k y / k! of the printed rhs in 60-digit series arithmetic (`reference.lie_coefficients`, no
   recurrences), at random states away from equilibria (as `codegen.passes.checks`: coordinates and angles in
   [-0.1, 0.1], rates in [-1, 1], parameters 0.5x to 1.5x the defaults, t = 0 and random t in [0, 10],
   and a time past each Piecewise switch, so every branch of a run-up's speed law is checked): norm-wise
   relative difference per order at most `LIE_TOLERANCE`.
2. One step of Taylor's method (order `STEP_ORDER`, Jorba & Zou's step size) from such a state, the
   series program run in 30-digit arithmetic (`pyeval` with mpmath), against mpmath's own Taylor solver
   (`odefun`) at 30 digits on the printed rhs: at most `STEP_TOLERANCE` of max(1, |y|).  In 30 digits
   the comparison sees the recurrences and the step, not double rounding: the dimensional fixed-frame
   models' rhs cancels terms of omega^2 R ~ 1e4 m/s^2 down to O(1), so in double it rounds to ~3e-10
   absolute and one double step of any method is off by h times that (2e-13 at h = 7.6e-4, measured on
   single_plane_fixed_n3); check 1 is the double-precision one.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np

from ...passes.checks import CheckFailed
from .pyeval import flags as series_flags, taylor as series_taylor
from .reference import lie_coefficients, odefun_step

LIE_ORDER = 5
LIE_TOLERANCE = 1e-11  # measured <= 1.5e-15 (autonomous models), 1.4e-12 (sin(omega t) at omega t ~ 2e3)
STEP_ORDER = 20
STEP_TOLERANCE = 1e-13  # of the 30-digit step: measured 1.8e-19 to 2.4e-19 (thesis n3, fixed n4, two_plane_hill)


def _points(ir, samples: int, seed: int):
    rng = np.random.default_rng(seed)
    defaults = np.array([p.default for p in ir.parameters], dtype=float)
    for k in range(samples):
        y = rng.uniform(-1, 1, ir.n_states)
        y[: ir.n_coordinates] *= 0.1
        t = 0.0 if k == 0 else float(rng.uniform(0, 10))
        yield t, y, defaults * rng.uniform(0.5, 1.5, defaults.size)


def branch_times(prog, y, p) -> list[float]:
    """Times at which the Piecewise conditions take values they do not take at t = 0 (the run-ups'
    later branches), the first of each new combination along t = 10^k, k = 0..6."""
    seen = {series_flags(prog, 0.0, y, p)}
    out = []
    for k in range(7):
        t = 10.0 ** k
        f = series_flags(prog, t, y, p)
        if f not in seen:
            seen.add(f)
            out.append(t * 1.1)
    return out


def lie_errors(ir, prog, samples: int = 3, seed: int = 0, order: int = LIE_ORDER) -> list[float]:
    """Largest norm-wise relative difference per order 0..order over the sample points, and at a point
    past every Piecewise switch (`branch_times`)."""
    worst = [0.0] * (order + 1)
    points = list(_points(ir, samples, seed))
    if prog.flags:
        _, y, p = points[-1]
        points += [(t, y, p) for t in branch_times(prog, y, p)]
    for t, y, p in points:
        ref = lie_coefficients(ir, t, y, p, order)
        got = np.array(series_taylor(prog, t, y, p, order), dtype=float)
        for k in range(order + 1):
            scale = max(1e-300, float(np.max(np.abs(ref[k]))))
            worst[k] = max(worst[k], float(np.max(np.abs(got[k] - ref[k]))) / scale)
    return worst


def jorba_step(rows: np.ndarray) -> float:
    """Jorba & Zou's step from coefficients rows 0..p (heyoka's rule): rho_m = min over k = p - 1, p of
    (max(1, |y|_inf) / |y_k|_inf)^(1/k), h = rho_m exp(-0.7 / (p - 1)) / e^2."""
    p = len(rows) - 1
    num = max(1.0, float(np.max(np.abs(rows[0]))))
    rho = min((num / max(1e-300, float(np.max(np.abs(rows[k]))))) ** (1.0 / k) for k in (p - 1, p))
    return rho * math.exp(-0.7 / (p - 1)) / math.e ** 2


def step_error(ir, prog, seed: int = 5) -> tuple[float, float]:
    """(|one order-20 Taylor step of the series program in 30 digits - odefun's| / max(1, |y|), the step)."""
    t, y, p = next(_points(ir, 2, seed))
    t = 1.0
    with mpmath.workdps(30):
        rows = series_taylor(prog, mpmath.mpf(t), [mpmath.mpf(float(v)) for v in y],
                             [mpmath.mpf(float(v)) for v in p], STEP_ORDER, lib=mpmath)
        h = mpmath.mpf(jorba_step(np.array([[float(v) for v in row] for row in rows])))
        yh = [mpmath.mpf(0)] * ir.n_states
        for k in range(STEP_ORDER, -1, -1):
            yh = [a * h + b for a, b in zip(yh, rows[k])]
        ref = odefun_step(ir, t, y, p, float(h))
        err = max(abs(float(a - b)) for a, b in zip(yh, ref))
    return err / max(1.0, float(np.max(np.abs(y)))), float(h)


def check_series(ir, prog) -> dict:
    """Both checks, or CheckFailed naming what differs; returns the measured errors."""
    lie = lie_errors(ir, prog)
    for k, err in enumerate(lie):
        if not err <= LIE_TOLERANCE:
            raise CheckFailed(f"{ir.name}: Taylor coefficient {k} of the series program differs from the Lie "
                              f"derivative of the rhs by {err:.2e} (tolerance {LIE_TOLERANCE:g})")
    err, h = step_error(ir, prog)
    if not err <= STEP_TOLERANCE:
        raise CheckFailed(f"{ir.name}: a Taylor step (order {STEP_ORDER}, h = {h:.3g}) differs from mpmath's odefun "
                          f"at 30 digits by {err:.2e} (tolerance {STEP_TOLERANCE:g})")
    return {"lie": lie, "step": err, "h": h}
