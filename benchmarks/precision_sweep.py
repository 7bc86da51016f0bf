"""The work-precision sweep (`adbgen bench precision`): the curves from loose to tight tolerance under
the cost control of `precision`'s docstring, their records (error against the reference, CPU time,
the attractor check of problem A, the loosest reliable tolerance) and the targets on problem A.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import numpy as np

from .pathways import Pathway, error, measure, time_at_error
from .precision_curves import TDEC_DT, THRESHOLD, Curve
from .report import target
from .timing import cpu_with_children

if TYPE_CHECKING:
    from .precision import PrecisionProblem

SLOW_S = 0.5
PROBE_FRACTION = 0.01
CHEAP_S = 0.5  # runs faster than this go on after the time budget is spent
ATTRACTOR_TOL = 1e-2
TDEC_REL = 0.01
TARGET_ERROR = 1e-8
# the charts and targets compare CPU time (this process and its children; single-threaded pathways):
# on the shared machine it moves less with the load than wall time, which is recorded beside it
TIME = "cpu_s"


def sweep(model, pp: PrecisionProblem, cs: list[Curve], tols, *, t_end: float, repeats: int, max_run_s: float,
          budget_s: float, progress=None) -> None:
    """Run the curves from loose to tight tolerance with the cost control of the module docstring."""
    say = progress or (lambda line: None)
    started = time.perf_counter()
    tols = sorted(tols, reverse=True)
    active = []
    for c in cs:  # probe: the loosest tolerance over a short horizon
        horizon = t_end * PROBE_FRACTION
        try:
            res = c.make(tols[0], horizon).run()
        except Exception as exc:
            c.skipped.append({"tol": tols[0], "reason": f"error in the probe: {type(exc).__name__}: {exc}"})
            continue
        predicted = res["wall_s"] / PROBE_FRACTION
        c.probe = {"t_end": horizon, "wall_s": round(res["wall_s"], 6), "predicted_full_s": round(predicted, 3)}
        if predicted > max_run_s:
            why = (f"probe over [0, {horizon:g}] took {res['wall_s']:.3g} s: predicted {predicted:.3g} s for the "
                   f"full run at tol {tols[0]:g} > {max_run_s:g} s")
            c.skipped += [{"tol": t, "reason": why,
                           "last_measured_s": round(res["wall_s"], 6)} for t in tols]
            say(f"  skip {c.name}: predicted {predicted:.3g} s")
        else:
            active.append(c)
    for k, tol in enumerate(tols):
        if not active:
            break
        pws = [track_cpu(c.make(tol, t_end)) for c in active]
        measure(pws, repeats, SLOW_S)
        still = []
        over_budget = time.perf_counter() - started > budget_s
        for c, pw in zip(active, pws):
            c.points.append(pw)
            ok = pw.last.get("status") == "success" and pw.runs_s
            last = min(pw.runs_s) if pw.runs_s else None
            if ok and len(c.points) >= 2 and c.points[-2].runs_s:
                growth = min(10.0, max(1.2, last / min(c.points[-2].runs_s)))
            else:
                growth = 2.0
            rest = tols[k + 1:]
            reason = None
            if not ok:
                reason = f"failed at tol {tol:g}: {pw.last.get('status')}"
            elif last * growth > max_run_s:
                reason = (f"next run predicted {last * growth:.3g} s (last {last:.3g} s x growth {growth:.2g}) "
                          f"> {max_run_s:g} s")
            elif over_budget and last > CHEAP_S:
                reason = f"problem time budget {budget_s:g} s spent (runs under {CHEAP_S:g} s go on)"
            if reason and rest:
                c.skipped += [{"tol": t, "reason": reason, "last_measured_s": last} for t in rest]
            elif not reason:
                still.append(c)
        say(f"  tol {tol:g}: " + ", ".join(f"{c.name} {1e3 * min(pw.runs_s):.3g} ms" for c, pw in zip(active, pws)
                                           if pw.runs_s))
        active = still


# ------------------------------------------------------------------------------------- records

def track_cpu(pw: Pathway) -> Pathway:
    """Record the CPU time of each run of `pw` (its own figure when it gives one: the solve_ivp runs
    leave out their untimed t_dec evaluation) in pw.cpu_runs and in the run's ``cpu_s``."""
    inner, runs = pw.run, []

    def run():
        before = cpu_with_children()
        out = inner()
        spent = cpu_with_children() - before
        out.setdefault("cpu_s", spent)
        runs.append(out["cpu_s"])
        return out

    pw.run, pw.cpu_runs = run, runs
    return pw


