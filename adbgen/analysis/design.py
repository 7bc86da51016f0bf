"""Design a balancer (issue 39): the parameters that keep the balancing state stable over a whole operating
box (a speed range, further parameter ranges, and every imbalance up to a maximum).

    problem = Problem(model, base, box, varied)       box: Axis (name, low, high) per operating range and the
                                                        imbalance; varied: Axis per design parameter
    verdict = assess(problem, values)                  Verdict: exists (capacity), feasible, worst margin and where
    design = solve(problem)                            Design: the feasible interval(s) (one varied parameter),
                                                        the chart (two), or the optimiser's answer (more); the best
                                                        design, what limits it, the margin's sensitivities

Everything is read from the generated module's self-description: the balancing state is the label of
STEADY_STATES whose closed form has the rotor at rest (the thesis' balanced state 1 of (3.6), the paper's B
of (9)); the imbalance is SCALES["eccentricity"]; the speed SCALES["speed"].

**Forced models** (a rotor in the fixed frame, FORCING_FREQUENCY w): the balancing state is the orbit of period
T = 2 pi / w through the same closed form (the rotor at rest, the balls turning with it), checked over one period
before use; its margin is the leading non-trivial Floquet exponent's real part log max|mu| / T with its uncertainty
(design_orbit: the monodromy matrix of the variational equations, the multipliers 1 of the balancing family
removed), so every scan, interval, chart and optimiser below reads it as it reads an equilibrium's leading real
part, and a boundary is named by its multiplier (torus, fold, period doubling).  Where the closed form is absent
(its guards: e.g. no gravity) the state does not exist, exactly as beyond the capacity.

**Existence (the capacity limit).**  The balancing state exists at p when its closed form does
(`steady_state(label, p)`: thesis (3.14) mu >= delta/n, paper m >= M eps/(4R)).  The capacity is the largest
eccentricity at which it exists (bisection on the closed form's existence, assumed monotone in the
eccentricity: the balls cancel any imbalance up to their capacity); `capacity_slack` = capacity / imbalance_max - 1,
continuous in the design, so its root is found by Brent's method.

**Stability over the box, certified.**  The box's non-degenerate axes are scanned by the certified
one-parameter lines of `windows.certify` (the steady state refined by Newton from its closed form at every
sample, its transverse spectrum's leading real part the margin, `steady.refine`): along each axis, through the
low, middle and high values of the others.  The lines are refined where the margin changes sign or heads for
zero or has an extremum near zero; a change is located and seen on both sides.  The box is stable when every
line is (no unstable sample, no change, no failure).  The worst margin (the largest leading real part over
the box) is then polished by a bounded local maximisation from the worst sample (scipy), so it is not a grid
value.  What this certifies: no instability window wider than the lines' resolution along the lines, and
the worst margin is a local maximum of the margin near the lines' worst sample (assumed: the margin's largest
value over the box is not in a narrow peak between the lines).

**One varied parameter.**  The worst margin g(v) along the design parameter v is itself a line for
`windows.certify` (each sample a whole box scan): its feasible windows, each end located by Brent's method on
g (to `windows`' xtol) or on the capacity slack, and named: the range's end, the capacity limit, or a
stability boundary, "Hopf" when the eigenvalue crossing is a complex pair and "real eigenvalue" (fold,
pitchfork) when it is real.  **Two**: rows and columns of a grid, each a certified line of g (as the stability
maps are, `stability_map`), with the located boundary points and the resolution certified.  **More**:
scipy's COBYLA, maximising the worst decay rate with the capacity slack and the worst margin as constraints,
each evaluation a certified box scan.

**Dask and resuming** (issue 39 item 5).  With `Problem.parallel` the chart's grid and the first samples of a
line go to the local Dask cluster as one batch (`prefetch`), and the chart's rows and columns run together
(`scan_lines`); with `Problem.journal` every verdict is journalled as it is found, keyed by `verdict_key`, and
read back by a rerun (`Design.resumed` counts them).  The answer does not depend on either: each verdict is a
deterministic function of the problem and the design, and the certified lines are determined by their verdicts.

**Sensitivity.**  dg/dv_k at the best design, two ways: (1) from the emitted parameter Jacobian jac_p at the
box's worst point, the eigenvalue's first-order perturbation d lambda = l^H dJ r / l^H r (Wilkinson) with
dJ = d/dh J(y + h dy, p + h e_k), dy = -J^+ f_p e_k (the state's move, from jac_p; e_k moves v_k and every
parameter tied to it); (2) by one-sided finite
differences of g itself.  They agree where the worst point does not jump (the envelope theorem); at a max-min
optimum (two box points equally worst) g has a kink and jac_p's slope matches one side: the output says
which, and how far each parameter may move before g reaches 0 at that slope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize, minimize_scalar

from .design_runs import Journal, evaluate, key_of
from .identify import rotor_size, tolerance
from .loading import AnalysisError, Model
from .windows import Sample, SolveFailed, certify

LINE_POINTS = 17  # the box's lines: initial samples per axis
LINE_REFINE = 8  # ... certified to the initial spacing / LINE_REFINE
VARY_POINTS = 9  # one varied parameter: initial designs
VARY_REFINE = 8
CHART_POINTS = 7  # two: the chart's grid per axis
CHART_REFINE = 4
CAPACITY_RTOL = 1e-12
CAPACITY_GROWTH = 60  # doublings of the eccentricity tried before the capacity is called unbounded
FD_STEP = 1e-5  # relative step of the finite differences (of jac along the state's move, and of the worst margin)
AGREE = 1e-3  # relative agreement of the two sensitivities
# an imbalance interval from 0 is scanned from IMBALANCE_FLOOR times its maximum: at zero imbalance the
# balancing state is a continuum (the balls' pattern free to turn: a zero eigenvalue, margin 0 whatever the
# design), and the balancing mode's rate vanishes with the imbalance, so "every imbalance down to 0" has margin 0
IMBALANCE_FLOOR = 1e-3
# the journal's verdict record (design-journal.jsonl, design_runs.Journal): its key names what decides a verdict
# (the model's SOURCE_HASH, the parameters left alone, the box, the varied and tied names, the lines' sampling and
# this format); raise it when assess computes differently, so an old journal is not read as the new computation
VERDICT_FORMAT = 1


@dataclass(frozen=True)
class Axis:
    name: str
    low: float
    high: float

    @property
    def fixed(self) -> bool:
        return self.low == self.high

    def to_json(self) -> dict:
        return {"name": self.name, "low": self.low, "high": self.high}


@dataclass
class Problem:
    model: Model
    base: np.ndarray  # the parameters the box and the design leave alone
    box: list[Axis]  # the operating box: ranges and the imbalance (the eccentricity axis)
    varied: list[Axis]  # the design parameters
    label: str = ""  # the balancing state's label (default: `balancing_label`)
    ties: dict = field(default_factory=dict)  # {parameter: varied parameter it equals} (the balls' masses alike)
    cache: dict = field(default_factory=dict)
    # how the designs are assessed (issue 39 item 5): `journal` keeps every verdict as it is found and gives back
    # those of a killed run; `parallel` sends batches of designs (the chart's grid, a line's first samples) to the
    # local Dask cluster (design_runs.evaluate: `workers` threads, a progress bar when `progress`)
    journal: Journal | None = None
    parallel: bool = False
    workers: int | None = None
    progress: bool = False
    box_lines_parallel: bool = False  # with `parallel`: a design's box lines on the cluster (the optimiser's evaluations)

    def __getstate__(self):
        # a copy sent to a Dask task: without the cache (the task's verdict comes back as its result) and the
        # journal (only this process writes it)
        state = dict(self.__dict__)
        state.update(cache={}, journal=None, parallel=False, progress=False, box_lines_parallel=False)
        return state

    def __post_init__(self):
        m = self.model
        if not m.autonomous and not m.forcing_frequency:
            raise AnalysisError(f"{m.name} depends on time explicitly but is not periodically forced (no forcing "
                                "frequency): it has no balancing state or orbit to design for")
        names = [a.name for a in self.box + self.varied]
        for name in names:
            if name not in m.param_names:
                raise AnalysisError(f"{name!r} is not a parameter of {m.name}; parameters: {', '.join(m.param_names)}")
        for name, source in self.ties.items():
            if name not in m.param_names:
                raise AnalysisError(f"--tie {name}: not a parameter of {m.name}; parameters: {', '.join(m.param_names)}")
            if source not in [a.name for a in self.varied]:
                raise AnalysisError(f"--tie {name}={source}: {source} is not a varied parameter (--vary)")
        names = names + list(self.ties)
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise AnalysisError(f"{', '.join(twice)} given twice (a parameter is either a range, the imbalance, varied "
                                "or tied)")
        for a in self.box + self.varied:
            if not (math.isfinite(a.low) and math.isfinite(a.high)) or a.low > a.high:
                raise AnalysisError(f"{a.name}: expected LOW <= HIGH, got {a.low}:{a.high}")
        for a in self.varied:
            if a.fixed:
                raise AnalysisError(f"--vary {a.name}: LOW and HIGH are equal: nothing to vary (use --set)")
        self.label = self.label or balancing_label(m, self.base)
        ecc = m.scales.get("eccentricity")
        if ecc is None:
            raise AnalysisError(f"{m.name} names no eccentricity parameter (SCALES): no imbalance to design for")
        if ecc not in [a.name for a in self.box]:
            value = float(self.base[m.param_names.index(ecc)])
            self.box.append(Axis(ecc, value, value))
        self.floor = None
        for k, a in enumerate(self.box):
            if a.name == ecc and a.low == 0 and a.high > 0:
                self.floor = IMBALANCE_FLOOR * a.high
                self.box[k] = Axis(ecc, self.floor, a.high)

    @property
    def eccentricity(self) -> str:
        return self.model.scales["eccentricity"]

    @property
    def imbalance(self) -> Axis:
        return next(a for a in self.box if a.name == self.eccentricity)

    def params(self, design, point: dict | None = None) -> np.ndarray:
        p = np.array(self.base, float)
        for a, v in zip(self.varied, np.atleast_1d(design)):
            p[self.model.param_names.index(a.name)] = float(v)
        for name, source in self.ties.items():
            p[self.model.param_names.index(name)] = p[self.model.param_names.index(source)]
        for name, v in (point or {}).items():
            p[self.model.param_names.index(name)] = float(v)
        return p


def balancing_label(model: Model, p_first: np.ndarray | None = None) -> str:
    """The label of the module's STEADY_STATES whose closed form has the rotor at rest (the balancing state)
    at `p_first` (the problem's parameters), START_PARAMETERS or DEFAULTS; AnalysisError when there is none."""
    for label in model.steady_states:
        for p in (p_first, getattr(model.module, "START_PARAMETERS", None), model.module.DEFAULTS):
            if p is None:
                continue
            y = model.steady_state(label, p)
            if y is not None:
                if rotor_size(model, y) == 0.0:
                    return label
                break
    where = "".join(f"; {label}: {model.steady_state_note(label)}" for label in model.steady_states)
    raise AnalysisError(f"{model.name} has no closed-form balancing state at these parameters (a labelled steady "
                        f"state with the rotor at rest; labels: {', '.join(model.steady_states) or 'none'}{where}): "
                        "nothing to design for")


# ------------------------------------------------------------------------------------------ capacity

def _exists(problem: Problem, p: np.ndarray) -> bool:
    return problem.model.steady_state(problem.label, p) is not None


def capacity(problem: Problem, design) -> float:
    """The largest eccentricity at which the balancing state's closed form exists at this design (the balls'
    capacity: thesis (3.14) n mu, paper M eps <= 4 m R), by bisection to CAPACITY_RTOL; inf when it exists at
    every eccentricity tried (2^CAPACITY_GROWTH times the interval's maximum), 0 when not even at 0."""
    key = ("capacity", tuple(np.atleast_1d(design)))
    if key in problem.cache:
        return problem.cache[key]
    k = problem.model.param_names.index(problem.eccentricity)
    p = problem.params(design)

    def exists(e):
        q = p.copy()
        q[k] = e
        return _exists(problem, q)
    lo, hi = 0.0, max(problem.imbalance.high, 1e-300)
    if not exists(lo):
        out = 0.0
    else:
        for _ in range(CAPACITY_GROWTH):
            if not exists(hi):
                break
            lo, hi = hi, 2 * hi
        else:
            problem.cache[key] = math.inf
            return math.inf
        while hi - lo > CAPACITY_RTOL * hi:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if exists(mid) else (lo, mid)
        out = lo
    problem.cache[key] = out
    return out


def capacity_slack(problem: Problem, design) -> float:
    """capacity / imbalance_max - 1 (>= 0: the balls cover every imbalance of the interval)."""
    top = problem.imbalance.high
    c = capacity(problem, design)
    if top <= 0:
        return math.inf if c > 0 or _exists(problem, problem.params(design)) else -1.0
    return c / top - 1.0


# ------------------------------------------------------------------------------------- the box scan

@dataclass
class Verdict:
    """The design's verdict over the box."""

    design: tuple
    exists: bool
    capacity: float
    feasible: bool = False
    margin: float = math.nan  # the worst (largest) leading real part over the box
    margin_uncertainty: float = math.nan
    worst: dict = field(default_factory=dict)  # the box point where it is
    leading: complex = complex(math.nan)  # the leading transverse eigenvalue there
    unstable_at: list = field(default_factory=list)  # box points (dicts) found unstable
    failures: list = field(default_factory=list)  # (point, why)
    samples: int = 0
    # a forced model's balancing orbit at the worst point: its period T (nan: an equilibrium); `leading` is then
    # the leading Floquet exponent log(mu) / T and `margin` its real part (design_orbit)
    period: float = math.nan

    @property
    def marginal(self) -> bool:
        return bool(abs(self.margin) <= self.margin_uncertainty)

    def record(self) -> dict:
        """The verdict as the journal keeps it (JSON: floats exactly, non-finite as JSON's NaN and Infinity)."""
        return {"design": list(self.design), "exists": self.exists, "capacity": self.capacity,
                "feasible": self.feasible, "margin": self.margin, "margin_uncertainty": self.margin_uncertainty,
                "worst": self.worst, "leading": [self.leading.real, self.leading.imag],
                "unstable_at": self.unstable_at, "failures": [[pt, why] for pt, why in self.failures],
                "samples": self.samples, "period": self.period}

    @classmethod
    def from_record(cls, r: dict) -> Verdict:
        return cls(tuple(r["design"]), bool(r["exists"]), float(r["capacity"]), feasible=bool(r["feasible"]),
                   margin=float(r["margin"]), margin_uncertainty=float(r["margin_uncertainty"]), worst=dict(r["worst"]),
                   leading=complex(*r["leading"]), unstable_at=[dict(pt) for pt in r["unstable_at"]],
                   failures=[(dict(pt), why) for pt, why in r["failures"]], samples=int(r["samples"]),
                   period=float(r.get("period", math.nan)))

    @property
    def crossing(self) -> str:
        """How the leading eigenvalue leaves: "Hopf" (a complex pair) or "real eigenvalue" (fold, pitchfork); a
        forced model's balancing orbit: how its leading multiplier leaves the unit circle, "torus", "fold" or
        "period doubling" (design_orbit.crossing)."""
        if math.isfinite(self.period):
            from .design_orbit import crossing

            return crossing(self.leading, self.period)
        return "Hopf" if abs(self.leading.imag) > 1e-9 * max(1.0, abs(self.leading)) else "real eigenvalue"

    def to_json(self, problem: Problem) -> dict:
        return {**dict(zip([a.name for a in problem.varied], map(float, self.design))),
                "balancing_state_exists": self.exists, "capacity": _num(self.capacity),
                "capacity_slack": _num(self.capacity / problem.imbalance.high - 1.0) if problem.imbalance.high > 0 else None,
                "feasible": self.feasible, "margin": _num(self.margin), "decay_rate": _num(-self.margin),
                "margin_uncertainty": _num(self.margin_uncertainty),
                "marginal": self.marginal if math.isfinite(self.margin) else None,
                "worst_point": self.worst, "leading_eigenvalue": [_num(self.leading.real), _num(self.leading.imag)],
                "unstable_at": self.unstable_at[:5], "failures": [[pt, why] for pt, why in self.failures[:5]],
                "box_samples": self.samples,
                "orbit_period": _num(self.period),
                "leading_multiplier": ([_num(mu.real), _num(mu.imag)] if (mu := self._multiplier()) is not None
                                       else None)}

    def _multiplier(self) -> complex | None:
        """A forced model's leading Floquet multiplier exp(leading T) (None: an equilibrium's verdict)."""
        if not (math.isfinite(self.period) and np.isfinite(self.leading)):
            return None
        return complex(np.exp(self.leading * self.period))


def _num(x):
    return float(x) if x is not None and math.isfinite(x) else None


def _state_at(problem: Problem, p: np.ndarray):
    """The balancing state refined from its closed form at p (steady.refine: Newton, transverse spectrum,
    margin); SolveFailed when it does not exist or Newton leaves it.  A forced model's: the balancing orbit
    through the closed form, checked over one forcing period, its Floquet multipliers' margin in decay-rate
    units (design_orbit.balancing_orbit)."""
    from .steady import SteadyStateError, refine

    m = problem.model
    y0 = m.steady_state(problem.label, p)
    if y0 is None:
        raise SolveFailed(f"no balancing state {problem.label} here (beyond the balls' capacity)")
    if not m.autonomous:
        from .design_orbit import balancing_orbit

        return balancing_orbit(m, p, y0)
    try:
        s = refine(m, p, y0, label=problem.label)
    except SteadyStateError as exc:
        raise SolveFailed(str(exc)) from None
    if rotor_size(m, s.y) > tolerance(m, p):
        raise SolveFailed(f"Newton left the balancing state {problem.label} (rotor displaced by {rotor_size(m, s.y):.3g})")
    return s


def _sample(problem: Problem, p: np.ndarray, x: float) -> Sample:
    s = _state_at(problem, p)
    return Sample(float(x), float(s.margin.value), int(s.n_unstable), s, s.transverse)


def assess(problem: Problem, design) -> Verdict:
    """The design's verdict over the box (see the module's docstring): existence at the largest imbalance,
    then the certified lines, then the worst margin polished."""
    design = tuple(float(v) for v in np.atleast_1d(design))
    key = ("assess", design)
    if key in problem.cache:
        return problem.cache[key]
    journal = problem.journal
    if journal is not None and (k := verdict_key(problem, design)) in journal.done:
        v = problem.cache[key] = Verdict.from_record(journal.done[k])
        return v
    v = problem.cache[key] = _assess(problem, design)
    if journal is not None:
        journal.put(k, v.record())
    return v


def verdict_key(problem: Problem, design: tuple) -> str:
    """The journal key of a design's verdict: everything assess reads besides the design (VERDICT_FORMAT)."""
    return key_of("assess", VERDICT_FORMAT, problem.model.source_hash, problem.base.tolist(),
                  [a.to_json() for a in problem.box], [a.name for a in problem.varied], sorted(problem.ties.items()),
                  problem.label, LINE_POINTS, LINE_REFINE, list(design))


def _verdict_record(problem: Problem, design: tuple) -> dict:
    return assess(problem, design).record()  # a Dask task's: on a copy of the problem (Problem.__getstate__)


def prefetch(problem: Problem, designs, desc: str) -> None:
    """With `problem.parallel`: the designs not yet assessed, assessed together on the local Dask cluster
    (design_runs.evaluate: journalled as each finishes, those in the journal read back, progress under `desc`)
    and kept in the cache, so the certified scans that follow read them; without it nothing (each is assessed
    when the scan reaches it).  The verdicts are the same either way: assess is deterministic."""
    if not problem.parallel:
        return
    todo = {}
    for d in designs:
        d = tuple(float(v) for v in np.atleast_1d(d))
        if ("assess", d) not in problem.cache:
            todo[verdict_key(problem, d)] = d
    if not todo:
        return
    journal = problem.journal or Journal(None)
    done, _ = evaluate([(k, _verdict_record, (problem, d)) for k, d in todo.items()], journal,
                       workers=problem.workers, progress=problem.progress, desc=desc)
    for k, d in todo.items():
        problem.cache[("assess", d)] = Verdict.from_record(done[k])


def _line_task(problem: Problem, k: int, at: list, points: int, refine: int, known: dict) -> dict:
    """scan_line over the k-th varied parameter on a copy of the problem (a Dask task), reading the verdicts of
    `known` as from a journal: the line, its capacity edges and every verdict it used ({key: record})."""
    problem.journal = Journal(None)
    problem.journal.done.update(known)
    line, edges = scan_line(problem, problem.varied[k], at, points, refine)
    used = {verdict_key(problem, key[1]): v.record() for key, v in problem.cache.items() if key[0] == "assess"}
    return {"line": line, "edges": edges, "used": used}


def scan_lines(problem: Problem, specs: list, points: int, refine: int, desc: str) -> list:
    """[(line, edges)] of scan_line for each (k, at) of `specs` (the k-th varied parameter, the others at `at`).
    With `problem.parallel` the lines run together on the local Dask cluster (design_runs.evaluate, progress
    under `desc`), each on a copy of the problem that knows every verdict found so far; as each line finishes the
    verdicts it used are cached here and its new ones journalled, so a kill loses only the lines in flight.  The lines are those of
    the sequential scan: each is determined by its verdicts, and assess is deterministic."""
    if not problem.parallel:
        return [scan_line(problem, problem.varied[k], at, points, refine) for k, at in specs]
    known = dict(problem.journal.done) if problem.journal is not None else {}
    known.update({verdict_key(problem, key[1]): v.record() for key, v in problem.cache.items() if key[0] == "assess"})

    def each(_, result):
        for key, record in result["used"].items():
            if problem.journal is not None and key not in problem.journal.done:
                problem.journal.put(key, record)
            problem.cache.setdefault(("assess", tuple(record["design"])), Verdict.from_record(record))
    tasks = [(key_of("line", k, list(at), points, refine), _line_task, (problem, k, list(at), points, refine, known))
             for k, at in specs]
    done, _ = evaluate(tasks, Journal(None), workers=problem.workers, progress=problem.progress, desc=desc, each=each)
    return [(done[key]["line"], done[key]["edges"]) for key, _, _ in tasks]


def _assess(problem: Problem, design: tuple) -> Verdict:
    cap = capacity(problem, design)
    v = Verdict(design, exists=capacity_slack(problem, design) >= 0, capacity=cap)
    if not v.exists:
        return v
    active = [a for a in problem.box if not a.fixed]
    fixed = {a.name: a.low for a in problem.box if a.fixed}
    best = None  # (margin, point, state)

    def consider(margin, point, state):
        nonlocal best
        if best is None or margin > best[0]:
            best = (margin, point, state)
    if not active:
        try:
            s = _state_at(problem, problem.params(design, fixed))
            consider(s.margin.value, dict(fixed), s)
            v.samples = 1
            if not s.stable:
                v.unstable_at.append(dict(fixed))
        except SolveFailed as exc:
            v.failures.append((dict(fixed), str(exc)))
    specs = [(axis, {**fixed, **through}) for k, axis in enumerate(active)
             for through in _through(active[:k] + active[k + 1:])]
    for (axis, point), (line, failed) in zip(specs, _box_lines(problem, design, specs)):
        v.failures += failed
        v.samples += len(line.samples)
        v.failures += [({**point, axis.name: float(x)}, why) for x, why in line.failures]
        for s in line.samples:
            if not s.stable:
                v.unstable_at.append({**point, axis.name: s.x})
            consider(s.margin, {**point, axis.name: s.x}, s.state)
        for c in line.changes:
            v.unstable_at.append({**point, axis.name: c.x})
    if best is None:
        return v
    margin, point, state = _polish(problem, design, active, fixed, best)
    v.margin, v.worst = margin, point
    v.margin_uncertainty = float(state.margin.uncertainty)
    v.leading = complex(state.transverse[0]) if len(state.transverse) else complex(math.nan)
    v.period = float(getattr(state, "period", math.nan))
    # a margin inside what the computation can certify (`margins`) decides nothing: not counted feasible, and
    # the verdict says `marginal`
    v.feasible = not v.unstable_at and not v.failures and margin < -v.margin_uncertainty
    return v


def _box_line(problem: Problem, design: tuple, axis: Axis, point: dict):
    """One certified line of the box along `axis` through `point` (windows.certify): (the line, the failures of
    its initial samples [(point, why)])."""
    def solve(x, near=None):
        return _sample(problem, problem.params(design, {**point, axis.name: x}), x)
    xs = np.linspace(axis.low, axis.high, LINE_POINTS)
    samples, failed = [], []
    for x in xs:
        try:
            samples.append(solve(float(x)))
        except SolveFailed as exc:
            samples.append(None)
            failed.append(({**point, axis.name: float(x)}, str(exc)))
    return certify(samples, solve, (axis.high - axis.low) / (LINE_POINTS - 1) / LINE_REFINE, xs=list(xs)), failed


def _box_lines(problem: Problem, design: tuple, specs: list) -> list:
    """_box_line for each (axis, point) of `specs`, in their order: with `problem.box_lines_parallel` (the
    optimiser's evaluations, one design at a time) together on the local Dask cluster (design_runs.evaluate, not
    journalled: the verdict they make is), else one after another.  The same lines either way (each is
    deterministic), so the verdict is the same."""
    if not (problem.parallel and problem.box_lines_parallel and len(specs) > 1):
        return [_box_line(problem, design, axis, point) for axis, point in specs]
    tasks = [(key_of("box-line", k), _box_line, (problem, design, axis, point)) for k, (axis, point) in enumerate(specs)]
    done, _ = evaluate(tasks, Journal(None), workers=problem.workers, progress=False)
    return [done[k] for k, _, _ in tasks]


def _through(others: list[Axis]) -> list[dict]:
    """The points of the other axes a line passes through: each at its low, middle and high value."""
    grids = [[a.low, 0.5 * (a.low + a.high), a.high] for a in others]
    out = [{}]
    for a, g in zip(others, grids):
        out = [{**o, a.name: float(x)} for o in out for x in g]
    return out


def _polish(problem: Problem, design, active: list[Axis], fixed: dict, best):
    """The worst margin maximised locally from the worst sample (bounded: the box), and the state there."""
    margin, point, state = best
    if not active:
        return margin, point, state

    def g(z):
        try:
            s = _state_at(problem, problem.params(design, {**fixed, **dict(zip([a.name for a in active], z))}))
            return -s.margin.value
        except SolveFailed:
            return math.inf
    z0 = np.array([point[a.name] for a in active])
    if len(active) == 1:
        a = active[0]
        h = (a.high - a.low) / (LINE_POINTS - 1)
        lo, hi = max(a.low, z0[0] - h), min(a.high, z0[0] + h)
        r = minimize_scalar(lambda z: g([z]), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-10 * max(1.0, abs(z0[0]))})
        z = np.array([r.x])
    else:
        r = minimize(g, z0, method="Nelder-Mead", bounds=[(a.low, a.high) for a in active],
                     options={"xatol": 1e-10, "fatol": 1e-14, "maxiter": 400})
        z = np.asarray(r.x)
    if -g(z) <= margin:  # the sample itself is the largest seen
        return margin, point, state
    where = {**fixed, **{a.name: float(x) for a, x in zip(active, z)}}
    s = _state_at(problem, problem.params(design, where))
    return float(s.margin.value), where, s


