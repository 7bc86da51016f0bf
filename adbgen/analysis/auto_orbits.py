"""Periodically forced models on the command line (issue 24 item 3): their AUTO-07p files, both stages.

    continue_orbit(model, "omega", p, to)   -> OrbitRun: the forced response continued, labelled points
    forced_response(model, p)               -> Response: the orbit at p and its Floquet multipliers

A forced model (fixed frame, anisotropic support or gravity) has periodic responses, not steady
states.  Its emitted AUTO files continue them as periodic orbits of the autonomous extension (an
oscillator whose limit cycle is the forcing, paper (40), its states named by the AUTO files' data) from an exact start
orbit (stpnt): stage 1 (c.<model>) in the parameter the start moved (gravity g from 0), stage 2
(c.<model>.2) in the forcing frequency.  Here the stages run one after the other on a temporary copy
(`auto.Session`): stage 1 up to the requested value of its parameter, then the requested
continuation.  Stability along the branch is AUTO's (PT < 0: every Floquet multiplier but the two
structural ones of the extension inside the unit circle).

At one parameter point (`forced_response`), the orbit AUTO reaches there is refined by Newton's
method on the forced model's period map (the shooting system of `orbits.shooting` over one forcing
period 2 pi / omega from the orbit's phase, the variational equations integrated in the compiled
driver of `orbits.flow`; minimum-norm steps, so a continuum of balanced orbits converges too), and
its Floquet multipliers are the eigenvalues of the monodromy matrix: the model's own, n_states of
them (no structural ones: time is not a state of the forced model).  `adbgen continue --orbits`
continues the same response by shooting alone (`orbits.branches`), without AUTO.

A start orbit on a continuum (n >= 3 balanced balls) makes AUTO's continuation singular: it stops at
its first steps (MX), which is reported as a continuation that ended early.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from .auto07p import TYPES, AutoError, Point, Session, Solution, _mapping, auto_parameter, continuation_range
from .loading import AnalysisError, Model

CLOSURE_TOL = 1e-7  # an orbit closes when |y(T) - y(0)| <= CLOSURE_TOL (1 + |y|) (angles mod 2 pi)
ON_CIRCLE = 1e-6  # a multiplier with ||mu| - 1| below this is neutral


# --- the emitted files ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Stages:
    """What the model's AUTO files do (their data, auto/stages.json, written by the AUTO target beside
    them): stage 1's parameter (0-based model index) and its target, the start orbit (stpnt) and its
    parameters, whether a second stage (c.<model>.2) exists, the oscillator's states (paper (40)) in the
    extension's state vector, and whether the start lies on a continuum."""

    first: int
    first_target: float | None
    second: int | None
    start: np.ndarray  # stpnt at t = 0, oscillator included
    start_parameters: np.ndarray
    oscillator: tuple[int, int] | None = None
    continuum: bool = False


def stages(model: Model) -> Stages:
    data_file = model.folder / "auto" / "stages.json"
    if not data_file.is_file():
        raise AutoError(f"{model.name} has no AUTO files ({data_file.parent}, or they predate stages.json); regenerate "
                        "it with the 'auto' target (a forced model needs an exact start orbit for them)")
    d = json.loads(data_file.read_text())
    return Stages(int(d["first"]), d["first_target"], d["second"], np.array(d["start"], float),
                  np.array(d["start_parameters"], float), tuple(d["oscillator"]) if d["oscillator"] else None,
                  bool(d["continuum"]))


# --- the forced model's period map -------------------------------------------------------------------

def _model_states(model: Model, u: np.ndarray) -> tuple[np.ndarray, float]:
    """(state of the forced model, the time the oscillator is at) from an extension state u: the forced
    model's states first, the oscillator's (sin, cos) where the AUTO files' data put them (`stages`)."""
    osc = stages(model).oscillator
    y = np.asarray(u[: model.n_states], float)
    phase = math.atan2(u[osc[0]], u[osc[1]]) if osc and len(u) > max(osc) else 0.0
    return y, phase