def curve_record(c: Curve, y_ref, resolution: float | None, attractor=None) -> dict:
    pts = []
    for pw in c.points:
        rec = pw.record()
        cpu = getattr(pw, "cpu_runs", [])
        rec["runs_cpu_s"] = [round(v, 6) for v in cpu]
        rec["cpu_s"] = round(min(cpu), 6) if cpu else None
        e = error(pw.last.get("y_end"), y_ref)
        rec["error"] = e
        rec["below_resolution"] = bool(e is not None and resolution is not None and e < 10 * resolution)
        if attractor is not None and pw.last.get("status") == "success":
            rec.update(attractor(c, pw))
        pts.append(rec)
    return {"name": c.name, "kind": c.kind, "description": c.description, "adbgen": c.adbgen, "setup": c.setup,
            "probe": c.probe, "points": pts, "skipped": c.skipped}


def attractor_check(model, ref: dict, p):
    """A closure: does a run reach the reference's attractor with t_dec within 1 %? (problem A)"""
    angles = list(model.angle_indices)
    ix, iy = model.amplitude_indices[:2]
    t_ref = ref["t_dec"]

    def check(c: Curve, pw: Pathway) -> dict:
        y = np.asarray(pw.last["y_end"], float)
        d = np.remainder(y[angles] - ref["y_end"][angles] + math.pi, 2 * math.pi) - math.pi
        same = bool(np.max(np.abs(d)) <= ATTRACTOR_TOL and math.hypot(y[ix], y[iy]) < THRESHOLD)
        if "t_dec" in pw.last:
            t_dec, how = pw.last["t_dec"], "own"
        elif c.t_dec_of is not None:
            t_dec, how = c.t_dec_of(pw.tol), f"untimed run on a grid of {TDEC_DT:g}"
        else:
            t_dec, how = None, "not available"
        ok_t = bool(t_dec is not None and t_ref is not None and abs(t_dec - t_ref) <= TDEC_REL * t_ref)
        return {"attractor_angle_difference": float(np.max(np.abs(d))), "same_attractor": same, "t_dec": t_dec,
                "t_dec_how": how, "t_dec_within_1pct": ok_t, "reliable": bool(same and ok_t)}

    return check


def loosest_reliable(rec: dict) -> dict:
    """The loosest tolerance from which on every tighter measured tolerance is reliable."""
    pts = sorted((p for p in rec["points"] if "reliable" in p), key=lambda q: q["tol"])
    if not pts:
        return {"tol": None, "why": "no successful run"}
    best = None
    for p in pts:  # tight to loose
        if not p["reliable"]:
            break
        best = p["tol"]
    return {"tol": best, "tightest_measured": pts[0]["tol"],
            "why": None if best is not None else "the tightest measured tolerance is not reliable"}


# ------------------------------------------------------------------------------------- targets

def _curve_points(rec: dict) -> list[tuple[float, float]]:
    return [(p["error"], p[TIME]) for p in rec["points"] if p.get("error") and p.get(TIME)
            and p.get("status") == "success"]


def _interpolated(rec: dict, e: float) -> float | None:
    pts = _curve_points(rec)
    errs = [x for x, _ in pts]
    if not errs or not (min(errs) <= e <= max(errs)):
        return None
    r = time_at_error(pts, e)
    return r["time_s"] if r else None


