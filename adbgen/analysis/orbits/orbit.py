"""A periodic orbit of a generated model: found, refined, its multipliers, stability and amplitude.

    find(model, p, y0, t_transient=2000)   simulate, detect the period (and windings) on the settled
                                           trajectory, refine by Newton shooting -> PeriodicOrbit
    refine(model, p, y, T, windings)       Newton shooting from a guess -> PeriodicOrbit

The orbit carries its point y (on the phase condition's hyperplane, or at t = 0 for a forced model), its
period, the windings k_i of each angle (the orbit closes when each angle returns modulo 2 pi k_i: a
ball that laps the rotor has k_i != 0, a desynchronised orbit), the Floquet multipliers from the
monodromy matrix of the variational equations, the trivial multiplier's distance from 1 (the
accuracy check: an autonomous orbit's monodromy maps f(y) to itself), stability (every other
multiplier inside the unit circle), and the amplitude range r_min, r_max of r = hypot of the model's
AMPLITUDE states along the orbit (and the maximum of every other measure the module emits, e.g. the
maximum A-bar of a vibration measure A).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..loading import AnalysisError, Model
from . import describe
from ..margins import Margin, multiplier_margin
from .flow import RTOL, Flow
from .shooting import NEWTON_TOL, Evaluation, Shooting

TWO_PI = 2 * math.pi
UNIT_TOL = 1e-6  # no longer decides stability (the margin's own uncertainty does, `margins`); kept for importers
SAMPLES = 2000  # points per period for the amplitude range
MAX_ARC_GROWTH = 1e4  # multiple shooting: each arc's Phi amplifies by at most this much


@dataclass
class PeriodicOrbit:
    model: Model
    p: np.ndarray
    y: np.ndarray  # a point on the orbit (arc 0's start)
    period: float
    windings: dict  # angle state -> k (the angle gains 2 pi k per period)
    multipliers: np.ndarray  # Floquet multipliers, by decreasing modulus
    trivial: int | None  # index of the trivial multiplier (autonomous), None for a forced orbit
    residual: float
    iterations: int
    arcs: np.ndarray  # m x N, the shooting points
    forced: bool
    subharmonic: int = 1
    r_min: float = float("nan")
    r_max: float = float("nan")
    measures: dict = field(default_factory=dict)  # name -> its maximum along the orbit (e.g. "A": A-bar)
    monodromy: np.ndarray | None = None  # M (the multipliers' condition numbers; None: not kept)
    start: np.ndarray | None = None  # the state the shooting began from (after any transient), if known

    @property
    def trivial_multiplier_error(self) -> float | None:
        return None if self.trivial is None else float(abs(self.multipliers[self.trivial] - 1.0))

    @property
    def nontrivial(self) -> np.ndarray:
        return np.delete(self.multipliers, self.trivial) if self.trivial is not None else self.multipliers

    @cached_property
    def margin(self) -> Margin:
        """max |mu| - 1 over the non-trivial multipliers and its uncertainty (`margins.multiplier_margin`;
        without the monodromy matrix, the condition number is taken as 1)."""
        M = self.monodromy if self.monodromy is not None else np.diag(self.multipliers.real)
        return multiplier_margin(M, self.nontrivial, self.trivial_multiplier_error, RTOL, self.residual)

    @property
    def stable(self) -> bool:
        """Every non-trivial multiplier inside the unit circle by more than the margin's uncertainty."""
        m = self.margin
        return bool(m.value < -m.uncertainty)

    @property
    def n_unstable(self) -> int:
        """The multipliers outside the unit circle by more than the margin's uncertainty."""
        return int(np.sum(np.abs(self.nontrivial) > 1.0 + self.margin.uncertainty))

    def to_json(self) -> dict:
        m = self.model
        return {
            "model": m.name, "parameters": dict(zip(m.param_names, map(float, self.p))),
            "period": float(self.period),
            "multipliers": [[float(z.real), float(z.imag)] for z in self.multipliers],
            "trivial_multiplier_error": self.trivial_multiplier_error,
            "stable": self.stable, "n_unstable": self.n_unstable, **self.margin.to_json(),
            "windings": {k: int(v) for k, v in self.windings.items()},
            "r_min": float(self.r_min), "r_max": float(self.r_max),
            **{f"{name}_bar": float(v) for name, v in self.measures.items()},
            "y": dict(zip(m.state_names, map(float, self.y))),
            "residual": float(self.residual), "newton_iterations": int(self.iterations),
            "arcs": int(len(self.arcs)), "forced": self.forced, "subharmonic": int(self.subharmonic),
        }


