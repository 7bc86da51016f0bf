"""Stability charts in two parameters: where the followed solution (a steady state, or a forced model's
periodic response) is stable, and the curves of bifurcations that bound it (e.g. an imbalance against the speed with the
balls' mass tied to the imbalance, on a log scale).

    chart = compute(model, pmap, start, (lo1, hi1), (lo2, hi2), log2=True)
    chart.to_json(); plot(chart, "chart.png")

1. A grid: rows of lambda_2 (log-spaced if log2), each marched along lambda_1 by Newton from its
   neighbour (steady state, or orbit by shooting), the stability of every grid point (the transverse
   spectrum; the multipliers).
2. Seeds: wherever stability changes between neighbours of a row, the kind of the change is read off the
   two spectra (a complex pair: hopf / torus; a real eigenvalue: fold; a real multiplier through -1:
   period-doubling, through +1: fold of cycles) and the point is located on the row (Brent's method on
   that kind's critical quantity).
3. Curves: each seed not already on a curve of its kind is continued both ways by the generic continuer
   on the kind's defining system (`boundary`, `hopf`, `torus`, `period_doubling`, `fold_cycle`), to the
   chart's edges, with the kind's codimension-two points.

The curves go through every row they cross and beyond, so a boundary missed between two grid columns on
one row is found from another; a closed curve lying between two rows would be missed (the rows' spacing
is the resolution in lambda_2, reported).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from .. import steady
from ..figure_style import title_lines
from ..loading import AnalysisError, Model
from . import continuer
from .boundary import FoldCurve, OrbitFollower, follower_for
from .fold_cycle import FoldCycleCurve
from .hopf import HopfCurve
from .parameters import ParameterMap
from .period_doubling import PeriodDoublingCurve
from .torus import TorusCurve

# the curve of each kind of stability change (one place: a new kind is a module and a line here)
CURVES = {"hopf": HopfCurve, "fold": FoldCurve, "torus": TorusCurve, "period-doubling": PeriodDoublingCurve,
          "fold of cycles": FoldCycleCurve}

UNIT_TOL = 1e-7
REFINE = 8  # the certified resolution's default: the grid's spacing / REFINE, in each parameter


@dataclass
class Curve:
    kind: str
    points: list  # (lambda_1, lambda_2)
    special: list
    end: str
    seed: tuple


@dataclass
class Chart:
    model: Model
    names: tuple[str, str]
    log2: bool
    lam1: np.ndarray
    lam2: np.ndarray
    stable: np.ndarray  # rows x columns: 1 stable, 0 unstable, -1 not computed (why: not_computed), -2 does not exist
    curves: list[Curve]
    seeds: list[dict]
    ties: list[str]
    wall_s: float = 0.0
    extra: dict = field(default_factory=dict)
    lines: dict = field(default_factory=dict)  # grid(): the certified rows and columns, the failures' reasons
    certify: "Certify | None" = None
    rejected: list = field(default_factory=list)  # sign changes that are no change (the same count both sides)

    def windows(self, axis: str = "rows") -> dict:
        """{row (column) index: the stable windows [a, b] found along it}."""
        return {k: line.windows for k, line in self.lines.get(axis, {}).items()}

    def _resolution(self) -> dict:
        n1, n2 = self.names
        out = {n1: float(np.max(np.diff(self.lam1))), n2: float(np.max(np.diff(
            np.log10(self.lam2) if self.log2 else self.lam2))), "scale2": "log10" if self.log2 else "linear"}
        c = self.certify
        if c is None:
            return out
        rows, cols = self.lines.get("rows", {}), self.lines.get("columns", {})
        out["certified"] = {
            n1: c.res1 if c.refine else None, n2: c.res2 if c.refine else None, "refined": c.refine,
            "statement": (f"every stable window wider than {c.res1:.3g} in {n1} along each grid row, and wider than "
                          f"{c.res2:.3g} in {'log10 ' if self.log2 else ''}{n2} along each grid column, holds a "
                          "sample: refined where stability changes between neighbours, where the stability margin "
                          "(leading real part, or leading |multiplier| - 1) heads for zero, and at its extrema near "
                          "zero (assumed: the margin turns at most once between samples the rules leave apart); "
                          "every change reported is seen to cross (a sample on each side)" if c.refine else
                          "not certified: the grid alone (refinement off); a window between grid points is missed"),
            "samples_added": int(sum(line.inserted for line in rows.values()) + sum(
                line.inserted for line in cols.values()))}
        return out

    def to_json(self, timing: bool = True) -> dict:
        """The chart as data; `timing=False` leaves out the wall time, for documents that must come out
        byte-identical from run to run (docs/reproduction.md's figures)."""
        n1, n2 = self.names
        return {"model": self.model.name, "parameter": n1, "parameter2": n2, "ties": list(self.ties),
                "log2": self.log2,
                "grid": {n1: self.lam1.tolist(), n2: self.lam2.tolist(), "stable": self.stable.astype(int).tolist()},
                "curves": [{"kind": c.kind, "points": [[float(a), float(b)] for a, b in c.points], "special": c.special,
                            "end": c.end, "seed": {n1: c.seed[0], n2: c.seed[1]}} for c in self.curves],
                "special": [s | {"curve": i} for i, c in enumerate(self.curves) for s in c.special],
                "resolution": self._resolution(),
                "windows": {"rows": [{n2: float(self.lam2[i]), "stable": [list(w) for w in ws]}
                                     for i, ws in sorted(self.windows("rows").items())],
                            "columns": [{n1: float(self.lam1[j]), "stable": [[float(10.0 ** a if self.log2 else a),
                                                                               float(10.0 ** b if self.log2 else b)]
                                                                              for a, b in ws]}
                                        for j, ws in sorted(self.windows("columns").items())]},
                "not_computed": [{"row": i, "column": j, n1: float(self.lam1[j]), n2: float(self.lam2[i]), "why": why}
                                 for (i, j), why in sorted(self.lines.get("reasons", {}).items())],
                "rejected_changes": self.rejected,
                } | ({"wall_s": self.wall_s} if timing else {})


# ---------------------------------------------------------------------------------------- the grid

def chart_start(model: Model, pmap: ParameterMap, lam):
    """The followed solution at the chart's start pmap(lam): an autonomous model's START carried along the ties
    (a state); a forced model's first labelled steady state that exists there (a constant solution, e.g. the
    balanced state with the rotor at rest), refined as its periodic response by shooting (a PeriodicOrbit)."""
    from .equilibrium import carried_start
    from .orbit import refine

    p = pmap(lam)
    if model.autonomous:
        return carried_start(model, p, pmap)
    for label in model.steady_states:
        y = model.steady_state(label, p)
        if y is not None:
            return refine(model, p, np.asarray(y, float), None)
    raise AnalysisError(f"{model.name}: no labelled steady state exists at the chart's start to begin from")


def _unstable(spectrum: np.ndarray, orbit: bool) -> int:
    if orbit:
        return int(np.sum(np.abs(spectrum) > 1.0 + UNIT_TOL))
    return steady.classify(spectrum)[1]


def _ordered(ev: np.ndarray, orbit: bool) -> np.ndarray:
    """Real parts (multipliers: moduli - 1), largest first: the (m+1)-th changes sign where the number of
    unstable ones goes from m to more."""
    ev = np.asarray(ev, complex)
    return np.sort(np.abs(ev) - 1.0 if orbit else ev.real)[::-1]


def _critical(ev: np.ndarray, orbit: bool, m: int) -> complex:
    """The eigenvalue (multiplier) at the (m+1)-th place of `_ordered`; of a complex pair, the member with
    the positive imaginary part (the one the curves track).  The two members of a pair tie in the key, and
    which of them a sort puts first depends on the sort's implementation (numpy's SIMD sorts, switched
    off in `adbgen reproduce`'s pinned environment, break the tie the other way): the conjugate of the
    tracked member made the curves follow another eigenvalue, and no curve was found there."""
    ev = np.asarray(ev, complex)
    key = np.abs(ev) - 1.0 if orbit else ev.real
    z = complex(ev[np.argsort(key, kind="stable")[::-1][m]])
    return complex(z.real, abs(z.imag))


def _kind_of(z: complex, orbit: bool) -> str:
    """The kind of stability change a critical eigenvalue (multiplier) z makes."""
    cx = abs(z.imag) > 1e-9 * (1 + abs(z))
    if not orbit:
        return "hopf" if cx else "fold"
    return "torus" if cx else ("period-doubling" if z.real < 0 else "fold of cycles")


JUMP = 0.2  # a solution that moved this much (max norm, angles wrapped) between neighbours is re-found in halves


def _moved(a, b) -> float:
    if isinstance(a, tuple):  # an orbit: (arcs, period)
        a, b = a[0].ravel(), b[0].ravel()
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.max(np.abs(np.remainder(d + math.pi, 2 * math.pi) - math.pi)))