def precision_targets(prob: dict, default: str) -> list[dict]:
    """Targets on problem A: at error 1e-8 best adbgen vs fastest peer and vs lambdify; default engine
    left of every peer's curve over 1e-4..1e-12 (where both curves cover the error)."""
    out = []
    recs = prob["curves"]
    at = {}
    for rec in recs:
        r = time_at_error(_curve_points(rec), TARGET_ERROR)
        if r:
            at[rec["name"]] = {**r, "error_range": [min(x for x, _ in _curve_points(rec)),
                                                    max(x for x, _ in _curve_points(rec))]}
    prob["time_at_1e-8"] = at
    adb = {k: v for k, v in at.items() if next(r for r in recs if r["name"] == k)["adbgen"]}
    peers = {k: v for k, v in at.items() if k.startswith("peer:")}
    lam = {k: v for k, v in at.items() if k.startswith("ivp:lambdify")}
    best = min(adb, key=lambda k: adb[k]["time_s"]) if adb else None
    if best and peers:
        fastest = min(peers, key=lambda k: peers[k]["time_s"])
        ratio = peers[fastest]["time_s"] / adb[best]["time_s"]
        out.append(target("A, error 1e-8: best adbgen pathway vs the fastest peer", "peer / adbgen >= 1", ratio, 1.0,
                           f"{best} {1e3 * adb[best]['time_s']:.3g} ms CPU ({adb[best]['how']}); {fastest} "
                           f"{1e3 * peers[fastest]['time_s']:.3g} ms CPU ({peers[fastest]['how']})"))
    else:
        out.append(target("A, error 1e-8: best adbgen pathway vs the fastest peer", "peer / adbgen >= 1", None, 1.0,
                           "not measured"))
    if best and lam:
        fastest = min(lam, key=lambda k: lam[k]["time_s"])
        ratio = lam[fastest]["time_s"] / adb[best]["time_s"]
        out.append(target("A, error 1e-8: best adbgen pathway vs lambdify + solve_ivp", "lambdify / adbgen >= 50",
                           ratio, 50.0, f"{best} {1e3 * adb[best]['time_s']:.3g} ms CPU; the faster lambdify pathway "
                           f"{fastest} {lam[fastest]['time_s']:.3g} s CPU ({lam[fastest]['how']}, its errors "
                           f"{lam[fastest]['error_range'][0]:.1e}..{lam[fastest]['error_range'][1]:.1e})"))
    else:
        out.append(target("A, error 1e-8: best adbgen pathway vs lambdify + solve_ivp", "lambdify / adbgen >= 50",
                           None, 50.0, "not measured"))
    # default engine on or left of every peer's curve
    levels = [10.0 ** (-k / 2) for k in range(8, 25)]  # 1e-4 .. 1e-12, half decades
    drec = next((r for r in recs if r["name"] == default), None)
    worst, rows, best_by_level = None, [], []
    for e in levels:
        td = _interpolated(drec, e) if drec else None
        times = {r["name"]: _interpolated(r, e) for r in recs}
        times = {k: v for k, v in times.items() if v}
        if times:
            winner = min(times, key=times.get)
            best_by_level.append({"error": e, "fastest": winner, "time_s": times[winner],
                                  "default_time_s": td})
        for r in recs:
            if not r["name"].startswith("peer:"):
                continue
            tp = times.get(r["name"])
            if td and tp:
                rows.append({"error": e, "peer": r["name"], "peer_s": tp, "default_s": td, "ratio": tp / td})
                worst = tp / td if worst is None else min(worst, tp / td)
    prob["default_vs_peers"] = rows
    prob["fastest_by_error"] = best_by_level
    lost = sorted({f"{r['peer']} at {r['error']:.0e}" for r in rows if r["ratio"] < 1.0})
    out.append(target("A: default engine on or left of every peer's curve, errors 1e-4..1e-12",
                       "min over errors and peers of peer time / default time >= 1", worst, 1.0,
                       ("default slower than " + ", ".join(lost)) if lost else
                       ("compared where both curves cover the error (interpolated)" if rows else "no overlap")))
    return out