# ------------------------------------------------------------------------------------------ designs

@dataclass
class Boundary:
    """A place where the design stops being feasible."""

    values: dict  # the varied parameters there
    kind: str  # "range end", "capacity limit", "Hopf", "real eigenvalue", "not located"
    worst_point: dict = field(default_factory=dict)  # the box point where the margin crosses (stability limits)
    bracket: tuple | None = None

    def to_json(self) -> dict:
        return {"at": self.values, "kind": self.kind, "worst_point": self.worst_point,
                "bracket": list(self.bracket) if self.bracket else None}


@dataclass
class Design:
    problem: Problem
    method: str  # "interval" (one varied parameter), "chart" (two), "optimiser" (more)
    best: Verdict | None
    feasible_intervals: list = field(default_factory=list)  # one varied parameter: [(a, b)]
    boundaries: list = field(default_factory=list)
    active: Boundary | None = None  # the boundary nearest the best design (what limits it)
    sensitivity: list = field(default_factory=list)
    chart: dict | None = None
    resolution: dict = field(default_factory=dict)
    evaluations: int = 0
    resumed: int = 0  # of the evaluations, those read back from the journal (a killed design run again)
    verdicts: list = field(default_factory=list)  # every design assessed (sorted by design)
    objective_runs: list = field(default_factory=list)  # objective t_dec: the run of each candidate
    verification: list = field(default_factory=list)  # the chosen design's runs at the box's corners
    verification_run_up: dict | None = None  # the chosen design's run-up (design_transients.verify_run_up)
    verification_run_up_note: str | None = None  # why there is none (one line)
    residual: dict | None = None  # objective residual: its summary (design_transients.residual_summary)