def _step(follower, pmap, lam_from, lam_to, depth: int = 0):
    """The solution at lam_to from the follower's (at lam_from): re-found in halves where it would jump (Newton
    landing on another solution), up to 5 halvings."""
    prev = follower.last
    state, ev = follower.solve(pmap(lam_to))
    if depth < 5 and _moved(state, prev) > JUMP:
        mid = tuple(0.5 * (np.asarray(lam_from) + np.asarray(lam_to)))
        follower.accept(prev)
        s_mid, _ = _step(follower, pmap, lam_from, mid, depth + 1)
        follower.accept(s_mid)
        state, ev = _step(follower, pmap, mid, lam_to, depth + 1)
    return state, ev


def _row(follower, pmap, lam1, lam2, j0, state0, retry=None, reasons=None):
    """March one row from column j0 (where `state0` is the solution) to both ends; (spectra, states).  A column
    where the solution is not re-found is retried from the followed state's closed form (`retry(p)`: a state
    guess, or None where the closed form says the state does not exist); `reasons[j]` says why a column has
    no solution ("does not exist: ..." or "not computed: ..."); the march goes on from the last solution found
    (three failures in a row end it: the rest of the row is "not computed")."""
    n = len(lam1)
    spectra, states = [None] * n, [None] * n
    reasons = {} if reasons is None else reasons
    for direction in (1, -1):
        follower.accept(state0)
        j = j0 if direction == 1 else j0 - 1
        prev, misses = lam1[j0], 0
        while 0 <= j < n:
            try:
                state, ev = _step(follower, pmap, (prev, lam2), (lam1[j], lam2))
            except (AnalysisError, ArithmeticError) as exc:
                state, ev, why = _retry(follower, pmap, (lam1[j], lam2), retry, exc)
                if state is None:
                    reasons[j] = why
                    misses += 1
                    if misses >= 3:
                        for k in range(j + direction, n if direction == 1 else -1, direction):
                            reasons.setdefault(k, "not computed: the row's march stopped after three failures")
                        break
                    j += direction
                    continue
            misses = 0
            follower.accept(state)
            spectra[j], states[j] = ev, state
            prev = lam1[j]
            j += direction
    return spectra, states


