"""Balls that merge in floating point, and a formulation that keeps each race's separation
(issue 14, item 3, "the converse failure").

In the section-6 run-ups of the two-plane paper the two balls of a race can come within round-off of
each other: theta_1 - theta_2 falls below ulp(theta_1) (theta grows like Omega t, so ulp(theta) is
~1e-13 at theta ~ 1000).  From then on the two angles are the same double and, because the generated
code evaluates every ball by the same floating-point operations (exact exchange symmetry), their
derivatives are the same double too: the balls stay merged for ever, although the exact solution
(whose separation is small but not zero) can separate them again.

The change of variables.  For a pair (k, l) of a race: the mean s = (theta_k + theta_l)/2 and the
half-difference d = (theta_k - theta_l)/2, likewise for the rates; the other states are kept.  With
y = T^-1 z (theta_k = s + d, theta_l = s - d) the system is z' = T f(t, T^-1 z): an exact
transformation of the generated rhs, no new equations (the code generator's emitted form for it is
issue 10's).  The numerics: d is now a variable of its own, carried at its own scale, so a separation
far below ulp(s) is represented; but the rhs still sees theta_k = fl(s + d), and fl(s + d) = fl(s - d)
once |d| < ulp(s)/2, so f_k - f_l would again be exactly 0.  The rounding of the reconstruction is
known exactly (TwoSum: r = (s + d) - fl(s + d) computed without error), so the rhs is evaluated as
f(fl(y)) + J(fl(y)) r, the first-order Taylor term carrying what the rounding removed (J is the
generated analytic Jacobian).  In exact arithmetic r = 0 and this is y' = T f(T^-1 z) exactly; in
floating point it gives d'' = (J r)_k - (J r)_l over 2 when the balls' angles round to the same
double: the linearised separation dynamics, instead of 0.  The Jacobian is evaluated only when some
pair is within `CLOSE` (relative) of merging, where the correction is not negligible.
"""

from __future__ import annotations

import math
import time

import numpy as np

CLOSE = 2.0 ** -20  # relative separation below which the rounding correction J r is applied


def pair_indices(model, pairs) -> tuple[np.ndarray, np.ndarray]:
    """Index arrays (first, second) of the paired states: each angle pair and its rate pair."""
    a, b = [], []
    for k, l in pairs:
        a += [model.index(k), model.index(k + "_dot")]
        b += [model.index(l), model.index(l + "_dot")]
    return np.array(a, np.int64), np.array(b, np.int64)


def to_pairs(y, ia, ib) -> np.ndarray:
    """z = T y: (mean, half-difference) in the places of (first, second)."""
    z = np.array(y, float)
    z[ia] = 0.5 * (y[ia] + y[ib])
    z[ib] = 0.5 * (y[ia] - y[ib])
    return z


def from_pairs(z, ia, ib) -> np.ndarray:
    """y = T^-1 z (rounded; the rhs below also keeps the rounding error)."""
    y = np.array(z, float)
    y[ia] = z[ia] + z[ib]
    y[ib] = z[ia] - z[ib]
    return y


def separation(y, ia_angles, ib_angles) -> np.ndarray:
    """|theta_k - theta_l| (wrapped to [0, pi]) per pair, along the last axis of y."""
    return wrapped(y[ia_angles] - y[ib_angles])


def wrapped(d) -> np.ndarray:
    """|d| modulo 2 pi, in [0, pi]; exact for small d (no `+ pi` that would round a tiny d away)."""
    d = np.asarray(d, float)
    return np.abs(d - 2 * math.pi * np.round(d / (2 * math.pi)))