def _margin_sample(problem: Problem, design, x: float) -> Sample:
    """The design's worst margin as the sample at x of a line over the design; SolveFailed (not computed) beyond
    the capacity or where a box sample failed."""
    v = assess(problem, design)
    if not v.exists:
        raise SolveFailed(f"beyond the balls' capacity ({v.capacity:.6g} < {problem.imbalance.high:.6g})")
    if v.failures or not math.isfinite(v.margin):
        raise SolveFailed("a sample of the box not computed: " + (v.failures[0][1] if v.failures else "?"))
    # an unstable box sample has a positive leading real part, so the worst margin's sign is the verdict
    return Sample(float(x), float(v.margin), 0 if v.feasible else 1, v, None)


def scan_line(problem: Problem, axis: Axis, at, points: int, refine: int):
    """A certified line over one design parameter (the others at `at`): the worst margin's line refined and
    its changes located (windows.certify), with the capacity limits located by Brent's method on the slack.
    Returns (line, capacity_edges [(x, feasible_below)])."""
    k = problem.varied.index(axis)

    def design(x):
        d = list(at)
        d[k] = x
        return d
    xs = list(np.linspace(axis.low, axis.high, points))
    slack = [capacity_slack(problem, design(x)) for x in xs]
    edges = []
    for i in range(len(xs) - 1):
        if (slack[i] >= 0) != (slack[i + 1] >= 0):
            f = lambda x: capacity_slack(problem, design(x))  # noqa: E731
            try:
                x = brentq(f, xs[i], xs[i + 1], xtol=1e-12 * max(1.0, abs(xs[i])), rtol=4 * np.finfo(float).eps)
            except ValueError:  # an infinite slack on one side: bisect on existence instead
                a, b = xs[i], xs[i + 1]
                while b - a > 1e-12 * max(1.0, abs(a)):
                    mid = 0.5 * (a + b)
                    a, b = (mid, b) if (f(mid) >= 0) == (slack[i] >= 0) else (a, mid)
                x = a if slack[i] >= 0 else b
            edges.append((float(x), slack[i] >= 0))
    # a sample just inside each capacity edge, so a window reaching the edge is drawn to it
    inside = [x - 1e-9 * (axis.high - axis.low) if below else x + 1e-9 * (axis.high - axis.low) for x, below in edges]
    xs = sorted(set(xs) | set(inside))
    prefetch(problem, [design(x) for x in xs], f"design line over {axis.name}")
    samples = []
    for x in xs:
        try:
            samples.append(_margin_sample(problem, design(x), x))
        except SolveFailed:
            samples.append(None)
    line = certify(samples, lambda x, near: _margin_sample(problem, design(x), x),
                   (axis.high - axis.low) / (points - 1) / refine, xs=xs)
    return line, edges