def _retry(follower, pmap, lam, retry, exc):
    """(state, spectrum, None) re-found from the closed form at lam, or (None, None, why)."""
    why = f"not computed: Newton failed ({type(exc).__name__}: {str(exc)[:80]})"
    if retry is None:
        return None, None, why + "; no closed form of the followed state to retry from"
    try:
        guess = retry(pmap(lam))
    except (AnalysisError, ArithmeticError, ValueError) as exc2:
        return None, None, why + f"; the closed form failed too ({type(exc2).__name__})"
    if guess is None:
        return None, None, "does not exist: the followed state's closed form has no solution here"
    last = follower.last
    try:
        state, ev = follower.solve(pmap(lam), guess)
        return state, ev, None
    except (AnalysisError, ArithmeticError) as exc2:
        follower.accept(last)
        return None, None, why + f"; from the closed form too ({type(exc2).__name__})"


def closed_form_retry(model: Model, start, p0, orbit: bool):
    """retry(p) for `_row`: the closed-form steady state (of the module's STEADY_STATES) that the chart's start
    is, at p (None where it does not exist); None when the start is none of them (no closed form to retry
    from).  An orbit's start is matched through its first arc's point, and the guess is the constant state
    as a degenerate orbit (a forced model's balanced response is a constant solution)."""
    from ..identify import identify

    label = identify(model, start.arcs[0] if orbit else start, p0).label
    if label is None:
        return None

    def retry(p):
        y = model.steady_state(label, p)
        if y is None or not orbit:
            return y
        X = np.tile(np.asarray(y, float), (len(start.arcs), 1))
        return X, float(start.period)
    retry.label = label
    return retry