# --------------------------------------------------------------------------------------- building

def shift_vector(model: Model, windings: dict) -> np.ndarray:
    s = np.zeros(model.n_states)
    for name, k in windings.items():
        s[model.index(name)] = TWO_PI * k
    return s


def sort_multipliers(mu: np.ndarray) -> np.ndarray:
    mu = np.asarray(mu, complex)
    return mu[np.lexsort((-mu.imag, -np.abs(mu)))]


def trivial_index(mu: np.ndarray, M: np.ndarray, f: np.ndarray) -> int:
    """The multiplier of the flow direction: M f = f on an autonomous orbit.  Among the multipliers, the one
    whose eigenvector is most nearly parallel to f (ties: the one nearest 1)."""
    w, V = np.linalg.eig(M)
    fn = f / max(np.linalg.norm(f), 1e-300)
    align = np.abs(V.conj().T @ fn) / np.linalg.norm(V, axis=0)
    best = int(np.argmax(align - 1e-3 * np.abs(w - 1.0)))
    return int(np.argmin(np.abs(mu - w[best])))


def from_evaluation(model: Model, shooting: Shooting, u: np.ndarray, ev: Evaluation, p: np.ndarray, iterations: int,
                    windings: dict, amplitude: bool = True) -> PeriodicOrbit:
    M = ev.monodromy
    mu = sort_multipliers(np.linalg.eigvals(M))
    X = shooting.arcs_of(u)
    trivial = None if shooting.forced else trivial_index(mu, M, np.asarray(model.module.rhs(0.0, X[0], p)))
    orbit = PeriodicOrbit(model, np.array(p, float), X[0].copy(), ev.T, dict(windings), mu, trivial,
                          float(np.max(np.abs(ev.F))), iterations, X.copy(), shooting.forced, shooting.q,
                          monodromy=np.array(M))
    if amplitude:
        add_amplitude(orbit, shooting.flow)
    return orbit


def add_amplitude(orbit: PeriodicOrbit, flow: Flow, samples: int = SAMPLES) -> None:
    """r_min, r_max (and each emitted measure's maximum) on the continuous solution over one period."""
    t, Y = trace(orbit, flow, samples)
    ix, iy = describe.amplitude_indices(orbit.model)
    r = np.hypot(Y[:, ix], Y[:, iy])
    orbit.r_min, orbit.r_max = -extremum(-r), extremum(r)
    for name in describe.measures(orbit.model):
        orbit.measures[name] = extremum(describe.measure(orbit.model, name, t, Y, orbit.p))


def extremum(v: np.ndarray) -> float:
    """The maximum of periodic samples v (v[-1] = v[0]), refined by the parabola through the largest
    sample and its neighbours (the samples are equally spaced within each arc)."""
    v = np.asarray(v, float)[:-1]
    i = int(np.argmax(v))
    a, b, c = v[i - 1], v[i], v[(i + 1) % len(v)]
    den = a - 2 * b + c
    return float(b - 0.125 * (a - c) ** 2 / den) if den < 0 else float(b)