def _boundaries_of(problem: Problem, axis: Axis, at, line, edges) -> list[Boundary]:
    k = problem.varied.index(axis)

    def values(x):
        d = list(at)
        d[k] = x
        return {a.name: float(v) for a, v in zip(problem.varied, d)}
    out = [Boundary(values(x), "capacity limit") for x, _ in edges]
    for c in line.changes:
        if c.bracket is not None:
            out.append(Boundary(values(c.x), "not located", bracket=c.bracket))
            continue
        v = assess(problem, list(values(c.x).values()))
        out.append(Boundary(values(c.x), v.crossing if math.isfinite(v.margin) else "not located", v.worst))
    return sorted(out, key=lambda b: b.values[axis.name])


def solve(problem: Problem) -> Design:
    """The design over the varied parameters (see the module's docstring)."""
    d = len(problem.varied)
    journalled = set(problem.journal.done) if problem.journal is not None else set()  # a killed run's verdicts
    if d == 1:
        out = _interval(problem)
    elif d == 2:
        out = _chart(problem)
    else:
        out = _optimiser(problem)
    if out.best is not None and out.best.feasible:
        out.sensitivity = sensitivity(problem, out.best)
    out.evaluations = len([k for k in problem.cache if k[0] == "assess"])
    out.resumed = sum(verdict_key(problem, key[1]) in journalled for key in problem.cache if key[0] == "assess")
    out.verdicts = [v for k, v in sorted(problem.cache.items(), key=lambda kv: str(kv[0])) if k[0] == "assess"]
    return out