def grid(model, pmap: ParameterMap, start, lam1: np.ndarray, lam2: np.ndarray, lam1_0: float, lam2_0: float,
         threads: int = 2, certify: "Certify | None" = None):
    """The stability of the followed solution on the grid: the start carried to the column nearest lam1_0 on
    its own row, then row to row along that column, then every row marched from there both ways (rows on
    `threads` threads: the compiled integrations release the GIL).  With `certify`, every row and every column
    is refined between its grid points (`windows.certify`) to the stated resolution.

    Returns (rows {i: (spectra, states)}, stable, orbit, lines): `stable` 1 stable, 0 unstable, -1 not computed
    (the reason in lines["reasons"]), -2 does not exist (the closed form says so); `lines` the certified rows
    and columns ({"rows": {i: Line}, "columns": {j: Line}, "reasons": {(i, j): why}})."""
    from concurrent.futures import ThreadPoolExecutor

    follower = follower_for(model, start)
    orbit = isinstance(follower, OrbitFollower)
    state = (start.arcs, start.period) if orbit else np.asarray(start, float)
    j0 = int(np.argmin(np.abs(lam1 - lam1_0)))
    i0 = int(np.argmin(np.abs(lam2 - lam2_0)))
    p_start = pmap((lam1_0, lam2_0))
    retry = closed_form_retry(model, start, p_start, orbit)
    follower.accept(state)
    state, _ = follower.solve(pmap((lam1[j0], lam2_0)))
    column, reasons = {}, {}
    for order in (range(i0, len(lam2)), range(i0 - 1, -1, -1)):
        follower.accept(state)
        for i in order:
            try:
                s, _ = follower.solve(pmap((lam1[j0], lam2[i])))
            except (AnalysisError, ArithmeticError) as exc:
                s, _, why = _retry(follower, pmap, (lam1[j0], lam2[i]), retry, exc)
                if s is None:
                    reasons[(i, j0)] = why
                    continue
            follower.accept(s)
            column[i] = s

    def row(i):
        f = follower_for(model, start)
        r = {}
        out = _row(f, pmap, lam1, lam2[i], j0, column[i], retry, r)
        line = None
        if certify is not None:
            line = certify.line(f, pmap, lam1, lambda x, i=i: (x, lam2[i]), out, orbit, certify.res1)
        return i, out, r, line
    with ThreadPoolExecutor(max_workers=max(1, threads)) as pool:
        done = list(pool.map(row, sorted(column)))
    rows = {i: out for i, out, _, _ in done}
    lines = {"rows": {i: line for i, _, _, line in done if line is not None}, "columns": {}, "reasons": reasons}
    for i, _, r, _ in done:
        for j, why in r.items():
            reasons[(i, j)] = why
    for i in range(len(lam2)):
        if i not in column:
            for j in range(len(lam1)):
                reasons.setdefault((i, j), "not computed: the row's start on the starting column was not found")
    stable = np.full((len(lam2), len(lam1)), -1, dtype=int)
    for i, (spectra, _) in rows.items():
        for j, ev in enumerate(spectra):
            if ev is not None:
                stable[i, j] = int(_unstable(ev, orbit) == 0)
    for (i, j), why in reasons.items():
        if stable[i, j] == -1 and why.startswith("does not exist"):
            stable[i, j] = -2
    if certify is not None:
        x2 = np.log10(lam2) if certify.log2 else np.asarray(lam2, float)

        def col(j):
            f = follower_for(model, start)
            spectra = [rows[i][0][j] if i in rows else None for i in range(len(lam2))]
            states = [rows[i][1][j] if i in rows else None for i in range(len(lam2))]
            line = certify.line(f, pmap, x2, lambda x: (lam1[j], float(10.0 ** x if certify.log2 else x)),
                                (spectra, states), orbit, certify.res2)
            return j, line
        with ThreadPoolExecutor(max_workers=max(1, threads)) as pool:
            lines["columns"] = dict(pool.map(col, range(len(lam1))))
    return rows, stable, orbit, lines