# issue 22: the default (auto) engine at or left of heyoka on the hand-written equations at every decade of
# error, on problems A and B; at least 4x JiTCODE at 1e-8 on A
AUTO_LEVELS = tuple(10.0 ** -k for k in range(6, 14))
HAND = "peer:heyoka-hand"


def auto_targets(problems: dict, default: str) -> list[dict]:
    """The issue-22 targets from the work-precision curves (time interpolated log-log at each error, CPU
    time).  At a level the peer's curve does not reach (its tightest tolerance errs more) and the default
    reaches, the default counts as ahead ("peer does not reach"); the measured ratio is the smallest over
    the levels both curves cover.  At a level above the default's whole curve (its loosest run errs less),
    the default's time is that of its cheapest run reaching the level: an upper bound, so the ratio is a
    lower bound."""
    out = []
    for label in ("A", "B"):
        prob = problems.get(label)
        if not prob:
            continue
        recs = {r["name"]: r for r in prob["curves"]}
        d, h = recs.get(default), recs.get(HAND)
        pts_d = _curve_points(d) if d else []
        reach = min((x for x, _ in _curve_points(h)), default=None) if h else None
        rows, worst = [], None
        for e in AUTO_LEVELS:
            td = _interpolated(d, e) if d else None
            th = _interpolated(h, e) if h else None
            row = {"error": e, "default_s": td, "peer_s": th}
            if td is None and th and pts_d and max(x for x, _ in pts_d) < e:
                # the default's loosest run already errs less than e: its cheapest run at or below e (an
                # upper bound of its time at e) against the peer's interpolated time
                td = min(t for x, t in pts_d if x <= e)
                row.update(default_s=td, note="the default's loosest run errs less: its cheapest run reaching it")
            if td and th:
                row["ratio"] = th / td
                worst = th / td if worst is None else min(worst, th / td)
            elif td and reach is not None and reach > e:
                row["note"] = f"peer does not reach (its smallest error {reach:.1e})"
            rows.append(row)
        prob["auto_vs_heyoka_hand"] = rows
        lost = [f"{r['error']:.0e} ({r['ratio']:.2f}x)" for r in rows if r.get("ratio", 1.0) < 1.0]
        missing = [f"{r['error']:.0e}" for r in rows if "ratio" not in r and "note" not in r]
        detail = ", ".join(f"{r['error']:.0e}: {r['ratio']:.2f}x" + (" (cheapest run reaching it)" if "note" in r
                                                                       else "")
                           if "ratio" in r else f"{r['error']:.0e}: "
                           + r.get("note", "not covered") for r in rows)
        out.append(target(f"{label}: {default} at or left of heyoka on the hand-written equations, errors 1e-6..1e-13",
                          "min over the decades of heyoka-hand time / default time >= 1", worst, 1.0,
                          ("slower at " + ", ".join(lost) + "; " if lost else "")
                          + ("not covered: " + ", ".join(missing) + "; " if missing else "") + detail))
        if label == "A":
            j = recs.get("peer:jitcode-dop853")
            tj, td = (time_at_error(_curve_points(j), TARGET_ERROR) if j else None,
                      time_at_error(_curve_points(d), TARGET_ERROR) if d else None)
            ratio = tj["time_s"] / td["time_s"] if tj and td else None
            out.append(target(f"A, error 1e-8: {default} vs JiTCODE dop853", "JiTCODE / default >= 4", ratio, 4.0,
                              f"{default} {1e3 * td['time_s']:.3g} ms CPU ({td['how']}); JiTCODE "
                              f"{1e3 * tj['time_s']:.3g} ms CPU ({tj['how']})" if ratio else "not measured"))
    return out


__all__ = ["ATTRACTOR_TOL", "AUTO_LEVELS", "CHEAP_S", "PROBE_FRACTION", "SLOW_S", "TARGET_ERROR", "TDEC_REL", "TIME",
           "attractor_check", "auto_targets",
           "curve_record", "loosest_reliable", "precision_targets", "sweep", "track_cpu"]