def _flow(model: Model, p: np.ndarray, y0: np.ndarray, t0: float, period: float, variational: bool):
    """y(t0 + period) from y(t0) = y0 (and the monodromy with `variational`) on the compiled driver."""
    from .orbits.flow import Flow

    X, Phi, _ = Flow(model).arcs(y0, t0, period, p, phi=variational)
    return X[0], (Phi[0] if variational else None)


def _gap(model: Model, y1: np.ndarray, y0: np.ndarray) -> np.ndarray:
    """y(T) - y(0) with the ball angles taken modulo 2 pi."""
    d = y1 - y0
    for i in model.angle_indices:
        d[i] = math.remainder(d[i], 2 * math.pi)
    return d


@dataclass
class Response:
    """The forced response at parameters p: a periodic orbit and its Floquet stability."""

    model: Model
    p: np.ndarray
    y0: np.ndarray  # the orbit's state at t0
    t0: float
    period: float
    multipliers: np.ndarray
    family: np.ndarray  # True where a multiplier is 1 along a continuum of orbits (free ball angles)
    closure: float  # |y(T) - y(0)| after refinement
    amplitude_max: float  # max r over the orbit
    newton_steps: int
    route: list = field(default_factory=list)  # the AUTO stages that led here
    monodromy: np.ndarray | None = None  # the period map's Jacobian (the margin's condition numbers)

    @property
    def margin(self):
        """The leading transverse |mu| - 1 and what it is certain to (`margins.multiplier_margin`: the
        multiplier's condition number x |M| x max(the flow's rtol, the closure)), issue 34 item 5."""
        from .margins import multiplier_margin
        from .orbits.flow import RTOL

        M = self.monodromy if self.monodromy is not None else np.diag(self.multipliers)
        return multiplier_margin(M, self.transverse, None, RTOL, self.closure)

    @property
    def transverse(self) -> np.ndarray:
        """The multipliers that decide stability: all but the family's (which are 1 exactly)."""
        return self.multipliers[~self.family]

    @property
    def classification(self) -> str:
        size = np.abs(self.transverse)
        if np.any(size > 1 + ON_CIRCLE):
            return "unstable"
        if np.any(size > 1 - ON_CIRCLE):
            return "neutral"
        return "stable"

    @property
    def n_unstable(self) -> int:
        return int(np.sum(np.abs(self.transverse) > 1 + ON_CIRCLE))

    def to_json(self) -> dict:
        m = self.model
        order = np.argsort(-np.abs(self.transverse))
        mult = self.transverse[order]
        return {"model": m.name, "kind": "periodic orbit (forced response)", "classification": self.classification,
                "n_unstable": self.n_unstable, "period": self.period, "t0": self.t0,
                "parameters": dict(zip(m.param_names, map(float, self.p))),
                "state": dict(zip(m.state_names, map(float, self.y0))), "amplitude_max": self.amplitude_max,
                "multipliers": [[float(z.real), float(z.imag)] for z in mult],
                "multiplier_moduli": [float(abs(z)) for z in mult],
                "neutral_multipliers": [[float(z.real), float(z.imag)] for z in self.multipliers[self.family]],
                "floquet_exponents": [[float(v.real), float(v.imag)] for v in np.log(mult.astype(complex)) / self.period],
                "closure": self.closure, "newton_steps": self.newton_steps, "route": self.route,
                **self.margin.to_json()}