@dataclass
class Certify:
    """What a chart certifies: every stable window wider than res1 along a row (in lambda_1) and wider than res2
    along a column (in lambda_2, log10 when log2) holds a sample (`windows.certify`: refinement where stability
    changes between neighbours, where a margin heads for zero, and at its extrema near zero; every reported
    change checked on both sides).  refine=False: the grid alone (the uncertified chart, a negative control)."""

    res1: float
    res2: float
    log2: bool
    refine: bool = True

    def line(self, follower, pmap, xs, lam_of, row, orbit: bool, resolution: float):
        from ..windows import Sample, SolveFailed, certify, margin_of

        spectra, states = row

        def sample(x, ev, state):
            return Sample(float(x), margin_of(ev, orbit), _unstable(ev, orbit), state, ev)

        def solve(x, near):
            follower.accept(near.state)
            try:
                state, ev = _step(follower, pmap, lam_of(near.x), lam_of(x))
            except (AnalysisError, ArithmeticError) as exc:
                raise SolveFailed(f"{type(exc).__name__}: {str(exc)[:80]}") from None
            return sample(x, ev, state)
        samples = [sample(x, ev, st) if ev is not None else None for x, ev, st in zip(xs, spectra, states)]
        return certify(samples, solve, resolution, refine=self.refine)


# --------------------------------------------------------------------------------------- curves

def _on_curve(curve: Curve, x, log2: bool, tol: float) -> bool:
    pts = np.array(curve.points)
    if not len(pts):
        return False
    if log2:
        pts = np.column_stack([pts[:, 0], np.log10(pts[:, 1])])
        x = (x[0], math.log10(x[1]))
    d = np.hypot(pts[:, 0] - x[0], pts[:, 1] - x[1])
    return bool(d.min() <= tol)


