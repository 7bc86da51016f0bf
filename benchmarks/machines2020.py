"""Study (not a test): the Machines 2020 study of temporary speed reduction (Machines 2020, 8(4), 74) reproduced on
its statements: stiction scatters the balancing, a temporary speed reduction counters it, and the influence of
stiction, shaft damping, initial unbalance and the reduction's plateau; and item 5's practical question: which
reduction (depth, plateau) brings the residual imbalance below a target in every start (issue 37, item 5).

    python3 -m benchmarks.machines2020 [--side K] [--out docs/figures]    -> machines2020.png and .json
    python3 -m benchmarks.machines2020 --check                            the tiny version, exit 1 on a failure

The paper's statements (its abstract; its parameter table and figures were not readable here, and
machines2020_scene.toml says which values were chosen): (1) "the presence of stiction ... scatters consistent
qualitative balancing"; (2) "temporary speed reduction ... could be used as a countermeasure for the
stiction-induced scattering"; (3) the influence of "the initial mass positions, the initial unbalance, the adopted
speed profile, shaft damping, stiction and the speed reduction plateau" is studied (the abstract's findings
sentence is cut off in the copy read, so no direction of an influence is the paper's here).

Model: machines2020_scene.toml's values on the generated model of speed_reduction_scene.toml (friction_studies.py):
a Jeffcott rotor, two balls with rolling resistance mu_r and stiction mu_s (the event-driven stick/slip model of
docs/friction.md), the spin prescribed by the `schedule` law.  Each case is one sweep (`--measure residual`) over
side x side starting ball angles with the rotor and balls at rest; r is read at t_end, the same for every case
(the longest schedule's end plus SETTLE s), where every ball is stuck (at rest); starts with a ball still
slipping (undecided) or failed are counted apart, never as balanced (adbgen.analysis.residual).

Checks, computed from the distributions (`verdicts`): (1) scatter: without a reduction the 90 % quantile of r at
rest is at least SCATTER times its median, and the 90 % grows with mu_s (0.0025 < 0.005 < 0.01); (2) the best
reduction of the grid (smallest 90 %) has its median and 90 % below those without a reduction; influences
(damping, unbalance, plateau) are reported as measured.  A case with a start still moving or failed has no
quantile in the verdicts (`q_all`): a verdict that reads it is None.  The practical answer: the reductions of the grid that
are feasible for TARGET (a tenth of the rotor's response without balancing at omega): every start at rest below
it (speed_reduction.feasible).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks import friction_studies as fs
from benchmarks.speed_reduction import every_start_below, feasible

SCENE = Path(__file__).with_name("machines2020_scene.toml")
FIGURE = "machines2020.png"
DEPTHS = (0.3, 0.5, 0.65, 0.8)
PLATEAUS = (0.5, 1.5, 3.0)  # s
STICTIONS = (0.0025, 0.01)  # mu_s beside the scene's (mu_r = mu_s 0.4, as in the scene)
DAMPINGS = (3.0, 12.0)  # N s/m beside the scene's
UNBALANCES = (2.5e-4,)  # m beside the scene's
SETTLE = 3.0  # s at omega after the longest schedule
DEFAULT_SIDE = 16
TARGET_FRACTION = 0.1
SCATTER = 2.0
RTOL, ATOL = 1e-9, 1e-13


def grid_cases(base: dict, depths=DEPTHS, plateaus=PLATEAUS) -> list[dict]:
    """No reduction, then every depth x plateau, on the scene's rotor."""
    none = {"name": "no reduction", "group": "grid", "values": {**base, "depth": 0.0, "t_plateau": 0.0}}
    return [none] + [{"name": f"depth {d:g}, plateau {p:g} s", "group": "grid",
                      "values": {**base, "depth": d, "t_plateau": p}} for d in depths for p in plateaus]


def influence_cases(base: dict, stictions=STICTIONS, dampings=DAMPINGS, unbalances=UNBALANCES) -> list[dict]:
    """Each influence's values without a reduction and with the scene's reference reduction."""
    out = []
    for what, key, values in (("stiction", "mu_s", stictions), ("damping", "c", dampings),
                              ("unbalance", "eps", unbalances)):
        for v in values:
            changed = {key: v, **({"mu_r": 0.4 * v} if key == "mu_s" else {})}
            for reduced in (False, True):
                vals = {**base, **changed, **({} if reduced else {"depth": 0.0, "t_plateau": 0.0})}
                out.append({"name": f"{key} {v:g}, " + (f"depth {base['depth']:g}, plateau {base['t_plateau']:g} s"
                                                       if reduced else "no reduction"),
                            "group": what, "key": key, "value": v, "reduced": reduced, "values": vals})
    return out


def q(case: dict, which: str):
    return case["distribution"]["quantiles"][which]


