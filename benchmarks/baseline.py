"""The expert baseline of the benchmarks: thesis Appendix A written by hand in numba, for n balls.

Issue 14 ("a hand-written numba rhs of the thesis' Appendix A, the expert baseline, written once
inside the benchmark").  This is the one place in adbgen where the equations are typed by hand; it
exists only so that `adbgen bench precision` can time the generated code against what an expert
would write, and a test checks that it equals the generated rhs to round-off at random states.

The thesis' rotating-frame model (2.25)-(2.27), written as in Appendix A with u = x', v = y',
theta_i = phi_i' (A.1):

    a u' + b v' = f,   b u' + c v' = g                                  (A.3)-(A.4) with (A.6) inserted
    a = 1 + n mu - mu sum s_i^2,  b = mu sum s_i c_i,  c = 1 + n mu - mu sum c_i^2          (A.9)-(A.11)
    f = -2 zeta u + 2 Omega (1 + n mu) v - K x + 2 Omega zeta y + delta Omega^2
        + mu sum (Omega + theta_i)^2 c_i - mu beta sum theta_i s_i
        - mu A sum s_i^2 + mu B sum s_i c_i                                                 (A.12)
    g = -2 Omega (1 + n mu) u - 2 zeta v - 2 Omega zeta x - K y
        + mu sum (Omega + theta_i)^2 s_i + mu beta sum theta_i c_i
        + mu A sum s_i c_i - mu B sum c_i^2                                                 (A.13)
    u' = (c f - b g) / (a c - b^2),  v' = (a g - b f) / (a c - b^2)                         (A.7)-(A.8)
    theta_i' = -beta theta_i + (u' - A) s_i - (v' - B) c_i                                  (A.6)

with s_i = sin phi_i, c_i = cos phi_i, A = Omega^2 x + 2 Omega v, B = Omega^2 y - 2 Omega u and
K = 1 - Omega^2 (1 + n mu) (2.27).  The thesis' text of (A.12)-(A.13) as extracted interleaves the
two formulas' lines (the second line printed under (A.13) is the end of (A.12)); read in order they
agree with the above, which is what (2.25)-(2.26) give.

The state and parameter layout is the generated model's (`thesis_rotating_n<n>`): y = (x, y,
phi_1..phi_n, x', y', phi_1'..phi_n'), p = (Omega, beta, delta, mu, zeta) (`PARAM_ORDER`).  One
loop over the balls accumulates the sums (keeping each sin and cos in the output array's ball slots),
a second writes the balls' accelerations: O(n), one sin and one cos per ball, no matrix, no Python.
The thesis gives no Jacobian, so there is no hand-written one.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

PARAM_ORDER = ("Omega", "beta", "delta", "mu", "zeta")


@njit(cache=True)
def rhs_inplace(t, y, p, out):
    """out[:] = y'(t, y, p) for n = (len(y) - 4) / 2 balls, thesis (A.6)-(A.14)."""
    n = (y.shape[0] - 4) // 2
    Omega = p[0]
    beta = p[1]
    delta = p[2]
    mu = p[3]
    zeta = p[4]
    x = y[0]
    yy = y[1]
    u = y[n + 2]
    v = y[n + 3]
    W2 = Omega * Omega
    M = 1.0 + n * mu
    K = 1.0 - W2 * M
    A = W2 * x + 2.0 * Omega * v
    B = W2 * yy - 2.0 * Omega * u
    ss = 0.0
    sc = 0.0
    cc = 0.0
    cen_c = 0.0
    cen_s = 0.0
    damp_s = 0.0
    damp_c = 0.0
    for i in range(n):  # s_i, c_i parked in out (read back below): one sin and cos per ball
        s = math.sin(y[2 + i])
        c = math.cos(y[2 + i])
        out[n + 4 + i] = s
        out[2 + i] = c
        th = y[n + 4 + i]
        w = Omega + th
        w = w * w
        ss += s * s
        sc += s * c
        cc += c * c
        cen_c += w * c
        cen_s += w * s
        damp_s += th * s
        damp_c += th * c
    a = M - mu * ss
    b = mu * sc
    c_ = M - mu * cc
    f = (-2.0 * zeta * u + 2.0 * Omega * M * v - K * x + 2.0 * Omega * zeta * yy + delta * W2
         + mu * cen_c - mu * beta * damp_s - mu * A * ss + mu * B * sc)
    g = (-2.0 * Omega * M * u - 2.0 * zeta * v - 2.0 * Omega * zeta * x - K * yy
         + mu * cen_s + mu * beta * damp_c + mu * A * sc - mu * B * cc)
    det = a * c_ - b * b
    ud = (c_ * f - b * g) / det
    vd = (a * g - b * f) / det
    out[0] = u
    out[1] = v
    out[n + 2] = ud
    out[n + 3] = vd
    for i in range(n):
        th = y[n + 4 + i]
        out[n + 4 + i] = -beta * th + (ud - A) * out[n + 4 + i] - (vd - B) * out[2 + i]
        out[2 + i] = th


@njit(cache=True)
def rhs(t, y, p):
    """y'(t, y, p), a new array (what solve_ivp calls)."""
    out = np.empty(y.shape[0])
    rhs_inplace(t, y, p, out)
    return out


def check_layout(module) -> None:
    """Refuse a generated module whose layout is not the one written above (thesis_rotating_n<n>)."""
    n = int(module.N_BALLS)
    states = tuple(module.STATE_NAMES)
    want = ("x", "y", *(f"phi_{i}" for i in range(1, n + 1)), "x_dot", "y_dot",
            *(f"phi_{i}_dot" for i in range(1, n + 1)))
    if states != want or tuple(module.PARAM_NAMES) != PARAM_ORDER:
        raise ValueError(f"{module.NAME}: the hand-written baseline needs states {want} and parameters "
                         f"{PARAM_ORDER}, got {states} and {tuple(module.PARAM_NAMES)}")


def max_difference(module, samples: int = 200, seed: int = 0) -> float:
    """Largest relative difference (norm-wise) between the baseline and the generated rhs at random
    states and parameters (balls anywhere, rotor and rates small, mu and beta varied)."""
    check_layout(module)
    rng = np.random.default_rng(seed)
    n_states = len(module.STATE_NAMES)
    worst = 0.0
    for _ in range(samples):
        y = rng.uniform(-1.0, 1.0, n_states)
        y[2:2 + module.N_BALLS] *= math.pi
        p = np.asarray(module.DEFAULTS, float) * rng.uniform(0.5, 2.0, len(PARAM_ORDER))
        ref = np.asarray(module.rhs(0.0, y, p), float)
        got = rhs(0.0, y, p)
        worst = max(worst, float(np.max(np.abs(got - ref)) / max(np.max(np.abs(ref)), 1e-300)))
    return worst


__all__ = ["PARAM_ORDER", "check_layout", "max_difference", "rhs", "rhs_inplace"]