def compute(model: Model, pmap: ParameterMap, start, range1, range2, log2: bool = False, n1: int = 81, n2: int = 25,
            kinds=None, max_points: int = 400, lam1_0: float | None = None, lam2_0: float | None = None,
            resolution1: float | None = None, resolution2: float | None = None, refine: bool = True) -> Chart:
    """The chart (see the module's docstring).  resolution1, resolution2: the widths of stable window it
    certifies along lambda_1 and along lambda_2 (log10 with log2); default the grid's spacing / REFINE.
    refine=False: the grid alone (uncertified)."""
    t0 = time.perf_counter()
    lo1, hi1 = range1
    lo2, hi2 = range2
    if log2 and not lo2 > 0:
        raise AnalysisError("a log scale needs the second parameter's range above 0")
    lam1 = np.linspace(lo1, hi1, n1)
    lam2 = np.logspace(math.log10(lo2), math.log10(hi2), n2) if log2 else np.linspace(lo2, hi2, n2)
    lam1_0 = float(pmap.base[pmap.index[0]]) if lam1_0 is None else lam1_0
    lam2_0 = float(pmap.base[pmap.index[1]]) if lam2_0 is None else lam2_0
    span1 = hi1 - lo1
    span2 = (math.log10(hi2) - math.log10(lo2)) if log2 else (hi2 - lo2)
    cert = Certify(span1 / (n1 - 1) / REFINE if resolution1 is None else resolution1,
                   span2 / max(n2 - 1, 1) / REFINE if resolution2 is None else resolution2, log2, refine)
    rows, stable, orbit, lines = grid(model, pmap, start, lam1, lam2, lam1_0, lam2_0, certify=cert)
    x2_of = (lambda i: math.log10(lam2[i])) if log2 else (lambda i: float(lam2[i]))
    seeds, rejected = [], []
    # changes of stability: located and checked on both sides by the certified rows and columns
    for i, line in sorted(lines["rows"].items()):
        seeds += [{"x": np.array([c.x, x2_of(i)]), "state": c.state, "m": 0} for c in line.changes if c.bracket is None]
        rejected += [r | {"row": i} for r in line.rejected]
    for j, line in sorted(lines["columns"].items()):
        seeds += [{"x": np.array([lam1[j], c.x]), "state": c.state, "m": 0} for c in line.changes if c.bracket is None]
        rejected += [r | {"column": j} for r in line.rejected]
    # changes in the number of unstable eigenvalues of an unstable state (the further curves the paper draws),
    # between grid neighbours along the rows and along the columns
    for i, (spectra, states) in sorted(rows.items()):
        for j in range(n1 - 1):
            a, b = spectra[j], spectra[j + 1]
            if a is None or b is None or _unstable(a, orbit) == _unstable(b, orbit) or min(
                    _unstable(a, orbit), _unstable(b, orbit)) == 0:
                continue
            seeds.append({"row": i, "col": j, "state": states[j], "along": 0,
                          "m": min(_unstable(a, orbit), _unstable(b, orbit))})
    for i in sorted(rows):
        if i + 1 not in rows:
            continue
        for j in range(n1):
            a, b = rows[i][0][j], rows[i + 1][0][j]
            if a is None or b is None or _unstable(a, orbit) == _unstable(b, orbit) or min(
                    _unstable(a, orbit), _unstable(b, orbit)) == 0:
                continue
            seeds.append({"row": i, "col": j, "state": rows[i][1][j], "along": 1,
                          "m": min(_unstable(a, orbit), _unstable(b, orbit))})
    ds_max = max(span1, span2) / 80
    curves: list[Curve] = []
    located = []
    lam_of = (lambda x: (float(x[0]), float(10.0 ** x[1] if log2 else x[1])))
    for sd in seeds:
        follower = follower_for(model, start)
        follower.accept(sd["state"])
        m_ = sd["m"]

        def g(x):  # the (m+1)-th eigenvalue's real part (multiplier's modulus - 1): it changes sign there
            _, ev = follower.solve(pmap(lam_of(x)))
            return _ordered(ev, orbit)[m_]
        try:
            if "x" in sd:  # located by the certified line
                x_seed = sd["x"]
            else:
                x2 = x2_of(sd["row"])
                if sd["along"] == 0:  # along the row
                    ends = (np.array([lam1[sd["col"]], x2]), np.array([lam1[sd["col"] + 1], x2]))
                else:  # along the column
                    ends = (np.array([lam1[sd["col"]], x2]), np.array([lam1[sd["col"]], x2_of(sd["row"] + 1)]))
                d = ends[1] - ends[0]
                t = brentq(lambda t: g(ends[0] + t * d), 0.0, 1.0, xtol=1e-12)
                x_seed = ends[0] + t * d
                # seen to cross: the count differs on the two sides (a twentieth of the way to the grid points)
                sides = [_unstable(follower.solve(pmap(lam_of(ends[0] + u * d)))[1], orbit)
                         for u in (t - 0.05 * t, t + 0.05 * (1 - t))]
                if sides[0] == sides[1]:
                    rejected.append({"x": lam_of(x_seed), "unstable": sides, "why": "no change across the root"})
                    continue
            _, ev = follower.solve(pmap(lam_of(x_seed)))
        except (AnalysisError, ArithmeticError, ValueError):
            continue
        z = _critical(ev, orbit, m_)
        kind = _kind_of(z, orbit)
        if kinds is not None and kind not in kinds:
            continue
        cls = CURVES[kind]
        cv = cls(model, pmap, follower, log2=log2, range2=(lo2, hi2))
        cv.crit = z
        seed = cv.lam(x_seed)
        located.append({"kind": kind, pmap.free[0]: seed[0], pmap.free[1]: seed[1]})
        if any(c.kind == kind and _on_curve(c, seed, log2, 3 * ds_max) for c in curves):
            continue
        halves, specials, ends = [], [], []
        state_seed = cv._solve(x_seed)[0]
        _, grad = cv.evaluate(x_seed)
        along = np.array([-grad[0, 1], grad[0, 0]])  # the curve's direction: normal to the gradient of g
        for direction in (1.0, -1.0):
            cv = cls(model, pmap, follower_for(model, start), log2=log2, range2=(lo2, hi2))
            cv.follower.accept(state_seed)
            cv.crit = z
            settings = continuer.Settings(ds=ds_max / 4, ds_max=ds_max, ds_min=1e-6 * ds_max, max_points=max_points,
                                          bounds=(lo1, hi1), newton_tol=1e-10, fold_test=False)
            try:
                br = continuer.run(cv, x_seed, direction * along, settings)
            except AnalysisError as exc:
                ends.append(f"failed: {exc}")
                continue
            halves.append([cv.lam(pt.x) for pt in br.points])
            ends.append(br.end)
            for sp in br.specials:
                l1v, l2v = cv.lam(sp.x)
                specials.append({"type": sp.info["kind"], pmap.free[0]: l1v, pmap.free[1]: l2v,
                                 **{k: v for k, v in sp.info.items() if k != "kind"}})
        if not halves:
            continue
        pts = (list(reversed(halves[1])) + halves[0][1:]) if len(halves) == 2 else halves[0]
        curves.append(Curve(kind, pts, specials, "; ".join(ends), seed))
    chart = Chart(model, tuple(pmap.free), log2, lam1, lam2, stable, curves, located, list(pmap.tie_text))
    chart.lines, chart.certify, chart.rejected = lines, cert, rejected
    chart.wall_s = time.perf_counter() - t0
    return chart