def q_all(case: dict, which: str):
    """q, or None unless every start of the case came to rest: a quantile over the starts at rest only is not the
    case's (its moving or failed starts are not counted as physics)."""
    d = case["distribution"]
    return None if d["not_at_rest"] or d["failed"] else q(case, which)


def verdicts(result: dict) -> dict:
    """The paper's statements checked on the distributions (True, False, or None where a quantile is missing or
    some start of a case compared did not come to rest or failed: `q_all`)."""
    cases = result["cases"]
    none = cases[0]
    grid = [c for c in cases if c["group"] == "grid" and c["values"]["depth"] > 0 and q_all(c, "90") is not None]
    best = min(grid, key=lambda c: q_all(c, "90")) if grid else None
    mu = result["values"]["mu_s"]
    # the 90 % without a reduction at each mu_s, the scene's in its place
    by_mu = sorted([(c["value"], q_all(c, "90")) for c in cases if c["group"] == "stiction" and not c["reduced"]]
                   + [(mu, q_all(none, "90"))])
    scatter = None if q_all(none, "50") is None else q_all(none, "90") >= SCATTER * q_all(none, "50")
    grows = None if any(v is None for _, v in by_mu) else all(a[1] < b[1] for a, b in zip(by_mu, by_mu[1:]))
    helps = None if best is None or q_all(none, "50") is None else (q_all(best, "50") < q_all(none, "50")
                                                                and q_all(best, "90") < q_all(none, "90"))
    return {"stiction_scatters": scatter, "scatter_grows_with_stiction": grows, "reduction_helps": helps,
            "best_reduction": None if best is None else best["name"],
            "q90_by_mu_s": [[m, v] for m, v in by_mu]}


def run_case(model, case: dict, side: int, t_end: float, target: float, workers: int | None = 1) -> dict:
    """One case's sweep over side x side starts (`--measure residual`, r at t_end): the case with "r" and "at_rest"
    per start, its distribution of r at rest, whether it is feasible for `target` (every start at rest below it),
    how many starts are below it, the smallest target it meets in every start, and its wall time."""
    from adbgen.analysis.residual import AT_REST, distribution

    started = time.perf_counter()
    out = fs.sweep(model, case["values"], side, t_end, "residual", rtol=RTOL, atol=ATOL, workers=workers)
    dist = distribution(out["value"], out["at_rest"])
    return {**case, "r": out["value"], "at_rest": out["at_rest"], "distribution": dist,
            "feasible": feasible(dist, target),
            "below_target": int(((out["at_rest"] == AT_REST) & (out["value"] < target)).sum()),
            "every_start_below_m": every_start_below(dist, side * side),
            "wall_s": round(time.perf_counter() - started, 2)}


def study(side: int = DEFAULT_SIDE, workers: int | None = 1, progress=print, depths=DEPTHS, plateaus=PLATEAUS,
          stictions=STICTIONS, dampings=DAMPINGS, unbalances=UNBALANCES) -> tuple[dict, list[dict]]:
    model = fs.load()
    base = fs.scene_values(SCENE)
    cases = grid_cases(base, depths, plateaus) + influence_cases(base, stictions, dampings, unbalances)
    t_end = max(fs.schedule_end(c["values"]) for c in cases) + SETTLE
    target = TARGET_FRACTION * fs.free_response(base)
    runs = []
    for case in cases:
        runs.append(run_case(model, case, side, t_end, target, workers))
        dist = runs[-1]["distribution"]
        progress(f"{case['name']} ({case['group']}): {dist['at_rest']} at rest, {dist['not_at_rest']} moving, "
                 f"{dist['failed']} failed, {dist['quantiles']}, {runs[-1]['wall_s']} s")
    keep = ("name", "group", "key", "value", "reduced", "values", "distribution", "feasible", "below_target",
            "every_start_below_m", "wall_s")
    result = {"study": "machines2020", "scene": str(SCENE.relative_to(fs.ROOT)),
              "model_scene": str(fs.MODEL_SCENE.relative_to(fs.ROOT)), "model": model.name, "values": base,
              "starts": side * side, "grid": fs.axes(side), "t_end": t_end, "rtol": RTOL, "atol": ATOL,
              "initial_state": "rotor at rest, balls at rest on the race at phi_1, phi_2",
              "r_without_balancing_m": fs.free_response(base), "target_m": target,
              "target": f"{TARGET_FRACTION:g} of r without balancing at omega",
              "cases": [{k: run[k] for k in keep if k in run} for run in runs]}
    result["feasible_reductions"] = [c["name"] for c in result["cases"]
                                     if c["group"] == "grid" and c["values"]["depth"] > 0 and c["feasible"]]
    result["verdicts"] = verdicts(result)
    return result, runs