def _interval(problem: Problem) -> Design:
    axis = problem.varied[0]
    line, edges = scan_line(problem, axis, [axis.low], VARY_POINTS, VARY_REFINE)
    bounds = _boundaries_of(problem, axis, [axis.low], line, edges)
    windows = [w for w in line.windows]
    out = Design(problem, "interval", None, windows, bounds)
    out.resolution = {axis.name: (axis.high - axis.low) / (VARY_POINTS - 1) / VARY_REFINE,
                      "ends": "stability limits located by Brent's method on the worst margin (xtol 1e-12 relative) "
                              "and seen on both sides; capacity limits by Brent's method on the capacity slack "
                              "(xtol 1e-12 relative)",
                      "statement": f"every feasible interval wider than {out_resolution(axis):.3g} in {axis.name} holds a "
                                   "sample (windows.certify on the worst margin over the box)"}
    best = None
    for a, b in windows:
        if b > a:
            r = minimize_scalar(lambda x: assess(problem, [x]).margin if assess(problem, [x]).feasible else 1.0,
                                bounds=(a, b), method="bounded", options={"xatol": 1e-6 * max(1.0, b - a)})
            cands = [assess(problem, [r.x])]
        else:
            cands = []
        cands += [s.state for s in line.samples if a <= s.x <= b and s.state is not None]
        for v in cands:
            if v.feasible and (best is None or v.margin < best.margin):
                best = v
    out.best = best
    out.active = active_limit(problem, best, bounds)
    return out


