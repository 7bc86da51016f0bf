"""Large provable basin regions of a stable steady state: a quadratic Lyapunov function with the
NONLINEAR decrease condition (the sweeps' early stop, `attractors.Classifier(method="lyapunov")`).

    lyapunov_region(model, y, p)  -> (P, c, rate) or None: E = {e : e'Pe <= c} around the steady state y

Lyapunov (direct method): if V(e) = e'Pe (P > 0) satisfies dV/dt = 2 e'P f(y + e) < 0 at every e != 0
of the sublevel set E_c = {V <= c}, then E_c is forward invariant (V cannot grow past c) and every
trajectory in it converges to y (V decreases strictly and the only point where it cannot is e = 0).
This needs far less than the contraction condition of `attractors.stop_region` (the symmetric part
of P J(z) negative at every z of the region, i.e. the linearisation dominating everywhere): here only
the flow itself must point inwards, which for a lightly damped rotor allows regions about ten times
larger across (at (5.1) the balls' angles within about 2e-2 rad of balance instead of 2e-3; every
factor e of size saves 1 / (slowest decay rate) = 200 time units of each trajectory).

The metric is modal: P = Re(V^-H W V^-1) (V the eigenvectors of the Jacobian J, W > 0 diagonal,
equal on complex-conjugate pairs), so that e'Pe = sum_k w_k |m_k|^2 in the modal coordinates m and
the linearisation decays at least at the slowest mode's rate a: dV/dt = -2 sum_k a_k w_k |m_k|^2 +
O(|e|^3) <= -2 a V + O(|e|^3).  The weights W (one per mode, the slowest mode's fixed to 1) are chosen
to maximise the certified size (a few Nelder-Mead steps on a small set of rays): the nonlinear terms
feed some modes more than others, and giving those less weight lets the region grow.

What is proven and what is sampled: near e = 0 the condition holds exactly (the linearisation's
-2 a V dominates the O(|e|^3) remainder).  Further out it is CHECKED, not proven: along `rays` random
directions from the centre (uniform on the unit sphere of P), at radii on a geometric grid from 1e-4
to the first failure (refined by bisection), dV/dt <= -2 a keep V is required (keep = 0.2: a margin of
80 % of the decay is left for the points between samples); the worst directions are then searched
locally (random perturbations) for a smaller failure radius.  The region is the smallest failure
radius found, times `shrink` (0.8), squared.  The angles' half-widths are kept below pi/2, so the
region lies inside one period of the balls' angles.  This is sampling (no interval arithmetic); the
sweep tests and the benchmark check the labels it gives against full integrations.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import steady
from .loading import Model


@njit(cache=True)
def _first_failures(rhs, y0, p, P, D, radii, rate):
    """For each row d of D (d'Pd = 1): the smallest s on the grid `radii` (then refined by bisection
    between it and the grid point before) where dV/dt(s d) > -2 rate V(s d); radii[-1] if none."""
    n, ny = D.shape
    out = np.empty(n)
    f = np.empty(ny)
    y = np.empty(ny)
    Pd = np.empty(ny)
    for k in range(n):
        for i in range(ny):
            acc = 0.0
            for j in range(ny):
                acc += P[i, j] * D[k, j]
            Pd[i] = acc
        lo = 0.0
        hi = -1.0
        for g in range(radii.shape[0]):
            s = radii[g]
            for i in range(ny):
                y[i] = y0[i] + s * D[k, i]
            rhs(0.0, y, p, f)
            v = 0.0
            for i in range(ny):
                v += Pd[i] * f[i]
            # dV/dt = 2 s (Pd . f), V = s^2: fails when 2 s (Pd . f) > -2 rate s^2
            if v > -rate * s:
                hi = s
                break
            lo = s
        if hi < 0.0:
            out[k] = radii[-1]
            continue
        for _ in range(30):
            s = 0.5 * (lo + hi)
            for i in range(ny):
                y[i] = y0[i] + s * D[k, i]
            rhs(0.0, y, p, f)
            v = 0.0
            for i in range(ny):
                v += Pd[i] * f[i]
            if v > -rate * s:
                hi = s
            else:
                lo = s
        out[k] = lo
    return out


def modal_groups(lam: np.ndarray) -> list[np.ndarray]:
    """Indices of the eigenvalues by mode (a complex-conjugate pair is one mode), slowest decay first."""
    left = list(range(len(lam)))
    groups = []
    while left:
        k = left.pop(0)
        g = [k]
        if abs(lam[k].imag) > 0:
            j = min(left, key=lambda i: abs(lam[i] - np.conj(lam[k])), default=None)
            if j is not None and abs(lam[j] - np.conj(lam[k])) <= 1e-9 * max(1.0, abs(lam[k])):
                left.remove(j)
                g.append(j)
        groups.append(np.array(g))
    groups.sort(key=lambda g: -lam[g[0]].real)
    return groups


def weighted_metric(Vi: np.ndarray, groups, logw) -> np.ndarray:
    """P = Re(V^-H W V^-1), W = exp(logw) on the modes (the first, slowest, weighted 1)."""
    w = np.ones(Vi.shape[0])
    for g, v in zip(groups[1:], logw):
        w[g] = math.exp(v)
    P = (Vi.conj().T @ (w[:, None] * Vi)).real
    return 0.5 * (P + P.T)


def _directions(P: np.ndarray, n: int, rng) -> np.ndarray:
    """n directions d uniform on the unit sphere of P (d'Pd = 1)."""
    u = rng.standard_normal((n, len(P)))
    u /= np.linalg.norm(u, axis=1)[:, None]
    return np.ascontiguousarray(u @ np.linalg.inv(np.linalg.cholesky(P)))


def lyapunov_region(model: Model, y, p, *, rays: int = 4096, keep: float = 0.2, shrink: float = 0.8,
                    seed: int = 0, optimise: bool = True) -> tuple[np.ndarray, float, float] | None:
    """(P, c, a) of a provable basin region {e'Pe <= c} of the stable hyperbolic steady state y (see the
    module docstring), a its decay rate at the centre; None if y is not stable and hyperbolic, or its
    eigenvectors are (nearly) defective."""
    m = model.module
    y = np.asarray(y, float)
    p = np.asarray(p, float)
    J = m.jac(0.0, y, p)
    if not np.all(np.isfinite(J)) or steady.family_tangent(model, y, p, J).shape[1]:
        return None
    lam, V = np.linalg.eig(J)
    if np.max(lam.real) >= -1e-9 or np.linalg.cond(V) > 1e8:
        return None
    Vi = np.linalg.inv(V)
    groups = modal_groups(lam)
    rate = -float(np.max(lam.real))  # the slowest decay: V = e'Pe decays at >= 2 rate near the centre
    radii = np.geomspace(1e-4, 10.0, 64)
    rhs = m.rhs_inplace
    rng = np.random.default_rng(seed)

    def radius(P, D):
        return _first_failures(rhs, y, p, P, D, radii, keep * rate)

    logw = np.zeros(len(groups) - 1)
    if optimise and len(groups) > 1:
        from scipy.optimize import minimize

        probe = np.random.default_rng(seed + 1)
        n_probe = max(64, rays // 8)

        def objective(x):
            P = weighted_metric(Vi, groups, np.clip(x, -6, 6))
            return -float(radius(P, _directions(P, n_probe, probe)).min())

        # the same probe directions (in the unit sphere's coordinates) for every weight vector
        state = probe.bit_generator.state

        def fixed(x):
            probe.bit_generator.state = state
            return objective(x)

        best = minimize(fixed, logw, method="Nelder-Mead",
                        options={"maxfev": 40, "xatol": 0.1, "fatol": 1e-6, "initial_simplex": None})
        if -best.fun > -fixed(logw):
            logw = np.clip(best.x, -6, 6)
    P = weighted_metric(Vi, groups, logw)
    if np.min(np.linalg.eigvalsh(P)) <= 0:
        return None
    D = _directions(P, rays, rng)
    r = radius(P, D)
    # local search around the worst directions: random perturbations on the sphere, keep the worse
    Li = np.linalg.inv(np.linalg.cholesky(P))
    L = np.linalg.cholesky(P)
    worst = np.argsort(r)[:16]
    r_min = float(r.min())
    for k in worst:
        u = L.T @ D[k]
        best_r = r[k]
        step = 0.3
        for _ in range(24):
            cand = u + step * rng.standard_normal((8, len(u)))
            cand /= np.linalg.norm(cand, axis=1)[:, None]
            rc = radius(P, np.ascontiguousarray(cand @ Li))
            j = int(np.argmin(rc))
            if rc[j] < best_r:
                best_r, u = rc[j], cand[j]
            else:
                step *= 0.6
        r_min = min(r_min, float(best_r))
    # keep the region inside one period of every angle: half-width sqrt(c (P^-1)_ii) <= pi/2
    Pi = np.linalg.inv(P)
    angles = list(model.angle_indices)
    half = math.sqrt(float(np.max(np.diag(Pi)[angles]))) if angles else 0.0
    s = shrink * r_min
    if half > 0:
        s = min(s, 0.5 * math.pi / half)
    return P, s * s, rate
