"""The first Lyapunov coefficient of a Hopf point: whether the bifurcating cycle is stable (supercritical)
or unstable (subcritical).

    l1, info = first_lyapunov(model, p, y, derivatives="jet")

Kuznetsov's formula (Elements of Applied Bifurcation Theory, 3rd ed., (3.20)), at an equilibrium y with
Jacobian A, A q = i w q, A^T p = -i w p, <q, q> = <p, q> = 1 (<a, b> = conj(a) . b):

    l1 = Re[ <p, C(q, q, q-bar)> - 2 <p, B(q, A^-1 B(q, q-bar))> + <p, B(q-bar, (2 i w - A)^-1 B(q, q))> ] / (2 w)

with B, C the second and third derivatives of the rhs.  l1 < 0: supercritical (a stable cycle on the
side where the equilibrium is unstable); l1 > 0: subcritical.  The cycle's amplitude squared then grows
linearly with the distance from the Hopf point: r^2 ~ -Re lambda'(alpha) (alpha - alpha_0) / l1.

B and C come from `jets.jacobian_jet` (exact: the generated Jacobian propagated as truncated Taylor
series) or, as the independent check, from central differences of the exact Jacobian.

On a continuum of equilibria (the balanced family of n >= 3 balls) A is singular along the family; the
formula then uses the family's tangent space T removed: A^-1 is taken on the complement (least squares,
the minimum-norm h with A h = -B(q, q-bar) + its projection on the left null space), and the drift term
is reported as `info["drift"]` = |L^T B(q, q-bar)| (L the left null space): where it is non-zero the
cycle's mean moves along the family at a rate proportional to its amplitude squared.
"""

from __future__ import annotations

import numpy as np

from ..loading import AnalysisError, Model
from . import jets


def hopf_vectors(A: np.ndarray, omega: float | None = None):
    """(w, q, p): the eigenvalue pair on (or nearest) the imaginary axis with Im > 0 (nearest i omega if
    given), q the right and p the left eigenvector, <q, q> = 1, <p, q> = 1."""
    ev, V = np.linalg.eig(A)
    cand = np.nonzero(ev.imag > 1e-10 * max(1.0, np.max(np.abs(ev))))[0]
    if not len(cand):
        raise AnalysisError("no complex eigenvalue pair: not a Hopf point")
    if omega is None:
        k = cand[np.argmin(np.abs(ev[cand].real))]
    else:
        k = cand[np.argmin(np.abs(ev[cand] - 1j * omega))]
    lam = ev[k]
    q = V[:, k] / np.linalg.norm(V[:, k])
    evl, W = np.linalg.eig(A.T)
    j = int(np.argmin(np.abs(evl - np.conj(lam))))
    p = W[:, j]
    p = p / np.conj(np.vdot(p, q))  # <p, q> = conj(p) . q = 1
    return lam, q, p


def first_lyapunov(model: Model, p, y, omega: float | None = None, derivatives: str = "jet", t: float = 0.0,
                   h: float = 1e-4) -> tuple[float, dict]:
    """l1 at the Hopf point (y, p) (see the module's docstring); info holds the frequency, the pair's real
    part (0 at an exact Hopf point), and the drift along a continuum of equilibria."""
    p = np.asarray(p, float)
    y = np.asarray(y, float)
    A = np.asarray(model.module.jac(t, y, p))
    lam, q, pv = hopf_vectors(A, omega)
    w = float(lam.imag)
    if derivatives == "jet":
        J = jets.jacobian_jet(model, t, y, p, q, order=2)
    elif derivatives == "differences":
        J = jets.differences(model, t, y, p, q, h=h)
    else:
        raise AnalysisError(f"derivatives: 'jet' or 'differences', not {derivatives!r}")
    Bq = J[1]  # B(q, .)
    Bqq_bar = Bq @ np.conj(q)
    Bqq = Bq @ q
    Cqqqb = 2.0 * J[2] @ np.conj(q)
    n = len(y)
    # A^-1 on the complement of its null space (an isolated equilibrium: the plain inverse)
    U, s, Vt = np.linalg.svd(A)
    null = s <= 1e-10 * s[0]
    drift = float(np.linalg.norm(U[:, null].T @ Bqq_bar)) if null.any() else 0.0
    h11 = -np.linalg.lstsq(A, Bqq_bar - U[:, null] @ (U[:, null].T @ Bqq_bar), rcond=1e-10)[0]
    h20 = np.linalg.solve(2j * w * np.eye(n) - A, Bqq)
    # B(q-bar, v) = conj(B(q, conj(v))) for a real rhs
    term = np.vdot(pv, Cqqqb) + 2 * np.vdot(pv, Bq @ h11) + np.vdot(pv, np.conj(Bq @ np.conj(h20)))
    l1 = float(term.real / (2 * w))
    return l1, {"frequency": w, "real_part": float(lam.real), "drift": drift, "null_dimension": int(null.sum())}


def criticality(l1: float) -> str:
    return "supercritical" if l1 < 0 else "subcritical"


def add_to_scan(scan) -> None:
    """first_lyapunov and criticality on each Hopf point of a `continuation.Scan` (at its located state)."""
    k = scan.model.param_names.index(scan.name)
    for b in scan.points:
        if b.kind != "hopf" or scan.p is None:
            continue
        p = np.array(scan.p, float)
        p[k] = b.value
        try:
            l1, _ = first_lyapunov(scan.model, p, b.y, b.frequency)
        except AnalysisError:
            continue
        b.extra.update(first_lyapunov=l1, criticality=criticality(l1))