def make_pair_rhs(model, pairs, compensate: bool = True):
    """njit functions (rhs(t, z, p) -> z', rhs_inplace(t, z, p, out), jac(t, z, p)) of the system in
    pair coordinates, from the generated rhs_inplace and jac."""
    from numba import njit

    f_in = model.module.rhs_inplace
    jac = model.module.jac
    ia, ib = pair_indices(model, pairs)
    n = model.n_states
    close = CLOSE
    comp = bool(compensate)

    @njit(cache=False)
    def rhs_inplace(t, z, p, out):
        y = z.copy()
        r = np.zeros(n)
        near = False
        for q in range(ia.shape[0]):
            i, j = ia[q], ib[q]
            s, d = z[i], z[j]
            hi = s + d  # TwoSum: hi + lo == s + d exactly
            bb = hi - s
            lo = (s - (hi - bb)) + (d - bb)
            hi2 = s - d
            bb2 = hi2 - s
            lo2 = (s - (hi2 - bb2)) + (-d - bb2)
            y[i], y[j], r[i], r[j] = hi, hi2, lo, lo2
            if abs(d) < close * max(abs(s), 1.0):
                near = True
        f_in(t, y, p, out)
        if comp and near:
            out += jac(t, y, p) @ r
        for q in range(ia.shape[0]):
            i, j = ia[q], ib[q]
            fa, fb = out[i], out[j]
            out[i] = 0.5 * (fa + fb)
            out[j] = 0.5 * (fa - fb)

    @njit(cache=False)
    def rhs(t, z, p):
        out = np.empty(n)
        rhs_inplace(t, z, p, out)
        return out

    @njit(cache=False)
    def pair_jac(t, z, p):
        # dz'/dz = T J T^-1: columns (first, second) of J combine as (J_a + J_b, J_a - J_b), rows as T
        y = z.copy()
        for q in range(ia.shape[0]):
            i, j = ia[q], ib[q]
            y[i] = z[i] + z[j]
            y[j] = z[i] - z[j]
        J = jac(t, y, p)
        K = J.copy()
        for q in range(ia.shape[0]):
            i, j = ia[q], ib[q]
            ca, cb = J[:, i].copy(), J[:, j].copy()
            K[:, i] = ca + cb
            K[:, j] = ca - cb
        L = K.copy()
        for q in range(ia.shape[0]):
            i, j = ia[q], ib[q]
            ra, rb = K[i, :].copy(), K[j, :].copy()
            L[i, :] = 0.5 * (ra + rb)
            L[j, :] = 0.5 * (ra - rb)
        return L

    return rhs, rhs_inplace, pair_jac


_CALLBACKS: dict = {}


def _callback(rhs_inplace, n: int, n_p: int) -> int:
    """Address of a C callback (numba cfunc) around rhs_inplace, compiled once per function and size."""
    key = (id(rhs_inplace), n, n_p)
    if key not in _CALLBACKS:
        import numba as nb
        from CyRK import nb_diffeq_addr

        f = rhs_inplace

        def diffeq(dy, t, y, args):
            yy = nb.carray(y, (n,))
            out = nb.carray(dy, (n,))
            pp = nb.carray(args, (n_p,))
            f(t, yy, pp, out)

        _CALLBACKS[key] = (nb_diffeq_addr(diffeq), rhs_inplace)  # keep the function alive with its id
    return _CALLBACKS[key][0]


def cyrk_solve(rhs_inplace, n: int, y0, p, t_end: float, rtol: float, atol: float, method: str = "DOP853",
               t_eval=None) -> dict:
    """CyRK's C++ solver (the same one the cyrk-* engines call) on an njit rhs_inplace(t, y, p, out),
    through a numba C callback (`CyRK.nb_diffeq_addr`): no Python per step."""
    from CyRK import nbsolve2_ivp

    addr = _callback(rhs_inplace, n, len(p))
    te = None if t_eval is None else np.ascontiguousarray(t_eval, float)
    start = time.perf_counter()
    res = nbsolve2_ivp(addr, (0.0, float(t_end)), np.ascontiguousarray(y0, float), method=method, t_eval=te,
                       args=np.ascontiguousarray(p, float), rtol=rtol, atol=atol)
    wall = time.perf_counter() - start
    try:
        out = {"status": "success" if res.success else f"failed ({res.status})", "t": np.array(res.t),
               "y": np.array(res.y).reshape(n, -1) if np.ndim(res.y) == 1 else np.array(res.y),
               "n_steps": int(res.steps_taken), "wall_s": wall}
    finally:
        res.free()
    return out


__all__ = ["CLOSE", "cyrk_solve", "from_pairs", "make_pair_rhs", "pair_indices", "separation", "to_pairs", "wrapped"]