def refine_orbit(model: Model, p: np.ndarray, y0: np.ndarray, t0: float, period: float, max_steps: int = 8):
    """Newton on y(t0 + T; y0) - y0 = 0 (angles modulo 2 pi) by `orbits.shooting`: (orbit state, monodromy,
    closure, steps); where Newton does not close the orbit in max_steps, the start's (the caller checks the
    closure)."""
    from .orbits.flow import Flow
    from .orbits.shooting import Shooting, ShootingError

    flow = Flow(model)
    y = np.array(y0, float)
    y1, _ = _flow(model, p, y, t0, period, variational=False)
    shift = np.zeros(len(y))  # the whole turns an angle gains over the period
    for i in model.angle_indices:
        shift[i] = y1[i] - y[i] - math.remainder(y1[i] - y[i], 2 * math.pi)
    forcing = model.param_names.index(model.forcing_frequency)
    sh = Shooting(model, flow, 1, shift, forcing, max(1, round(period * p[forcing] / (2 * math.pi))), t_start=t0)
    try:
        u, ev, steps = sh.solve(y, p, tol=1e-12, max_iter=max_steps, min_iter=0)
    except ShootingError:
        u, steps = y, max_steps
        ev = sh.evaluate(u, p)
    return np.array(u, float), ev.monodromy, float(np.max(np.abs(ev.F))), steps


def _amplitude_max(model: Model, p, y0, t0, period) -> float:
    from .orbits.flow import Flow

    ix, iy = model.amplitude_indices[:2]
    Y = Flow(model).sample(y0, t0, np.linspace(t0, t0 + period, 201)[1:], p)
    return float(max(np.hypot(y0[ix], y0[iy]), np.max(np.hypot(Y[:, ix], Y[:, iy]))))


# --- running the stages ------------------------------------------------------------------------------

@dataclass
class StageRun:
    parameter: str
    start: float
    stop: float
    points: list[Point]
    solutions: list[Solution]

    @property
    def last_label(self) -> Solution | None:
        return self.solutions[-1] if self.solutions else None

    def reached(self, model: Model) -> bool:
        col = f"PAR({auto_parameter(model.param_names.index(self.parameter))})"
        if not self.points:
            return False
        last = self.points[-1].values[col]  # AUTO locates UZSTOP to about 1e-8 relative
        return abs(last - self.stop) <= 1e-6 * max(abs(self.stop), abs(self.stop - self.start))

    def end(self, model: Model) -> tuple[str, float]:
        col = f"PAR({auto_parameter(model.param_names.index(self.parameter))})"
        last = self.points[-1] if self.points else None
        return (TYPES.get(last.ty, str(last.ty)) if last else "none"), (last.values[col] if last else self.start)


def _check_start(model: Model, st: Stages, p: np.ndarray) -> None:
    """The start orbit must still be an orbit with the user's parameters (all but stage 1's, which
    starts from its stpnt value): one forcing period from stpnt must close."""
    q = p.copy()
    q[st.first] = st.start_parameters[st.first]
    if np.array_equal(q, st.start_parameters):
        return
    freq = model.forcing_frequency
    if not freq:
        raise AnalysisError(f"{model.name}: no forcing frequency known (FORCING_FREQUENCY)")
    omega = float(q[model.param_names.index(freq)])
    if not omega > 0:
        raise AnalysisError(f"{model.name}: the forcing frequency {freq} must be positive, got {omega:g}")
    y0, phase = _model_states(model, st.start)
    t0 = phase / omega
    y1, _ = _flow(model, q, y0, t0, 2 * math.pi / omega, variational=False)
    gap = float(np.max(np.abs(_gap(model, y1, y0))))
    if gap > CLOSURE_TOL * (1 + float(np.max(np.abs(y0)))):
        changed = [n for n, a, b in zip(model.param_names, q, st.start_parameters) if a != b]
        raise AnalysisError(f"{model.name}: its AUTO files start from an exact orbit at their own parameters; with "
                            f"{', '.join(changed)} changed it is no orbit (|y(T) - y(0)| = {gap:.2e}); continue in "
                            f"those parameters, or generate the model with these values (a scene file)")