# ------------------------------------------------------------------------------------------ output

STYLE = {"hopf": ("C3", "-"), "fold": ("C0", "--"), "torus": ("C1", "-"), "period-doubling": ("C2", "-."),
         "fold of cycles": ("C4", ":")}


def _half_cells(values: np.ndarray, log: bool) -> np.ndarray:
    """The cell edges half way between grid values (geometrically on a log axis)."""
    v = np.log10(values) if log else np.asarray(values, float)
    edges = np.r_[v[0], 0.5 * (v[1:] + v[:-1]), v[-1]]
    return 10.0 ** edges if log else edges


def _draw_windows(ax, chart: Chart, scale2: float) -> None:
    """The stable windows the certified rows and columns found, shaded like the grid's stable region: each row's
    windows as bands half way to the neighbouring rows, each column's likewise (a window narrower than the grid's
    spacing shows, bounded by the curves continued from its ends)."""
    from matplotlib.patches import Rectangle

    e2 = _half_cells(chart.lam2, chart.log2) * scale2
    e1 = _half_cells(chart.lam1, False)
    cell = float(np.max(np.diff(chart.lam1))) if len(chart.lam1) > 1 else 0.0
    for i, ws in chart.windows("rows").items():
        for a, b in ws:
            ax.add_patch(Rectangle((a, e2[i]), max(b - a, 0.0), e2[i + 1] - e2[i], color="0.8", lw=0, zorder=0.5))
            if b - a < cell:  # narrower than the grid: outlined, or it would not show at the figure's scale
                ax.add_patch(Rectangle((a, e2[i]), max(b - a, 0.0), e2[i + 1] - e2[i], fill=False, ec="k", lw=1.2,
                                       zorder=2.5))
    for j, ws in chart.windows("columns").items():
        for a, b in ws:
            lo, hi = (10.0 ** a, 10.0 ** b) if chart.log2 else (a, b)
            ax.add_patch(Rectangle((e1[j], lo * scale2), e1[j + 1] - e1[j], (hi - lo) * scale2, color="0.8", lw=0,
                                   zorder=0.5))


