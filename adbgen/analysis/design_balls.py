"""The ball count as a design variable (issue 39 item 1, `adbgen design --balls N1..N2`): each count is its own
model (the state has a ball angle per ball), so the count is optimised by designing every count of the interval
(exhaustive: the best over the counts is the best of the interval, not a local optimum in the count) and
comparing their best designs by the objective; each count's continuous design is its own method's (interval and
chart certified, the optimiser local).

    row(n, design, objective)     what one count gives: its best design, its worst margin with its uncertainty,
                                  its objective value, its capacity, what limits it or why it is infeasible
    choose(rows, objective)       (the chosen count, `balls_choice`): the counts ranked by the objective, the
                                  runner-up, whether the choice is decided (the margins apart beyond their
                                  uncertainties; the runs' values apart beyond RUN_RTOL) and why, in one line

Smaller is better for every objective: the worst margin (minus the worst decay rate, thesis (3.17)'s leading real
part over the box), t_dec, r_max through the run-up, the residual's quantile.
"""

from __future__ import annotations

import math

from .design import Design

VALUE = {"margin": "margin", "t_dec": "t_dec", "r_max-run-up": "r_max", "residual": "residual_quantile"}
WHAT = {"margin": "worst margin", "t_dec": "t_dec at the operating point", "r_max-run-up": "r_max through the run-up",
        "residual": "residual quantile"}
RUN_RTOL = 1e-6  # two runs' values closer than this (relative) do not decide between counts (the runs' rtol 1e-8)
METHOD = ("every count of the interval designed (the count is its own model: exhaustive, so the best over the "
          "counts is the best of the interval); each count's continuous design by its own method")


def _finite(x) -> float | None:
    return float(x) if x is not None and math.isfinite(x) else None


def _fmt(x) -> str:
    return "—" if x is None else f"{x:.4g}"


def row(n: int, design: Design, objective: str) -> dict:
    """One count's result: the keys the `balls` rows have always had (n, feasible, best, margin, t_dec) and
    objective_value, margin_uncertainty, capacity, limit (the active boundary's kind, or why infeasible)."""
    pr, b = design.problem, design.best
    names = [a.name for a in pr.varied]
    feasible = b is not None and b.feasible
    runs = [r for r in design.objective_runs if b is not None and r["design"] == dict(zip(names, b.design))]
    if not feasible:
        value = None
    elif objective == "margin":
        value = _finite(b.margin)
    else:
        value = _finite(runs[0][VALUE[objective]]) if runs and runs[0].get(VALUE[objective]) is not None else None
    if feasible:
        limit = design.active.kind if design.active is not None else None
    elif not any(v.exists for v in design.verdicts):
        cap = max((v.capacity for v in design.verdicts if math.isfinite(v.capacity)), default=None)
        limit = (f"beyond the balls' capacity everywhere (at most {_fmt(cap)} < {pr.eccentricity} "
                 f"{_fmt(pr.imbalance.high)})")
    elif any(v.feasible for v in design.verdicts):
        limit = f"no feasible design settles or is computed by the objective {objective}"
    else:
        limit = "no design of the varied box is stable over the whole box"
    return {"n": n, "feasible": feasible, "best": dict(zip(names, b.design)) if b is not None else None,
            "margin": _finite(b.margin) if b is not None else None, "t_dec": runs[0]["t_dec"] if runs else None,
            "objective_value": value, "margin_uncertainty": _finite(b.margin_uncertainty) if b is not None else None,
            "capacity": _finite(b.capacity) if b is not None else None, "limit": limit}


def _apart(a: dict, b: dict, objective: str) -> bool:
    """The two counts' values differ beyond what is known of them: the worst margins by more than the sum of
    their uncertainties; a run's value by more than RUN_RTOL relative."""
    x, y = a["objective_value"], b["objective_value"]
    if objective == "margin":
        return abs(x - y) > (a["margin_uncertainty"] or 0.0) + (b["margin_uncertainty"] or 0.0)
    return abs(x - y) > RUN_RTOL * max(abs(x), abs(y))


def choose(rows: list[dict], objective: str) -> tuple[int | None, dict]:
    """(the chosen count or None, the `balls_choice` object): the feasible counts with a value ranked (smallest
    first; a tie broken by the fewer balls), the runner-up, `decided` and `why`."""
    ranked = sorted((r for r in rows if r["feasible"] and r["objective_value"] is not None),
                    key=lambda r: (r["objective_value"], r["n"]))
    out = {"objective": objective, "value": WHAT[objective], "method": METHOD,
           "ranking": [{"n": r["n"], "value": r["objective_value"]} for r in ranked], "chosen": None,
           "runner_up": None, "decided": False}
    others = "; ".join(f"n = {r['n']}: {r['limit']}" for r in rows if r not in ranked)
    if not ranked:
        out["why"] = "no count has a feasible design: " + others
        return None, out
    best = ranked[0]
    design = ", ".join(f"{k} = {_fmt(v)}" for k, v in best["best"].items())
    why = f"n = {best['n']} ({design}): {WHAT[objective]} {_fmt(best['objective_value'])}"
    why += f", limited by: {best['limit']}" if best.get("limit") else ", no boundary active"
    if len(ranked) > 1:
        second = ranked[1]
        out["runner_up"], out["decided"] = second["n"], _apart(best, second, objective)
        tol = "their margins' uncertainties" if objective == "margin" else "the runs' tolerance"
        why += (f"; the next, n = {second['n']}, {_fmt(second['objective_value'])}"
                + ("" if out["decided"] else f" (not apart beyond {tol}: the choice is not decided)"))
    else:
        out["decided"] = True
        why += "; the only count with a feasible design"
    out["chosen"] = best["n"]
    out["why"] = why + (f"; {others}" if others else "")
    return best["n"], out
