"""Large provable basin regions of a stable steady state: a Lyapunov function with the NONLINEAR decrease
condition (the sweeps' early stop, `attractors.stop_region(method="lyapunov")`, the default).

    lyapunov_region(model, y, p)  -> Region(P, T, rho2, c, rate) or None: around the steady state y,
                                     E = {e : e'Pe <= rho2 and V(e) <= c},  V(e) = e'Pe + T(e, e, e)

Lyapunov (direct method): if V > 0 and dV/dt = grad V(e) . f(y + e) < 0 at every e != 0 of the ball
B = {e'Pe <= rho2}, and c is below V's least value on the sphere e'Pe = rho2, then a trajectory in E
never reaches the sphere (V cannot grow while it is in B), so it stays in E and converges to y (V
decreases strictly and the only point where it cannot is e = 0).  This needs far less than the
contraction condition of `attractors.stop_region(method="contraction")` (the symmetric part of P J(z)
negative at every z of the region, i.e. the linearisation dominating everywhere): here only the flow
itself must point inwards, which for a lightly damped rotor allows far larger regions: at (5.1) the
balls' angles within 0.013 rad of balance for V = e'Pe alone (against 0.0023 by contraction) and 0.17
rad with the cubic term; every factor e of size saves 1 / (slowest decay rate) = 200 time units of
each trajectory.

The quadratic part is modal: P = Re(V^-H W V^-1) (V the eigenvectors of the Jacobian J, W > 0 diagonal,
equal on complex-conjugate pairs), so that e'Pe = sum_k w_k |m_k|^2 in the modal coordinates m and
the linearisation decays at least at the slowest mode's rate a: d(e'Pe)/dt = -2 sum_k a_k w_k |m_k|^2
+ O(|e|^3).  The weights (the slowest mode's fixed to 1) are chosen to enlarge the region (a grid of
starts and a few Nelder-Mead steps on a small set of rays): the nonlinear terms mix some modes more
than others.  The cubic form T removes the O(|e|^3) terms of dV/dt (`cubic_correction`: the
homological equation of normal-form theory, solvable because every Re lam < 0), leaving O(|e|^4)
against the -2 a V of the damping: on a lightly damped rotor that is what lets the region grow by an
order of magnitude.

What is proven and what is sampled: near e = 0 the condition holds exactly (the linearisation's
-2 a V dominates).  Further out it is CHECKED, not proven: along `rays` random directions from the
centre (uniform on the unit sphere of P), at radii on a geometric grid from 1e-3 to the first
failure (refined by bisection), V > 0 and dV/dt <= -2 a keep V are required (keep = 0.2: a margin of
80 % of the decay is left for the points between samples); the 16 worst directions are then searched
locally (random perturbations) for a smaller failure radius.  rho is the smallest failure radius
found times `shrink` (0.8); c is 0.9 times the least V found on the sphere (4 x `rays` random
points, the 16 lowest searched locally the same way).  The angles' half-widths in B are kept below
pi/2, so the region lies inside one period of the balls' angles.  This is sampling (no interval arithmetic); the
sweep tests and the benchmark check the labels it gives against full integrations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, types

from . import steady
from .loading import Model


# the generated rhs_inplace(t, y, p, out) as a first-class function: with this explicit type the kernel
# compiles once and is cached on disk (typed by the dispatcher itself it recompiles in every process)
_VEC = types.float64[::1]
_RHS = types.FunctionType(types.void(types.float64, _VEC, _VEC, _VEC))


@njit(cache=True)
def _fails(rhs, y0, p, s, d, q, t, a, b, rate, y, f):
    """Along the ray e = s d: V = s^2 q + s^3 t, grad V = 2 s a + 3 s^2 b (q = d'Pd, a = P d, b = T(d, d, .),
    t = b . d); True where V <= 0 or dV/dt > -2 rate V."""
    ny = y0.shape[0]
    for i in range(ny):
        y[i] = y0[i] + s * d[i]
    rhs(0.0, y, p, f)
    vdot = 0.0
    for i in range(ny):
        vdot += (2.0 * s * a[i] + 3.0 * s * s * b[i]) * f[i]
    v = s * s * q + s * s * s * t
    return v <= 0.0 or vdot > -2.0 * rate * v


@njit(_VEC(_RHS, _VEC, _VEC, types.float64[:, ::1], types.float64[:, :, ::1], types.boolean,
           types.float64[:, ::1], _VEC, types.float64), cache=True)
def _first_failures(rhs, y0, p, P, T, cubic, D, radii, rate):
    """For each row d of D: the smallest s on the grid `radii` (refined by bisection between it and the
    grid point before) where V(s d) <= 0 or dV/dt(s d) > -2 rate V(s d); radii[-1] if none.  V = e'Pe,
    plus T(e, e, e) if `cubic`."""
    n, ny = D.shape
    out = np.empty(n)
    y = np.empty(ny)
    f = np.empty(ny)
    a = np.empty(ny)
    b = np.zeros(ny)
    for k in range(n):
        d = D[k]
        q = 0.0
        t = 0.0
        for i in range(ny):
            acc = 0.0
            for j in range(ny):
                acc += P[i, j] * d[j]
            a[i] = acc
            q += acc * d[i]
        if cubic:
            for i in range(ny):
                acc = 0.0
                for j in range(ny):
                    inner = 0.0
                    for l in range(ny):
                        inner += T[i, j, l] * d[l]
                    acc += inner * d[j]
                b[i] = acc
                t += acc * d[i]
        lo = 0.0
        hi = -1.0
        for j in range(radii.shape[0]):
            if _fails(rhs, y0, p, radii[j], d, q, t, a, b, rate, y, f):
                hi = radii[j]
                break
            lo = radii[j]
        if hi < 0.0:
            out[k] = radii[-1]
            continue
        for _ in range(16):
            s = 0.5 * (lo + hi)
            if _fails(rhs, y0, p, s, d, q, t, a, b, rate, y, f):
                hi = s
            else:
                lo = s
        out[k] = lo
    return out


def _cubic_values(T: np.ndarray, U: np.ndarray) -> np.ndarray:
    """T(u, u, u) for the rows u of U."""
    n = T.shape[0]
    return np.sum((U @ T.reshape(n, n * n)) * (U[:, :, None] * U[:, None, :]).reshape(len(U), n * n), axis=1)


def hessian(model: Model, y, p, h: float = 1e-5) -> np.ndarray:
    """H[i, j, k] = d^2 f_i / dy_j dy_k at y: central differences of the generated analytic Jacobian
    (its accuracy only shapes the Lyapunov function; the check uses the exact rhs and gradient of V)."""
    n = len(y)
    H = np.zeros((n, n, n))
    for k in range(n):
        d = np.zeros(n)
        d[k] = h
        H[:, :, k] = (model.module.jac(0.0, y + d, p) - model.module.jac(0.0, y - d, p)) / (2.0 * h)
    return 0.5 * (H + H.transpose(0, 2, 1))


def cubic_correction(P: np.ndarray, H: np.ndarray, lam: np.ndarray, V: np.ndarray, Vi: np.ndarray) -> np.ndarray:
    """The symmetric cubic form T that removes the cubic terms of dV/dt for V = e'Pe + T(e, e, e).

    With f(e) = J e + g2(e) + O(|e|^3), g2_i = H_ijk e_j e_k / 2: dV/dt = e'(PJ + J'P)e + [e'P H(e, e) +
    3 T(e, e, J e)] + O(|e|^4).  In the modal coordinates m = V^-1 e the operator T -> 3 T(e, e, J e)
    multiplies the monomial m_a m_b m_c by lam_a + lam_b + lam_c (never 0: every Re lam < 0), so the
    bracket vanishes for T_abc = -C_abc / (lam_a + lam_b + lam_c), C the modal coefficients of e'P H(e, e)
    (the homological equation of normal-form theory)."""
    C = np.einsum("li,ijk->ljk", P, H)
    Cm = np.einsum("ljk,la,jb,kc->abc", C, V, V, V, optimize=True)
    S = lam[:, None, None] + lam[None, :, None] + lam[None, None, :]
    T = np.einsum("abc,al,bj,ck->ljk", -Cm / S, Vi, Vi, Vi, optimize=True).real
    perms = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    return sum(T.transpose(q) for q in perms) / 6.0


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


@dataclass
class Region:
    """{e : e'Pe <= rho2 and V(e) <= c}, V = e'Pe (+ T(e, e, e) when T is not None)."""

    P: np.ndarray
    T: np.ndarray | None
    rho2: float
    c: float
    rate: float  # the decay rate of V at the centre (the slowest mode's)


def lyapunov_region(model: Model, y, p, *, rays: int = 4096, keep: float = 0.2, shrink: float = 0.8,
                    seed: int = 0, optimise: bool = True, cubic: bool = True) -> Region | None:
    """A provable basin region of the stable hyperbolic steady state y (see the module docstring); None
    if y is not stable and hyperbolic, or its eigenvectors are (nearly) defective."""
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
    radii = np.geomspace(1e-3, 10.0, 52)
    rhs = m.rhs_inplace
    rhs.compile(_RHS.signature)
    rng = np.random.default_rng(seed)

    T0 = np.zeros((len(y),) * 3)

    def radius(P, D, T=None):
        return _first_failures(rhs, y, p, P, T0 if T is None else T, T is not None, D, radii, keep * rate)

    H = hessian(model, y, p) if cubic else None
    logw = np.zeros(len(groups) - 1)
    if optimise and len(groups) > 1:
        from scipy.optimize import minimize

        probe = np.random.default_rng(seed + 1)
        n_probe = max(64, rays // 8)

        def objective(x):
            """-(the region's level c) on the probe rays: its extent along the slowest mode is sqrt(c)."""
            P = weighted_metric(Vi, groups, np.clip(x, -6, 6))
            D = _directions(P, n_probe, probe)
            if H is None:
                return -float(radius(P, D).min()) ** 2
            T = cubic_correction(P, H, lam, V, Vi)
            r = float(radius(P, D, T).min())
            return -(r * r + r ** 3 * min(float(_cubic_values(T, D).min()), 0.0))

        # the same probe directions (in the unit sphere's coordinates) for every weight vector
        state = probe.bit_generator.state

        def fixed(x):
            probe.bit_generator.state = state
            return objective(x)

        # starts: equal weights and, for up to 3 weights, a grid of e^0 ... e^3 on each (the nonlinear terms
        # mix the slowest mode with one or two others; giving those more weight lets the region grow: at
        # (5.1) the best grid point doubles the level's root against equal weights); beyond, each faster
        # mode in turn weighted e^1.5
        if len(logw) <= 3:
            import itertools

            starts = [np.array(x, float) for x in itertools.product((0.0, 1.0, 2.0, 3.0), repeat=len(logw))]
        else:
            starts = [logw] + [1.5 * np.eye(len(logw))[k] for k in range(len(logw))]
        x0 = min(starts, key=fixed)
        best = minimize(fixed, x0, method="Nelder-Mead", options={"maxfev": 60, "xatol": 0.05, "fatol": 1e-7})
        logw = np.clip(best.x, -6, 6) if best.fun < fixed(x0) else x0
    P = weighted_metric(Vi, groups, logw)
    if np.min(np.linalg.eigvalsh(P)) <= 0:
        return None
    T = cubic_correction(P, H, lam, V, Vi) if cubic else None
    D = _directions(P, rays, rng)
    r = radius(P, D, T)
    # local search around the worst directions: random perturbations on the sphere, keep the worse
    L = np.linalg.cholesky(P)
    Li = np.linalg.inv(L)
    worst = np.argsort(r)[:16]
    r_min = float(r.min())
    for k in worst:
        u = L.T @ D[k]
        best_r = r[k]
        step = 0.3
        for _ in range(16):
            cand = u + step * rng.standard_normal((8, len(u)))
            cand /= np.linalg.norm(cand, axis=1)[:, None]
            rc = radius(P, np.ascontiguousarray(cand @ Li), T)
            j = int(np.argmin(rc))
            if rc[j] < best_r:
                best_r, u = rc[j], cand[j]
            else:
                step *= 0.6
        r_min = min(r_min, float(best_r))
    # keep the region inside one period of every angle: half-width rho sqrt((P^-1)_ii) <= pi/2
    Pi = np.linalg.inv(P)
    angles = list(model.angle_indices)
    half = math.sqrt(float(np.max(np.diag(Pi)[angles]))) if angles else 0.0
    rho = shrink * r_min
    if half > 0:
        rho = min(rho, 0.5 * math.pi / half)
    if T is None:
        return Region(P, None, rho * rho, rho * rho, rate)
    # the level: below V's least value on the sphere e'Pe = rho^2 (sampled, then a local search), so a
    # trajectory in {V <= c} never reaches the sphere while V decreases inside the ball
    U = _directions(P, 4 * rays, rng)
    tU = _cubic_values(T, U)
    worst = U[np.argsort(tU)[:16]]
    low = float(tU.min())
    for d in worst:
        u = L.T @ d
        step = 0.3
        for _ in range(30):
            cand = u + step * rng.standard_normal((16, len(u)))
            cand /= np.linalg.norm(cand, axis=1)[:, None]
            tc = _cubic_values(T, cand @ Li)
            j = int(np.argmin(tc))
            if tc[j] < low:
                low, u = float(tc[j]), cand[j]
            else:
                step *= 0.6
    c = 0.9 * (rho * rho + rho ** 3 * min(low, 0.0))
    if c <= 0:
        return None
    return Region(P, T, rho * rho, c, rate)
