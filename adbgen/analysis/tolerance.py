"""Tolerance-sensitive outcomes (issue 34, item 2): a transient re-run tighter and on a second engine, its
outcome compared; a disagreement is reported, never resolved.

    check = check_simulation(model, p, y0, sim, t_end=..., threshold=..., engine="auto")
    check.sensitive, check.reasons, check.to_json()

A case runs three times: as asked (engine E at rtol, atol), **tighter** (E at rtol/TIGHTEN, atol/TIGHTEN)
and on a **second engine** of another method (`second_engine`: DOP853 beside Taylor's method, Taylor's
method beside every other engine) at the asked tolerance.  Two outcomes agree when

* their status is the same (a failed run never agrees with a successful one),
* their labels are the same (`attractors.Classifier.label`, the sweeps' labelling: autonomous models;
  a model with no steady states has no label and is compared by its numbers only),
* r_max agrees to REL_TOL relative, and t_dec too (both settled or both not; t_dec = 0, r never reached
  the threshold, agrees only with 0).

Any disagreement of the tighter run or of the second engine with the run as asked makes the case
`tolerance_sensitive`, and both outcomes are kept (`ToleranceCheck.runs`).  So does a global error
estimate above its bound (issue 35, `error_estimate`): the run as asked against a run that truly is
tighter, max_i |y_i - y_tight,i| / (atol + rtol |y_tight,i|) at t_end above 2 tolerance units (the promise's
`error_estimate.BOUND` = 10 over `error_estimate.SAFETY` = 5; `ToleranceCheck.error_estimate`, --json's
"error_estimate"), and so does its conditioning probe above the same 2 units (the run compared with, again
from y0 moved an ulp: how much round-off the transient amplifies; "error_estimate"."conditioning").  Runs
`shown` beside them (the thesis' solver, `matlab-ode45`, at its defaults) are reported with their own
agreement but do not decide the flag: they are an explanation of a published number, not a convergence test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import error_estimate
from .loading import Model

TIGHTEN = 100.0  # the tighter run: rtol / 100 and atol / 100
REL_TOL = 0.01  # r_max and t_dec agree when within 1 % of the larger
MIN_RTOL = 1e-14  # the tighter rtol is kept at or above this (double precision resolves 1e-15 at best)
MARK = "(!)"  # the mark of a tolerance-sensitive outcome in tables (figures: `mark_points`)


def tightened_tolerances(rtol: float, atol: float) -> tuple[float, float]:
    """(rtol, atol) of the tighter run: both divided by TIGHTEN, rtol not below MIN_RTOL (atol scaled alike)."""
    factor = min(TIGHTEN, rtol / MIN_RTOL) if rtol > MIN_RTOL else 1.0
    return rtol / factor, atol / factor


def resolved(engine, model: Model, rtol: float, atol: float, *, ensemble: bool = False,
             measures: bool = True) -> str:
    """The name of the engine that actually runs (the auto engine's pick), for choosing a second one."""
    from .engines import engine_for

    eng = engine_for(model, engine)
    if ensemble and hasattr(eng, "picked_many"):
        return eng.picked_many(rtol, atol, model, measures)[3]["engine"]
    if hasattr(eng, "picked"):
        return eng.picked(rtol, atol, model)[3]["engine"]
    return eng.name


def _has_series(model: Model) -> bool:
    from .engines.taylor import taylor_source
    from .loading import AnalysisError

    try:
        taylor_source(model)
    except AnalysisError:
        return False
    return True


def second_engine(name: str, model: Model) -> str:
    """An engine of another method than `name` (the engine that ran, `resolved`): its steps fall elsewhere,
    so an outcome that hangs on where the steps fall shows.  DOP853 (compiled) beside Taylor's method; Taylor's
    method beside every other engine where the model has a Taylor series, else Verner's 8(7) (CyRK) beside
    DOP853 and DOP853 beside the rest."""
    if name.startswith("taylor"):
        return "rk-dop853"
    if _has_series(model):
        return "taylor"
    return "cyrk-vern8" if "dop853" in name else "rk-dop853"


@dataclass
class Outcome:
    """What one run gave: the numbers compared (label, r_max, t_dec) and how it was run."""

    role: str  # "as run", "tighter", "second engine", or what a shown run is ("thesis' solver")
    engine: str
    picked: str  # the engine that ran (the auto engine's pick)
    rtol: float
    atol: float
    status: str
    label: str | None
    r_max: float
    t_dec: float | None

    def to_json(self) -> dict:
        from .results import plain

        return plain({"role": self.role, "engine": self.engine, "picked": self.picked, "rtol": self.rtol,
                      "atol": self.atol, "status": self.status, "label": self.label, "r_max": self.r_max,
                      "t_dec": self.t_dec})

    def text(self) -> str:
        """One short phrase: 'limit cycle (rtol 1e-10, rk-dop853)'."""
        what = self.label or (f"r_max {self.r_max:.4g}, t_dec "
                              + ("not settled" if self.t_dec is None else f"{self.t_dec:.6g}"))
        if self.status != "success":
            what = f"failed ({self.status})"
        return f"{what} (rtol {self.rtol:g}, {self.picked})"


def _close(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b))


