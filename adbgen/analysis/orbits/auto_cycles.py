"""The independent method: the same periodic orbits by AUTO-07p's collocation (IPS = 2) on the emitted files.

    auto_branches(model, "Omega", p, [1.88, ...], to)   cycle branches from the HB labels of AUTO's own
                                                        one-parameter run nearest the given values
    auto_orbit(model, orbit, name)                      AUTO's correction of an orbit given as data (its
                                                        `dat` file: t, u), with its Floquet multipliers

Both run in a temporary copy of the model's auto/ folder (`auto07p.Session`).  For n >= 3 thesis models
the emitted func carries the regularising term that pins the balanced continuum's free angles; it
vanishes on the pinned equilibrium but not along a cycle, so AUTO's cycles there are those of the
regularised system (said in the output as `regularised: true`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import auto07p
from ..loading import AnalysisError, Model

NTST, NCOL = 60, 4


def _pinned_model(model: Model) -> bool:
    """The model's AUTO user file regularises the continuum of balanced states (its data: `pinned`)."""
    data = auto07p.stages_data(model)
    return bool(data and data.get("pinned"))


def _branch_json(points: list, name: str, column: str, amp: str, origin: float, regularised: bool) -> dict:
    rows = [pt for pt in points]
    return {"from": {"kind": "hopf", name: origin}, "regularised": regularised,
            "parameter": [pt.values[column] for pt in rows], "period": [pt.values["PERIOD"] for pt in rows],
            "stable": [bool(pt.stable) for pt in rows], "amplitude_at_t0": [pt.values.get(amp) for pt in rows],
            "points": [{"type": pt.type, name: pt.values[column], "period": pt.values["PERIOD"]}
                       for pt in rows if pt.label > 0 and pt.type in ("TR", "PD", "LP", "BP")]}


def auto_branches(model: Model, name: str, p: np.ndarray, hb_values, to: float | None, nmx: int = 200,
                  ds: float = 0.01, ds_max: float = 0.05, y: np.ndarray | None = None) -> list[dict]:
    """AUTO's cycle branches (IPS = 2, ISP = 2: TR, PD, LP detected) from the HB labels nearest hb_values, each
    run at most `nmx` steps (AUTO's NMX and NPR; `continue --max-points`)."""
    k = model.param_names.index(name)
    a = auto07p.auto_parameter(k)
    amp = auto07p.auto_parameter(model.n_params)
    column = f"PAR({a})"
    start = float(p[k])
    to = (0.5 * start if start > 0 else start - 1.0) if to is None else float(to)
    lo, hi = min(start, to), max(start, to)
    out = []
    with auto07p.Session(model) as session:
        one = auto07p.continue_one(model, name, p, y if y is not None else None, to, session=session)
        session.keep_solutions(model.name)
        hb = [pt for pt in one.labelled() if pt.kind == "HB"]
        for value in hb_values:
            if not hb:
                break
            pt = min(hb, key=lambda q: abs(q.values[column] - value))
            runs = []
            for sign in (-1.0, 1.0):
                points, _, _ = session.run(s=repr(model.name), IRS=pt.label, IPS=2, ISW=1, ICP=f"[{a}, 11, {amp}]",
                                           NTST=NTST, NCOL=NCOL, ISP=2, DS=sign * ds, DSMAX=ds_max, NMX=nmx, NPR=nmx,
                                           UZSTOP=auto07p._mapping({a: [lo, hi]}), U=None, PAR=None)
                runs.append(points)
            # the side the cycles exist on: the run that got away from the Hopf point
            best = max(runs, key=lambda pts: len(pts))
            out.append(_branch_json(best, name, column, f"PAR({amp})", pt.values[column], _pinned_model(model)))
    return out