def trace(orbit: PeriodicOrbit, flow: Flow, samples: int = SAMPLES) -> tuple[np.ndarray, np.ndarray]:
    """(t, Y): the orbit at `samples` + 1 times over one period (each arc from its own start)."""
    m = len(orbit.arcs)
    h = orbit.period / m
    per = max(2, samples // m)
    ts, ys = [np.array([0.0])], [orbit.arcs[:1]]
    for i, x in enumerate(orbit.arcs):
        times = i * h + h * np.arange(1, per + 1) / per
        ts.append(times)
        ys.append(flow.sample(x, i * h, times, orbit.p))
    return np.concatenate(ts), np.vstack(ys)


def arcs_for(flow: Flow, y: np.ndarray, T: float, p: np.ndarray, max_growth: float = MAX_ARC_GROWTH) -> int:
    """How many arcs keep each arc's amplification below max_growth (from Phi over the whole period)."""
    _, Phi, _ = flow.arcs(y, 0.0, T, p, phi=True)
    growth = float(np.linalg.norm(Phi[0], 2))
    return max(1, math.ceil(math.log(max(growth, 1.0)) / math.log(max_growth)))


def windings_over(model: Model, flow: Flow, y: np.ndarray, T: float, p: np.ndarray) -> dict:
    """The whole turns each angle gains from y over T (the windings of an orbit through y with period T)."""
    end = flow.end(y, 0.0, T, p)
    return {model.state_names[i]: int(round((end[i] - y[i]) / TWO_PI)) for i in describe.angle_indices(model)}


def initial_arcs(flow: Flow, y: np.ndarray, T: float, p: np.ndarray, m: int) -> np.ndarray:
    """The m shooting points along the trajectory from y (y itself first)."""
    if m == 1:
        return np.atleast_2d(y)
    times = T * np.arange(1, m) / m
    return np.vstack([y, flow.sample(y, 0.0, times, p)])


def refine(model: Model, p: np.ndarray, y: np.ndarray, period: float | None, windings: dict | None = None, *,
           arcs: int | None = None, subharmonic: int = 1, flow: Flow | None = None, tol: float = NEWTON_TOL,
           amplitude: bool = True) -> PeriodicOrbit:
    """Newton shooting from the guess (y, period) -> PeriodicOrbit.  A forced model's period is
    subharmonic * 2 pi / w (w its forcing frequency) whatever `period` says."""
    p = np.asarray(p, float)
    flow = flow or Flow(model)
    forcing = describe.forcing_parameter(model, p)
    if forcing is not None:
        period = subharmonic * TWO_PI / p[forcing]
    if period is None or not (period > 0 and math.isfinite(period)):
        raise AnalysisError(f"a period > 0 is needed to refine an orbit of {model.name}")
    windings = windings or {}
    m = arcs or arcs_for(flow, y, period, p)
    sh = Shooting(model, flow, m, shift_vector(model, windings), forcing, subharmonic)
    X = initial_arcs(flow, y, period, p, m)
    sh.set_reference(X[0], p)
    u, ev, it = sh.solve(sh.pack(X, period), p, tol=tol)
    orbit = from_evaluation(model, sh, u, ev, p, it, windings, amplitude)
    orbit.start = np.array(y, float)
    return orbit


# ------------------------------------------------------------------- from a simulated trajectory

@dataclass
class Return:
    period: float
    windings: dict
    distance: float  # |y(T) - y(0)| with the angles wrapped, at the detected return


def wrap_angles(model: Model, y: np.ndarray) -> np.ndarray:
    """y with its angles in [-pi, pi) (the same point of the state space)."""
    return wrapped(model, y)


def settled_on_steady_state(model: Model, y: np.ndarray, p: np.ndarray, tol: float = 1e-4) -> None:
    """Raise if y is within tol (relative) of a steady state Newton reaches from it: the trajectory has
    settled on an equilibrium, not an orbit."""
    from ..steady import SteadyStateError, newton

    try:
        ys, _ = newton(model, p, y)
    except SteadyStateError:
        return
    d = float(np.linalg.norm(wrapped(model, ys - y)))
    if d <= tol * (1.0 + float(np.linalg.norm(ys))):
        raise AnalysisError(f"the trajectory settled on a steady state (|y - y_eq| = {d:.2g}), not a periodic orbit "
                            f"(see `adbgen stability`)")


def wrapped(model: Model, d: np.ndarray) -> np.ndarray:
    d = np.array(d, float)
    idx = list(describe.angle_indices(model))
    d[..., idx] = np.remainder(d[..., idx] + math.pi, TWO_PI) - math.pi
    return d


def fastest_time(model: Model, y: np.ndarray, p: np.ndarray) -> float:
    """2 pi / the spectral radius of the Jacobian at y: the shortest time scale of the motion there."""
    rho = float(np.max(np.abs(np.linalg.eigvals(np.asarray(model.module.jac(0.0, y, p))))))
    return TWO_PI / max(rho, 1e-12)


def detect_return(model: Model, flow: Flow, y: np.ndarray, p: np.ndarray, t_max: float | None = None,
                  per_scale: int = 40, close: float = 1e-3) -> Return:
    """The first return of the trajectory from y to the hyperplane through y normal to the flow (in the
    flow's direction) that comes back within `close` of the trajectory's size: the crossings are found on
    samples, then each is located on the flow itself (Newton on the section's equation) in time order
    until one is that close, so interpolation between samples never decides.  Angles are compared modulo
    2 pi; the windings are counted on the unwrapped angles."""
    tau = fastest_time(model, y, p)
    t_max = t_max or 2000 * tau
    n = int(min(400_000, max(2000, per_scale * t_max / tau)))
    times = t_max * np.arange(1, n + 1) / n
    Y = flow.sample(y, 0.0, times, p)
    f = np.asarray(model.module.rhs(0.0, y, p))
    D = wrapped(model, Y - y)
    g = D @ f
    idx = np.nonzero((g[:-1] < 0) & (g[1:] >= 0))[0]
    if len(idx) == 0:
        raise AnalysisError(f"no return to the start within t = {t_max:.4g}: the trajectory has not settled on a "
                            f"periodic orbit (a longer --t-transient?)")
    size = float(np.linalg.norm(np.minimum(np.ptp(np.vstack([Y, y]), axis=0), TWO_PI)))
    frac = g[idx] / (g[idx] - g[idx + 1])
    candidates = times[idx] + frac * (times[idx + 1] - times[idx])
    best = None
    for T in candidates[:200]:
        for _ in range(8):  # Newton on g(T) = f(y) . (y(T) - y) along the flow
            yT = flow.end(y, 0.0, T, p)
            gT = float(wrapped(model, yT - y) @ f)
            dg = float(f @ np.asarray(model.module.rhs(T, yT, p)))
            if dg == 0:
                break
            T -= gT / dg
            if abs(gT / dg) <= 1e-12 * T:
                break
        yT = flow.end(y, 0.0, T, p)
        d = float(np.linalg.norm(wrapped(model, yT - y)))
        if best is None or d < best[2]:
            best = (T, yT, d)
        if d <= close * size:
            break
    T, yT, d = best
    windings = {model.state_names[i]: int(round((yT[i] - y[i]) / TWO_PI)) for i in describe.angle_indices(model)}
    return Return(float(T), windings, d)


def detect_subharmonic(model: Model, flow: Flow, y: np.ndarray, p: np.ndarray, forcing: int, q_max: int = 16,
                       close: float = 1e-3) -> Return:
    """A forced model: the smallest q <= q_max with y(q T_f) back within `close` of the trajectory's size from
    y (modulo 2 pi on the angles; else the closest return), T_f the forcing period."""
    Tf = TWO_PI / p[forcing]
    per = 32
    times = Tf * np.arange(1, q_max * per + 1) / per
    Y = flow.sample(y, 0.0, times, p)
    size = float(np.linalg.norm(np.minimum(np.ptp(np.vstack([Y, y]), axis=0), TWO_PI)))
    strobe = Y[per - 1::per]
    dist = np.linalg.norm(wrapped(model, strobe - y), axis=1)
    ok = np.nonzero(dist <= close * size)[0]
    q = int(ok[0] if len(ok) else np.argmin(dist)) + 1
    windings = {model.state_names[i]: int(round((strobe[q - 1, i] - y[i]) / TWO_PI)) for i in describe.angle_indices(model)}
    return Return(q * Tf, windings, float(dist[q - 1]))


def find(model: Model, p: np.ndarray, y0: np.ndarray, t_transient: float = 2000.0, *, arcs: int | None = None,
         flow: Flow | None = None, t_return: float | None = None, tol: float = NEWTON_TOL) -> PeriodicOrbit:
    """The periodic orbit a trajectory from y0 settles on: integrate t_transient (a whole number of forcing
    periods for a forced model, so that t = 0 keeps the forcing's phase), detect the period and the
    windings, then Newton shooting."""
    p = np.asarray(p, float)
    flow = flow or Flow(model)
    forcing = describe.forcing_parameter(model, p)
    if not (t_transient >= 0 and math.isfinite(t_transient)):
        raise AnalysisError(f"--t-transient must be a finite number >= 0, got {t_transient}")
    if forcing is not None:
        Tf = TWO_PI / p[forcing]
        t_transient = math.ceil(t_transient / Tf) * Tf
    y = flow.end(y0, 0.0, t_transient, p) if t_transient > 0 else np.array(y0, float)
    y = wrap_angles(model, y)
    if forcing is not None:
        ret = detect_subharmonic(model, flow, y, p, forcing)
        q = int(round(ret.period * p[forcing] / TWO_PI))
        return refine(model, p, y, None, ret.windings, arcs=arcs, subharmonic=q, flow=flow, tol=tol)
    settled_on_steady_state(model, y, p)
    ret = detect_return(model, flow, y, p, t_return)
    return refine(model, p, y, ret.period, ret.windings, arcs=arcs, flow=flow, tol=tol)