def _t_dec(v) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def disagreements(a: Outcome, b: Outcome, rel: float = REL_TOL) -> list[str]:
    """How outcome b differs from a (empty: they agree); each item one phrase."""
    if a.status != b.status:
        return [f"status {a.status} vs {b.status}"]
    if a.status != "success":
        return []
    out = []
    if a.label != b.label:
        out.append(f"label {a.label} vs {b.label}")
    if not _close(a.r_max, b.r_max, rel):
        out.append(f"r_max {a.r_max:.6g} vs {b.r_max:.6g}")
    ta, tb = _t_dec(a.t_dec), _t_dec(b.t_dec)
    if (ta is None) != (tb is None) or (ta is not None and not _close(ta, tb, rel)):
        show = lambda t: "not settled" if t is None else f"{t:.6g}"  # noqa: E731
        out.append(f"t_dec {show(ta)} vs {show(tb)}")
    return out


def label_of(model: Model, p, sim, engine, rtol: float, atol: float) -> str | None:
    """The sweeps' label of a run's end state (`attractors.classifier`); None for a model without steady
    states (not autonomous) or a failed run."""
    if not model.autonomous:
        return None
    from .attractors import classifier

    # the run's own end time: a run not named there is carried on to the cap of `decide`, as in sweeps
    return classifier(model, p).label(sim.status, sim.y_end, -1, engine=engine, rtol=rtol, atol=atol,
                                      t=sim.t_end)


def outcome(model: Model, p, sim, role: str, engine, label: bool = True) -> Outcome:
    """The Outcome of a Simulation (labelled on the engine and tolerance it ran with)."""
    name = engine if isinstance(engine, str) else getattr(engine, "name", str(engine))
    picked = (sim.picked or {}).get("engine", sim.engine)
    lab = label_of(model, p, sim, engine, sim.rtol, sim.atol) if label and sim.status == "success" else None
    return Outcome(role, name, picked, sim.rtol, sim.atol, sim.status, lab, float(sim.r_max), _t_dec(sim.t_dec))


@dataclass
class ToleranceCheck:
    """The runs of one case and their disagreements with the run as asked (`runs[0]`)."""

    runs: list[Outcome]
    reasons: list[str]
    shown: list[tuple[Outcome, list[str]]] = field(default_factory=list)
    factor: float = TIGHTEN
    rel_tol: float = REL_TOL
    error_estimate: dict | None = None  # the global error estimate at t_end (`error_estimate.estimate`)

    @property
    def sensitive(self) -> bool:
        return bool(self.reasons)

    def to_json(self) -> dict:
        return {"tolerance_sensitive": self.sensitive, "factor": self.factor, "rel_tol": self.rel_tol,
                "outcomes": [o.to_json() for o in self.runs], "disagreements": list(self.reasons),
                "shown": [{**o.to_json(), "disagreements": r} for o, r in self.shown],
                "error_estimate": self.error_estimate}

    def text(self) -> str:
        """'tolerance-sensitive (!): balanced 1 (rtol 1e-08, taylor) | limit cycle (rtol 1e-10, taylor)'
        or 'robust: ...' (every outcome named)."""
        head = f"tolerance-sensitive {MARK}" if self.sensitive else "robust"
        return f"{head}: " + " | ".join(o.text() for o in self.runs)


def judge(runs: list[Outcome], shown=(), rel: float = REL_TOL, factor: float = TIGHTEN) -> ToleranceCheck:
    """The check of outcomes already computed: runs[0] the run as asked, the rest compared with it."""
    reasons = [f"{o.role}: {r}" for o in runs[1:] for r in disagreements(runs[0], o, rel)]
    return ToleranceCheck(list(runs), reasons, [(o, disagreements(runs[0], o, rel)) for o in shown], factor, rel)