def auto_orbit(model: Model, orbit, name: str, samples: int = 400) -> dict:
    """AUTO's collocation started from `orbit` (its `dat` file: t and the states over one period) at the
    orbit's parameters and one tiny step in `name`: that step's parameter, period and Floquet multipliers,
    AUTO's own solution near the orbit (compare with our orbit refined at that parameter)."""
    from .flow import Flow
    from .orbit import trace

    if orbit.forced:
        raise AnalysisError("auto_orbit: an autonomous orbit (a forced model's AUTO files carry the oscillator)")
    k = model.param_names.index(name)
    a = auto07p.auto_parameter(k)
    amp = auto07p.auto_parameter(model.n_params)
    t, Y = trace(orbit, Flow(model), samples)
    # AUTO reads the angles as they are: unwrap them along the orbit (a lapping angle gains 2 pi k)
    with auto07p.Session(model) as session:
        rows = "\n".join(" ".join(f"{v:.17g}" for v in (ti, *yi)) for ti, yi in zip(t, Y))
        (session.dir / f"{model.name}.dat").write_text(rows + "\n")
        par = {auto07p.auto_parameter(j): float(v) for j, v in enumerate(orbit.p)}
        points, solutions, log = session.run(
            IPS=2, IRS=0, ISW=1, dat=repr(model.name), ICP=f"[{a}, 11, {amp}]", NTST=NTST, NCOL=NCOL, ISP=2,
            DS=1e-7, DSMIN=1e-9, DSMAX=1e-6, NMX=2, NPR=2, U=None, PAR=auto07p._mapping(par), UZSTOP=None)
        if not points:
            raise AnalysisError(f"AUTO-07p did not converge the orbit:\n{log}")
        mu = auto07p.read_multipliers(session.dir / "fort.9", model.n_states)
    # the start is the data itself; the step after it is AUTO's own solution, a little way along the branch
    last = points[-1]
    return {"period": last.values["PERIOD"], name: last.values[f"PAR({a})"], "stable": bool(last.stable),
            "multipliers": [[float(z.real), float(z.imag)] for z in mu]}


def compare(branch, theirs: dict, pmap, samples: int = 8, tries: int = 3) -> dict:
    """Our branch against AUTO's at AUTO's own points (no interpolation between either method's steps): at
    `samples` of AUTO's steps spread along the common range, our nearest orbit is refined onto AUTO's point
    and the other coordinate compared.  Where the branch runs more in the parameter than in the period, at
    AUTO's parameter value (Newton shooting, `refine`): the periods are compared (`period_rel`); where it
    runs more in the period (about a fold of cycles, where one parameter value holds several cycles and a
    refine at fixed parameter may land on another of them), at AUTO's period (the continuation's corrector
    with the period's row): the parameter values are compared (`parameter_rel`).  The next nearest orbits
    are tried, up to `tries`; a point none of them reaches is listed with ``shooting: None`` and counted in
    ``unrefined``."""
    from . import continuer
    from .cycle import CycleCurve
    from .flow import Flow
    from .orbit import refine

    name = pmap.free[0]
    ours = [(o.p_value, o) for o in branch.orbits if o.period > 0]
    lam = np.array([v for v, _ in ours])
    per = np.array([o.period for _, o in ours])
    # AUTO's points on the stretch both branches cover: AUTO's points are in branch order and its steps may
    # run on past our last point (longer steps, the same number of them; past a fold of cycles the branch
    # comes back over parameter values and periods ours had), so its points up to the one nearest our end
    tp, tT = np.asarray(theirs["parameter"], float), np.asarray(theirs["period"], float)
    end = int(np.argmin(np.hypot(tp - lam[-1], (tT - per[-1]) / max(1.0, per[-1])))) if len(tp) else -1
    idx = [i for i in range(end + 1) if lam.min() <= tp[i] <= lam.max()]
    worst_T, worst_p, rows, unrefined = 0.0, 0.0, [], 0
    flow = None
    for i in np.unique(np.linspace(1, len(idx) - 1, min(samples, max(len(idx) - 1, 0))).astype(int)) if idx else []:
        v, T = theirs["parameter"][idx[i]], theirs["period"][idx[i]]
        row = None
        for j in (int(k) for k in np.argsort(np.hypot(lam - v, (per - T) / max(1.0, T)))[:tries]):
            o = ours[j][1]
            lo, hi = max(j - 1, 0), min(j + 1, len(ours) - 1)
            fix_period = abs(per[hi] - per[lo]) / max(1.0, T) > abs(lam[hi] - lam[lo])
            try:
                if not fix_period:
                    mine = refine(branch_model(o), pmap(v), o.arcs[0], o.period, o.windings, arcs=len(o.arcs),
                                  amplitude=False)
                    row = {name: v, "auto": T, "fixed": "parameter", "shooting": mine.period,
                           "rel": abs(mine.period - T) / T}
                else:
                    flow = flow or Flow(branch_model(o))
                    curve = CycleCurve(branch_model(o), pmap, flow, arcs=len(o.arcs), windings=o.windings,
                                       subharmonic=o.subharmonic)
                    curve.shooting.set_reference(o.arcs[0], o.p)
                    x0 = curve.pack(o.arcs, o.period, o.p_value)
                    corr = continuer._Corrector(curve, continuer.Settings(newton_max=12, newton_tol=1e-11))
                    e = np.zeros(curve.size)
                    e[-2] = 1.0 / corr.w2[-2]  # the corrector's row is this times the weights: T = AUTO's T
                    anchor = x0.copy()
                    anchor[-2] = T
                    x = corr.solve(x0, e, anchor, 0.0, radius=1.0 + corr.norm(x0))
                    row = {name: v, "auto": T, "fixed": "period", "shooting": float(x[-1]),
                           "rel": abs(float(x[-1]) - v) / abs(v)}
                break
            except AnalysisError:
                continue
        if row is None:
            unrefined += 1
            rows.append({name: v, "auto": T, "shooting": None, "rel": None})
            continue
        if row["fixed"] == "parameter":
            worst_T = max(worst_T, row["rel"])
        else:
            worst_p = max(worst_p, row["rel"])
        rows.append(row)
    return {"period_rel": worst_T, "parameter_rel": worst_p, "points": rows, "unrefined": unrefined,
            "common": len(idx), "auto_points": len(theirs["parameter"])}


