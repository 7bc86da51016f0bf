"""A generic pseudo-arclength continuer: it follows any curve F(x) = 0, F: R^(n+1) -> R^n, knowing nothing
of what the curve is (MATCONT's and BifurcationKit's split: the curve supplies its defining system, its
Jacobian and its test functions; this module steps, corrects, watches the test functions and locates
their zeros).

    branch = run(curve, x0, direction, Settings(ds=0.01, ds_max=0.1, bounds=(0.5, 4.0)))
    branch.points       accepted points (x, the curve's data there, the test functions, the tangent)
    branch.specials     located zeros of test functions the curve calls special (fold, Hopf, torus, ...)

A curve is any object with
    size                      n + 1, the number of unknowns
    parameter(x)              the value bounds apply to (the continuation parameter)
    evaluate(x)               (F, dF/dx) at x, F of length n, dF/dx n x (n + 1)
    data(x)                   what the curve computes at a converged point (spectrum, multipliers, ...)
    test_names                names of its test functions; tests(x, data) their values (a sign change
                              between two points means a zero between them)
    special(name, x, data)    the special point a located zero is (a dict with at least "kind"), or None
                              when the zero is not one (a neutral saddle for a Hopf test)
    accept(x, data)           called with each accepted point (a moving phase condition)
    weights                   optional: scales of the unknowns for the arclength metric

Steps (Keller): predict along the unit tangent, correct by Newton on F = 0 and the hyperplane through the
prediction orthogonal to the tangent; halve the step when Newton fails, the correction jumps or the
tangent turns by more than `max_turn`.  Each step is bounded by how fast the test functions move: a test
function heading for zero at rate sigma may cover at most `approach` of its distance |tau| in one step, so
the step shrinks near a zero, down to `resolution` (the smallest step this bound imposes; reported).
A curve may also name margins it wants watched (`margins(data)`: e.g. the leading |multiplier| - 1 of a
cycle, whose sign is its stability): they bound the steps and are checked at their extrema like the test
functions, so a stable window wider than `resolution` is not stepped over, but they are not located.
Where a test function has an extremum inside a step without changing sign there (the parabola through
the last three points says so, and its extreme value is of the other sign or within `near` of zero), the
step is checked at the extremum: two zeros close together (a window a plain scan steps over) are found.
A sign change is located by Brent's method on the chord between the two points, each trial point
corrected onto the curve (to `locate_tol` of the chord).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..loading import AnalysisError


class ContinuationError(AnalysisError):
    """The continuer could not take a first step."""


@dataclass
class Settings:
    ds: float = 0.01  # first step (arclength in the weighted metric)
    ds_min: float = 1e-7
    ds_max: float = 0.1
    max_points: int = 500
    bounds: tuple[float, float] | None = None  # of curve.parameter(x): stop when it leaves
    newton_tol: float = 1e-9  # max |F| (the curve scales its F)
    newton_max: int = 7
    max_turn: float = 0.5  # radians between consecutive tangents
    approach: float = 0.5  # a test function heading for zero covers at most this part of its distance per step
    resolution: float | None = None  # smallest step the test-function bound imposes (default ds_max / 50)
    near: float = 0.1  # an extremum within near * (the test's range over the three points) of zero is checked
    locate_tol: float = 1e-10
    fold_test: bool = True  # watch d parameter / ds (folds of the curve)
    watch: bool = True  # False: no step bound by the test functions and no extremum checks (plain stepping)


@dataclass
class Point:
    x: np.ndarray
    data: object
    tests: np.ndarray
    tangent: np.ndarray
    s: float  # arclength from the start


@dataclass
class Special:
    name: str  # the test function
    x: np.ndarray
    data: object
    info: dict
    index: int  # between points[index] and points[index + 1]


@dataclass
class Branch:
    points: list[Point]
    specials: list[Special]
    end: str
    resolution: float  # the test-function step bound's floor (arclength)
    checks: int = 0  # extremum checks inside steps
    missed: list = field(default_factory=list)  # sign changes that could not be located: (name, index)


class _Corrector:
    def __init__(self, curve, settings: Settings):
        self.curve, self.s = curve, settings
        w = getattr(curve, "weights", None)
        self.w2 = np.ones(curve.size) if w is None else np.asarray(w, float) ** 2

    def dot(self, a, b) -> float:
        return float(np.sum(a * self.w2 * b))

    def norm(self, a) -> float:
        return math.sqrt(self.dot(a, a))

    def solve(self, x0: np.ndarray, direction: np.ndarray, anchor: np.ndarray, offset: float,
              radius: float | None = None) -> np.ndarray:
        """Newton on F(x) = 0, direction . W^2 (x - anchor) = offset, from x0; a Newton step longer than
        `radius` (default: 4 times the larger of the offset and the smallest step) is a failure, not a jump."""
        x = np.array(x0, float)
        row = direction * self.w2
        radius = radius if radius is not None else 4 * max(abs(offset), self.s.ds_min, 1e-12) + 1e-3 * self.norm(x0)
        if hasattr(self.curve, "residual"):
            done = self._chord(x, row, anchor, offset, radius)
            if done is not None:
                return done
        for _ in range(self.s.newton_max + 1):
            try:
                F, J = self.curve.evaluate(x)
            except (ArithmeticError, ValueError) as exc:  # the model's own arithmetic failed there
                raise AnalysisError(f"corrector: {type(exc).__name__}") from None
            g = float(row @ (x - anchor)) - offset
            if not (np.all(np.isfinite(F)) and math.isfinite(g)):
                break
            if np.max(np.abs(F), initial=0.0) <= self.s.newton_tol and abs(g) <= self.s.newton_tol * (1 + abs(offset)):
                return x
            A = np.vstack([J, row])
            try:
                dx = np.linalg.solve(A, -np.r_[F, g])
            except np.linalg.LinAlgError:
                dx = np.linalg.lstsq(A, -np.r_[F, g], rcond=1e-14)[0]
            if not np.all(np.isfinite(dx)) or self.norm(dx) > radius:
                break
            x = x + dx
        raise AnalysisError("corrector: Newton did not converge")

    def _chord(self, x, row, anchor, offset, radius):
        """The chord method: the Jacobian at the anchor (the last accepted point, whose evaluation the curve
        still holds) factorised once, then only residuals (`curve.residual`, cheaper: a cycle's arcs without
        their variational equations).  None where it does not contract: the caller then runs Newton."""
        from scipy.linalg import lu_factor, lu_solve

        try:
            _, J = self.curve.evaluate(anchor)
            lu = lu_factor(np.vstack([J, row]))
        except (ArithmeticError, ValueError, AnalysisError, np.linalg.LinAlgError):
            return None
        last = math.inf
        for _ in range(2 * self.s.newton_max):
            try:
                F = self.curve.residual(x)
            except (ArithmeticError, ValueError, AnalysisError):
                return None
            g = float(row @ (x - anchor)) - offset
            if not (np.all(np.isfinite(F)) and math.isfinite(g)):
                return None
            if np.max(np.abs(F), initial=0.0) <= self.s.newton_tol and abs(g) <= self.s.newton_tol * (1 + abs(offset)):
                return x
            dx = lu_solve(lu, -np.r_[F, g])
            size = self.norm(dx)
            if not np.all(np.isfinite(dx)) or size > radius or size > 0.5 * last:
                return None
            last = size
            x = x + dx
        return None

    def tangent(self, x: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
        _, J = self.curve.evaluate(x)
        if previous is None:
            t = np.linalg.svd(J / np.sqrt(self.w2)[None, :])[2][-1] / np.sqrt(self.w2)
        else:
            A = np.vstack([J, previous * self.w2])
            try:
                t = np.linalg.solve(A, np.r_[np.zeros(len(J)), 1.0])
            except np.linalg.LinAlgError:
                t = np.linalg.lstsq(A, np.r_[np.zeros(len(J)), 1.0], rcond=1e-14)[0]
        t = t / self.norm(t)
        if previous is not None and self.dot(t, previous) < 0:
            t = -t
        return t


def _tests(curve, x, data, tangent, settings) -> np.ndarray:
    """The test functions (located where they change sign), then the curve's watched margins (`margins`: bound
    the steps and are checked at their extrema, never located: a stability margin whose sign changes inside an
    unstable region is no special point)."""
    values = list(curve.tests(x, data))
    if settings.fold_test:
        values.append(float(curve.parameter(tangent + x) - curve.parameter(x)))  # d parameter / ds
    margins = getattr(curve, "margins", None)
    if margins is not None:
        values += [float(v) for v in margins(data)]
    return np.array(values, float)


def names(curve, settings: Settings) -> list[str]:
    return list(curve.test_names) + (["fold"] if settings.fold_test else [])


def run(curve, x0: np.ndarray, direction, settings: Settings | None = None, tangent: np.ndarray | None = None) -> Branch:
    """Follow the curve from x0 (near it: corrected first).  `direction`: +1 / -1, the sign of the parameter's
    change along the first tangent, or a tangent-like vector the first tangent is oriented along.  `tangent`:
    the first step's direction itself (a branch switch: x0 is on the curve, the tangent given)."""
    s = settings or Settings()
    floor = s.resolution if s.resolution is not None else s.ds_max / 50
    corr = _Corrector(curve, s)
    x = np.array(x0, float)
    if tangent is None:
        t = _oriented(curve, corr, x, corr.tangent(x, None), direction)
        try:
            x = corr.solve(x, t, x, 0.0)
        except AnalysisError:
            raise ContinuationError("the start is not on the curve (Newton failed there)") from None
        t = _oriented(curve, corr, x, corr.tangent(x, t), direction)
    else:
        t = np.asarray(tangent, float) / corr.norm(np.asarray(tangent, float))
    data = curve.data(x)
    curve.accept(x, data)
    if tangent is None:
        t = corr.tangent(x, t)  # under the curve's state after accept (a moving phase condition)
    first = Point(x, data, _tests(curve, x, data, t, s), t, 0.0)
    branch = Branch([first], [], "max_points", floor)
    tnames = names(curve, s)
    h = s.ds
    while len(branch.points) < s.max_points:
        a = branch.points[-1]
        try:
            xb = corr.solve(a.x + h * a.tangent, a.tangent, a.x, h)
            if corr.norm(xb - a.x) > 2 * h:
                raise AnalysisError("jumped")
            tb = corr.tangent(xb, a.tangent)
            if math.acos(max(-1.0, min(1.0, corr.dot(tb, a.tangent)))) > s.max_turn and h > s.ds_min:
                raise AnalysisError("turned")
            data = curve.data(xb)
        except AnalysisError:
            h /= 2
            if h < s.ds_min:
                branch.end = "step size underflow"
                break
            continue
        b = Point(xb, data, _tests(curve, xb, data, tb, s), tb, a.s + corr.norm(xb - a.x))
        remesh = getattr(curve, "remesh", None)
        inserted = _check_extrema(curve, corr, branch, b, tnames, s) if s.watch else []
        for mid in inserted:
            _append(curve, corr, branch, mid, tnames, s)
        _append(curve, corr, branch, b, tnames, s)
        bnd = s.bounds
        par = curve.parameter(xb)
        if bnd is not None and not (bnd[0] - 1e-12 <= par <= bnd[1] + 1e-12):
            branch.end = "left the range"
            break
        stop = getattr(curve, "stop", None)
        if stop is not None and stop(xb, data):
            branch.end = stop(xb, data)
            break
        if remesh is not None:
            new = remesh(xb, data)
            if new is not None:
                xn = np.asarray(new, float)
                old_dpar = curve.parameter(xb + tb) - curve.parameter(xb)
                corr = _Corrector(curve, s)  # the unknowns changed: new weights
                tn = corr.tangent(xn, None)
                # keep the direction: the parameter's change as before the remesh
                if (curve.parameter(xn + tn) - curve.parameter(xn)) * old_dpar < 0:
                    tn = -tn
                dn = curve.data(xn)
                curve.accept(xn, dn)
                tn = corr.tangent(xn, tn)
                branch.points[-1] = Point(xn, dn, _tests(curve, xn, dn, tn, s), tn, branch.points[-1].s)
        # the next step: Newton's effort, then the test functions' approach to zero
        h = min(s.ds_max, h * 1.3)
        if not s.watch:
            continue
        last = branch.points[-1]
        prev = branch.points[-2]
        ds = max(last.s - prev.s, 1e-300)
        for tau_a, tau_b in zip(prev.tests, last.tests):
            rate = (tau_b - tau_a) / ds
            if rate * tau_b < 0:  # heading for zero
                h = min(h, max(s.approach * abs(tau_b) / abs(rate), floor))
        h = max(h, min(floor, s.ds_max))
    return branch