def check(workers: int | None = 1, side: int = 3) -> list[str]:
    """The tiny version (one reduction, one value per influence): every start at rest or counted, none failed;
    the verdicts computed; negative control: the scatter verdict on a planted distribution with the 90 % below
    SCATTER medians is False."""
    result, _ = study(side, workers, progress=lambda line: None, depths=(0.5,), plateaus=(1.0,),
                      stictions=(0.01,), dampings=(12.0,), unbalances=())
    fails = []
    for c in result["cases"]:
        d = c["distribution"]
        if d["failed"]:
            fails.append(f"{c['name']}: {d['failed']} failed runs")
        if d["at_rest"] + d["not_at_rest"] + d["failed"] != side * side:
            fails.append(f"{c['name']}: the counts do not add up to the {side * side} starts")
    if result["verdicts"]["stiction_scatters"] is None:
        fails.append("no start without a reduction came to rest")
    planted = json.loads(json.dumps(result))
    planted["cases"][0]["distribution"]["quantiles"].update({"50": 1.0, "90": 0.5 * SCATTER})
    if verdicts(planted)["stiction_scatters"] is not False:
        fails.append("negative control: a planted narrow distribution passes for scattered")
    return fails


def draw(result: dict, runs: list[dict], path: Path) -> Path:
    """Left: CDFs of r at rest, no reduction and every reduction of the grid, the target as a line; right: the 90 %
    of r at rest without and with the reference reduction for each influence's values."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8))
    for run in runs:
        if run["group"] != "grid":
            continue
        rest = np.sort(run["r"][run["at_rest"] == 1]) * 1e3
        if rest.size:
            d = run["distribution"]
            extra = (f", {d['not_at_rest']} moving" if d["not_at_rest"] else "") + \
                (f", {d['failed']} failed" if d["failed"] else "")
            none = run["values"]["depth"] == 0
            ax.step(rest, np.arange(1, rest.size + 1) / rest.size, where="post", label=run["name"] + extra,
                    lw=2.2 if none else 1.0, color="k" if none else None)
    ax.axvline(result["target_m"] * 1e3, color="r", ls="--", lw=1, label=f"target {result['target_m'] * 1e3:.3g} mm")
    ax.set_xscale("log")
    ax.set_xlabel("residual imbalance r at rest (mm)")
    ax.set_ylabel("fraction of starts at rest with r below")
    ax.set_title(f"{result['starts']} starts per case: depth x plateau")
    ax.legend(fontsize=6, loc="upper left", ncol=2)
    base = result["values"]
    labels, without, with_ = [], [], []
    none = result["cases"][0]
    ref = next((c for c in result["cases"] if c["group"] == "grid" and c["values"]["depth"] == base["depth"]
                and c["values"]["t_plateau"] == base["t_plateau"]), None)
    rows = [("scene", none, ref)]
    for group in ("stiction", "damping", "unbalance"):
        cs = [c for c in result["cases"] if c["group"] == group]
        for v in sorted({c["value"] for c in cs}):
            pair = [c for c in cs if c["value"] == v]
            rows.append((f"{pair[0]['key']} {v:g}", next(c for c in pair if not c["reduced"]),
                         next(c for c in pair if c["reduced"])))
    for label, a, b in rows:
        labels.append(label)
        without.append(np.nan if a is None or q(a, "90") is None else q(a, "90") * 1e3)
        with_.append(np.nan if b is None or q(b, "90") is None else q(b, "90") * 1e3)
    x = np.arange(len(labels))
    bx.bar(x - 0.2, without, 0.4, label="no reduction", color="0.5")
    bx.bar(x + 0.2, with_, 0.4, label=f"depth {base['depth']:g}, plateau {base['t_plateau']:g} s", color="tab:blue")
    bx.set_xticks(x, labels, fontsize=8, rotation=20)
    bx.set_ylabel("90 % quantile of r at rest (mm)")
    bx.set_title("influences (the scene's other values kept)")
    bx.legend(fontsize=8)
    fig.suptitle(f"Machines 2020 reproduced (chosen values): M {base['M']:g} kg, k {base['k']:g} N/m, c {base['c']:g} "
                 f"N s/m, eps {base['eps'] * 1e3:g} mm, 2 x {base['m'] * 1e3:g} g on R {base['R'] * 1e3:g} mm, mu_r "
                 f"{base['mu_r']:g}, mu_s {base['mu_s']:g}, omega {base['omega']:g} rad/s; fall {base['drop_rate']:g}, "
                 f"recovery {base['recovery_rate']:g} rad/s^2", fontsize=9)
    return fs.save(fig, path)


def main(argv=None) -> int:
    return fs.main("machines2020", __doc__.splitlines()[0], argv, default_side=DEFAULT_SIDE, study=study, check=check,
                   draw=draw, figure=FIGURE,
                   summary=lambda r: (f"verdicts: {r['verdicts']}; feasible for r < {r['target_m']:.3g} m in every start: "
                              f"{r['feasible_reductions'] or 'none in this grid'}"))


if __name__ == "__main__":
    sys.exit(main())