def branch_model(o):
    return o.model


def nearest_special(points: list[dict], kind: str, value: float, name: str) -> float:
    """Distance in the parameter from `value` to the nearest special point of `kind` (AUTO's TR/PD/LP names)."""
    code = {"torus": "TR", "period-doubling": "PD", "fold": "LP"}[kind]
    vals = [pt[name] for pt in points if pt.get("type") == code]
    return min((abs(v - value) for v in vals), default=math.inf)


def auto_forced_bifurcations(model: Model, name: str, p: np.ndarray, lo: float, hi: float, ds: float | None = None,
                             nmx: int = 400) -> list[dict]:
    """A forced model's emitted AUTO files (the oscillator extension, IPS = 2) continued in `name` from their
    stpnt orbit, with the model parameters `p` (AUTO's PAR key): the TR, PD and LP points AUTO detects
    between lo and hi.  (`auto07p.Session` runs the autonomous models' steady-state files; this runs the
    forced model's own.)"""
    import shutil
    import tempfile
    from pathlib import Path

    missing = auto07p.missing_tools()
    if missing:
        raise auto07p.AutoError("AUTO-07p cannot run here: missing " + ", ".join(missing))
    src = model.folder / "auto"
    k = model.param_names.index(name)
    a = auto07p.auto_parameter(k)
    with tempfile.TemporaryDirectory(prefix="adbgen-auto-") as tmp:
        d = Path(tmp)
        for f in src.iterdir():
            if f.is_file():
                shutil.copy(f, d / f.name)
        base = (d / f"c.{model.name}").read_text()
        par = {auto07p.auto_parameter(j): float(v) for j, v in enumerate(p)}
        consts = dict(NMX=nmx, NPR=nmx, UZSTOP=auto07p._mapping({a: [lo, hi]}), PAR=auto07p._mapping(par))
        if ds is not None:
            consts.update(DS=ds, DSMAX=4 * abs(ds))
        (d / "c.run").write_text(auto07p.set_constants(base, **consts))
        log = auto07p.build_and_run({}, model.name, d, "c.run")
        if not (d / "fort.7").is_file():
            raise auto07p.AutoError(f"AUTO-07p did not run:\n{log}")
        points = auto07p.read_fort7(d / "fort.7")
    return [{"type": pt.type, name: pt.values[f"PAR({a})"], "period": pt.values.get("PERIOD")}
            for pt in points if pt.label > 0 and pt.type in ("TR", "PD", "LP")]
