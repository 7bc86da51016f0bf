"""Study (not a test): Wright and Peng (arXiv 1906.04823) reproduced: constant speed against a ramped run-up, and a
non-monotone speed profile enlarging the basin of the balanced state (issue 37, item 5).

    python3 -m benchmarks.wright_peng [--side K] [--out docs/figures]     -> wright_peng.png and .json
    python3 -m benchmarks.wright_peng --check                             the tiny version, exit 1 on a failure

The paper's statements (its abstract; its numbers were not readable here, wright_peng_scene.toml says which values
were chosen): (1) "there are cases where one must take the acceleration phase into consideration to obtain an
accurate picture of the dynamics"; (2) "similarly we identify cases where the acceleration phase of the disc may be
ignored"; (3) "nonmonotonic variations of the angular velocity, with a view of maximising the basin of attraction
of the desired solution".

Model: wright_peng_scene.toml's values on the generated model of speed_reduction_scene.toml with mu_r = mu_s = 0
(friction_studies.py): a Jeffcott rotor with two balls under viscous drag, the spin prescribed by the `schedule`
law.  Cases, all over the same side x side starting ball angles (the rotor at rest, t_end the same for all):

- *constant speed*: the disc at omega from the start with the balls at rest on it.  The schedule starts from rest,
  so this is a step: a ramp of STEP s with the balls' initial speed on the race phi_i' = omega (the step's
  acceleration takes exactly that from them: they leave it at rest on the race, as on a disc already turning).
  The step's acceleration also pushes the eccentric disc's centre (an impulse eps M omega), a transient the
  rotor's damping removes; the paper's constant case presumably starts without it (not read);
- *ramps*: from rest to omega in RAMPS s, the balls at rest on the race;
- *non-monotone*: the REFERENCE ramp, then a dip (the schedule's temporary reduction: DIPS).

Each start is labelled from t_dec (the last time r >= THRESHOLD) and its run's status: BALANCED when r stayed
below THRESHOLD over the last CONFIRM s, NOT_BALANCED when r(t_end) >= THRESHOLD (`whirling` counts those whose
balls still turn on the race at t_end, |phi_i'| > omega / 10: the non-synchronous state), UNDECIDED when r fell
below THRESHOLD only within the last CONFIRM s, FAILED when the run failed.  Undecided and failed starts are
counted and said, never counted as balanced, and a start undecided or failed in either of two cases is left out
of their comparison (and counted); a verdict that those starts could change, taken either way, is None
(`_at_most`, `_enlarges`).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from benchmarks import friction_studies as fs

SCENE = Path(__file__).with_name("wright_peng_scene.toml")
FIGURE = "wright_peng.png"
STEP = 1e-3  # s: the "constant speed" start
RAMPS = (0.1, 0.3, 1.0, 3.0)  # s
REFERENCE = 1.0  # s: the ramp the dips follow
DIPS = ({"t_hold": 1.0, "depth": 0.75, "drop_rate": 4000.0, "t_plateau": 2.0, "recovery_rate": 4000.0},
        {"t_hold": 1.0, "depth": 0.85, "drop_rate": 4000.0, "t_plateau": 1.0, "recovery_rate": 4000.0})
SETTLE = 10.0  # s at omega after the longest schedule, before t_end
CONFIRM = 2.0  # s: r below THRESHOLD over the last CONFIRM s is balanced
THRESHOLD = 5e-5  # m: a tenth of the eccentricity
DEFAULT_SIDE = 16
BALANCED, NOT_BALANCED, UNDECIDED, FAILED = 1, 0, 2, -1
# the verdicts: the acceleration phase may be ignored when the fastest ramp differs from constant speed in at
# most IGNORABLE of the starts compared; it matters when the slowest differs in at least MATTERS
IGNORABLE, MATTERS = 0.05, 0.25


def labels(t_dec: np.ndarray, failed: np.ndarray, t_end: float, confirm: float = CONFIRM) -> np.ndarray:
    """Per start: BALANCED (r < threshold from t_dec <= t_end - confirm on), NOT_BALANCED (r(t_end) >= threshold:
    t_dec is nan), UNDECIDED (t_dec within the last `confirm`), FAILED."""
    t_dec, failed = np.asarray(t_dec, float), np.asarray(failed, bool)
    out = np.full(t_dec.shape, UNDECIDED, dtype=np.int8)
    out[~np.isfinite(t_dec)] = NOT_BALANCED
    out[np.isfinite(t_dec) & (t_dec <= t_end - confirm)] = BALANCED
    out[failed] = FAILED
    return out


def counts(label: np.ndarray) -> dict:
    return {"balanced": int((label == BALANCED).sum()), "not_balanced": int((label == NOT_BALANCED).sum()),
            "undecided": int((label == UNDECIDED).sum()), "failed": int((label == FAILED).sum())}


def differ(a: np.ndarray, b: np.ndarray) -> dict:
    """How many starts decided in both cases end differently (balanced or not); `left_out`: undecided or failed in
    either."""
    decided = np.isin(a, (BALANCED, NOT_BALANCED)) & np.isin(b, (BALANCED, NOT_BALANCED))
    n = int(decided.sum())
    d = int((a[decided] != b[decided]).sum())
    return {"compared": n, "differ": d, "fraction": d / n if n else None, "left_out": int((~decided).sum())}


def cases(base: dict) -> list[dict]:
    """(name, values, y0) of every case; the values complete (the schedule without a dip unless given)."""
    flat = {**base, "t_hold": 0.0, "depth": 0.0, "t_plateau": 0.0}
    out = [{"name": "constant", "values": {**flat, "t_ramp": STEP}, "y0": [f"phi_1_dot={base['omega']!r}",
                                                                         f"phi_2_dot={base['omega']!r}"]}]
    out += [{"name": f"ramp {t:g} s", "values": {**flat, "t_ramp": t}, "y0": []} for t in RAMPS]
    out += [{"name": f"ramp {REFERENCE:g} s, dip {d['depth']:g} for {d['t_plateau']:g} s",
             "values": {**flat, "t_ramp": REFERENCE, **d}, "y0": []} for d in DIPS]
    return out


def _at_most(d: dict, limit: float, strict: bool = False) -> bool | None:
    """Whether the share of starts that end differently (`differ`'s counts) is <= limit (< limit: strict), with
    the starts left out (undecided or failed in either case) taken both ways: True when it holds even if every one
    of them differed, False when it fails even if none did, else None (they could change the answer)."""
    total = d["compared"] + d["left_out"]
    if not d["compared"]:
        return None
    low, high = d["differ"] / total, (d["differ"] + d["left_out"]) / total
    below = (lambda x: x < limit) if strict else (lambda x: x <= limit)
    return True if below(high) else False if not below(low) else None


def _enlarges(dip: dict, ref: dict) -> bool | None:
    """The dip balances more starts than the ramp without it: True when it does even if every start undecided or
    failed in the ramp were balanced, False when it does not even if every such start of the dip were, else None
    (the undecided and failed starts could change the answer; they are never counted as balanced)."""
    open_ = (lambda c: c.get("undecided", 0) + c.get("failed", 0))
    if dip["balanced"] > ref["balanced"] + open_(ref):
        return True
    if dip["balanced"] + open_(dip) <= ref["balanced"]:
        return False
    return None


def verdicts(result: dict) -> dict:
    """The three statements checked on the cases' labels (each True, False or None when nothing was compared or,
    for the dip, when its undecided or failed starts or the ramp's could change the answer)."""
    by = {c["name"]: c for c in result["cases"]}
    fast, slow = by[f"ramp {min(RAMPS):g} s"]["vs_constant"], by[f"ramp {max(RAMPS):g} s"]["vs_constant"]
    dips = [c for c in result["cases"] if "dip" in c["name"]]
    best = max(dips, key=lambda c: c["counts"]["balanced"])
    return {
        "acceleration_may_be_ignored": _at_most(fast, IGNORABLE),
        "acceleration_matters": None if _at_most(slow, MATTERS, strict=True) is None
        else not _at_most(slow, MATTERS, strict=True),
        "dip_enlarges_basin": _enlarges(best["counts"], by[f"ramp {REFERENCE:g} s"]["counts"]),
        "best_dip": best["name"],
    }


def study(side: int = DEFAULT_SIDE, workers: int | None = 1, progress=print) -> tuple[dict, list[dict]]:
    model = fs.load()
    base = fs.scene_values(SCENE)
    all_cases = cases(base)
    t_end = max(fs.schedule_end(c["values"]) for c in all_cases) + SETTLE
    runs = []
    for case in all_cases:
        started = time.perf_counter()
        out = fs.sweep(model, case["values"], side, t_end, "t_dec", y0=case["y0"], threshold=THRESHOLD,
                       workers=workers)
        label = labels(out["value"], out["failed"], t_end)
        rate = out["y_end"][:, [out["state"].index("phi_1_dot"), out["state"].index("phi_2_dot")]]
        whirling = int(((label == NOT_BALANCED) & (np.abs(rate).max(axis=1) > base["omega"] / 10)).sum())
        runs.append({**case, "label": label, "t_dec": out["value"], "whirling": whirling,
                     "wall_s": round(time.perf_counter() - started, 2)})
        progress(f"{case['name']}: {counts(label)}, whirling {whirling}, {runs[-1]['wall_s']} s")
    constant = runs[0]["label"]
    result = {"study": "wright_peng", "scene": str(SCENE.relative_to(fs.ROOT)),
              "model_scene": str(fs.MODEL_SCENE.relative_to(fs.ROOT)), "model": model.name, "values": base,
              "starts": side * side, "grid": fs.axes(side), "t_end": t_end, "threshold_m": THRESHOLD,
              "confirm_s": CONFIRM, "rtol": 1e-9, "atol": 1e-13,
              "cases": [{"name": r["name"], "values": r["values"], "y0": r["y0"], "counts": counts(r["label"]),
                         "whirling": r["whirling"], "vs_constant": differ(r["label"], constant),
                         "wall_s": r["wall_s"]} for r in runs]}
    result["verdicts"] = verdicts(result)
    return result, runs


def check(workers: int | None = 1, side: int = 3) -> list[str]:
    """The tiny version: the study on side x side starts must give decided labels for most starts and the
    constant case must differ from itself nowhere; negative control: a planted label change is counted."""
    result, runs = study(side, workers, progress=lambda line: None)
    fails = []
    for c in result["cases"]:
        if c["counts"]["failed"]:
            fails.append(f"{c['name']}: {c['counts']['failed']} failed runs")
    if result["cases"][0]["vs_constant"]["differ"] != 0:
        fails.append("the constant case differs from itself")
    planted = runs[0]["label"].copy()
    decided = np.flatnonzero(np.isin(planted, (BALANCED, NOT_BALANCED)))
    if decided.size:
        planted[decided[0]] = BALANCED + NOT_BALANCED - planted[decided[0]]
        if differ(planted, runs[0]["label"])["differ"] != 1:
            fails.append("negative control: a planted change of one label is not counted")
    else:
        fails.append("no start of the constant case was decided")
    return fails


def draw(result: dict, runs: list[dict], path: Path) -> Path:
    """One panel per case: the label of each start over (phi_1, phi_2)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    side = int(round(result["starts"] ** 0.5))
    cols = 4
    rows = -(-len(runs) // cols)
    fig, axs = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    cmap = ListedColormap(["0.2", "tab:red", "tab:green", "gold"])  # failed, not balanced, balanced, undecided
    for ax, run in zip(axs.ravel(), runs):
        ax.imshow(run["label"].reshape(side, side).T + 1, origin="lower", cmap=cmap, vmin=0, vmax=3,
                  extent=(0, 360, 0, 360))
        c = counts(run["label"])
        ax.set_title(f"{run['name']}\n{c['balanced']} balanced, {c['not_balanced']} not"
                     + (f", {c['undecided']} undecided" if c["undecided"] else "")
                     + (f", {c['failed']} failed" if c["failed"] else ""), fontsize=8)
        ax.set_xlabel("phi_1(0) (deg)", fontsize=8)
        ax.set_ylabel("phi_2(0) (deg)", fontsize=8)
    for ax in axs.ravel()[len(runs):]:
        ax.axis("off")
    v = result["values"]
    fig.suptitle(f"Wright and Peng reproduced: green balanced, red not, yellow undecided, black failed; omega "
                 f"{v['omega']:g} rad/s, omega_n {(v['k'] / v['M']) ** 0.5:g} rad/s, D {v['D']:g}, "
                 f"{result['starts']} starts, t_end {result['t_end']:g} s", fontsize=9)
    return fs.save(fig, path)


def main(argv=None) -> int:
    return fs.main("wright_peng", __doc__.splitlines()[0], argv, default_side=DEFAULT_SIDE, study=study, check=check,
                   draw=draw, figure=FIGURE,
                   summary=lambda r: f"verdicts: {r['verdicts']}")


if __name__ == "__main__":
    sys.exit(main())
