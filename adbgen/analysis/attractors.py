"""Where a trajectory ends (thesis ch. 3-5): steady states, their spectra, provable basin regions, labels.

    newton(model, y, p)             a steady state refined from y on the generated rhs and jac
    spectrum(model, y, p)           eigenvalues; for the balanced family of n >= 3 balls the n - 2 exact
                                    zeros along the family removed (reported as neutral)
    stop_region(model, y, p)        a region around a stable steady state every trajectory entering it
                                    provably converges to it (Lyapunov; early stop of sweeps): by the
                                    nonlinear decrease condition (`basin_regions`, the default) or by
                                    contraction (method="contraction", smaller)
    Classifier(model, p).decide(...) an Outcome: a steady state's name (the rest state's with " (algebraic
                                    approach)" where r falls like a power of t), limit cycle,
                                    desynchronised (windings), or undecided with the reason; .label(...)

Newton and the transverse spectrum are those of `steady` (the stability layer); this module adds
what the sweeps need on top: names, provable basin regions, and the classification of final states.

The steady states are named by their configuration, with the names the generated module gives them
(`Model.steady_state_names`; the thesis': balanced 1 (3.6) with the rotor's amplitude zero, coincident 2+- (3.9)
with all balls together, in-line 3(n-m)+- (3.10) with m balls together and n - m opposite; a model that
names none gets plain descriptions, `GENERIC_NAMES`).  The sign is the branch of the closed form the state is (the
arccosine's in (3.9)/(3.10)): the trailing + or - of the label of the generated module's closed-form
steady state (`Model.steady_states`) at the same angle; a model without such labels names no sign.
Everything here reads the module's self-description: the balls are the states of role "ball_angle",
the angles (wrapped) `Model.angles`, the amplitude `Model.amplitude`, the exchanges of identical balls
`Model.symmetries`.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg

from . import steady
from .loading import AnalysisError, Model

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

def newton(model: Model, y, p) -> np.ndarray | None:
    """A zero of rhs(0, ., p) near y (`steady.newton`: minimum-norm steps, so it also converges onto the
    balanced family of n >= 3 balls); None if it does not converge or the model is not autonomous."""
    if not model.autonomous:
        return None
    try:
        return steady.newton(model, np.asarray(p, float), np.asarray(y, float))[0]
    except steady.SteadyStateError:
        return None


def amplitude_of(model: Model, y) -> float:
    ix, iy, _, _ = model.amplitude_indices
    return float(math.hypot(y[ix], y[iy]))


@dataclass
class Spectrum:
    eigenvalues: np.ndarray  # the transverse spectrum (the balanced family's neutral directions removed)
    neutral: int  # number of exact zeros removed (n - 2 on the balanced family of n >= 3 balls)

    def unstable(self) -> int:
        """Eigenvalues with positive real part (`steady.classify`'s tolerance for the imaginary axis)."""
        return steady.classify(self.eigenvalues)[1]

    @property
    def abscissa(self) -> float:
        return float(np.max(self.eigenvalues.real)) if len(self.eigenvalues) else float("nan")


def spectrum(model: Model, y, p) -> Spectrum:
    """Eigenvalues of the Jacobian at a steady state; on the balanced family of n >= 3 balls those
    transverse to it (`steady.transverse_spectrum`: spec J = {0}^(n-2) + spec(S'JS) exactly)."""
    y, p = np.asarray(y, float), np.asarray(p, float)
    J = steady.jacobian(model, y, p)
    T = steady.family_tangent(model, y, p, J)
    return Spectrum(steady.transverse_spectrum(J, T), T.shape[1])


# --------------------------------------------------------------------------------------------- names

def balls(model: Model) -> list[int]:
    """The positions of the balls' angles (role "ball_angle"), in ball order."""
    return list(model.role_indices("ball_angle"))


ALGEBRAIC = " (algebraic approach)"  # appended to a state's name where r falls like a power of t
DESYNCHRONISED = "desynchronised"
UNDECIDED = "undecided"
APPROACHES = ("", "exponential", "algebraic")  # the stored approach codes ("": not fitted, named directly)
UNDECIDED_REASONS = ("",  # the stored codes of why a run is undecided
                     "r decays but is still above the balanced criterion at the cap",
                     "still drifting: no steady state, no band of r, no decay of r by the cap",
                     "the carried-on run failed")
CARRY_FACTOR = 2.0  # a run not named at t is carried on to CARRY_FACTOR t (the cap)


GENERIC_NAMES = {"rest": "rotor at rest", "together": "balls together", "opposed": "balls opposed {m}-{k}"}


def state_name(model: Model, configuration: str, m: int = 0) -> str:
    """The name the model gives its steady states of a configuration (`Model.steady_state_names`: "rest",
    "together", "opposed" with m balls together and the rest opposite); a plain description where the model
    names none."""
    n = len(balls(model))
    template = model.steady_state_names.get(configuration, GENERIC_NAMES[configuration])
    return template.format(n=n, m=m, k=n - m)


def rest_name(model: Model) -> str:
    """The name of the state with the rotor at rest (the thesis' balanced 1)."""
    return state_name(model, "rest")


def labels(model: Model) -> list[str]:
    """Every label a sweep of `model` can give, in a fixed order (the stored codes index this list)."""
    n = len(balls(model))
    rest = rest_name(model)
    out = [rest]
    if n >= 2:
        together = state_name(model, "together")
        out += [together + "-", together + "+", together]
        for m in range(n - 1, (n - 1) // 2, -1):  # m balls together, n - m opposite, m >= n - m
            opposed = state_name(model, "opposed", m)
            out += [opposed] if 2 * m == n else [opposed + "-", opposed + "+", opposed]
    out += ["other steady state", "limit cycle", DESYNCHRONISED, UNDECIDED, "failed", rest + ALGEBRAIC]
    return out


def balanced_labels(model: Model) -> tuple[str, str]:
    """The labels of a balanced outcome, the rotor at rest: approached exponentially, algebraically."""
    rest = rest_name(model)
    return rest, rest + ALGEBRAIC


@dataclass(frozen=True)
class Outcome:
    """Where a run ends, decided: its label, how r approached it where that decided it ("exponential",
    "algebraic", or "" where the state was named directly), why it is undecided (`UNDECIDED_REASONS`
    index and a sentence), the time the decision reached (t_end, or the cap a run was carried on to),
    the balls' whole turns over the carried-on stretch, and the tail's fits (`approach.Tail`)."""

    label: str
    approach: str = ""
    reason_code: int = 0
    reason: str = ""
    t_decided: float | None = None
    windings: tuple[int, ...] = ()
    tail: object = None

    def to_json(self) -> dict:
        return {"label": self.label, "approach": self.approach or None, "undecided_reason": self.reason or None,
                "t_decided": self.t_decided, "windings": list(self.windings),
                "tail": None if self.tail is None else self.tail.to_json()}


def _grouping(model: Model, y, tol: float = 1e-6) -> tuple[int, float] | None:
    """(m, angle): the balls lie in two opposite groups, the larger of m balls at `angle`; None if not."""
    angles = np.asarray(y)[balls(model)]
    n = len(angles)
    if n < 2:
        return None
    ref = angles[0]
    same = np.abs(_wrap(angles - ref)) < tol
    opposite = np.abs(_wrap(angles - ref - math.pi)) < tol
    if not np.all(same | opposite):
        return None
    m = int(same.sum())
    if m < n - m:  # name by the larger group
        m, ref = n - m, ref + math.pi
    return m, float(ref)


def _signed_closed_forms(model: Model, p, m: int) -> list[tuple[str, float]]:
    """(sign, angle of the larger group) of each closed-form steady state whose label ends in + or - and
    whose balls make m and n - m: the branches a state of that grouping is named by."""
    out = []
    for label in model.steady_states:
        if label[-1:] not in ("+", "-"):
            continue
        y = model.steady_state(label, p)
        group = None if y is None or amplitude_of(model, y) < 1e-8 else _grouping(model, y)
        if group is not None and group[0] == m:
            out.append((label[-1], group[1]))
    return out


def name_steady_state(model: Model, y, p, tol: float = 1e-6) -> str:
    """The model's name of the steady state y (`state_name`; thesis: balanced 1, coincident 2+-, in-line
    3(n-m)+-)."""
    if amplitude_of(model, y) < 1e-8:
        return rest_name(model)
    group = _grouping(model, y, tol)
    if group is None:
        return "other steady state"
    m, ref = group
    n = len(balls(model))
    kind = state_name(model, "together") if m == n else state_name(model, "opposed", m)
    if 2 * m == n:
        return kind
    for sign, phi in _signed_closed_forms(model, p, m):
        if abs(_wrap(ref - phi)) < 1e-5:
            return kind + sign
    return kind


# ------------------------------------------------------------------------------ provable basin regions

@dataclass
class StopRegion:
    """A stable steady state with a region E = {e : e'Pe <= rho2, V(e) <= c} (e = y - centre, angles
    wrapped; V = e'Pe, plus the cubic form T(e, e, e) when T is given) on which V decreases along every
    trajectory, so a trajectory inside E stays inside and converges to the centre (see `stop_region`)."""

    label: str
    centre: np.ndarray
    P: np.ndarray
    c: float
    T: np.ndarray | None = None
    rho2: float = math.inf

    def value(self, model: Model, y) -> tuple[np.ndarray, np.ndarray]:
        """(e'Pe, V) at the rows of y."""
        e = state_difference(model, np.atleast_2d(y), self.centre)
        q = np.einsum("ki,ij,kj->k", e, self.P, e)
        return q, q if self.T is None else q + np.einsum("ijk,ni,nj,nk->n", self.T, e, e, e, optimize=True)

    def contains(self, model: Model, y) -> np.ndarray:
        q, v = self.value(model, y)
        return (q <= self.rho2) & (v <= self.c)

    def target(self) -> tuple:
        """The compiled engines' target region (centre, W, K, level): e'We <= 1 and e'We + K(e) <= level."""
        if self.T is None:
            return self.centre, self.P / self.c
        s = self.rho2
        return self.centre, self.P / s, self.T / s, self.c / s


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


REGION_METHODS = ("lyapunov", "contraction")


def stop_region(model: Model, y, p, *, method: str = "lyapunov", samples: int = 256, seed: int = 0,
                keep: float = 0.2) -> StopRegion | None:
    """A provable basin region of the steady state y if it is stable and hyperbolic, else None.

    method "lyapunov" (default): `basin_regions.lyapunov_region`, V = e'Pe with dV/dt < 0 checked on
    the flow itself (the nonlinear decrease condition).  method "contraction", described here: the
    symmetric part of P J(z) negative at every point z of the region, a much stronger condition.

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
    if method not in REGION_METHODS:
        raise AnalysisError(f"unknown stop-region method {method!r}; methods: {', '.join(REGION_METHODS)}")
    m = model.module
    y = np.asarray(y, float)
    p = np.asarray(p, float)
    if method == "lyapunov":
        from .basin_regions import lyapunov_region

        found = lyapunov_region(model, y, p, seed=seed)
        return None if found is None else StopRegion("", y.copy(), found.P, found.c, found.T, found.rho2)
    J = m.jac(0.0, y, p)
    if not np.all(np.isfinite(J)) or steady.family_tangent(model, y, p, J).shape[1]:
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
    permutation is a steady state too, physically the same, in state space another point), and the
    module's closed-form steady states at p (`Model.steady_states`; those that exist there)."""
    import itertools

    start = np.array(model.module.START, dtype=float)
    angles = balls(model)
    out = []
    for perm in itertools.islice(itertools.permutations(range(len(angles))), 120):
        y = start.copy()
        y[angles] = start[[angles[k] for k in perm]]
        if not any(np.array_equal(y, o) for o in out):
            out.append(y)
    for label in model.steady_states:
        y = model.steady_state(label, p)
        if y is not None:  # that state exists at these parameters
            out.append(np.array(y, float))
    return out


def ball_states(model: Model) -> list[list[int]]:
    """Each ball's state indices (its angle and its rate), in ball order."""
    return [[k, model.rate_index(k)] for k in balls(model)]


def identical_balls(model: Model, p) -> list[set[int]]:
    """The groups of identical balls at p (each a set of angle positions): the orbits of the balls under
    the module's "identical-balls" symmetries whose parameter condition holds at p (masses equal, ...).
    Balls of one race that are identical can be exchanged in any order (the generators given, an exchange
    of two and a cyclic shift, generate every permutation of them)."""
    p = np.asarray(p, float)
    group = {b: b for b in balls(model)}

    def root(b):
        while group[b] != b:
            b = group[b]
        return b

    for sym in model.symmetries:
        if sym["kind"] != "identical-balls":
            continue
        params, signs = sym["params"], sym.get("param_signs") or (1,) * len(p)
        if not all(p[k] == signs[k] * p[params[k]] for k in range(len(p))):
            continue
        for b in group:
            group[root(b)] = root(sym["states"][b])
    orbits: dict[int, set[int]] = {}
    for b in group:
        orbits.setdefault(root(b), set()).add(b)
    return list(orbits.values())


def equivariant(model: Model, p, perm) -> bool:
    """Is the state permutation perm (y -> y[perm]) an exchange of identical balls at p, so that
    rhs(s y) = s rhs(y)?  It must move whole balls (angle and rate together) within a group of
    `identical_balls` and keep every other state."""
    perm = list(perm)
    if sorted(perm) != list(range(model.n_states)):
        return False
    rate_of = {k: r for k, r in ball_states(model)}
    group_of = {b: k for k, g in enumerate(identical_balls(model, p)) for b in g}
    for k, j in enumerate(perm):
        if k in rate_of:
            if j not in rate_of or group_of[j] != group_of[k] or perm[rate_of[k]] != rate_of[j]:
                return False
        elif k not in rate_of.values() and j != k:
            return False
    return True


@dataclass
class Classifier:
    """Labels final states for one parameter vector: stop regions of its stable steady states, then
    Newton from the final state, then a short continuation telling a limit cycle from the rest."""

    model: Model
    p: np.ndarray
    regions: list = field(default_factory=list)
    window: float = 200.0
    method: str = "lyapunov"  # of the stop regions (`stop_region`)

    def __post_init__(self):
        self.codes = {name: k for k, name in enumerate(labels(self.model))}
        found: list[np.ndarray] = []
        for s in seeds(self.model, self.p):
            y = newton(self.model, s, self.p)
            if y is None or any(np.max(np.abs(state_difference(self.model, y, f))) < 1e-7 for f in found):
                continue
            found.append(y)
            region = self._mirrored(y)
            if region is None:
                region = stop_region(self.model, y, self.p, method=self.method)
            if region is not None:
                region.label = name_steady_state(self.model, y, self.p)
                self.regions.append(region)

    def _mirrored(self, y) -> StopRegion | None:
        """An earlier region carried over by a permutation of the balls that maps its centre onto y, when
        the model is equivariant under it (identical balls): the regions of ball-swapped states are then
        exact images of each other, so a point and its swapped image are inside together (the sweeps'
        symmetry shortcut relies on it)."""
        import itertools

        balls = ball_states(self.model)
        for region in self.regions:
            for perm in itertools.islice(itertools.permutations(range(len(balls))), 1, 120):
                s = list(range(self.model.n_states))
                for k, j in enumerate(perm):
                    for a, b in zip(balls[k], balls[j]):
                        s[a] = b
                if np.max(np.abs(state_difference(self.model, region.centre[s], y))) < 1e-7 and \
                        equivariant(self.model, self.p, s):
                    T = None if region.T is None else region.T[np.ix_(s, s, s)]
                    return StopRegion("", y.copy(), region.P[np.ix_(s, s)], region.c, T, region.rho2)
        return None

    def inside(self, Y) -> np.ndarray:
        """Index of the stop region each row of Y is in, -1 if none."""
        Y = np.atleast_2d(Y)
        out = np.full(len(Y), -1)
        for k, r in reversed(list(enumerate(self.regions))):
            out[r.contains(self.model, Y)] = k
        return out

    def code(self, name: str) -> int:
        return self.codes[name]

    def label(self, status: str, y_end, target: int, *, engine=None, rtol=1e-8, atol=1e-10, t=None,
              threshold=None) -> str:
        """The label of `decide`."""
        return self.decide(status, y_end, target, engine=engine, rtol=rtol, atol=atol, t=t,
                           threshold=threshold).label

    def decide(self, status: str, y_end, target: int, *, engine=None, rtol=1e-8, atol=1e-10, t=None,
               threshold=None) -> Outcome:
        """Where a run that reached y_end at time t ends.

        Named directly: a stop region reached (or entered by t), or a steady state Newton finds at y_end
        (within 1e-5, or within 1e-3 of a stable one).  Else a further window tells a limit cycle (r keeps
        one band).  Else the run is carried on to the cap CARRY_FACTOR t (t None: the run's time is not
        known, taken as the carried-on length 10 windows) and decided by r's rate of approach over the
        carried-on stretch (`approach.tail`, its criterion): a steady state Newton finds at the cap is named
        (with " (algebraic approach)" for the balanced state where r fell like a power of t); r decaying
        and below `threshold` at the cap (the balanced criterion: the thesis' r < 1e-3, the model's tenth
        of the eccentricity, `units.default_threshold`) is balanced, exponentially or algebraically (over
        the stretch, or over its second half after a transient); r's envelope in one band
        (`approach.BAND`) over the second half is a limit cycle; balls still turning (a whole turn or more
        over the second half) without either are desynchronised; anything else is undecided, with the reason.
        """
        from .results import STOPPED, SUCCESS

        if status == STOPPED and target >= 0:
            return Outcome(self.regions[target].label, t_decided=t)
        if status != SUCCESS:
            return Outcome("failed", t_decided=t)
        named = self._named(y_end)
        if named is not None:
            return Outcome(named, t_decided=t)
        if self._oscillation(y_end, engine, rtol, atol) == "limit cycle":
            return Outcome("limit cycle", t_decided=t)
        if threshold is None:
            from .units import default_threshold

            threshold = default_threshold(self.model, self.p)[0]
        return self._carry_on(y_end, t, engine, rtol, atol, threshold)

    def _named(self, y_end) -> str | None:
        """The region's or steady state's name of y_end, None where it is neither."""
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
        return None

    def _carry_on(self, y_end, t, engine, rtol, atol, threshold) -> Outcome:
        """The run carried on from (t, y_end) to the cap and decided by its tail (see `decide`)."""
        from .approach import tail, windings
        from .simulate import simulate

        t0 = 10.0 * self.window if t is None or not t > 0 else float(t)
        cap = CARRY_FACTOR * t0
        sim = simulate(self.model, self.p, np.asarray(y_end, float), t_end=cap - t0, rtol=rtol, atol=atol,
                       engine=engine, keep_trajectory=True, check=False)
        if not sim.ok or sim.t.size < 8:
            return Outcome(UNDECIDED, reason_code=3, reason=f"the carried-on run failed ({sim.status})", t_decided=cap)
        times, Y = self._fine(sim)
        ix, iy, _, _ = self.model.amplitude_indices
        r = np.hypot(Y[ix], Y[iy])
        fit = tail(t0 + times, r)
        late = times >= 0.5 * times[-1]  # the stretch's second half: where the run has got to
        late_fit = tail(t0 + times[late], r[late])
        turns = tuple(int(w) for w in windings(Y[balls(self.model)]))
        late_turns = windings(Y[balls(self.model)][:, late])
        named = self._named(sim.y_end)
        if named is not None:
            kind = fit.kind if fit.trend == "decays" else late_fit.kind if late_fit.trend == "decays" else ""
            label = named + ALGEBRAIC if named == rest_name(self.model) and kind == "algebraic" else named
            return Outcome(label, kind, t_decided=cap, windings=turns, tail=fit)
        for f in (fit, late_fit):  # decaying over the stretch, or over its second half (after a transient)
            if f.trend == "decays" and f.r_last < threshold:
                return Outcome(rest_name(self.model) + (ALGEBRAIC if f.kind == "algebraic" else ""), f.kind,
                               t_decided=cap, windings=turns, tail=f)
        # a cycle approached slowly: r's envelope keeps one band (within BAND) over the second half (one band
        # over a last window alone would also pass a slow drift)
        if late_fit.trend == "band":
            return Outcome("limit cycle", t_decided=cap, windings=turns, tail=fit)
        if fit.trend != "decays" and np.any(np.abs(late_turns) >= 1):  # balls still turning at the cap
            return Outcome(DESYNCHRONISED, t_decided=cap, windings=turns, tail=fit)
        where = f"r {fit.r_first:.2e} -> {fit.r_last:.2e} over t in [{t0:g}, {cap:g}]"
        if fit.trend == "decays":
            return Outcome(UNDECIDED, fit.kind, 1, f"{UNDECIDED_REASONS[1]} ({where}, {fit.kind}; criterion r < "
                           f"{threshold:g})", cap, turns, fit)
        return Outcome(UNDECIDED, "", 2, f"{UNDECIDED_REASONS[2]} ({where}, {fit.trend})", cap, turns, fit)

    def _fine(self, sim) -> tuple[np.ndarray, np.ndarray]:
        """(times from the carried-on start, the coordinates) on the cubic Hermite interpolant of each
        coordinate and its rate, ten points a step (r read between the engine's step points, as the band
        test does)."""
        from scipy.interpolate import CubicHermiteSpline

        t, keep = np.unique(sim.t, return_index=True)
        Y = sim.y[:, keep]
        fine = np.linspace(t[0], t[-1], 10 * t.size)
        nq = self.model.n_coordinates
        out = np.empty((nq, fine.size))
        for k in range(nq):
            out[k] = CubicHermiteSpline(t, Y[k], Y[self.model.rate_index(k)])(fine)
        return fine, out

    def _oscillation(self, y_end, engine, rtol, atol) -> str:
        """limit cycle: over a further window r keeps one band (its max and min in both halves agree to
        1 % of the max); otherwise not named here ("").  r is read between the engine's step points too, on
        the cubic Hermite interpolant of x and y (their rates are states), ten points a step: on the step
        points alone the band depended on where an engine's steps fell (long Taylor steps put a cycle's band
        over 1 %)."""
        from scipy.interpolate import CubicHermiteSpline

        from .simulate import simulate

        sim = simulate(self.model, self.p, np.asarray(y_end, float), t_end=self.window, rtol=rtol, atol=atol,
                       engine=engine, keep_trajectory=True, check=False)
        if not sim.ok or sim.t.size < 8:
            return ""
        t, keep = np.unique(sim.t, return_index=True)
        Y = sim.y[:, keep]
        ix, iy, ixd, iyd = self.model.amplitude_indices
        fine = np.linspace(t[0], t[-1], 10 * t.size)
        r = np.hypot(CubicHermiteSpline(t, Y[ix], Y[ixd])(fine), CubicHermiteSpline(t, Y[iy], Y[iyd])(fine))
        half = fine >= 0.5 * self.window
        return "limit cycle" if _one_band(r[~half], r[half]) else ""


def _one_band(a, b) -> bool:
    """r keeps one band: its max and min over the two halves a, b of a window agree to 1 % of the max."""
    top = max(a.max(), b.max())
    return abs(a.max() - b.max()) <= 0.01 * top and abs(a.min() - b.min()) <= 0.01 * top


@lru_cache(maxsize=64)
def _classifier_cached(model: Model, p: tuple, method: str) -> Classifier:
    return Classifier(model, np.array(p), method=method)


_classifier_lock = threading.Lock()


def classifier(model: Model, p, method: str = "lyapunov") -> Classifier:
    """The Classifier for parameters p (cached: the regions are computed once per parameter vector and
    method; a lock keeps a sweep's worker threads from computing the same one side by side)."""
    with _classifier_lock:
        return _classifier_cached(model, tuple(float(v) for v in p), method)