def out_resolution(axis: Axis) -> float:
    return (axis.high - axis.low) / (VARY_POINTS - 1) / VARY_REFINE


def active_limit(problem: Problem, best: Verdict | None, bounds: list[Boundary]) -> Boundary | None:
    """What limits the best design: the varied range's end where the best design sits on it (the design would
    improve beyond it), else the located boundary nearest it, in the varied parameters scaled by their ranges."""
    if best is None:
        return None
    here = dict(zip([a.name for a in problem.varied], best.design))
    for a in problem.varied:
        for end, word in ((a.low, "low"), (a.high, "high")):
            if abs(here[a.name] - end) <= 1e-9 * (a.high - a.low):
                return Boundary(here, f"range end ({a.name} at its {word} end)", best.worst)
    if not bounds:
        return None
    scale = {a.name: a.high - a.low for a in problem.varied}
    return min(bounds, key=lambda b: math.hypot(*[(b.values[n] - here[n]) / scale[n] for n in scale]))


def _chart(problem: Problem) -> Design:
    a1, a2 = problem.varied
    g1 = np.linspace(a1.low, a1.high, CHART_POINTS)
    g2 = np.linspace(a2.low, a2.high, CHART_POINTS)
    seen = []  # every verdict of the grid and of the certified lines
    margin = np.full((CHART_POINTS, CHART_POINTS), np.nan)
    feasible = np.zeros((CHART_POINTS, CHART_POINTS), bool)
    exists = np.zeros((CHART_POINTS, CHART_POINTS), bool)
    prefetch(problem, [[x, y] for x in g1 for y in g2], "design chart")
    for i, x in enumerate(g1):
        for j, y in enumerate(g2):
            v = assess(problem, [x, y])
            seen.append(v)
            margin[i, j], feasible[i, j], exists[i, j] = v.margin, v.feasible, v.exists
    bounds, rows, cols = [], [], []
    # rows along the first parameter, columns along the second
    specs = [(0, [a1.low, float(y)]) for y in g2] + [(1, [float(x), a2.low]) for x in g1]
    lines = scan_lines(problem, specs, CHART_POINTS, CHART_REFINE, "design chart lines")
    for (k, at), (line, edges) in zip(specs, lines):
        bounds += _boundaries_of(problem, problem.varied[k], at, line, edges)
        seen += [s.state for s in line.samples]
        if k == 0:
            rows.append({a2.name: at[1], "feasible": [list(w) for w in line.windows]})
        else:
            cols.append({a1.name: at[0], "feasible": [list(w) for w in line.windows]})
    res = [(a.high - a.low) / (CHART_POINTS - 1) / CHART_REFINE for a in (a1, a2)]
    chart = {"axes": [a1.name, a2.name], a1.name: g1.tolist(), a2.name: g2.tolist(),
             "margin": [[_num(m) for m in row] for row in margin], "feasible": feasible.tolist(),
             "exists": exists.tolist(), "rows": rows, "columns": cols}
    out = Design(problem, "chart", None, [], bounds, chart=chart)
    out.resolution = {a1.name: res[0], a2.name: res[1],
                      "statement": f"every feasible window wider than {res[0]:.3g} in {a1.name} along each row, and wider "
                                   f"than {res[1]:.3g} in {a2.name} along each column, holds a sample (windows.certify on "
                                   "the worst margin over the box); each stability boundary seen on both sides, located "
                                   "by Brent's method; capacity limits by Brent's method on the capacity slack"}
    cands = [v for v in seen if v is not None and v.feasible]
    best = min(cands, key=lambda v: v.margin) if cands else None
    if best is not None:  # polished: the worst margin minimised over the design, inside the chart
        r = minimize(lambda z: _penalised(problem, z), np.array(best.design), method="Nelder-Mead",
                     bounds=[(a.low, a.high) for a in problem.varied],
                     options={"xatol": 1e-6, "fatol": 1e-12, "maxiter": 60})
        v = assess(problem, r.x)
        best = v if v.feasible and v.margin < best.margin else best
    out.best = best
    out.active = active_limit(problem, best, bounds)
    return out


