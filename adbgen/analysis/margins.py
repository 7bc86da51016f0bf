"""Stability margins and what a computation can certify of them (issue 34, item 5).

    Margin(value, uncertainty)                 value: leading real part (steady state) or leading |mu| - 1
                                               (periodic orbit); marginal when |value| <= uncertainty
    Margin.verdict(classification)             the classification, or "marginal (unstable by .., uncertain to
                                               ..)" when the margin cannot support it
    Margin.widened(extra, why)                 the same margin with `extra` added to its uncertainty
    eigenvalue_margin(A, J_moved=None)         of the (transverse) linearisation A
    multiplier_margin(M, mu, trivial, ...)     of a monodromy matrix M's non-trivial multipliers

A verdict (stable / unstable) is a sign; the margin says how far it is from changing, the uncertainty how
far the computed margin may be from the exact one.  Both are first-order perturbation bounds: an
eigenvalue z of A moves by at most kappa(z) |dA| + O(|dA|^2), kappa(z) = |l| |r| / |l^H r| its condition
number from the left and right eigenvectors (Wilkinson; Golub & Van Loan, Matrix Computations, 7.2.2).

* Steady state: dA is the rounding of A (|A| times N times the unit roundoff) plus the change of A over the
  state's own error, the size of one more Newton step (J(y + dy) - J(y), dy = -J^+ rhs(y)).
* Periodic orbit: dM is |M| times the integration's relative tolerance (the variational equations are
  integrated with RTOL), or the shooting residual where that is larger; and, for an autonomous orbit, the
  measured error of the trivial multiplier (exactly 1 in exact arithmetic) bounds the uncertainty from
  below: it is the accuracy the monodromy matrix actually has.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

UNIT_ROUNDOFF = float(np.finfo(float).eps) / 2


@dataclass(frozen=True)
class Margin:
    """A stability margin (< 0: stable side) and the uncertainty of the computation that produced it."""

    value: float
    uncertainty: float
    how: str  # how the uncertainty was estimated, for the output

    @property
    def marginal(self) -> bool:
        """The margin is inside what the computation can certify: the verdict may be either."""
        return bool(abs(self.value) <= self.uncertainty)

    def verdict(self, classification: str) -> str:
        """The classification a headline may state: as given when the margin certifies it; otherwise "marginal"
        with the side the computed margin is on and how far, against its uncertainty (a sign inside the
        uncertainty is not a verdict)."""
        if not self.marginal:
            return classification
        side = "unstable" if self.value > 0 else "stable" if self.value < 0 else "on the boundary"
        by = "" if self.value == 0 else f" by {abs(self.value):.2g}"
        return f"marginal ({side}{by}, uncertain to {self.uncertainty:.2g})"

    def widened(self, extra: float, why: str) -> Margin:
        """This margin with `extra` (>= 0) added to its uncertainty, `why` appended to how it was estimated."""
        return Margin(self.value, self.uncertainty + float(extra), f"{self.how}; {why}")

    def to_json(self) -> dict:
        return {"margin": float(self.value), "margin_uncertainty": float(self.uncertainty),
                "marginal": self.marginal, "margin_estimate": self.how}


def condition_numbers(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(eigenvalues, their condition numbers kappa = |l| |r| / |l^H r|) of A; inf for a defective one."""
    w, vl, vr = scipy.linalg.eig(A, left=True, right=True)
    dots = np.abs(np.sum(vl.conj() * vr, axis=0))
    norms = np.linalg.norm(vl, axis=0) * np.linalg.norm(vr, axis=0)
    with np.errstate(divide="ignore"):
        kappa = np.where(dots > 0, norms / np.maximum(dots, 1e-300), np.inf)
    return w, kappa


def eigenvalue_margin(A: np.ndarray, A_moved: np.ndarray | None = None) -> Margin:
    """The leading real part of A's spectrum; uncertainty kappa * (rounding of A + |A_moved - A|), with
    A_moved the linearisation at the state moved by its own error (None: rounding only).  An empty A
    (no transverse directions) has margin 0, certified as nothing."""
    A = np.asarray(A, float)
    if A.size == 0:
        return Margin(0.0, np.inf, "no transverse eigenvalues")
    w, kappa = condition_numbers(A)
    lead = int(np.argmax(w.real))
    perturbation = np.linalg.norm(A, 2) * A.shape[0] * UNIT_ROUNDOFF
    how = "eigenvalue condition number x (rounding of J"
    if A_moved is not None:
        perturbation += float(np.linalg.norm(np.asarray(A_moved) - A, 2))
        how += " + its change over the state's Newton error"
    # every eigenvalue within the bound of the leading one could lead: take the worst of their bounds
    near = w.real >= w.real[lead] - kappa * perturbation
    return Margin(float(w.real[lead]), float(np.max(kappa[near]) * perturbation), how + ")")


def multiplier_margin(M: np.ndarray, nontrivial: np.ndarray, trivial_error: float | None, rtol: float,
                      residual: float = 0.0) -> Margin:
    """max |mu| - 1 over the non-trivial multipliers of the monodromy matrix M; uncertainty: the larger of
    kappa(mu) |M| max(rtol, residual) and the trivial multiplier's error (autonomous orbits)."""
    M = np.asarray(M)
    mu = np.asarray(nontrivial, complex)
    if mu.size == 0:
        return Margin(0.0, np.inf, "no non-trivial multipliers")
    w, kappa = condition_numbers(M)
    lead = mu[int(np.argmax(np.abs(mu)))]
    k = kappa[int(np.argmin(np.abs(w - lead)))]
    bound = float(k * np.linalg.norm(M, 2) * max(rtol, residual))
    how = "multiplier condition number x |M| x the integration's rtol (or the shooting residual)"
    if trivial_error is not None:
        bound = max(bound, float(trivial_error))
        how += ", at least the trivial multiplier's error |mu - 1|"
    return Margin(float(abs(lead) - 1.0), bound, how)
