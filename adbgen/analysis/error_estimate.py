"""The global error estimate at t_end (issue 35, item 1): the run as asked against a run that is truly
tighter, in the tolerance's own units.

    estimate = max_i |y_i - y_tight,i| / (atol + rtol |y_tight,i|)        (the angles' differences wrapped)

is the error of the run as asked where the tighter run's own error is small beside it (Richardson's
argument with a step TIGHTEN x finer: e_asked - e_tight ~ e_asked).  A per-step rule cannot bound the
global error over an ill-conditioned transient (docs/benchmarks/tolerance.md, "Why cells miss"); a second
run compared at t_end measures it, and the promise becomes: the default engine's error at t_end is at most
`BOUND` tolerance units, or `adbgen simulate --check-tolerance` says it may not be.  It flags above BOUND / `SAFETY`
(2 units): the estimate ran up to 4-35x under the true error where its own row errs alike.

Which run is tighter: a run of a Taylor row of fixed order p and step factor f (the auto engine's rows,
`TaylorEngine.settings`) aims each step at `taylor.nominal_error(p, f)` in the weights whatever the rtol, its
steps depending on the tolerance only through atol / rtol.  Its run at rtol / 100 can be the same row, the
same steps and the same end state: an estimate of 0 whatever the error (the planted miss of the tests).  So
where the tighter run's aim is not at least `GAIN` x finer than the asked run's, the estimate runs its own
row (`reference_row`): Jorba & Zou's order for an aim TIGHTEN x finer (not below `AIM_FLOOR`, double
precision's reach) at step factor 1.  Engines whose step control scales with rtol (the Runge-Kutta and
multistep engines) use the tighter run as it is.

The conditioning probe (`probe_state`, `conditioning`): where round-off amplified by an ill-conditioned
transient dominates, the run as asked and the tighter run err alike and their difference under-reads (the
two silent misses of docs/benchmarks/tolerance.md: 22.8 units estimated 1.18, 46.7 estimated 1.34).  The
forward error of any computed solution is at least about the condition number of the flow map times the
size of the perturbations the computation makes (Higham, Accuracy and Stability of Numerical Algorithms,
2nd ed. 2002, sec. 1.6: forward error <~ condition number x backward error, and no smaller in general); the
very first of them, rounding y0 to double, is of relative size eps / 2 in each component.  So the same
tighter run started from y0 moved by `PROBE_ULPS` ulps of each component's weight scale, in alternating
directions, ends at t_end as far from the unperturbed tighter run as the transient amplifies a perturbation of
that size: `conditioning` = that distance in the asked tolerance's units, of the order of the least error any
double-precision run reaches there (each step's round-off adds to it; the probe's direction is not the worst
one).  It flags above the same BOUND / SAFETY as the estimate.
"""

from __future__ import annotations

import math

import numpy as np

from .results import SUCCESS

BOUND = 10.0  # the promise: the error at t_end at most this many tolerance units
SAFETY = 5.0  # the estimate flags above BOUND / SAFETY: measured, it ran 4-35x under the true error on
# held-out scenes where the estimate's own row errs alike (docs/benchmarks/tolerance.md, the promise restated)
GAIN = 10.0  # the tighter run counts as tighter when it aims each step at least this many times finer
AIM_FLOOR = 1e-16  # the finest per-step aim asked of the estimate's own row (double precision's reach)
PROBE_ULPS = 1.0  # the conditioning probe's start: y0 moved by this many ulps (eps = 2.2e-16) of each component's
# weight scale: twice the largest rounding of y0 (eps / 2), the least any double-precision run makes (every step
# makes more).  At 4 ulps, measured ad hoc, it read 3-19x over the true error (held-out scenes of
# docs/benchmarks/tolerance.md: no. 13 at rtol 1e-12, 432 against 22.8; no. 15 at 1e-6, 158 against 46.7; no. 29 at
# 1e-12, 10.9 against 1.15): so one.


def estimate_ratio(y, y_tight, rtol: float, atol: float, angles=()) -> float:
    """max_i |y_i - y_tight,i| / (atol + rtol |y_tight,i|), the weights of the engines' step control, with
    the differences of the states at `angles` (the model's self-described angles, `Model.angle_indices`)
    wrapped into [-pi, pi): two runs one turn apart on an angle end at the same configuration."""
    y, y_tight = np.asarray(y, float), np.asarray(y_tight, float)
    d = y - y_tight
    idx = list(angles)
    if idx:
        d[idx] = (d[idx] + math.pi) % (2 * math.pi) - math.pi
    return float(np.max(np.abs(d) / (atol + rtol * np.abs(y_tight))))


def step_aim(picked: dict | None) -> float | None:
    """The per-step aim of a run's Taylor row (`taylor.nominal_error` of its order and step factor; Jorba &
    Zou 2005, sec. 3.3); None for a run of another method (its step control scales with rtol)."""
    if not picked or "order" not in picked or "step_factor" not in picked:
        return None
    from .engines.taylor import nominal_error

    return nominal_error(int(picked["order"]), float(picked["step_factor"]))


