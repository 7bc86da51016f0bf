"""The balancing state of a periodically forced model (issue 39): a periodic orbit, not an equilibrium.

    balancing_orbit(model, p, y)    -> BalancingOrbit: the closed form y checked to be an orbit of period
                                       T = 2 pi / w (w the forcing frequency), its Floquet multipliers, the
                                       trivial ones removed, and its margin in decay-rate units

A rotor in the fixed frame (anisotropic supports, paper (43); thesis (2.10)-(2.13)) is forced at its spin
speed w: the imbalance's force turns with the rotor.  Its balancing state is the rotor at rest with the balls at
the angles that cancel the imbalance, turning with the rotor: in the model's coordinates (the balls' angles
measured from the rotor) the constant state y that the module's closed form gives (the same closed form as the
rotating-frame balanced state, thesis (3.6), paper (9) B), which is a periodic orbit of the forced system of
any period, so of the forcing period T.  It is used only once checked: the flow over one period from y returns
to y within the shooting's tolerance (`orbits.shooting.NEWTON_TOL`, relative to the state's size), else the
design sample fails (never counted feasible).

**Stability.**  The monodromy matrix M = Phi(T) of the variational equations (`orbits.flow`: CyRK's DOP853 on
y' = f, Phi' = J Phi with the generated analytic Jacobian); its eigenvalues are the Floquet multipliers mu.  The
trivial ones: where the balancing orbits form a continuum at fixed parameters (n >= 3 balls: the balls' phases
free on the manifold of thesis (3.6)), J(t) V = 0 at every t for V tangent to it, so Phi(t) V = V and M has the
multiplier 1 on span V exactly.  V is the common null space of J(t_k) at TANGENT_SAMPLES times of the period
(read from the generated jac, no family named); with Q = [V, S] orthogonal, Q^T M Q = [[I, *], [0, S^T M S]]
(block triangular: S^T M V = S^T V = 0), so the non-trivial multipliers are the eigenvalues of S^T M S, and
|M V - V| is the trivial multipliers' measured error.  A forced orbit has no time-direction multiplier (its
phase is fixed by the forcing).

**Margin** (`margins.multiplier_margin` on S^T M S: max |mu| - 1 with its uncertainty), reported in decay-rate
units: log max|mu| / T, the leading Floquet exponent's real part, so it compares with an autonomous model's
leading real part (Floquet-Lyapunov: where the fixed frame's rotation is the only time dependence, an isotropic
rotor, mu = exp(lambda T) with lambda the rotating-frame eigenvalues).  Its uncertainty: the multiplier's
uncertainty du carried through the logarithm on the side where it is larger, (log|mu| - log(|mu| - du)) / T.
The exponents log(mu) / T (principal branch) stand for the eigenvalues; the crossing is named from mu itself:
a complex pair (torus, Neimark-Sacker), mu -> +1 (fold), mu -> -1 (period doubling).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .loading import Model
from .margins import Margin, multiplier_margin
from .orbits.flow import RTOL, Flow, FlowError
from .orbits.shooting import NEWTON_TOL
from .steady import complement, sort_spectrum
from .windows import SolveFailed

TANGENT_SAMPLES = 8  # times of the period at which the family's tangent must be in J's null space
NULL_RTOL = 1e-10  # a singular value of the stacked J below this (relative to the largest) is a null direction
_flows: dict = {}


@dataclass
class BalancingOrbit:
    """The balancing orbit at p: what design.py reads of a steady state (y, margin, transverse, n_unstable,
    stable) and the orbit's own (period, multipliers, trivial count, residual, the multipliers' margin)."""

    y: np.ndarray
    period: float
    multipliers: np.ndarray  # non-trivial, by decreasing modulus
    trivial: int  # the family's multipliers 1 removed
    trivial_error: float | None  # |M V - V| (None: no trivial multiplier)
    residual: float  # max |phi(T; y) - y|
    multiplier_margin: Margin  # max |mu| - 1
    margin: Margin  # log max |mu| / T
    transverse: np.ndarray  # the Floquet exponents log(mu) / T, by decreasing real part

    @property
    def n_unstable(self) -> int:
        return int(np.sum(np.abs(self.multipliers) > 1.0 + self.multiplier_margin.uncertainty))

    @property
    def stable(self) -> bool:
        return bool(self.margin.value < -self.margin.uncertainty)


def crossing(exponent: complex, period: float) -> str:
    """How the leading multiplier mu = exp(exponent T) leaves the unit circle: "torus" (a complex pair,
    Neimark-Sacker), "fold" (mu real > 0: +1) or "period doubling" (mu real < 0: -1)."""
    mu = np.exp(complex(exponent) * period)
    if abs(mu.imag) > 1e-9 * max(1.0, abs(mu)):
        return "torus"
    return "fold" if mu.real > 0 else "period doubling"


def flow_of(model: Model) -> Flow:
    key = (model.name, model.source_hash)
    if key not in _flows:
        _flows[key] = Flow(model)
    return _flows[key]


def family_tangent(model: Model, y: np.ndarray, p: np.ndarray, period: float) -> np.ndarray:
    """Orthonormal basis (N x k) of the common null space of J(t_k, y, p) at TANGENT_SAMPLES times of the
    period: the directions along which y stays an orbit (see the module's docstring)."""
    times = period * np.arange(TANGENT_SAMPLES) / TANGENT_SAMPLES
    G = np.vstack([np.asarray(model.module.jac(float(t), y, p)) for t in times])
    _, s, vt = np.linalg.svd(G)
    rank = int(np.sum(s > NULL_RTOL * max(1e-300, s[0])))
    return vt[rank:].T.copy()


def rate(m: Margin, period: float) -> Margin:
    """A multiplier margin (max |mu| - 1, uncertainty du) in decay-rate units: log max|mu| / T, uncertainty
    (log|mu| - log(|mu| - du)) / T (inf where du >= |mu|)."""
    r = 1.0 + m.value
    if not (r > 0 and math.isfinite(m.uncertainty)):
        return Margin(math.log(r) / period if r > 0 else -math.inf, math.inf, m.how)
    du = m.uncertainty
    unc = (math.log(r) - math.log(r - du)) / period if du < r else math.inf
    return Margin(math.log(r) / period, unc, m.how + "; in decay-rate units log|mu| / T")


def balancing_orbit(model: Model, p: np.ndarray, y: np.ndarray) -> BalancingOrbit:
    """The balancing orbit through the closed form y at p (see the module's docstring); SolveFailed where y is
    not an orbit over one forcing period to the shooting's tolerance, or the flow fails."""
    p = np.asarray(p, float)
    y = np.asarray(y, float)
    w = float(p[model.param_names.index(model.forcing_frequency)])
    if not (w > 0 and math.isfinite(w)):
        raise SolveFailed(f"forcing frequency {model.forcing_frequency} = {w}: no period")
    T = 2 * math.pi / w
    try:
        ends, Phi, _ = flow_of(model).arcs(y, 0.0, T, p, phi=True)
    except FlowError as exc:
        raise SolveFailed(str(exc)) from None
    residual = float(np.max(np.abs(ends[0] - y)))
    if residual > NEWTON_TOL * (1.0 + float(np.max(np.abs(y)))):
        raise SolveFailed(f"the closed-form balancing state is not an orbit of period {T:.6g} here (the flow over one "
                          f"period leaves it by {residual:.3g})")
    M = Phi[0]
    V = family_tangent(model, y, p, T)
    S = complement(V)
    Mt = S.T @ M @ S
    mu = np.linalg.eigvals(Mt)
    mu = mu[np.lexsort((-mu.imag, -np.abs(mu)))]
    trivial_error = float(np.max(np.abs(M @ V - V))) if V.shape[1] else None
    mm = multiplier_margin(Mt, mu, trivial_error, RTOL, residual)
    with np.errstate(divide="ignore"):
        exponents = sort_spectrum(np.log(mu.astype(complex)) / T)
    return BalancingOrbit(y, T, mu, int(V.shape[1]), trivial_error, residual, mm, rate(mm, T), exponents)
