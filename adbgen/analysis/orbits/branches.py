"""Branches of periodic orbits in one parameter: from a Hopf point, from an orbit, or a forced response.

    from_hopf(model, pmap, hp, settings)         the cycles born at the Hopf point hp
    from_orbit(model, pmap, orbit, settings, +1) an orbit (found by `orbit.find`, e.g. a desynchronised one)
                                                 continued towards larger (+1) or smaller (-1) parameter
    CycleBranch.to_json()                        {"parameter": [...], "period": [...], "stable": [...],
                                                  "amplitude": [...], ...} and its special points
    plot_branches(path, model, NAME, branches)   amplitude and period against the parameter (stable thick)

Each branch is followed by the generic continuer on the limit-cycle curve (`cycle.CycleCurve`); its
special points (folds of cycles, period-doubling, torus) are located by their test functions and listed
with the parameter, the period and the multipliers there.  The amplitude of an orbit is r_max, the
largest r = hypot(AMPLITUDE states) along it (the thesis' measure); where the module emits further
measures (e.g. a vibration measure "A") their maxima go along as "<name>_bar".
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..loading import AnalysisError, Model
from . import continuer
from .cycle import CycleCurve
from .flow import Flow
from .hopf import HopfPoint, cycle_start
from .orbit import PeriodicOrbit
from .parameters import ParameterMap

MAX_PERIOD_FACTOR = 200.0  # stop a branch whose period grew this much (a homoclinic end)


@dataclass
class CycleBranch:
    name: str  # the parameter
    origin: dict
    orbits: list[PeriodicOrbit]
    specials: list[dict]
    end: str
    windings: dict = field(default_factory=dict)
    resolution: float | None = None
    steps: dict = field(default_factory=dict)  # the continuer's extremum checks and the largest parameter step

    def to_json(self) -> dict:
        measures = sorted({k for o in self.orbits for k in o.measures})
        out = {"from": self.origin, "windings": {k: int(v) for k, v in self.windings.items()},
               "parameter": [float(o.p_value) for o in self.orbits],
               "period": [float(o.period) for o in self.orbits],
               "stable": [bool(o.stable) for o in self.orbits],
               "margin": [float(o.margin.value) for o in self.orbits],
               "marginal": [o.margin.marginal for o in self.orbits],
               "amplitude": [float(o.r_max) for o in self.orbits],
               "r_min": [float(o.r_min) for o in self.orbits],
               "max_multiplier": [float(np.max(np.abs(o.nontrivial))) if len(o.nontrivial) else 0.0
                                  for o in self.orbits],
               "end": self.end}
        if self.resolution is not None:
            # what the branch certifies: its steps near a zero of a test function or of the stability margin
            # (max |mu| - 1) shrink to `step_floor` (arclength), so a stable window wider than that is not
            # stepped over (provided the margin turns at most once inside a step: checked at its extrema)
            out["resolution"] = {"step_floor": float(self.resolution), "extremum_checks": int(self.steps.get("checks", 0)),
                                 "largest_step": float(self.steps.get("largest_step", 0.0))}
        for name in measures:
            out[f"{name}_bar"] = [float(o.measures.get(name, math.nan)) for o in self.orbits]
        return out

    def points_json(self, index: int) -> list[dict]:
        return [{**s, "branch": index} for s in self.specials]


UNIT_TOL = 1e-7  # a multiplier counts as outside the unit circle beyond 1 + UNIT_TOL (as the charts count)


def _outside(data) -> int:
    return int(np.sum(np.abs(data.nontrivial) > 1.0 + UNIT_TOL))


def _special_json(name: str, curve: CycleCurve, sp: continuer.Special, points=None) -> dict:
    """A special point; with the branch's points, the multipliers outside the unit circle at the two points
    around it (`unstable_before`, `unstable_after`, along the branch) and `stability_change`: whether the
    orbit is stable on one side and unstable on the other (a torus point of an orbit already unstable is a
    bifurcation, not a change of stability)."""
    d = sp.data
    mu = d.multipliers
    out = {"kind": sp.info["kind"], name: float(d.lam), "period": float(d.T),
           "multipliers": [[float(z.real), float(z.imag)] for z in mu]}
    if points is not None and sp.index + 1 < len(points):
        before, after = _outside(points[sp.index].data), _outside(points[sp.index + 1].data)
        out |= {"unstable_before": before, "unstable_after": after,
                "stability_change": (before == 0) != (after == 0)}
    if "angle" in sp.info:
        out["angle"] = sp.info["angle"]
    return out


def _settings(settings: continuer.Settings | None, lam0: float, to: float | None) -> continuer.Settings:
    s = settings or continuer.Settings(ds=0.01, ds_max=0.05, max_points=200)
    if s.bounds is None and to is not None:
        s.bounds = (min(lam0, to), max(lam0, to))
    return s


def _run(model: Model, curve: CycleCurve, x0, name: str, origin: dict, settings: continuer.Settings,
         direction=None, tangent=None, amplitude: bool = True) -> CycleBranch:
    T0 = None

    def stop(x, data):
        nonlocal T0
        T0 = T0 or data.T
        if data.T > MAX_PERIOD_FACTOR * T0:
            return f"period grew past {MAX_PERIOD_FACTOR:g} times its start (a homoclinic end?)"
        return None
    curve.stop = stop
    try:
        br = continuer.run(curve, x0, direction, settings, tangent=tangent)
    except continuer.ContinuationError as exc:
        return CycleBranch(name, origin, [], [], f"no branch: {exc}", dict(curve.windings))
    orbits = []
    for pt in br.points:
        if pt.data.T <= 0:
            continue
        o = _orbit(curve, pt, amplitude)
        orbits.append(o)
    # a fold of cycles also zeroes the branch test (a real multiplier at +1): reported once, as the fold
    folds = [sp.x[-1] for sp in br.specials if sp.info["kind"] == "fold"]
    # and a branch born at a Hopf point starts with two multipliers at +1 (the zero-amplitude cycle): the branch
    # test's zero there is the Hopf point itself, not a branch point
    start = [br.points[0].x[-1]] if br.points and origin.get("kind") == "hopf" else []
    kept = [sp for sp in br.specials if sp.info["kind"] != "branch point"
            or not any(abs(sp.x[-1] - f) <= 1e-6 * (1 + abs(f)) for f in folds + start)]
    specials = [_special_json(name, curve, sp, br.points) for sp in kept]
    return CycleBranch(name, origin, orbits, specials, br.end, dict(curve.windings), br.resolution,
                       {"checks": br.checks, "largest_step": float(np.max(np.abs(np.diff(
                           [curve.parameter(pt.x) for pt in br.points])))) if len(br.points) > 1 else 0.0})


def _orbit(curve: CycleCurve, pt, amplitude: bool) -> PeriodicOrbit:
    d = pt.data
    o = PeriodicOrbit(curve.model, d.p, d.X[0].copy(), d.T, dict(curve.windings), d.multipliers, d.trivial,
                      0.0, 0, d.X.copy(), curve.shooting.forced, curve.q, monodromy=d.monodromy)
    o.p_value = d.lam
    if amplitude:
        from .orbit import add_amplitude

        try:
            add_amplitude(o, curve.flow)
        except AnalysisError:
            pass
    return o


def from_hopf(model: Model, pmap: ParameterMap, hp: HopfPoint, settings: continuer.Settings | None = None,
              flow: Flow | None = None, to: float | None = None, amplitude: bool = True) -> CycleBranch:
    """The branch of cycles born at the Hopf point hp (both ways from the equilibrium: the continuer
    takes the eigenvector's direction; the side it goes to is the one the cycles exist on)."""
    flow = flow or Flow(model)
    name = pmap.free[0]
    origin = {"kind": "hopf", name: hp.lam, "frequency": hp.omega, "first_lyapunov": hp.l1,
              "criticality": hp.criticality}
    if hp.info.get("drift", 0.0) > 1e-8:
        origin["drift"] = hp.info["drift"]
    curve = CycleCurve(model, pmap, flow)
    x0, t0 = cycle_start(curve, hp)
    s = _settings(settings, hp.lam, to)
    br = _run(model, curve, x0, name, origin, s, tangent=t0, amplitude=amplitude)
    if not br.orbits[1:] and hp.info.get("drift", 0.0) > 1e-8:
        br.end = (f"no cycle branch: the Hopf point lies on a {hp.info['null_dimension']}-dimensional continuum of "
                  f"equilibria and the oscillation drifts along it (|L^T B(q, q-bar)| = {hp.info['drift']:.3g}), so "
                  f"no small cycle closes")
    return br


def from_orbit(model: Model, pmap: ParameterMap, orbit: PeriodicOrbit, direction: float,
               settings: continuer.Settings | None = None, flow: Flow | None = None, to: float | None = None,
               amplitude: bool = True) -> CycleBranch:
    """Continue `orbit` (found at pmap's base parameters) in pmap's free parameter."""
    flow = flow or Flow(model)
    name = pmap.free[0]
    lam0 = float(orbit.p[pmap.index[0]])
    origin = {"kind": "orbit", name: lam0, "period": float(orbit.period)}
    curve = CycleCurve(model, pmap, flow, arcs=len(orbit.arcs), windings=orbit.windings, subharmonic=orbit.subharmonic)
    x0 = curve.pack(orbit.arcs, orbit.period, lam0)
    curve.shooting.set_reference(orbit.arcs[0], orbit.p)
    s = _settings(settings, lam0, to)
    return _run(model, curve, x0, name, origin, s, direction=direction, amplitude=amplitude)


def plot_branches(path: Path, model, name: str, branches_) -> None:
    """Amplitude and period against the parameter: stable solid, unstable thin, special points marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, constrained_layout=True)
    marks = {"torus": ("*", "C3"), "period-doubling": ("D", "C2"), "fold": ("s", "C1")}
    for i, br in enumerate(branches_):
        j = br.to_json()
        lam, amp, per, st = (np.array(j[k]) for k in ("parameter", "amplitude", "period", "stable"))
        if len(lam) == 0:
            continue
        for ax, v in ((a1, amp), (a2, per)):
            ax.plot(lam, v, "-", color=f"C{i % 10}", lw=0.7)
            ax.plot(lam, np.where(st, v, np.nan), "-", color=f"C{i % 10}", lw=2.2)
        for sp in br.specials:
            mk, c = marks.get(sp["kind"], ("o", "k"))
            k = int(np.argmin(np.abs(lam - sp[name])))
            a1.plot(sp[name], amp[k], mk, color=c, ms=8)
            a2.plot(sp[name], sp["period"], mk, color=c, ms=8)
    a1.set_ylabel("amplitude r_max")
    a2.set_ylabel("period T")
    a2.set_xlabel(name)
    a1.set_title(f"{model.name}: periodic orbits (thick stable; * torus, D period-doubling, s fold)", fontsize=9)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name("." + path.name + ".tmp")
    fig.savefig(tmp, dpi=120, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    os.replace(tmp, path)