def reference_row(asked: dict | None, tight: dict | None, tighten: float) -> tuple[int, float] | None:
    """(order, step factor) of the estimate's own run where the tighter run (`tight`, its `picked`) does not
    aim its steps `GAIN` x finer than the run as asked (`asked`); None where it does or where the run as
    asked is not a Taylor row.  The row: Jorba & Zou's order (`taylor.heyoka_order`) for an aim `tighten` x
    finer than the asked run's, not below `AIM_FLOOR`, nor below the asked order, at step factor 1."""
    a = step_aim(asked)
    if a is None:
        return None
    b = step_aim(tight)
    if b is not None and b <= a / GAIN:
        return None
    from .engines.taylor import MAX_ORDER, heyoka_order

    order = max(int(asked["order"]), heyoka_order(max(a / tighten, AIM_FLOOR)))
    return min(order, MAX_ORDER), 1.0


def reference_engine(row: tuple[int, float]):
    """The Taylor engine fixed at one (order, step factor) row: the estimate's own run."""
    from .engines.taylor import TaylorEngine

    order, factor = row
    return TaylorEngine(f"taylor-o{order}-f{factor:g}", "the error estimate's row", table=[(0.0, order, factor)])


def estimate(y, y_tight, rtol: float, atol: float, angles=(), *, against: str, row=None) -> dict:
    """The estimate's record (`ToleranceCheck.error_estimate`, --json): the ratio, the bound, whether it is
    exceeded, and what the run as asked was compared with ("tighter run", or the estimate's own row)."""
    value = estimate_ratio(y, y_tight, rtol, atol, angles)
    out = {"ratio": value, "bound": BOUND, "flag_above": BOUND / SAFETY,
           "exceeded": bool(not value <= BOUND / SAFETY), "against": against}
    if row is not None:
        out.update(order=row[0], step_factor=row[1])
    return out


def probe_state(y0, rtol: float, atol: float, ulps: float = PROBE_ULPS, *, symmetries=(), p=None) -> np.ndarray:
    """The conditioning probe's start: y0_i + s_i ulps eps (|y0_i| + atol / rtol), s_i = (-1)^i, i = 0, 1, ...

    ulps x eps relative where |y0_i| is above atol / rtol (the rounding of y0 to double, a few times over),
    and as many ulps of the weights' absolute scale atol / rtol where y0_i is 0 (a ball released at rest: its
    rounding is exact, but the first step's is not, and the probe must move every component).  The signs
    alternate so that no common scaling of the state (which a symmetric model could absorb) is all it probes;
    fixed, so the probe is deterministic.

    Except across identical balls started together (`symmetric_signs`): where y0 lies on the fixed set of an
    exchange of identical balls (`Model.symmetries`, kind "identical-balls": S y0 = y0 with p as S asks), the
    engines keep the balls together bit for bit (each ball's equation is the same code on the same numbers, so
    their round-off is the same), and no run leaves the set; a probe that did would measure how fast the balls
    part, not how far round-off carries this run (thesis n = 2 from rest: 6.6e7 units, a false alarm).  So the
    probe moves those balls alike."""
    y0 = np.asarray(y0, float)
    signs = symmetric_signs(np.where(np.arange(y0.size) % 2 == 0, 1.0, -1.0), y0, symmetries, p)
    return y0 + signs * ulps * np.finfo(float).eps * (np.abs(y0) + atol / rtol)


def symmetric_signs(signs: np.ndarray, y0: np.ndarray, symmetries=(), p=None) -> np.ndarray:
    """`signs` made invariant under every exchange of identical balls whose fixed set holds y0 (with p as the
    exchange asks): the components such an exchange maps onto each other (y[k] = signs[k] y[states[k]] on
    the set) take the sign of their class's first component, times the exchange's signs on the way; a component mapped onto
    its own negative gets 0 (the set fixes it at 0, and the probe must not leave the set)."""
    signs = np.array(signs, float)
    kept = [s for s in symmetries if s.get("kind") == "identical-balls" and _fixes(s, y0, p)]
    if not kept:
        return signs
    parent = list(range(y0.size))
    rel = [1.0] * y0.size  # component k = rel[k] x its parent's value on the fixed set

    def find(k):
        if parent[k] == k:
            return k, 1.0
        root, r = find(parent[k])
        parent[k], rel[k] = root, rel[k] * r
        return root, rel[k]

    zero = set()
    for s in kept:
        for k, (j, sign) in enumerate(zip(s["states"], s["signs"])):  # on the set: y[k] = sign y[j]
            (rk, ak), (rj, aj) = find(k), find(j)
            if rk != rj:  # the later root under the earlier: y[rk] = sign aj ak y[rj] (a's are +-1)
                lo, hi = min(rk, rj), max(rk, rj)
                parent[hi], rel[hi] = lo, sign * aj * ak
            elif ak != sign * aj:
                zero.add(rk)
    out = np.empty_like(signs)
    for k in range(y0.size):
        root, r = find(k)
        out[k] = 0.0 if root in zero else r * signs[root]
    return out


