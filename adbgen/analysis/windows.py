"""Stable windows along a line of samples, certified to a stated resolution (issue 34 item 3).

    line = certify(samples, solve, resolution)      samples: Sample or None (not computed) at ascending x
    line.windows        stable intervals [a, b] (ends located where the margin crosses zero)
    line.changes        stability changes, each seen to cross: stable on one side, unstable on the other
    line.rejected       sign changes of the margin that are not a change of stability (unstable on both sides)

A sample carries its stability margin: the leading real part of the (transverse) spectrum of a steady state,
or the leading Floquet multiplier's modulus minus one of an orbit; the state is stable where the margin is
negative (`unstable == 0`).  Between two neighbouring samples a and b (b - a longer than `resolution`) a
sample is inserted, recursively, wherever

* their stability differs (the change is then located by Brent's method on the margin, and checked on both
  sides: a sample each side of the root, SIDE of the way to a and to b, must be stable on one side and unstable on the
  other; otherwise it is rejected, not reported);
* the margin, extrapolated from a neighbour's slope, heads for zero and could cover at least `approach` of
  its distance inside the interval (the rule the one-parameter scans step by:
  `orbits.continuer`);
* the parabola through three consecutive samples has its vertex inside the interval with its value across
  zero, or within `near` of the samples' spread from zero (an extremum near the boundary).

What is certified: a stable window wider than `resolution` holds a sample, provided the margin does not turn
twice inside an interval the rules left unsplit (a margin that is locally linear or parabolic between
samples); windows narrower than that may be seen (`windows` lists them too) but are not certified.
`refine=False` keeps the samples as given (the uncertified grid: the negative control).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.optimize import brentq

APPROACH = 0.5
NEAR = 0.1
SIDE = 0.05  # the both-sides check's distance from a located change, as a fraction of the way to the samples


@dataclass
class Sample:
    x: float
    margin: float  # < 0: stable
    unstable: int  # eigenvalues (multipliers) on the unstable side
    state: object = None
    spectrum: np.ndarray | None = None

    @property
    def stable(self) -> bool:
        return self.unstable == 0


@dataclass
class Change:
    x: float
    stable_below: bool  # the side of smaller x
    unstable: tuple[int, int]  # counts just below and just above x
    state: object = None
    spectrum: np.ndarray | None = None
    bracket: tuple[float, float] | None = None  # set where the root could not be located: the interval it lies in


@dataclass
class Line:
    samples: list[Sample]
    changes: list[Change]
    windows: list[tuple[float, float]]
    rejected: list[dict] = field(default_factory=list)
    failures: list[tuple[float, str]] = field(default_factory=list)  # (x, why) where a solve failed
    resolution: float = 0.0
    inserted: int = 0


class SolveFailed(Exception):
    """The solution could not be found at x (the reason in the message)."""


def _split_needed(xs, ms, i, floor: float, approach: float, near: float) -> float | None:
    """Where to split the interval (i, i+1) of the line (xs, ms), or None: the rules of the module's docstring."""
    a, b = xs[i], xs[i + 1]
    L = b - a
    if L <= floor:
        return None
    va, vb = ms[i], ms[i + 1]
    if (va < 0) != (vb < 0):
        return None  # a change: located, not split
    where = None
    # the approach rule from each end, the slope from the neighbour on the far side
    if i > 0:
        slope = (va - ms[i - 1]) / (a - xs[i - 1])
        if slope * va < 0 and L > approach * abs(va) / abs(slope):
            where = a + max(approach * abs(va) / abs(slope), floor)
    if i + 2 < len(xs):
        slope = (ms[i + 2] - vb) / (xs[i + 2] - b)
        if slope * vb > 0 and L > approach * abs(vb) / abs(slope):
            w = b - max(approach * abs(vb) / abs(slope), floor)
            where = w if where is None else 0.5 * (where + w)
    # an extremum inside the interval near zero (the parabolas through each three consecutive samples)
    for k in (i - 1, i):
        if k < 0 or k + 2 >= len(xs):
            continue
        sx = vertex_near_zero(np.array(xs[k:k + 3], float) - a, np.array(ms[k:k + 3], float), va, L, near)
        if sx is not None and where is None:
            where = a + sx
    if where is None:
        return None
    return float(min(max(where, a + 0.5 * floor), b - 0.5 * floor))


def vertex_near_zero(s: np.ndarray, v: np.ndarray, va: float, length: float, near: float = NEAR) -> float | None:
    """Where the parabola through the points (s, v) (s measured from the step's start, where the value is va)
    has its vertex inside the step (0, length) with a value of the other sign than va, or within `near` of its
    spread from zero (the largest difference from va of the three values and the vertex's); else None."""
    c2, c1, c0 = np.polyfit(s, v, 2)
    if c2 == 0:
        return None
    sx = -c1 / (2 * c2)
    if not 0 < sx < length:
        return None
    vx = c0 + c1 * sx + c2 * sx * sx
    spread = max(float(np.max(np.abs(v - va))), abs(vx - va))
    return float(sx) if (vx < 0) != (va < 0) or abs(vx) <= near * spread else None


