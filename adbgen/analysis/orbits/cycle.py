"""The limit-cycle curve: a periodic orbit continued in one parameter by Newton shooting.

Defining system (x = (u, lambda), u the shooting unknowns of `shooting`):

    F(u, lambda) = 0     the shooting system at p(lambda) (arcs, closure modulo 2 pi k, phase condition)

with its exact Jacobian [dF/du, dF/dlambda] from the variational equations (dF/dlambda along
d p / d lambda, ties included).  Test functions, on the Floquet multipliers mu_i without the trivial one
(MATCONT's choice of products, scaled so that each factor stays bounded):

    period-doubling   prod_i (1 + mu_i) / (1 + |mu_i|)                  zero when a real mu passes -1
    torus             prod_{i<j} (mu_i mu_j - 1) / (1 + |mu_i mu_j|)    zero when mu_i mu_j = 1: a complex pair
                                                                        on the unit circle (Neimark-Sacker), or a
                                                                        real pair mu, 1/mu (a neutral saddle: not
                                                                        reported)
    branch point      prod_{real mu} tanh(mu - 1)                       zero when a real mu passes +1 without a
                                                                        fold (a fold also changes d lambda / ds)
    fold (of cycles)  d lambda / ds                                     watched by the continuer

A located zero is a period-doubling point when a real multiplier is within 1e-4 of -1 there, a torus
point when a complex pair is within 1e-4 of the unit circle (its angle reported); the period and the
multipliers are reported at each.  When the period grows so that one arc's Phi amplifies by more than
`MAX_ARC_GROWTH` x 100 the orbit is re-cut into more arcs (multiple shooting) and the continuation goes on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..loading import Model
from . import describe
from .flow import Flow
from .orbit import MAX_ARC_GROWTH, PeriodicOrbit, add_amplitude, shift_vector, sort_multipliers, trivial_index
from .parameters import ParameterMap
from .shooting import Evaluation, Shooting

SPECIAL_TOL = 1e-4


@dataclass
class CycleData:
    lam: float
    p: np.ndarray
    X: np.ndarray  # arcs
    T: float
    multipliers: np.ndarray  # sorted, trivial included
    trivial: int | None
    growth: float  # largest arc amplification |Phi_i|_2
    monodromy: np.ndarray | None = None  # M, for the margin's condition number

    @property
    def nontrivial(self) -> np.ndarray:
        return np.delete(self.multipliers, self.trivial) if self.trivial is not None else self.multipliers


def pd_test(mu: np.ndarray) -> float:
    return float(np.real(np.prod((1 + mu) / (1 + np.abs(mu)))))


def branch_test(mu: np.ndarray) -> float:
    """prod over the real multipliers of tanh(mu - 1): its sign changes when a real multiplier passes +1 (a
    branch point of cycles, or a fold of cycles: the continuer's fold test tells the two apart); a complex pair
    that turns real adds two factors of one sign, so no change then."""
    mu = np.asarray(mu, complex)
    real = mu[np.abs(mu.imag) <= 1e-12 * (1 + np.abs(mu))].real
    return float(np.prod(np.tanh(real - 1.0))) if len(real) else 1.0


def torus_test(mu: np.ndarray) -> float:
    i, j = np.triu_indices(len(mu), 1)
    prod = mu[i] * mu[j]
    return float(np.real(np.prod((prod - 1) / (1 + np.abs(prod)))))


class CycleCurve:
    """A periodic orbit of `model` along the free parameter of `pmap` (see the module's docstring)."""

    test_names = ("period-doubling", "torus", "branch")

    def __init__(self, model: Model, pmap: ParameterMap, flow: Flow, arcs: int = 1, windings: dict | None = None,
                 subharmonic: int = 1):
        self.model, self.pmap, self.flow = model, pmap, flow
        self.windings = dict(windings or {})
        self.forcing = describe.forcing_parameter(model, pmap.base)
        self.q = subharmonic
        self._build(arcs)

    def _build(self, arcs: int) -> None:
        self.shooting = Shooting(self.model, self.flow, arcs, shift_vector(self.model, self.windings), self.forcing,
                                 self.q)
        self.size = self.shooting.size + 1
        m = self.shooting.m
        w = np.full(self.size, 1.0 / math.sqrt(m))
        if not self.shooting.forced:
            w[-2] = 0.1  # the period
        w[-1] = 1.0
        self.weights = w
        self._cache: dict = {}

    # --- packing ------------------------------------------------------------------------------------

    def pack(self, X: np.ndarray, T: float, lam: float) -> np.ndarray:
        return np.r_[self.shooting.pack(X, T), lam]

    def parameter(self, x: np.ndarray) -> float:
        return float(x[-1])

    def _key(self, x):
        return x.tobytes()

    # --- the defining system ----------------------------------------------------------------------------

    def _evaluation(self, x: np.ndarray) -> Evaluation:
        key = self._key(x)
        if key not in self._cache:
            lam = float(x[-1])
            p = self.pmap(lam)
            ev = self.shooting.evaluate(x[:-1], p, dp=self.pmap.direction(lam))
            self._cache = {key: ev}  # one point at a time: the continuer evaluates, then asks for data
        return self._cache[key]

    def scale(self, x) -> float:
        return 1.0 + float(np.max(np.abs(x[: self.shooting.m * self.model.n_states])))

    def residual(self, x: np.ndarray) -> np.ndarray:
        """F alone (the arcs without their variational equations): the chord iterations' residual."""
        ev = self.shooting.evaluate(x[:-1], self.pmap(float(x[-1])), jacobian=False)
        return ev.F / self.scale(x)

    def evaluate(self, x: np.ndarray):
        ev = self._evaluation(x)
        c = self.scale(x)
        return ev.F / c, np.hstack([ev.A, ev.Fk[:, None]]) / c

    def data(self, x: np.ndarray) -> CycleData:
        ev = self._evaluation(x)
        lam = float(x[-1])
        p = self.pmap(lam)
        M = ev.monodromy
        mu = sort_multipliers(np.linalg.eigvals(M))
        X = self.shooting.arcs_of(x[:-1])
        trivial = None if self.shooting.forced else trivial_index(mu, M, np.asarray(self.model.module.rhs(0.0, X[0], p)))
        growth = max(float(np.linalg.norm(P, 2)) for P in ev.Phi)
        return CycleData(lam, p, X.copy(), ev.T, mu, trivial, growth, M)

    def tests(self, x: np.ndarray, data: CycleData) -> np.ndarray:
        mu = data.nontrivial
        return np.array([pd_test(mu), torus_test(mu), branch_test(mu)])

    def margins(self, data: CycleData) -> np.ndarray:
        """The stability margin, max |mu| - 1 over the non-trivial multipliers (watched by the continuer: a
        stable window is not stepped over)."""
        mu = data.nontrivial
        return np.array([float(np.max(np.abs(mu))) - 1.0 if len(mu) else -1.0])

    def special(self, name: str, x: np.ndarray, data: CycleData) -> dict | None:
        mu = data.nontrivial
        if name == "period-doubling":
            real = mu[np.abs(mu.imag) <= SPECIAL_TOL]
            if len(real) and np.min(np.abs(real + 1)) <= SPECIAL_TOL:
                return {"kind": "period-doubling"}
            return None
        if name == "branch":
            real = mu[np.abs(mu.imag) <= SPECIAL_TOL]
            if len(real) and np.min(np.abs(real - 1)) <= SPECIAL_TOL:
                return {"kind": "branch point"}
            return None
        if name == "torus":
            # a pair of any angle: near the 1:1 resonance (Fig. 11's wedge at eps = 1e-6, angle 8e-5) its imaginary
            # part is far below SPECIAL_TOL, and a test on it dropped the torus point
            cx = mu[mu.imag > 1e-10 * (1 + np.abs(mu))]
            if len(cx) and np.min(np.abs(np.abs(cx) - 1)) <= SPECIAL_TOL:
                z = cx[np.argmin(np.abs(np.abs(cx) - 1))]
                return {"kind": "torus", "angle": float(np.angle(z))}
            return None
        return None

    def accept(self, x: np.ndarray, data: CycleData) -> None:
        """The phase condition moves with the branch: through the accepted point, normal to the flow there
        (kept where the flow vanishes: the equilibrium a branch starts from at a Hopf point)."""
        if self.shooting.forced:
            return
        f = np.asarray(self.model.module.rhs(0.0, data.X[0], data.p))
        if np.linalg.norm(f) > 1e-9 * (1.0 + np.linalg.norm(data.X[0])):
            self.shooting.set_reference(data.X[0], data.p)
            # the phase row changed: patch the held evaluation of this point (its arcs are unchanged)
            ev = self._cache.get(self._key(x))
            self._cache = {}
            if ev is not None and ev.A is not None:
                N = self.model.n_states
                ev.F[-1] = 0.0  # x_0 is the new reference point
                ev.A[-1, :] = 0.0
                ev.A[-1, :N] = self.shooting.ref_f
                self._cache[self._key(x)] = ev

    def remesh(self, x: np.ndarray, data: CycleData):
        """More arcs when one arc amplifies too much (long periods near a homoclinic end)."""
        if data.growth <= MAX_ARC_GROWTH * 100:
            return None
        m = self.shooting.m
        total = math.log(max(data.growth, 1.0)) * m  # the amplification over the period, roughly
        m_new = max(m + 1, math.ceil(total / math.log(MAX_ARC_GROWTH)))
        X = data.X[0]
        times = data.T * np.arange(1, m_new) / m_new
        Xn = np.vstack([X, self.flow.sample(X, 0.0, times, data.p)]) if m_new > 1 else np.atleast_2d(X)
        self._build(m_new)
        self.shooting.set_reference(Xn[0], data.p)
        return self.pack(Xn, data.T, data.lam)

    # --- output ---------------------------------------------------------------------------------------

    def orbit(self, x: np.ndarray, data: CycleData | None = None, amplitude: bool = True) -> PeriodicOrbit:
        data = data or self.data(x)
        ev = self._evaluation(x)
        o = PeriodicOrbit(self.model, data.p, data.X[0].copy(), data.T, dict(self.windings), data.multipliers,
                          data.trivial, float(np.max(np.abs(ev.F))), 0, data.X.copy(), self.shooting.forced, self.q,
                          monodromy=data.monodromy)
        if amplitude:
            add_amplitude(o, self.flow)
        return o