def _fixes(symmetry: dict, y0: np.ndarray, p) -> bool:
    """Whether y0 lies on the symmetry's fixed set, S y0 = y0 exactly, with the parameters as it asks."""
    states, signs = np.asarray(symmetry["states"]), np.asarray(symmetry["signs"], float)
    if p is None or len(states) != y0.size:
        return False
    p = np.asarray(p, float)
    params, psigns = np.asarray(symmetry["params"]), np.asarray(symmetry["param_signs"], float)
    return bool(np.array_equal(signs * y0[states], y0) and np.array_equal(psigns * p[params], p))


def conditioning(y_probe, y_ref, rtol: float, atol: float, angles=(), *, status: str = SUCCESS) -> dict:
    """The conditioning record (`error_estimate.conditioning`, --json): the probe's distance at t_end from the
    unperturbed tighter run in the asked tolerance's units (`estimate_ratio`), the ulps of its start
    (`probe_state`), its flag (above BOUND / SAFETY); ratio None where the probe's run failed (`status`),
    flagged: a run that fails from a start a few ulps away is not one to trust."""
    out = {"ulps": PROBE_ULPS, "flag_above": BOUND / SAFETY, "status": status}
    if status != SUCCESS:
        return {**out, "ratio": None, "exceeded": None}
    value = estimate_ratio(y_probe, y_ref, rtol, atol, angles)
    return {**out, "ratio": value, "exceeded": bool(not value <= BOUND / SAFETY)}


def with_conditioning(record: dict, cond: dict) -> dict:
    """The estimate's record with the probe beside it (key `conditioning`) and `exceeded` made the OR of both:
    True where either is above its flag, None (flagged, not known) where the probe was not made and the
    estimate is within its flag; `estimate_exceeded` keeps the estimate's own verdict."""
    est = record["exceeded"]
    both = True if est or cond["exceeded"] else (None if cond["exceeded"] is None or est is None else False)
    return {**record, "estimate_exceeded": est, "exceeded": both, "conditioning": cond}


def finer(asked: dict | None, row: tuple[int, float]) -> bool:
    """Whether `row` aims its steps at least `GAIN` x finer than the run as asked (`step_aim`)."""
    a = step_aim(asked)
    return a is None or step_aim({"order": row[0], "step_factor": row[1]}) <= a / GAIN


def not_made(against: str, row, why: str) -> dict:
    """The record of an estimate that could not be made (ratio None: the check flags it, `reason`)."""
    out = {"ratio": None, "bound": BOUND, "exceeded": None, "against": against, "status": why}
    if row is not None:
        out.update(order=row[0], step_factor=row[1])
    return out


def reason(record: dict) -> str:
    """The disagreement naming the estimate: 'error estimate: 37.2 tolerance units at t_end against the
    tighter run (bound 10)', or that it could not be made (the estimate's own run failed), or, where the
    estimate is within its flag but the conditioning probe is not, the probe's distance."""
    cond = record.get("conditioning")
    if cond is not None and record.get("estimate_exceeded") is False:
        if cond["ratio"] is None:
            return (f"error estimate: the conditioning probe (the tighter run from y0 moved {cond['ulps']:g} ulps) "
                    f"ended {cond['status']}, so the error at t_end is not known to be within "
                    f"{record['bound']:g} tolerance units")
        return (f"error estimate: the conditioning probe (the tighter run from y0 moved {cond['ulps']:g} ulps) ends "
                f"{cond['ratio']:.3g} tolerance units away at t_end (flagged above {cond['flag_above']:g}): the "
                f"transient amplifies round-off beyond what double precision resolves at this tolerance, where "
                f"the estimate ({record['ratio']:.3g}) under-reads")
    if record.get("ratio") is None:
        return (f"error estimate: not made ({record.get('status')}), so the error at t_end is not known to be "
                f"within {record['bound']:g} tolerance units")
    return (f"error estimate: {record['ratio']:.3g} tolerance units at t_end against the {record['against']} "
            f"(flagged above {record.get('flag_above', record['bound']):g}: the bound {record['bound']:g} over the "
            f"estimate's safety factor)")


__all__ = ["AIM_FLOOR", "BOUND", "GAIN", "PROBE_ULPS", "SAFETY", "conditioning", "estimate", "estimate_ratio", "finer",
           "not_made", "probe_state", "reason", "reference_engine", "reference_row", "step_aim", "symmetric_signs",
           "with_conditioning"]