def _penalised(problem: Problem, z) -> float:
    v = assess(problem, z)
    return v.margin if v.feasible else 1.0 + (0.0 if not math.isfinite(v.margin) else abs(v.margin))


def _optimiser(problem: Problem) -> Design:
    """COBYLA on the worst margin, in coordinates scaled to [0, 1] per varied parameter; constraints: the
    capacity slack and -(worst margin) non-negative, the bounds; every evaluation a certified box scan."""
    lo = np.array([a.low for a in problem.varied])
    span = np.array([a.high - a.low for a in problem.varied])

    def at(u):
        return lo + span * np.clip(u, 0, 1)

    from contextlib import nullcontext

    from ..progress import activity
    from .design_runs import session

    desc = "design optimiser (COBYLA)"
    # on the local Dask cluster (issue 39 item 5), one cluster for the whole optimisation: COBYLA's first n + 1
    # designs (the centre and a step of rhobeg along each coordinate, scipy's initial simplex) assessed together
    # (prefetch: journalled, with progress), then each later design's box lines together (_box_lines); the
    # verdicts, and so the optimiser's path, are those of the sequential run
    rhobeg = 0.25
    start = np.full(len(lo), 0.5)
    with (session(problem.workers) if problem.parallel else nullcontext()), \
            activity(desc, problem.progress) as note:  # one design after another: elapsed time and the count
        first = [at(start)] + [at(start + rhobeg * e) for e in np.eye(len(lo))]
        prefetch(problem, first, f"{desc}: first designs")
        for d in first:  # assessed either way, so the designs assessed (and `evaluations`) do not depend on Dask
            assess(problem, d)
        problem.box_lines_parallel = True

        def worst(u):
            v = assess(problem, at(u))
            note(f"{desc}: {sum(k[0] == 'assess' for k in problem.cache)} designs assessed")
            return v.margin if math.isfinite(v.margin) else 1.0
        cons = [{"type": "ineq", "fun": lambda u: min(capacity_slack(problem, at(u)), 1e6)},
                {"type": "ineq", "fun": lambda u: -worst(u)}]
        cons += [{"type": "ineq", "fun": lambda u, k=k: u[k]} for k in range(len(lo))]
        cons += [{"type": "ineq", "fun": lambda u, k=k: 1 - u[k]} for k in range(len(lo))]
        try:
            r = minimize(worst, start, method="COBYLA", constraints=cons,
                         options={"rhobeg": rhobeg, "tol": 1e-6, "maxiter": 200})
            v = assess(problem, at(r.x))
        finally:
            problem.box_lines_parallel = False
    out = Design(problem, "optimiser", v if v.feasible else None)
    out.active = active_limit(problem, out.best, [])  # a varied range's end where the optimum sits on it
    out.resolution = {"statement": f"COBYLA (scipy) from the centre of the design box, {r.nfev} evaluations, "
                                   f"status: {r.message}; a local optimum: other feasible regions may exist"}
    return out


