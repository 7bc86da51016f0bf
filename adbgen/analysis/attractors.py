"""Where a trajectory ends (thesis ch. 3-5): steady states, their spectra, provable basin regions, labels.

    newton(model, y, p)             a steady state refined from y on the generated rhs and jac
    spectrum(model, y, p)           eigenvalues; for the balanced family of n >= 3 balls the n - 2 exact
                                    zeros along the family removed (reported as neutral)
    stop_region(model, y, p)        a region around a stable steady state every trajectory entering it
                                    provably converges to it (Lyapunov; early stop of sweeps)
    Classifier(model, p).label(...) balanced 1, coincident 2+-, in-line 3(n-m)+-, limit cycle, unsettled

These are the small pieces the sweeps need; the general steady-state and continuation tools live in
the stability layer (a Newton refinement and a deflated spectrum there are the same mathematics).

The steady states and their names follow the thesis: balanced 1 (3.6) with x = y = 0; coincident 2+-
(3.9) with all balls together; in-line 3(n-m)+- (3.10) with m balls together and n - m opposite.  The
sign is that of the arccosine in (3.9)/(3.10), read off the closed form for the thesis' rotating-frame
models; for other models the names carry no sign.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg

from .loading import Model

TWO_PI = 2.0 * math.pi


def _wrap(a):
    return np.remainder(np.asarray(a) + math.pi, TWO_PI) - math.pi


def state_difference(model: Model, a, b) -> np.ndarray:
    """a - b with the ball angles wrapped to [-pi, pi)."""
    d = np.asarray(a, float) - np.asarray(b, float)
    idx = list(model.angle_indices)
    d[..., idx] = _wrap(d[..., idx])
    return d


# ------------------------------------------------------------------------------------- steady states

def newton(model: Model, y, p, *, tol: float = 1e-11, max_iter: int = 40) -> np.ndarray | None:
    """A zero of rhs(0, ., p) near y (least-squares steps: the balanced family of n >= 3 is a continuum,
    so the Jacobian is singular along it); None if it does not converge."""
    if not model.autonomous:
        return None
    m = model.module
    y = np.array(y, dtype=float)
    p = np.asarray(p, dtype=float)
    for _ in range(max_iter):
        f = m.rhs(0.0, y, p)
        if not np.all(np.isfinite(f)):
            return None
        if np.max(np.abs(f)) < tol:
            return y
        step = np.linalg.lstsq(m.jac(0.0, y, p), -f, rcond=None)[0]
        y = y + step
        if not np.all(np.isfinite(y)):
            return None
    f = m.rhs(0.0, y, p)
    return y if np.max(np.abs(f)) < 100 * tol else None


def amplitude_of(model: Model, y) -> float:
    ix, iy, _, _ = model.amplitude_indices
    return float(math.hypot(y[ix], y[iy]))


def family_tangent(model: Model, y, p) -> np.ndarray | None:
    """Tangent space (columns, orthonormal) of the balanced family (3.6) through y, for n >= 3 balls.

    Along the family x = y = 0, the rates are 0 and sum cos(phi_i), sum sin(phi_i) are fixed, so its
    tangent vectors v (angle components only) satisfy sum sin(phi_i) v_i = sum cos(phi_i) v_i = 0: an
    (n - 2)-dimensional space, in the kernel of the Jacobian (checked here, else None)."""
    angles = list(model.angle_indices)
    n = len(angles)
    if n < 3 or amplitude_of(model, y) > 1e-9:
        return None
    phi = np.asarray(y)[angles]
    null = scipy.linalg.null_space(np.vstack([np.sin(phi), np.cos(phi)]))
    if null.shape[1] != n - 2:
        return None
    T = np.zeros((model.n_states, n - 2))
    T[angles] = null
    J = model.module.jac(0.0, np.asarray(y, float), np.asarray(p, float))
    if np.linalg.norm(J @ T) > 1e-8 * max(1.0, np.linalg.norm(J)):
        return None
    return T


@dataclass
class Spectrum:
    eigenvalues: np.ndarray  # the deflated spectrum (neutral family directions removed)
    neutral: int  # number of exact zeros removed (n - 2 on the balanced family of n >= 3 balls)

    def unstable(self, tol: float = 1e-9) -> int:
        return int(np.sum(self.eigenvalues.real > tol))

    @property
    def abscissa(self) -> float:
        return float(np.max(self.eigenvalues.real)) if len(self.eigenvalues) else float("nan")


def spectrum(model: Model, y, p) -> Spectrum:
    """Eigenvalues of the Jacobian at a steady state; on the balanced family of n >= 3 balls, the
    spectrum transverse to it: with V = [T, W] orthonormal (T the family's tangent, J T = 0),
    V' J V = [[0, T'JW], [0, W'JW]] is block triangular, so spec J = {0}^(n-2) + spec(W'JW) exactly."""
    J = model.module.jac(0.0, np.asarray(y, float), np.asarray(p, float))
    T = family_tangent(model, y, p)
    if T is None:
        return Spectrum(np.linalg.eigvals(J), 0)
    W = scipy.linalg.null_space(T.T)
    return Spectrum(np.linalg.eigvals(W.T @ J @ W), T.shape[1])


# --------------------------------------------------------------------------------------------- names

def _thesis_like(model: Model) -> bool:
    return (model.autonomous and tuple(model.module.CORE) == ("x", "y")
            and {"Omega", "delta", "mu", "zeta"} <= set(model.param_names))


def labels(model: Model) -> list[str]:
    """Every label a sweep of `model` can give, in a fixed order (the stored codes index this list)."""
    n = len(model.angle_indices)
    out = ["balanced 1"]
    if n >= 2:
        out += ["coincident 2-", "coincident 2+", "coincident 2"]
        for m in range(n - 1, (n - 1) // 2, -1):  # m balls together, n - m opposite, m >= n - m
            if 2 * m == n:
                out.append(f"in-line 3({n}-{m})")
            else:
                out += [f"in-line 3({n}-{m})-", f"in-line 3({n}-{m})+", f"in-line 3({n}-{m})"]
    out += ["other steady state", "limit cycle", "unsettled", "failed"]
    return out


def _closed_form_angles(model: Model, p, n_net: int) -> tuple[float, float] | None:
    """phi_1 of (3.9)/(3.10) for the signs -, + (n_net = 2m - n balls net on phi_1's side)."""
    if not _thesis_like(model):
        return None
    par = dict(zip(model.param_names, np.asarray(p, float)))
    n = len(model.angle_indices)
    Om, mu, zeta, delta = par["Omega"], par["mu"], par["zeta"], par["delta"]
    K = 1.0 - Om**2 * (1.0 + n * mu)
    if zeta <= 0:
        return None
    arg = -2.0 * n_net * mu * zeta * Om / math.sqrt((2 * Om * zeta * delta) ** 2 + (K * delta) ** 2)
    if abs(arg) > 1:
        return None
    shift = math.atan(-K / (2.0 * Om * zeta))
    return -math.acos(arg) - shift, math.acos(arg) - shift


def name_steady_state(model: Model, y, p, tol: float = 1e-6) -> str:
    """The thesis' name of the steady state y: balanced 1, coincident 2+-, in-line 3(n-m)+-."""
    if amplitude_of(model, y) < 1e-8:
        return "balanced 1"
    angles = np.asarray(y)[list(model.angle_indices)]
    n = len(angles)
    ref = angles[0]
    same = np.abs(_wrap(angles - ref)) < tol
    opposite = np.abs(_wrap(angles - ref - math.pi)) < tol
    if not np.all(same | opposite) or n < 2:
        return "other steady state"
    m = int(same.sum())
    if m < n - m:  # name by the larger group
        same, opposite, m, ref = opposite, same, n - m, ref + math.pi
    kind = "coincident 2" if m == n else f"in-line 3({n}-{m})"
    if 2 * m == n:
        return kind
    closed = _closed_form_angles(model, p, 2 * m - n)
    if closed is None:
        return kind
    for sign, phi in zip("-+", closed):
        if abs(_wrap(ref - phi)) < 1e-5:
            return kind + sign
    return kind


# ------------------------------------------------------------------------------ provable basin regions

@dataclass
class StopRegion:
    """A stable steady state with an ellipsoid E = {e : e'Pe <= c} (e = y - centre, angles wrapped) on
    which V = e'Pe decreases along every trajectory, so a trajectory inside E stays inside and converges
    to the centre (see `stop_region`)."""

    label: str
    centre: np.ndarray
    P: np.ndarray
    c: float

    def contains(self, model: Model, y) -> np.ndarray:
        e = state_difference(model, np.atleast_2d(y), self.centre)
        return np.einsum("ki,ij,kj->k", e, self.P, e) <= self.c


def _modal_metric(J: np.ndarray) -> np.ndarray | None:
    """P = Re(V^-H V^-1), V the eigenvectors of J: e'Pe = |modal coordinates|^2, so the linearisation
    decays in this norm at the slowest mode's rate (a lightly damped rotor's natural norm; the identity
    Lyapunov metric J'P + PJ = -I is far worse conditioned for it)."""
    lam, V = np.linalg.eig(J)
    if np.linalg.cond(V) > 1e8:  # (nearly) defective: fall back to the Lyapunov metric
        P = scipy.linalg.solve_continuous_lyapunov(J.T, -np.eye(len(J)))
    else:
        Vi = np.linalg.inv(V)
        P = (Vi.conj().T @ Vi).real
    P = 0.5 * (P + P.T)
    return P if np.min(np.linalg.eigvalsh(P)) > 0 else None


def stop_region(model: Model, y, p, *, samples: int = 256, seed: int = 0,
                keep: float = 0.2) -> StopRegion | None:
    """A provable basin region of the steady state y if it is stable and hyperbolic, else None.

    With the modal metric P (`_modal_metric`) and L its Cholesky factor, the decay rate of V = e'Pe at
    a point z is bounded by the largest eigenvalue of L^-1 (P J(z) + J(z)'P) L^-T; at the centre it is
    -2 a (a = the slowest mode's decay rate).  E_c qualifies when that bound stays below -2 a `keep` at
    every sampled z of E_c (its boundary and the half-size shell, `samples` points each): on the segment
    from the centre to any point of E_c the averaged Jacobian then keeps dV/dt <= -2 a keep V, so E_c
    is forward invariant and V -> 0 (Lyapunov).  `keep` < 1 is the margin left for unsampled points;
    c is halved from 1 until the check passes, then halved once more as a further margin.  The check
    samples E_c (it is not interval arithmetic); the sweep tests compare the labels it gives with full
    integrations.

    How large E_c can be is physics: the Jacobian may change by about the slowest decay rate a across
    it, so its size is about a / |d J / d y|.  At (5.1) (a = 0.005) the balls' angles must be within
    about 2e-3 rad of balance, which trajectories reach late (t ~ 1100-1600 of 2000; benchmarks/sweep.json)."""
    m = model.module
    y = np.asarray(y, float)
    p = np.asarray(p, float)
    J = m.jac(0.0, y, p)
    if not np.all(np.isfinite(J)) or family_tangent(model, y, p) is not None:
        return None
    if np.max(np.linalg.eigvals(J).real) >= -1e-9:
        return None
    P = _modal_metric(J)
    if P is None:
        return None
    L = np.linalg.cholesky(P)
    Li = np.linalg.inv(L)  # small and well conditioned; products are much cheaper than triangular solves

    def rate(z):
        S = P @ m.jac(0.0, z, p)
        M = Li @ (S + S.T) @ Li.T
        return np.max(np.linalg.eigvalsh(0.5 * (M + M.T)))

    bound = keep * rate(y)  # -2 a keep
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((samples, len(y)))
    u /= np.linalg.norm(u, axis=1)[:, None]
    directions = u @ Li  # e = L^-T u: e'Pe = |u|^2 = 1
    c = 1.0
    for _ in range(80):
        if all(rate(y + math.sqrt(c) * shell * d) <= bound for shell in (1.0, 0.5) for d in directions):
            return StopRegion("", y.copy(), P, 0.5 * c)
        c *= 0.5
    return None


# ---------------------------------------------------------------------------------------- classifier

def seeds(model: Model, p) -> list[np.ndarray]:
    """Starting points for the steady states: START with its balls permuted (identical balls: each
    permutation is a steady state too, physically the same, in state space another point), and for
    the thesis' models the closed forms of the coincident (3.9) and in-line (3.10) states."""
    import itertools

    start = np.array(model.module.START, dtype=float)
    angles = list(model.angle_indices)
    out = []
    for perm in itertools.islice(itertools.permutations(range(len(angles))), 120):
        y = start.copy()
        y[angles] = start[[angles[k] for k in perm]]
        if not any(np.array_equal(y, o) for o in out):
            out.append(y)
    n = len(model.angle_indices)
    ix, iy, _, _ = model.amplitude_indices
    for m in range(n, (n - 1) // 2, -1):
        closed = _closed_form_angles(model, p, 2 * m - n)
        for phi in closed or ():
            y = np.zeros(model.n_states)
            for k, i in enumerate(model.angle_indices):
                y[i] = phi if k < m else phi + math.pi
            y[ix] = y[iy] = 0.0  # Newton finds x, y (linear in them)
            out.append(y)
    return out


@dataclass
class Classifier:
    """Labels final states for one parameter vector: stop regions of its stable steady states, then
    Newton from the final state, then a short continuation telling a limit cycle from the rest."""

    model: Model
    p: np.ndarray
    regions: list = field(default_factory=list)
    window: float = 200.0

    def __post_init__(self):
        self.codes = {name: k for k, name in enumerate(labels(self.model))}
        found: list[np.ndarray] = []
        for s in seeds(self.model, self.p):
            y = newton(self.model, s, self.p)
            if y is None or any(np.max(np.abs(state_difference(self.model, y, f))) < 1e-7 for f in found):
                continue
            found.append(y)
            region = stop_region(self.model, y, self.p)
            if region is not None:
                region.label = name_steady_state(self.model, y, self.p)
                self.regions.append(region)

    def inside(self, Y) -> np.ndarray:
        """Index of the stop region each row of Y is in, -1 if none."""
        Y = np.atleast_2d(Y)
        out = np.full(len(Y), -1)
        for k, r in reversed(list(enumerate(self.regions))):
            out[r.contains(self.model, Y)] = k
        return out

    def code(self, name: str) -> int:
        return self.codes[name]

    def label(self, status: str, y_end, target: int, *, engine=None, rtol=1e-8, atol=1e-10) -> str:
        from .results import STOPPED, SUCCESS

        if status == STOPPED and target >= 0:
            return self.regions[target].label
        if status != SUCCESS:
            return "failed"
        k = self.inside(y_end)[0]  # forward invariant: inside at t_end means converging to it
        if k >= 0:
            return self.regions[k].label
        y = newton(self.model, y_end, self.p)
        if y is not None:
            # at a steady state; or near a stable one (its deflated spectrum: the n >= 3 balanced family
            # has no stop region, its members are approached slowly, like every lightly damped state)
            gap = np.max(np.abs(state_difference(self.model, y, y_end)))
            if gap < 1e-5 or (gap < 1e-3 and spectrum(self.model, y, self.p).unstable() == 0):
                return name_steady_state(self.model, y, self.p)
        return self._oscillation(y_end, engine, rtol, atol)

    def _oscillation(self, y_end, engine, rtol, atol) -> str:
        """limit cycle: over a further window r keeps one band (its max and min in both halves agree to
        1 % of the max); otherwise unsettled."""
        from .simulate import amplitude, simulate

        sim = simulate(self.model, self.p, np.asarray(y_end, float), t_end=self.window, rtol=rtol, atol=atol,
                       engine=engine, keep_trajectory=True, check=False)
        if not sim.ok or sim.t.size < 8:
            return "unsettled"
        r = amplitude(self.model, sim.y)
        half = sim.t >= 0.5 * self.window
        a, b = r[~half], r[half]
        top = max(a.max(), b.max())
        if abs(a.max() - b.max()) <= 0.01 * top and abs(a.min() - b.min()) <= 0.01 * top:
            return "limit cycle"
        return "unsettled"


@lru_cache(maxsize=64)
def _classifier_cached(model: Model, p: tuple) -> Classifier:
    return Classifier(model, np.array(p))


def classifier(model: Model, p) -> Classifier:
    """The Classifier for parameters p (cached: the regions are computed once per parameter vector)."""
    return _classifier_cached(model, tuple(float(v) for v in p))