def check_simulation(model: Model, p, y0, sim, *, t_end: float, threshold: float, engine=None,
                     max_steps: int = 10_000_000, label: bool = True, tight=None, second: str | None = None,
                     shown=(), estimate: bool = False) -> ToleranceCheck:
    """`sim` (run from y0 with engine `engine` at sim.rtol, sim.atol) against the tighter run and the second
    engine.  `tight`: the tighter run if already computed (its tolerance is then whatever it ran at);
    `second`: the second engine's name (default `second_engine`); `shown`: (role, engine, rtol, atol) of runs
    reported beside them (not deciding the flag), or (role, engine, Simulation) of such runs already made.
    `estimate`: also the global error estimate at t_end (`global_error`), flagging above its bound: what
    `adbgen simulate --check-tolerance` asks (the default engine's promise); off for the checks of outcomes
    alone (the reproduction's transients, whose labels, not final states, are the published result)."""
    from .simulate import simulate

    p = np.asarray(model.params(p) if isinstance(p, dict) or p is None else p, float)
    y0 = np.asarray(model.state(y0) if isinstance(y0, dict) or y0 is None else y0, float)

    def run(eng, rtol, atol, start=y0):
        return simulate(model, p, start, t_end=t_end, rtol=rtol, atol=atol, engine=eng, threshold=threshold,
                        keep_trajectory=False, max_steps=max_steps, check=False)

    rt, at = tightened_tolerances(sim.rtol, sim.atol)
    if tight is None:
        tight = run(engine, rt, at)
    picked = (sim.picked or {}).get("engine", sim.engine)
    other = second or second_engine(picked, model)
    runs = [outcome(model, p, sim, "as run", engine, label), outcome(model, p, tight, "tighter", engine, label),
            outcome(model, p, run(other, sim.rtol, sim.atol), "second engine", other, label)]
    extra = [outcome(model, p, run(item[1], *item[2:]) if len(item) == 4 else item[2], item[0], item[1], label)
             for item in shown]
    check = judge(runs, extra, factor=sim.rtol / tight.rtol)
    if estimate and sim.ok and tight.ok:
        check.error_estimate = global_error(model, sim, tight, run, y0=y0, p=p, engine=engine)
        if check.error_estimate["exceeded"] is not False:  # exceeded, or not made (its run failed)
            check.reasons.append(error_estimate.reason(check.error_estimate))
    return check


def global_error(model: Model, sim, tight, run, *, y0, p, engine) -> dict:
    """The error estimate at t_end of `sim` (`error_estimate`): against the tighter run where it aims its
    steps finer, else against the estimate's own row, run by `run(engine, rtol, atol)` at the tighter
    tolerance; angles compared as the model describes them (`Model.angle_indices`).  Not made (ratio None,
    so flagged) where no row within double precision's reach is finer or the estimate's own run fails.

    Beside it the conditioning probe (`error_estimate.conditioning`): the run compared with (`engine` at the
    tighter tolerance, or the estimate's own row) again from `error_estimate.probe_state(y0)` (identical balls
    started together moved alike: `model.symmetries` at `p`), by
    `run(engine, rtol, atol, start)`; the record flags where either is above its flag."""
    asked = sim.picked or {}
    row = error_estimate.reference_row(asked, tight.picked or {}, sim.rtol / tight.rtol)
    against, y_ref, ref_engine = "tighter run", tight.y_end, engine
    if row is not None:
        against = f"Taylor order {row[0]}, step factor {row[1]:g}"
        if not error_estimate.finer(asked, row):
            return error_estimate.not_made(against, row, "no row finer than the run as asked within double "
                                                         "precision's reach")
        ref_engine = error_estimate.reference_engine(row)
        ref = run(ref_engine, tight.rtol, tight.atol)
        if not ref.ok:
            return error_estimate.not_made(against, row, f"its run, {against}, ended {ref.status}")
        y_ref = ref.y_end
    record = error_estimate.estimate(sim.y_end, y_ref, sim.rtol, sim.atol, model.angle_indices, against=against,
                                     row=row)
    probe = run(ref_engine, tight.rtol, tight.atol, error_estimate.probe_state(y0, sim.rtol, sim.atol,
                                                                         symmetries=model.symmetries, p=p))
    cond = error_estimate.conditioning(probe.y_end, y_ref, sim.rtol, sim.atol, model.angle_indices,
                                       status=probe.status)
    return error_estimate.with_conditioning(record, cond)


# ------------------------------------------------------------------------------------------ ensembles

def differ(a: np.ndarray, b: np.ndarray, rel: float = REL_TOL) -> np.ndarray:
    """Element-wise disagreement of two sweeps' values: label codes (integers) unequal; numbers (r_max,
    t_dec, NaN: not settled or failed) not within rel of the larger, or one NaN and the other not."""
    a, b = np.asarray(a), np.asarray(b)
    if np.issubdtype(a.dtype, np.integer):
        return a != b
    a, b = a.astype(float), b.astype(float)
    nan_a, nan_b = np.isnan(a), np.isnan(b)
    with np.errstate(invalid="ignore"):
        far = np.abs(a - b) > rel * np.maximum(np.abs(a), np.abs(b))
    return (nan_a != nan_b) | (~nan_a & ~nan_b & far)


def mark_points(ax, x, y=None, *, label: str = "tolerance-sensitive") -> None:
    """Mark tolerance-sensitive points on a figure: a black-edged white diamond on each (x, y) (1-D plots:
    y the plotted values), with the count in the legend's label."""
    x = np.atleast_1d(np.asarray(x, float))
    if x.size == 0:
        return
    y = np.zeros_like(x) if y is None else np.atleast_1d(np.asarray(y, float))
    ax.plot(x, y, "D", mfc="white", mec="black", ms=4, mew=0.8, ls="none", label=f"{label} ({x.size})")


__all__ = ["MARK", "MIN_RTOL", "Outcome", "REL_TOL", "TIGHTEN", "ToleranceCheck", "check_simulation", "differ",
           "disagreements", "global_error", "judge", "label_of", "mark_points", "outcome", "resolved", "second_engine",
           "tightened_tolerances"]