# -------------------------------------------------------------------------------------- sensitivity

def sensitivity(problem: Problem, best: Verdict) -> list[dict]:
    """d(worst margin)/d(varied parameter) at the best design: from jac_p (the eigenvalue's first-order
    perturbation at the worst box point) and by one-sided finite differences of the worst margin (up, down);
    `agree` when jac_p's slope matches one of them to AGREE, `kink` when they differ (two box points equally
    worst: a max-min optimum); and how far the parameter may move at jac_p's slope before the margin reaches 0.
    A forced model's balancing orbit: the finite differences only (jac_p's perturbation is an equilibrium's
    eigenvalue's; a multiplier's would need the second variational equations): `dmargin` their mean, `agree`
    None (not checked), `method` says which."""
    m = problem.model
    if not m.autonomous:
        out = []
        for k, axis in enumerate(problem.varied):
            one_sided = _one_sided(problem, best, k, axis)
            finite = [x for x in one_sided if math.isfinite(x)]
            slope = float(np.mean(finite)) if finite else math.nan
            kink = bool(len(finite) == 2 and abs(finite[0] - finite[1]) > AGREE * max(map(abs, finite)) + 1e-9)
            room = -best.margin / abs(slope) if math.isfinite(slope) and slope != 0 else math.inf
            out.append({"parameter": axis.name, "dmargin": _num(slope), "dmargin_finite_difference":
                        [_num(x) for x in one_sided], "agree": None, "kink": kink,
                        "direction_to_boundary": "increase" if slope > 0 else "decrease", "room_linear": _num(room),
                        "method": "one-sided finite differences of the worst margin (a forced model's orbit)"})
        return out
    from .steady import complement, family_tangent, jacobian

    p = problem.params(best.design, best.worst)
    s = _state_at(problem, p)
    J = jacobian(m, s.y, p)
    T = family_tangent(m, s.y, p, J)
    S = complement(T)
    A = S.T @ J @ S
    import scipy.linalg

    w, vl, vr = scipy.linalg.eig(A, left=True, right=True)
    lead = int(np.argmax(w.real))
    l, r = vl[:, lead], vr[:, lead]
    fp = np.asarray(m.module.jac_p(0.0, s.y, p))
    out = []
    for k, axis in enumerate(problem.varied):
        col = m.param_names.index(axis.name)
        # the direction in the parameters: the varied one and every parameter tied to it (--tie) move together
        e = np.zeros_like(p)
        for name in [axis.name] + [n for n, source in problem.ties.items() if source == axis.name]:
            e[m.param_names.index(name)] = 1.0
        dy = -np.linalg.lstsq(J, fp @ e, rcond=1e-11)[0]
        h = FD_STEP * (abs(p[col]) or 1.0)
        dJ = (jacobian(m, s.y + h * dy, p + h * e) - jacobian(m, s.y - h * dy, p - h * e)) / (2 * h)
        via_jac_p = float((l.conj() @ (S.T @ dJ @ S) @ r / (l.conj() @ r)).real)
        one_sided = _one_sided(problem, best, k, axis)
        # at a max-min optimum two box points are equally worst and the worst margin has a kink: its one-sided
        # slopes differ, and jac_p's slope (at one of them) matches one side only
        kink = bool(all(map(math.isfinite, one_sided)) and abs(one_sided[0] - one_sided[1])
                    > AGREE * max(map(abs, one_sided)) + 1e-9)
        agree = any(math.isfinite(fd) and abs(fd - via_jac_p) <= AGREE * max(abs(fd), abs(via_jac_p), 1e-9)
                    for fd in one_sided)
        room = -best.margin / abs(via_jac_p) if via_jac_p != 0 else math.inf
        out.append({"parameter": axis.name, "dmargin": via_jac_p, "dmargin_finite_difference": [_num(x) for x in one_sided],
                    "agree": agree, "kink": kink, "direction_to_boundary": ("increase" if via_jac_p > 0 else "decrease"),
                    "room_linear": _num(room)})
    return out


def _one_sided(problem: Problem, best: Verdict, k: int, axis: Axis) -> list[float]:
    """The worst margin's one-sided finite differences (up, down) in the k-th varied parameter at `best`."""
    hd = FD_STEP * (abs(best.design[k]) or axis.high - axis.low)
    out = []
    for sign in (1, -1):
        moved = list(best.design)
        moved[k] += sign * hd
        vm = assess(problem, moved)
        out.append(sign * (vm.margin - best.margin) / hd if math.isfinite(vm.margin) else math.nan)
    return out