def certify(samples: list, solve: Callable[[float, Sample], Sample], resolution: float, refine: bool = True,
            approach: float = APPROACH, near: float = NEAR, max_inserted: int = 2000,
            xs: list | None = None) -> Line:
    """The line's samples refined and its stability changes located (see the module's docstring).

    `samples`: a Sample, or None where the solution was not computed, at ascending x (`xs` gives the x of the
    None entries; failures are not refined across: the line is certified piece by piece between them).
    `solve(x, near)`: the Sample at x, started from the neighbouring sample `near`; raises SolveFailed."""
    pieces, current = [], []
    for s in samples:
        if s is None:
            if current:
                pieces.append(current)
            current = []
        else:
            current.append(s)
    if current:
        pieces.append(current)
    out = Line([], [], [], resolution=resolution)
    for piece in pieces:
        pts = list(piece)
        if refine:
            i, budget = 0, max_inserted
            while i < len(pts) - 1 and budget > 0:
                xs_, ms = [p.x for p in pts], [p.margin for p in pts]
                where = _split_needed(xs_, ms, i, resolution, approach, near)
                if where is None:
                    i += 1
                    continue
                near_s = pts[i] if where - pts[i].x <= pts[i + 1].x - where else pts[i + 1]
                try:
                    pts.insert(i + 1, solve(where, near_s))
                    out.inserted += 1
                    budget -= 1
                except SolveFailed as exc:
                    out.failures.append((where, str(exc)))
                    i += 1
        out.samples += pts
        for a, b in zip(pts, pts[1:]):
            if a.stable != b.stable:
                _locate(a, b, solve, resolution, out)
    out.windows = _windows(out.samples, out.changes)
    return out


def _locate(a: Sample, b: Sample, solve, resolution: float, out: Line) -> None:
    """The stability change between a and b: the root of the margin (Brent), then one sample each side."""
    cache = {}

    def g(x):
        if x == a.x:
            return a.margin
        if x == b.x:
            return b.margin
        if x not in cache:
            cache[x] = solve(x, a if x - a.x <= b.x - x else b)
        return cache[x].margin
    try:
        if a.margin * b.margin > 0:  # the counts and the margin's sign disagree (a tolerance's edge)
            raise SolveFailed("the margin does not change sign")
        x = brentq(g, a.x, b.x, xtol=1e-12 * max(1.0, abs(a.x)), rtol=4 * np.finfo(float).eps)
        # one sample each side, a twentieth of the way to the ends: far enough that the margin there is beyond
        # the stability test's tolerance, near enough that no second crossing lies between
        lo = solve(x - SIDE * (x - a.x), a) if x > a.x else a
        hi = solve(x + SIDE * (b.x - x), b) if x < b.x else b
    except (SolveFailed, ValueError) as exc:
        out.changes.append(Change(0.5 * (a.x + b.x), a.stable, (a.unstable, b.unstable), a.state, a.spectrum,
                                  (a.x, b.x)))
        out.failures.append((0.5 * (a.x + b.x), f"change not located: {exc}"))
        return
    if lo.stable == hi.stable:
        out.rejected.append({"x": float(x), "unstable": [lo.unstable, hi.unstable],
                             "why": "unstable on both sides" if not lo.stable else "stable on both sides"})
        return
    at = cache.get(x) or (a if x - a.x <= b.x - x else b)
    out.changes.append(Change(float(x), lo.stable, (lo.unstable, hi.unstable), at.state, at.spectrum))


def _windows(samples: list[Sample], changes: list[Change]) -> list[tuple[float, float]]:
    """Stable intervals: runs of stable samples extended to the located changes that bound them."""
    events = sorted([(s.x, "s", s.stable) for s in samples] + [(c.x, "c", c) for c in changes],
                    key=lambda e: e[0])
    out, start, last = [], None, None
    for x, kind, what in events:
        if kind == "c":
            if what.stable_below and start is not None:
                out.append((start, x))
                start = None
            elif not what.stable_below:
                start = x
            continue
        if what and start is None:
            start = x
        if not what and start is not None:
            out.append((start, last))
            start = None
        last = x if what else last
    if start is not None:
        out.append((start, last))
    return [(float(a), float(b)) for a, b in out if b >= a]


def narrowest_missed(windows_true: list[tuple[float, float]], found: list[tuple[float, float]],
                     resolution: float) -> list[tuple[float, float]]:
    """The true windows wider than `resolution` that no found window overlaps (tests and measurements)."""
    return [(a, b) for a, b in windows_true if b - a > resolution
            and not any(fa <= b and fb >= a for fa, fb in found)]


def margin_of(spectrum: np.ndarray, orbit: bool) -> float:
    """The stability margin of a spectrum: max Re (steady state) or max |mu| - 1 (multipliers)."""
    ev = np.asarray(spectrum, complex)
    if not ev.size:
        return -math.inf
    return float(np.max(np.abs(ev)) - 1.0) if orbit else float(np.max(ev.real))