def _run_stage(session: Session, model: Model, k: int, frm: float, to: float, restart: int | None,
               ds_max: float | None, p: np.ndarray, nmx: int = 2000, every: int | None = None) -> StageRun:
    """One continuation in parameter k from `frm` to `to`: from stpnt (restart None; the other
    parameters set to p) or from label `restart` of the previous stage's solutions."""
    name = model.param_names[k]
    apar = auto_parameter(k)
    amp = auto_parameter(model.n_params)
    span = abs(to - frm)
    ds_max = ds_max if ds_max is not None else span / 20
    # stop at `to` and, should the branch turn back, a span beyond the start (a stop at the start value
    # itself would be met at once)
    constants = dict(ICP=f"[{apar}, 11, {amp}]", ISW=1, NMX=nmx, NPR=every or nmx, DS=math.copysign(ds_max / 10, to - frm),
                     DSMIN=ds_max * 1e-6, DSMAX=ds_max, UZSTOP=_mapping({apar: [to, frm + (frm - to)]}))
    if restart is None:
        pars = {auto_parameter(j): float(v) for j, v in enumerate(p) if j != k}
        constants.update(IRS=0, PAR=_mapping(pars), s=None)
    else:
        constants.update(IRS=restart, s=repr(f"{model.name}"), PAR=None)
    points, solutions, _ = session.run(**constants)
    if points:
        session.keep_solutions(model.name)
    return StageRun(name, frm, to, points, solutions)


def _route(model: Model, p: np.ndarray, session: Session, ds_max: float | None = None) -> tuple[list[StageRun], Stages]:
    """Stage 1 from stpnt to p's value of its parameter (skipped where they agree); the runs made."""
    st = stages(model)
    _check_start(model, st, p)
    runs = []
    frm, to = float(st.start_parameters[st.first]), float(p[st.first])
    if frm != to:
        run = _run_stage(session, model, st.first, frm, to, None, None, p)
        runs.append(run)
        if not run.reached(model):
            kind, at = run.end(model)
            raise ContinuationEnded(f"stage 1 in {run.parameter} stopped at {run.parameter} = {at:.9g} before "
                                    f"{to:.9g} (AUTO-07p {kind})", runs)
    return runs, st


class ContinuationEnded(AnalysisError):
    """AUTO-07p stopped before the requested value (exit status 3 on the command line)."""

    def __init__(self, message: str, runs: list):
        super().__init__(message)
        self.runs = runs


@dataclass
class OrbitRun:
    model: Model
    name: str
    start: float
    to: float
    stages: list[StageRun]
    located: list = field(default_factory=list)  # stability changes AUTO did not label (`locate_changes`)

    @property
    def main(self) -> StageRun:
        return self.stages[-1]

    @property
    def complete(self) -> bool:
        return self.main.reached(self.model)

    def to_json(self) -> dict:
        m, main = self.model, self.main
        col = f"PAR({auto_parameter(m.param_names.index(self.name))})"
        by_label = {s.label: s for s in main.solutions}
        ix, iy = m.amplitude_indices[:2]
        points = []
        for pt in main.points:
            if pt.label <= 0 or pt.type == "RG":  # every step is saved (NPR = 1); the regular ones are not news
                continue
            row = {"label": pt.label, "type": pt.type, self.name: pt.values[col],
                   "stability": "stable" if pt.stable else "unstable", "step": abs(pt.pt),
                   "period": pt.values.get("PERIOD")}
            sol = by_label.get(pt.label)
            if sol is not None:
                row["amplitude_max"] = float(np.max(np.hypot(sol.u[:, ix], sol.u[:, iy])))
                row["state"] = dict(zip(m.state_names, map(float, sol.u[0][: m.n_states])))
            points.append(row)
        kind, at = main.end(m)
        return {"model": m.name, "kind": "periodic orbits (forced response)", "parameter": self.name,
                "from": self.start, "to": self.to,
                "stages": [{"parameter": s.parameter, "from": s.start, "to": s.stop, "steps": len(s.points),
                            "reached": s.reached(m)} for s in self.stages],
                "points": points, "unlabelled": self.located, "complete": self.complete, "end": kind, "end_at": at}