def _oriented(curve, corr, x, t, direction) -> np.ndarray:
    """t or -t: the parameter's change along it has the sign of `direction` (a number), or it points along
    `direction` (a vector)."""
    if np.ndim(direction) == 0:
        return -t if (curve.parameter(x + t) - curve.parameter(x)) * float(direction) < 0 else t
    return -t if corr.dot(t, np.asarray(direction, float)) < 0 else t


def _append(curve, corr, branch: Branch, b: Point, tnames, s: Settings) -> None:
    a = branch.points[-1]
    i = len(branch.points) - 1
    branch.points.append(b)
    curve.accept(b.x, b.data)
    b.tangent = corr.tangent(b.x, b.tangent)  # the tangent under the accepted state (a moved phase condition)
    for j, name in enumerate(tnames):
        if a.tests[j] == 0 or b.tests[j] == 0 or np.sign(a.tests[j]) == np.sign(b.tests[j]):
            continue
        try:
            x, data = locate(curve, corr, a, b, j, s)
        except (AnalysisError, ValueError):
            branch.missed.append((name, i))
            continue
        info = curve.special(name, x, data) if name != "fold" else {"kind": "fold"}
        if info is not None:
            branch.specials.append(Special(name, x, data, info, i))


def _chord(curve, corr, a: Point, b: Point):
    d = b.x - a.x
    L = corr.norm(d)
    d = d / L
    cache = {}

    def at(sig: float) -> np.ndarray:
        if sig not in cache:
            cache[sig] = corr.solve(a.x + sig * d, d, a.x, sig)
        return cache[sig]
    return at, L, d