def _draw_missing(ax, chart: Chart, scale2: float) -> None:
    """Grid points without a solution: "not computed" (a failure, hatched red) apart from "does not exist" (the
    closed form says so, blue dots); neither is drawn as stable or unstable."""
    for code, mk, color, label in ((-1, "x", "C3", "not computed (failed)"), (-2, ".", "C0", "does not exist")):
        i, j = np.nonzero(chart.stable == code)
        if len(i):
            ax.plot(chart.lam1[j], chart.lam2[i] * scale2, mk, color=color, ms=4, ls="none", label=label, zorder=3)


FIGSIZE, TITLE_FONTSIZE = (7, 4.5), 8


def default_title(name: str, ties: list[str]) -> str:
    """The chart's title: the model, then its ties between words on the lines below (the ties of the paper's
    Fig. 14(a) on one line were clipped at both edges of the figure)."""
    return title_lines(f"{name}: stable region shaded", f"tied: {', '.join(ties)}" if ties else "")


def plot(chart: Chart, path: Path, title: str | None = None, scale2: float = 1.0, label2: str | None = None,
         timing: bool = True) -> None:
    """The chart as the paper draws it: stable region shaded, curves by kind, lambda_2 on a log axis if asked;
    the curves also written as data (<path>.json beside the figure; its wall time only with `timing`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n1, n2 = chart.names
    fig, ax = plt.subplots(figsize=FIGSIZE, constrained_layout=True)
    S = np.where(chart.stable < 0, np.nan, chart.stable.astype(float))
    ax.contourf(chart.lam1, chart.lam2 * scale2, S, levels=[0.5, 1.5], colors=["0.8"])
    _draw_windows(ax, chart, scale2)
    _draw_missing(ax, chart, scale2)
    seen = set()
    for c in chart.curves:
        color, ls = STYLE.get(c.kind, ("k", "-"))
        pts = np.array(c.points)
        ax.plot(pts[:, 0], pts[:, 1] * scale2, ls, color=color, lw=1.3, label=None if c.kind in seen else c.kind)
        seen.add(c.kind)
        for s in c.special:
            ax.plot(s[n1], s[n2] * scale2, "o", color=color, ms=4)
    if chart.log2:
        ax.set_yscale("log")
    ax.set_xlim(chart.lam1[0], chart.lam1[-1])
    ax.set_ylim(chart.lam2[0] * scale2, chart.lam2[-1] * scale2)
    ax.set_xlabel(n1)
    ax.set_ylabel(label2 or n2)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(title or default_title(chart.model.name, chart.ties), fontsize=TITLE_FONTSIZE)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name("." + path.name + ".tmp")
    fig.savefig(tmp, dpi=130, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    import json

    data = path.with_suffix(".json")
    tmpd = data.with_name("." + data.name + ".tmp")
    tmpd.write_text(json.dumps(chart.to_json(timing)))
    os.replace(tmp, path)
    os.replace(tmpd, data)