def continue_orbit(model: Model, name: str, p: np.ndarray, to: float | None = None, ds_max: float | None = None,
                   keep: str | None = None) -> OrbitRun:
    """The forced response continued in `name` from p's value to `to` (default half of it): stage 1
    first where p moves the start orbit's parameter, then this continuation (from stage 1's end)."""
    k, frm, to = continuation_range(model, name, p, to)
    with Session(model, keep=keep, forced=True) as session:
        runs, st = _route(model, p, session)
        if k == st.first and not runs:  # continuing stage 1's own parameter straight from stpnt
            runs.append(_run_stage(session, model, k, frm, to, None, ds_max, p, every=1))
        else:
            restart = runs[-1].last_label.label if runs else None
            q = p.copy()
            if restart is None:
                q[st.first] = st.start_parameters[st.first]
            runs.append(_run_stage(session, model, k, frm, to, restart, ds_max, q, every=1))
    out = OrbitRun(model, name, frm, to, runs)
    out.located = locate_changes(out, p)
    return out


def _multipliers_at(model: Model, p: np.ndarray, u: np.ndarray):
    """(orbit state, t0, multipliers) of the forced response near the extension state u, at p."""
    freq = model.forcing_frequency
    omega = float(p[model.param_names.index(freq)])
    y0, phase = _model_states(model, u)
    t0 = (phase % (2 * math.pi)) / omega
    y, mono, closure, _ = refine_orbit(model, p, y0, t0, 2 * math.pi / omega, max_steps=4)
    if closure > CLOSURE_TOL * (1 + float(np.max(np.abs(y)))):
        raise AnalysisError("no orbit")
    return np.r_[y, u[len(y):]], t0, np.linalg.eigvals(mono)


def _crossing(before: np.ndarray, after: np.ndarray) -> str:
    """AUTO's name of the change between two multiplier sets: the one(s) that crossed the unit circle."""
    out_after = after[np.abs(after) > 1 + ON_CIRCLE]
    out_before = before[np.abs(before) > 1 + ON_CIRCLE]
    moved = out_after if len(out_after) > len(out_before) else out_before
    if not len(moved):
        return "?"
    z = moved[np.argmax(np.abs(moved))]
    if abs(z.imag) > 1e-6 * abs(z):
        return "TR"
    return "PD" if z.real < 0 else "LP"


def locate_changes(run: "OrbitRun", p: np.ndarray, tol: float = 1e-8) -> list[dict]:
    """Stability changes between consecutive steps that AUTO-07p did not label (its torus test misses
    some at large steps): located by bisection on the parameter with the multipliers of the period map
    (orbits by Newton from the nearer step's), named by the multiplier that crossed (TR: a complex pair,
    LP: +1, PD: -1)."""
    m, main = run.model, run.main
    k = m.param_names.index(run.name)
    col = f"PAR({auto_parameter(k)})"
    sols = {s.label: s for s in main.solutions}
    labelled = [pt for pt in main.points if pt.label > 0 and pt.label in sols]
    found = []
    for a, b in zip(labelled, labelled[1:]):
        if a.stable == b.stable or a.kind or b.kind or TYPES.get(a.ty) in ("TR", "PD", "LP", "BP") \
                or TYPES.get(b.ty) in ("TR", "PD", "LP", "BP"):
            continue
        la, lb = a.values[col], b.values[col]
        qa, qb = p.copy(), p.copy()
        qa[k], qb[k] = la, lb
        try:
            ua, _, ma = _multipliers_at(m, qa, sols[a.label].u[0])
            ub, _, mb = _multipliers_at(m, qb, sols[b.label].u[0])
        except AnalysisError:
            continue
        stable_a = bool(np.all(np.abs(ma) < 1 + ON_CIRCLE))
        if stable_a == bool(np.all(np.abs(mb) < 1 + ON_CIRCLE)):
            continue
        for _ in range(60):
            if abs(lb - la) <= tol * max(1.0, abs(la)):
                break
            mid = 0.5 * (la + lb)
            q = p.copy()
            q[k] = mid
            try:
                um, _, mm = _multipliers_at(m, q, 0.5 * (ua + ub))
            except AnalysisError:
                break
            if bool(np.all(np.abs(mm) < 1 + ON_CIRCLE)) == stable_a:
                la, ua, ma = mid, um, mm
            else:
                lb, ub, mb = mid, um, mm
        kind = _crossing(ma, mb)
        near = mb[np.argmin(np.abs(np.abs(mb) - 1))]
        found.append({"type": kind, run.name: 0.5 * (la + lb), "bracket": [la, lb],
                      "direction": "destabilising" if stable_a else "stabilising",
                      "multiplier": [float(near.real), float(near.imag)],
                      "located": "bisection on the period map's multipliers (AUTO-07p left it unlabelled)"})
    return found