def locate(curve, corr, a: Point, b: Point, j: int, s: Settings):
    """The zero of test function j between a and b: Brent on the chord, each trial corrected onto the curve."""
    at, L, d = _chord(curve, corr, a, b)
    fold = s.fold_test and j == len(curve.test_names)

    def tau(sig):
        if sig == 0.0:
            return a.tests[j]
        if sig == L:
            return b.tests[j]
        x = at(sig)
        if fold:
            t = corr.tangent(x, d)
            return float(curve.parameter(x + t) - curve.parameter(x))
        return float(curve.tests(x, curve.data(x))[j])
    sig = brentq(tau, 0.0, L, xtol=s.locate_tol * max(L, 1e-12), rtol=4 * np.finfo(float).eps)
    x = at(sig) if 0.0 < sig < L else (a.x if sig == 0.0 else b.x)
    return x, curve.data(x)


def _check_extrema(curve, corr, branch: Branch, b: Point, tnames, s: Settings) -> list[Point]:
    """Points to insert before b where a test function may cross zero twice inside the step a -> b."""
    if len(branch.points) < 2:
        return []
    z, a = branch.points[-2], branch.points[-1]
    S = np.array([z.s, a.s, b.s])
    found = None
    for j in range(len(b.tests)):
        if j < len(tnames) and tnames[j] == "fold":
            continue
        v = np.array([z.tests[j], a.tests[j], b.tests[j]])
        if np.sign(v[1]) != np.sign(v[2]) or v[1] == 0:
            continue
        c2, c1, c0 = np.polyfit(S - a.s, v, 2)
        if c2 == 0:
            continue
        sx = -c1 / (2 * c2)
        if not (0 < sx < b.s - a.s):
            continue
        vx = c0 + c1 * sx + c2 * sx * sx
        spread = float(np.ptp(v))
        if np.sign(vx) != np.sign(v[1]) or abs(vx) <= s.near * max(spread, abs(v).min()):
            found = sx if found is None else min(found, sx)
    if found is None:
        return []
    branch.checks += 1
    at, L, d = _chord(curve, corr, a, b)
    frac = found / max(b.s - a.s, 1e-300)
    try:
        xm = at(frac * L)
        tm = corr.tangent(xm, a.tangent)
        dm = curve.data(xm)
    except AnalysisError:
        return []
    return [Point(xm, dm, _tests(curve, xm, dm, tm, s), tm, a.s + corr.norm(xm - a.x))]
