"""Follow a steady state in one parameter and locate where its stability changes (thesis ch. 4).

    scan(model, p, y0, "Omega", 4.0, 0.5)   -> Scan: the branch, Hopf points and folds, stable intervals

The branch is followed by the one continuer, `orbits.continuer.run` (pseudo-arclength, test functions,
step bound, extremum checks, Brent location), on the equilibrium curve `orbits.equilibrium.EquilibriumCurve`:
unknowns z = (y, lambda), F = rhs(y, lambda) with the pins T^T (y - y_a) = 0 onto one member of the balanced
family (3.6) when the state lies on it (n >= 3; T is N x 0 otherwise).  Stability along the branch is that of
the transverse spectrum (`steady.transverse_spectrum`: the family's zero eigenvalues removed exactly).  This
module turns the continuer's branch and special points into the scan's points:

* a Hopf point: a complex pair crosses (the curve's "hopf" test); frequency = |Im| of that pair there;
* a fold (saddle-node): the branch turns back in lambda (the root of d lambda/ds of the tangent);
* a real eigenvalue crossing zero where the branch does not turn (the "real" test) is a branch point
  (pitchfork), reported apart from `points`;
* a change of the unstable count (or a turn) that was not located: reported with its step as `bracket`.

Direction: "stabilising" when the count of unstable eigenvalues drops in the direction of the scan
(from FROM to TO), "destabilising" when it grows, null for a fold where it does not change (the
balanced branch turning at mu_c into its mirror copy phi_1 <-> phi_2, the thesis' pitchfork PF1,2).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .loading import AnalysisError, Model
from .steady import _require_autonomous, classify, refine

NEWTON_TOL = 1e-12
LOCATE_TOL = 1e-12


@dataclass
class BranchPoint:
    lam: float
    y: np.ndarray
    tangent: np.ndarray  # unit tangent (dy, dlambda) of the branch
    spectrum: np.ndarray  # transverse spectrum
    n_unstable: int
    classification: str


@dataclass
class Bifurcation:
    kind: str  # "hopf", "fold" or "branch"
    value: float
    frequency: float | None
    direction: str | None  # "stabilising" | "destabilising" along the scan; None: no change (a fold only)
    y: np.ndarray
    n_unstable_before: int
    n_unstable_after: int
    bracket: tuple[float, float] | None = None  # set when root finding failed: the step it lies in
    extra: dict = field(default_factory=dict)  # e.g. first_lyapunov, criticality of a Hopf point

    def to_json(self, name: str) -> dict:
        out = {"kind": self.kind, name: self.value, "frequency": self.frequency, "direction": self.direction,
               "n_unstable_before": self.n_unstable_before, "n_unstable_after": self.n_unstable_after, **self.extra}
        if self.bracket is not None:
            out["bracket"] = list(self.bracket)
        return out


@dataclass
class Scan:
    model: Model
    name: str
    start: float
    stop: float
    branch: list[BranchPoint]
    bifurcations: list[Bifurcation]
    stable_intervals: list[tuple[float, float]]
    end_reason: str
    extra: dict = field(default_factory=dict)
    p: np.ndarray | None = None  # the parameters (the scanned one at its start)

    @property
    def complete(self) -> bool:
        """Whether the branch was followed until it left the parameter range (at TO, or at FROM after
        turning back at a fold); False when a step limit or step-size underflow stopped it inside."""
        return self.end_reason == "left the range"

    @property
    def end_at(self) -> float:
        """The parameter value of the last step."""
        return float(self.branch[-1].lam)

    @property
    def points(self) -> list[Bifurcation]:
        """Hopf points and folds, in the order met along the branch."""
        return [b for b in self.bifurcations if b.kind in ("hopf", "fold")]

    @property
    def branch_points(self) -> list[Bifurcation]:
        return [b for b in self.bifurcations if b.kind == "branch"]

    def to_json(self) -> dict:
        return {"model": self.model.name, "parameter": self.name, "from": self.start, "to": self.stop,
                "points": [b.to_json(self.name) for b in self.points],
                "branch_points": [b.to_json(self.name) for b in self.branch_points],
                "stable_intervals": [list(iv) for iv in self.stable_intervals],
                "steps": len(self.branch), "end": self.end_reason, "complete": self.complete, "end_at": self.end_at,
                "range": [float(min(b.lam for b in self.branch)), float(max(b.lam for b in self.branch))],
                **self.extra}


def scan(model: Model, p: np.ndarray, y0: np.ndarray, name: str, start: float, stop: float, ds: float = 0.005,
         ds_max: float = 0.01, ds_min: float = 1e-7, max_steps: int = 20000, progress=None,
         ds_floor: float | None = None, watch: bool = True) -> Scan:
    """Follow the steady state near y0 from name = start to stop; Hopf points, folds, stable intervals.

    The branch is the generic continuer's (`orbits.continuer.run`) on the equilibrium curve
    (`orbits.equilibrium.EquilibriumCurve`): steps at most ds_max long in (y, lambda) until lambda leaves
    [min, max](start, stop), or `max_steps` steps ("step limit") or a step below ds_min ("step size underflow")
    end it early; `progress(lambda)` is called at each accepted point.  Steps that miss nothing (issue 21 item
    5): the LEADING largest real parts are the curve's margins, so a step is bounded by how fast they head for
    zero (down to ds_floor, default ds_max / 50) and an extremum of one inside a step is checked (watch=False:
    neither, plain stepping)."""
    from .orbits import continuer
    from .orbits.equilibrium import EquilibriumCurve
    from .orbits.parameters import ParameterMap

    _require_autonomous(model)
    if name not in model.param_names:
        raise AnalysisError(f"{name!r} is not a parameter of {model.name}; parameters: {', '.join(model.param_names)}")
    if not start != stop:
        raise AnalysisError(f"empty scan range {name}={start}:{stop}")
    floor = ds_max / 50 if ds_floor is None else ds_floor
    pmap = ParameterMap(model, np.array(p, float), [name])
    first = refine(model, pmap(start), y0)
    curve = EquilibriumCurve(model, pmap)
    x0 = np.r_[first.y, start]
    curve.accept(x0, curve.data(x0))
    if abs(np.linalg.svd(curve.evaluate(x0)[1])[2][-1][-1]) < 1e-8:
        raise AnalysisError(f"the start state is a fold in {name}: move {name} a little")
    curve.progress = progress
    lo, hi = min(start, stop), max(start, stop)
    settings = continuer.Settings(ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_steps + 1, bounds=(lo, hi),
                                  newton_tol=NEWTON_TOL, newton_max=15, resolution=floor, locate_tol=LOCATE_TOL,
                                  watch=watch)
    run = continuer.run(curve, x0, 1.0 if stop > start else -1.0, settings)
    branch = [_branch_point(pt) for pt in run.points]
    found = _bifurcations(branch, run, lo, hi)
    reason = {"max_points": "step limit"}.get(run.end, run.end)
    lam = np.array([b.lam for b in branch])
    stats = {"ds_floor": floor, "ds_max": ds_max, "extremum_checks": run.checks,
             "largest_step": float(np.max(np.abs(np.diff(lam)))) if len(lam) > 1 else 0.0}
    return Scan(model, name, start, stop, branch, [b for _, b in found], _stable_intervals(branch, found, lo, hi),
                reason, {"resolution": _resolution(branch, stats)}, np.array(pmap.base, float))


def _branch_point(pt) -> BranchPoint:
    kind, unstable, _ = classify(pt.data.spectrum)
    return BranchPoint(float(pt.x[-1]), pt.x[:-1], pt.tangent, pt.data.spectrum, unstable, kind)


KINDS = {"hopf": "hopf", "real": "branch", "fold": "fold"}  # the equilibrium curve's test -> the point's kind


def _bifurcations(branch: list[BranchPoint], run, lo: float, hi: float) -> list[tuple[int, Bifurcation]]:
    """The located special points (Hopf points, folds, branch points: a real eigenvalue through zero where the
    branch does not turn; at a fold only the fold; Hopf and branch points only where the number of unstable
    eigenvalues changes), each with the step it lies in; a change of the unstable
    count or a turn that could not be located is reported with that step as `bracket`."""
    def direction(a, b):
        return "stabilising" if b.n_unstable < a.n_unstable else "destabilising" if b.n_unstable > a.n_unstable else None

    folds = {sp.index for sp in run.specials if sp.name == "fold"}
    found, seen = [], set()
    for sp in run.specials:
        a, b = branch[sp.index], branch[sp.index + 1]
        if sp.name != "fold" and (sp.index in folds or a.n_unstable == b.n_unstable):
            continue  # a test's zero that changes no stability (at the turn of a pitchfork PF1,2): not a point
        freq = abs(sp.info["frequency"]) if sp.info["kind"] == "hopf" else None
        found.append((sp.index, Bifurcation(sp.info["kind"], float(sp.x[-1]), freq, direction(a, b), sp.x[:-1],
                                            a.n_unstable, b.n_unstable)))
        seen.add(sp.index)
    for i, (a, b) in enumerate(zip(branch, branch[1:])):
        turned = a.tangent[-1] * b.tangent[-1] < 0
        if i in seen or not (turned or a.n_unstable != b.n_unstable):
            continue
        kind = "fold" if turned else ("hopf" if abs(a.n_unstable - b.n_unstable) == 2 else "branch")
        near = b.spectrum[np.argsort(np.abs(b.spectrum.real))[:2]]
        found.append((i, Bifurcation(kind, 0.5 * (a.lam + b.lam), float(np.max(np.abs(near.imag))) if kind == "hopf"
                                     else None, direction(a, b), 0.5 * (a.y + b.y), a.n_unstable, b.n_unstable,
                                     (a.lam, b.lam))))
    found.sort(key=lambda f: f[0])
    return [(i, bif) for i, bif in found if lo <= bif.value <= hi]


def _stable_intervals(branch: list[BranchPoint], bifurcations: list[tuple[int, Bifurcation]],
                      lo: float, hi: float) -> list[tuple[float, float]]:
    """Parameter intervals (ascending, overlapping ones merged) where the followed state is stable:
    runs of stable steps, extended to the located bifurcations that bound them (a fold inside a run,
    e.g. the turn of the balanced branch at mu_c into its mirror copy, keeps the run going)."""
    after: dict[int, list[float]] = {}
    for i, bif in bifurcations:  # located between steps i and i + 1
        after.setdefault(i, []).append(bif.value)
    runs, current = [], None
    for i, b in enumerate(branch):
        if b.classification == "stable":
            if current is None:
                current = list(after.get(i - 1, []))[-1:]
            current.append(b.lam)
            current += after.get(i, [])
        elif current is not None:
            runs.append(current)
            current = None
    if current is not None:
        runs.append(current)
    spans = sorted((min(max(min(r), lo), hi), min(max(max(r), lo), hi)) for r in runs)
    merged: list[list[float]] = []
    for a, b in spans:
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        else:
            merged.append([a, b])
    return [(float(a), float(b)) for a, b in merged]


def _resolution(branch: list[BranchPoint], stats: dict) -> dict:
    """What the scan resolved: a window of the parameter wider than `largest_step` always holds a step end and
    is seen; narrower ones are seen where the step bound shrank the steps around them (`step_near_axis`: the
    largest parameter step taken while a leading real part was within 1e-2 of zero) or an extremum check
    caught them."""
    lam = np.array([b.lam for b in branch])
    lead = np.array([float(np.max(b.spectrum.real)) if b.spectrum.size else 0.0 for b in branch])
    near = [abs(lam[i + 1] - lam[i]) for i in range(len(lam) - 1)
            if min(abs(lead[i]), abs(lead[i + 1])) < 1e-2 or np.sign(lead[i]) != np.sign(lead[i + 1])]
    return {"largest_step": stats["largest_step"], "step_near_axis": float(max(near, default=0.0)),
            "ds_max": stats["ds_max"], "ds_floor": stats["ds_floor"], "extremum_checks": stats["extremum_checks"]}