def forced_response(model: Model, p: np.ndarray, keep: str | None = None) -> Response:
    """The periodic response at p, refined by shooting, and its Floquet multipliers.  The start orbit
    (stpnt) is checked to be an orbit at p (but for stage 1's parameter); where p's value of that
    parameter differs from stpnt's, AUTO's stage 1 carries the orbit there, the other parameters at p."""
    freq = model.forcing_frequency
    if not freq:
        raise AnalysisError(f"{model.name}: no forcing frequency known (FORCING_FREQUENCY)")
    st = stages(model)
    route, u = [], st.start
    if float(p[st.first]) != float(st.start_parameters[st.first]):
        with Session(model, keep=keep, forced=True) as session:
            runs, st = _route(model, p, session)
        u = runs[-1].last_label.u[0]
        route = [{"parameter": r.parameter, "from": r.start, "to": r.stop, "steps": len(r.points)} for r in runs]
    else:
        _check_start(model, st, p)
    omega = float(p[model.param_names.index(freq)])
    y0, phase = _model_states(model, u)
    return response_at(model, p, y0, (phase % (2 * math.pi)) / omega, route)


def response_at(model: Model, p: np.ndarray, y0: np.ndarray, t0: float, route: list | None = None) -> Response:
    """The periodic response through (t0, y0) at p, refined by shooting over one forcing period, and its
    Floquet multipliers; where the orbit is known (a balanced state exact at every forcing frequency), no
    AUTO-07p route is needed to reach p."""
    omega = float(p[model.param_names.index(model.forcing_frequency)])
    period = 2 * math.pi / omega
    y, mono, closure, steps = refine_orbit(model, p, np.asarray(y0, float), t0, period)
    scale = 1.0 + float(np.max(np.abs(y)))
    if closure > CLOSURE_TOL * scale:
        raise AnalysisError(f"{model.name}: Newton on the period map did not close the orbit "
                            f"(|y(T) - y(0)| = {closure:.2e} after {steps} steps)")
    multipliers, family = _split_family(model, mono)
    return Response(model, np.array(p, float), y, t0, period, multipliers, family, closure,
                    _amplitude_max(model, p, y, t0, period), steps, list(route or []), monodromy=np.array(mono))


def _split_family(model: Model, mono: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The monodromy's eigenvalues, and which of them are the continuum's: 1 to 1e-8 with an
    eigenvector in the ball angles alone (moving the free balls along the balanced family; the
    steady states' `neutral` eigenvalues, for orbits)."""
    values, vectors = np.linalg.eig(mono)
    angles = list(model.angle_indices)
    family = np.zeros(len(values), bool)
    for j, (z, v) in enumerate(zip(values, vectors.T)):
        v = v / np.linalg.norm(v)
        family[j] = abs(z - 1) < 1e-8 and np.linalg.norm(v[angles]) > 1 - 1e-6
    return values, family


def describe_stage_end(run: OrbitRun) -> str:
    kind, at = run.main.end(run.model)
    continuum = stages(run.model).continuum
    hint = ("; the start orbit lies on a continuum of balanced orbits (n >= 3 free ball angles), where AUTO-07p's "
            "Newton system is singular: `adbgen stability` gives such an orbit's Floquet multipliers") if continuum else ""
    return (f"continuation of the forced response in {run.name} stopped at {run.name} = {at:.9g} before "
            f"{run.to:.9g} (AUTO-07p {kind}){hint}")


