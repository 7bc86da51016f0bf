"""Steady states of a generated autonomous model, their eigenvalues and stability (thesis ch. 3-4).

    refine(model, p, y0)              Newton on the generated rhs/jac -> SteadyState
    family_tangent(model, y, p)       the tangent space of the balanced family (3.6) at y (N x (n-2)),
                                      from the manifold of equilibria the module declares (EQUILIBRIA)
    transverse_spectrum(J, T)         the eigenvalues of J without the family's zero eigenvalues

**The continuum of balanced states.**  For n >= 3 balls (3.6) leaves n - 2 angles free: the balanced
states form an (n - 2)-dimensional manifold of equilibria {x = y = 0, rates = 0,
sum cos phi_i = -delta/mu, sum sin phi_i = 0}.  Its tangent space at a point is known in closed form:
the state vectors (0, 0, v, 0) with v in the null space of the gradients of the two constraints,
G = [[-sin phi_i]; [cos phi_i]] (2 x n).  The rhs vanishes along the manifold, so J T = 0 for an
orthonormal basis T of that space: n - 2 exact zero eigenvalues that are neutral directions (moving
along the family), not instability.  With Q = [T, S] orthogonal (S spanning the complement),

    Q^T J Q = [[0, T^T J S], [0, S^T J S]],

block upper triangular, so spec J = {0}^(n-2) u spec(S^T J S) exactly: S^T J S is the linearisation
in coordinates transverse to the family and carries the rest of the spectrum unchanged (shown in
tests/analysis/test_steady.py against the full spectrum, with a wrong tangent as negative control).
The same holds for the rank-(n-2) deflation J - sigma T T^T used to make AUTO-07p's problem regular
(every left eigenvector l of a non-zero eigenvalue has l^T T = 0, so l^T (J - sigma T T^T) = lambda l^T;
the zero eigenvalues move to -sigma).

Classification of the transverse spectrum (neutral directions of the family reported separately):
"stable" (all real parts < -tol), "unstable" (with the number of eigenvalues of positive real part),
"neutral" (none positive, some on the imaginary axis within tol: a bifurcation point).  Each state also
carries its margin (the leading transverse real part) and what the computation can certify of it
(`margins.eigenvalue_margin`: the eigenvalue condition number times the rounding of J and J's change over
the state's own Newton error): JSON margin, margin_uncertainty, marginal (issue 34 item 5).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .loading import AnalysisError, Model
from .margins import Margin, eigenvalue_margin

NEWTON_TOL = 1e-12  # max |rhs| accepted as a steady state, relative to max|J| max(1, max|y|)
ON_AXIS = 1e-9  # |Re lambda| <= ON_AXIS * max(1, |lambda|_max): on the imaginary axis


class SteadyStateError(AnalysisError):
    """Newton did not converge to a steady state."""


def _require_autonomous(model: Model) -> None:
    if not model.autonomous:
        raise AnalysisError(f"{model.name} depends on time explicitly (a forced model): it has periodic orbits, "
                            f"not steady states; use a rotating-frame model, or its AUTO files (periodic orbits)")


def residual(model: Model, y: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.asarray(model.module.rhs(0.0, y, p))


def jacobian(model: Model, y: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.asarray(model.module.jac(0.0, y, p))


def newton(model: Model, p: np.ndarray, y0: np.ndarray, tol: float = NEWTON_TOL, max_iter: int = 40,
           extra=None) -> tuple[np.ndarray, int]:
    """Newton's method with minimum-norm steps (SVD least squares) on rhs(y) = 0.

    Minimum-norm steps are orthogonal to the null space of J: on the continuum of balanced states
    (singular J) they converge to the nearest point of the family instead of failing, and elsewhere
    they are ordinary Newton steps.  `extra` = (g(y), dg/dy) appends equations (e.g. a pin).
    Returns (y, iterations); raises SteadyStateError if it does not converge."""
    y = np.array(y0, dtype=float)
    for it in range(max_iter + 1):
        f = residual(model, y, p)
        if not np.all(np.isfinite(f)):
            raise SteadyStateError("Newton: non-finite rhs (the state left the model's domain)")
        g = extra[0](y) if extra else np.zeros(0)
        J = jacobian(model, y, p)
        # relative to the size of the terms (dimensional models: accelerations of order omega^2)
        scale = max(1.0, float(np.max(np.abs(J))) * max(1.0, float(np.max(np.abs(y)))))
        if max(np.max(np.abs(f)), np.max(np.abs(g), initial=0.0)) <= tol * scale:
            return y, it
        if extra:
            J, f = np.vstack([J, extra[1](y)]), np.r_[f, g]
        y = y + _step(J, f)
    raise SteadyStateError(f"Newton did not converge in {max_iter} steps (|rhs| = {np.max(np.abs(f)):.3g}); "
                           f"start closer to a steady state (--y0 / --state)")


def _two_product(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """a * b = hi + lo exactly (Dekker's product by Veltkamp splitting; plain IEEE operations)."""
    split = 134217729.0  # 2^27 + 1
    ca, cb = split * a, split * b
    ah = ca - (ca - a)
    bh = cb - (cb - b)
    al, bl = a - ah, b - bh
    hi = a * b
    return hi, ((ah * bh - hi) + ah * bl + al * bh) + al * bl


def _step(J: np.ndarray, f: np.ndarray, refinements: int = 3) -> np.ndarray:
    """The minimum-norm Newton step -J^+ f, reproducible to the last bit on any BLAS.

    LAPACK's result depends in its last bits on the BLAS kernel it runs (OpenBLAS picks one per CPU
    type), and where Newton starts far from a steady state (the sweep's START at small mu) the state
    it reaches is chaotic in those bits: the thesis model with n = 4 at Omega = 0.4, mu = 0.007 reached
    coincident 2+, in-line 3(4-3)- or the balanced state by kernel.  Iterative refinement with the
    residual f + J s computed exactly and rounded once (Dekker products, math.fsum) converges on every
    kernel to the double nearest the exact step, barring ties within ~cond(J) eps of a rounding
    boundary."""
    step = np.linalg.lstsq(J, -f, rcond=1e-11)[0]
    for _ in range(refinements):
        hi, lo = _two_product(J, step[None, :])
        r = -np.array([math.fsum(row) for row in np.column_stack([f, hi, lo]).tolist()])
        new = step + np.linalg.lstsq(J, r, rcond=1e-11)[0]
        if np.array_equal(new, step):
            break
        step = new
    return step


# ---------------------------------------------------------------------------- the balanced family

def on_balanced_family(model: Model, y: np.ndarray, tol: float = 1e-9) -> bool:
    """At a state of the model's manifold of equilibria (its EQUILIBRIA, e.g. the balanced states of thesis
    (3.6) for n >= 3 balls): an autonomous model that declares one with more free coordinates than
    constraints, at a state where the states that vanish on it (the rotor's and every rate) are within
    tol of 0."""
    e = model.equilibria
    if e is None or not model.autonomous or model.n_states - len(e["zero"]) <= e["constraints"]:
        return False
    return bool(np.max(np.abs(y[[model.index(name) for name in e["zero"]]])) <= tol)


def constraint_gradients(model: Model, y: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
    """The gradients of the manifold's constraints with respect to the states (constraints x N), as the
    module emits them (thesis (3.6) for identical balls: -sin phi_i and cos phi_i)."""
    out = np.zeros((model.equilibria["constraints"], model.n_states))
    q = model.params() if p is None else np.asarray(p, dtype=float)
    model.module.equilibria_gradient_inplace(np.asarray(y, dtype=float), q, out)
    return out


def balanced_family_tangent(model: Model, y: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
    """Orthonormal basis (N x (free - rank)) of the tangent space of the manifold of equilibria at y.

    The null space of the constraint gradients (`constraint_gradients`; thesis (3.6) for identical
    balls) in the states that do not vanish on the manifold, taken by SVD (exact to rounding).  p: the
    parameters the gradients are taken at (default: the model's defaults).  N x 0 when y is not on it."""
    N = model.n_states
    if not on_balanced_family(model, y):
        return np.zeros((N, 0))
    zero = {model.index(name) for name in model.equilibria["zero"]}
    free = [i for i in range(N) if i not in zero]
    return _null_in(constraint_gradients(model, y, p)[:, free], free, N)


def _null_in(G: np.ndarray, leaves: list[int], N: int) -> np.ndarray:
    """Orthonormal null space of G (constraints x free states) embedded in the N states."""
    _, s, vt = np.linalg.svd(G)
    rank = int(np.sum(s > 1e-12 * max(1e-300, s[0])))
    T = np.zeros((N, len(leaves) - rank))
    T[leaves, :] = vt[rank:].T
    return T


def family_tangent(model: Model, y: np.ndarray, p: np.ndarray, J: np.ndarray | None = None) -> np.ndarray:
    """`balanced_family_tangent`, kept only where it is one: |J T| <= 1e-8 |J| (else N x 0, no reduction)."""
    T = balanced_family_tangent(model, y, p)
    if T.shape[1] and family_residual(jacobian(model, y, p) if J is None else J, T) > 1e-8:
        return np.zeros((model.n_states, 0))
    return T


def complement(T: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the orthogonal complement of span T (N x (N - k))."""
    N, k = T.shape
    if k == 0:
        return np.eye(N)
    q, _ = np.linalg.qr(np.hstack([T, np.eye(N)]))
    return q[:, k:N]


def transverse_jacobian(J: np.ndarray, T: np.ndarray) -> np.ndarray:
    """S^T J S: the linearisation in coordinates transverse to span T (J T = 0)."""
    S = complement(T)
    return S.T @ J @ S


def transverse_spectrum(J: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Eigenvalues of J without the family's zero eigenvalues: those of S^T J S (sorted)."""
    return sort_spectrum(np.linalg.eigvals(transverse_jacobian(J, T)))


def deflated_jacobian(J: np.ndarray, T: np.ndarray, sigma: float = 1.0) -> np.ndarray:
    """J - sigma T T^T: the family's zero eigenvalues moved to -sigma, the others unchanged."""
    return J - sigma * T @ T.T


def sort_spectrum(ev: np.ndarray) -> np.ndarray:
    """Descending real part, then descending imaginary part: a stable order for output and tests."""
    ev = np.asarray(ev, dtype=complex)
    return ev[np.lexsort((-ev.imag, -ev.real))]


def family_residual(J: np.ndarray, T: np.ndarray) -> float:
    """|J T| relative to |J|: ~1e-16 when T is the family's tangent space."""
    if T.shape[1] == 0:
        return 0.0
    return float(np.linalg.norm(J @ T) / max(1.0, np.linalg.norm(J)))


# ------------------------------------------------------------------------------------ results

def classify(spectrum: np.ndarray) -> tuple[str, int, int]:
    """(classification, number with Re > 0, number on the imaginary axis) of a (transverse) spectrum."""
    if spectrum.size == 0:
        return "neutral", 0, 0
    tol = ON_AXIS * max(1.0, float(np.max(np.abs(spectrum))))
    unstable = int(np.sum(spectrum.real > tol))
    on_axis = int(np.sum(np.abs(spectrum.real) <= tol))
    if unstable:
        return "unstable", unstable, on_axis
    return ("neutral" if on_axis else "stable"), 0, on_axis


@dataclass
class SteadyState:
    """A refined steady state: the state, its spectrum split into the family's neutral directions
    and the transverse eigenvalues that decide stability."""

    model: Model
    p: np.ndarray
    y: np.ndarray
    residual: float  # max |rhs(y)|
    iterations: int
    jacobian: np.ndarray
    tangent: np.ndarray  # N x k, the family's tangent space (k = 0: an isolated steady state)
    eigenvalues: np.ndarray  # the full spectrum of J
    transverse: np.ndarray  # the spectrum without the family's k zero eigenvalues
    neutral: np.ndarray  # the k eigenvalues of J along the family (zero to rounding)
    classification: str
    n_unstable: int
    n_on_axis: int
    tangent_residual: float = 0.0
    label: str = ""
    extra: dict = field(default_factory=dict)
    margin: Margin | None = None  # the leading transverse real part and its uncertainty (`margins`)

    @property
    def stable(self) -> bool:
        return self.classification == "stable"

    def to_json(self) -> dict:
        m = self.model
        pairs = lambda ev: [[float(z.real), float(z.imag)] for z in ev]  # noqa: E731
        return {
            "model": m.name, "state_label": self.label or None,
            "parameters": dict(zip(m.param_names, map(float, self.p))),
            "state": dict(zip(m.state_names, map(float, self.y))),
            "residual": self.residual, "newton_iterations": self.iterations,
            "classification": self.classification, "stable": self.stable,
            "n_unstable": self.n_unstable, "n_on_axis": self.n_on_axis,
            "family_dimension": int(self.tangent.shape[1]),
            "eigenvalues": pairs(self.transverse),
            "neutral_eigenvalues": pairs(self.neutral),
            "all_eigenvalues": pairs(self.eigenvalues),
            "tangent_residual": self.tangent_residual,
            **(self.margin.to_json() if self.margin is not None else {}),
        }


def _split_neutral(full: np.ndarray, transverse: np.ndarray) -> np.ndarray:
    """The eigenvalues of `full` left after matching each transverse eigenvalue to its nearest one."""
    rest = list(full)
    for z in transverse:
        rest.pop(int(np.argmin([abs(z - w) for w in rest])))
    return sort_spectrum(np.array(rest, dtype=complex))


def analyse(model: Model, p: np.ndarray, y: np.ndarray, iterations: int = 0, label: str = "") -> SteadyState:
    """Eigenvalues and classification of the steady state y (already refined)."""
    J = jacobian(model, y, p)
    T = family_tangent(model, y, p, J)
    res = family_residual(J, T)
    full = sort_spectrum(np.linalg.eigvals(J))
    transverse = transverse_spectrum(J, T)
    neutral = _split_neutral(full, transverse)
    kind, unstable, on_axis = classify(transverse)
    return SteadyState(model, np.array(p, float), np.array(y, float), float(np.max(np.abs(residual(model, y, p)))),
                       iterations, J, T, full, transverse, neutral, kind, unstable, on_axis, res, label,
                       margin=steady_margin(model, p, y, J, T))


def margin_at(model: Model, p: np.ndarray, y: np.ndarray) -> Margin:
    """`steady_margin` at the state y (e.g. a point of AUTO-07p's branch), the family's directions removed."""
    J = jacobian(model, y, p)
    return steady_margin(model, p, y, J, family_tangent(model, y, p, J))


def steady_margin(model: Model, p: np.ndarray, y: np.ndarray, J: np.ndarray, T: np.ndarray) -> Margin:
    """The leading transverse real part and what it is certain to: the eigenvalue condition number times
    the rounding of J plus J's change over the state's own error (one more Newton step, `margins`)."""
    S = complement(T)
    dy = _step(J, residual(model, y, p))
    moved = S.T @ jacobian(model, y + dy, p) @ S
    return eigenvalue_margin(S.T @ J @ S, moved)


def refine(model: Model, p: np.ndarray, y0: np.ndarray, label: str = "", tol: float = NEWTON_TOL) -> SteadyState:
    """Newton-refine y0 to a steady state of the generated rhs at p and analyse it."""
    _require_autonomous(model)
    y, it = newton(model, np.asarray(p, float), np.asarray(y0, float), tol=tol)
    return analyse(model, p, y, it, label)
